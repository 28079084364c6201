#pragma once
// The hypoelastic stress update in the unrotated frame of Flanagan and Taylor 1987 ("An
// accurate numerical algorithm for stress integration with finite rotations", CMAME 62,
// 305-320), with an optional von Mises return: the rate form Peridigm's correspondence
// materials integrate (Elastic, Elastic Plastic and Isotropic Hardening Correspondence).
// Their golds fix it: on ElasticCorrespondenceFullyPrescribedTension (uniaxial strain,
// nu = 0) the gold's Left_Stretch_TensorYY after one step of 2e-9 is 1 + dt D_yy =
// 1.00019996 (D = F_dot F^-1 at the new F = 1.0002), not F_yy = 1.0002, and its Cauchy
// stress is E dt D_yy summed over the steps (39992001.6, 79976008.0, ...), not E (F - 1).
//
// One step from the committed state (F_n, V_n, R_n, sigma_u,n, alpha_n) to F over dt:
//   L = F_dot F^-1 with F_dot = (F - F_n)/dt,  D = sym L,  W = skew L;
//   Omega = W + A, A the skew tensor whose axial vector a solves (tr(V) I - V) a =
//     axial(D V - V D): the spin of R that keeps V symmetric in V_dot = L V - V Omega
//     (Flanagan and Taylor's eq. for omega; derived: for skew A and symmetric V,
//     A V + V A is skew with axial vector (tr(V) I - V) a);
//   R = (I - dt/2 Omega)^-1 (I + dt/2 Omega) R_n  (their midpoint rotation update),
//   V = V_n + dt (L V_n - V_n Omega);
//   d = R^T D R  (the unrotated rate of deformation),
//   sigma_u = sigma_u,n + dt (lambda tr(d) I + 2 mu d), then, with a yield stress, where
//     the trial von Mises stress q exceeds y_n = sigma_y + H alpha_n, the radial return
//     of its deviator s = s_trial y/q (Simo and Hughes 1998, "Computational
//     Inelasticity", box 3.1) with Peridigm's increment of the equivalent plastic strain
//       Delta alpha = (q^2 - y_n^2) / (6 mu q),   y = y_n + H Delta alpha,
//     the plastic work of the return taken by the trapezoid rule, (s_trial + s)/2 :
//     Delta eps_p = (q^2 - y_n^2)/(6 mu), over q. Fitted from the golds, not published:
//     ElasticPlasticCorrespondenceFullyPrescribedTension (H = 0) has its stresses from
//     the standard return to 1e-15 and its Equivalent_Plastic_Strain from this increment
//     to 1e-15 at all four frames, where the standard (q - y_n)/(3 mu) is 11 % above; on
//     IsotropicHardeningPlasticFullyPrescribedTension_NoFlaw (H = 5e9) it leaves the von
//     Mises stress 0.09 % below the gold's (the standard return: 2.3 % above), the
//     hardening rule of Peridigm not being recovered exactly;
//   sigma = R sigma_u R^T,  P = J sigma F^-T.
// dt <= 0 (an evaluation at the committed time) keeps the committed stress.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "horizon/material/classical/stress_laws.hpp"

namespace horizon::classical {

struct HypoState {
  Mat3 F = Mat3::Identity();        // the deformation gradient of the committed step
  Mat3 V = Mat3::Identity();        // left stretch
  Mat3 R = Mat3::Identity();        // rotation
  Mat3 sigma_u = Mat3::Zero();      // unrotated Cauchy stress [Pa]
  double alpha = 0;                 // equivalent plastic strain
};

struct HypoResult {
  LawResult law;
  Mat3 d = Mat3::Zero();  // unrotated rate of deformation [1/s]
};

// The skew tensor of axial vector a (A b = a x b) and the axial vector of skew S.
inline Mat3 skew_of(const Eigen::Vector3d& a) {
  Mat3 A;
  A << 0, -a[2], a[1], a[2], 0, -a[0], -a[1], a[0], 0;
  return A;
}
inline Eigen::Vector3d axial_of(const Mat3& S) { return {S(2, 1), S(0, 2), S(1, 0)}; }

// `yield` <= 0: elastic. `plastic_work`: sigma_y Delta alpha + H (alpha^2 - alpha_n^2)/2.
// `Fdot`, when given, is F_dot (the caller's, from the displacement increments: free of
// the cancellation of F - F_n); else (F - F_n)/dt.
inline HypoResult hypoelastic_step(const Elastic& c, double yield, double hardening, const HypoState& n,
                                   const Mat3& F, double dt, HypoState& trial, double& plastic_work,
                                   const Mat3* Fdot = nullptr) {
  HypoResult out;
  trial = n;
  plastic_work = 0;
  const Mat3 I = Mat3::Identity();
  const double J = F.determinant();
  if (!(J > 0) || !std::isfinite(J)) {
    out.law.ok = false;
    return out;
  }
  const Mat3 Finv = F.inverse();
  if (dt > 0) {
    const Mat3 L = (Fdot ? *Fdot : Mat3((F - n.F) / dt)) * Finv;
    const Mat3 D = 0.5 * (L + L.transpose()), W = 0.5 * (L - L.transpose());
    const Mat3 C = D * n.V - n.V * D;  // skew
    const Mat3 M = n.V.trace() * I - n.V;
    const Eigen::Vector3d a = M.lu().solve(axial_of(C));
    const Mat3 Omega = W + skew_of(a);
    trial.R = (I - 0.5 * dt * Omega).lu().solve((I + 0.5 * dt * Omega) * n.R);
    trial.V = n.V + dt * (L * n.V - n.V * Omega);
    trial.F = F;
    out.d = trial.R.transpose() * D * trial.R;
    Mat3 s = n.sigma_u + dt * (c.lambda * out.d.trace() * I + 2.0 * c.mu * out.d);
    const double p = s.trace() / 3.0;
    Mat3 dev = s - p * I;
    if (yield > 0) {
      const double q = std::sqrt(1.5 * (dev.array() * dev.array()).sum());
      const double limit = yield + hardening * n.alpha;
      if (q > limit) {
        const double da = (q * q - limit * limit) / (6.0 * c.mu * q);
        dev *= std::min(limit + hardening * da, q) / q;
        trial.alpha = n.alpha + da;
        plastic_work = yield * da + 0.5 * hardening * (trial.alpha * trial.alpha - n.alpha * n.alpha);
      }
    }
    trial.sigma_u = p * I + dev;
  }
  const Mat3 sigma = trial.R * trial.sigma_u * trial.R.transpose();
  out.law.sigma = sigma;
  out.law.P = J * sigma * Finv.transpose();
  // The elastic energy of the linear law at this stress: p^2/(2 kappa) + |s|^2/(4 mu).
  const double p = trial.sigma_u.trace() / 3.0;
  const Mat3 dev = trial.sigma_u - p * I;
  out.law.W = (c.kappa > 0 ? 0.5 * p * p / c.kappa : 0.0) + (c.mu > 0 ? (dev.array() * dev.array()).sum() / (4.0 * c.mu) : 0.0);
  return out;
}

}  // namespace horizon::classical
