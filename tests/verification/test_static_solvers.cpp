// Static and implicit solvers (docs/verification.md, "Static and implicit solvers"):
// - the 3-D LPS block of examples/block_tension_static.yaml solved by Newton and by ADR:
//   the same displacements, and the interior's Young's modulus and Poisson's ratio;
// - Newton's quadratic convergence on an elastic problem (residual ratios);
// - step cutting and quasi-static bond breaking on a small notched plate.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <omp.h>

#include "horizon/solver/forces.hpp"
#include "horizon/solver/static_driver.hpp"
#include "../single_thread.hpp"
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

// One OpenMP thread for these small problems (tests/single_thread.hpp).
using OneThread = test::SingleThread;

double max_abs_u(const System& s) {
  double m = 0;
  for (const auto& u : s.particles.u) m = std::max({m, std::abs(u.x), std::abs(u.y), std::abs(u.z)});
  return m;
}

// The interior moduli of the block of examples/block_tension_static.yaml: strains from
// the displacement gradient of the particles more than a horizon from every surface,
// stress from the force flux through the interior square of the mid-plane (as
// test_uniaxial_tension.cpp). Reports both under `name`.
std::pair<double, double> interior_moduli(const System& s, const Config& deck, const std::string& name) {
  const double E = deck.materials.at(0).youngs_modulus, nu = deck.materials.at(0).poissons_ratio;
  const auto& P = s.particles;
  const Box3 box = deck.bodies.at(0).shape.bounds();
  const double d = s.horizon;
  std::vector<std::size_t> interior;
  for (std::size_t i = 0; i < P.size(); ++i) {
    bool inside = true;
    for (int k = 0; k < 3; ++k) inside = inside && P.X[i][k] > box.min[k] + d && P.X[i][k] < box.max[k] - d;
    if (inside) interior.push_back(i);
  }
  std::size_t expected = 1;  // 14 x 4 x 4 in the example's block
  for (int k = 0; k < 3; ++k) expected *= static_cast<std::size_t>(std::lround((box.max[k] - box.min[k] - 2 * d) / s.spacing));
  EXPECT_EQ(interior.size(), expected);
  const Eigen::Matrix3d G = displacement_gradient(P, interior);
  const double lo = box.min.y + d, hi = box.max.y - d;
  const Vec3 F = force_through_patch(s, 0, 0.5 * (box.min.x + box.max.x), lo, hi);
  const double stress = F.x / ((hi - lo) * (hi - lo));
  const double E_int = stress / G(0, 0);
  const double nu_int = -0.5 * (G(1, 1) + G(2, 2)) / G(0, 0);
  report(name + "_youngs", E_int,
         fmt::format("LPS block ({}): interior E = {:.2f} GPa ({:+.2f} %), interior stress {:.2f} MPa", name,
                     E_int / 1e9, 100 * (E_int / E - 1), stress / 1e6));
  report(name + "_poisson", nu_int,
         fmt::format("LPS block ({}): interior nu = {:.4f} ({:+.2f} %)", name, nu_int, 100 * (nu_int / nu - 1)));
  return {E_int, nu_int};
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

  const auto [E_int, nu_int] = interior_moduli(newton.system, deck, "block_static");
  EXPECT_NEAR(E_int / E, 1.0, 0.02);
  EXPECT_NEAR(nu_int / nu, 1.0, 0.02);
}

