#pragma once
// 3 x 3 decompositions for the stress laws (kernels/laws.hpp) as device-portable functions
// (core/portable.hpp, issue 30): the determinant, the singular value decomposition and
// the polar decomposition with the Hencky strain ln U (classical/polar.hpp), over
// row-major double[9], no Eigen.
//
// Bits. The host computed these with Eigen 3.4 (Eigen::JacobiSVD of a fixed 3 x 3 matrix,
// MatrixBase::determinant); the functions below are that code's algorithm written out with
// its operations in its order, so they give its bits (tests/unit/test_law_kernels.cpp
// compares them on random inputs):
//   - the determinant: m00 (m11 m22 - m12 m21) - m01 (m10 m22 - m12 m20) + m02 (m10 m21 -
//     m11 m20), left to right (Eigen's bruteforce_det3_helper);
//   - the SVD: Eigen's two-sided Jacobi SVD (Eigen/src/SVD/JacobiSVD.h,
//     read for its algorithm): no QR preconditioning for a square matrix; the matrix scaled
//     by its largest |entry|; sweeps over the pairs (p, q) = (1, 0), (2, 0), (2, 1) until
//     no off-diagonal entry exceeds max(DBL_MIN, 2 eps max|diagonal|); each pair's 2 x 2
//     block made symmetric by a rotation, then diagonalised by a Jacobi rotation (Eigen's
//     real_2x2_jacobi_svd and JacobiRotation::makeJacobi, whose formulas are the classical
//     ones of Golub and Van Loan, "Matrix Computations", 4th ed., sec. 8.5.2 and 8.6.3),
//     the rotations accumulated into U and V; the signs moved into U, then the singular
//     values sorted in decreasing order (the first of equal maxima kept in place). Every
//     rotation acts entry by entry (x' = c x + s y, y' = -s x + c y), so no sum order is
//     involved beyond what is written;
//   - products and the trace in affine.hpp's order (mat3_mul, mat3_trace), but for the
//     spectral product V diag(d) V^T, which Eigen evaluates entry by entry (spectral3).
// The sweep loop ends after kSvdSweeps sweeps at the latest: Eigen's has no bound, and a
// 3 x 3 matrix converges in a handful (a device thread must not loop forever on NaN-free
// but pathological input; the bound is never reached on finite input in the tests).
#include <cfloat>
#include <cmath>

#include "horizon/core/portable.hpp"
#include "horizon/kernels/affine.hpp"

namespace horizon::kernels {

HORIZON_HD inline double absolute(double x) { return x < 0 ? -x : (x == 0 ? 0.0 : x); }

// det m in Eigen's order (above).
HORIZON_HD inline double mat3_det(const double* m) {
  return m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6]) + m[2] * (m[3] * m[7] - m[4] * m[6]);
}

// c = a b^T and c = a^T (c may not alias a or b), in mat3_mul's order (the operands' values
// transposed first: Eigen's product reads a transposed operand by coefficient).
HORIZON_HD inline void mat3_transpose(const double* a, double* t) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) t[3 * c + r] = a[3 * r + c];
}
HORIZON_HD inline void mat3_mul_transposed(const double* a, const double* b, double* c) {
  double bt[9];
  mat3_transpose(b, bt);
  mat3_mul(a, bt, c);
}

// A plane rotation (c, s) as Eigen's JacobiRotation holds it.
struct Rotation2 {
  double c, s;
};

// Apply (c, s) to the pair (x, y): x' = c x + s y, y' = -s x + c y (Eigen's
// apply_rotation_in_the_plane; the identity rotation leaves them untouched).
HORIZON_HD inline void rotate_pair(double& x, double& y, Rotation2 j) {
  const double xi = x, yi = y;
  x = j.c * xi + j.s * yi;
  y = -j.s * xi + j.c * yi;
}
// Rows p and q of a row-major 3 x 3 (Eigen's applyOnTheLeft(p, q, j)).
HORIZON_HD inline void rotate_rows(double* m, int p, int q, Rotation2 j) {
  if (j.c == 1.0 && j.s == 0.0) return;
  for (int k = 0; k < 3; ++k) rotate_pair(m[3 * p + k], m[3 * q + k], j);
}
// Columns p and q with the rotation j applied as Eigen's applyOnTheRight(p, q, j) does:
// by j's transpose (c, -s).
HORIZON_HD inline void rotate_columns(double* m, int p, int q, Rotation2 j) {
  const Rotation2 t{j.c, -j.s};
  if (t.c == 1.0 && t.s == 0.0) return;
  for (int k = 0; k < 3; ++k) rotate_pair(m[3 * k + p], m[3 * k + q], t);
}

