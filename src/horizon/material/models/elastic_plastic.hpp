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
// The plastic multiplier lambda (Mitchell's, the variable Peridigm writes as Lambda). The
// flow rule in backward Euler is e^dp_n+1 = e^dp_n + d lambda grad psi(t^d_n+1), with
// grad psi = t^d/omega (= t^d for omega = 1, Mitchell's case). The return above gives
// d e^dp = (1 - beta) e^de_tr and t^d_n+1 = alpha omega beta e^de_tr, so
//   d lambda = (1 - beta) / (alpha beta)      (0 in an elastic step, beta = 1),
// and lambda is the sum of the committed steps' d lambda. With perfect plasticity and
// yield_reference particle this is lambda = m eps_p / (5 sigma_y) in 3-D.
//
// yield_reference: continuum takes psi_0 = sigma_y^2/(2 c m_c) with m_c = 4 pi int omega r^4 dr
// of the full sphere instead of the particle's m: Mitchell's psi_0 = 25 sigma_y^2/(8 pi
// delta^5) for omega = 1 (SAND2011-3166), which Peridigm uses whatever the lattice, so
// that the discrete model yields below sigma_y where m < m_c (ep_cube: m = 0.375 against
// m_c = 41.2; checked against Peridigm's gold, docs/peridigm.md).
//
// Energy: W = k' theta^2/2 + (alpha/2) sum_j omega (e^de)^2 V_j (seed 003 eq. 104 with the
// elastic part). The dissipated energy of a step (material/models/history_ledger.hpp) is
// the trapezoidal work of the step less the change of W; without broken bonds that is
// exactly the plastic work sum_j (t^d_n + t^d_n+1)/2 (e^dp_n+1 - e^dp_n) V_j, so that
// kinetic + stored + dissipated - external work closes to the time integrator's error.
//
// Plane stress is refused: the model's plastic extension has no dilatation (eq. 127), while
// J2 flow under s_33 = 0 changes the in-plane area (d eps_33^p = -(d eps_11^p + d eps_22^p)),
// and the in-plane criterion gives uniaxial yield at 2 sigma_y/sqrt(3) there. In plane
// strain the same assumption (s_33 = 0 in the plastic range) is the classical one of
// plane-strain plasticity, exact in in-plane shear.
#include <cmath>

#include "horizon/kernels/ordinary.hpp"
#include "horizon/material/model.hpp"

namespace horizon {

// The kernels of the derivation above (c, psi_0, sigma_eq, e^d, the return mapping) are
// device-portable functions in kernels/ordinary.hpp (issue 30), which the rows call.
using kernels::deviatoric_extension;
using kernels::ep_equivalent_stress;
using kernels::ep_equivalent_stress_factor;
using kernels::ep_return_map;
using kernels::ep_yield_value;
using kernels::ReturnMap;

// d eps_p per unit ||d e^dp||_o: sqrt(5/m) in 3-D, sqrt(8/(3m)) in 2-D (derivation above).
inline double ep_plastic_strain_factor(double weighted_volume, int dimension) {
  return std::sqrt((dimension == 2 ? 8.0 / 3.0 : 5.0) / weighted_volume);
}

// d lambda of a step whose return scaled the trial deviatoric state by beta (above).
using kernels::plastic_multiplier_step;  // (kernels/ordinary.hpp)

ModelEntry elastic_plastic_model();

}  // namespace horizon