// The same block with the LPS surface correction (material/models/lps.cpp): the end
// traction over the section's mean strain (the block's modulus as a whole, +18 %
// uncorrected: docs/verification.md check 2) comes within 2 % of E, and so do the interior
// moduli: measured +0.75 % and -1.19 % (with the lattice's interior particle as the
// reference of the deviatoric factor, before 2026-11-26: +2.22 % and -2.12 %).
TEST(StaticSolvers, SurfaceCorrectedLpsBlockKeepsItsInteriorModuli) {
  Config deck = load_deck(source_path("examples/block_tension_static.yaml"));
  deck.materials.at(0).parameters["surface_correction"] = 1;
  const double E = deck.materials.at(0).youngs_modulus, nu = deck.materials.at(0).poissons_ratio;
  StaticRun run(deck);
  ASSERT_TRUE(run.run()) << run.solver.failure();
  const auto [E_int, nu_int] = interior_moduli(run.system, deck, "block_corrected");
  const auto& P = run.system.particles;
  std::vector<std::size_t> middle;
  for (std::size_t i = 0; i < P.size(); ++i)
    if (P.X[i].x > 0.005 && P.X[i].x < 0.015) middle.push_back(i);
  const Eigen::Matrix3d G = displacement_gradient(P, middle);
  const double E_section = 2.0e7 / G(0, 0);
  report("block_corrected_section", E_section,
         fmt::format("LPS block, surface_correction: true: traction / section strain = {:.2f} GPa ({:+.2f} %)",
                     E_section / 1e9, 100 * (E_section / E - 1)));
  EXPECT_NEAR(E_section / E, 1.0, 0.02);
  EXPECT_NEAR(E_int / E, 1.0, 0.02);
  EXPECT_NEAR(nu_int / nu, 1.0, 0.02);
}

// The block of examples/block_tension_static.yaml resized to nx x ny x ny spacings, the
// supports and loaded end layers moved with it.
Config resized_block(int nx, int ny) {
  Config c = load_deck(source_path("examples/block_tension_static.yaml"));
  const double h = c.spacing, X = nx * h, Y = ny * h;
  c.bodies.at(0).shape = Shape::box({0, 0, 0}, {X, Y, Y});
  c.regions.at("left") = Shape::box({0, 0, 0}, {1.2 * h, Y, Y});
  c.regions.at("right") = Shape::box({X - 1.2 * h, 0, 0}, {X, Y, Y});
  c.regions.at("roller") = Shape::box({X - h, 0, 0}, {X, h, h});
  c.regions.at("guide") = Shape::box({0, Y - h, 0}, {h, Y, h});
  return c;
}

// Is the interior measurement of the 20 x 10 x 10 block biased by the block's size? Its
// interior box (14 x 4 x 4) lies within one horizon of the surface layers. The same
// measurement on a 40 x 20 x 20 block (16,000 particles; about 40 s per run on the shared
// machine, so out of `make test`: --gtest_also_run_disabled_tests
// --gtest_filter='StaticSolvers.DISABLED_LpsBlockInterior*'). Measured 2026-11-26
// (docs/verification.md "Surface correction"): plain +0.55 %, +0.68 % (the stiff surface
// layers still pull the interior: the lattice's own interior is +1.46 %, -0.97 %, test
// SurfaceCorrection.LpsLatticeInteriorModuli); corrected +0.18 %, -0.36 %.
TEST(StaticSolvers, DISABLED_LpsBlockInteriorModuliOnALargerBlock) {
  OneThread one;
  for (const bool corrected : {false, true}) {
    Config deck = resized_block(40, 20);
    deck.materials.at(0).parameters["surface_correction"] = corrected ? 1 : 0;
    const double E = deck.materials.at(0).youngs_modulus, nu = deck.materials.at(0).poissons_ratio;
    StaticRun run(deck);
    ASSERT_TRUE(run.run()) << run.solver.failure();
    const auto [E_int, nu_int] = interior_moduli(run.system, deck, corrected ? "block40_corrected" : "block40_plain");
    if (corrected) {
      EXPECT_NEAR(E_int / E, 1.0, 0.01);
      EXPECT_NEAR(nu_int / nu, 1.0, 0.01);
    }
  }
}

