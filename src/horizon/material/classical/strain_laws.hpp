#pragma once
// Stress laws written on a strain tensor E (symmetric, 3 x 3) rather than on F, for the
// extended correspondence model (material/models/extended_correspondence.hpp), whose
// nonlocal strain E_(m) (Tupek thesis eq. 4.3) is the argument of the classical law and
// whose work-conjugate stress sigma_(m) = d psi / d E_(m) (eq. 4.7) is what the law returns.
// With m = 0, E is the logarithmic (Hencky) strain and an isotropic quadratic energy in
// it is the "hyperelastic response on logarithmic strains" of the thesis's sec. 7.2.
//
// All laws share one structure (Simo and Hughes 1998, "Computational Inelasticity",
// box 3.1-3.2, written in Hencky-strain space as Miehe, Apel and Lambrecht 2002, CMAME
// 191, 5383, sec. 2):
//   E = E_e + E_p (additive split, E_p traceless), S = kappa tr(E_e) I + 2 mu dev(E_e),
//   von Mises yield |dev S| <= sqrt(2/3) Y(eps_p, eps_p_rate),
// and the radial return Delta eps_p solving  q_trial - 3 mu Delta eps_p = Y(eps_p,n +
// Delta eps_p, Delta eps_p / dt)  (q = sqrt(3/2) |dev S|, the von Mises stress).
//   elastic:       no yield (Y = infinity).
//   j2:            Y = sigma_y + H eps_p (linear isotropic hardening; closed-form return).
//   johnson_cook:  Tupek's modified Johnson-Cook flow stress (thesis sec. 7.2; seed 000
//                  digest sec. 6.2):
//                    Y = sigma_0 (1 + eps_p/eps_p0)^n (1 + C asinh(rate / (2 rate_0))),
//                    eps_p0 = (sigma_0 / B)^(1/n),
//                  no thermal softening; the return is solved by a safeguarded Newton
//                  iteration (Y grows with Delta eps_p, the trial line falls: one root).
// Damage (johnson_cook only; thesis sec. 7.2, digest sec. 6.2): D += Delta eps_p / eps_f,
//   eps_f = [d1 + d2 exp(-d3 sigma_m / sigma_e)] [1 + d4 ln(max(rate / rate_0D, 1))],
// with sigma_m the mean and sigma_e the von Mises stress at the end of the step (the
// max(., 1) is the rate guard of the digest: the log term never goes negative); once
// D >= 1 the material point has failed and carries no stress (LawOut::failed).
// The plastic work of the step, Y_(n+1) Delta eps_p (backward Euler), is returned for the
// energy ledger; W is the elastic energy kappa/2 tr(E_e)^2 + mu |dev E_e|^2.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

