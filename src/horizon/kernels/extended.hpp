#pragma once
// The per-bond work of Tupek's extended correspondence in its pair form (material/models/
// extended_correspondence.{hpp,cpp}, ExtendedCorrespondence::pair_forces; docs/design.md
// "The pair form") as device-portable functions (core/portable.hpp, issue 30): the bond
// geometry (H<xi> of Tupek's eq. 4.4 and the normal projector p from n = xi/|xi|), the
// pair strain, the strain sum of the breaking sweep, and the pair sum's bond term
//   T_ij - T_ji = omega g ((A_i . h + 2 coef r_ij) + (A_j . h + 2 coef r_ji)) Y + ...
// (the volumetric gradient's omega PK xi terms: kernels/extended_law.hpp pressure_bond_term).
// Symmetric tensors are 6-vectors (11, 22, 33, 23, 13, 12) as double[6], the records'
// Eigen vectors read through .data().
//
// Bits: the host's pass computed these with Eigen 6-vectors; the dot product below keeps
// the order Eigen's SSE2 packets give it in this build (pairs of entries in two lanes,
// lane l = e_l + (e_(l+2) + e_(l+4)), then lane 0 + lane 1), so the pass kept its bits
// (tests/unit/test_affine_kernels.cpp compares it with Eigen's).
#include "horizon/core/portable.hpp"
#include "horizon/kernels/tupek.hpp"

