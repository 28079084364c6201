#pragma once
// The position-aware linear solid (material/models/pals.hpp; Mitchell, Silling and
// Littlewood 2015) as device-portable functions (core/portable.hpp, issue 30): the set-up's
// per-particle Lagrange multipliers (two 6 x 6 systems assembled over the family and solved
// by Gaussian elimination with partial pivoting, written out here: small and fixed-size),
// the influence functions they give each bond, and the per-bond and per-row work of the
// force pass (pals_row: the scalar pass's row; Pals::force_state, the vector pass, calls
// the per-bond functions). Each keeps the model's operations in their order, so its
// answers keep their bits.
//
//   sigma_ij = omega (1 + Lambda : xi xi),   tau_ij = omega' (1 + sum_k mu_k g_k(xi))
//   theta = sum_j sigma |xi| e V_j,  e^d = e - theta |xi|/3,  S = sum_j tau e^d |xi| V_j
//   t_ij = kappa theta sigma |xi| + 2 mu tau e^d - (2 mu/3) S sigma |xi|
//   W_i = kappa theta^2/2 + mu sum_j tau (e^d)^2 V_j
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "horizon/core/portable.hpp"
#include "horizon/kernels/ordinary.hpp"

namespace horizon::kernels {

// |x| (std::abs of a double; the device's fabs).
HORIZON_HD inline double pals_abs(double x) {
#if defined(__CUDA_ARCH__)
  return ::fabs(x);
#else
  return std::fabs(x);
#endif
}

// Solves the 6 x 6 system a x = b (a and b are overwritten) by Gaussian elimination with
// partial pivoting; false when a pivot is below 1e-13 of the largest entry (a family too
// small or too flat to carry the six constraints).
HORIZON_HD inline bool pals_solve6(double a[6][6], double b[6], double x[6]) {
  double scale = 0;
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c) {
      const double m = pals_abs(a[r][c]);
      scale = scale < m ? m : scale;  // std::max(scale, m)
    }
  if (!(scale > 0)) return false;
  for (int c = 0; c < 6; ++c) {
    int p = c;
    for (int r = c + 1; r < 6; ++r)
      if (pals_abs(a[r][c]) > pals_abs(a[p][c])) p = r;
    if (!(pals_abs(a[p][c]) > 1e-13 * scale)) return false;
    if (p != c) {
      for (int k = 0; k < 6; ++k) {
        const double t = a[p][k];
        a[p][k] = a[c][k], a[c][k] = t;
      }
      const double t = b[p];
      b[p] = b[c], b[c] = t;
    }
    for (int r = c + 1; r < 6; ++r) {
      const double f = a[r][c] / a[c][c];
      for (int k = c; k < 6; ++k) a[r][k] -= f * a[c][k];
      b[r] -= f * b[c];
    }
  }
  for (int r = 5; r >= 0; --r) {
    double s = b[r];
    for (int k = r + 1; k < 6; ++k) s -= a[r][k] * x[k];
    x[r] = s / a[r][r];
  }
  return true;
}

// The dilatation constraints' measures of a bond xi: xi_a xi_b in the order xx, yy, zz, xy,
// xz, yz (Peridigm's order of Lagrange_Multiplier_Dilatation_1..6).
HORIZON_HD inline void pals_quadratic(double x, double y, double z, double q[6]) {
  q[0] = x * x, q[1] = y * y, q[2] = z * z;
  q[3] = x * y, q[4] = x * z, q[5] = y * z;
}

// g_k(xi) = (xi . D_k . xi)^2 / |xi|^2 of the six deviatoric modes (material/models/pals.hpp):
// D_a = e_a e_a - I/3 (xi . D . xi = xi_a^2 - |xi|^2/3), then the shears xy, xz, yz (2 xi_a xi_b).
HORIZON_HD inline void pals_modes(double x, double y, double z, double g[6]) {
  const double r2 = x * x + y * y + z * z;
  const double s[6] = {x * x - r2 / 3, y * y - r2 / 3, z * z - r2 / 3, 2 * x * y, 2 * x * z, 2 * y * z};
  for (int k = 0; k < 6; ++k) g[k] = s[k] * s[k] / r2;
}

// D_k : D_k of the modes: 2/3 for the deviatoric uniaxial strains, 2 for the shears.
HORIZON_HD inline double pals_mode_norm(int k) { return k < 3 ? 2.0 / 3.0 : 2.0; }

// 1 + Lambda : xi (x) xi, Lambda symmetric (the off-diagonal terms twice): sigma / omega.
HORIZON_HD inline double pals_dilatation_factor(const double lambda[6], double x, double y, double z) {
  double q[6];
  pals_quadratic(x, y, z, q);
  return 1 + lambda[0] * q[0] + lambda[1] * q[1] + lambda[2] * q[2] +
         2 * (lambda[3] * q[3] + lambda[4] * q[4] + lambda[5] * q[5]);
}

// 1 + sum_k mu_k g_k(xi): tau / omega.
HORIZON_HD inline double pals_deviatoric_factor(const double mu[6], double x, double y, double z) {
  double g[6];
  pals_modes(x, y, z, g);
  double s = 1;
  for (int k = 0; k < 6; ++k) s += mu[k] * g[k];
  return s;
}

