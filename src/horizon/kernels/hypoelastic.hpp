#pragma once
// The correspondence model's rate-form laws (material/classical/hypoelastic.hpp:
// hypoelastic_step with the work, peridigm and needleman returns and the Cayley and
// Peridigm rotation updates; the formulas and their sources are there) as a
// device-portable function (core/portable.hpp, issue 30) over row-major double[9] and a
// plain history struct.
//
// Bits: Eigen's operations in Eigen's order, as in kernels/laws.hpp, with the LU solves
// written out: `M.lu().solve(b)` (Eigen's PartialPivLU of a fixed 3 x 3: partial pivoting
// on the first largest |entry|, the column below the pivot divided by it, the rank-one
// update d - l u), a vector right-hand side by its unrolled substitutions (sums of the
// known terms first, then one subtraction, a division by the pivot), a matrix right-hand
// side by the column sweep of Eigen's triangular_solve_matrix (each known entry's term
// subtracted in turn, the pivot's reciprocal multiplied); a scalar times a product,
// s (A B), as Eigen rewrites it, (s A) B. tests/unit/test_law_kernels.cpp
// compares the whole step with hypoelastic_step bit for bit.
#include <cmath>
#include <cstdint>

#include "horizon/core/portable.hpp"
#include "horizon/kernels/affine.hpp"
#include "horizon/kernels/eigen3.hpp"
#include "horizon/kernels/laws.hpp"
#include "horizon/kernels/unified.hpp"