namespace horizon::kernels {

// The functions below that take a type T compute one bond (T = double) or eight at once
// (T a vector of eight doubles, the pair form's lanes: extended_correspondence.cpp
// pair_*_lanes), with the same IEEE operations in the same order in every lane.

// a . b of two 6-vectors (plain components; the contraction's weights are in the vectors).
template <class T>
HORIZON_HD_INLINE T dot6(const T* a, const T* b) {
  T e[6];
  for (int k = 0; k < 6; ++k) e[k] = a[k] * b[k];
  return (e[0] + (e[2] + e[4])) + (e[1] + (e[3] + e[5]));
}

// p . (a + b)/2: the midpoint residual's projection.
template <class T>
HORIZON_HD_INLINE T dot6_mid(const T* p, const T* a, const T* b) {
  T e[6];
  for (int k = 0; k < 6; ++k) e[k] = p[k] * (0.5 * (a[k] + b[k]));
  return (e[0] + (e[2] + e[4])) + (e[1] + (e[3] + e[5]));
}

// H<xi> of Tupek's (4.4) from n = xi/|xi|: 3-D 5/2 n n - 1/2 I; 2-D 2 n n - 1/2 I_2.
template <class T>
HORIZON_HD_INLINE void unit_shape_state(const T* n, int dimension, T* h) {
  const double a = dimension == 3 ? 2.5 : 2.0;
  h[0] = a * n[0] * n[0] - 0.5;
  h[1] = a * n[1] * n[1] - 0.5;
  if (dimension == 3)
    h[2] = a * n[2] * n[2] - 0.5;
  else
    h[2] = T{};
  h[3] = a * n[1] * n[2];
  h[4] = a * n[0] * n[2];
  h[5] = a * n[0] * n[1];
}

// p with p . e = n . e n (the bond's normal strain of a tensor e).
template <class T>
HORIZON_HD_INLINE void unit_normal_projector(const T* n, T* p) {
  p[0] = n[0] * n[0];
  p[1] = n[1] * n[1];
  p[2] = n[2] * n[2];
  p[3] = 2.0 * n[1] * n[2];
  p[4] = 2.0 * n[0] * n[2];
  p[5] = 2.0 * n[0] * n[1];
}

// |Y|^2 of a bond, summed as Vec3's dot and kernels::bond_length sum it.
template <class T>
HORIZON_HD_INLINE T squared_length(T x, T y, T z) {
  return x * x + y * y + z * z;
}

// The m = 1 bond strain (c - 1)/2 (pair_strain below), c = |Y|^2/|xi|^2.
template <class T>
HORIZON_HD_INLINE T green_bond_strain(T c) {
  return 0.5 * (c - 1.0);
}

// The Seth-Hill strain of (4.2) in the pair pass: for m = 1 (c - 1)/2, exact in c
// (Sterbenz), else seth_hill_strain (extended_correspondence.hpp pair_strain).
HORIZON_HD inline double pair_strain(double c, double m) { return m == 1.0 ? 0.5 * (c - 1.0) : seth_hill_strain(c, m); }

// The strain sum of the breaking sweep, S += (w eps) H<xi> (w = omega V_j).
HORIZON_HD inline void strain_sum_add(double* S, double w_eps, const double* h) {
  for (int k = 0; k < 6; ++k) S[k] += w_eps * h[k];
}

// One end of a bond as the pair sum reads its record: A = a - 2 k_s b, the strain E its
// residuals read, k_s, whether it carries stress, whether it sends E for the midpoint.
struct PairEnd {
  const double* A;
  const double* E;
  double ks;
  bool on, mid;
};

// 2 coef r of a's side of the bond to b: coef = (k_a + k_b)/2 with the midpoint residual
// when b sends its E, else k_a with a's own (ExtendedCorrespondence::stabilisation()).
HORIZON_HD_INLINE double pair_side_residual(const PairEnd& a, const PairEnd& b, const double* p, double eps) {
  if (a.ks == 0) return 0.0;
  if (b.mid) return (a.ks + b.ks) * (eps - dot6_mid(p, a.E, b.E));
  return 2.0 * a.ks * (eps - dot6(p, a.E));
}

// The pair sum's bond term: q_i = omega g (A_i . h + 2 coef r_i) (i's side, kept for the
// energy of a bond broken in the next pass) and the factor s of Y in f_i += s Y,
// s = V (q_i + omega g (A_j . h + 2 coef r_j)), g = c^(m-1)/|xi|^2 (digest sec. 3.2).
// n: xi/|xi| by the kind's 1/|xi|; Y2 = Y . Y; V = V_j's share.
struct PairBond {
  double q, scale;
};
HORIZON_HD_INLINE PairBond pair_bond(const PairEnd& ri, const PairEnd& rj, const double* n, int dimension,
                                     double inv_length, double Y2, double eps, double m, double omega, double V) {
  double h[6], p[6];
  unit_shape_state(n, dimension, h);
  unit_normal_projector(n, p);
  const double inv2 = inv_length * inv_length, c = Y2 * inv2;
  const double g = (m == 0.0 ? 1.0 / c : m == 1.0 ? 1.0 : power(c, m - 1.0)) * inv2;
  double si = ri.on ? dot6(ri.A, h) : 0.0, sj = rj.on ? dot6(rj.A, h) : 0.0;
  if (ri.mid && rj.mid) {
    // Both ends take the midpoint residual: one r, the same bits from either end.
    const double rr = (ri.ks + rj.ks) * (eps - dot6_mid(p, ri.E, rj.E));
    if (ri.on && ri.ks != 0) si += rr;
    if (rj.on && rj.ks != 0) sj += rr;
  } else {
    if (ri.on) si += pair_side_residual(ri, rj, p, eps);
    if (rj.on) sj += pair_side_residual(rj, ri, p, eps);
  }
  const double wg = omega * g, qi = wg * si;
  return {qi, V * (qi + wg * sj)};
}

// pair_bond with i's residual r_i as i's row computed it for its stabilisation sum
// (pair_law_row: eps - p . (E_i + E_j)/2 when j sends its E, else eps - p . E_i; valid when
// i carries stress with k_s != 0): the same operations on the same values, so the same bits,
// without the midpoint projection per bond (and, when both ends take the midpoint, without
// reading E of either end: the midpoint residual is the same number from both).
// eps: the bond's strain, read only where a residual is computed here (not when both
// ends take the midpoint and i's is kept).
HORIZON_HD_INLINE PairBond pair_bond_kept(const PairEnd& ri, const PairEnd& rj, const double* n, int dimension,
                                          double inv_length, double Y2, const double* eps, double r_i, double m,
                                          double omega, double V) {
  double h[6];
  unit_shape_state(n, dimension, h);
  const double inv2 = inv_length * inv_length, c = Y2 * inv2;
  const double g = (m == 0.0 ? 1.0 / c : m == 1.0 ? 1.0 : power(c, m - 1.0)) * inv2;
  double si = ri.on ? dot6(ri.A, h) : 0.0, sj = rj.on ? dot6(rj.A, h) : 0.0;
  const bool kept = ri.on && ri.ks != 0;
  if (ri.mid && rj.mid) {
    double rr;
    if (kept) {
      rr = (ri.ks + rj.ks) * r_i;
    } else {
      double p[6];
      unit_normal_projector(n, p);
      rr = (ri.ks + rj.ks) * (*eps - dot6_mid(p, ri.E, rj.E));
    }
    if (kept) si += rr;
    if (rj.on && rj.ks != 0) sj += rr;
  } else {
    if (kept) si += rj.mid ? (ri.ks + rj.ks) * r_i : 2.0 * ri.ks * r_i;
    if (rj.on) {
      double p[6];
      unit_normal_projector(n, p);
      sj += pair_side_residual(rj, ri, p, *eps);
    }
  }
  const double wg = omega * g, qi = wg * si;
  return {qi, V * (qi + wg * sj)};
}

}  // namespace horizon::kernels
