// J2-plastic finite elements (fe/fe_region.hpp with the classical small-strain J2 law of
// classical/strain_laws.hpp). Checked here, on a bar 10 x 2 x 2 mm of hex8 or tet4
// elements (nodes on the box faces) pulled quasi-statically at one end and let back:
// - the stress-strain curve follows the uniaxial J2 curve with linear hardening,
//   sigma = E eps below sigma_y, sigma_y + E_t (eps - sigma_y/E) above it, with the
//   tangent E_t = E H / (E + H) (Simo and Hughes 1998, "Computational Inelasticity",
//   sec. 1.4, eq. 1.4.15), within 1 %;
// - unloading is elastic and the bar carries no force at the residual strain
//   eps_max - sigma_max / E, within 1 %;
// - the energy ledger closes (1e-3) with the plastic work as dissipation, which equals
//   V (sigma_y alpha + H alpha^2 / 2) (the work of the flow stress over alpha), and the
//   mean equivalent plastic strain is the residual strain;
// - the FE bar and a correspondence-J2 peridynamic strip (static Newton, the strip of
//   tests/verification/test_correspondence.cpp) give the same stress at the same strain.
// - a checkpoint written mid-run restores the plastic history: the run continues
//   bit-identically.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "../single_thread.hpp"
#include "horizon/core/error.hpp"
#include "horizon/deck/deck.hpp"
#include "horizon/driver/run.hpp"
#include "horizon/fe/fe_region.hpp"
#include "horizon/loading/loads.hpp"
#include "horizon/solver/static_driver.hpp"
#include "verification_support.hpp"

