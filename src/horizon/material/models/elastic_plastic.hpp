#pragma once
// The elastic-plastic ordinary state-based solid (Silling et al. 2007, sec. 16: seed 003
// eq. 114-129, digest reference/notes/003_silling_states.md sec. 7.4; the discrete radial
// return of J. A. Mitchell, "A nonlocal, ordinary, state-based plasticity model for
// peridynamics", SAND2011-3166, which Peridigm's "Elastic Plastic" implements), with
// linear isotropic hardening. docs/models/elastic_plastic.md has the derivations.
//
// Per particle i, with the LPS constants (seed 003 eq. 113; 2-D: digest sec. 8), d the
// dimension, k' = lps_bulk_modulus, alpha = (15 or 8) mu/m:
//   theta = (d/m) sum_j omega |xi| e V_j                     (seed 003 eq. 113 discrete, digest sec. 9)
//   e^d   = e - theta |xi| / d                               (seed 003 sec. 15; 2-D digest sec. 8)
//   t     = (d k' theta/m) omega |xi| + t^d                  (eq. 121: the dilatation stays elastic)
//   t^d   = alpha omega (e^d - e^dp)                         (eq. 122-123)
// e^dp the plastic deviatoric extension of each directed bond (history).
//
// The yield function. Seed 003 eq. 120 with psi = ||t^d||^2/2 and omega = 1 (the paper's
// example, eq. 128). For a general influence function we take the norm weighted by
// 1/omega, ||t^d||_w^2 = sum_j (t^d)^2/omega V_j = alpha^2 sum_j omega (e^d - e^dp)^2 V_j:
// it is the paper's norm for omega = 1, and with it grad psi = t^d/omega = alpha e^de is
// co-deviatoric (theta of e^de is 0), so the constrained gradient of eq. 118 is grad psi
// itself and the backward-Euler return of eq. 124 is an exact uniform scaling of the
// trial state for any omega (with the unweighted norm it is a per-bond scaling
// 1/(1 + alpha omega dlambda) and needs a scalar solve: digest sec. 7.4).
//   f = ||t^d||_w^2 / 2 - psi_0.
// psi_0 from the yield stress [DERIVED here; digest sec. 7.4 and 8 for omega = 1]: under a
// homogeneous small strain with elastic deviatoric part s, e^de = s:(n n) |xi| and
//   ||t^d||_w^2 = alpha^2 s_ij s_kl int omega xi_i xi_j xi_k xi_l / |xi|^2 dV
//             = alpha^2 (2 m / 15) s:s     (3-D, eq. 109-110: the moment is (m/15)(sym))
//             = alpha^2 (m / 4) s:s        (2-D, digest sec. 8: the moment is (m/8)(sym)),
// and with the classical deviatoric stress S = 2 mu s and alpha = 15 mu/m (8 mu/m):
//   3-D: ||t^d||_w^2 = (15/(2m)) S:S; von Mises S:S = (2/3) sigma_y^2  =>  psi_0 = 5 sigma_y^2/(2m)
//        (= 25 sigma_y^2/(8 pi delta^5) for omega = 1, m = 4 pi delta^5/5: Mitchell's value);
//   2-D: ||t^d||_w^2 = 4 S2:S2/m (S2 the in-plane deviator); calibrated on in-plane pure
//        shear (where s_33 = 0, so J2 = S2:S2/2): psi_0 = 4 sigma_y^2/(3m)
//        (= 8 sigma_y^2/(3 pi h delta^4) for omega = 1, m = pi h delta^4/2).
// Both are psi_0 = sigma_y^2 / (2 c m) with c = 1/5 (3-D), 3/8 (2-D): the equivalent stress
// of a force state is sigma_eq = sqrt(c m) ||t^d||_w.
//
// Hardening [DERIVED here]. An equivalent plastic strain per particle, eps_p, measured like
// the classical one (d eps_p = sqrt(2/3 d eps^p : d eps^p)): with the same moment
// integrals, a homogeneous plastic strain increment gives
//   d eps_p = sqrt(5/m) ||d e^dp||_o (3-D),  sqrt(8/(3m)) ||d e^dp||_o (2-D),
// ||x||_o^2 = sum_j omega x^2 V_j. The yield stress is sigma_y(eps_p) = sigma_y0 + H eps_p,
// i.e. psi_0(eps_p) = (sigma_y0 + H eps_p)^2 / (2 c m). The return (eq. 124 in backward
// Euler) scales the trial state: e^de = beta e^de_tr, d e^dp = (1 - beta) e^de_tr. Then
// sigma_eq = beta sigma_tr and d eps_p = (1 - beta) sigma_tr / (3 mu) exactly, because
// sqrt(c m) alpha = 3 mu sqrt(5/m) (3-D) and 3 mu sqrt(8/(3m)) (2-D) identically. So the
// discrete return is the classical J2 radial return on sigma_eq:
//   d eps_p = (sigma_tr - sigma_y(eps_p,n)) / (3 mu + H),   beta = 1 - 3 mu d eps_p / sigma_tr,
// and a homogeneous uniaxial test has the classical tangent slope E H/(E + H) (H = 0:
// perfect plasticity, Silling's eq. 128-129).
//
// Energy: W = k' theta^2/2 + (alpha/2) sum_j omega (e^de)^2 V_j (seed 003 eq. 104 with the
// elastic part); the plastic work of a step, sum_j (t^d_n + t^d_n+1)/2 (e^dp_n+1 - e^dp_n) V_j,
// is exactly the trapezoidal work of the step minus the change of W, so that kinetic +
// stored + dissipated - external work closes to the time integrator's error.
//
// Plane stress is refused: the model's plastic extension has no dilatation (eq. 127), while
// J2 flow under s_33 = 0 changes the in-plane area (d eps_33^p = -(d eps_11^p + d eps_22^p)),
// and the in-plane criterion gives uniaxial yield at 2 sigma_y/sqrt(3) there. In plane
// strain the same assumption (s_33 = 0 in the plastic range) is the classical one of
// plane-strain plasticity, exact in in-plane shear.
#include <cmath>

