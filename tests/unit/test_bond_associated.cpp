// The bond-associated correspondence model (material/models/bond_associated.hpp) through
// the force pass on lattice blocks, against identities that hold exactly:
//   - a homogeneous deformation gives every particle the law's energy W(F) (truncated
//     families included), no force in the bulk, and forces whose virial
//     sum_i V_i f_i (x) X_i is -P sum_i V_i: the body carries the classical stress P(F);
//   - the forces are the derivative of the energy E = sum_i V_i W_i (central differences
//     at a finite non-affine strain, bulk and surface particles);
//   - the checkerboard that the classical correspondence model cannot see (F_i = I, no
//     energy without stabilisation) stores energy here, quadratic in its amplitude;
//   - the static solvers' finite-difference tangent, whose probes share a pass when they
//     are far enough apart, equals one-probe-at-a-time differences: the forces reach three
//     bonds (System::model.reach_hops).
#include <gtest/gtest.h>
#include <omp.h>

#include <Eigen/Dense>
#include <cmath>
#include <string>
#include <vector>

#include "horizon/material/classical/stress_laws.hpp"
#include "horizon/solver/equilibrium.hpp"
#include "horizon/solver/forces.hpp"
#include "horizon/solver/tangent.hpp"
#include "test_helpers.hpp"

