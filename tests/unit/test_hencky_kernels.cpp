// Extended correspondence's Hencky map as portable kernels (kernels/hencky.hpp, issue 30)
// against the Eigen host form it replaced in the model's law step
// (material/models/extended_correspondence.hpp: hencky_of_green with Eigen's
// SelfAdjointEigenSolver, green_stress_of_hencky): the same bits on random strains, near
// isotropic ones (repeated eigenvalues: the deflation paths), diagonal and plane ones (the
// tridiagonalisation's identity path), zero, and locally inverted ones (the floor); and the
// strain laws elastic and j2 (kernels/strain_laws.hpp) against classical/strain_laws.hpp, and
// the volumetric gradient's corrections against the model's former Eigen expressions.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstring>
#include <random>

#include "horizon/kernels/hencky.hpp"
#include "horizon/kernels/strain_laws.hpp"
#include "horizon/material/classical/strain_laws.hpp"
#include "horizon/material/models/extended_correspondence.hpp"
#include "kernel_bits.hpp"

namespace horizon {
namespace {

using test::Mat3;
using test::differing;
using test::same_bits;
using test::to_rows;

Mat3 random_symmetric(std::mt19937_64& g, int kind) {
  std::uniform_real_distribution<double> u(-1, 1);
  Mat3 E = Mat3::Zero();
  const double amp = kind % 4 == 0 ? 1e-3 : (kind % 4 == 1 ? 0.05 : (kind % 4 == 2 ? 0.4 : 3.0));
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c <= r; ++c) E(r, c) = E(c, r) = amp * u(g);
  switch (kind % 7) {
    case 0: E = Mat3::Identity() * E(0, 0) + 1e-9 * E; break;  // nearly isotropic
    case 1: E(2, 0) = E(0, 2) = 0.0; break;                      // identity tridiagonalisation
    case 2: E(2, 0) = E(0, 2) = E(2, 1) = E(1, 2) = E(2, 2) = 0.0; break;  // plane (2-D)
    case 3: E = E.diagonal().asDiagonal(); break;                 // diagonal
    case 4: E(0, 0) = -0.5 - 0.1 * std::abs(u(g)); break;         // C below the floor
    default: break;
  }
  if (kind % 101 == 0) E.setZero();
  if (kind % 53 == 0) E(1, 1) = E(0, 0);  // a repeated diagonal entry
  return E;
}

TEST(HenckyKernels, SelfAdjointEigenSolverKeepsEigensBits) {
  std::mt19937_64 g(11);
  int bad = 0;
  for (int t = 0; t < 30000; ++t) {
    const Mat3 E = random_symmetric(g, t);
    const Mat3 C = Mat3::Identity() + 2.0 * E;
    double A[9], ev[3], Q[9];
    to_rows(C, A);
    const bool ok = kernels::sym_eigen3(A, ev, Q);
    const Eigen::SelfAdjointEigenSolver<Mat3> eig(C);
    ASSERT_EQ(ok, eig.info() == Eigen::Success);
    bad += differing(eig.eigenvectors(), Q);
    for (int a = 0; a < 3; ++a) bad += same_bits(eig.eigenvalues()[a], ev[a]) ? 0 : 1;
  }
  EXPECT_EQ(bad, 0);
  // and the decomposition it is: C Q = Q diag(ev)
  double A[9] = {2, 1, 0.5, 1, 3, -1, 0.5, -1, 1}, ev[3], Q[9];
  ASSERT_TRUE(kernels::sym_eigen3(A, ev, Q));
  for (int r = 0; r < 3; ++r)
    for (int a = 0; a < 3; ++a) {
      const double CQ = A[3 * r] * Q[a] + A[3 * r + 1] * Q[3 + a] + A[3 * r + 2] * Q[6 + a];
      EXPECT_NEAR(CQ, Q[3 * r + a] * ev[a], 1e-14);
    }
  EXPECT_LT(ev[0], ev[1]);
  EXPECT_LT(ev[1], ev[2]);
}

TEST(HenckyKernels, HenckyMapAndGreenStressKeepTheHostsBits) {
  std::mt19937_64 g(13);
  std::uniform_real_distribution<double> u(-1, 1);
  int bad_map = 0, bad_strain = 0, bad_stress = 0;
  for (int t = 0; t < 30000; ++t) {
    const Mat3 E = random_symmetric(g, t);
    const extended::HenckyMap h = extended::hencky_of_green(E);
    double e[9], N[9], l[3], strain[9];
    to_rows(E, e);
    kernels::hencky_of_green3(e, 1e-6, N, l, strain);
    bad_map += differing(h.N, N);
    bad_strain += differing(h.strain, strain);
    for (int a = 0; a < 3; ++a) bad_map += same_bits(h.l[a], l[a]) ? 0 : 1;
    Mat3 T;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c <= r; ++c) T(r, c) = T(c, r) = 1e8 * u(g);
    if (t % 5 == 0) T(0, 1) = 3e7, T(1, 0) = -2e7;  // not symmetric: the products' orders show
    double Tr[9], S[9];
    to_rows(T, Tr);
    kernels::green_stress_of_hencky3(N, l, Tr, S);
    bad_stress += differing(extended::green_stress_of_hencky(h, T), S);
  }
  EXPECT_EQ(bad_map, 0);
  EXPECT_EQ(bad_strain, 0);
  EXPECT_EQ(bad_stress, 0);
}

