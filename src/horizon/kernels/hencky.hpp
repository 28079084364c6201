#pragma once
// Extended correspondence's Hencky map (material/models/extended_correspondence.hpp,
// HenckyMap: E_log = 1/2 ln C of C = I + 2 E_(1), and the stress conjugate to E_(1) by the
// Daleckii-Krein formula, Miehe, Apel and Lambrecht 2002, CMAME 191, 5383, eqs. 2.5 and 2.8)
// as device-portable functions (core/portable.hpp, issue 30) over row-major double[9].
//
// Bits. The host form diagonalises C with Eigen 3.4's SelfAdjointEigenSolver of a fixed
// 3 x 3 (Eigen/src/Eigenvalues/SelfAdjointEigenSolver.h and Tridiagonalization.h, read for
// the algorithm); sym_eigen3 below is that algorithm written out in its order:
//   - the lower triangle scaled by its largest |entry| (a division per entry);
//   - one Householder reflection brings it to tridiagonal form (the closed form Eigen uses
//     for 3 x 3: beta = |(a10, a20)|, q = 2 m01 a21 + m02 (a22 - a11)), Q = [1 0 0; 0 m01
//     m02; 0 m02 -m01], or the identity when a20^2 <= DBL_MIN;
//   - implicit symmetric QR steps with Wilkinson's shift on the trailing unreduced block
//     (Golub and Van Loan, "Matrix Computations", 4th ed., alg. 8.3.2), a subdiagonal
//     entry deflated when (e / eps)^2 <= |d_i| + |d_i+1| or |e| < DBL_MIN; Givens rotations
//     as Eigen's JacobiRotation::makeGivens makes them, accumulated into Q's columns;
//     at most 30 n = 90 steps (Eigen's bound; without convergence the values stay unsorted);
//   - the eigenvalues scaled back, then sorted increasing by selection (first minimum).
// The products follow the orders the host's Eigen expressions take, measured against them by
// tests/unit/test_hencky_kernels.cpp: A B is affine.hpp's mat3_mul, A B^T mat3_mul_transposed
// (eigen3.hpp), A^T B mat3_mul_dots (hypoelastic.hpp); but (N Lg) N^T with a diagonal Lg
// (stored dense) takes p0 + (p1 + p2) in every entry, as eigen3.hpp's spectral3 (the three
// orders differ in 12-18 % of the entries on random input).
#include <cfloat>

#include "horizon/core/portable.hpp"
#include "horizon/kernels/eigen3.hpp"
#include "horizon/kernels/hypoelastic.hpp"
#include "horizon/kernels/unified.hpp"

