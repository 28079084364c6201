// Conditioning of the tangent (solver/conditioning.hpp; docs/verification.md, "Static
// and implicit solvers"): the 1-D nonlocal problem of Parks (digest 004 sec. 10.3, 10.5)
// on Horizon's own tangent, and the condition number's growth with the horizon.
//
// The bar: nodes x_p = p h, unknowns p = 1 .. 1/h - 1, the collars p <= 0 and p >= 1/h
// held at zero (u = 0 on [-delta, 0] and [1, 1 + delta]), horizon delta = m h, partial
// volumes (the neighbour at exactly delta counts half). With the influence weight set to
// omega = |xi|/delta, the PMB bond stiffness omega c V_i V_j / |xi| is the same for every
// bond: Horizon's tangent is then a multiple of Parks' piecewise-constant matrix
// (K_ii = h(2 delta - h), K_ij = -h^2 for 1 <= |i - j| < m, -h^2/2 at |i - j| = m), whose
// condition numbers the digest reproduces to 3 digits. With the PMB's own omega = 1
// the bond stiffness is c/|xi|, and kappa picks up a factor of about ln(m).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <omp.h>

#include "horizon/solver/conditioning.hpp"
#include "horizon/solver/tangent.hpp"
#include "../single_thread.hpp"
#include "verification_support.hpp"