namespace horizon::kernels {

HORIZON_HD inline double sine(double x) {
#if defined(__CUDA_ARCH__)
  return ::sin(x);
#else
  return std::sin(x);
#endif
}

// std::max and std::min as the host forms call them (the first argument on ties and NaN).
HORIZON_HD inline double std_max(double a, double b) { return a < b ? b : a; }
HORIZON_HD inline double std_min(double a, double b) { return b < a ? b : a; }

// Eigen's PartialPivLU of a row-major 3 x 3 in place: perm[k] the row swapped into k.
HORIZON_HD inline void lu3(double* lu, int* perm) {
  for (int k = 0; k < 2; ++k) {
    int p = k;
    double big = absolute(lu[3 * k + k]);
    for (int r = k + 1; r < 3; ++r)
      if (absolute(lu[3 * r + k]) > big) big = absolute(lu[3 * r + k]), p = r;
    perm[k] = p;
    if (big != 0.0) {
      if (p != k)
        for (int c = 0; c < 3; ++c) {
          const double t = lu[3 * k + c];
          lu[3 * k + c] = lu[3 * p + c], lu[3 * p + c] = t;
        }
      for (int r = k + 1; r < 3; ++r) lu[3 * r + k] = lu[3 * r + k] / lu[3 * k + k];
    }
    for (int r = k + 1; r < 3; ++r)
      for (int c = k + 1; c < 3; ++c) lu[3 * r + c] = lu[3 * r + c] - lu[3 * r + k] * lu[3 * k + c];
  }
  perm[2] = 2;
}

// The row transpositions of lu3 applied to the rows of x (n columns, row-major).
HORIZON_HD inline void lu3_permute(const int* perm, double* x, int n) {
  for (int k = 0; k < 3; ++k)
    if (perm[k] != k)
      for (int c = 0; c < n; ++c) {
        const double t = x[n * k + c];
        x[n * k + c] = x[n * perm[k] + c], x[n * perm[k] + c] = t;
      }
}

// x = M^-1 b for a vector (Eigen's unrolled triangular solves).
HORIZON_HD inline void lu3_solve_vector(const double* lu, const int* perm, const double* b, double* x) {
  for (int r = 0; r < 3; ++r) x[r] = b[r];
  lu3_permute(perm, x, 1);
  x[1] = x[1] - lu[3] * x[0];
  x[2] = x[2] - (lu[6] * x[0] + lu[7] * x[1]);
  x[2] = x[2] / lu[8];
  x[1] = (x[1] - lu[5] * x[2]) / lu[4];
  x[0] = (x[0] - (lu[1] * x[1] + lu[2] * x[2])) / lu[0];
}

// X = M^-1 B for a 3 x 3 right-hand side (Eigen's triangular_solve_matrix, column by
// column: forward with the unit lower factor, then backward with the upper one).
HORIZON_HD inline void lu3_solve_matrix(const double* lu, const int* perm, const double* B, double* X) {
  for (int k = 0; k < 9; ++k) X[k] = B[k];
  lu3_permute(perm, X, 3);
  for (int j = 0; j < 3; ++j) {
    X[3 + j] = X[3 + j] - X[j] * lu[3];
    X[6 + j] = X[6 + j] - X[j] * lu[6];
    X[6 + j] = X[6 + j] - X[3 + j] * lu[7];
  }
  const double a2 = 1.0 / lu[8], a1 = 1.0 / lu[4], a0 = 1.0 / lu[0];
  for (int j = 0; j < 3; ++j) {
    X[6 + j] = X[6 + j] * a2;
    X[j] = X[j] - X[6 + j] * lu[2];
    X[3 + j] = X[3 + j] - X[6 + j] * lu[5];
    X[3 + j] = X[3 + j] * a1;
    X[j] = X[j] - X[3 + j] * lu[1];
    X[j] = X[j] * a0;
  }
}

// A product whose left operand is a transpose (Eigen's R.transpose() * D): Eigen takes each
// entry as a dot product of two contiguous rows in one packet and a remainder,
// (a0 b0 + a1 b1) + a2 b2, for every row (mat3_mul does so for rows 0 and 1 alone).
HORIZON_HD inline void mat3_mul_dots(const double* a, const double* b, double* c) {
  for (int r = 0; r < 3; ++r)
    for (int j = 0; j < 3; ++j)
      c[3 * r + j] = (a[3 * r] * b[j] + a[3 * r + 1] * b[3 + j]) + a[3 * r + 2] * b[6 + j];
}

// The rate-form history (classical::HypoState), row-major.
struct HypoHistory {
  double F[9], V[9], R[9], sigma_u[9];
  double alpha, thermal;
};

enum HypoReturn : int { kReturnWork = 0, kReturnPeridigm = 1, kReturnNeedleman = 2 };
enum HypoRotation : int { kRotationCayley = 0, kRotationPeridigm = 1 };

struct HypoConstants {
  double lambda = 0, mu = 0, kappa = 0;
  double hardening = 0;
  int plastic_return = kReturnWork, rotation = kRotationCayley;
  double N = 0, m = 0, rate0 = 1, eps0 = 1, eps1 = 1;  // Needleman's flow stress
};

// Needleman's flow stress (classical::Needleman::flow).
HORIZON_HD inline double needleman_flow(const HypoConstants& c, double sigma0, double x, double alpha, double dt) {
  const double hardening = sigma0 * power(1.0 + alpha / c.eps0, c.N) / (1.0 + (alpha / c.eps1) * (alpha / c.eps1));
  return hardening * power(root(2.0 / 3.0) * x / dt / c.rate0, c.m);
}

// Peridigm's scaling of the trial deviator (classical::peridigm_scale).
HORIZON_HD inline void hypo_peridigm_scale(const HypoConstants& c, double y, double q_tr, double norm_tr,
                                           const double* dev_n, double alpha_n, const double* de, double* dev,
                                           double& alpha, double& plastic_work) {
  const double norm_n = root(mat3_contract(dev_n, dev_n));
  const double f = y / q_tr, two_mu = 2.0 * c.mu, mn = std_max(1e-20, norm_n);
  for (int k = 0; k < 9; ++k) dev[k] = dev[k] * f;
  double dep[9], mean[9], half[9];
  for (int k = 0; k < 9; ++k) {
    dep[k] = de[k] - (dev[k] - dev_n[k]) / two_mu;
    mean[k] = 0.5 * (dev[k] / norm_tr + dev_n[k] / mn);
    half[k] = 0.5 * (dev[k] + dev_n[k]);
  }
  alpha = alpha_n + std_max(0.0, root(2.0 / 3.0) * mat3_contract(dep, mean));
  plastic_work = std_max(0.0, mat3_contract(half, dep));
}

// Peridigm's returns (classical::peridigm_return).
HORIZON_HD inline void hypo_peridigm_return(const HypoConstants& c, double sigma0, const double* dev_n, double alpha_n,
                                            const double* de, double dt, double* dev, double& alpha,
                                            double& plastic_work) {
  alpha = alpha_n;
  const double norm_tr = std_max(1e-20, root(mat3_contract(dev, dev)));
  const double q_tr = root(1.5) * norm_tr;
  if (q_tr < sigma0) return;
  const double norm_n = root(mat3_contract(dev_n, dev_n));
  const double de_s = mat3_contract(dev, de) / norm_tr;
  double y = 0;
  if (c.plastic_return == kReturnNeedleman) {
    auto residual = [&](double x) {
      return de_s - x - (root(2.0 / 3.0) * needleman_flow(c, sigma0, x, alpha_n + x, dt) - norm_n) / (2.0 * c.mu);
    };
    double lo = 0, hi = 1, mid = 0.5;
    for (int iter = 0; iter < 200; ++iter) {
      const double r_hi = residual(hi), r_mid = residual(mid);
      const bool same = (r_hi > 0 && r_mid > 0) || (r_hi < 0 && r_mid < 0);
      if (same)
        hi = mid;
      else
        lo = mid;
      const double next = 0.5 * (lo + hi);
      const bool done = absolute(next - mid) / absolute(next) < 1e-6;
      mid = next;
      if (done) break;
    }
    y = needleman_flow(c, sigma0, mid, alpha_n + root(2.0 / 3.0) * mid, dt);
  } else {
    const double dlambda =
        (6.0 * c.mu * de_s + 3.0 * norm_n - root(6.0) * sigma0) / (2.0 * (c.hardening + 3.0 * c.mu));
    y = sigma0 + c.hardening * (alpha_n + root(2.0 / 3.0) * dlambda);
  }
  if (!(q_tr > y)) return;
  hypo_peridigm_scale(c, y, q_tr, norm_tr, dev_n, alpha_n, de, dev, alpha, plastic_work);
}

// Peridigm's rotation increment Q over dt for the spin Omega
// (classical::peridigm_rotation_increment).
HORIZON_HD inline void hypo_peridigm_rotation(const double* Omega, double dt, double* Q) {
  const double w[3] = {Omega[7], Omega[2], Omega[3]};
  const double w2 = squared_norm3(w);
  if (!(w2 > 1e-30)) {
    for (int k = 0; k < 9; ++k) Q[k] = identity3(k);
    return;
  }
  const double norm = root(w2);
  const double f1 = sine(dt * norm) / norm, f2 = -(1.0 - cosine(dt * norm)) / w2;
  // Eigen takes f2 (Omega Omega) as (f2 Omega) Omega (its scalar-times-product rewrite):
  // the scaled left factor, then mat3_mul's order.
  double fO[9], O2[9];
  for (int k = 0; k < 9; ++k) fO[k] = f2 * Omega[k];
  mat3_mul(fO, Omega, O2);
  for (int k = 0; k < 9; ++k) Q[k] = (identity3(k) + f1 * Omega[k]) + O2[k];
}

// F_dot of the rate-form laws (Correspondence's law_at): N = sum_j omega V_j du (x) xi over
// the acting bonds, du the bond's displacement increment since the commit, then
// F_dot = N K^-1 / dt (Eigen's outer product: N_ij + xi_j (w du_i)).
HORIZON_HD inline void rate_gradient_add(double* N, const double* du, const double* xi, double w) {
  const double a[3] = {w * du[0], w * du[1], w * du[2]};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) N[3 * r + c] = N[3 * r + c] + xi[c] * a[r];
}
// Row i's sum N of F_dot over its acting bonds (intact != 0), in bond order, as
// Correspondence::affine_row formed it with a host loop: du = (u_j - uc_j) - (u_i - uc_i)
// (uc: u at the last commit), xi = X_j - X_i, each a difference per component, and the
// bond's w = omega V_j from w_of(k) (the host: B.weight[k] * B.volume[k]). X, u and uc are
// xyz interleaved (3n; a std::vector<Vec3>'s data read as doubles). N starts at 0.
template <class WeightOf>
HORIZON_HD inline void rate_gradient_row(const double* X, const double* u, const double* uc, const uint64_t* offset,
                                         const uint32_t* nbr, const uint8_t* intact, const WeightOf& w_of,
                                         uint64_t i, double* N) {
  for (int k = 0; k < 9; ++k) N[k] = 0.0;
  const double dui[3] = {u[3 * i] - uc[3 * i], u[3 * i + 1] - uc[3 * i + 1], u[3 * i + 2] - uc[3 * i + 2]};
  for (uint64_t k = offset[i]; k < offset[i + 1]; ++k) {
    if (!intact[k]) continue;
    const uint64_t j = nbr[k];
    double du[3], xi[3];
    for (int c = 0; c < 3; ++c) {
      du[c] = (u[3 * j + c] - uc[3 * j + c]) - dui[c];
      xi[c] = X[3 * j + c] - X[3 * i + c];
    }
    rate_gradient_add(N, du, xi, w_of(k));
  }
}
HORIZON_HD inline void rate_gradient_finish(const double* N, const double* Kinv, double dt, double* Fdot) {
  double NK[9];
  mat3_mul(N, Kinv, NK);
  for (int k = 0; k < 9; ++k) Fdot[k] = NK[k] / dt;
}