// The multipliers of one particle from its n bonds xi (Vec: members x, y, z) and omega V_j
// (wv) of each: sum_j omega V (1 + Lambda : xi xi) xi_a xi_b = delta_ab (dilatation), and
// sum_j omega V (1 + sum_l mu_l g_l) g_k = D_k : D_k (deviatoric). False: singular.
template <class Vec>
HORIZON_HD inline bool pals_dilatation_multipliers(const Vec* xi, const double* wv, std::size_t n, double out[6]) {
  double a[6][6] = {}, b[6] = {1, 1, 1, 0, 0, 0};
  for (std::size_t j = 0; j < n; ++j) {
    double q[6];
    pals_quadratic(xi[j].x, xi[j].y, xi[j].z, q);
    for (int r = 0; r < 6; ++r) {
      b[r] -= wv[j] * q[r];
      for (int c = 0; c < 6; ++c) a[r][c] += wv[j] * q[r] * q[c] * (c < 3 ? 1.0 : 2.0);
    }
  }
  return pals_solve6(a, b, out);
}
template <class Vec>
HORIZON_HD inline bool pals_deviatoric_multipliers(const Vec* xi, const double* wv, std::size_t n, double out[6]) {
  double a[6][6] = {}, b[6];
  for (int k = 0; k < 6; ++k) b[k] = pals_mode_norm(k);
  for (std::size_t j = 0; j < n; ++j) {
    double g[6];
    pals_modes(xi[j].x, xi[j].y, xi[j].z, g);
    for (int r = 0; r < 6; ++r) {
      b[r] -= wv[j] * g[r];
      for (int c = 0; c < 6; ++c) a[r][c] += wv[j] * g[r] * g[c];
    }
  }
  return pals_solve6(a, b, out);
}

// --- The force pass, per bond (v = V_j, the kind's volume times its fraction) ---

// The bond's term of theta: sigma |xi| e V_j, in the pass's order (volume, then fraction).
HORIZON_HD inline double pals_dilatation_term(double sigma, double length, double e, double volume, double fraction) {
  return sigma * length * e * volume * fraction;
}
// The bond's terms of S = sum tau e^d |xi| V_j and of sum tau (e^d)^2 V_j.
HORIZON_HD inline double pals_shear_term(double tau, double ed, double length, double v) { return tau * ed * length * v; }
HORIZON_HD inline double pals_deviatoric_term(double tau, double ed, double v) { return tau * ed * ed * v; }
// t_ij = kappa theta sigma |xi| + 2 mu tau e^d - (2 mu/3) S sigma |xi|.
HORIZON_HD inline double pals_force_scalar(double kappa, double mu, double theta, double sigma, double tau,
                                           double length, double ed, double S) {
  return kappa * theta * sigma * length + 2 * mu * tau * ed - (2 * mu / 3) * S * sigma * length;
}
// W_i = kappa theta^2/2 + mu sum tau (e^d)^2 V_j.
HORIZON_HD inline double pals_energy(double kappa, double mu, double theta, double dev) {
  return 0.5 * kappa * theta * theta + mu * dev;
}

// The flat arrays of the scalar pass's rows (per bond unless said). Kind: a per-kind struct
// with members length, volume and fraction (the host's BondKind).
template <class Kind>
struct PalsRow {
  const Kind* kinds = nullptr;  // per kind
  const uint32_t* kind = nullptr;
  const uint8_t* intact = nullptr;
  const double* r = nullptr;  // |Y| of the pass
  const double* sigma = nullptr;
  const double* tau = nullptr;
  double* q = nullptr;  // out: t/|Y| (0 where the bond does not act)
  double kappa = 0, mu = 0;
};
struct PalsSums {
  double theta, W;
};

// Row [first, last) in bond order: theta, S and the deviatoric sum, then each bond's q.
template <class Kind>
HORIZON_HD inline PalsSums pals_row(const PalsRow<Kind>& a, uint64_t first, uint64_t last) {
  double theta = 0;
  for (uint64_t k = first; k < last; ++k) {
    const Kind& b = a.kinds[a.kind[k]];
    const double e = a.r[k] - b.length;
    if (a.intact[k]) theta += pals_dilatation_term(a.sigma[k], b.length, e, b.volume, b.fraction);
  }
  double S = 0, dev = 0;
  for (uint64_t k = first; k < last; ++k) {
    if (!a.intact[k]) continue;
    const Kind& b = a.kinds[a.kind[k]];
    const double ed = deviatoric_extension(a.r[k] - b.length, theta, b.length, 3);
    const double v = b.volume * b.fraction;
    S += pals_shear_term(a.tau[k], ed, b.length, v);
    dev += pals_deviatoric_term(a.tau[k], ed, v);
  }
  for (uint64_t k = first; k < last; ++k) {
    if (!a.intact[k]) {
      a.q[k] = 0;
      continue;
    }
    const Kind& b = a.kinds[a.kind[k]];
    const double ed = deviatoric_extension(a.r[k] - b.length, theta, b.length, 3);
    const double t = pals_force_scalar(a.kappa, a.mu, theta, a.sigma[k], a.tau[k], b.length, ed, S);
    a.q[k] = a.r[k] > 0 ? t / a.r[k] : 0.0;
  }
  return {theta, pals_energy(a.kappa, a.mu, theta, dev)};
}

}  // namespace horizon::kernels