// Newton on the elastic problem: with the exact tangent and exact (Cholesky) solves, the
// residual falls quadratically, r_{k+1} ~ C r_k^2, until round-off (about 1e-13 here).
// A smaller LPS block at a large strain (2 %) keeps the geometric nonlinearity, and so
// several iterations, above round-off.
TEST(StaticSolvers, NewtonConvergesQuadratically) {
  OneThread one;
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

// examples/plate_with_hole.yaml: a square plane-stress PMB plate, 251 x 251 spacings, with
// a central hole of diameter one tenth of the width (radius 12.5 spacings, horizon 3), under
// a remote tension of 10 MPa. The stress concentration factor at the edge of the hole is
// measured from the strain of the bonds at the edge: on the ligament (y = 0) the columns of
// particles x = R + h/2, R + 3h/2, R + 5h/2 give eps_yy from their bonds to (x, +-h),
// sigma_yy = E eps_yy (sigma_xx = 0 on the free edge, plane stress), and the factor at the
// edge x = R is the quadratic through the three, extrapolated half a spacing (the same
// extrapolation of the classical Kirsch field gives 3.014 instead of 3.032: -0.6 %). The
// reference is 3.03 for d/W = 0.1 in a strip (Howland 1930; Pilkey, Peterson's Stress
// Concentration Factors, chart 4.1), 3.032 by Heywood's formula 2 + (1 - d/W)^3 over 1 - d/W.
// K_t of examples/plate_with_hole.yaml (as described above), reported under `name`.
double plate_hole_kt(const Config& deck, const std::string& name) {
  const double E = deck.materials.at(0).youngs_modulus, h = deck.spacing;
  const double sigma = (*deck.loads.at(0).value[1])(0);
  const double R = 0.0025, W = 0.0502;
  StaticRun run(deck);
  EXPECT_TRUE(run.run()) << run.solver.failure();
  const System& s = run.system;
  for (const char* load : {"x_mirror:displacement", "y_mirror:displacement"})
    EXPECT_LT(norm(run.reaction(load)), 1e-6 * sigma * W * deck.thickness) << load;

  auto find = [&](double x, double y) {
    for (std::size_t i = 0; i < s.particles.size(); ++i)
      if (std::abs(s.particles.X[i].x - x) < 1e-3 * h && std::abs(s.particles.X[i].y - y) < 1e-3 * h) return i;
    ADD_FAILURE() << "no particle at " << x << ", " << y;
    return std::size_t{0};
  };
  // Both edges (x = +-R) agree by symmetry; average them.
  double k[3] = {0, 0, 0};
  for (const double side : {-1.0, 1.0})
    for (int c = 0; c < 3; ++c) {
      const double x = side * (R + (c + 0.5) * h);
      const double eps = (s.particles.u[find(x, h)].y - s.particles.u[find(x, -h)].y) / (2 * h);
      k[c] += 0.5 * E * eps / sigma;
    }
  // Quadratic through r = R + h/2, 3h/2, 5h/2, evaluated at r = R (Newton's forward form at -1/2).
  const double kt = k[0] - 0.5 * (k[1] - k[0]) + 0.375 * (k[0] - 2 * k[1] + k[2]);
  const double reference = 3.03;
  report(name, kt,
         fmt::format("plate with hole (d/W = {:.4f}{}): Kt = {:.3f} at the edge ({:+.2f} % from {}); E eps_yy / sigma "
                     "at R + h/2, 3h/2, 5h/2: {:.3f}, {:.3f}, {:.3f}; {} Newton iterations",
                     2 * R / W, name == "plate_hole_kt" ? "" : ", surface_correction: true", kt,
                     100 * (kt / reference - 1), reference, k[0], k[1], k[2], run.solver.total_iterations()));
  return kt / reference;
}

TEST(StaticSolvers, PlateWithHoleStressConcentration) {
  EXPECT_NEAR(plate_hole_kt(load_deck(source_path("examples/plate_with_hole.yaml")), "plate_hole_kt"), 1.0, 0.05);
}

// The same with the PMB surface correction (material/models/pmb.cpp): K_t stays in its band
// (3.020, -0.33 %, docs/verification.md). Out of `make test` (it costs what the plate above costs,
// the largest static test of the suite); run it with build/tests/test_verification
// --gtest_also_run_disabled_tests --gtest_filter='StaticSolvers.DISABLED_PlateWithHole*'.
TEST(StaticSolvers, DISABLED_PlateWithHoleStressConcentrationWithSurfaceCorrection) {
  Config deck = load_deck(source_path("examples/plate_with_hole.yaml"));
  deck.materials.at(0).parameters["surface_correction"] = 1;
  EXPECT_NEAR(plate_hole_kt(deck, "plate_hole_kt_corrected"), 1.0, 0.05);
}

// A small edge-notched plate (2-D PMB, 40 x 20 particles) pulled apart under displacement
// control: the top layer moves up 1 um per load step, the bottom layer is held.
std::string notched_plate_deck(bool damage, int load_steps, const std::string& extra_solver_keys) {
  return fmt::format(R"(dimension: 2
plane: stress
thickness: 0.01
spacing: 5.0e-4
horizon_factor: 3
partial_volume: true
materials:
  solid: {{model: pmb, density: 2400, youngs_modulus: 30.0e9{damage}}}
bodies:
  - {{name: plate, material: solid, shape: {{box: {{min: [0, 0], max: [0.02, 0.01]}}}}}}
precracks:
  - {{from: [-0.0001, 0.005], to: [0.006, 0.005]}}
regions:
  top:    {{box: {{min: [0, 0.0095], max: [0.02, 0.01]}}}}
  bottom: {{box: {{min: [0, 0], max: [0.02, 0.0005]}}}}
  grips:  {{box: {{min: [0, 0], max: [0.02, 0.0015]}}}}
  grips2: {{box: {{min: [0, 0.0085], max: [0.02, 0.01]}}}}
no_fail_regions: [grips, grips2]
loads:
  - {{region: top,    displacement: [0, "1.0e-6*t"]}}
  - {{region: bottom, displacement: [0, 0]}}
solver: {{type: static, end_time: {steps}, load_steps: {steps}, linear_solver: cholesky{extra}}}
)",
                     fmt::arg("damage", damage ? ", damage: {fracture_energy: 100}" : ""), fmt::arg("steps", load_steps),
                     fmt::arg("extra", extra_solver_keys));
}

