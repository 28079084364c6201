#pragma once
// Extended correspondence's strain laws (material/classical/strain_laws.hpp: S = kappa
// tr(E_e) I + 2 mu dev(E_e), von Mises yield, the radial return of Simo and Hughes 1998,
// "Computational Inelasticity", box 3.1-3.2: elastic; j2, linear isotropic hardening, closed
// form; johnson_cook, Tupek's modified Johnson-Cook flow stress (thesis sec. 7.2) by a
// safeguarded Newton iteration, and its damage) as a device-portable function
// (core/portable.hpp, issue 30) over row-major double[9], and the volumetric gradient's
// strain and stress corrections around it.
//
// Bits. The host form's Eigen expressions, in their order (tests/unit/test_hencky_kernels.cpp
// holds this to them on random input): the trace d0 + (d1 + d2); scalar factors multiplied
// first ((2 mu) (E_e - (tr/3) I), ((2 mu) dgamma) n, (kappa tr) I); the identity's zeros
// multiplied in (they set the signs of zero entries); and the sum of the nine squares
// (s.array() * s.array()).sum() as Eigen's vectorised reduction of a column-major 3 x 3 with
// two-double packets takes it: packets P_k = (a_2k, a_2k+1), k = 0..3, summed as
// (P_0 + P_1) + (P_2 + P_3), its two lanes added, then the ninth entry a_8 (column-major).
#include "horizon/core/portable.hpp"
#include "horizon/kernels/affine.hpp"
#include "horizon/kernels/eigen3.hpp"
#include "horizon/kernels/hypoelastic.hpp"
#include "horizon/kernels/tupek.hpp"
#include "horizon/kernels/unified.hpp"

namespace horizon::kernels {

// The law's constants (classical::StrainLawParams as plain data; law: 0 elastic, 1 j2,
// 2 johnson_cook).
struct StrainLawConstants {
  int law = 0;
  double kappa = 0, mu = 0;                // bulk and shear moduli [Pa]
  double yield_stress = 0, hardening = 0;  // j2: sigma_y, H
  double sigma0 = 0, B = 0, n = 1, C = 0, rate0 = 1;                       // johnson_cook flow
  double d1 = 0, d2 = 0, d3 = 0, d4 = 0, damage_rate0 = 1;                 // johnson_cook damage
  bool damage = false;                                                     // accumulate D
};
inline constexpr int kStrainElastic = 0, kStrainJ2 = 1, kStrainJohnsonCook = 2;

struct StrainLawPoint {
  double S[9];              // stress conjugate to E [Pa]
  double W = 0;             // elastic energy [J/m^3]
  double plastic_work = 0;  // dissipated in the step [J/m^3]
  double rate = 0;          // equivalent plastic strain rate [1/s]
};

HORIZON_HD inline double arc_sinh(double x) {
#if defined(__CUDA_ARCH__)
  return ::asinh(x);
#else
  return std::asinh(x);
#endif
}

// Tupek's modified Johnson-Cook flow stress and its slopes in eps_p and in the rate, and
// the failure strain with the rate guard (classical/strain_laws.hpp, in its order).
HORIZON_HD inline double jc_flow(const StrainLawConstants& p, double eps_p, double rate) {
  const double eps0 = power(p.sigma0 / p.B, 1.0 / p.n);
  return p.sigma0 * power(1.0 + eps_p / eps0, p.n) * (1.0 + p.C * arc_sinh(rate / (2.0 * p.rate0)));
}
HORIZON_HD inline double jc_hardening(const StrainLawConstants& p, double eps_p, double rate) {
  const double eps0 = power(p.sigma0 / p.B, 1.0 / p.n);
  return p.sigma0 * p.n / eps0 * power(1.0 + eps_p / eps0, p.n - 1.0) * (1.0 + p.C * arc_sinh(rate / (2.0 * p.rate0)));
}
HORIZON_HD inline double jc_rate(const StrainLawConstants& p, double eps_p, double rate) {
  const double eps0 = power(p.sigma0 / p.B, 1.0 / p.n);
  const double x = rate / (2.0 * p.rate0);
  return p.sigma0 * power(1.0 + eps_p / eps0, p.n) * p.C / (2.0 * p.rate0 * root(1.0 + x * x));
}
HORIZON_HD inline double jc_failure(const StrainLawConstants& p, double triaxiality, double rate) {
  const double ratio = std_max(rate / p.damage_rate0, 1.0);
  return (p.d1 + p.d2 * natural_exp(-p.d3 * triaxiality)) * (1.0 + p.d4 * natural_log(ratio));
}
HORIZON_HD inline double strain_flow(const StrainLawConstants& p, double eps_p, double rate) {
  if (p.law == kStrainJ2) return p.yield_stress + p.hardening * eps_p;
  if (p.law == kStrainJohnsonCook) return jc_flow(p, eps_p, rate);
  return INFINITY;
}

// Sum of the entrywise products of two 3 x 3 (row-major storage), (x.array() * y.array()).sum(),
// in Eigen's order for column-major ones.
HORIZON_HD inline double products_sum9(const double* x, const double* y) {
  double a[9];
  for (int k = 0; k < 9; ++k) a[k] = x[3 * (k % 3) + k / 3] * y[3 * (k % 3) + k / 3];
  const double lane0 = (a[0] + a[2]) + (a[4] + a[6]), lane1 = (a[1] + a[3]) + (a[5] + a[7]);
  return (lane0 + lane1) + a[8];
}
HORIZON_HD inline double squares_sum9(const double* m) { return products_sum9(m, m); }

// I_d, the identity of the d in-plane axes (d = 2: no zz entry), row-major entry k.
HORIZON_HD inline double plane_identity(int d, int k) { return (k % 4 == 0 && (d == 3 || k != 8)) ? 1.0 : 0.0; }

// Extended correspondence's volumetric_strain gradient (material/models/extended_correspondence.cpp,
// run_law): the law's strain with its trace replaced by ln J, J = max(det Fbar, 1e-6),
//   E' = E + ((ln J - I_d : E)/d) I_d,
// and the split of the law's stress T into T - p I_d and the pressure map p Fbar^-T,
// p = (I_d : T)/d. The host's Eigen expressions in their order (det and inverse as
// eigen3.hpp's mat3_det and affine.hpp's mat3_inverse, the I_d contractions as products_sum9).
HORIZON_HD inline void volumetric_gradient_strain(const double* Fbar, int d, double* strain) {
  const double J = std_max(mat3_det(Fbar), 1e-6);
  double Id[9];
  for (int k = 0; k < 9; ++k) Id[k] = plane_identity(d, k);
  const double f = (natural_log(J) - products_sum9(Id, strain)) / d;
  for (int k = 0; k < 9; ++k) strain[k] += f * Id[k];
}
HORIZON_HD inline void volumetric_pressure_split(const double* Fbar, int d, double* T, double* pressure_map) {
  double Id[9], inv[9];
  for (int k = 0; k < 9; ++k) Id[k] = plane_identity(d, k);
  const double p = products_sum9(Id, T) / d;
  for (int k = 0; k < 9; ++k) T[k] -= p * Id[k];
  mat3_inverse(Fbar, inv);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) pressure_map[3 * r + c] = p * inv[3 * c + r];
}

