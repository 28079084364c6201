#pragma once
// Classical (local) stress laws for the correspondence model (material/models/
// correspondence.hpp): each maps a deformation gradient F (3 x 3; det F > 0) and, for the
// plastic law, the committed history to the first Piola-Kirchhoff stress P, the Cauchy
// stress sigma and the stored energy density W per reference volume. Pure functions: the
// trial history is returned, never written over the committed one.
//
//   linear_elastic: small strain, eps = sym(F) - I, sigma = lambda tr(eps) I + 2 mu eps,
//     P = sigma (Piola and Cauchy are not told apart at small strain), W = sigma:eps/2.
//     Not objective: a rigid rotation by theta strains it by O(theta^2).
//   neo_hookean: the compressible (decoupled) neo-Hookean solid of Bonet and Wood 2008,
//     "Nonlinear Continuum Mechanics for Finite Element Analysis", 2nd ed., sec. 6.6
//     ("nearly incompressible neo-Hookean", volumetric energy kappa/2 (J - 1)^2):
//       W = mu/2 (J^(-2/3) I1 - 3) + kappa/2 (J - 1)^2,   I1 = tr(F^T F), J = det F,
//       tau = J sigma = mu J^(-2/3) dev(b) + kappa J (J - 1) I,   b = F F^T,
//       P = tau F^-T.
//     At small strain it is Hooke's law with shear modulus mu and bulk modulus kappa.
//   j2: von Mises plasticity with linear isotropic hardening in the unrotated frame of
//     the polar decomposition F = R U, taken anew at every evaluation (classical/polar.hpp):
//     the total strain is the Hencky strain E = ln U, split additively E = E_e + E_p
//     (the logarithmic-strain-space plasticity of Miehe, Apel and Lambrecht 2002, CMAME
//     191, 5383-5425, sec. 2, with an isotropic quadratic elastic energy); the unrotated
//     Kirchhoff stress tau_u = kappa tr(E_e) I + 2 mu dev(E_e) is returned radially to
//     the yield surface |dev tau_u| = sqrt(2/3) (sigma_y + H alpha) by the closest-point
//     return of Simo and Hughes 1998, "Computational Inelasticity", box 3.2 (Delta gamma =
//     f_trial / (2 mu + 2H/3)), and rotated: tau = R tau_u R^T, sigma = tau/J, P = tau F^-T.
//     History: E_p (symmetric, traceless) and the equivalent plastic strain alpha.
//     Rotation enters only through R, so the law is objective. tau_u is the exact
//     conjugate of ln U when E_p is coaxial with U (proportional loading); otherwise this
//     is the usual approximation of the rotated formulation (Miehe et al. project the
//     stress exactly; we do not).
//     The plastic work of the step, int sigma_y d alpha = sigma_y Delta alpha +
//     H (alpha_new^2 - alpha_old^2)/2 per reference volume, is what goes to the ledger
//     as dissipated; W is the elastic energy kappa/2 tr(E_e)^2 + mu |dev E_e|^2.
//
// Plane stress (2-D): plane_stress() finds the out-of-plane stretch F33 with sigma33 = 0
// by a secant iteration started from the elastic estimate; plane strain takes F33 = 1.
// The runs evaluate these laws in the device-portable kernels (kernels/laws.hpp, and
// kernels/plane_stress.hpp for the iteration and the thermal split, through
// correspondence::total_form_law); the forms here are their reference (the unit tests
// hold the kernels to them bit for bit) and what the tests of the laws call.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "horizon/material/classical/polar.hpp"