// Eigen's JacobiRotation::makeJacobi(x, y, z): the rotation that diagonalises the
// symmetric 2 x 2 [[x, y], [y, z]].
HORIZON_HD inline Rotation2 make_jacobi(double x, double y, double z) {
  const double deno = 2.0 * absolute(y);
  if (deno < DBL_MIN) return {1.0, 0.0};
  const double tau = (x - z) / deno;
  const double w = root(tau * tau + 1.0);
  const double t = tau > 0.0 ? 1.0 / (tau + w) : 1.0 / (tau - w);
  const double sign_t = t > 0.0 ? 1.0 : -1.0;
  const double n = 1.0 / root(t * t + 1.0);
  return {n, -sign_t * (y / absolute(y)) * absolute(t) * n};
}

// Eigen's real_2x2_jacobi_svd of block (p, q) of w: the left and right rotations.
HORIZON_HD inline void jacobi_2x2(const double* w, int p, int q, Rotation2& left, Rotation2& right) {
  double m[4] = {w[3 * p + p], w[3 * p + q], w[3 * q + p], w[3 * q + q]};
  Rotation2 rot1{1.0, 0.0};
  const double t = m[0] + m[3], d = m[2] - m[1];
  if (!(absolute(d) < DBL_MIN)) {
    const double u = t / d, tmp = root(1.0 + u * u);
    rot1 = {u / tmp, 1.0 / tmp};
  }
  if (!(rot1.c == 1.0 && rot1.s == 0.0))
    for (int k = 0; k < 2; ++k) rotate_pair(m[k], m[2 + k], rot1);
  right = make_jacobi(m[0], m[1], m[3]);
  // left = rot1 * right^T (JacobiRotation::operator*, transpose: (c, -s)).
  const Rotation2 rt{right.c, -right.s};
  left = {rot1.c * rt.c - rot1.s * rt.s, rot1.c * rt.s + rot1.s * rt.c};
}

inline constexpr int kSvdSweeps = 64;