// The law at strain E from the committed plastic strain Ep_n, alpha_n and damage D_n; dt the
// time since (0: rate 0). Ep, alpha, D: the trial history (Ep may alias Ep_n). The caller
// refuses a failed point (D_n >= 1) first, as the host form does.
HORIZON_HD inline void strain_law_point(const StrainLawConstants& p, const double* Ep_n, double alpha_n,
                                        double D_n, const double* E, double dt, double* Ep, double& alpha, double& D,
                                        StrainLawPoint& out) {
  double Ee[9], s[9];
  for (int k = 0; k < 9; ++k) Ee[k] = E[k] - Ep_n[k];
  const double tr = Ee[0] + (Ee[4] + Ee[8]);
  const double t3 = tr / 3.0, mu2 = 2.0 * p.mu;
  for (int k = 0; k < 9; ++k) s[k] = mu2 * (Ee[k] - t3 * ((k % 4 == 0) ? 1.0 : 0.0));
  const double s_norm = root(squares_sum9(s));
  const double q_trial = root(1.5) * s_norm;
  double deps = 0, rate = 0;
  alpha = alpha_n;
  D = D_n;
  bool yielded = false;
  if (p.law != kStrainElastic) {
    const double Y0 = strain_flow(p, alpha_n, 0.0);
    if (q_trial > Y0) {
      yielded = true;
      if (p.law == kStrainJ2) {
        deps = (q_trial - Y0) / (3.0 * p.mu + p.hardening);  // Simo-Hughes box 3.2
      } else {
        // g(x) = q_trial - 3 mu x - Y(alpha + x, x/dt) = 0 on [0, q_trial/(3 mu)]: Newton,
        // falling back to bisection when it leaves the bracket (the host form's iteration).
        double lo = 0, hi = q_trial / (3.0 * p.mu), x = 0.5 * (lo + hi);
        for (int it = 0; it < 100; ++it) {
          const double gx = q_trial - 3.0 * p.mu * x - strain_flow(p, alpha_n + x, dt > 0 ? x / dt : 0.0);
          if (gx > 0)
            lo = x;
          else
            hi = x;
          const double r = dt > 0 ? x / dt : 0.0;
          const double dg = -3.0 * p.mu - jc_hardening(p, alpha_n + x, r) - (dt > 0 ? jc_rate(p, alpha_n + x, r) / dt : 0.0);
          double xn = x - gx / dg;
          if (!(xn > lo && xn < hi)) xn = 0.5 * (lo + hi);
          if (absolute(xn - x) <= 1e-14 * std_max(hi, 1e-300)) {
            x = xn;
            break;
          }
          x = xn;
        }
        deps = x;
      }
      rate = dt > 0 ? deps / dt : 0.0;
      const double dgamma = root(1.5) * deps;
      const double f = mu2 * dgamma;
      for (int k = 0; k < 9; ++k) {
        const double nk = s[k] / s_norm;
        s[k] -= f * nk;
        Ep[k] = Ep_n[k] + dgamma * nk;
      }
      alpha = alpha_n + deps;
      out.plastic_work = strain_flow(p, alpha, rate) * deps;
    }
  }
  if (!yielded && Ep != Ep_n)
    for (int k = 0; k < 9; ++k) Ep[k] = Ep_n[k];
  out.rate = rate;
  const double kt = p.kappa * tr;
  for (int k = 0; k < 9; ++k) out.S[k] = kt * ((k % 4 == 0) ? 1.0 : 0.0) + s[k];
  const double s2 = squares_sum9(s);
  out.W = 0.5 * p.kappa * tr * tr + s2 / (4.0 * p.mu);
  if (p.damage && deps > 0) {
    const double sm = p.kappa * tr, se = root(1.5) * root(s2);
    const double ef = jc_failure(p, se > 0 ? sm / se : 0.0, rate);
    D = ef > 0 ? std_min(1.0, D_n + deps / ef) : 1.0;
  }
}

}  // namespace horizon::kernels
