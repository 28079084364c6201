// The kernels of the elastic-plastic solid (material/models/elastic_plastic.hpp) alone:
// - psi_0 against the closed forms for omega = 1 (Mitchell's 25 sigma_y^2/(8 pi delta^5);
//   digest 003 sec. 8 for 2-D);
// - the yield surface: a homogeneous deviatoric strain at the von Mises yield point gives
//   f = 0, with the moment integrals done by numerical quadrature over the ball (disc),
//   for omega = 1 and for non-constant influence functions (the 1/omega-weighted norm);
// - the return mapping on a random family: consistency (f = 0 after the return with the
//   hardened psi_0), t^d = alpha omega (e^d - e^dp) identically, zero dilatation of e^dp
//   (seed 003 eq. 127), and the equivalent plastic strain measure.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "horizon/material/models/elastic_plastic.hpp"
#include "test_helpers.hpp"

namespace horizon {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(ElasticPlasticKernels, YieldValueMatchesClosedFormsForUnitInfluence) {
  const double sy = 250e6, delta = 3e-3, h = 1e-3;
  // 3-D: m = 4 pi delta^5/5 (seed 003 digest sec. 13.16).
  const double m3 = 4 * kPi * std::pow(delta, 5) / 5;
  EXPECT_NEAR(ep_yield_value(sy, m3, 3) / (25 * sy * sy / (8 * kPi * std::pow(delta, 5))), 1.0, 1e-14);
  // 2-D: m = pi h delta^4/2, psi_0 = 8 sigma_y^2/(3 pi h delta^4) (digest sec. 8).
  const double m2 = kPi * h * std::pow(delta, 4) / 2;
  EXPECT_NEAR(ep_yield_value(sy, m2, 2) / (8 * sy * sy / (3 * kPi * h * std::pow(delta, 4))), 1.0, 1e-14);
}

// Gauss-Legendre nodes and weights on [-1, 1] (Newton on P_n).
void gauss_legendre(int n, std::vector<double>& x, std::vector<double>& w) {
  x.assign(n, 0);
  w.assign(n, 0);
  for (int i = 0; i < n; ++i) {
    double z = std::cos(kPi * (i + 0.75) / (n + 0.5)), dp = 0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1, p1 = z;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (z * p1 - p0) / (z * z - 1);
      const double dz = p1 / dp;
      z -= dz;
      if (std::abs(dz) < 1e-16) break;
    }
    x[i] = z;
    w[i] = 2 / ((1 - z * z) * dp * dp);
  }
}

// f at the von Mises yield point of a homogeneous deviatoric strain, the integrals over
// the ball (3-D) or disc (2-D) by quadrature: ||t^d||_w^2 = alpha^2 int omega (s:nn)^2 r^2 dV,
// m = int omega r^2 dV.
double yield_function_at_von_mises_yield(int dimension, double (*omega)(double r, double delta)) {
  const double mu = 80e9, sy = 300e6, delta = 2e-3;
  // A deviatoric elastic strain (3-D: general traceless; 2-D: in-plane pure shear in
  // rotated axes), scaled so that the classical von Mises stress is sigma_y.
  double s[3][3] = {{0.7, 0.3, -0.2}, {0.3, -0.5, 0.4}, {-0.2, 0.4, -0.2}};
  if (dimension == 2) {
    const double a[3][3] = {{0.6, 0.45, 0}, {0.45, -0.6, 0}, {0, 0, 0}};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) s[i][j] = a[i][j];
  }
  double ss = 0;
  for (auto& row : s)
    for (double v : row) ss += v * v;
  // sigma_vm = sqrt(3/2 S:S), S = 2 mu s (2-D in-plane shear: s_33 = 0, the calibration case).
  const double scale = sy / std::sqrt(1.5 * 4 * mu * mu * ss);
  for (auto& row : s)
    for (double& v : row) v *= scale;
  std::vector<double> xr, wr, xa, wa;
  gauss_legendre(60, xr, wr);
  gauss_legendre(40, xa, wa);
  double m = 0, moment = 0;  // m and int omega (s:nn)^2 r^2 dV
  for (int a = 0; a < 60; ++a) {
    const double r = 0.5 * delta * (xr[a] + 1), wrad = 0.5 * delta * wr[a] * omega(r, delta);
    if (dimension == 3) {
      for (int b = 0; b < 40; ++b) {
        const double c = xa[b], sn = std::sqrt(1 - c * c);
        for (int p = 0; p < 80; ++p) {
          const double phi = 2 * kPi * (p + 0.5) / 80;
          const double n[3] = {sn * std::cos(phi), sn * std::sin(phi), c};
          double snn = 0;
          for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) snn += s[i][j] * n[i] * n[j];
          const double dv = wrad * r * r * wa[b] * (2 * kPi / 80);  // r^2 dr dcos dphi
          m += dv * r * r;
          moment += dv * r * r * snn * snn;
        }
      }
    } else {
      for (int p = 0; p < 200; ++p) {
        const double phi = 2 * kPi * (p + 0.5) / 200;
        const double n[2] = {std::cos(phi), std::sin(phi)};
        double snn = 0;
        for (int i = 0; i < 2; ++i)
          for (int j = 0; j < 2; ++j) snn += s[i][j] * n[i] * n[j];
        const double da = wrad * r * (2 * kPi / 200);  // r dr dphi (unit thickness)
        m += da * r * r;
        moment += da * r * r * snn * snn;
      }
    }
  }
  const double alpha = (dimension == 2 ? 8.0 : 15.0) * mu / m;
  const double norm2 = alpha * alpha * moment;
  return (0.5 * norm2 - ep_yield_value(sy, m, dimension)) / ep_yield_value(sy, m, dimension);
}

