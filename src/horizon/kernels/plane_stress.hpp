#pragma once
// The correspondence family's total-form stress laws at one point (the linear elastic,
// neo-Hookean and J2 laws of kernels/laws.hpp) with what the host wrapped around them in
// Eigen: 2-D plane stress's secant iteration for the out-of-plane stretch
// (classical/stress_laws.hpp plane_stress) and the thermal expansion's multiplicative
// split (correspondence.cpp evaluate_with_expansion), as device-portable functions
// (core/portable.hpp, issue 30). correspondence::evaluate_law and evaluate_with_expansion
// call `law_point` for these laws, so the correspondence model (its affine row and its
// general pass), its tangent and the bond-associated model's bonds run this code on the host.
//
// Bits: the operations of the Eigen forms in their order (tests/unit/test_plane_stress_
// kernels.cpp compares them bit for bit on random inputs): F * inverse and
// (J P) inverse^T as 3 x 3 products in mat3_mul's order, the determinant in Eigen's
// (mat3_det). The iteration's scale max(max |sigma_ab| over the in-plane 2 x 2 block,
// 1e-12 mu) is a maximum, which no order changes for finite stresses.
#include "horizon/core/portable.hpp"
#include "horizon/kernels/affine.hpp"
#include "horizon/kernels/eigen3.hpp"
#include "horizon/kernels/laws.hpp"
#include "horizon/kernels/unified.hpp"

