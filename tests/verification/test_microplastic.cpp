// Proportional microplastic bonds (material/models/microplastic.hpp; seed 002 eq. 19-21):
// - one bond, driven through tension beyond yield, unloading, reverse yield in
//   compression and reloading: the force is c (s - sbar) on the elastic lines and
//   +-c s_Y on the plateaus, the plastic stretch the return map's, and the energy the
//   model books as dissipated is the plastic work c s_Y sum |d sbar| |xi| V_i V_j;
// - a 1-D bar pulled beyond yield under explicit dynamics: the ledger (kinetic + stored +
//   dissipated - external work) closes to the integrator's second-order error.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "horizon/material/models/microplastic.hpp"
#include "horizon/solver/forces.hpp"
#include "../single_thread.hpp"
#include "verification_support.hpp"

namespace horizon::verification {
namespace {

TEST(Microplastic, ReturnMapFollowsTheElasticPerfectlyPlasticLoop) {
  const double sy = 1e-3;
  double sbar = 0;
  // Tension beyond yield: sbar follows s - s_Y.
  sbar = microplastic_return(0.5 * sy, sbar, sy);
  EXPECT_EQ(sbar, 0.0);
  sbar = microplastic_return(3 * sy, sbar, sy);
  EXPECT_DOUBLE_EQ(sbar, 2 * sy);
  // Unloading inside the elastic range keeps it; reverse yield moves it down.
  EXPECT_DOUBLE_EQ(microplastic_return(1.5 * sy, sbar, sy), 2 * sy);
  EXPECT_DOUBLE_EQ(microplastic_return(-sy, sbar, sy), 0.0);
  // Critical stretch with the same work to break as an elastic bond breaking at s_e.
  const double se = 4e-3, s0 = microplastic_critical_stretch(se, sy);
  EXPECT_NEAR(sy * s0 - 0.5 * sy * sy, 0.5 * se * se, 1e-18);
  EXPECT_EQ(microplastic_critical_stretch(0.5 * sy, sy), 0.5 * sy);
}

const char* kOneBond = R"(
dimension: 1
area: 1.0e-4
spacing: 1.0e-3
horizon: 1.5e-3
materials:
  steel: {model: microplastic, density: 7800, youngs_modulus: 200.0e9, yield_stretch: 1.0e-3}
bodies:
  - {name: pair, material: steel, shape: {box: {min: [0], max: [2.0e-3]}}}
solver: {end_time: 1.0e-6}
)";

TEST(Microplastic, OneBondLoadUnloadReverse) {
  test::SingleThread one;
  Config config = parse_deck(kOneBond, "one_bond.yaml");
  System s = build_system(config);
  ASSERT_EQ(s.particles.size(), 2u);
  ASSERT_EQ(s.bonds.size(), 2u);
  const double sy = 1e-3, L = 1e-3;
  const double c = pmb_micromodulus(200e9, InfluenceKind::constant, {1, PlaneMode::none, 1, 1e-4, 1.5e-3});
  const double V = s.particles.volume[0];
  const double EA = c * V * V;  // the pair's truss stiffness (seed 002 eq. 47)
  // Stretches in units of s_Y: each step is wholly elastic or wholly plastic, so the
  // trapezoidal work the ledger uses is exact.
  const std::vector<double> path = {0.5, 1, 1.5, 2, 2.5, 3, 2.5, 2, 1.5, 1, 0.5, 0, -0.5, -1, -0.5, 0, 0.5, 1};
  double sbar = 0, moved = 0;
  for (double q : path) {
    const double stretch = q * sy;
    s.particles.u[1].x = stretch * L;
    compute_forces(s, true);
    const double force = s.particles.f[1].x * V;  // on the right particle: -c (s - sbar) V V
    const double next = microplastic_return(stretch, sbar, sy);
    moved += std::abs(next - sbar);
    sbar = next;
    EXPECT_NEAR(-force, EA * (stretch - sbar), 1e-6 * EA * sy) << "s = " << q << " s_Y";
    EXPECT_LE(std::abs(force), EA * sy * (1 + 1e-6));
    s.models[0].commit(s);
  }
  EXPECT_NEAR(moved, 4 * sy, 1e-15);
  // Plastic work: c s_Y per unit plastic stretch, over the bond's length.
  const double dissipated = s.dissipated_at[0] + s.dissipated_at[1];
  const double expected = EA * sy * moved * L;
  report("microplastic_one_bond", dissipated / expected - 1,
         fmt::format("one microplastic bond, 0 -> 3 s_Y -> -s_Y -> s_Y: dissipated {:.6e} J against c s_Y "
                     "sum|d sbar| L V^2 = {:.6e} J ({:+.1e})",
                     dissipated, expected, dissipated / expected - 1));
  EXPECT_NEAR(dissipated / expected, 1.0, 1e-6);
}

const char* kBar = R"(
dimension: 1
area: 1.0e-4
spacing: 1.0e-3
horizon: 3.0e-3
materials:
  steel: {model: microplastic, density: 7800, youngs_modulus: 200.0e9, yield_stretch: 1.0e-3}
bodies:
  - {name: bar, material: steel, shape: {box: {min: [0], max: [0.1]}}}
regions:
  left:  {box: {min: [0], max: [0.003]}}
  right: {box: {min: [0.097], max: [0.1]}}
loads:
  - {region: left,  velocity: [0]}
  - {region: right, velocity: ["t < 3.0e-5 ? 15 : 0"]}
solver: {end_time: 6.0e-5}
)";

// The balance error is the time integrator's: it falls fourfold when the step is halved.
TEST(Microplastic, LedgerClosesInAPlasticBar) {
  test::SingleThread one;
  auto run = [](double safety, Ledger& g) {
    Config config = parse_deck(kBar, "bar.yaml");
    config.solver.safety_factor = safety;
    Simulation sim(std::move(config));
    double worst = 0;
    const double end = sim.config.solver.end_time;
    while (sim.solver->time() < end - 1e-12 * end) {
      sim.solver->step(true);
      worst = std::max(worst, std::abs(sim.solver->ledger().balance_error()));
    }
    g = sim.solver->ledger();
    return worst;
  };
  Ledger g, g2;
  const double worst = run(0.5, g), worst2 = run(0.25, g2);
  report("microplastic_bar_ledger", worst,
         fmt::format("1-D microplastic bar pulled at 15 m/s for 30 us: dissipated {:.4e} J, external work {:.4e} J; "
                     "max |balance error| {:.1e} (safety 0.5), {:.1e} (0.25), ratio {:.2f}",
                     g.dissipated, g.external_work, worst, worst2, worst / worst2));
  EXPECT_GT(g.dissipated, 0.5 * g.external_work);
  EXPECT_LT(worst, 5e-3);
  EXPECT_GT(worst / worst2, 3.0);
  EXPECT_LT(worst / worst2, 5.0);
}

}  // namespace
}  // namespace horizon::verification