// a = U diag(sv) V^T (row-major U, V; sv decreasing, >= 0), Eigen::JacobiSVD<Matrix3d>
// with ComputeFullU | ComputeFullV. False for a matrix with a non-finite entry (Eigen's
// InvalidInput).
HORIZON_HD inline bool svd3(const double* a, double* U, double* sv, double* V) {
  double scale = 0;
  for (int k = 0; k < 9; ++k) {
    if (!finite(a[k])) return false;
    const double v = absolute(a[k]);
    scale = v > scale ? v : scale;
  }
  if (scale == 0.0) scale = 1.0;
  double w[9];
  for (int k = 0; k < 9; ++k) w[k] = a[k] / scale, U[k] = V[k] = (k % 4 == 0) ? 1.0 : 0.0;
  const double precision = 2.0 * DBL_EPSILON;
  auto larger = [](double x, double y) { return x < y ? y : x; };  // numext::maxi
  double max_diag = absolute(w[0]);
  max_diag = absolute(w[4]) > max_diag ? absolute(w[4]) : max_diag;
  max_diag = absolute(w[8]) > max_diag ? absolute(w[8]) : max_diag;
  bool finished = false;
  for (int sweep = 0; !finished && sweep < kSvdSweeps; ++sweep) {
    finished = true;
    // The pairs (1, 0), (2, 0), (2, 1) in Eigen's order, unrolled: constant indices keep
    // w, U and V in a device thread's registers (no local memory).
#if defined(__CUDA_ARCH__)
#pragma unroll
#endif
    for (int pair = 0; pair < 3; ++pair) {
      const int p = pair == 0 ? 1 : 2, q = pair == 2 ? 1 : 0;
        const double threshold = larger(DBL_MIN, precision * max_diag);
        if (absolute(w[3 * p + q]) > threshold || absolute(w[3 * q + p]) > threshold) {
          finished = false;
          Rotation2 left, right;
          jacobi_2x2(w, p, q, left, right);
          rotate_rows(w, p, q, left);
          rotate_columns(U, p, q, {left.c, -left.s});  // applyOnTheRight(p, q, left^T)
          rotate_columns(w, p, q, right);
          rotate_columns(V, p, q, right);
          max_diag = larger(max_diag, larger(absolute(w[3 * p + p]), absolute(w[3 * q + q])));
        }
      }
  }
  for (int i = 0; i < 3; ++i) {
    const double d = w[4 * i];
    sv[i] = absolute(d);
    if (d < 0.0)
      for (int k = 0; k < 3; ++k) U[3 * k + i] = -U[3 * k + i];
  }
  for (int i = 0; i < 3; ++i) sv[i] *= scale;
  // Eigen's selection sort: for i = 0, 1 the first largest of sv[i..2] swapped to i with
  // its columns of U and V, stopping at a zero maximum (written with constant indices).
  auto swap_entries = [&](int i, int j) {
    const double t = sv[i];
    sv[i] = sv[j], sv[j] = t;
    for (int k = 0; k < 3; ++k) {
      const double u = U[3 * k + i], v = V[3 * k + i];
      U[3 * k + i] = U[3 * k + j], U[3 * k + j] = u;
      V[3 * k + i] = V[3 * k + j], V[3 * k + j] = v;
    }
  };
  const int first = sv[1] > sv[0] ? (sv[2] > sv[1] ? 2 : 1) : (sv[2] > sv[0] ? 2 : 0);
  const double largest = first == 0 ? sv[0] : (first == 1 ? sv[1] : sv[2]);
  if (largest == 0.0) return true;
  if (first == 1) swap_entries(0, 1);
  if (first == 2) swap_entries(0, 2);
  if (sv[1] == 0.0 && sv[2] == 0.0) return true;
  if (sv[2] > sv[1]) swap_entries(1, 2);
  return true;
}

// V diag(d) V^T in Eigen's order for `V * d.asDiagonal() * V.transpose()` (polar.hpp):
// Eigen does not vectorise this nested product (unlike a product of two plain matrices,
// mat3_mul): every entry is its scalar reduction p0 + (p1 + p2), p_k = (V_rk d_k) V_ck.
// Measured, not read from Eigen's cost model: this order, and no packet order, gives the
// host's bits in the unit test and the Taylor bar's state_crc32 (docs/design.md).
HORIZON_HD inline void spectral3(const double* V, const double* d, double* out) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      const double p0 = (V[3 * r] * d[0]) * V[3 * c], p1 = (V[3 * r + 1] * d[1]) * V[3 * c + 1],
                   p2 = (V[3 * r + 2] * d[2]) * V[3 * c + 2];
      out[3 * r + c] = p0 + (p1 + p2);
    }
}

// The polar decomposition F = R U and the Hencky strain ln U of classical/polar.hpp
// (F = W S V^T: R = W V^T, ln U = V ln(S) V^T); false (R = I, ln U = 0) when det F <= 0,
// F is not finite or a singular value is not positive.
HORIZON_HD inline bool polar_log3(const double* F, double* R, double* log_U) {
  for (int k = 0; k < 9; ++k) R[k] = (k % 4 == 0) ? 1.0 : 0.0, log_U[k] = 0.0;
  const double J = mat3_det(F);
  if (!(J > 0) || !finite(J)) return false;
  double W[9], V[9], s[3];
  if (!svd3(F, W, s, V)) return false;
  const double smin = s[1] < s[0] ? (s[2] < s[1] ? s[2] : s[1]) : (s[2] < s[0] ? s[2] : s[0]);
  if (!(smin > 0)) return false;
  mat3_mul_transposed(W, V, R);
  const double ls[3] = {natural_log(s[0]), natural_log(s[1]), natural_log(s[2])};
  spectral3(V, ls, log_U);
  return true;
}

}  // namespace horizon::kernels