TEST(HenckyKernels, LogDividedDifferenceIsTheSlopeOfTheLog) {
  EXPECT_NEAR(kernels::log_divided_difference3(2.0, 1.0), std::log(2.0), 1e-15);
  EXPECT_NEAR(kernels::log_divided_difference3(1.0 + 1e-9, 1.0), 1.0 - 0.5e-9, 1e-15);  // series branch
}

TEST(HenckyKernels, StrainLawsKeepTheHostsBits) {
  std::mt19937_64 g(17);
  std::uniform_real_distribution<double> u(-1, 1);
  classical::StrainLawParams p;  // steel-like; Johnson-Cook as in examples/ballistic_plate.yaml's order
  p.kappa = 160e9, p.mu = 80e9, p.yield_stress = p.sigma0 = 1e9, p.hardening_modulus = 2e9;
  p.B = 5e8, p.n = 0.3, p.C = 0.02, p.rate0 = 1.0;
  p.d1 = 0.05, p.d2 = 3.4, p.d3 = -1.5, p.d4 = 0.01, p.damage_rate0 = 1.0;
  int bad = 0, yielded[3] = {0, 0, 0}, damaged = 0;
  for (int t = 0; t < 30000; ++t) {
    const int law = t % 3;
    p.law = law == 0 ? classical::StrainLaw::elastic : law == 1 ? classical::StrainLaw::j2 : classical::StrainLaw::johnson_cook;
    p.damage = law == 2 && t % 2 == 0;
    const Mat3 E = random_symmetric(g, t / 3) * ((t / 3) % 2 ? 0.01 : 1.0);
    classical::StrainLawState committed;  // a traceless plastic history half of the time
    if ((t / 2) % 2 == 0) {
      const Mat3 P = random_symmetric(g, 5) * 0.02;
      committed.plastic_strain = P - (P.trace() / 3.0) * Mat3::Identity();
      committed.alpha = 0.05 * std::abs(u(g));
      committed.damage = 0.5 * std::abs(u(g));
    }
    const double dt = t % 7 == 0 ? 0.0 : 1e-8;
    classical::StrainLawState trial;
    const classical::StrainLawOut host = classical::strain_law(p, committed, E, dt, trial);
    const kernels::StrainLawConstants k = extended::strain_law_constants(p);
    double e[9], Ep_n[9], Ep[9], alpha = -1, D = -1;
    to_rows(E, e);
    to_rows(committed.plastic_strain, Ep_n);
    kernels::StrainLawPoint out;
    kernels::strain_law_point(k, Ep_n, committed.alpha, committed.damage, e, dt, Ep, alpha, D, out);
    yielded[law] += host.plastic_work > 0 ? 1 : 0;
    damaged += trial.damage > committed.damage ? 1 : 0;
    bad += differing(host.S, out.S) + differing(trial.plastic_strain, Ep);
    bad += (same_bits(host.W, out.W) ? 0 : 1) + (same_bits(host.plastic_work, out.plastic_work) ? 0 : 1);
    bad += (same_bits(host.rate, out.rate) ? 0 : 1) + (same_bits(trial.alpha, alpha) ? 0 : 1);
    bad += same_bits(trial.damage, D) ? 0 : 1;
  }
  EXPECT_EQ(bad, 0);
  EXPECT_EQ(yielded[0], 0);
  EXPECT_GT(yielded[1], 1500);  // the return maps ran
  EXPECT_GT(yielded[2], 1500);
  EXPECT_GT(damaged, 500);
}

// run_law's volumetric_strain gradient corrections as the host wrote them with Eigen
// (extended_correspondence.cpp before the kernels), against kernels/strain_laws.hpp.
TEST(HenckyKernels, VolumetricGradientCorrectionsKeepTheHostsBits) {
  std::mt19937_64 g(19);
  std::uniform_real_distribution<double> u(-1, 1);
  int bad = 0;
  for (int t = 0; t < 30000; ++t) {
    const int dim = t % 4 == 0 ? 2 : 3;
    Mat3 Fbar = Mat3::Identity();
    for (int c = 0; c < 9; ++c) Fbar(c / 3, c % 3) += (t % 2 ? 0.01 : 0.3) * u(g);
    if (dim == 2) Fbar(2, 0) = Fbar(2, 1) = Fbar(0, 2) = Fbar(1, 2) = 0.0, Fbar(2, 2) = 1.0;
    if (t % 97 == 0) Fbar *= 1e-3;  // det below the clamp
    Mat3 strain = random_symmetric(g, t), T = random_symmetric(g, t + 1) * 1e9;
    double st[9], Tr[9], F[9], pm[9];
    to_rows(strain, st);
    to_rows(T, Tr);
    to_rows(Fbar, F);
    Mat3 Id = Mat3::Identity();
    if (dim == 2) Id(2, 2) = 0.0;
    const double J = std::max(Fbar.determinant(), 1e-6);
    strain += ((std::log(J) - (Id.array() * strain.array()).sum()) / dim) * Id;
    kernels::volumetric_gradient_strain(F, dim, st);
    bad += differing(strain, st);
    const double p = (Id.array() * T.array()).sum() / dim;
    T -= p * Id;
    const Mat3 map = p * Fbar.inverse().transpose();
    kernels::volumetric_pressure_split(F, dim, Tr, pm);
    bad += differing(T, Tr) + differing(map, pm);
  }
  EXPECT_EQ(bad, 0);
}

}  // namespace
}  // namespace horizon