double unit(double, double) { return 1.0; }
double linear(double r, double delta) { return 1.0 - r / delta; }
double gaussian(double r, double delta) { return std::exp(-r * r / (delta * delta)); }

TEST(ElasticPlasticKernels, YieldSurfaceIsTheVonMisesPointForAnyInfluence) {
  for (int dim : {3, 2}) {
    EXPECT_NEAR(yield_function_at_von_mises_yield(dim, unit), 0.0, 1e-10) << dim << "-D, omega = 1";
    EXPECT_NEAR(yield_function_at_von_mises_yield(dim, linear), 0.0, 1e-10) << dim << "-D, omega = 1 - r/delta";
    EXPECT_NEAR(yield_function_at_von_mises_yield(dim, gaussian), 0.0, 1e-10) << dim << "-D, gaussian omega";
  }
}

// A random family: weights omega_j, volumes V_j, lengths; a trial deviatoric elastic
// extension with zero weighted dilatation.
struct Family {
  std::vector<double> omega, volume, length, ede;
  double m = 0;
};

Family random_family(uint64_t seed, double amplitude) {
  test::Rng rng(seed);
  Family f;
  const int n = 60;
  for (int j = 0; j < n; ++j) {
    f.omega.push_back(rng.uniform(0.2, 1.0));
    f.volume.push_back(rng.uniform(0.5e-9, 1.5e-9));
    f.length.push_back(rng.uniform(0.5e-3, 3e-3));
    f.ede.push_back(rng.uniform(-amplitude, amplitude) * f.length.back());
    f.m += f.omega[j] * f.length[j] * f.length[j] * f.volume[j];
  }
  // Remove the dilatation: e -= (sum omega |xi| e V / m) |xi|.
  double th = 0;
  for (int j = 0; j < n; ++j) th += f.omega[j] * f.length[j] * f.ede[j] * f.volume[j];
  for (int j = 0; j < n; ++j) f.ede[j] -= th / f.m * f.length[j];
  return f;
}

TEST(ElasticPlasticKernels, ReturnMappingIsConsistentAndKeepsThePlasticExtensionDeviatoric) {
  const double mu = 26e9, sy = 100e6, H = 2e9, eps_p0 = 0.004;
  for (int dim : {3, 2}) {
    for (uint64_t seed : {1u, 2u, 3u}) {
      const Family f = random_family(seed, 0.02);
      const double alpha = lps_deviatoric_factor(dim) * mu / f.m;
      double n2 = 0;
      for (std::size_t j = 0; j < f.ede.size(); ++j) n2 += alpha * alpha * f.omega[j] * f.ede[j] * f.ede[j] * f.volume[j];
      const ReturnMap r = ep_return_map(n2, f.m, dim, mu, sy, H, eps_p0);
      ASSERT_GT(r.trial_yield, 0) << "the trial state must lie outside the surface";
      ASSERT_GT(r.scale, 0);
      ASSERT_LT(r.scale, 1);
      // After the return: t^d = beta t^d_tr = alpha omega (e^d - e^dp_n+1) with
      // e^dp_n+1 = e^dp_n + (1 - beta) e^de_tr, on the hardened surface.
      double n2_new = 0, theta_p = 0, dep2 = 0;
      for (std::size_t j = 0; j < f.ede.size(); ++j) {
        const double td = r.scale * alpha * f.omega[j] * f.ede[j];
        const double dep = (1 - r.scale) * f.ede[j];
        EXPECT_NEAR(td, alpha * f.omega[j] * (f.ede[j] - dep), 1e-12 * std::abs(alpha * f.omega[j] * f.ede[j]));
        n2_new += td * td / f.omega[j] * f.volume[j];
        theta_p += f.omega[j] * f.length[j] * dep * f.volume[j];
        dep2 += f.omega[j] * dep * dep * f.volume[j];
      }
      const double psi = ep_yield_value(sy + H * (eps_p0 + r.plastic_strain), f.m, dim);
      EXPECT_NEAR(0.5 * n2_new / psi, 1.0, 1e-12) << dim << "-D: on the hardened surface after the return";
      EXPECT_NEAR(theta_p * dim / f.m, 0.0, 1e-15) << "the plastic extension has no dilatation (eq. 127)";
      // The equivalent plastic strain is the measure of the header: sqrt(5/m) ||d e^dp||_o.
      EXPECT_NEAR(r.plastic_strain / (ep_plastic_strain_factor(f.m, dim) * std::sqrt(dep2)), 1.0, 1e-12);
      // Perfect plasticity returns onto sigma_y itself.
      const ReturnMap p = ep_return_map(n2, f.m, dim, mu, sy, 0, 0);
      EXPECT_NEAR(0.5 * p.scale * p.scale * n2 / ep_yield_value(sy, f.m, dim), 1.0, 1e-12);
    }
  }
}

TEST(ElasticPlasticKernels, InsideTheSurfaceTheStepIsElastic) {
  const Family f = random_family(7, 1e-5);
  const double mu = 26e9, alpha = 15 * mu / f.m;
  double n2 = 0;
  for (std::size_t j = 0; j < f.ede.size(); ++j) n2 += alpha * alpha * f.omega[j] * f.ede[j] * f.ede[j] * f.volume[j];
  const double sy = 1.01 * ep_equivalent_stress(n2, f.m, 3);  // 1 % above the trial
  const ReturnMap r = ep_return_map(n2, f.m, 3, mu, sy, 1e9, 0);
  EXPECT_LT(r.trial_yield, 0);
  EXPECT_EQ(r.scale, 1.0);
  EXPECT_EQ(r.plastic_strain, 0.0);
}

}  // namespace
}  // namespace horizon