#include "horizon/material/model.hpp"

namespace horizon {

// c of sigma_eq^2 = c m ||t^d||_w^2: 1/5 in 3-D, 3/8 in 2-D (derivation above).
inline double ep_equivalent_stress_factor(int dimension) { return dimension == 2 ? 3.0 / 8.0 : 1.0 / 5.0; }

// psi_0 = sigma^2 / (2 c m): 5 sigma^2/(2m) in 3-D, 4 sigma^2/(3m) in 2-D.
inline double ep_yield_value(double yield_stress, double weighted_volume, int dimension) {
  return yield_stress * yield_stress / (2.0 * ep_equivalent_stress_factor(dimension) * weighted_volume);
}

// The equivalent stress of a force state of weighted norm^2 n2 = ||t^d||_w^2.
inline double ep_equivalent_stress(double norm2, double weighted_volume, int dimension) {
  return std::sqrt(ep_equivalent_stress_factor(dimension) * weighted_volume * norm2);
}

// d eps_p per unit ||d e^dp||_o: sqrt(5/m) in 3-D, sqrt(8/(3m)) in 2-D (derivation above).
inline double ep_plastic_strain_factor(double weighted_volume, int dimension) {
  return std::sqrt((dimension == 2 ? 8.0 / 3.0 : 5.0) / weighted_volume);
}

// Deviatoric extension e^d = e - theta |xi| / d (seed 003 sec. 15; digest sec. 8).
inline double deviatoric_extension(double e, double theta, double length, int dimension) {
  return e - theta * length / dimension;
}

// The return mapping of one particle. Input: the trial weighted norm^2 ||t^d_tr||_w^2, m,
// the dimension, mu, sigma_y0, H and eps_p of the committed state. Output: beta (t^d =
// beta t^d_tr, d e^dp = (1 - beta) e^de_tr), d eps_p, and the yield function of the trial.
struct ReturnMap {
  double scale = 1;         // beta
  double plastic_strain = 0;  // d eps_p
  double trial_yield = 0;   // f = ||t^d_tr||_w^2/2 - psi_0(eps_p,n): > 0 means plastic flow
};
inline ReturnMap ep_return_map(double trial_norm2, double weighted_volume, int dimension, double shear_modulus,
                               double yield_stress, double hardening, double eps_p) {
  ReturnMap r;
  const double sy = yield_stress + hardening * eps_p;
  r.trial_yield = 0.5 * trial_norm2 - ep_yield_value(sy, weighted_volume, dimension);
  if (!(r.trial_yield > 0)) return r;
  const double s_trial = ep_equivalent_stress(trial_norm2, weighted_volume, dimension);
  // Classical radial return on sigma_eq (derivation above).
  r.plastic_strain = (s_trial - sy) / (3.0 * shear_modulus + hardening);
  r.scale = 1.0 - 3.0 * shear_modulus * r.plastic_strain / s_trial;
  return r;
}

ModelEntry elastic_plastic_model();

}  // namespace horizon