// Quasi-static fracture: at every load step bonds break, the plate re-equilibrates, and
// so on until no bond is overstretched. The load rises, peaks and falls as the crack
// runs across; the energy ledger stays balanced (the strain energy released on
// re-equilibration is booked as damped energy).
TEST(StaticSolvers, QuasiStaticBondBreakingUnderDisplacementControl) {
  OneThread one;
  StaticRun run(parse_deck(notched_plate_deck(true, 30, ", max_break_rounds: 1000"), "notched.yaml"));
  std::vector<double> load;
  while (!run.solver.done()) {
    ASSERT_TRUE(run.solver.advance()) << run.solver.failure();
    load.push_back(run.reaction("top:displacement").y);
    // Equilibrium holds with no bond left beyond its critical stretch.
    const System& s = run.system;
    for (std::size_t i = 0; i < s.particles.size(); ++i)
      for (uint64_t k = s.bonds.begin(i); k < s.bonds.end(i); ++k) {
        const uint32_t j = s.bonds.nbr[k];
        if (!s.bonds.intact[k] || s.particles.no_fail[i] || s.particles.no_fail[j]) continue;
        const double L = s.bonds.length[k];
        const double e = norm(s.particles.X[j] + s.particles.u[j] - s.particles.X[i] - s.particles.u[i]) - L;
        ASSERT_LE(e, std::min(s.model.critical_stretch[i], s.model.critical_stretch[j]) * L * (1 + 1e-12))
            << "an overstretched bond survived load step " << run.solver.steps();
      }
  }
  const std::size_t peak = static_cast<std::size_t>(std::max_element(load.begin(), load.end()) - load.begin());
  double dmax = 0;
  for (double d : run.system.particles.damage) dmax = std::max(dmax, d);
  const Ledger& g = run.solver.ledger();
  report("notched_plate_peak", load[peak],
         fmt::format("notched plate: peak load {:.1f} N at step {} of {}, final {:.1f} N; {} bonds broken, max damage "
                     "{:.2f}; energy: work {:.4e} J = strain {:.4e} + dissipated {:.4e} + released {:.4e} (balance "
                     "{:.1e})",
                     load[peak], peak + 1, load.size(), load.back(), run.system.broken, dmax, g.external_work, g.strain,
                     g.dissipated, g.damped, g.balance_error()));
  EXPECT_GT(peak, 2u);
  EXPECT_LT(peak + 3, load.size());
  EXPECT_LT(load.back(), 0.5 * load[peak]);
  EXPECT_GT(dmax, 0.3);
  EXPECT_GT(g.dissipated, 0);
  EXPECT_LT(std::abs(g.balance_error()), 1e-3);
}

