// Kernels of O'Grady's bond-pair model (material/models/bond_pair.hpp; seed 001):
// - the pair gradient against finite differences of 1 + cos theta (eq. 4.1);
// - the elastic-perfectly-plastic return mapping (eq. 4.8, digest sec. 3.5);
// - the moment-curvature law of a beam of bond pairs under uniform curvature,
//   M = sum_j omega alpha V |xi| sin(kink_e), against the classical rectangle
//   M = M_y (3/2 - (kappa_y/kappa)^2/2) and the limits M_inf/M_y = 3/2 (omega = 1) and
//   4/3 (omega = |xi|) (digest sec. 3.5).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "horizon/material/models/bond_pair.hpp"

namespace horizon {
namespace {

TEST(BondPairKernels, GradientMatchesFiniteDifferences) {
  const Vec3 Y{1.0, 0.2, -0.1}, Yp{-0.9, 0.1, 0.3};
  const PairGradient g = bond_pair_gradient(Y, Yp);
  auto f = [](const Vec3& a, const Vec3& b) { return 1 + dot(a, b) / (norm(a) * norm(b)); };
  EXPECT_NEAR(g.one_plus_cos, f(Y, Yp), 1e-15);
  const double h = 1e-6;
  for (int c = 0; c < 3; ++c) {
    Vec3 e{};
    e[c] = h;
    EXPECT_NEAR(g.dY[c], (f(Y + e, Yp) - f(Y - e, Yp)) / (2 * h), 1e-8);
    EXPECT_NEAR(g.dYp[c], (f(Y, Yp + e) - f(Y, Yp - e)) / (2 * h), 1e-8);
  }
  // A straight pair carries no force (theta = pi).
  const PairGradient s = bond_pair_gradient({1, 0, 0}, {-2, 0, 0});
  EXPECT_EQ(s.one_plus_cos, 0.0);
  EXPECT_EQ(norm(s.dY), 0.0);
}

TEST(BondPairKernels, ReturnMappingLoadAndUnload) {
  const double c = 0.01;
  EXPECT_EQ(plastic_offset(0.005, 0, c), 0.0);              // elastic
  EXPECT_NEAR(plastic_offset(0.03, 0, c), 0.02, 1e-15);      // yields: elastic part stays at c
  EXPECT_NEAR(plastic_offset(0.025, 0.02, c), 0.02, 1e-15);  // unloading is elastic
  EXPECT_NEAR(plastic_offset(0.0, 0.02, c), 0.01, 1e-15);    // reverse yield at -c
  EXPECT_NEAR(critical_kink(0.3, 0.002, 0.1), 2 * 0.3 * 0.002 / 0.1, 1e-15);
}

// Moment of the pairs of one node of a beam under uniform curvature kappa, loaded
// monotonically from 0: M = dW/dkappa = sum_j omega alpha V |xi| sin(min(kappa |xi|, c)),
// over both orientations (the energy-conjugate moment, digest sec. 3.5).
double pair_moment(double kappa, double c, int per_horizon, bool by_length, double dx, double alpha) {
  double M = 0;
  for (int k = 1; k <= per_horizon; ++k) {
    const double L = k * dx, w = by_length ? L : 1.0;
    double tp = 0;
    for (int step = 1; step <= 20; ++step) tp = plastic_offset(kappa * L * step / 20, tp, c);
    M += 2 * w * alpha * dx * L * std::sin(kappa * L - tp);
  }
  return M;
}

TEST(BondPairKernels, MomentCurvatureOfElasticPerfectlyPlasticPairs) {
  // A rectangle b x t, delta = 200 dx (the lattice sums approach the integrals of sec. 3.5).
  const int N = 200;
  const double t = 0.1, delta = 0.3, dx = delta / N, E = 200e9, b = 0.1, eps_c = 0.002;
  const double EI = E * b * t * t * t / 12, c = critical_kink(delta, eps_c, t);
  for (bool by_length : {false, true}) {
    double m = 0;
    for (int k = 1; k <= N; ++k) m += 2 * (by_length ? k * dx : 1.0) * (k * dx) * (k * dx) * dx;
    const double alpha = EI / m;                  // eq. 4.4
    const double kappa_y = c / delta;             // the longest pairs yield first: 2 eps_c / t
    EXPECT_NEAR(kappa_y, 2 * eps_c / t, 1e-12);
    const double My = pair_moment(kappa_y, c, N, by_length, dx, alpha);
    EXPECT_NEAR(My / (EI * kappa_y), 1.0, 1e-4);  // M_y = EI kappa_y = sigma_y b t^2/6
    const double limit = pair_moment(1000 * kappa_y, c, N, by_length, dx, alpha) / My;
    const double expected = by_length ? 4.0 / 3.0 : 1.5;
    std::printf("[ figure ] omega = %s: M_inf/M_y = %.4f (expected %.4f)\n", by_length ? "|xi|" : "1", limit, expected);
    EXPECT_NEAR(limit, expected, 0.02 * expected);
    if (!by_length)
      for (double r : {1.25, 1.5, 2.0, 3.0, 5.0}) {
        const double M = pair_moment(r * kappa_y, c, N, false, dx, alpha) / My;
        const double classical = 1.5 - 0.5 / (r * r);
        std::printf("[ figure ] kappa/kappa_y = %.2f: M/M_y = %.4f (classical %.4f)\n", r, M, classical);
        EXPECT_NEAR(M, classical, 0.03 * classical);
      }
  }
}

}  // namespace
}  // namespace horizon