namespace horizon::verification {
namespace {

constexpr double kE = 70e9, kNu = 0.25, kSy = 200e6, kH = 1e9;
constexpr double kL = 10e-3, kA = 4e-6;
// Load to eps1 in T1 (displacement U1 sin^2(pi t / (2 T1)): no jump in velocity), then
// back by eps2 in T2 (eps2 < 2 sigma_max / E: no reverse yield).
constexpr double kEps1 = 8e-3, kT1 = 100e-6, kT2 = 50e-6;

double tangent() { return kE * kH / (kE + kH); }
double uniaxial(double eps) { return eps < kSy / kE ? kE * eps : kSy + tangent() * (eps - kSy / kE); }
double sigma_max() { return uniaxial(kEps1); }
double eps2() { return 1.5 * sigma_max() / kE; }

// `core`: a peridynamic body (elastic PMB, no damage) across the bar's middle third, so
// the elements around it couple to it (fe/fe_region.hpp) while the rest yield.
std::string bar_deck(const char* element, const std::string& output = "", bool core = false) {
  const double U1 = kEps1 * kL, U2 = eps2() * kL;
  return fmt::format(R"deck(
dimension: 3
spacing: 1.0e-3
horizon: 3.0e-3
lattice_origin: [0, 0, 0]
materials:
  al: {{model: pmb, density: 2700, youngs_modulus: {E}}}
bodies:
{core}  - {{name: bar, material: al, discretization: fe, element: {el}, j2: {{yield_stress: {sy}, hardening_modulus: {H}}},
     shape: {{box: {{min: [0, 0, 0], max: [{L}, 2.0e-3, 2.0e-3]}}}}}}
regions:
  left: {{box: {{min: [-1, -1, -1], max: [0.5e-3, 1, 1]}}}}
  right: {{box: {{min: [9.5e-3, -1, -1], max: [1, 1, 1]}}}}
loads:
  - {{region: left, displacement: [0, null, null]}}
  - {{region: right, displacement: ["t < {T1} ? {U1}*sin(pi*t/(2*{T1}))^2 : {U1} - {U2}*sin(pi*(t-{T1})/(2*{T2}))^2",
     null, null]}}
solver: {{end_time: {end}, safety_factor: 0.8}}
{out}
)deck",
                     fmt::arg("E", kE), fmt::arg("el", element), fmt::arg("sy", kSy), fmt::arg("H", kH),
                     fmt::arg("L", kL), fmt::arg("T1", kT1), fmt::arg("U1", U1), fmt::arg("U2", U2),
                     fmt::arg("T2", kT2), fmt::arg("end", kT1 + kT2), fmt::arg("out", output),
                     fmt::arg("core", core ? "  - {name: core, material: al, shape: {box: {min: [3.5e-3, 0, 0], max: "
                                             "[6.5e-3, 2.0e-3, 2.0e-3]}}}\n"
                                           : ""));
}

struct BarRun {
  std::vector<double> eps, sigma;  // per step: end strain, bar stress (left reaction / A)
  double max_balance_error = 0, worst_at = 0, final_balance_error = 0;
  double max_coupling_work = 0;  // largest |FeRegion::coupling_work| [J]
  double max_balance_without_coupling = 0;  // the ledger's balance less W_c, largest |.| past strain 1e-4
  double dissipated = 0;
  double alpha_max = 0;   // largest equivalent plastic strain of an element
  double alpha_mean = 0;  // volume average
  std::size_t elements = 0;
};

BarRun run_bar(const char* element, bool core = false) {
  test::SingleThread one;
  Simulation sim(parse_deck(bar_deck(element, "", core), "j2_bar.yaml"));
  BarRun r;
  r.elements = sim.system.fe->elements();
  const AppliedLoad* left = nullptr;
  for (const auto& L : sim.loads.loads())
    if (L.name.rfind("left", 0) == 0) left = &L;
  const std::size_t probe = sim.nearest({kL, 1e-3, 1e-3});
  while (sim.solver->time() < sim.config.solver.end_time) {
    sim.solver->step(true);
    r.eps.push_back(sim.system.particles.u[probe].x / kL);
    r.sigma.push_back(-left->reaction.x / kA);
    const double be = std::abs(sim.solver->ledger().balance_error());
    // Over the first steps the energies are round-off small and so is the scale of the
    // relative error: counted once the strain passes 1e-4 (measured: 5e-2 at 2e-8).
    if (r.eps.back() > 1e-4 && be > r.max_balance_error) r.max_balance_error = be, r.worst_at = r.eps.back();
    r.final_balance_error = be;
    const Ledger& g = sim.solver->ledger();
    r.max_coupling_work = std::max(r.max_coupling_work, std::abs(sim.system.fe->coupling_work));
    const double scale = std::max({std::abs(g.initial), std::abs(g.external_work), std::abs(g.coupling_work),
                                   g.kinetic + g.strain + g.dissipated + g.damped, 1e-300});
    if (r.eps.back() > 1e-4)
      r.max_balance_without_coupling = std::max(r.max_balance_without_coupling, std::abs(g.balance_error() + g.coupling_work / scale));
  }
  r.dissipated = sim.system.dissipated();
  for (std::size_t e = 0; e < r.elements; ++e) {
    r.alpha_max = std::max(r.alpha_max, sim.system.fe->plastic_strain(e));
    r.alpha_mean += sim.system.fe->plastic_strain(e) * sim.system.fe->volume[e] / (kA * kL);
  }
  return r;
}

void check_bar(const char* element) {
  const BarRun r = run_bar(element);
  ASSERT_GT(r.eps.size(), 100u);
  // Loading branch: the stress at strains through the elastic and the plastic range.
  double worst = 0;
  std::string where;
  std::size_t peak = 0;
  for (std::size_t k = 0; k < r.eps.size(); ++k)
    if (r.eps[k] > r.eps[peak]) peak = k;
  for (double target : {1.0e-3, 2.0e-3, 3.5e-3, 5.0e-3, 6.5e-3, 7.9e-3}) {
    std::size_t k = 0;
    while (k + 1 < peak && r.eps[k + 1] < target) ++k;
    const double t = (target - r.eps[k]) / (r.eps[k + 1] - r.eps[k]);
    const double s = r.sigma[k] + t * (r.sigma[k + 1] - r.sigma[k]);
    const double err = s / uniaxial(target) - 1;
    where += fmt::format(" {:.1e}: {:.2f} MPa ({:+.2e})", target, s / 1e6, err);
    worst = std::max(worst, std::abs(err));
  }
  // Unloading branch: the strain where the force crosses zero.
  double residual = NAN;
  for (std::size_t k = peak; k + 1 < r.eps.size(); ++k)
    if (r.sigma[k] > 0 && r.sigma[k + 1] <= 0) {
      const double t = r.sigma[k] / (r.sigma[k] - r.sigma[k + 1]);
      residual = r.eps[k] + t * (r.eps[k + 1] - r.eps[k]);
      break;
    }
  const double residual_exact = kEps1 - sigma_max() / kE;
  // alpha at the peak = the residual plastic strain; plastic work V (sigma_y a + H a^2/2).
  const double alpha = residual_exact;
  const double work = kA * kL * (kSy * alpha + 0.5 * kH * alpha * alpha);
  report(fmt::format("fe_j2_bar_{}", element), worst,
         fmt::format("J2 {} bar ({} elements), E {:.0f} GPa, sigma_y {:.0f} MPa, H {:.0f} GPa (E_t {:.4f} GPa): "
                     "stress vs the uniaxial curve at strain{}; residual strain {:.5e} vs {:.5e} ({:+.2e}); "
                     "dissipated {:.5e} J vs {:.5e} ({:+.2e}); eps_p mean {:.5e}, max {:.5e}; largest balance error past strain 1e-4 {:.1e} "
                     "(at strain {:.1e}), at the end {:.1e}",
                     element, r.elements, kE / 1e9, kSy / 1e6, kH / 1e9, tangent() / 1e9, where, residual,
                     residual_exact, residual / residual_exact - 1, r.dissipated, work, r.dissipated / work - 1,
                     r.alpha_mean, r.alpha_max, r.max_balance_error, r.worst_at, r.final_balance_error));
  EXPECT_LT(worst, 0.01);
  EXPECT_NEAR(residual / residual_exact, 1.0, 0.01);
  EXPECT_NEAR(r.dissipated / work, 1.0, 0.01);
  EXPECT_NEAR(r.alpha_mean / alpha, 1.0, 0.01);
  EXPECT_LT(r.max_balance_error, 1e-3);
  // Elements alone have no interface: nothing is booked as coupling work, so the plastic
  // work is checked by the ledger itself (it once lagged a step behind here: issue 33).
  EXPECT_EQ(r.max_coupling_work, 0.0);
}

TEST(FePlasticity, Hex8BarFollowsTheJ2CurveAndUnloadsElastically) { check_bar("hex8"); }
TEST(FePlasticity, Tet4BarFollowsTheJ2CurveAndUnloadsElastically) { check_bar("tet4"); }

// The bar with a peridynamic core (bar_deck's `core`): the elements on either side yield
// while the force-based coupling does work at the interface. The ledger books that work
// (Ledger::coupling_work) from the interface set alone, with U + D read after the step's
// plastic commit, so it closes as the pure-FE bar's does while the elements dissipate;
// without W_c it does not (the coupling's work is the interface's, not the plastic work).
TEST(FePlasticity, CoupledBarBooksTheInterfaceWorkAndThePlasticWorkOnce) {
  const BarRun r = run_bar("hex8", true);
  const double work_scale = kA * kL * kSy * (kEps1 - sigma_max() / kE);  // the plastic work's order
  report("fe_j2_coupled_balance", r.max_balance_error,
         fmt::format("J2 hex8 bar with a PMB core (x 3.5 to 6.5 mm): dissipated {:.4e} J (plastic work of the "
                     "whole bar by the uniaxial curve {:.4e} J); largest |coupling work| {:.3e} J; largest "
                     "|balance error| past strain 1e-4 {:.1e} with W_c booked, {:.1e} without; at the end {:.1e}",
                     r.dissipated, work_scale, r.max_coupling_work, r.max_balance_error,
                     r.max_balance_without_coupling, r.final_balance_error));
  EXPECT_GT(r.dissipated, 0.3 * work_scale);  // the elements yield
  EXPECT_GT(r.max_coupling_work, 0.0);
  EXPECT_LT(r.max_balance_error, 1e-3);
}

// The correspondence-J2 strip of tests/verification/test_correspondence.cpp (plane
// stress, 27 x 7 mm, h = 1 mm, delta = 3h, static Newton) stretched to `strain`: the
// nominal stress (right reaction / section).
double correspondence_strip(double strain) {
  const std::string deck = strip_deck(
      fmt::format("model: correspondence, stress_law: j2, stabilization: 0.1, density: 2700, youngs_modulus: {}, "
                  "poissons_ratio: {}, yield_stress: {}, hardening_modulus: {}",
                  kE, kNu, kSy, kH),
      strain, 4);
  const Config config = parse_deck(deck, "strip.yaml");
  System system = build_system(config);
  Loads loads(config, system);
  StaticSolver solver(system, loads, config.solver);
  loads.apply_initial_conditions(config, system);
  solver.initialize();
  while (!solver.done())
    if (!solver.advance()) {
      ADD_FAILURE() << solver.failure();
      return NAN;
    }
  for (const auto& L : loads.loads())
    if (L.name.rfind("right", 0) == 0) return L.reaction.x / (7e-3 * config.thickness);
  return NAN;
}

TEST(FePlasticity, FeBarAndCorrespondenceStripAgree) {
  test::SingleThread one;
  const BarRun fe = run_bar("hex8");
  const double strain = 5e-3;
  std::size_t k = 0;
  while (fe.eps[k + 1] < strain) ++k;
  const double t = (strain - fe.eps[k]) / (fe.eps[k + 1] - fe.eps[k]);
  const double s_fe = fe.sigma[k] + t * (fe.sigma[k + 1] - fe.sigma[k]);
  const double s_pd = correspondence_strip(strain);
  report("fe_j2_vs_correspondence", s_fe / s_pd - 1,
         fmt::format("J2 at strain {:.1e}: hex8 bar {:.3f} MPa, correspondence strip (nominal) {:.3f} MPa ({:+.2e}); "
                     "small-strain curve {:.3f} MPa",
                     strain, s_fe / 1e6, s_pd / 1e6, s_fe / s_pd - 1, uniaxial(strain) / 1e6));
  EXPECT_NEAR(s_fe / s_pd, 1.0, 0.01);
}

// A checkpoint taken in the plastic range (step 600 of about 1400) restores the elements'
// plastic history: the restarted run writes the same history.csv bytes (reactions,
// energies, dissipation) as the straight one.
TEST(FePlasticity, RestartContinuesThePlasticHistoryBitForBit) {
  namespace fs = std::filesystem;
  const Config c = parse_deck(bar_deck("hex8", "output: {frames: 2, history_every: 20, checkpoint: {every: 600}}"),
                              "j2_restart.yaml");
  auto quiet_in = [](const std::string& name) {
    RunOptions o;
    o.quiet = true;
    o.handle_signals = false;
    o.output_dir = output_dir(name).string();
    return o;
  };
  RunOptions a = quiet_in("fe_j2_restart_straight");
  ExplicitRun straight(c, a);
  straight.advance(std::numeric_limits<int64_t>::max());
  ASSERT_EQ(straight.finish(), 0);
  RunOptions b = quiet_in("fe_j2_restart");
  {
    ExplicitRun killed(c, b);
    killed.advance(700);
  }
  b.restart = (fs::path(*b.output_dir) / "checkpoint.hzc").string();
  ExplicitRun restarted(c, b);
  EXPECT_EQ(restarted.steps(), 600);
  restarted.advance(std::numeric_limits<int64_t>::max());
  ASSERT_EQ(restarted.finish(), 0);
  EXPECT_EQ(straight.history_csv(), restarted.history_csv());
}

// Deck errors for the j2 key: deck name, line:column and what was expected.
TEST(FePlasticity, DeckErrorsNameTheKey) {
  auto fails_with = [](const std::string& text, const std::string& expected) {
    try {
      parse_deck(text, "bad.yaml");
      ADD_FAILURE() << "no error; expected " << expected;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  };
  const std::string head =
      "dimension: 3\nspacing: 1.0e-3\nhorizon: 3.0e-3\nmaterials:\n  al: {model: pmb, density: 2700, "
      "youngs_modulus: 68.9e9}\nbodies:\n";
  const std::string box = "shape: {box: {min: [0, 0, 0], max: [4e-3, 4e-3, 4e-3]}}";
  fails_with(head + "  - {name: a, material: al, j2: {yield_stress: 2e8}, " + box + "}\nsolver: {end_time: 1e-6}\n",
             "bad.yaml:7:29: error: bodies[0].j2: applies to finite-element bodies only (discretization: fe)");
  fails_with(head + "  - {name: a, material: al, discretization: fe, j2: {hardening_modulus: 1e9}, " + box +
                 "}\nsolver: {end_time: 1e-6}\n",
             "yield_stress");
  fails_with(head + "  - {name: a, material: al, discretization: fe, j2: {yield_stress: -1}, " + box +
                 "}\nsolver: {end_time: 1e-6}\n",
             "bad.yaml:7:68");
}

}  // namespace
}  // namespace horizon::verification
