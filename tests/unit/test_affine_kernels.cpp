// The correspondence model's portable kernels (kernels/affine.hpp, issue 30) against the
// Eigen forms the host computed before them: the same bits for the inverse, the
// deformation gradient, the linear elastic law, the von Mises stress, A = P K^-1 and the
// stabilisation energy (so that moving the host onto the kernels changed no answer), and
// the shape tensor's condition number against Eigen's eigenvalues to round-off.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstring>
#include <random>

#include "horizon/kernels/affine.hpp"
#include "horizon/kernels/extended.hpp"
#include "horizon/material/classical/stress_laws.hpp"
#include "kernel_bits.hpp"

namespace horizon {
namespace {

using test::Mat3;
using test::differing;
using test::same_bits;
using test::to_rows;

// A shape tensor like a family's: sum of w xi (x) xi over a few random bonds.
Mat3 random_shape_tensor(std::mt19937_64& g, int bonds) {
  std::uniform_real_distribution<double> u(-1, 1);
  Mat3 K = Mat3::Zero();
  for (int b = 0; b < bonds; ++b) {
    const Eigen::Vector3d xi(u(g) * 1e-3, u(g) * 1e-3, u(g) * 1e-3);
    K += (1e-9 * (1.5 + u(g))) * xi * xi.transpose();
  }
  return K;
}

TEST(AffineKernels, AlgebraKeepsEigensBits) {
  std::mt19937_64 g(7);
  std::uniform_real_distribution<double> u(-1, 1);
  int bad = 0;
  for (int t = 0; t < 20000; ++t) {
    Mat3 a, b;
    for (int c = 0; c < 9; ++c) a(c / 3, c % 3) = u(g) * std::exp(3 * u(g)), b(c / 3, c % 3) = u(g) * std::exp(3 * u(g));
    const Eigen::Vector3d v(u(g), u(g), u(g));
    double A[9], B[9], C[9], w[3], I[9];
    to_rows(a, A);
    to_rows(b, B);
    kernels::mat3_mul(A, B, C);
    bad += differing(a * b, C);
    kernels::mat3_vec(A, v.data(), w);
    const Eigen::Vector3d av = a * v;
    for (int r = 0; r < 3; ++r) bad += same_bits(av[r], w[r]) ? 0 : 1;
    kernels::mat3_inverse(A, I);
    bad += differing(a.inverse(), I);
    bad += same_bits(a.trace(), kernels::mat3_trace(A)) ? 0 : 1;
    bad += same_bits((a.array() * b.array()).sum(), kernels::mat3_contract(A, B)) ? 0 : 1;
    bad += same_bits(v.squaredNorm(), kernels::squared_norm3(v.data())) ? 0 : 1;
  }
  EXPECT_EQ(bad, 0);
}

TEST(AffineKernels, GradientAndLinearElasticRowKeepBits) {
  std::mt19937_64 g(11);
  std::uniform_real_distribution<double> u(-1, 1);
  const classical::Elastic el = classical::elastic_from_bulk_shear(160e9, 80e9);
  int bad = 0, refused = 0;
  for (int t = 0; t < 5000; ++t) {
    const Mat3 K = random_shape_tensor(g, 2 + t % 12);
    Mat3 Ftrue;
    for (int c = 0; c < 9; ++c) Ftrue(c / 3, c % 3) = (c % 4 == 0 ? 1.0 : 0.0) + 0.01 * u(g);
    const Mat3 N = Ftrue * K;
    double sums[18];
    to_rows(K, sums);
    to_rows(N, sums + 9);
    const double G = 3e20;
    double rec[kernels::kAffineRecord];
    const kernels::AffineRow row = kernels::linear_elastic_row(sums, 3, 1e-4, el.lambda, el.mu, G, rec);
    // The Eigen forms (material/nonlocal_gradient.hpp, classical/stress_laws.hpp and
    // correspondence.cpp as they were).
    Eigen::SelfAdjointEigenSolver<Mat3> es;
    es.computeDirect(K, Eigen::EigenvaluesOnly);
    const double ratio = es.eigenvalues()[2] > 0 ? es.eigenvalues()[0] / es.eigenvalues()[2] : 0.0;
    EXPECT_NEAR(kernels::shape_condition(sums, 3), ratio, 1e-12);
    const bool ok = ratio > 1e-4;
    if (ok != row.carries) {
      ADD_FAILURE() << "acceptance differs at ratio " << ratio;
      continue;
    }
    if (!ok) {
      ++refused;
      continue;
    }
    const Mat3 Kinv = K.inverse(), F = N * Kinv;
    bad += differing(F, row.F);
    const classical::LawResult r = classical::linear_elastic(el, F);
    bad += same_bits(r.W, row.W) ? 0 : 1;
    const Mat3 dev = r.sigma - (r.sigma.trace() / 3.0) * Mat3::Identity();
    bad += same_bits(std::sqrt(1.5 * (dev.array() * dev.array()).sum()), row.von_mises) ? 0 : 1;
    const Mat3 M = r.P * Kinv - G * F;
    bad += differing(M, rec);
    bad += same_bits(G, rec[9]) ? 0 : 1;
    // The stabilisation energy of a bond.
    const Eigen::Vector3d xi(u(g) * 1e-3, u(g) * 1e-3, u(g) * 1e-3), Y = 1.01 * xi;
    const double e_eigen = 0.5 * G * 2e-9 * (Y - F * xi).squaredNorm();
    bad += same_bits(e_eigen, kernels::stabilization_energy(row.F, G, 2e-9, xi.data(), Y.data())) ? 0 : 1;
  }
  EXPECT_EQ(bad, 0);
  EXPECT_LT(refused, 5000);
}

TEST(AffineKernels, SixVectorDotKeepsEigensBits) {
  // extended correspondence's pair sum (kernels/extended.hpp dot6, dot6_mid).
  using Vec6 = Eigen::Matrix<double, 6, 1>;
  std::mt19937_64 g(5);
  std::uniform_real_distribution<double> u(-1, 1);
  int bad = 0;
  for (int t = 0; t < 20000; ++t) {
    Vec6 a, b, c;
    for (int k = 0; k < 6; ++k) a[k] = u(g) * std::exp(3 * u(g)), b[k] = u(g) * std::exp(3 * u(g)), c[k] = u(g);
    bad += same_bits(a.dot(b), kernels::dot6(a.data(), b.data())) ? 0 : 1;
    bad += same_bits(a.dot(0.5 * (b + c)), kernels::dot6_mid(a.data(), b.data(), c.data())) ? 0 : 1;
  }
  EXPECT_EQ(bad, 0);
}

// The pair sum's bond term with i's residual kept by its law row (pair_bond_kept, issue 31)
// against pair_bond, bit for bit, over every combination of the ends' flags (carries
// stress, sends E for the midpoint, k_s zero or not) and the three strain measures: r_i is
// computed as ExtendedCorrespondence::pair_law_row does (eps - p . (E_i + E_j)/2 when j
// sends its E, else eps - p . E_i), and only where that row computes it.
TEST(AffineKernels, PairBondWithKeptResidualKeepsBits) {
  std::mt19937_64 g(11);
  std::uniform_real_distribution<double> u(-1, 1);
  int bad = 0, cases = 0;
  for (int t = 0; t < 4000; ++t) {
    double Ai[6], Aj[6], Ei[6], Ej[6], nv[3];
    for (int k = 0; k < 6; ++k) Ai[k] = 1e9 * u(g), Aj[k] = 1e9 * u(g), Ei[k] = 1e-2 * u(g), Ej[k] = 1e-2 * u(g);
    for (double& c : nv) c = u(g);
    const double L = std::sqrt(nv[0] * nv[0] + nv[1] * nv[1] + nv[2] * nv[2]), inv_length = 1 / (1e-3 * (1 + 0.5 * u(g)));
    for (double& c : nv) c /= L;
    const double Y2 = (1 + 0.01 * u(g)) / (inv_length * inv_length), eps = 0.5 * (Y2 * inv_length * inv_length - 1);
    const double m = t % 3 == 0 ? 0.0 : t % 3 == 1 ? 1.0 : 0.5, omega = 1 + u(g), V = 1e-9 * (1.5 + u(g));
    for (int flags = 0; flags < 64; ++flags) {
      const kernels::PairEnd ri{Ai, Ei, (flags & 1) ? 0.0 : 3e9 * (1.5 + u(g)), (flags & 2) != 0, (flags & 4) != 0};
      const kernels::PairEnd rj{Aj, Ej, (flags & 8) ? 0.0 : 3e9 * (1.5 + u(g)), (flags & 16) != 0, (flags & 32) != 0};
      double p[6];
      kernels::unit_normal_projector(nv, p);
      const double r_i = ri.on && ri.ks != 0
                             ? (rj.mid ? eps - kernels::dot6_mid(p, ri.E, rj.E) : eps - kernels::dot6(p, ri.E))
                             : std::nan("");  // the law row leaves it stale: must not be read
      const kernels::PairBond a = kernels::pair_bond(ri, rj, nv, 3, inv_length, Y2, eps, m, omega, V);
      const kernels::PairBond b = kernels::pair_bond_kept(ri, rj, nv, 3, inv_length, Y2, &eps, r_i, m, omega, V);
      bad += same_bits(a.q, b.q) && same_bits(a.scale, b.scale) ? 0 : 1;
      ++cases;
    }
  }
  EXPECT_EQ(bad, 0) << "of " << cases;
}

TEST(AffineKernels, RefusedShapeTensorsCarryNothing) {
  // A family in a plane (singular in 3-D), an empty one, and a needle.
  double sums[18] = {};
  double rec[kernels::kAffineRecord];
  std::fill(rec, rec + kernels::kAffineRecord, 1.0);
  EXPECT_FALSE(kernels::linear_elastic_row(sums, 3, 1e-4, 1e11, 1e11, 1.0, rec).carries);
  for (double v : rec) EXPECT_EQ(v, 0.0);
  const double plane[9] = {1, 0, 0, 0, 2, 0, 0, 0, 0};
  EXPECT_EQ(kernels::shape_condition(plane, 3), 0.0);
  const double needle[9] = {1, 0, 0, 0, 1e-7, 0, 0, 0, 1e-7};
  EXPECT_NEAR(kernels::shape_condition(needle, 3), 1e-7, 1e-15);
  const double iso[9] = {2, 0, 0, 0, 2, 0, 0, 0, 2};
  EXPECT_EQ(kernels::shape_condition(iso, 3), 1.0);
  // 2-D: the top-left block only.
  const double k2[9] = {4, 1, 0, 1, 3, 0, 0, 0, 0};
  double Kinv[9], F[9];
  const double N2[9] = {4, 1, 0, 1, 3, 0, 0, 0, 0};
  ASSERT_TRUE(kernels::gradient_finish(k2, N2, 2, 1e-4, Kinv, F));
  EXPECT_NEAR(F[0], 1.0, 1e-15);
  EXPECT_NEAR(F[1], 0.0, 1e-15);
  EXPECT_NEAR(F[4], 1.0, 1e-15);
  EXPECT_EQ(F[8], 1.0);
  EXPECT_EQ(Kinv[8], 0.0);
}

}  // namespace
}  // namespace horizon