namespace horizon::verification {
namespace {

// One OpenMP thread for these small problems (tests/single_thread.hpp).
using OneThread = test::SingleThread;

struct BarCase {
  int inv_h;      // 1/h
  int inv_delta;  // 1/delta
};

ConditionEstimate bar_condition(const BarCase& bc, bool canonical_kernel) {
  const double h = 1.0 / bc.inv_h, delta = 1.0 / bc.inv_delta;
  const int m = bc.inv_h / bc.inv_delta;
  Config c;
  c.dimension = 1;
  c.area = 1e-6;
  c.spacing = h;
  c.horizon = delta;
  c.lattice_origin = Vec3{};
  c.partial_volume = true;
  MaterialConfig mat;
  mat.name = "bar";
  mat.model = "pmb";
  mat.density = 1000;
  mat.youngs_modulus = 1e9;
  c.materials = {mat};
  // Nodes p = -(m - 1) .. 1/h + m - 1.
  c.bodies = {BodyConfig{"bar", "bar", Shape::box({(-(m - 1) - 0.5) * h, -0.5, -0.5},
                                                  {(bc.inv_h + m - 1 + 0.5) * h, 0.5, 0.5})}};
  System s = build_system(c);
  if (canonical_kernel)
    for (auto& kind : s.bonds.kinds) kind.weight = kind.length / delta;
  DofMap d;
  d.dimension = 1;
  d.index.assign(3 * s.particles.size(), -1);
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    const long p = std::lround(s.particles.X[i].x / h);
    if (p >= 1 && p <= bc.inv_h - 1) {
      d.index[3 * i] = static_cast<int32_t>(d.particle.size());
      d.particle.push_back(static_cast<uint32_t>(i));
      d.component.push_back(0);
    }
  }
  EXPECT_EQ(d.size(), static_cast<std::size_t>(bc.inv_h - 1));
  return estimate_condition(assemble_tangent(s, d));
}

// Least-squares slope of ln kappa against ln delta.
double fitted_exponent(const std::vector<double>& delta, const std::vector<double>& kappa) {
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t k = 0; k < delta.size(); ++k) {
    const double x = std::log(delta[k]), y = std::log(kappa[k]);
    n += 1;
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

TEST(Conditioning, CanonicalKernelReproducesParksTable) {
  OneThread one;
  const auto t0 = std::chrono::steady_clock::now();
  // Digest 004 sec. 10.5, 1D PWC (computed there to 5 digits; printed in the slides to 3).
  const std::vector<std::pair<BarCase, double>> cases = {
      {{2000, 20}, 313.31}, {{4000, 20}, 313.48}, {{8000, 20}, 313.56}, {{8000, 40}, 1218.9}, {{8000, 80}, 4804.9}};
  std::vector<double> delta, kappa;
  for (const auto& [bc, parks] : cases) {
    const ConditionEstimate e = bar_condition(bc, true);
    ASSERT_TRUE(e.converged) << e.message;
    report(fmt::format("kappa_{}_{}", bc.inv_h, bc.inv_delta), e.condition,
           fmt::format("1-D canonical kernel, 1/h = {}, 1/delta = {}: kappa = {:.2f} (Parks {:.2f}, {:+.3f} %)",
                       bc.inv_h, bc.inv_delta, e.condition, parks, 100 * (e.condition / parks - 1)));
    EXPECT_NEAR(e.condition / parks, 1.0, 0.005);
    if (bc.inv_h == 8000) {
      delta.push_back(1.0 / bc.inv_delta);
      kappa.push_back(e.condition);
    }
  }
  const double p = fitted_exponent(delta, kappa);
  report("kappa_exponent_canonical", p,
         fmt::format("1-D canonical kernel at 1/h = 8000: kappa ~ delta^{:.3f} (expected -2)", p));
  EXPECT_NEAR(p, -2.0, 0.2);
  std::printf("[ figure ] conditioning test time %.1f s\n",
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
}

// The PMB's own kernel (omega = 1, bond stiffness c/|xi|, c ~ delta^-2): lambda_min tends
// to the local value E A h (pi/L)^2, while lambda_max ~ (c A^2 h^2 / h) sum_{k <= m} 1/k
// picks up the harmonic sum H_m ~ ln m over the family (the neighbour at exactly delta
// counting half). So kappa ~ H_m delta^-2: the raw exponent is shallower than -2 by
// about 1/H_m, and kappa grows slowly (like ln m) as the spacing shrinks.
TEST(Conditioning, PmbKernelGrowsAsHarmonicSumOverDeltaSquared) {
  OneThread one;
  const int inv_h = 2000;
  std::vector<double> delta, kappa, kappa_over_harmonic;
  for (const int inv_delta : {20, 40, 80}) {
    const ConditionEstimate e = bar_condition({inv_h, inv_delta}, false);
    ASSERT_TRUE(e.converged) << e.message;
    const int m = inv_h / inv_delta;
    double harmonic = 0.5 / m;
    for (int k = 1; k < m; ++k) harmonic += 1.0 / k;
    delta.push_back(1.0 / inv_delta);
    kappa.push_back(e.condition);
    kappa_over_harmonic.push_back(e.condition / harmonic);
    report(fmt::format("kappa_pmb_{}_{}", inv_h, inv_delta), e.condition,
           fmt::format("1-D PMB (omega = 1), 1/h = {}, 1/delta = {}: kappa = {:.1f}, kappa / H_m = {:.2f}", inv_h,
                       inv_delta, e.condition, e.condition / harmonic));
  }
  const ConditionEstimate fine = bar_condition({2 * inv_h, 80}, false);
  ASSERT_TRUE(fine.converged) << fine.message;
  report("kappa_pmb_4000_80", fine.condition,
         fmt::format("1-D PMB (omega = 1), 1/h = {}, 1/delta = 80: kappa = {:.1f} ({:+.1f} % for half the spacing)",
                     2 * inv_h, fine.condition, 100 * (fine.condition / kappa[2] - 1)));
  const double p = fitted_exponent(delta, kappa);
  const double q = fitted_exponent(delta, kappa_over_harmonic);
  report("kappa_exponent_pmb", p,
         fmt::format("1-D PMB kernel at 1/h = {}: kappa ~ delta^{:.3f}; kappa / H_m ~ delta^{:.3f}", inv_h, p, q));
  EXPECT_NEAR(q, -2.0, 0.2);
  EXPECT_LT(p, -1.6);
  EXPECT_NEAR(fine.condition / kappa[2], 1.0, 0.2) << "weak dependence on the spacing";
}

// ADR's damping on structures (adr.hpp) uses the lowest eigenvalue of K x = lambda M x:
// the fourth-order stencil (1 -4 6 -4 1) of a simply supported beam of n unknowns has
// the eigenvalues (2 - 2 cos(k pi/(n + 1)))^2 (its sine modes), and a diagonal mass m
// divides them by m. Asymmetric input is symmetrised (K + K^T)/2.
TEST(Conditioning, LowestGeneralizedEigenvalueOfBendingStencil) {
  const int n = 200;
  const double mass = 4.0;
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, i, i == 0 || i == n - 1 ? 5.0 : 6.0);
    if (i + 1 < n) {
      t.emplace_back(i, i + 1, -4.0 + 1e-3);  // antisymmetric part: dropped by symmetrisation
      t.emplace_back(i + 1, i, -4.0 - 1e-3);
    }
    if (i + 2 < n) {
      t.emplace_back(i, i + 2, 1.0);
      t.emplace_back(i + 2, i, 1.0);
    }
  }
  SparseMatrix K(n, n);
  K.setFromTriplets(t.begin(), t.end());
  const double pi = 3.14159265358979323846;
  const double expected = std::pow(2 - 2 * std::cos(pi / (n + 1)), 2) / mass;
  const double got = lowest_generalized_eigenvalue(K, Eigen::VectorXd::Constant(n, mass), 1e-8);
  report("lowest_eigenvalue", got / expected,
         fmt::format("bending stencil n = {}: lowest eigenvalue / exact = {:.10f}", n, got / expected));
  EXPECT_NEAR(got / expected, 1.0, 1e-6);
  // Not positive definite: a negative answer.
  SparseMatrix N = -K;
  EXPECT_LT(lowest_generalized_eigenvalue(N, Eigen::VectorXd::Constant(n, mass)), 0);
}

}  // namespace
}  // namespace horizon::verification