namespace horizon {
namespace {

using Mat3 = Eigen::Matrix3d;
constexpr double kE = 200e9, kNu = 0.3;

System block(const test::BlockSpec& b, const std::string& law, const std::string& model = "bond_associated_correspondence") {
  MaterialConfig mat = test::make_material(model, kE, kNu, 7800.0);
  mat.choices["stress_law"] = law;
  if (model == "correspondence") mat.parameters["stabilization"] = 0.0;
  fill_model_defaults(mat);
  return test::make_block(b, mat);
}

void deform(System& s, const Mat3& F) {
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    const Vec3& X = s.particles.X[i];
    const Eigen::Vector3d x = F * Eigen::Vector3d(X.x, X.y, X.z);
    s.particles.u[i] = Vec3{x[0], x[1], x[2]} - X;
  }
}

TEST(BondAssociated, HomogeneousDeformationCarriesTheClassicalStress) {
  // f_i reads the families of i's neighbours' neighbours (F_j and m_j of each neighbour
  // j, whose bonds reach on): the bulk, where no force is left, is three horizons in.
  test::BlockSpec b;
  b.n = {12, 12, 12};
  b.horizon_factor = 1.5;
  Mat3 F;
  F << 1.002, 0.0007, -0.0004, 0.0003, 0.9985, 0.0006, -0.0002, 0.0005, 1.001;
  for (const std::string law : {"linear_elastic", "neo_hookean"}) {
    System s = block(b, law);
    deform(s, F);
    compute_forces(s, true);
    const classical::Elastic c = classical::elastic_from_bulk_shear(kE / (3 * (1 - 2 * kNu)), kE / (2 * (1 + kNu)));
    const classical::LawResult r = law == "linear_elastic" ? classical::linear_elastic(c, F) : classical::neo_hookean(c, F);
    // W_i = sum_j c_ij V_j W(F) = W(F) at every particle (sum_j c_ij V_j = 1); 1e-9: the
    // strains of 1e-3 are differences of O(1) gradients (2e-11 seen).
    for (std::size_t i = 0; i < s.particles.size(); ++i) ASSERT_NEAR(s.particles.energy[i], r.W, 1e-9 * r.W) << law << i;
    // No force in the bulk: f there is round-off of P/h.
    const double fscale = r.P.norm() / b.spacing;
    int bulk = 0;
    for (std::size_t i = 0; i < s.particles.size(); ++i) {
      bool inside = true;
      for (int k = 0; k < 3; ++k) {
        const long index = std::lround(s.particles.X[i][k] / b.spacing);
        inside = inside && index >= 5 && index <= b.n[static_cast<std::size_t>(k)] - 6;
      }
      if (!inside) continue;
      ++bulk;
      EXPECT_LT(norm(s.particles.f[i]), 1e-10 * fscale) << law << i;
    }
    EXPECT_EQ(bulk, 8);
    // The virial of the forces: -P times the body's volume, truncated families included
    // (dE = P : dF sum V_i under an affine variation; E = W(F) sum V_i exactly).
    Mat3 virial = Mat3::Zero();
    double volume = 0;
    for (std::size_t i = 0; i < s.particles.size(); ++i) {
      const Vec3& f = s.particles.f[i];
      const Vec3& X = s.particles.X[i];
      const double V = s.particles.volume[i];
      virial += V * Eigen::Vector3d(f.x, f.y, f.z) * Eigen::Vector3d(X.x, X.y, X.z).transpose();
      volume += V;
    }
    EXPECT_LT((virial + volume * r.P).norm(), 1e-10 * volume * r.P.norm()) << law;
  }
}

TEST(BondAssociated, ForcesAreTheEnergyDerivative) {
  test::BlockSpec b;
  b.n = {5, 5, 5};
  b.horizon_factor = 2.0;
  System s = block(b, "neo_hookean");
  Mat3 F;
  F << 1.06, 0.03, 0.0, 0.0, 0.96, 0.02, 0.01, 0.0, 1.02;
  deform(s, F);
  for (std::size_t i = 0; i < s.particles.size(); ++i)
    s.particles.u[i] += 2e-5 * Vec3{std::sin(7.0 * i), std::cos(11.0 * i), std::sin(13.0 * i + 1)};
  auto energy = [&]() {
    compute_forces(s, true);
    double U = 0;
    for (std::size_t i = 0; i < s.particles.size(); ++i) U += s.particles.energy[i] * s.particles.volume[i];
    return U;
  };
  energy();
  const std::vector<Vec3> f = s.particles.f;
  double fmax = 0;
  for (std::size_t i = 0; i < f.size(); ++i) fmax = std::max(fmax, norm(f[i]) * s.particles.volume[i]);
  const auto inner = test::interior_particles(s, b);
  ASSERT_FALSE(inner.empty());
  for (std::size_t p : {inner.front(), std::size_t{0}, std::size_t{7}, std::size_t{31}}) {
    for (int c = 0; c < 3; ++c) {
      const double dh = 1e-9;
      s.particles.u[p][c] += dh;
      const double Up = energy();
      s.particles.u[p][c] -= 2 * dh;
      const double Um = energy();
      s.particles.u[p][c] += dh;
      EXPECT_NEAR(f[p][c] * s.particles.volume[p], -(Up - Um) / (2 * dh), 1e-5 * fmax) << "particle " << p << " " << c;
    }
  }
}

// u = a (-1)^(i+j+k) e_x: the classical F_i = I in the bulk (a bond and its opposite move
// alike), so the classical model without stabilisation stores nothing; the bond-level
// F_ij = I + du (x) xi/|xi|^2 strains every odd bond.
TEST(BondAssociated, CheckerboardStoresEnergy) {
  test::BlockSpec b;
  b.n = {8, 8, 8};
  b.horizon_factor = 2.0;
  auto interior_energy = [&](const std::string& model, double a) {
    System s = block(b, "linear_elastic", model);
    for (std::size_t i = 0; i < s.particles.size(); ++i) {
      const Vec3& X = s.particles.X[i];
      const long parity = std::lround(X.x / b.spacing) + std::lround(X.y / b.spacing) + std::lround(X.z / b.spacing);
      s.particles.u[i] = Vec3{parity % 2 ? -a : a, 0, 0};
    }
    compute_forces(s, true);
    double W = 0;
    const auto ids = test::interior_particles(s, b);
    for (std::size_t i : ids) W += s.particles.energy[i];
    return W / static_cast<double>(ids.size());
  };
  const double a = 1e-7, mu = kE / (2 * (1 + kNu)), scale = mu * std::pow(2 * a / b.spacing, 2);
  EXPECT_LT(std::abs(interior_energy("correspondence", a)), 1e-9 * scale);
  const double w1 = interior_energy("bond_associated_correspondence", a),
               w2 = interior_energy("bond_associated_correspondence", 2 * a);
  EXPECT_GT(w1, 0.01 * scale);
  EXPECT_NEAR(w2 / w1, 4.0, 1e-6);
}

TEST(BondAssociated, FiniteDifferenceTangentReachesThreeBonds) {
  test::BlockSpec b;
  b.n = {3, 3, 8};
  b.horizon_factor = 1.5;
  System s = block(b, "neo_hookean");
  Mat3 F;
  F << 1.01, 0.002, 0.0, 0.0, 0.995, 0.003, 0.001, 0.0, 1.004;
  deform(s, F);
  for (std::size_t i = 0; i < s.particles.size(); ++i)
    s.particles.u[i] += 2e-5 * Vec3{std::sin(3.0 * i), std::cos(5.0 * i), std::sin(2.0 * i + 1)};
  const DofMap d = make_free_dof_map(s);
  const Eigen::MatrixXd K = Eigen::MatrixXd(finite_difference_tangent(s, d)).transpose();  // stored: K^T
  const double h = 1e-6 * b.spacing;
  double worst = 0;
  const double scale = K.cwiseAbs().maxCoeff();
  for (std::size_t col = 0; col < d.particle.size(); col += 7) {
    const uint32_t p = d.particle[col];
    const int c = d.component[col];
    auto forces = [&](double du) {
      s.particles.u[p][c] += du;
      compute_forces(s, false);
      s.particles.u[p][c] -= du;
      Eigen::VectorXd f(static_cast<Eigen::Index>(d.particle.size()));
      for (std::size_t r = 0; r < d.particle.size(); ++r)
        f[static_cast<Eigen::Index>(r)] = s.particles.f[d.particle[r]][d.component[r]] * s.particles.volume[d.particle[r]];
      return f;
    };
    const Eigen::VectorXd column = -(forces(h) - forces(-h)) / (2 * h);
    worst = std::max(worst, (column - K.col(static_cast<Eigen::Index>(col))).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst, 1e-6 * scale);
}

// The passes split their rows over threads (above 512 particles), each row written by
// its own thread alone: the same bits on one and two threads.
TEST(BondAssociated, OneAndTwoThreadsGiveTheSameBits) {
  test::BlockSpec b;
  b.n = {12, 12, 12};
  b.horizon_factor = 1.5;
  auto forces = [&](int threads) {
    const int saved = omp_get_max_threads();
    omp_set_num_threads(threads);
    System s = block(b, "neo_hookean");
    for (std::size_t i = 0; i < s.particles.size(); ++i)
      s.particles.u[i] = 1e-5 * Vec3{std::sin(3.0 * i), std::cos(5.0 * i), std::sin(2.0 * i + 1)};
    compute_forces(s, true);
    omp_set_num_threads(saved);
    return s.particles.f;
  };
  const std::vector<Vec3> one = forces(1), two = forces(2);
  ASSERT_EQ(one.size(), two.size());
  for (std::size_t i = 0; i < one.size(); ++i)
    for (int c = 0; c < 3; ++c) ASSERT_EQ(one[i][c], two[i][c]) << i;
}

}  // namespace
}  // namespace horizon
