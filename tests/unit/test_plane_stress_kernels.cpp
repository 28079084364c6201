// The correspondence family's total-form law at a point as a portable kernel
// (kernels/plane_stress.hpp law_point: the law, 2-D plane stress's secant iteration, the
// thermal split; issue 30) against the Eigen forms the host ran before it (classical/
// stress_laws.hpp plane_stress around the classical laws, and correspondence.cpp's
// evaluate_with_expansion, copied below as they were): the same bits for P, sigma, W, the
// plastic work, the J2 history and the out-of-plane stretch, on random gradients, committed
// histories, starting stretches and thermal strains.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>

#include "horizon/kernels/force_state.hpp"
#include "horizon/kernels/plane_stress.hpp"
#include "horizon/material/models/correspondence.hpp"
#include "horizon/material/nonlocal_gradient.hpp"
#include "horizon/material/classical/stress_laws.hpp"
#include "kernel_bits.hpp"

namespace horizon {
namespace {

using test::Mat3;
using test::differing;
using test::same_bits;
using test::to_rows;

enum class Law { linear_elastic, neo_hookean, j2 };

struct History {
  classical::J2State plastic;
  double lambda3 = 1;
};

// correspondence::evaluate_law and evaluate_with_expansion for the total-form laws, as
// the host had them (Eigen; the reference).
classical::LawResult reference_law(Law law, const classical::Elastic& el, const classical::J2Params& jp, int dim,
                                   bool plane_stress, const Mat3& F, const History& committed, History& trial,
                                   double& work) {
  trial = committed;
  work = 0;
  auto eval = [&](const Mat3& F3) -> classical::LawResult {
    switch (law) {
      case Law::linear_elastic: return classical::linear_elastic(el, F3);
      case Law::neo_hookean: return classical::neo_hookean(el, F3);
      case Law::j2: return classical::j2_plasticity(el, jp, committed.plastic, F3, trial.plastic, work);
    }
    return {};
  };
  if (dim == 2 && plane_stress) {
    double l3 = committed.lambda3;
    const classical::LawResult r = classical::plane_stress(F, el, l3, eval);
    trial.lambda3 = l3;
    return r;
  }
  return eval(F);
}

classical::LawResult reference_with_expansion(Law law, const classical::Elastic& el, const classical::J2Params& jp,
                                              int dim, bool plane_stress, const Mat3& F, double eps,
                                              const History& committed, History& trial, double& work) {
  if (eps == 0) return reference_law(law, el, jp, dim, plane_stress, F, committed, trial, work);
  Mat3 inverse = Mat3::Identity();
  for (int a = 0; a < dim; ++a) inverse(a, a) = 1.0 / (1.0 + eps);
  classical::LawResult r = reference_law(law, el, jp, dim, plane_stress, F * inverse, committed, trial, work);
  const double J = 1.0 / inverse.determinant();
  r.P = J * r.P * inverse.transpose();
  r.W *= J;
  work *= J;
  return r;
}

// I + a random part of size amp (2-D: the in-plane block, F33 = 1), sometimes rotated.
Mat3 random_gradient(std::mt19937_64& g, double amp, int dim) {
  std::uniform_real_distribution<double> u(-1, 1);
  Mat3 F = Mat3::Identity();
  for (int r = 0; r < dim; ++r)
    for (int c = 0; c < dim; ++c) F(r, c) += amp * u(g);
  if (u(g) > 0) {
    const double a = 3.0 * u(g);
    Mat3 Q = Mat3::Identity();
    Q(0, 0) = std::cos(a), Q(0, 1) = -std::sin(a), Q(1, 0) = std::sin(a), Q(1, 1) = std::cos(a);
    F = Q * F;
  }
  return F;
}

TEST(PlaneStressKernels, LawPointKeepsTheHostsBits) {
  std::mt19937_64 g(30);
  std::uniform_real_distribution<double> u(-1, 1);
  const classical::Elastic el = classical::elastic_from_bulk_shear(130e9, 43e9);
  const classical::J2Params jp{300e6, 1e9};
  int bad = 0, n = 0, plastic = 0, iterated = 0, refused = 0;
  for (int t = 0; t < 30000; ++t) {
    const Law law = static_cast<Law>(t % 3);
    const int dim = (t / 3) % 4 == 3 ? 3 : 2;
    const bool plane_stress = dim == 2 && (t / 3) % 4 != 2;
    const double amp = (t / 12) % 3 == 0 ? 0.002 : ((t / 12) % 3 == 1 ? 0.05 : 0.3);
    Mat3 F = random_gradient(g, amp, dim);
    if (t % 101 == 0) F.row(0) = -F.row(0);  // inverted
    const double eps = t % 5 == 0 ? 0.0 : 0.003 * u(g);
    History committed;
    if (t % 2) {  // a committed plastic history, traceless and symmetric
      Mat3 e;
      for (int c = 0; c < 9; ++c) e(c / 3, c % 3) = 0.004 * u(g);
      e = 0.5 * (e + e.transpose()).eval();
      e -= (e.trace() / 3.0) * Mat3::Identity();
      committed.plastic.plastic_strain = e;
      committed.plastic.alpha = 0.01 * (1 + u(g));
    }
    committed.lambda3 = t % 7 == 0 ? 0.0 : (t % 11 == 0 ? NAN : 1.0 + 0.05 * u(g));
    History trial;
    double work = -1;
    const classical::LawResult r =
        reference_with_expansion(law, el, jp, dim, plane_stress, F, eps, committed, trial, work);

    kernels::LawConstants c;
    c.law = law == Law::j2 ? kernels::kJ2Law : law == Law::neo_hookean ? kernels::kNeoHookeanLaw
                                                                        : kernels::kLinearElasticLaw;
    c.lambda = el.lambda, c.mu = el.mu, c.kappa = el.kappa, c.yield_stress = jp.yield_stress;
    c.hardening = jp.hardening_modulus;
    kernels::J2History kc, kt;
    to_rows(committed.plastic.plastic_strain, kc.plastic_strain);
    kc.alpha = committed.plastic.alpha;
    double f[9], kwork = -2, l3 = committed.lambda3;
    to_rows(F, f);
    kernels::LawStress k;
    kernels::law_point(c, dim, plane_stress, eps, kc, f, l3, kt, kwork, k);
    ASSERT_EQ(r.ok, k.ok) << t;
    ++n;
    refused += r.ok ? 0 : 1;
    plastic += work > 0;
    iterated += plane_stress && r.ok && F(2, 2) != trial.lambda3;
    int b = differing(r.P, k.P) + differing(r.sigma, k.sigma) + (same_bits(r.W, k.W) ? 0 : 1) +
            (same_bits(work, kwork) ? 0 : 1) + (same_bits(trial.lambda3, l3) ? 0 : 1);
    if (law == Law::j2)
      b += differing(trial.plastic.plastic_strain, kt.plastic_strain) +
           (same_bits(trial.plastic.alpha, kt.alpha) ? 0 : 1);
    EXPECT_EQ(b, 0) << "case " << t;
    bad += b;
    if (bad > 20) break;
  }
  EXPECT_EQ(bad, 0);
  EXPECT_GT(plastic, n / 20) << "the random steps are meant to yield at times";
  EXPECT_GT(iterated, n / 3) << "and to iterate the out-of-plane stretch";
  EXPECT_GT(refused, 0);
}

// law_point_row (the affine row of 2-D plane stress) against correspondence.cpp's host
// path as it was: NonlocalGradient's K^-1 and F from the sums, the law with plane
// stress's iteration, von Mises of sigma, the record {P K^-1 - G F, G}.
TEST(PlaneStressKernels, LawPointRowKeepsTheHostsBits) {
  std::mt19937_64 g(33);
  std::uniform_real_distribution<double> u(-1, 1);
  const classical::Elastic el = classical::elastic_from_bulk_shear(130e9, 43e9);
  const classical::J2Params jp{300e6, 1e9};
  int bad = 0, refused = 0;
  for (int t = 0; t < 6000; ++t) {
    const Law law = static_cast<Law>(t % 3);
    // A 2-D family's sums: K = sum w xi (x) xi, N = sum w Y (x) xi, Y = F xi + noise.
    const Mat3 F0 = random_gradient(g, t % 2 ? 0.01 : 0.2, 2);
    Mat3 K = Mat3::Zero(), N = Mat3::Zero();
    const int bonds = t % 97 == 0 ? 1 : 12;  // one bond: a refused shape tensor
    for (int b = 0; b < bonds; ++b) {
      const Eigen::Vector3d xi(1e-3 * u(g), 1e-3 * u(g), 0.0);
      const Eigen::Vector3d Y = F0 * xi + Eigen::Vector3d(1e-6 * u(g), 1e-6 * u(g), 0.0);
      const double w = 1e-9 * (1.5 + u(g));
      K += w * xi * xi.transpose();
      N += w * Y * xi.transpose();
    }
    double sums[18];
    to_rows(K, sums);
    to_rows(N, sums + 9);
    History committed;
    if (t % 2) {
      committed.plastic.alpha = 0.01 * (1 + u(g));
      committed.plastic.plastic_strain(0, 0) = 0.002 * u(g);
      committed.plastic.plastic_strain(1, 1) = -committed.plastic.plastic_strain(0, 0);
    }
    committed.lambda3 = 1.0 + 0.01 * u(g);
    const double G = t % 4 == 0 ? 0.0 : 1e20 * (1 + u(g));
    // The host's path.
    NonlocalGradient grad;
    grad.set_sums(sums, sums + 9);
    Mat3 Kinv, F;
    const bool ok = grad.finish(2, 1e-4, Kinv, F);
    History trial = committed;
    double work = 0, vm = 0, W = 0, rec[10] = {}, f[9], ki[9];
    if (ok) {
      const classical::LawResult r = reference_law(law, el, jp, 2, true, F, committed, trial, work);
      vm = correspondence::von_mises(r.sigma);
      double p[9];
      to_rows(r.P, p), to_rows(Kinv, ki), to_rows(F, f);
      if (r.ok) W = r.W;
      kernels::affine_record_of_stress(r.ok ? p : nullptr, ki, f, G, rec);
    }
    refused += ok ? 0 : 1;
    // The kernel.
    kernels::LawConstants c;
    c.law = law == Law::j2 ? kernels::kJ2Law : law == Law::neo_hookean ? kernels::kNeoHookeanLaw
                                                                        : kernels::kLinearElasticLaw;
    c.lambda = el.lambda, c.mu = el.mu, c.kappa = el.kappa, c.yield_stress = jp.yield_stress;
    c.hardening = jp.hardening_modulus;
    kernels::J2History kc, kt;
    to_rows(committed.plastic.plastic_strain, kc.plastic_strain);
    kc.alpha = committed.plastic.alpha;
    double l3 = 0, kwork = -1, krec[10];
    const kernels::AffineRow row =
        kernels::law_point_row(sums, 2, 1e-4, c, true, G, kc, committed.lambda3, kt, l3, kwork, krec);
    ASSERT_EQ(ok, row.carries);
    int b = 0;
    for (int k = 0; k < 10; ++k) b += same_bits(rec[k], krec[k]) ? 0 : 1;
    if (ok)
      b += differing(F, row.F) + (same_bits(vm, row.von_mises) ? 0 : 1) + (same_bits(W, row.W) ? 0 : 1) +
           (same_bits(work, kwork) ? 0 : 1) + (same_bits(trial.lambda3, l3) ? 0 : 1) +
           differing(trial.plastic.plastic_strain, kt.plastic_strain) +
           (same_bits(trial.plastic.alpha, kt.alpha) ? 0 : 1);
    EXPECT_EQ(b, 0) << "case " << t;
    bad += b;
    if (bad > 20) break;
  }
  EXPECT_EQ(bad, 0);
  EXPECT_GT(refused, 0);
}

// The general pass's force state of a bond (kernels/force_state.hpp) against
// correspondence.hpp's Eigen forms: bond_force_state, peridigm_hourglass (added to it as
// force_state adds it), bond_stabilization_energy, von_mises.
TEST(PlaneStressKernels, GeneralPassBondStateKeepsTheHostsBits) {
  std::mt19937_64 g(32);
  std::uniform_real_distribution<double> u(-1, 1);
  int bad = 0;
  for (int t = 0; t < 20000; ++t) {
    const Mat3 F = random_gradient(g, 0.1, t % 2 ? 3 : 2);
    Mat3 A;
    for (int c = 0; c < 9; ++c) A(c / 3, c % 3) = 1e17 * u(g);
    if (t % 13 == 0) A.setZero();
    const Vec3 xi{1e-3 * u(g), 1e-3 * u(g), t % 2 ? 1e-3 * u(g) : 0.0};
    const Eigen::Vector3d Fx = F * correspondence::to_eigen(xi);
    Vec3 Y{Fx[0] + 1e-5 * u(g), Fx[1] + 1e-5 * u(g), Fx[2] + (t % 2 ? 1e-5 * u(g) : 0.0)};
    if (t % 17 == 0) Y = Vec3{};
    const double G = t % 5 == 0 ? 0.0 : 1e20 * (1 + u(g)), omega = 1 + 0.5 * u(g), Cc = 1e17 * (1 + u(g));
    const double wv = 1e-9 * (1.5 + u(g));
    Vec3 T = correspondence::bond_force_state(A, F, G, omega, xi, Y);
    const Vec3 T1 = T;
    T += correspondence::peridigm_hourglass(F, Cc, omega, xi, Y);
    const double E = correspondence::bond_stabilization_energy(F, G, wv, xi, Y);
    double a[9], f[9], x[3] = {xi.x, xi.y, xi.z}, y[3] = {Y.x, Y.y, Y.z}, kt[3];
    to_rows(A, a), to_rows(F, f);
    kernels::correspondence_bond_state(a, f, G, omega, x, y, kt);
    bad += (same_bits(T1.x, kt[0]) ? 0 : 1) + (same_bits(T1.y, kt[1]) ? 0 : 1) + (same_bits(T1.z, kt[2]) ? 0 : 1);
    kernels::peridigm_hourglass_add(f, Cc, omega, x, y, kt);
    bad += (same_bits(T.x, kt[0]) ? 0 : 1) + (same_bits(T.y, kt[1]) ? 0 : 1) + (same_bits(T.z, kt[2]) ? 0 : 1);
    bad += same_bits(E, kernels::stabilization_energy(f, G, wv, x, y)) ? 0 : 1;
    Mat3 sigma;
    for (int c = 0; c < 9; ++c) sigma(c / 3, c % 3) = 1e8 * u(g);
    double sg[9];
    to_rows(sigma, sg);
    bad += same_bits(correspondence::von_mises(sigma), kernels::von_mises(sg)) ? 0 : 1;
    if (bad) {
      ADD_FAILURE() << "case " << t;
      break;
    }
  }
  EXPECT_EQ(bad, 0);
}

}  // namespace
}  // namespace horizon
