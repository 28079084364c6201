#pragma once
// The bond-associated correspondence model's per-bond work (material/models/
// bond_associated.hpp has the equations and their sources: Breitzman and Dayal 2018's
// bond-level gradient, their energy averaging, Behzadinasab and Foster 2020's
// semi-Lagrangian form) as device-portable functions (core/portable.hpp, issue 30), over
// row-major double[9]. The law between them is kernels/plane_stress.hpp law_point (the
// total-form laws) or kernels/hypoelastic.hpp hypo_step (the rate form);
// BondAssociated::force_state calls these for every bond.
//
// Bits: the operations of the host's Eigen forms in Eigen's order (tests/unit/
// test_bond_associated_kernels.cpp compares them bit for bit on random inputs): a matrix
// times a vector in mat3_vec's order, a squared norm as squared_norm3, the outer product
// u (x) b as b_c u_r, and a scalar times a product s (M v) as Eigen rewrites it, (s M) v
// (kernels/hypoelastic.hpp met the same rewrite).
#include "horizon/core/portable.hpp"
#include "horizon/kernels/affine.hpp"
#include "horizon/kernels/eigen3.hpp"
#include "horizon/kernels/unified.hpp"

namespace horizon::kernels {

// The bond-level gradient of bond b (Breitzman and Dayal 2018):
//   G_b = Gbar + (y - Gbar b) (x) b / bb,   Gbar = (G_i + G_j)/2,   bb = |b|^2,
// for F_ij (G = F, b = xi, y = Y), the lagrangian F_dot_ij (G = F_dot, b = xi, y = the
// bond's displacement increment over dt) and the semi-Lagrangian L_ij (G = L, b = Y).
HORIZON_HD inline void bond_level_gradient(const double* Gi, const double* Gj, const double* b, const double* y,
                                           double bb, double* out) {
  double bar[9], gb[3];
  for (int k = 0; k < 9; ++k) bar[k] = 0.5 * (Gi[k] + Gj[k]);
  mat3_vec(bar, b, gb);
  const double v[3] = {y[0] - gb[0], y[1] - gb[1], y[2] - gb[2]};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) out[3 * r + c] = bar[3 * r + c] + b[c] * v[r] / bb;
}

// The bond's own term of the force state and its share of S_i (bond_associated.hpp):
//   T = c_ij P b / bb,   S += (V_j (c_ij + c_ji)/2) P (I - n (x) n),   n = b/|b|,
// with P the law's first Piola-Kirchhoff stress (semi-Lagrangian: J_n sigma) and b the
// bond (xi, or Y on the current bonds).
HORIZON_HD inline void bond_associated_terms(const double* P, const double* b, double bb, double c_ij, double c_ji,
                                             double volume, double* T, double* S) {
  double cP[9], Pb[3];
  for (int k = 0; k < 9; ++k) cP[k] = c_ij * P[k];  // Eigen's s (P b) is (s P) b
  mat3_vec(cP, b, Pb);
  for (int r = 0; r < 3; ++r) T[r] = Pb[r] / bb;
  const double s = root(bb);
  const double n[3] = {b[0] / s, b[1] / s, b[2] / s};
  double Pn[3];
  mat3_vec(P, n, Pn);
  const double a = 0.5 * volume * (c_ij + c_ji);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) S[3 * r + c] = S[3 * r + c] + a * (P[3 * r + c] - n[c] * Pn[r]);
}

// The second term of a bond's force state, added: T += omega A b, A = S_i K_i^-1.
HORIZON_HD inline void bond_associated_tail(const double* A, double omega, const double* b, double* T) {
  double oA[9], Ab[3];
  for (int k = 0; k < 9; ++k) oA[k] = omega * A[k];  // Eigen's s (A b) is (s A) b
  mat3_vec(oA, b, Ab);
  for (int r = 0; r < 3; ++r) T[r] = T[r] + Ab[r];
}

}  // namespace horizon::kernels
