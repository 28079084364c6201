// The bond-associated correspondence model's per-bond work as portable kernels
// (kernels/bond_associated.hpp, issue 30) against the Eigen forms BondAssociated::
// force_state computed before them (copied below as they were): the same bits for the
// bond-level gradient F_ij, its lagrangian rate and the semi-Lagrangian L_ij F_ij, the
// bond's force term, its share of S_i and the second term omega S_i K_i^-1 b, on random
// gradients, rates, bonds and stresses.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>

#include "horizon/kernels/bond_associated.hpp"
#include "kernel_bits.hpp"

namespace horizon {
namespace {

using test::Mat3;
using test::differing;
using test::same_bits;
using test::to_rows;
using Vec = Eigen::Vector3d;

Mat3 random_matrix(std::mt19937_64& g, double centre, double amp) {
  std::uniform_real_distribution<double> u(-1, 1);
  Mat3 m;
  for (int c = 0; c < 9; ++c) m(c / 3, c % 3) = (c % 4 == 0 ? centre : 0.0) + amp * u(g);
  return m;
}

int differing3(const Vec& v, const double* a) {
  int n = 0;
  for (int r = 0; r < 3; ++r) n += same_bits(v[r], a[r]) ? 0 : 1;
  return n;
}

TEST(BondAssociatedKernels, BondTermsKeepTheHostsBits) {
  std::mt19937_64 g(31);
  std::uniform_real_distribution<double> u(-1, 1);
  int bad = 0;
  for (int t = 0; t < 20000; ++t) {
    const bool two_d = t % 3 == 0;
    const Mat3 Fi = random_matrix(g, 1.0, 0.1), Fj = random_matrix(g, 1.0, 0.1);
    const Mat3 Ri = random_matrix(g, 0.0, 1e3), Rj = random_matrix(g, 0.0, 1e3);
    Vec xi(1e-3 * u(g), 1e-3 * u(g), two_d ? 0.0 : 1e-3 * u(g));
    const Vec Y = Fi * xi + Vec(1e-5 * u(g), 1e-5 * u(g), two_d ? 0.0 : 1e-5 * u(g));
    const Vec dY(u(g), u(g), two_d ? 0.0 : u(g));
    const double xx = xi.squaredNorm(), yy = Y.squaredNorm();
    // The host's Eigen forms (bond_associated.cpp before the kernels).
    const Mat3 Fbar = 0.5 * (Fi + Fj);
    const Mat3 Fb = Fbar + (Y - Fbar * xi) * xi.transpose() / xx;
    const Mat3 Rbar = 0.5 * (Ri + Rj);
    const Mat3 lag = Rbar + (dY - Rbar * xi) * xi.transpose() / xx;
    const Mat3 semi = (Rbar + (dY - Rbar * Y) * Y.transpose() / Y.squaredNorm()) * Fb;

    double fi[9], fj[9], ri[9], rj[9], x[3] = {xi[0], xi[1], xi[2]}, y[3] = {Y[0], Y[1], Y[2]},
                                       dy[3] = {dY[0], dY[1], dY[2]};
    to_rows(Fi, fi), to_rows(Fj, fj), to_rows(Ri, ri), to_rows(Rj, rj);
    double kfb[9], klag[9], kL[9], ksemi[9];
    kernels::bond_level_gradient(fi, fj, x, y, kernels::squared_norm3(x), kfb);
    kernels::bond_level_gradient(ri, rj, x, dy, xx, klag);
    kernels::bond_level_gradient(ri, rj, y, dy, kernels::squared_norm3(y), kL);
    kernels::mat3_mul(kL, kfb, ksemi);
    bad += differing(Fb, kfb) + differing(lag, klag) + differing(semi, ksemi);
    bad += (same_bits(xx, kernels::squared_norm3(x)) ? 0 : 1) + (same_bits(yy, kernels::squared_norm3(y)) ? 0 : 1);

    // The force terms with a stress P and the bond b (xi, or Y on the current bonds).
    const Mat3 P = random_matrix(g, 1e8 * u(g), 1e8);
    const bool on_y = t % 2;
    const Vec b = on_y ? Y : xi;
    const double bb = b.squaredNorm();
    const double c_ij = 1.0 + u(g), c_ji = 1.0 + u(g), V = 1e-9 * (1.5 + u(g)), omega = 1.0 + 0.5 * u(g);
    Mat3 S = random_matrix(g, 1e7, 1e7);
    double ks[9];
    to_rows(S, ks);
    const Vec nb = b / std::sqrt(bb);
    const Vec T = c_ij * (P * b) / bb;
    S += (0.5 * V * (c_ij + c_ji)) * (P - (P * nb) * nb.transpose());
    const Mat3 Kinv = random_matrix(g, 1e9, 1e9);
    const Mat3 A = S * Kinv;
    const Vec T2 = T + omega * (A * b);
    double kp[9], kb[3] = {b[0], b[1], b[2]}, kt[3], kk[9], ka[9];
    to_rows(P, kp), to_rows(Kinv, kk);
    kernels::bond_associated_terms(kp, kb, bb, c_ij, c_ji, V, kt, ks);
    const int bad_t = differing3(T, kt);
    bad += bad_t + differing(S, ks);
    kernels::mat3_mul(ks, kk, ka);
    kernels::bond_associated_tail(ka, omega, kb, kt);
    bad += differing(A, ka) + differing3(T2, kt);
    if (bad) {
      ADD_FAILURE() << "case " << t << ": Fb " << differing(Fb, kfb) << " lag " << differing(lag, klag) << " semi "
                    << differing(semi, ksemi) << " T " << bad_t << " T2 " << differing3(T2, kt) << " S " << differing(S, ks);
      break;
    }
  }
  EXPECT_EQ(bad, 0);
}

}  // namespace
}  // namespace horizon