namespace horizon::kernels {

// Eigen's numext::hypot (positive_real_hypot of |x|, |y|) for finite x, y.
HORIZON_HD inline double eigen_hypot(double x, double y) {
  const double ax = absolute(x), ay = absolute(y);
  if (ax == INFINITY || ay == INFINITY) return INFINITY;
  if (ax != ax || ay != ay) return ax + ay;  // NaN
  const double p = std_max(ax, ay);
  if (p == 0.0) return 0.0;
  const double qp = std_min(ay, ax) / p;
  return p * root(1.0 + qp * qp);
}

// Eigen's JacobiRotation::makeGivens(p, q) for real scalars (no r).
HORIZON_HD inline Rotation2 make_givens(double p, double q) {
  if (q == 0.0) return {p < 0.0 ? -1.0 : 1.0, 0.0};
  if (p == 0.0) return {0.0, q < 0.0 ? 1.0 : -1.0};
  if (absolute(p) > absolute(q)) {
    const double t = q / p;
    double u = root(1.0 + t * t);
    if (p < 0.0) u = -u;
    const double c = 1.0 / u;
    return {c, -t * c};
  }
  const double t = p / q;
  double u = root(1.0 + t * t);
  if (q < 0.0) u = -u;
  const double s = -1.0 / u;
  return {-t * s, s};
}

// One implicit symmetric QR step on diag/sub[start..end] (Eigen's tridiagonal_qr_step).
HORIZON_HD inline void tridiagonal_qr_step3(double* diag, double* sub, int start, int end, double* Q) {
  const double td = (diag[end - 1] - diag[end]) * 0.5;
  const double e = sub[end - 1];
  double mu = diag[end];
  if (td == 0.0) {
    mu -= absolute(e);
  } else if (e != 0.0) {
    const double e2 = e * e;
    const double h = eigen_hypot(td, e);
    if (e2 == 0.0)
      mu -= e / ((td + (td > 0.0 ? h : -h)) / e);
    else
      mu -= e2 / (td + (td > 0.0 ? h : -h));
  }
  double x = diag[start] - mu;
  double z = sub[start];
  for (int k = start; k < end && z != 0.0; ++k) {
    const Rotation2 rot = make_givens(x, z);
    const double c = rot.c, s = rot.s;
    const double sdk = s * diag[k] + c * sub[k];
    const double dkp1 = s * sub[k] + c * diag[k + 1];
    diag[k] = c * (c * diag[k] - s * sub[k]) - s * (c * sub[k] - s * diag[k + 1]);
    diag[k + 1] = s * sdk + c * dkp1;
    sub[k] = c * sdk - s * dkp1;
    if (k > start) sub[k - 1] = c * sub[k - 1] - s * z;
    x = sub[k];
    if (k < end - 1) {
      z = -s * sub[k + 1];
      sub[k + 1] = c * sub[k + 1];
    }
    rotate_columns(Q, k, k + 1, rot);  // Q = Q G (applyOnTheRight)
  }
}

// Eigen's SelfAdjointEigenSolver<Matrix3d>(A) (its lower triangle is read): eigenvalues in
// increasing order, eigenvectors the columns of Q (row-major). False when the QR steps did not
// converge (Eigen's NoConvergence: then the values are unsorted, as Eigen leaves them).
HORIZON_HD inline bool sym_eigen3(const double* A, double* eval, double* Q) {
  double m[9] = {A[0], 0.0, 0.0, A[3], A[4], 0.0, A[6], A[7], A[8]};  // triangularView<Lower>
  double scale = 0.0;
  for (int k = 0; k < 9; ++k) scale = std_max(scale, absolute(m[k]));
  if (scale == 0.0) scale = 1.0;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c <= r; ++c) m[3 * r + c] /= scale;
  // Tridiagonalization (Eigen's 3 x 3 tridiagonalization_inplace_selector).
  double diag[3], sub[2];
  diag[0] = m[0];
  const double v1norm2 = m[6] * m[6];
  for (int k = 0; k < 9; ++k) Q[k] = (k % 4 == 0) ? 1.0 : 0.0;
  if (v1norm2 <= DBL_MIN) {
    diag[1] = m[4];
    diag[2] = m[8];
    sub[0] = m[3];
    sub[1] = m[7];
  } else {
    const double beta = root(m[3] * m[3] + v1norm2);
    const double inv_beta = 1.0 / beta;
    const double m01 = m[3] * inv_beta, m02 = m[6] * inv_beta;
    const double q = 2.0 * m01 * m[7] + m02 * (m[8] - m[4]);
    diag[1] = m[4] + m02 * q;
    diag[2] = m[8] - m02 * q;
    sub[0] = beta;
    sub[1] = m[7] - m01 * q;
    Q[4] = m01, Q[5] = m02, Q[7] = m02, Q[8] = -m01;
  }
  // computeFromTridiagonal_impl.
  const double precision_inv = 1.0 / DBL_EPSILON;
  int end = 2, start = 0, iter = 0;
  const int max_iter = 30 * 3;
  while (end > 0) {
    for (int i = start; i < end; ++i) {
      if (absolute(sub[i]) < DBL_MIN) {
        sub[i] = 0.0;
      } else {
        const double scaled = precision_inv * sub[i];
        if (scaled * scaled <= (absolute(diag[i]) + absolute(diag[i + 1]))) sub[i] = 0.0;
      }
    }
    while (end > 0 && sub[end - 1] == 0.0) end--;
    if (end <= 0) break;
    iter++;
    if (iter > max_iter) break;
    start = end - 1;
    while (start > 0 && sub[start - 1] != 0.0) start--;
    tridiagonal_qr_step3(diag, sub, start, end, Q);
  }
  const bool ok = iter <= max_iter;
  if (ok) {
    for (int i = 0; i < 2; ++i) {
      int k = i;
      for (int j = i + 1; j < 3; ++j)
        if (diag[j] < diag[k]) k = j;
      if (k > i) {
        const double t = diag[i];
        diag[i] = diag[k];
        diag[k] = t;
        for (int r = 0; r < 3; ++r) {
          const double u = Q[3 * r + i];
          Q[3 * r + i] = Q[3 * r + k];
          Q[3 * r + k] = u;
        }
      }
    }
  }
  for (int a = 0; a < 3; ++a) eval[a] = diag[a] * scale;
  return ok;
}

// HenckyMap of the host form (extended_correspondence.hpp, hencky_of_green): C = I + 2 E1
// symmetrised, its eigenvectors N (columns), eigenvalues l clamped below at `floor`, and
// E_log = N diag(ln(l)/2) N^T.
HORIZON_HD inline void hencky_of_green3(const double* E1, double floor, double* N, double* l, double* strain) {
  double C[9], Cs[9];
  for (int k = 0; k < 9; ++k) C[k] = ((k % 4 == 0) ? 1.0 : 0.0) + 2.0 * E1[k];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) Cs[3 * r + c] = 0.5 * (C[3 * r + c] + C[3 * c + r]);
  double ev[3];
  sym_eigen3(Cs, ev, N);
  double Lg[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
  for (int a = 0; a < 3; ++a) {
    l[a] = std_max(ev[a], floor);
    Lg[4 * a] = 0.5 * natural_log(l[a]);
  }
  // The host's N Lg N^T: N Lg a product with Lg's zeros (they set the signs of zero entries),
  // then entry by entry p0 + (p1 + p2).
  double NL[9];
  mat3_mul(N, Lg, NL);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      strain[3 * r + c] = NL[3 * r] * N[3 * c] + (NL[3 * r + 1] * N[3 * c + 1] + NL[3 * r + 2] * N[3 * c + 2]);
}

// (ln a - ln b)/(a - b), stable as b -> a (the host's log_divided_difference).
HORIZON_HD inline double log_divided_difference3(double a, double b) {
  const double x = (a - b) / (a + b);
  if (absolute(x) < 1e-4) return 2.0 / (a + b) * (1.0 + x * x / 3.0 + x * x * x * x / 5.0);
  return (natural_log(a) - natural_log(b)) / (a - b);
}

// The stress conjugate to E_(1) from the law's stress T at the Hencky strain (the host's
// green_stress_of_hencky): S = N (theta o (N^T T N)) N^T.
HORIZON_HD inline void green_stress_of_hencky3(const double* N, const double* l, const double* T, double* S) {
  double Nt[9], NtT[9], Tt[9], St[9], NS[9];
  mat3_transpose(N, Nt);
  mat3_mul_dots(Nt, T, NtT);
  mat3_mul(NtT, N, Tt);
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      St[3 * a + b] = (a == b ? 1.0 / l[a] : log_divided_difference3(l[a], l[b])) * Tt[3 * a + b];
  mat3_mul(N, St, NS);
  mat3_mul_transposed(NS, N, S);
}

}  // namespace horizon::kernels