namespace horizon::classical {

struct Elastic {
  double lambda = 0, mu = 0, kappa = 0;  // Lame's constants and the bulk modulus
};

// From the bulk and shear moduli (3-D constants; plane stress is handled by plane_stress).
inline Elastic elastic_from_bulk_shear(double bulk, double shear) {
  return {bulk - 2.0 * shear / 3.0, shear, bulk};
}

struct LawResult {
  Mat3 P = Mat3::Zero();      // first Piola-Kirchhoff stress [Pa]
  Mat3 sigma = Mat3::Zero();  // Cauchy stress [Pa]
  double W = 0;               // stored (elastic) energy per reference volume [J/m^3]
  bool ok = true;             // false: det F <= 0, the law is undefined (P = 0)
};

inline LawResult linear_elastic(const Elastic& c, const Mat3& F) {
  LawResult r;
  const Mat3 eps = 0.5 * (F + F.transpose()) - Mat3::Identity();
  r.sigma = c.lambda * eps.trace() * Mat3::Identity() + 2.0 * c.mu * eps;
  r.P = r.sigma;
  r.W = 0.5 * (r.sigma.array() * eps.array()).sum();
  return r;
}

inline LawResult neo_hookean(const Elastic& c, const Mat3& F) {
  LawResult r;
  const double J = F.determinant();
  if (!(J > 0) || !std::isfinite(J)) {
    r.ok = false;
    return r;
  }
  const Mat3 b = F * F.transpose();
  const double I1 = b.trace(), Jm23 = std::cbrt(1.0 / (J * J));
  const Mat3 tau = c.mu * Jm23 * (b - (I1 / 3.0) * Mat3::Identity()) + c.kappa * J * (J - 1.0) * Mat3::Identity();
  r.sigma = tau / J;
  r.P = tau * F.inverse().transpose();
  r.W = 0.5 * c.mu * (Jm23 * I1 - 3.0) + 0.5 * c.kappa * (J - 1.0) * (J - 1.0);
  return r;
}

struct J2Params {
  double yield_stress = 0;       // sigma_y [Pa]
  double hardening_modulus = 0;  // H [Pa]: sigma_y(alpha) = sigma_y + H alpha
};

struct J2State {
  Mat3 plastic_strain = Mat3::Zero();  // E_p, unrotated Hencky plastic strain (traceless)
  double alpha = 0;                    // equivalent plastic strain
};

// `committed` is the history at the start of the step; `trial` receives the history after
// this evaluation and `plastic_work` the energy dissipated in the step [J/m^3].
inline LawResult j2_plasticity(const Elastic& c, const J2Params& p, const J2State& committed, const Mat3& F,
                               J2State& trial, double& plastic_work) {
  LawResult r;
  trial = committed;
  plastic_work = 0;
  const Polar pd = polar_decomposition(F);
  if (!pd.ok) {
    r.ok = false;
    return r;
  }
  const Mat3 I = Mat3::Identity();
  const Mat3 Ee = pd.log_U - committed.plastic_strain;
  const double tr = Ee.trace();
  Mat3 s = 2.0 * c.mu * (Ee - (tr / 3.0) * I);
  const double s_norm = std::sqrt((s.array() * s.array()).sum());
  const double k23 = std::sqrt(2.0 / 3.0);
  const double f = s_norm - k23 * (p.yield_stress + p.hardening_modulus * committed.alpha);
  if (f > 0) {
    // Radial return (Simo and Hughes 1998, box 3.2): the flow direction is the trial one.
    const double dgamma = f / (2.0 * c.mu + 2.0 * p.hardening_modulus / 3.0);
    const Mat3 n = s / s_norm;
    s -= 2.0 * c.mu * dgamma * n;
    trial.plastic_strain = committed.plastic_strain + dgamma * n;
    trial.alpha = committed.alpha + k23 * dgamma;
    const double da = trial.alpha - committed.alpha;
    plastic_work = p.yield_stress * da +
                   0.5 * p.hardening_modulus * (trial.alpha * trial.alpha - committed.alpha * committed.alpha);
  }
  const Mat3 tau_u = c.kappa * tr * I + s;
  const Mat3 tau = pd.R * tau_u * pd.R.transpose();
  const double J = F.determinant();
  r.sigma = tau / J;
  r.P = tau * F.inverse().transpose();
  // Elastic energy of E_e = E - E_p(new): kappa/2 tr^2 + mu |dev E_e|^2 = kappa/2 tr^2 + |s|^2/(4 mu).
  r.W = 0.5 * c.kappa * tr * tr + (s.array() * s.array()).sum() / (4.0 * c.mu);
  return r;
}

// Plane stress: F2 holds the in-plane deformation (F2(2,2), F2(0,2), ... ignored); finds
// F33 = lambda3 > 0 with sigma33(F) = 0 for law(F), F = [F2 in-plane, lambda3]. The
// secant iteration starts at `lambda3` (the committed value is a good guess) and its
// elastic estimate with modulus lambda + 2 mu; lambda3 returns the converged value.
// A linear law converges in one step. law(F) must return a LawResult.
template <class Law>
LawResult plane_stress(const Mat3& F2, const Elastic& c, double& lambda3, Law&& law) {
  Mat3 F = Mat3::Zero();
  F.topLeftCorner<2, 2>() = F2.topLeftCorner<2, 2>();
  double x0 = lambda3 > 0 && std::isfinite(lambda3) ? lambda3 : 1.0;
  F(2, 2) = x0;
  LawResult r0 = law(F);
  auto scale_of = [&](const LawResult& r) {
    return std::max(r.sigma.topLeftCorner<2, 2>().cwiseAbs().maxCoeff(), 1e-12 * c.mu);
  };
  constexpr double kTolerance = 1e-14;
  if (!r0.ok || std::abs(r0.sigma(2, 2)) <= kTolerance * scale_of(r0)) {
    lambda3 = x0;
    return r0;
  }
  double g0 = r0.sigma(2, 2);
  double x1 = x0 - g0 / (c.lambda + 2.0 * c.mu);
  if (!(x1 > 0)) x1 = 0.5 * x0;
  for (int it = 0; it < 60; ++it) {
    F(2, 2) = x1;
    const LawResult r1 = law(F);
    const double g1 = r1.sigma(2, 2);
    if (!r1.ok || std::abs(g1) <= kTolerance * scale_of(r1) || g1 == g0) {
      lambda3 = x1;
      return r1;
    }
    double x2 = x1 - g1 * (x1 - x0) / (g1 - g0);
    if (!(x2 > 0) || !std::isfinite(x2)) x2 = 0.5 * x1;
    x0 = x1, g0 = g1, x1 = x2;
  }
  F(2, 2) = x1;
  lambda3 = x1;
  return law(F);
}

}  // namespace horizon::classical