namespace horizon::classical {

enum class StrainLaw { elastic, j2, johnson_cook };

struct StrainLawParams {
  StrainLaw law = StrainLaw::elastic;
  double kappa = 0, mu = 0;  // bulk and shear moduli [Pa]
  // j2
  double yield_stress = 0, hardening_modulus = 0;
  // johnson_cook flow (Table 7.1 names): sigma_0, B, n, C, reference rate
  double sigma0 = 0, B = 0, n = 1, C = 0, rate0 = 1;
  // johnson_cook damage: d1..d4 and the reference rate of the failure strain
  double d1 = 0, d2 = 0, d3 = 0, d4 = 0, damage_rate0 = 1;
  bool damage = false;  // accumulate D (johnson_cook with d1 + d2 > 0)
};

struct StrainLawState {
  Eigen::Matrix3d plastic_strain = Eigen::Matrix3d::Zero();  // E_p (traceless)
  double alpha = 0;                                          // equivalent plastic strain eps_p
  double damage = 0;                                         // Johnson-Cook damage D in [0, 1]
};

struct StrainLawOut {
  Eigen::Matrix3d S = Eigen::Matrix3d::Zero();  // stress conjugate to E [Pa]
  double W = 0;                                 // elastic energy [J/m^3]
  double plastic_work = 0;                      // dissipated in the step [J/m^3]
  double rate = 0;                              // equivalent plastic strain rate of the step [1/s]
  bool failed = false;                          // D reached 1: no stress
};

// Tupek's modified Johnson-Cook flow stress (thesis sec. 7.2).
inline double jc_flow_stress(const StrainLawParams& p, double eps_p, double rate) {
  const double eps0 = std::pow(p.sigma0 / p.B, 1.0 / p.n);
  return p.sigma0 * std::pow(1.0 + eps_p / eps0, p.n) * (1.0 + p.C * std::asinh(rate / (2.0 * p.rate0)));
}

// d Y / d eps_p at fixed rate and d Y / d rate at fixed eps_p.
inline double jc_hardening_slope(const StrainLawParams& p, double eps_p, double rate) {
  const double eps0 = std::pow(p.sigma0 / p.B, 1.0 / p.n);
  return p.sigma0 * p.n / eps0 * std::pow(1.0 + eps_p / eps0, p.n - 1.0) *
         (1.0 + p.C * std::asinh(rate / (2.0 * p.rate0)));
}
inline double jc_rate_slope(const StrainLawParams& p, double eps_p, double rate) {
  const double eps0 = std::pow(p.sigma0 / p.B, 1.0 / p.n);
  const double x = rate / (2.0 * p.rate0);
  return p.sigma0 * std::pow(1.0 + eps_p / eps0, p.n) * p.C / (2.0 * p.rate0 * std::sqrt(1.0 + x * x));
}

// The Johnson-Cook failure strain with the rate guard (digest sec. 6.2).
inline double jc_failure_strain(const StrainLawParams& p, double triaxiality, double rate) {
  const double ratio = std::max(rate / p.damage_rate0, 1.0);
  return (p.d1 + p.d2 * std::exp(-p.d3 * triaxiality)) * (1.0 + p.d4 * std::log(ratio));
}

inline double flow_stress(const StrainLawParams& p, double eps_p, double rate) {
  switch (p.law) {
    case StrainLaw::elastic: return std::numeric_limits<double>::infinity();
    case StrainLaw::j2: return p.yield_stress + p.hardening_modulus * eps_p;
    case StrainLaw::johnson_cook: return jc_flow_stress(p, eps_p, rate);
  }
  return 0;
}

// The law at strain E from the committed state; dt: the time since it (0: rate 0).
inline StrainLawOut strain_law(const StrainLawParams& p, const StrainLawState& committed, const Eigen::Matrix3d& E,
                               double dt, StrainLawState& trial) {
  using Mat3 = Eigen::Matrix3d;
  StrainLawOut out;
  trial = committed;
  if (committed.damage >= 1.0) {
    out.failed = true;
    return out;
  }
  const Mat3 I = Mat3::Identity();
  const Mat3 Ee = E - committed.plastic_strain;
  const double tr = Ee.trace();
  Mat3 s = 2.0 * p.mu * (Ee - (tr / 3.0) * I);
  const double s_norm = std::sqrt((s.array() * s.array()).sum());
  const double q_trial = std::sqrt(1.5) * s_norm;  // von Mises of the trial stress
  double deps = 0, rate = 0;
  if (p.law != StrainLaw::elastic) {
    const double Y0 = flow_stress(p, committed.alpha, 0.0);
    if (q_trial > Y0) {
      if (p.law == StrainLaw::j2) {
        deps = (q_trial - Y0) / (3.0 * p.mu + p.hardening_modulus);  // Simo-Hughes box 3.2
      } else {
        // g(x) = q_trial - 3 mu x - Y(alpha + x, x/dt) = 0 on [0, q_trial/(3 mu)]:
        // g(0) > 0 >= g(hi); Newton, falling back to bisection when it leaves the bracket.
        double lo = 0, hi = q_trial / (3.0 * p.mu), x = 0.5 * (lo + hi);
        auto g = [&](double d) { return q_trial - 3.0 * p.mu * d - flow_stress(p, committed.alpha + d, dt > 0 ? d / dt : 0.0); };
        for (int it = 0; it < 100; ++it) {
          const double gx = g(x);
          if (gx > 0) lo = x; else hi = x;
          const double r = dt > 0 ? x / dt : 0.0;
          const double dg = -3.0 * p.mu - jc_hardening_slope(p, committed.alpha + x, r) -
                            (dt > 0 ? jc_rate_slope(p, committed.alpha + x, r) / dt : 0.0);
          double xn = x - gx / dg;
          if (!(xn > lo && xn < hi)) xn = 0.5 * (lo + hi);
          if (std::abs(xn - x) <= 1e-14 * std::max(hi, 1e-300)) {
            x = xn;
            break;
          }
          x = xn;
        }
        deps = x;
      }
      rate = dt > 0 ? deps / dt : 0.0;
      const Mat3 nrm = s / s_norm;
      const double dgamma = std::sqrt(1.5) * deps;  // |Delta E_p| = sqrt(3/2) Delta eps_p
      s -= 2.0 * p.mu * dgamma * nrm;
      trial.plastic_strain = committed.plastic_strain + dgamma * nrm;
      trial.alpha = committed.alpha + deps;
      out.plastic_work = flow_stress(p, trial.alpha, rate) * deps;
    }
  }
  out.rate = rate;
  out.S = p.kappa * tr * I + s;
  out.W = 0.5 * p.kappa * tr * tr + (s.array() * s.array()).sum() / (4.0 * p.mu);
  if (p.damage && deps > 0) {
    const double sm = p.kappa * tr, se = std::sqrt(1.5) * std::sqrt((s.array() * s.array()).sum());
    const double ef = jc_failure_strain(p, se > 0 ? sm / se : 0.0, rate);
    trial.damage = ef > 0 ? std::min(1.0, committed.damage + deps / ef) : 1.0;
  }
  return out;
}

}  // namespace horizon::classical
