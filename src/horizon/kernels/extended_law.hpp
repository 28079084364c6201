#pragma once
// Extended correspondence's per-particle law row and its volumetric-gradient bond terms
// (material/models/extended_correspondence.{hpp,cpp}; Tupek's thesis eq. 4.3-4.7, the
// moment map M_i and the volumetric_strain gradient's Fbar as the model header derives
// them) as device-portable functions (core/portable.hpp, issue 30):
//   - the moment map M_i = sum_j w_j H_j (x) p_j of the acting bonds (shape_state and
//     normal_projector with |xi|^2 divisions, as MomentMap::add takes them), its inverse by
//     Eigen's FullPivLU (full pivoting, the rank test, the solve of the identity), E = M^-1 S
//     and the dual a = M^-T (w .* t) (MomentMap::solve, dual, dual_weighted);
//   - `extended_law_row`: one particle's law row from E and the kept maps: Fbar = N K^-1, the
//     law step of kernels/hencky.hpp and strain_laws.hpp (the model's run_law), the pressure
//     map P K^-1, the record's a = dual(S), the von Mises stress;
//   - the pair form's stabilisation sums and record, and its whole law row in one call
//     (`extended_pair_law_row`);
//   - the vector form's stabilisation (capped or not) and its bond terms (the strain sum of
//     sweep 1, the force state (**));
//   - per bond, the volumetric gradient's sum N += w Y (x) xi and its force term w P xi.
// The 3 x 3 and 6 x 6 matrices here are column-major, Eigen's storage, which the model keeps
// (its maps, K^-1, N and P K^-1 are Eigen matrices read through .data()); 6-vectors are
// symmetric tensors (11, 22, 33, 23, 13, 12).
//
// Bits: the Eigen forms' operations in the order this build's Eigen 3.4 (SSE2 packets of two
// doubles, no FMA) gives them, held to them bit for bit on random input by
// tests/unit/test_extended_law_kernels.cpp:
//   - M's outer product entry by entry, M_ab += (w h_a) p_b;
//   - FullPivLU: the pivot is the first largest |entry| of the remaining corner in
//     column-major order (a later one must be strictly larger), rows then columns swapped,
//     the column below divided by the pivot, the rank-one update a - l u; rank: the pivots
//     with |u_kk| > 6 eps max|pivot|; the inverse solves P I: the unit-lower solve and the upper
//     one by triangular_solve_matrix's panels of four (within a panel each solved entry's
//     term subtracted in turn, the upper one multiplied by 1/u_kk; the rows past a panel
//     take the panel's four terms summed first, in column order, then subtracted: the gebp
//     kernel), the rows put back by Q;
//   - M^-1 S: each entry's six products summed in column order (the lazy product's packets);
//   - M^-T v: each entry a dot product of a column of M^-1 with v, Eigen's two-lane reduction
//     (kernels::dot6's order);
//   - w (P xi) as Eigen rewrites a scalar times a product, (w P) xi, in mat3_vec's order;
//   - normalized(): xi / sqrt((x^2 + y^2) + z^2), and R += ((w r) n_a) n_b;
//   - the 6-vector dot products in kernels::dot6's (and dot6_mid's) order.
#include <cstdint>

#include "horizon/core/portable.hpp"
#include "horizon/kernels/affine.hpp"
#include "horizon/kernels/extended.hpp"
#include "horizon/kernels/hencky.hpp"
#include "horizon/kernels/strain_laws.hpp"