// One step of the rate form from the committed history n to F over dt
// (classical::hypoelastic_step): trial, the plastic work, the law's P, sigma and W, and the
// unrotated rate of deformation d. `yield`: the (flawed) yield stress, <= 0 elastic;
// `Fdot`: F_dot, or null for (F - F_n)/dt; `thermal`: the thermal strain now.
HORIZON_HD inline void hypo_step(const HypoConstants& c, double yield, const HypoHistory& n, const double* F,
                                 double dt, const double* Fdot, double thermal, HypoHistory& trial,
                                 double& plastic_work, LawStress& law, double* d) {
  trial = n;
  plastic_work = 0;
  clear_law(law);
  for (int k = 0; k < 9; ++k) d[k] = 0.0;
  const double J = mat3_det(F);
  if (!(J > 0) || !finite(J)) return;
  double Finv[9];
  mat3_inverse(F, Finv);
  if (dt > 0) {
    double Ld[9], L[9], D[9], W[9];
    for (int k = 0; k < 9; ++k) Ld[k] = Fdot ? Fdot[k] : (F[k] - n.F[k]) / dt;
    mat3_mul(Ld, Finv, L);
    for (int r = 0; r < 3; ++r)
      for (int s = 0; s < 3; ++s) {
        D[3 * r + s] = 0.5 * (L[3 * r + s] + L[3 * s + r]);
        W[3 * r + s] = 0.5 * (L[3 * r + s] - L[3 * s + r]);
      }
    double DV[9], VD[9], C[9], M[9];
    mat3_mul(D, n.V, DV);
    mat3_mul(n.V, D, VD);
    for (int k = 0; k < 9; ++k) C[k] = DV[k] - VD[k];
    const double trV = mat3_trace(n.V);
    for (int k = 0; k < 9; ++k) M[k] = trV * identity3(k) - n.V[k];
    int perm[3];
    lu3(M, perm);
    const double axial[3] = {C[7], C[2], C[3]};
    double a[3];
    lu3_solve_vector(M, perm, axial, a);
    const double S[9] = {0, -a[2], a[1], a[2], 0, -a[0], -a[1], a[0], 0};
    double Omega[9];
    for (int k = 0; k < 9; ++k) Omega[k] = W[k] + S[k];
    if (c.rotation == kRotationCayley) {
      const double h = 0.5 * dt;
      double minus[9], plus[9], rhs[9];
      for (int k = 0; k < 9; ++k) minus[k] = identity3(k) - h * Omega[k], plus[k] = identity3(k) + h * Omega[k];
      mat3_mul(plus, n.R, rhs);
      lu3(minus, perm);
      lu3_solve_matrix(minus, perm, rhs, trial.R);
    } else {
      double Q[9];
      hypo_peridigm_rotation(Omega, dt, Q);
      mat3_mul(Q, n.R, trial.R);
    }
    double LV[9], VO[9];
    mat3_mul(L, n.V, LV);
    mat3_mul(n.V, Omega, VO);
    for (int k = 0; k < 9; ++k) trial.V[k] = n.V[k] + dt * (LV[k] - VO[k]);
    for (int k = 0; k < 9; ++k) trial.F[k] = F[k];
    double Rt[9], RtD[9];
    mat3_transpose(trial.R, Rt);
    mat3_mul_dots(Rt, D, RtD);
    mat3_mul(RtD, trial.R, d);
    const double ltr = c.lambda * mat3_trace(d), two_mu = 2.0 * c.mu;
    double s[9];
    for (int k = 0; k < 9; ++k) s[k] = n.sigma_u[k] + dt * (ltr * identity3(k) + two_mu * d[k]);
    trial.thermal = thermal;
    if (thermal != n.thermal) {
      const double e = 3.0 * c.kappa * (thermal - n.thermal);
      for (int k = 0; k < 9; ++k) s[k] = s[k] - e * identity3(k);
    }
    const double p = mat3_trace(s) / 3.0;
    double dev[9];
    for (int k = 0; k < 9; ++k) dev[k] = s[k] - p * identity3(k);
    if (yield > 0 && c.plastic_return != kReturnWork) {
      const double td = mat3_trace(d) / 3.0, tn = mat3_trace(n.sigma_u) / 3.0;
      double de[9], dev_n[9];
      for (int k = 0; k < 9; ++k) de[k] = dt * (d[k] - td * identity3(k)), dev_n[k] = n.sigma_u[k] - tn * identity3(k);
      hypo_peridigm_return(c, yield, dev_n, n.alpha, de, dt, dev, trial.alpha, plastic_work);
    } else if (yield > 0) {
      const double q = root(1.5 * mat3_contract(dev, dev));
      const double limit = yield + c.hardening * n.alpha;
      if (q > limit) {
        const double da = (q * q - limit * limit) / (6.0 * c.mu * q);
        const double f = std_min(limit + c.hardening * da, q) / q;
        for (int k = 0; k < 9; ++k) dev[k] = dev[k] * f;
        trial.alpha = n.alpha + da;
        plastic_work = yield * da + 0.5 * c.hardening * (trial.alpha * trial.alpha - n.alpha * n.alpha);
      }
    }
    for (int k = 0; k < 9; ++k) trial.sigma_u[k] = p * identity3(k) + dev[k];
  }
  double Rs[9], Js[9];
  mat3_mul(trial.R, trial.sigma_u, Rs);
  mat3_mul_transposed(Rs, trial.R, law.sigma);
  for (int k = 0; k < 9; ++k) Js[k] = J * law.sigma[k];
  double FinvT[9];
  mat3_transpose(Finv, FinvT);
  mat3_mul(Js, FinvT, law.P);
  const double p = mat3_trace(trial.sigma_u) / 3.0;
  double dev[9];
  for (int k = 0; k < 9; ++k) dev[k] = trial.sigma_u[k] - p * identity3(k);
  law.W = (c.kappa > 0 ? 0.5 * p * p / c.kappa : 0.0) + (c.mu > 0 ? mat3_contract(dev, dev) / (4.0 * c.mu) : 0.0);
  law.ok = true;
}

}  // namespace horizon::kernels
