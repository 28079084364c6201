// The portable stress laws (kernels/laws.hpp) and 3 x 3 decompositions (kernels/eigen3.hpp,
// issue 30) against the Eigen forms the host computed before them (classical/polar.hpp,
// classical/stress_laws.hpp): the same bits on random inputs for the determinant, the
// Jacobi SVD (U, the singular values, V), the polar decomposition and the Hencky strain,
// the neo-Hookean law, the J2 return map (elastic and plastic steps, with a committed
// plastic history) and the whole row (law_row: F, the law, the von Mises stress, the
// record), so that moving Correspondence::affine_row onto them changed no answer.
// (A build with wider SIMD packets, -mavx, would change Eigen's order of some sums; this
// test would then say so.)
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "horizon/core/vec3.hpp"
#include "horizon/kernels/eigen3.hpp"
#include "horizon/kernels/hypoelastic.hpp"
#include "horizon/kernels/laws.hpp"
#include "horizon/material/classical/hypoelastic.hpp"
#include "horizon/material/classical/stress_laws.hpp"
#include "kernel_bits.hpp"

namespace horizon {
namespace {

using test::Mat3;
using test::differing;
using test::same_bits;
using test::to_rows;

// A deformation gradient: I + a random part of size `amp`, sometimes a rotation in front
// (finite rotations are what the polar decomposition is for).
Mat3 random_gradient(std::mt19937_64& g, double amp) {
  std::uniform_real_distribution<double> u(-1, 1);
  Mat3 F;
  for (int c = 0; c < 9; ++c) F(c / 3, c % 3) = (c % 4 == 0 ? 1.0 : 0.0) + amp * u(g);
  if (u(g) > 0) {
    const Eigen::Vector3d axis = Eigen::Vector3d(u(g), u(g), u(g)).normalized();
    F = Eigen::AngleAxisd(3.0 * u(g), axis).toRotationMatrix() * F;
  }
  return F;
}

TEST(LawKernels, DeterminantAndSvdKeepEigensBits) {
  std::mt19937_64 g(3);
  std::uniform_real_distribution<double> u(-1, 1);
  int bad = 0;
  for (int t = 0; t < 20000; ++t) {
    Mat3 a;
    if (t % 3 == 0)
      for (int c = 0; c < 9; ++c) a(c / 3, c % 3) = u(g) * std::exp(3 * u(g));  // any matrix
    else
      a = random_gradient(g, t % 3 == 1 ? 0.01 : 0.4);
    if (t % 97 == 0) a.col(2) = a.col(0) * 2.0;  // singular
    double A[9], U[9], V[9], s[3];
    to_rows(a, A);
    bad += same_bits(a.determinant(), kernels::mat3_det(A)) ? 0 : 1;
    ASSERT_TRUE(kernels::svd3(A, U, s, V));
    const Eigen::JacobiSVD<Mat3> svd(a, Eigen::ComputeFullU | Eigen::ComputeFullV);
    bad += differing(svd.matrixU(), U) + differing(svd.matrixV(), V);
    for (int k = 0; k < 3; ++k) bad += same_bits(svd.singularValues()[k], s[k]) ? 0 : 1;
  }
  EXPECT_EQ(bad, 0);
  double inf[9] = {INFINITY, 0, 0, 0, 1, 0, 0, 0, 1}, U[9], V[9], s[3];
  EXPECT_FALSE(kernels::svd3(inf, U, s, V));
}

TEST(LawKernels, PolarDecompositionKeepsEigensBits) {
  std::mt19937_64 g(5);
  int bad = 0, refused = 0;
  for (int t = 0; t < 20000; ++t) {
    Mat3 F = random_gradient(g, t % 2 ? 0.02 : 0.5);
    if (t % 50 == 0) F.row(0) = -F.row(0);  // inverted: refused
    double f[9], R[9], L[9];
    to_rows(F, f);
    const classical::Polar p = classical::polar_decomposition(F);
    const bool ok = kernels::polar_log3(f, R, L);
    ASSERT_EQ(ok, p.ok);
    if (!ok) {
      ++refused;
      continue;
    }
    bad += differing(p.R, R) + differing(p.log_U, L);
  }
  EXPECT_EQ(bad, 0);
  EXPECT_GT(refused, 0);
}

TEST(LawKernels, NeoHookeanKeepsEigensBits) {
  std::mt19937_64 g(9);
  const classical::Elastic el = classical::elastic_from_bulk_shear(160e9, 80e9);
  int bad = 0;
  for (int t = 0; t < 20000; ++t) {
    Mat3 F = random_gradient(g, t % 2 ? 0.02 : 0.3);
    if (t % 50 == 0) F.row(1) = -F.row(1);
    double f[9];
    to_rows(F, f);
    const classical::LawResult r = classical::neo_hookean(el, F);
    kernels::LawStress k;
    kernels::neo_hookean_stress(el.mu, el.kappa, f, k);
    ASSERT_EQ(r.ok, k.ok);
    bad += differing(r.P, k.P) + differing(r.sigma, k.sigma) + (same_bits(r.W, k.W) ? 0 : 1);
  }
  EXPECT_EQ(bad, 0);
}

TEST(LawKernels, J2ReturnMapKeepsEigensBits) {
  std::mt19937_64 g(13);
  std::uniform_real_distribution<double> u(-1, 1);
  const classical::Elastic el = classical::elastic_from_bulk_shear(160e9, 80e9);
  const classical::J2Params jp{400e6, 2e9};
  int bad = 0, plastic = 0, n = 0;
  for (int t = 0; t < 20000; ++t) {
    const Mat3 F = random_gradient(g, t % 3 == 0 ? 0.001 : (t % 3 == 1 ? 0.01 : 0.2));
    classical::J2State committed;
    if (t % 2) {  // a committed plastic history (traceless, symmetric up to round-off)
      Mat3 e;
      for (int c = 0; c < 9; ++c) e(c / 3, c % 3) = 0.005 * u(g);
      e = 0.5 * (e + e.transpose()).eval();
      e -= (e.trace() / 3.0) * Mat3::Identity();
      committed.plastic_strain = e;
      committed.alpha = 0.01 * (1 + u(g));
    }
    classical::J2State trial;
    double work = 0;
    const classical::LawResult r = classical::j2_plasticity(el, jp, committed, F, trial, work);
    kernels::J2History kc, kt;
    to_rows(committed.plastic_strain, kc.plastic_strain);
    kc.alpha = committed.alpha;
    double f[9], kwork = -1;
    to_rows(F, f);
    kernels::LawStress k;
    kernels::j2_stress(el.mu, el.kappa, jp.yield_stress, jp.hardening_modulus, kc, f, kt, kwork, k);
    ASSERT_EQ(r.ok, k.ok);
    ++n;
    plastic += work > 0;
    bad += differing(r.P, k.P) + differing(r.sigma, k.sigma) + (same_bits(r.W, k.W) ? 0 : 1);
    bad += differing(trial.plastic_strain, kt.plastic_strain) + (same_bits(trial.alpha, kt.alpha) ? 0 : 1) +
           (same_bits(work, kwork) ? 0 : 1);
  }
  EXPECT_EQ(bad, 0);
  EXPECT_GT(plastic, n / 4) << "the random steps are meant to yield often";
  EXPECT_LT(plastic, n) << "and to stay elastic sometimes";
}

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

// law_row against correspondence.cpp's host path as it was for these laws: F = N K^-1,
// the law, von Mises of sigma, the record {P K^-1 - G F, G}.
TEST(LawKernels, LawRowKeepsTheHostsBits) {
  std::mt19937_64 g(17);
  const classical::Elastic el = classical::elastic_from_bulk_shear(160e9, 80e9);
  const classical::J2Params jp{400e6, 2e9};
  int bad = 0, carried = 0;
  for (int t = 0; t < 6000; ++t) {
    const bool j2 = t % 2;
    const Mat3 K = random_shape_tensor(g, 4 + t % 12);
    const Mat3 N = random_gradient(g, 0.05) * K;
    double sums[18];
    to_rows(K, sums);
    to_rows(N, sums + 9);
    kernels::LawConstants c;
    c.law = j2 ? kernels::kJ2Law : kernels::kNeoHookeanLaw;
    c.lambda = el.lambda, c.mu = el.mu, c.kappa = el.kappa, c.yield_stress = jp.yield_stress,
    c.hardening = jp.hardening_modulus;
    const double G = 3e20;
    kernels::J2History kc{}, kt;
    double rec[kernels::kAffineRecord], work = -1;
    const kernels::AffineRow row = kernels::law_row(sums, 3, 1e-4, c, G, kc, kt, work, rec);
    Eigen::SelfAdjointEigenSolver<Mat3> es;
    es.computeDirect(K, Eigen::EigenvaluesOnly);
    if (!row.carries) {
      EXPECT_LT(es.eigenvalues()[0] / es.eigenvalues()[2], 1.1e-4);
      continue;
    }
    ++carried;
    const Mat3 Kinv = K.inverse(), F = N * Kinv;
    bad += differing(F, row.F);
    classical::J2State trial;
    double w = 0;
    const classical::LawResult r = j2 ? classical::j2_plasticity(el, jp, {}, F, trial, w) : classical::neo_hookean(el, F);
    bad += same_bits(r.W, row.W) ? 0 : 1;
    const Mat3 dev = r.sigma - (r.sigma.trace() / 3.0) * Mat3::Identity();
    bad += same_bits(std::sqrt(1.5 * (dev.array() * dev.array()).sum()), row.von_mises) ? 0 : 1;
    bad += differing(Mat3(r.P * Kinv - G * F), rec) + (same_bits(G, rec[9]) ? 0 : 1);
    if (j2) bad += differing(trial.plastic_strain, kt.plastic_strain) + (same_bits(w, work) ? 0 : 1);
  }
  EXPECT_EQ(bad, 0);
  EXPECT_GT(carried, 3000);
}


void to_history(const classical::HypoState& h, kernels::HypoHistory& k) {
  to_rows(h.F, k.F);
  to_rows(h.V, k.V);
  to_rows(h.R, k.R);
  to_rows(h.sigma_u, k.sigma_u);
  k.alpha = h.alpha;
  k.thermal = h.thermal;
}

// Peridigm's rotation increment alone, where the rounding of its small terms shows: spins
// with a component 1e-9 of the others, and general (not skew) matrices.
TEST(LawKernels, PeridigmRotationIncrementKeepsEigensBits) {
  std::mt19937_64 g(23);
  std::uniform_real_distribution<double> u(-1, 1);
  int bad = 0;
  for (int t = 0; t < 20000; ++t) {
    Eigen::Vector3d w(u(g), u(g), u(g));
    w *= 1e4;
    if (t % 2) w[t % 3] *= 1e-9;
    Mat3 O;
    O << 0, -w[2], w[1], w[2], 0, -w[0], -w[1], w[0], 0;
    if (t % 4 >= 2)
      for (int c = 0; c < 9; ++c) O(c / 3, c % 3) = 1e4 * u(g);
    const Mat3 Q = classical::peridigm_rotation_increment(O, 1e-7);
    double o[9], q[9];
    to_rows(O, o);
    kernels::hypo_peridigm_rotation(o, 1e-7, q);
    bad += differing(Q, q);
  }
  EXPECT_EQ(bad, 0);
}

// hypoelastic_step against hypo_step: every return (work, peridigm, needleman) and
// rotation update (cayley, peridigm), with F_dot given or not, with a thermal increment or
// not, from random committed states; elastic and plastic steps.
TEST(LawKernels, HypoelasticStepKeepsEigensBits) {
  std::mt19937_64 g(21);
  std::uniform_real_distribution<double> u(-1, 1);
  const classical::Elastic el = classical::elastic_from_bulk_shear(160e9, 80e9);
  const classical::Needleman nm{0.1, 0.02, 1e-3, 0.002, 0.5};
  int bad = 0, plastic = 0, n = 0;
  int bad_by[3][2] = {};
  for (int t = 0; t < 12000; ++t) {
    const auto kind = static_cast<classical::PlasticReturn>(t % 3);
    const auto rot = (t / 3) % 2 ? classical::RotationUpdate::peridigm : classical::RotationUpdate::cayley;
    classical::HypoState h;
    h.F = random_gradient(g, 0.05);
    const Mat3 Ru = Eigen::AngleAxisd(3.0 * u(g), Eigen::Vector3d(u(g), u(g), u(g)).normalized()).toRotationMatrix();
    Mat3 V;
    for (int c = 0; c < 9; ++c) V(c / 3, c % 3) = (c % 4 == 0 ? 1.0 : 0.0) + 0.02 * u(g);
    h.V = 0.5 * (V + V.transpose());
    h.R = Ru;
    Mat3 sg;
    for (int c = 0; c < 9; ++c) sg(c / 3, c % 3) = 3e8 * u(g);
    h.sigma_u = 0.5 * (sg + sg.transpose());
    h.alpha = t % 2 ? 0.01 * (1 + u(g)) : 0.0;
    h.thermal = 1e-4 * u(g);
    Mat3 dF;
    for (int c = 0; c < 9; ++c) dF(c / 3, c % 3) = 2e-3 * u(g);
    const Mat3 F = h.F + dF;
    const double dt = 1e-7, yield = (t / 6) % 2 ? 4e8 : 0.0;
    const bool with_fdot = (t / 12) % 2, heat = (t / 24) % 2;
    const Mat3 Fdot = dF / dt;
    const double thermal = heat ? h.thermal + 1e-5 : h.thermal;
    classical::HypoState trial;
    double work = 0;
    const classical::HypoResult r = classical::hypoelastic_step(el, yield, 2e9, h, F, dt, trial, work,
                                                                with_fdot ? &Fdot : nullptr, kind, nm, thermal, rot);
    kernels::HypoConstants c;
    c.lambda = el.lambda, c.mu = el.mu, c.kappa = el.kappa, c.hardening = 2e9;
    c.plastic_return = static_cast<int>(kind);
    c.rotation = rot == classical::RotationUpdate::cayley ? kernels::kRotationCayley : kernels::kRotationPeridigm;
    c.N = nm.N, c.m = nm.m, c.rate0 = nm.rate0, c.eps0 = nm.eps0, c.eps1 = nm.eps1;
    kernels::HypoHistory kh, kt;
    to_history(h, kh);
    double f[9], fd[9], d[9], kwork = -1;
    to_rows(F, f);
    to_rows(Fdot, fd);
    kernels::LawStress k;
    kernels::hypo_step(c, yield, kh, f, dt, with_fdot ? fd : nullptr, thermal, kt, kwork, k, d);
    ASSERT_EQ(r.law.ok, k.ok);
    ++n;
    plastic += work > 0;
    const int b = differing(r.law.P, k.P) + differing(r.law.sigma, k.sigma) + (same_bits(r.law.W, k.W) ? 0 : 1) +
                  differing(r.d, d) + differing(trial.R, kt.R) + differing(trial.V, kt.V) +
                  differing(trial.sigma_u, kt.sigma_u) + (same_bits(trial.alpha, kt.alpha) ? 0 : 1) +
                  (same_bits(work, kwork) ? 0 : 1);
    bad += b;
    bad_by[t % 3][(t / 3) % 2] += b;
  }
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 2; ++b) EXPECT_EQ(bad_by[a][b], 0) << "return " << a << ", rotation " << b;
  EXPECT_EQ(bad, 0);
  EXPECT_GT(plastic, n / 8) << "the random steps are meant to yield";
}

// F_dot's bond sum as a portable row (rate_gradient_row) against the host loop it replaced
// in Correspondence::hypo_row (Vec3 differences, then rate_gradient_add bond by bond): the
// same bits on random families, broken bonds skipped.
TEST(LawKernels, RateGradientRowKeepsTheHostLoopsBits) {
  std::mt19937_64 g(30);
  std::uniform_real_distribution<double> u(-1, 1);
  const std::size_t n = 40;
  std::vector<Vec3> X(n), U(n), Uc(n);
  for (std::size_t i = 0; i < n; ++i) {
    X[i] = {1e-3 * u(g), 1e-3 * u(g), 1e-3 * u(g)};
    U[i] = {1e-5 * u(g), 1e-5 * u(g), 1e-5 * u(g)};
    Uc[i] = {U[i].x + 1e-8 * u(g), U[i].y + 1e-8 * u(g), U[i].z + 1e-8 * u(g)};
  }
  std::vector<uint64_t> offset{0};
  std::vector<uint32_t> nbr;
  std::vector<uint8_t> intact;
  std::vector<double> w;
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < n; ++j)
      if (j != i && u(g) > 0) nbr.push_back(static_cast<uint32_t>(j)), intact.push_back(u(g) > -0.6 ? 1 : 0),
                                  w.push_back(1e-9 * (1.5 + u(g)));
    offset.push_back(nbr.size());
  }
  int bad = 0;
  for (std::size_t i = 0; i < n; ++i) {
    double host[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    const Vec3 dui = U[i] - Uc[i];
    for (uint64_t k = offset[i]; k < offset[i + 1]; ++k) {
      if (!intact[k]) continue;
      const uint32_t j = nbr[k];
      const Vec3 du = (U[j] - Uc[j]) - dui, xi = X[j] - X[i];
      const double a[3] = {du.x, du.y, du.z}, x[3] = {xi.x, xi.y, xi.z};
      kernels::rate_gradient_add(host, a, x, w[k]);
    }
    double row[9];
    kernels::rate_gradient_row(&X[0].x, &U[0].x, &Uc[0].x, offset.data(), nbr.data(), intact.data(),
                               [&w](uint64_t k) { return w[k]; }, i, row);
    for (int c = 0; c < 9; ++c) bad += same_bits(host[c], row[c]) ? 0 : 1;
  }
  EXPECT_EQ(bad, 0);
}

}  // namespace
}  // namespace horizon
