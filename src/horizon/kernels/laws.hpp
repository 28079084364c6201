#pragma once
// The correspondence model's finite-strain stress laws (material/classical/stress_laws.hpp:
// neo_hookean, j2_plasticity; the formulas and their sources are there) as device-portable
// functions (core/portable.hpp, issue 30), and `law_row`: one particle of the affine pass
// (kernels/affine.hpp) from its sums of K and N to its record, for the linear elastic,
// neo-Hookean and J2 laws, with the J2 history as plain numbers. Row-major double[9].
//
// Bits. Each function keeps the operations of its Eigen form in Eigen's order as this
// build compiles them (affine.hpp's header lists the orders of products, traces and
// contractions; eigen3.hpp those of the determinant and the SVD under the polar
// decomposition), so the host's answers kept their bits when Correspondence::affine_row
// moved onto them (tests/unit/test_law_kernels.cpp compares them with stress_laws.hpp
// on random inputs, bit for bit). Where Eigen forms `s * (A - t * I)` the identity's
// zeros are multiplied and added as Eigen does (a signed zero can then differ from a
// shortcut). Transcendentals: cbrt and log are the host's <cmath> or the device's library
// (a device may round them differently in the last bit).
#include <cmath>

#include "horizon/core/portable.hpp"
#include "horizon/kernels/affine.hpp"
#include "horizon/kernels/eigen3.hpp"

