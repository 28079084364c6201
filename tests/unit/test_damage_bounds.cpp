// Damage lies in [0, 1] exactly (docs/input.md, "History and summary"): a particle whose
// every bond is broken has damage 1, one whose bonds are all intact 0, bit for bit. The
// running intact sum of the force passes used to leave a rounding residue
// (1.0000000000000007 on the glass demo); a row whose bonds break now sums its intact
// bonds afresh (state/system.hpp intact_damage_weight). A plate whose right half is
// flung apart (every bond there breaks) and whose left half stays at rest (no bond
// breaks), in each force pass: bond-based and state-based, the SIMD and scalar loops and
// the general pass.
#include <gtest/gtest.h>

#include <string>

#include "horizon/deck/deck.hpp"
#include "horizon/loading/loads.hpp"
#include "horizon/solver/build.hpp"
#include "horizon/solver/explicit.hpp"
#include "horizon/solver/forces.hpp"
#include "../single_thread.hpp"

namespace horizon {
namespace {

std::string deck(const std::string& model) {
  return R"(dimension: 2
plane: stress
thickness: 1.0e-3
spacing: 2.5e-4
horizon: 7.5e-4
partial_volume: true
materials:
  glass: {model: )" +
         model + (model == "pmb" ? "" : ", poissons_ratio: 0.25") +
         R"(, density: 2440, youngs_modulus: 72.0e9, damage: {critical_stretch: 1.0e-3}}
bodies:
  - {name: plate, material: glass, shape: {box: {min: [-0.005, 0], max: [0.005, 0.0025]}}}
initial_conditions:
  - {velocity: ["x > 0.0015 ? 20000*(x - 0.0015) : 0", "x > 0.0015 ? 20000*y : 0"]}
solver: {end_time: 1.0e-5}
)";
}

struct Counts {
  std::size_t all_broken = 0, none_broken = 0, partly = 0;
};

Counts run_and_check(const std::string& model, KernelPath path) {
  set_kernel_path(path);
  const Config config = parse_deck(deck(model), model + ".yaml");
  System s = build_system(config);
  Loads loads(config, s);
  loads.apply_initial_conditions(config, s);
  ExplicitSolver solver(s, loads, 0.8 * stable_time_step(s), 0.0);
  solver.initialize();
  for (int step = 0; step < 60; ++step) solver.step(false);
  set_kernel_path(KernelPath::automatic);
  Counts c;
  const auto& B = s.bonds;
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    std::size_t intact = 0, bonds = 0;
    for (uint64_t k = B.begin(i); k < B.end(i); ++k, ++bonds) intact += B.intact[k] != 0;
    const double d = s.particles.damage[i];
    EXPECT_GE(d, 0.0) << model << " particle " << i;
    EXPECT_LE(d, 1.0) << model << " particle " << i;
    if (bonds > 0 && intact == 0) {
      EXPECT_EQ(d, 1.0) << model << " particle " << i << ": every bond broken";
      ++c.all_broken;
    } else if (intact == bonds) {
      EXPECT_EQ(d, 0.0) << model << " particle " << i << ": no bond broken";
      ++c.none_broken;
    } else {
      EXPECT_GT(d, 0.0);
      EXPECT_LT(d, 1.0);
      ++c.partly;
    }
  }
  return c;
}

TEST(DamageBounds, WholeFamiliesBrokenHaveDamageOneExactly) {
  test::SingleThread one;
  for (const char* model : {"pmb", "lps"})
    for (KernelPath path : {KernelPath::automatic, KernelPath::scalar, KernelPath::general}) {
      const Counts c = run_and_check(model, path);
      // The run does what the test needs: whole families broken, and untouched ones.
      EXPECT_GT(c.all_broken, 50u) << model;
      EXPECT_GT(c.none_broken, 50u) << model;
    }
}

}  // namespace
}  // namespace horizon