namespace horizon::kernels {

// ---- the moment map ----

// H<xi> of (4.4) and the normal projector p of a bond from xi itself (divisions by
// |xi|^2: MomentMap::add's shape_state and normal_projector).
HORIZON_HD inline void shape_state_of(const double* xi, int dimension, double* h) {
  const double L2 = xi[0] * xi[0] + xi[1] * xi[1] + xi[2] * xi[2];
  const double a = dimension == 3 ? 2.5 : 2.0;
  h[0] = a * xi[0] * xi[0] / L2 - 0.5;
  h[1] = a * xi[1] * xi[1] / L2 - 0.5;
  h[2] = dimension == 3 ? a * xi[2] * xi[2] / L2 - 0.5 : 0.0;
  h[3] = a * xi[1] * xi[2] / L2;
  h[4] = a * xi[0] * xi[2] / L2;
  h[5] = a * xi[0] * xi[1] / L2;
}
HORIZON_HD inline void normal_projector_of(const double* xi, double* p) {
  const double L2 = xi[0] * xi[0] + xi[1] * xi[1] + xi[2] * xi[2];
  p[0] = xi[0] * xi[0] / L2;
  p[1] = xi[1] * xi[1] / L2;
  p[2] = xi[2] * xi[2] / L2;
  p[3] = 2 * xi[1] * xi[2] / L2;
  p[4] = 2 * xi[0] * xi[2] / L2;
  p[5] = 2 * xi[0] * xi[1] / L2;
}

// M = 0, or in 2-D (plane strain: E_33 = E_23 = E_13 = 0) the identity on those rows.
HORIZON_HD inline void moment_map_reset(double* M, int dimension) {
  for (int k = 0; k < 36; ++k) M[k] = 0.0;
  if (dimension == 2) M[6 * 2 + 2] = M[6 * 3 + 3] = M[6 * 4 + 4] = 1.0;
}

// M += w H<xi> (x) p(xi) (column-major M): shape_state_of and normal_projector_of's
// numerators each divided by |xi|^2, then M_ab += (w h_a) p_b. On the host the twelve
// divisions and the 36 products go in pairs of lanes (GCC vectors of two doubles, as
// Eigen's SSE2 packets took the outer product): the same IEEE operations per entry.
HORIZON_HD inline void moment_map_add(double* M, const double* xi, double w, int dimension) {
  const double L2 = xi[0] * xi[0] + xi[1] * xi[1] + xi[2] * xi[2];
  const double a = dimension == 3 ? 2.5 : 2.0;
  double q[12] = {a * xi[0] * xi[0], a * xi[1] * xi[1], a * xi[2] * xi[2], a * xi[1] * xi[2],
                  a * xi[0] * xi[2], a * xi[0] * xi[1], xi[0] * xi[0],     xi[1] * xi[1],
                  xi[2] * xi[2],     2 * xi[1] * xi[2], 2 * xi[0] * xi[2], 2 * xi[0] * xi[1]};
#if defined(__CUDA_ARCH__) || !defined(__GNUC__) || defined(HORIZON_KERNELS_SCALAR)  // (scalar: the device, or a test)
  for (int k = 0; k < 12; ++k) q[k] = q[k] / L2;
  const double h[6] = {w * (q[0] - 0.5), w * (q[1] - 0.5), w * (dimension == 3 ? q[2] - 0.5 : 0.0),
                       w * q[3],         w * q[4],         w * q[5]};
  for (int b = 0; b < 6; ++b)
    for (int r = 0; r < 6; ++r) M[6 * b + r] += h[r] * q[6 + b];
#else
  typedef double pair __attribute__((vector_size(16)));
  pair v[6];
  __builtin_memcpy(v, q, sizeof v);
  for (int k = 0; k < 6; ++k) v[k] = v[k] / L2;
  __builtin_memcpy(q, v, sizeof v);
  const double h[6] = {w * (q[0] - 0.5), w * (q[1] - 0.5), w * (dimension == 3 ? q[2] - 0.5 : 0.0),
                       w * q[3],         w * q[4],         w * q[5]};
  pair hw[3];
  __builtin_memcpy(hw, h, sizeof hw);
  for (int b = 0; b < 6; ++b)
    for (int r = 0; r < 3; ++r) {
      pair m;
      __builtin_memcpy(&m, M + 6 * b + 2 * r, sizeof m);
      m += hw[r] * q[6 + b];
      __builtin_memcpy(M + 6 * b + 2 * r, &m, sizeof m);
    }
#endif
}

// Eigen's FullPivLU of a column-major 6 x 6 in place: row[k], col[k] the row and column
// swapped into k; the number of nonzero pivots and the largest |pivot| come back. |x| is
// tupek.hpp's magnitude (fabs: -0 scores as 0, which compares as absolute()'s -0 would).
HORIZON_HD inline void full_piv_lu6(double* lu, int* row, int* col, int& nonzero, double& max_pivot) {
  nonzero = 6;
  max_pivot = 0.0;
  for (int k = 0; k < 6; ++k) {
    // The first largest |entry| of the corner, column by column (Eigen's max_coeff_visitor).
    int pr = k, pc = k;
    double big = magnitude(lu[6 * k + k]);
    for (int c = k; c < 6; ++c)
      for (int r = (c == k ? k + 1 : k); r < 6; ++r) {
        const double v = magnitude(lu[6 * c + r]);
        if (v > big) big = v, pr = r, pc = c;
      }
    if (big == 0.0) {
      nonzero = k;
      for (int q = k; q < 6; ++q) row[q] = col[q] = q;
      return;
    }
    if (big > max_pivot) max_pivot = big;
    row[k] = pr, col[k] = pc;
    if (pr != k)
      for (int c = 0; c < 6; ++c) {
        const double t = lu[6 * c + k];
        lu[6 * c + k] = lu[6 * c + pr], lu[6 * c + pr] = t;
      }
    if (pc != k)
      for (int r = 0; r < 6; ++r) {
        const double t = lu[6 * k + r];
        lu[6 * k + r] = lu[6 * pc + r], lu[6 * pc + r] = t;
      }
    const double pivot = lu[6 * k + k];
    for (int r = k + 1; r < 6; ++r) lu[6 * k + r] = lu[6 * k + r] / pivot;
    for (int c = k + 1; c < 6; ++c)
      for (int r = k + 1; r < 6; ++r) lu[6 * c + r] = lu[6 * c + r] - lu[6 * k + r] * lu[6 * c + k];
  }
}

// One column x of the inverse's solve, L U x = b in place (Eigen's triangular_solve_matrix
// for six rows: panels of four, then two; the rows past a panel by the gebp kernel).
HORIZON_HD inline void lu6_solve_column(const double* lu, double* x) {
  // Unit lower, panel rows 0..3.
  for (int i = 0; i < 4; ++i)
    for (int r = i + 1; r < 4; ++r) x[r] -= x[i] * lu[6 * i + r];
  for (int r = 4; r < 6; ++r) {
    double acc = lu[6 * 0 + r] * x[0];
    for (int q = 1; q < 4; ++q) acc = acc + lu[6 * q + r] * x[q];
    x[r] = x[r] - acc;
  }
  x[5] -= x[4] * lu[6 * 4 + 5];
  // Upper, panel rows 5..2 (bottom up), then rows 1, 0.
  for (int i = 5; i >= 2; --i) {
    x[i] *= 1.0 / lu[6 * i + i];
    for (int r = 2; r < i; ++r) x[r] -= x[i] * lu[6 * i + r];
  }
  for (int r = 0; r < 2; ++r) {
    double acc = lu[6 * 2 + r] * x[2];
    for (int q = 3; q < 6; ++q) acc = acc + lu[6 * q + r] * x[q];
    x[r] = x[r] - acc;
  }
  x[1] *= 1.0 / lu[6 * 1 + 1];
  x[0] -= x[1] * lu[6 * 1 + 0];
  x[0] *= 1.0 / lu[0];
}

// MomentMap::finish: M^-1 of a column-major 6 x 6 into inv, or false when Eigen's
// FullPivLU calls M singular (rank < 6) or the inverse is not finite.
HORIZON_HD inline bool moment_map_inverse(const double* M, double* inv) {
  double lu[36];
  for (int k = 0; k < 36; ++k) lu[k] = M[k];
  int row[6], col[6], nonzero;
  double max_pivot;
  full_piv_lu6(lu, row, col, nonzero, max_pivot);
  const double threshold = max_pivot * (2.220446049250313e-16 * 6.0);
  int rank = 0;
  for (int k = 0; k < nonzero; ++k) rank += magnitude(lu[6 * k + k]) > threshold ? 1 : 0;
  if (rank != 6) return false;
  // P and Q as Eigen accumulates the transpositions (P: last to first, Q: first to last).
  int p[6], q[6];
  for (int k = 0; k < 6; ++k) p[k] = q[k] = k;
  for (int k = 5; k >= 0; --k) {
    const int t = p[k];
    p[k] = p[row[k]], p[row[k]] = t;
  }
  for (int k = 0; k < 6; ++k) {
    const int t = q[k];
    q[k] = q[col[k]], q[col[k]] = t;
  }
  for (int j = 0; j < 6; ++j) {
    double x[6];
    for (int r = 0; r < 6; ++r) x[p[r]] = r == j ? 1.0 : 0.0;  // (P I) column j
    lu6_solve_column(lu, x);
    for (int r = 0; r < 6; ++r) inv[6 * j + q[r]] = x[r];
  }
  bool finite_all = true;
  for (int k = 0; k < 36; ++k) finite_all = finite_all && finite(inv[k]);
  return finite_all;
}

// e = M^-1 s (MomentMap::solve).
HORIZON_HD inline void moment_solve(const double* inv, const double* s, double* e) {
  for (int r = 0; r < 6; ++r) {
    double v = inv[r] * s[0];
    for (int k = 1; k < 6; ++k) v = v + inv[6 * k + r] * s[k];
    e[r] = v;
  }
}

// a = M^-T v (MomentMap::dual_weighted: v a weighted 6-vector).
HORIZON_HD inline void moment_dual_weighted(const double* inv, const double* v, double* a) {
  for (int r = 0; r < 6; ++r) a[r] = dot6(inv + 6 * r, v);
}

// a = M^-T W t of a row-major 3 x 3 t (MomentMap::dual: t : Ht_j = a . h_j), its upper
// triangle read.
HORIZON_HD inline void moment_dual(const double* inv, const double* t, double* a) {
  const double v[6] = {t[0], t[4], t[8], 2.0 * t[5], 2.0 * t[2], 2.0 * t[1]};
  moment_dual_weighted(inv, v, a);
}

// One particle's moment map, shape-tensor guard and their factorisations over its acting
// bonds (ExtendedCorrespondence::rebuild_map): bond(k, xi, w) gives bond k's reference
// vector xi and weight w = omega V_j and says whether it acts. M^-1 into inv, K^-1
// (column-major) into Kinv, sum w into acting_weight; false when the acting weight is
// under min_weight, the shape tensor is refused (kernels/affine.hpp gradient_finish,
// `tolerance`) or M is singular (moment_map_inverse), in that order: a later test is not
// run, and inv and Kinv stay 0 where their test was not reached.
template <class Bond>
HORIZON_HD inline bool moment_map_row(uint64_t begin, uint64_t end, Bond bond, int dimension, double tolerance,
                                      double min_weight, double* M, double* inv, double* Kinv,
                                      double& acting_weight) {
  double Ml[36];  // summed here, in the function's own storage (M may alias what bond() reads)
  moment_map_reset(Ml, dimension);
  GradientSums g;  // K (N stays 0: only K's guard and inverse are asked for)
  acting_weight = 0.0;
  for (uint64_t k = begin; k < end; ++k) {
    double xi[3], w;
    if (!bond(k, xi, w)) continue;
    moment_map_add(Ml, xi, w, dimension);
    for (int r = 0; r < 3; ++r) {  // K += w xi (x) xi, as gradient_add (NonlocalGradient::add) sums it
      const double wa = w * xi[r];
      for (int q = 0; q < 3; ++q) g.v[3 * r + q] += wa * xi[q];
    }
    acting_weight += w;
  }
  for (int k = 0; k < 36; ++k) M[k] = Ml[k], inv[k] = 0.0;
  for (int k = 0; k < 9; ++k) Kinv[k] = 0.0;
  if (!(acting_weight >= min_weight)) return false;
  double ki[9], f[9];
  const bool shape_ok = gradient_finish(g.v, g.v + 9, dimension, tolerance, ki, f);
  for (int r = 0; r < 3; ++r)
    for (int q = 0; q < 3; ++q) Kinv[3 * q + r] = ki[3 * r + q];
  return shape_ok && moment_map_inverse(M, inv);
}

// ---- the pair form's stabilisation and record ----

// One acting bond of a row as the stabilisation reads it: n = xi/|xi| (from the kind's
// 1/|xi|), the bond strain eps, w = omega V_j, and (mid) the other end's E and k_s when it
// sends its E for the midpoint residual.
struct StabilisationBond {
  double n[3];
  double eps, w;
  const double* Ej;
  double ksj;
  bool mid;
};

// A bond's stabilisation residual r = eps - p : E and its spring coef (the midpoint option:
// r against the mean of both ends' strains, coef the mean of their k_s), shared by the pair
// and vector forms (B: StabilisationBond or VectorStabilisationBond).
template <class B>
HORIZON_HD inline double stabilisation_residual(const B& b, const double* p, const double* E, double ks,
                                                double& coef) {
  if (b.mid) {
    coef = 0.5 * (ks + b.ksj);
    return b.eps - dot6_mid(p, E, b.Ej);
  }
  coef = ks;
  return b.eps - dot6(p, E);
}

// The pair form's stabilisation sums of a row with k_s != 0 (ExtendedCorrespondence::
// pair_law_row): each acting bond's residual r = eps - p . E (midpoint: p . (E + E_j)/2,
// coef (k_s + k_s,j)/2, else k_s) into rforce[k], Rp = sum (w r coef/k_s) p and
// Ws = sum coef w r^2. bond(k, b) fills b and says whether bond k acts.
template <class Bond>
HORIZON_HD inline void pair_stabilisation_row(uint64_t begin, uint64_t end, Bond bond, const double* E, double ks,
                                              double* rforce, double* Rp, double& Ws) {
  const double inv_ks = 1.0 / ks;
  for (int q = 0; q < 6; ++q) Rp[q] = 0.0;
  Ws = 0.0;
  for (uint64_t k = begin; k < end; ++k) {
    StabilisationBond b;
    if (!bond(k, b)) continue;
    double p[6];
    unit_normal_projector(b.n, p);
    double coef;
    const double r = stabilisation_residual(b, p, E, ks, coef);
    rforce[k] = r;
    const double wr = b.w * r, f = wr * (coef * inv_ks);
    for (int q = 0; q < 6; ++q) Rp[q] += f * p[q];
    Ws += coef * wr * r;
  }
}

// The pair sum's record A = a - 2 k_s M^-T Rp (a = dual(S) of the law row).
HORIZON_HD inline void pair_record(const double* a, double ks, const double* inv, const double* Rp, double* A) {
  for (int q = 0; q < 6; ++q) A[q] = a[q];
  if (ks == 0) return;
  double d[6];
  moment_dual_weighted(inv, Rp, d);
  for (int q = 0; q < 6; ++q) A[q] -= (2.0 * ks) * d[q];
}

// ---- the vector form's bond terms ----

// Sweep 1 of the vector form (NonlocalStrain::add_strain): the bond's Seth-Hill strain of
// (4.2) from c = |Y|^2/|xi|^2, and S += (w eps) H<xi>; returns eps.
HORIZON_HD inline double vector_strain_add(double* S, const double* xi, const double* Y, double w, double m,
                                           int dimension) {
  const double c = (Y[0] * Y[0] + Y[1] * Y[1] + Y[2] * Y[2]) / (xi[0] * xi[0] + xi[1] * xi[1] + xi[2] * xi[2]);
  const double eps = seth_hill_strain(c, m);
  double h[6];
  shape_state_of(xi, dimension, h);
  strain_sum_add(S, w * eps, h);
  return eps;
}

// The force state (**) of one bond in the vector form (bond_force_state): a = dual(S),
// b = dual(R), omega the influence weight, r the bond's r_force:
//   T = omega (a . h + 2 k_s (r - b . h)) c^(m-1)/|xi|^2 Y.
HORIZON_HD inline void vector_bond_force(const double* a, const double* b, double ks, double omega, double m,
                                         int dimension, const double* xi, const double* Y, double r, double* T) {
  const double xi2 = xi[0] * xi[0] + xi[1] * xi[1] + xi[2] * xi[2];
  const double c = (Y[0] * Y[0] + Y[1] * Y[1] + Y[2] * Y[2]) / xi2;
  double h[6];
  shape_state_of(xi, dimension, h);
  const double s = dot6(a, h) + 2.0 * ks * (r - dot6(b, h));
  const double g = (m == 0.0 ? 1.0 / c : m == 1.0 ? 1.0 : power(c, m - 1.0)) / xi2;
  const double f = omega * s * g;
  for (int q = 0; q < 3; ++q) T[q] = f * Y[q];
}

// ---- the vector form's stabilisation ----

// std::copysign (the capped stabilisation's return).
HORIZON_HD inline double copy_sign(double x, double y) {
#if defined(__CUDA_ARCH__)
  return ::copysign(x, y);
#else
  return __builtin_copysign(x, y);
#endif
}

// One acting bond as the vector form's stabilisation reads it: xi itself (the residual's
// projector and n = xi/|xi| from it), the bond strain eps, w = omega V_j, and (mid) the other
// end's E and k_s for the midpoint residual.
struct VectorStabilisationBond {
  double xi[3];
  double eps, w;
  const double* Ej;
  double ksj;
  bool mid;
};

struct VectorStabilisation {
  double R[9];      // sum w r_force n (x) n (row-major)
  double W, work;   // W_s and the capped part's dissipation in the step [J/m^3]
};

// ExtendedCorrespondence::stabilisation (the vector form: force_state, energy_with): each
// acting bond's residual r0 = eps - p(xi) . E (midpoint: p . (E + E_j)/2, coef (k_s +
// k_s,j)/2, else k_s); capped (r_c > 0: the stabilisation yields at r_c), the plastic
// residual's closest-point return from rp_committed[k] (written to rp_trial[k] when given)
// and its work 2 coef r_c |dr_p| w; rforce[k] = r coef/k_s with r = r0 - r_p; R += (w
// r_force) n (x) n with n = xi/|xi| (Eigen's normalized(): xi / sqrt((x^2 + y^2) + z^2));
// W_s = sum coef w r^2. bond(k, b) fills b and says whether bond k acts.
template <class Bond>
HORIZON_HD inline void vector_stabilisation_row(uint64_t begin, uint64_t end, Bond bond, const double* E, double ks,
                                                bool capped, double r_c, const double* rp_committed,
                                                double* rp_trial, double* rforce, VectorStabilisation& out) {
  for (int q = 0; q < 9; ++q) out.R[q] = 0.0;
  out.W = out.work = 0.0;
  for (uint64_t k = begin; k < end; ++k) {
    VectorStabilisationBond b;
    if (!bond(k, b)) continue;
    double p[6];
    normal_projector_of(b.xi, p);
    double coef;
    const double r0 = stabilisation_residual(b, p, E, ks, coef);
    double rp = 0;
    if (capped) {
      const double rc = rp_committed[k];
      rp = magnitude(r0 - rc) > r_c ? r0 - copy_sign(r_c, r0 - rc) : rc;
      out.work += 2.0 * coef * r_c * magnitude(rp - rc) * b.w;
      if (rp_trial) rp_trial[k] = rp;
    }
    const double r = r0 - rp;
    rforce[k] = r * coef / ks;
    const double z = (b.xi[0] * b.xi[0] + b.xi[1] * b.xi[1]) + b.xi[2] * b.xi[2];
    double n[3] = {b.xi[0], b.xi[1], b.xi[2]};
    if (z > 0) {
      const double sz = root(z);
      for (int a = 0; a < 3; ++a) n[a] = n[a] / sz;
    }
    const double f = b.w * rforce[k];
    for (int a = 0; a < 3; ++a) {
      const double fa = f * n[a];
      for (int c = 0; c < 3; ++c) out.R[3 * a + c] += fa * n[c];
    }
    out.W += coef * b.w * r * r;
  }
}

// ---- the volumetric gradient's bond terms ----

// N += w Y (x) xi (column-major N; the classical nonlocal gradient's sum of the acting bonds).
HORIZON_HD inline void gradient_outer_add(double* N, double w, const double* Y, const double* xi) {
  double wy[3];
  for (int a = 0; a < 3; ++a) wy[a] = w * Y[a];
  for (int b = 0; b < 3; ++b)
    for (int a = 0; a < 3; ++a) N[3 * b + a] += wy[a] * xi[b];
}

// t = P v of a column-major P.
HORIZON_HD inline void mat3c_vec(const double* P, const double* v, double* t) {
  const double rows[9] = {P[0], P[3], P[6], P[1], P[4], P[7], P[2], P[5], P[8]};
  mat3_vec(rows, v, t);
}

// t = w (P xi), the bond's pressure term omega P K^-1 xi (column-major P), as Eigen
// evaluates w * (P * xi): (w P) xi.
HORIZON_HD inline void pressure_bond_term(const double* P, double w, const double* xi, double* t) {
  const double rows[9] = {w * P[0], w * P[3], w * P[6], w * P[1], w * P[4], w * P[7], w * P[2], w * P[5], w * P[8]};
  mat3_vec(rows, xi, t);
}

// ---- the law row ----

struct ExtendedLawConstants {
  StrainLawConstants law;
  int dimension = 3;
  bool hencky = false;        // strain_measure hencky: the law on E_log = ln(I + 2E)/2
  bool vol_gradient = false;  // volumetric_strain gradient: the trace from ln det Fbar
  double floor = 1e-6;        // the Hencky map's eigenvalue floor
};

// A particle's law history: E_p (row-major), eps_p, D.
struct ExtendedLawHistory {
  double Ep[9];
  double alpha, damage;
};

struct ExtendedLawRow {
  double S[9];           // the stress conjugate to E (row-major; the deviatoric part with Fbar)
  double law_stress[9];  // the law's own stress T (row-major)
  double PK[9];          // p Fbar^-T K^-1 (column-major; 0 without the volumetric gradient)
  double a[6];           // M^-T W S (the record's dual of S), when a map is given
  double W, plastic_work, rate, von_mises;
  bool ok;  // false: the point has failed (D >= 1) and carries no stress
};

// One particle's law row (ExtendedCorrespondence::row_law's run_law and row_end's von Mises):
// E the nonlocal strain (6-vector), N = sum w Y (x) xi and Kinv = K^-1 (column-major; read
// with vol_gradient), inv M^-1 (column-major; null: no dual), from the committed history
// to the trial one, dt the step (0: rate 0).
HORIZON_HD inline void extended_law_row(const ExtendedLawConstants& c, const double* inv, const double* E,
                                        const double* N, const double* Kinv, const ExtendedLawHistory& committed,
                                        double dt, ExtendedLawHistory& trial, ExtendedLawRow& out) {
  trial = committed;
  out.W = out.plastic_work = out.rate = out.von_mises = 0.0;
  for (int k = 0; k < 9; ++k) out.S[k] = out.law_stress[k] = out.PK[k] = 0.0;
  for (int k = 0; k < 6; ++k) out.a[k] = 0.0;
  out.ok = false;
  double Kr[9] = {}, F[9] = {}, pm[9] = {};
  for (int r = 0; r < 3; ++r)
    for (int q = 0; q < 3; ++q) Kr[3 * r + q] = Kinv[3 * q + r];
  if (c.vol_gradient) {
    double Nr[9];
    for (int r = 0; r < 3; ++r)
      for (int q = 0; q < 3; ++q) Nr[3 * r + q] = N[3 * q + r];
    mat3_mul(Nr, Kr, F);
    if (c.dimension == 2) F[8] = 1.0;
  }
  // The law step (run_law): E -> E_log (hencky), its trace from Fbar, the law, the split.
  double strain[9] = {E[0], E[5], E[4], E[5], E[1], E[3], E[4], E[3], E[2]};
  double hN[9] = {}, hl[3] = {};
  if (committed.damage >= 1.0) {
    // A failed point carries no stress (pressure map 0: PK = 0 K^-1).
    mat3_mul(pm, Kr, F);
    for (int r = 0; r < 3; ++r)
      for (int q = 0; q < 3; ++q) out.PK[3 * q + r] = F[3 * r + q];
    return;
  }
  if (c.hencky) {
    double e[9];
    for (int k = 0; k < 9; ++k) e[k] = strain[k];
    hencky_of_green3(e, c.floor, hN, hl, strain);
  }
  if (c.vol_gradient) volumetric_gradient_strain(F, c.dimension, strain);
  StrainLawPoint pt;
  strain_law_point(c.law, committed.Ep, committed.alpha, committed.damage, strain, dt, trial.Ep, trial.alpha,
                   trial.damage, pt);
  out.ok = true;
  out.W = pt.W, out.plastic_work = pt.plastic_work, out.rate = pt.rate;
  double T[9];
  for (int k = 0; k < 9; ++k) out.law_stress[k] = T[k] = pt.S[k];
  if (c.vol_gradient) volumetric_pressure_split(F, c.dimension, T, pm);
  if (c.hencky) {
    green_stress_of_hencky3(hN, hl, T, out.S);
  } else {
    for (int k = 0; k < 9; ++k) out.S[k] = T[k];
  }
  double PK[9];
  mat3_mul(pm, Kr, PK);
  for (int r = 0; r < 3; ++r)
    for (int q = 0; q < 3; ++q) out.PK[3 * q + r] = PK[3 * r + q];
  if (inv) moment_dual(inv, out.S, out.a);
  // row_end: sqrt(3/2 dev(T) : dev(T)).
  const double t3 = mat3_trace(out.law_stress) / 3.0;
  double dev[9];
  for (int k = 0; k < 9; ++k) dev[k] = out.law_stress[k] - t3 * (k % 4 == 0 ? 1.0 : 0.0);
  out.von_mises = root(1.5 * squares_sum9(dev));
}

// The pair form's whole law row of one particle (ExtendedCorrespondence::pair_law_row on
// rows the lanes do not take): extended_law_row, then with k_s != 0 the stabilisation sums
// (pair_stabilisation_row) and the record A (pair_record); W_s into Ws (0 without
// stabilisation). False: the point has failed (nothing else is written).
template <class Bond>
HORIZON_HD inline bool extended_pair_law_row(const ExtendedLawConstants& c, const double* inv, const double* E,
                                             const double* N, const double* Kinv,
                                             const ExtendedLawHistory& committed, double dt, double ks,
                                             uint64_t begin, uint64_t end, Bond bond, double* rforce,
                                             ExtendedLawHistory& trial, ExtendedLawRow& out, double* A,
                                             double& Ws) {
  extended_law_row(c, inv, E, N, Kinv, committed, dt, trial, out);
  Ws = 0.0;
  if (!out.ok) return false;
  double Rp[6] = {0, 0, 0, 0, 0, 0};
  if (ks != 0) pair_stabilisation_row(begin, end, bond, E, ks, rforce, Rp, Ws);
  pair_record(out.a, ks, inv, Rp, A);
  return true;
}

}  // namespace horizon::kernels
