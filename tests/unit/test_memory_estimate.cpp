// The pre-build memory estimate (solver/memory_guard.hpp) against the particles and bonds
// a deck really builds: box bodies are counted exactly from the lattice and the family's
// lattice offsets, other shapes from their bounding box (an upper bound).
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "horizon/deck/deck.hpp"
#include "horizon/solver/memory_guard.hpp"
#include "horizon/solver/build.hpp"
#include "../single_thread.hpp"

namespace horizon {
namespace {

struct Counts {
  double particles, bonds;
};

Counts built(const Config& c) {
  const System s = build_system(c);
  return {static_cast<double>(s.particles.size()), static_cast<double>(s.bonds.size())};
}

// 2-D plate, 40 x 20 particles, horizon 3 spacings (28 neighbours inside).
const std::string k2d = R"(dimension: 2
plane: stress
thickness: 1.0e-3
spacing: 5.0e-4
horizon_factor: 3
materials:
  glass: {model: pmb, density: 2440, youngs_modulus: 72.0e9}
bodies:
  - {name: plate, material: glass, shape: {box: {min: [0, 0], max: [0.02, 0.01]}}}
solver: {type: explicit, end_time: 1e-6}
)";

// 3-D block, 12 x 10 x 8 particles, horizon 3.01 spacings (122 neighbours inside).
const std::string k3d = R"(dimension: 3
spacing: 1.0e-3
horizon: 3.01e-3
materials:
  steel: {model: lps, density: 8000, youngs_modulus: 190.0e9, poissons_ratio: 0.3}
bodies:
  - {name: block, material: steel, shape: {box: {min: [0, 0, 0], max: [0.012, 0.010, 0.008]}}}
solver: {type: explicit, end_time: 1e-6}
)";

TEST(MemoryEstimate, TwoDimensionalBondsWithinTenPercentOfTheBuiltOnes) {
  const test::SingleThread one;
  const Config c = parse_deck(k2d, "plate.yaml");
  const MemoryEstimate e = estimate_memory(c);
  const Counts n = built(c);
  EXPECT_EQ(n.particles, 800);
  EXPECT_NEAR(e.particles, n.particles, 0.1 * n.particles);
  EXPECT_NEAR(e.bonds, n.bonds, 0.1 * n.bonds) << "built " << n.bonds;
  std::printf("2-D plate: estimate %.0f particles %.0f bonds, built %.0f, %.0f\n", e.particles, e.bonds, n.particles,
              n.bonds);
  // The old estimate (pi (r + 1)^2 per particle of a 3-cell-wider box) was 2.6x too high.
  EXPECT_LT(e.bonds, 1.1 * n.bonds);
}

TEST(MemoryEstimate, ThreeDimensionalBondsWithinTenPercentOfTheBuiltOnes) {
  const test::SingleThread one;
  const Config c = parse_deck(k3d, "block.yaml");
  const MemoryEstimate e = estimate_memory(c);
  const Counts n = built(c);
  EXPECT_EQ(n.particles, 960);
  EXPECT_NEAR(e.particles, n.particles, 0.1 * n.particles);
  EXPECT_NEAR(e.bonds, n.bonds, 0.1 * n.bonds) << "built " << n.bonds;
  std::printf("3-D block: estimate %.0f particles %.0f bonds, built %.0f, %.0f\n", e.particles, e.bonds, n.particles,
              n.bonds);
  // An interior particle of this lattice has 122 neighbours within 3.01 spacings.
  EXPECT_EQ(family_offsets(3, 3.01).size(), 122u);
  EXPECT_EQ(family_offsets(2, 3.0).size(), 28u);
}

// Any other shape: the bounding box's count, never below what is built.
TEST(MemoryEstimate, OtherShapesAreBoundedByTheirBox) {
  const test::SingleThread one;
  std::string deck = k3d;
  deck.replace(deck.find("box: {min: [0, 0, 0], max: [0.012, 0.010, 0.008]}"),
               std::string("box: {min: [0, 0, 0], max: [0.012, 0.010, 0.008]}").size(),
               "cylinder: {from: [0, 0.005, 0.004], to: [0.012, 0.005, 0.004], radius: 0.004}");
  const Config c = parse_deck(deck, "rod.yaml");
  const MemoryEstimate e = estimate_memory(c);
  const Counts n = built(c);
  EXPECT_GE(e.particles, n.particles);
  EXPECT_GE(e.bonds, n.bonds);
  EXPECT_LT(e.bonds, 2.0 * n.bonds);
  std::printf("3-D rod: estimate %.0f particles %.0f bonds, built %.0f, %.0f\n", e.particles, e.bonds, n.particles,
              n.bonds);
}

}  // namespace
}  // namespace horizon
