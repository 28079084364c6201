#pragma once
// The per-bond work of the correspondence model in its pair form (issue 31, scope 2), as
// plain functions over flat arrays (core/portable.hpp: the host and a device build
// compile the same source).
//
// The force state of correspondence.hpp (*), T_ij = omega (A_i xi + G (Y - F_i xi)) with
// A_i = P_i K_i^-1 (seed 003 eq. 142; Silling 2017 for the G term), is affine in the bond:
//   T_ij = omega (M_i xi + g_i Y),   M_i = A_i - G F_i,  g_i = G,
// with M_i = 0, g_i = 0 for a particle that carries no stress (refused shape tensor) and
// A_i = 0 when its law refuses F (det F <= 0: the stabilisation stays). One record of
// kAffineRecord numbers per particle holds {M_i row by row, g_i}.
//
// The reverse bond has xi_ji = -xi, Y_ji = -Y and the same omega (the influence function
// of |xi|), so T_ji = -omega (M_j xi + g_j Y) and the force density of seed 003 eq. 33,
//   f_i = sum_j V_j (T_ij - T_ji) = sum_j omega V_j ((M_i + M_j) xi + (g_i + g_j) Y),
// needs the neighbour's 80-byte record (read by particle index: the family's records stay
// in cache from row to row) instead of the reverse bond's force state (a random 24-byte
// read through the reverse-bond index). Summed as
//   f_i = M_i sum_j w xi + g_i sum_j w Y + sum_j w (M_j xi + g_j Y),   w = omega V_j,
// the bond costs 3 + 3 + 12 multiply-adds. The same forces as the vector form of the
// general pass up to the rounding of the sums (tests/verification/test_general_pass.cpp).
#include "horizon/core/portable.hpp"

namespace horizon::correspondence {

inline constexpr int kAffineRecord = 10;

// The record of one particle: A (row-major 3 x 3, or null: carries no stress through its
// law), F (row-major), G; null F: the particle carries no stress at all (record 0).
HORIZON_HD inline void affine_record(const double* A, const double* F, double G, double* rec) {
  for (int c = 0; c < kAffineRecord; ++c) rec[c] = 0;
  if (!F) return;
  for (int c = 0; c < 9; ++c) rec[c] = (A ? A[c] : 0.0) - G * F[c];
  rec[9] = G;
}

// T_ij = omega (M_i xi + g_i Y) of one bond.
HORIZON_HD inline void affine_force_state(const double* rec, double omega, const double* xi, const double* Y,
                                          double* T) {
  for (int r = 0; r < 3; ++r)
    T[r] = omega * (rec[3 * r] * xi[0] + rec[3 * r + 1] * xi[1] + rec[3 * r + 2] * xi[2] + rec[9] * Y[r]);
}

// The sums of the shape tensor and of the deformation gradient over a row's acting bonds
// (seed 003 eq. 17, 134; material/nonlocal_gradient.hpp): K = sum_j w xi (x) xi,
// N = sum_j w Y (x) xi, w = omega V_j, both row-major, added bond by bond as
// NonlocalGradient::add does (the same products in the same order: the same bits).
struct GradientSums {
  double v[18] = {};  // K, then N
};

HORIZON_HD inline void gradient_add(GradientSums& g, const double* xi, const double* Y, double w) {
  for (int r = 0; r < 3; ++r) {
    const double wa = w * xi[r], wy = w * Y[r];
    for (int c = 0; c < 3; ++c) {
      g.v[3 * r + c] += wa * xi[c];
      g.v[9 + 3 * r + c] += wy * xi[c];
    }
  }
}

// The running sums of one row (see above).
struct AffineRowSum {
  double sxi[3] = {0, 0, 0};  // sum_j w xi
  double sy[3] = {0, 0, 0};   // sum_j w Y
  double acc[3] = {0, 0, 0};  // sum_j w (M_j xi + g_j Y)
};

// One acting bond of the row: w = omega V_j, recj the neighbour's record.
HORIZON_HD inline void affine_pair_add(AffineRowSum& s, const double* recj, double w, const double* xi,
                                       const double* Y) {
  const double a[3] = {w * xi[0], w * xi[1], w * xi[2]};
  const double gy = w * recj[9];
  for (int r = 0; r < 3; ++r) {
    s.sxi[r] += a[r];
    s.sy[r] += w * Y[r];
    s.acc[r] += recj[3 * r] * a[0] + recj[3 * r + 1] * a[1] + recj[3 * r + 2] * a[2] + gy * Y[r];
  }
}

// f_i of the row from its sums and its own record.
HORIZON_HD inline void affine_pair_finish(const AffineRowSum& s, const double* reci, double* f) {
  for (int r = 0; r < 3; ++r)
    f[r] = reci[3 * r] * s.sxi[0] + reci[3 * r + 1] * s.sxi[1] + reci[3 * r + 2] * s.sxi[2] + reci[9] * s.sy[r] +
           s.acc[r];
}

}  // namespace horizon::correspondence