namespace horizon::kernels {

HORIZON_HD inline double cube_root(double x) {
#if defined(__CUDA_ARCH__)
  return ::cbrt(x);
#else
  return std::cbrt(x);
#endif
}

HORIZON_HD inline double identity3(int k) { return (k % 4 == 0) ? 1.0 : 0.0; }

// What a law gives: P and sigma (row-major), the stored energy W; ok false: the law is
// undefined at F (det F <= 0), P = sigma = 0, W = 0.
struct LawStress {
  bool ok = false;
  double P[9];
  double sigma[9];
  double W = 0;
};

HORIZON_HD inline void clear_law(LawStress& r) {
  r.ok = false;
  r.W = 0;
  for (int k = 0; k < 9; ++k) r.P[k] = 0.0, r.sigma[k] = 0.0;
}

// P = tau F^-T (F^-1 by cofactors, then the product with its transpose).
HORIZON_HD inline void piola_of_kirchhoff(const double* tau, const double* F, double* P) {
  double Finv[9];
  mat3_inverse(F, Finv);
  mat3_mul_transposed(tau, Finv, P);
}

// Bonet and Wood's compressible neo-Hookean solid (stress_laws.hpp neo_hookean):
// tau = mu J^(-2/3) dev(b) + kappa J (J - 1) I, sigma = tau/J, P = tau F^-T,
// W = mu/2 (J^(-2/3) I1 - 3) + kappa/2 (J - 1)^2.
HORIZON_HD inline void neo_hookean_stress(double mu, double kappa, const double* F, LawStress& r) {
  clear_law(r);
  const double J = mat3_det(F);
  if (!(J > 0) || !finite(J)) return;
  double b[9];
  mat3_mul_transposed(F, F, b);
  const double I1 = mat3_trace(b), Jm23 = cube_root(1.0 / (J * J));
  const double a = mu * Jm23, v = kappa * J * (J - 1.0), third = I1 / 3.0;
  double tau[9];
  for (int k = 0; k < 9; ++k) tau[k] = a * (b[k] - third * identity3(k)) + v * identity3(k);
  for (int k = 0; k < 9; ++k) r.sigma[k] = tau[k] / J;
  piola_of_kirchhoff(tau, F, r.P);
  r.W = 0.5 * mu * (Jm23 * I1 - 3.0) + 0.5 * kappa * (J - 1.0) * (J - 1.0);
  r.ok = true;
}

// The J2 law's history (stress_laws.hpp J2State): E_p row-major, the equivalent plastic
// strain.
struct J2History {
  double plastic_strain[9];
  double alpha;
};

// Von Mises plasticity on the Hencky strain of the unrotated frame with the radial return
// (stress_laws.hpp j2_plasticity): trial receives the history after the evaluation,
// work the plastic work of the step [J/m^3]. lambda is not read (tau_u = kappa tr(E_e) I +
// 2 mu dev(E_e)).
HORIZON_HD inline void j2_stress(double mu, double kappa, double yield_stress, double hardening,
                                 const J2History& committed, const double* F, J2History& trial, double& work,
                                 LawStress& r) {
  clear_law(r);
  trial = committed;
  work = 0;
  double R[9], logU[9];
  if (!polar_log3(F, R, logU)) return;
  double Ee[9];
  for (int k = 0; k < 9; ++k) Ee[k] = logU[k] - committed.plastic_strain[k];
  const double tr = mat3_trace(Ee), two_mu = 2.0 * mu, third = tr / 3.0;
  double s[9];
  for (int k = 0; k < 9; ++k) s[k] = two_mu * (Ee[k] - third * identity3(k));
  const double s_norm = root(mat3_contract(s, s));
  const double k23 = root(2.0 / 3.0);
  const double f = s_norm - k23 * (yield_stress + hardening * committed.alpha);
  if (f > 0) {
    // Simo and Hughes 1998, box 3.2: the radial return along the trial direction.
    const double dgamma = f / (2.0 * mu + 2.0 * hardening / 3.0);
    double n[9];
    for (int k = 0; k < 9; ++k) n[k] = s[k] / s_norm;
    const double step = 2.0 * mu * dgamma;
    for (int k = 0; k < 9; ++k) s[k] = s[k] - step * n[k];
    for (int k = 0; k < 9; ++k) trial.plastic_strain[k] = committed.plastic_strain[k] + dgamma * n[k];
    trial.alpha = committed.alpha + k23 * dgamma;
    const double da = trial.alpha - committed.alpha;
    work = yield_stress * da + 0.5 * hardening * (trial.alpha * trial.alpha - committed.alpha * committed.alpha);
  }
  const double kt = kappa * tr;
  double tau_u[9], Rt[9], tau[9];
  for (int k = 0; k < 9; ++k) tau_u[k] = kt * identity3(k) + s[k];
  mat3_mul(R, tau_u, Rt);
  mat3_mul_transposed(Rt, R, tau);
  const double J = mat3_det(F);
  for (int k = 0; k < 9; ++k) r.sigma[k] = tau[k] / J;
  piola_of_kirchhoff(tau, F, r.P);
  r.W = 0.5 * kappa * tr * tr + mat3_contract(s, s) / (4.0 * mu);
  r.ok = true;
}

// ---- one whole particle of the affine pass ----

enum LawKind : int { kLinearElasticLaw = 0, kNeoHookeanLaw = 1, kJ2Law = 2 };

// The constants of a law_row (correspondence's LawSettings as plain numbers).
struct LawConstants {
  int law = kLinearElasticLaw;
  double lambda = 0, mu = 0, kappa = 0;
  double yield_stress = 0, hardening = 0;  // j2
};

// The end of a law row once the law ran at F: the von Mises stress of sigma, the energy,
// the record {P K^-1 - G F, G} (A = 0 where the law refused F: the stabilisation stays).
// Two calls, not one with `r.ok ? r.P : nullptr`: a pointer chosen at run time would put
// r in a device thread's local memory.
HORIZON_HD inline void law_row_finish(const LawStress& r, const double* Kinv, double G, AffineRow& out, double* rec) {
  out.von_mises = von_mises(r.sigma);
  out.W = r.ok ? r.W : 0.0;
  if (r.ok)
    affine_record_of_stress(r.P, Kinv, out.F, G, rec);
  else
    affine_record(nullptr, out.F, G, rec);
}

// Row i from its sums (K then N, GradientSums) to its record, as linear_elastic_row, for
// the law of `c`: gradient_finish, the law at F from the committed history (J2; the others
// ignore it, trial = committed), the von Mises stress of sigma, the record {P K^-1 - G F,
// G} (A = 0 where the law refuses F: the stabilisation stays). `work`: the step's plastic
// work [J/m^3] (0 but for J2). A refused shape tensor: record 0, trial = committed.
HORIZON_HD inline AffineRow law_row(const double* sums, int d, double tolerance, const LawConstants& c, double G,
                                    const J2History& committed, J2History& trial, double& work, double* rec) {
  trial = committed;
  work = 0;
  if (c.law == kLinearElasticLaw) return linear_elastic_row(sums, d, tolerance, c.lambda, c.mu, G, rec);
  AffineRow out;
  double Kinv[9];
  if (!law_row_gradient(sums, d, tolerance, Kinv, out, rec)) return out;
  LawStress r;
  if (c.law == kNeoHookeanLaw)
    neo_hookean_stress(c.mu, c.kappa, out.F, r);
  else
    j2_stress(c.mu, c.kappa, c.yield_stress, c.hardening, committed, out.F, trial, work, r);
  law_row_finish(r, Kinv, G, out, rec);
  return out;
}

}  // namespace horizon::kernels