namespace horizon::kernels {

// The law of c at the full 3 x 3 F from the committed J2 history (the others ignore it):
// trial receives the history after the evaluation (= committed but for J2), work the
// step's plastic work [J/m^3]. The linear elastic law's P is its sigma.
HORIZON_HD inline void law_stress(const LawConstants& c, const J2History& committed, const double* F,
                                  J2History& trial, double& work, LawStress& r) {
  trial = committed;
  work = 0;
  if (c.law == kLinearElasticLaw) {
    clear_law(r);
    linear_elastic_stress(c.lambda, c.mu, F, r.sigma, r.W);
    for (int k = 0; k < 9; ++k) r.P[k] = r.sigma[k];
    r.ok = true;
  } else if (c.law == kNeoHookeanLaw) {
    neo_hookean_stress(c.mu, c.kappa, F, r);
  } else {
    j2_stress(c.mu, c.kappa, c.yield_stress, c.hardening, committed, F, trial, work, r);
  }
}

// The iteration's stress scale: the largest in-plane |sigma_ab|, at least 1e-12 mu.
HORIZON_HD inline double plane_stress_scale(const LawStress& r, double mu) {
  double m = absolute(r.sigma[0]);
  const int in_plane[3] = {3, 1, 4};  // column-major after (0, 0), as Eigen walks the block
  for (int q = 0; q < 3; ++q) {
    const double v = absolute(r.sigma[in_plane[q]]);
    m = m < v ? v : m;
  }
  const double floor = 1e-12 * mu;
  return m < floor ? floor : m;
}

// The law at F (row-major, written to): with `iterate` false once, at F as given; with it
// true the plane-stress iteration below on F's in-plane block, F33 = F[8] the start.
// One call site of the law for the whole iteration: on a device the J2 law (the SVD)
// inlined once, not three times.
HORIZON_HD inline void law_iterated(const LawConstants& c, const J2History& committed, double* F, bool iterate,
                                    double& lambda3, J2History& trial, double& work, LawStress& r) {
  constexpr double kTolerance = 1e-14;
  constexpr int kSteps = 60;
  double x = F[8], x_prev = 0, g_prev = 0;
  for (int it = 0; it <= kSteps + 1; ++it) {
    F[8] = x;
    law_stress(c, committed, F, trial, work, r);
    if (!iterate) return;
    if (it == kSteps + 1) break;  // the law at the last iterate
    const double g = r.sigma[8];
    if (!r.ok || absolute(g) <= kTolerance * plane_stress_scale(r, c.mu) || (it > 0 && g == g_prev)) break;
    double next;
    if (it == 0) {  // the elastic estimate with modulus lambda + 2 mu
      next = x - g / (c.lambda + 2.0 * c.mu);
      if (!(next > 0)) next = 0.5 * x;
    } else {  // a secant step
      next = x - g * (x - x_prev) / (g - g_prev);
      if (!(next > 0) || !finite(next)) next = 0.5 * x;
    }
    x_prev = x, g_prev = g, x = next;
  }
  lambda3 = x;
}

// Plane stress (classical/stress_laws.hpp plane_stress): F2's in-plane 2 x 2 block (its
// other entries ignored) with F33 = lambda3 > 0 such that sigma33 = 0, by the secant
// iteration started at `lambda3` (the committed value; 1 if it is not a positive finite
// number) and its elastic estimate with modulus lambda + 2 mu; at most 60 steps, then the
// law at the last iterate. lambda3 returns the stretch of the returned evaluation; r,
// trial and work are those of that evaluation.
HORIZON_HD inline void plane_stress_law(const LawConstants& c, const J2History& committed, const double* F2,
                                        double& lambda3, J2History& trial, double& work, LawStress& r) {
  double F[9] = {F2[0], F2[1], 0.0, F2[3], F2[4], 0.0, 0.0, 0.0, 0.0};
  F[8] = lambda3 > 0 && finite(lambda3) ? lambda3 : 1.0;
  law_iterated(c, committed, F, true, lambda3, trial, work, r);
}

// The law as the correspondence family evaluates it at a point (correspondence.hpp
// evaluate_law and correspondence.cpp evaluate_with_expansion, for the total-form laws):
// in 2-D plane stress (`plane_stress`) by the iteration above, from the committed stretch
// lambda3 (returned: the trial one; unchanged otherwise); with a thermal strain eps != 0 on
// the split F = F_e F_th, F_th = (1 + eps) on the first `dimension` axes (Lu and Pister
// 1975): the law at F F_th^-1, then P = J_th P_e F_th^-T, W and the work times J_th,
// J_th = 1/det F_th^-1.
HORIZON_HD inline void law_point(const LawConstants& c, int dimension, bool plane_stress, double eps,
                                 const J2History& committed, const double* F, double& lambda3, J2History& trial,
                                 double& work, LawStress& r) {
  double inverse[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  // The law's F in an array of its own in both cases (a pointer chosen at run time would
  // put the arrays in a device thread's local memory).
  double Fl[9];
  if (eps != 0) {
    // Constant indices (an index known at run time would put `inverse` in local memory).
    const double shrink = 1.0 / (1.0 + eps);
    inverse[0] = shrink;
    if (dimension > 1) inverse[4] = shrink;
    if (dimension > 2) inverse[8] = shrink;
    mat3_mul(F, inverse, Fl);
  } else {
    for (int k = 0; k < 9; ++k) Fl[k] = F[k];
  }
  if (plane_stress) {
    Fl[2] = 0.0, Fl[5] = 0.0, Fl[6] = 0.0, Fl[7] = 0.0;
    Fl[8] = lambda3 > 0 && finite(lambda3) ? lambda3 : 1.0;
  }
  law_iterated(c, committed, Fl, plane_stress, lambda3, trial, work, r);
  if (eps == 0) return;
  const double J = 1.0 / mat3_det(inverse);
  double JP[9];
  for (int k = 0; k < 9; ++k) JP[k] = J * r.P[k];
  mat3_mul_transposed(JP, inverse, r.P);
  r.W *= J;
  work *= J;
}

// Row i of the affine pass (kernels/affine.hpp) for a total-form law as law_point takes it
// (2-D plane stress's iteration included; no thermal strain: the affine pass runs without
// one): from its sums (K then N) to its record, as law_row (kernels/laws.hpp) — gradient_finish,
// the law from the committed history and stretch lambda3_n, the von Mises stress of sigma,
// the record {P K^-1 - G F, G} (A = 0 where the law refuses F). trial, lambda3 and work:
// the evaluation's history, stretch and plastic work. A refused shape tensor: record 0,
// trial = committed, lambda3 = lambda3_n, work 0.
HORIZON_HD inline AffineRow law_point_row(const double* sums, int d, double tolerance, const LawConstants& c,
                                          bool plane_stress, double G, const J2History& committed, double lambda3_n,
                                          J2History& trial, double& lambda3, double& work, double* rec) {
  trial = committed;
  lambda3 = lambda3_n;
  work = 0;
  AffineRow out;
  double Kinv[9];
  if (!law_row_gradient(sums, d, tolerance, Kinv, out, rec)) return out;
  LawStress r;
  law_point(c, d, plane_stress, 0.0, committed, out.F, lambda3, trial, work, r);
  law_row_finish(r, Kinv, G, out, rec);
  return out;
}

}  // namespace horizon::kernels