// The same plate with the elastic-plastic model (plane strain; it yields before bonds
// break): the plastic work done while the plate re-settles after bonds break is the
// model's to dissipate at its commit, not released energy too (static_driver.cpp), so the
// ledger still closes.
TEST(StaticSolvers, QuasiStaticBreakingWithPlasticityKeepsTheLedger) {
  OneThread one;
  std::string deck = notched_plate_deck(true, 6, ", max_break_rounds: 1000");
  deck.replace(deck.find("plane: stress"), 13, "plane: strain");
  deck.replace(deck.find("spacing: 5.0e-4"), 15, "spacing: 1.0e-3");  // 20 x 10 particles
  const std::string pmb = "model: pmb, density: 2400, youngs_modulus: 30.0e9";
  deck.replace(deck.find(pmb), pmb.size(),
               "model: elastic_plastic, density: 2400, youngs_modulus: 30.0e9, poissons_ratio: 0.2, "
               "yield_stress: 15.0e6");
  deck.replace(deck.find("1.0e-6*t"), 8, "5.0e-6*t");
  StaticRun run(parse_deck(deck, "notched_plastic.yaml"));
  while (!run.solver.done()) ASSERT_TRUE(run.solver.advance()) << run.solver.failure();
  const Ledger& g = run.solver.ledger();
  report("notched_plastic_balance", g.balance_error(),
         fmt::format("notched plastic plate: {} bonds broken; work {:.4e} J = strain {:.4e} + dissipated {:.4e} + "
                     "released {:.4e} (balance {:.1e})",
                     run.system.broken, g.external_work, g.strain, g.dissipated, g.damped, g.balance_error()));
  EXPECT_GT(run.system.broken, 0u);
  EXPECT_GT(g.dissipated, 0.2 * g.external_work);  // plasticity and breaking both dissipate
  EXPECT_LT(std::abs(g.balance_error()), 5e-3);  // measured 8.4e-4; 0.42 without the correction
}

// Step cutting: Newton limited to two iterations meets a tolerance only on small enough
// increments (its residual after two iterations falls like the square of the increment,
// through the geometric nonlinearity). The solver halves the increments that fail and
// still ends at the same equilibrium (to the tolerance).
TEST(StaticSolvers, StepCuttingRecoversFromFailedIncrements) {
  OneThread one;
  StaticRun reference(parse_deck(notched_plate_deck(false, 2, ", tolerance: 1.0e-10"), "ref.yaml"));
  ASSERT_TRUE(reference.run()) << reference.solver.failure();
  // Newton's residual after two iterations on the full first increment.
  StaticRun probe(parse_deck(notched_plate_deck(false, 2, ", max_iterations: 2, max_step_cuts: 0, tolerance: 1.0e-14"), "probe.yaml"));
  EXPECT_FALSE(probe.solver.advance());
  const double r2 = probe.solver.last_report().residual;
  ASSERT_GT(r2, 1e-10);
  const double tolerance = r2 / 3;
  const std::string keys = fmt::format(", max_iterations: 2, tolerance: {:.6e}, max_step_cuts: 4", tolerance);
  StaticRun cut(parse_deck(notched_plate_deck(false, 2, keys), "cut.yaml"));
  ASSERT_TRUE(cut.run()) << cut.solver.failure();
  double diff = 0;
  for (std::size_t i = 0; i < cut.system.particles.size(); ++i)
    diff = std::max(diff, norm(cut.system.particles.u[i] - reference.system.particles.u[i]));
  const double rel = diff / max_abs_u(reference.system);
  report("step_cuts", cut.solver.total_cuts(),
         fmt::format("step cutting: residual {:.2e} after two Newton iterations on the full increment; with tolerance "
                     "{:.2e}: {} cuts, {} increments for 2 load steps; max |u - u_ref| / max |u_ref| = {:.1e}",
                     r2, tolerance, cut.solver.total_cuts(), cut.solver.steps(), rel));
  EXPECT_GE(cut.solver.total_cuts(), 1);
  EXPECT_GT(cut.solver.steps(), 2);
  EXPECT_DOUBLE_EQ(cut.solver.lambda(), 1.0);
  EXPECT_LT(rel, 10 * tolerance);
}

}  // namespace
}  // namespace horizon::verification
