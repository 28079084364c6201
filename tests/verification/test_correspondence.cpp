// The correspondence model (material/models/correspondence.hpp; docs/models/
// correspondence.md) through the whole chain: deck or block, build_system, the general
// force pass, the solvers. Each figure is checked against an analytic value with its
// tolerance stated; docs/verification/models_correspondence.md lists them.
#include <gtest/gtest.h>
#include <omp.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "horizon/loading/loads.hpp"
#include "horizon/material/classical/stress_laws.hpp"
#include "horizon/material/models/correspondence.hpp"
#include "horizon/solver/explicit.hpp"
#include "horizon/solver/forces.hpp"
#include "horizon/solver/static_driver.hpp"
#include "../unit/test_helpers.hpp"
#include "verification_support.hpp"

namespace horizon::verification {
namespace {

using Mat3 = Eigen::Matrix3d;
using test::BlockSpec;

constexpr double kE = 70e9, kNu = 0.3, kRho = 2700;

MaterialConfig corr_material(const std::string& law, double stabilization, InfluenceKind omega = InfluenceKind::constant) {
  MaterialConfig m = test::make_material("correspondence", kE, kNu, kRho, omega);
  m.choices["stress_law"] = law;
  m.parameters["stabilization"] = stabilization;
  if (law == "j2") {
    m.parameters["yield_stress"] = 200e6;
    m.parameters["hardening_modulus"] = 1e9;
  }
  fill_model_defaults(m);
  return m;
}

correspondence::LawSettings law_of(const MaterialConfig& m, int d, PlaneMode plane) {
  correspondence::LawSettings s;
  const std::string& law = m.choices.at("stress_law");
  s.law = law == "neo_hookean" ? correspondence::StressLaw::neo_hookean
          : law == "j2"        ? correspondence::StressLaw::j2
                               : correspondence::StressLaw::linear_elastic;
  s.elastic = classical::elastic_from_bulk_shear(m.bulk_modulus, m.shear_modulus);
  s.j2 = {m.parameters.at("yield_stress"), m.parameters.at("hardening_modulus")};
  s.dimension = d;
  s.plane = plane;
  return s;
}

// sum_k T_k (x) xi_k V_k over particle i's bonds: P_i exactly (seed 003 digest sec. 13
// check 5; the stabilisation adds nothing to it).
Mat3 collapsed_stress(const System& s, std::size_t i) {
  Mat3 S = Mat3::Zero();
  const auto& B = s.bonds;
  for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
    if (!B.intact[k]) continue;
    const Vec3& T = s.model.force_state[k];
    const Vec3 xi = s.particles.X[B.nbr[k]] - s.particles.X[i];
    S += B.volume[k] * correspondence::to_eigen(T) * correspondence::to_eigen(xi).transpose();
  }
  return S;
}

// Lattice distance of every particle to the nearest face of the block, in spacings.
std::vector<double> depths(const System& s, const BlockSpec& b) {
  const int dim = b.dimension;
  const double h = b.spacing, last[3] = {b.n[0] - 1.0, b.n[1] - 1.0, b.n[2] - 1.0};
  std::vector<double> out(s.particles.size(), 1e300);
  for (std::size_t i = 0; i < out.size(); ++i)
    for (int k = 0; k < dim; ++k) {
      const double index = s.particles.X[i][k] / h;
      out[i] = std::min({out[i], index, last[k] - index});
    }
  return out;
}

// --- patch test -----------------------------------------------------------------------

// A homogeneous deformation (stretch + shear + rotation, F below) of a block with partial
// volumes: at every particle at least one horizon from the faces the model's stress
// (the collapsed stress of its force states) is the classical law's P(F) to 1e-10
// (relative), its energy density the law's W, and two horizons in the force density
// vanishes (1e-10 of |P|/h). 3-D and 2-D plane strain and plane stress; the three laws
// (j2 beyond yield: the stretch is 0.6 %, yield at 0.29 %).
TEST(Correspondence, PatchTestReproducesClassicalStress) {
  test::SingleThread one;
  struct Case {
    int d;
    PlaneMode plane;
  };
  for (const Case c : {Case{3, PlaneMode::none}, Case{2, PlaneMode::strain}, Case{2, PlaneMode::stress}}) {
    BlockSpec b;
    b.dimension = c.d;
    b.plane = c.plane;
    if (c.d == 3) {
      b.n = {13, 13, 13};
    } else {
      b.n = {15, 15, 1};
    }
    b.partial_volume = true;
    Mat3 Fa;
    if (c.d == 3)
      Fa = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix() *
           (Mat3() << 1.006, 0.002, 0.0, 0.0, 0.998, 0.001, 0.0015, 0.0, 1.001).finished();
    else
      Fa = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix() *
           (Mat3() << 1.006, 0.002, 0.0, 0.001, 0.998, 0.0, 0.0, 0.0, 1.0).finished();
    for (const char* law : {"linear_elastic", "neo_hookean", "j2"}) {
      const MaterialConfig mat = corr_material(law, 0.1);
      System s = test::make_block(b, mat);
      for (std::size_t i = 0; i < s.particles.size(); ++i) {
        const Eigen::Vector3d X = correspondence::to_eigen(s.particles.X[i]);
        s.particles.u[i] = correspondence::to_vec3(Fa * X - X + Eigen::Vector3d(1e-4, -2e-4, 0));
      }
      compute_forces(s, true);
      correspondence::History h0, h1;
      double work = 0;
      const classical::LawResult exact = correspondence::evaluate_law(law_of(mat, c.d, c.plane), Fa, h0, h1, work);
      if (std::string(law) == "j2") {
        EXPECT_GT(h1.plastic.alpha, 0) << "beyond yield";
      }
      const double delta = b.horizon_factor;
      const std::vector<double> depth = depths(s, b);
      int checked = 0;
      for (std::size_t i = 0; i < s.particles.size(); ++i) {
        if (depth[i] < delta) continue;
        const Mat3 P = collapsed_stress(s, i);
        EXPECT_LT((P - exact.P).topLeftCorner(c.d, c.d).norm(), 1e-10 * exact.P.norm()) << law << " " << i;
        EXPECT_NEAR(s.particles.energy[i], exact.W, 1e-10 * exact.W) << law << " " << i;
        if (depth[i] >= 2 * delta) {
          EXPECT_LT(norm(s.particles.f[i]), 1e-10 * exact.P.norm() / b.spacing) << law << " " << i;
        }
        ++checked;
      }
      EXPECT_GT(checked, 0);
    }
  }
}

}  // namespace
}  // namespace horizon::verification
