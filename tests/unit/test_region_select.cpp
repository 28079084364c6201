// Regions that survive coarsening (geometry/region_select.hpp; docs/input.md, "Regions"):
// a box that holds no particle selects the nearest lattice layer(s); one that holds any
// selects exactly those; one farther than a spacing from every particle selects nothing.
// On a coarsened deck a traction strip one (fine) spacing thick still loads the boundary
// layer, with the total force T times the layer's area.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "horizon/deck/deck.hpp"
#include "horizon/driver/run.hpp"
#include "horizon/geometry/region_select.hpp"
#include "horizon/loading/loads.hpp"
#include "horizon/solver/build.hpp"
#include "horizon/state/system.hpp"
#include "../single_thread.hpp"

namespace horizon {
namespace {

// A 2-D square lattice, spacing 1, points at (i + 0.5, j + 0.5), i < 10, j < 4.
std::vector<Vec3> lattice() {
  std::vector<Vec3> X;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 10; ++i) X.push_back({i + 0.5, j + 0.5, 0});
  return X;
}

TEST(RegionSelect, ABoxHoldingParticlesSelectsExactlyThose) {
  const auto X = lattice();
  const auto ids = select_region(Shape::box({0, 3.4, 0}, {10, 4, 0}), X, 2, 1.0);
  ASSERT_EQ(ids.size(), 10u);
  for (uint32_t i : ids) EXPECT_EQ(X[i].y, 3.5);
}

TEST(RegionSelect, AStripBetweenRowsSelectsTheNearestRow) {
  const auto X = lattice();
  // Above the top row (3.5), 0.2 to 0.45 away: the top row.
  auto ids = select_region(Shape::box({0, 3.7, 0}, {10, 3.95, 0}), X, 2, 1.0);
  ASSERT_EQ(ids.size(), 10u);
  for (uint32_t i : ids) EXPECT_EQ(X[i].y, 3.5);
  // Between rows 1.5 and 2.5, nearer 2.5.
  ids = select_region(Shape::box({0, 2.0, 0}, {10, 2.3, 0}), X, 2, 1.0);
  ASSERT_EQ(ids.size(), 10u);
  for (uint32_t i : ids) EXPECT_EQ(X[i].y, 2.5);
  // Midway: both rows (a tie keeps both, whatever the order of the particles).
  ids = select_region(Shape::box({0, 1.9, 0}, {10, 2.1, 0}), X, 2, 1.0);
  EXPECT_EQ(ids.size(), 20u);
}

TEST(RegionSelect, APointBetweenNodesSelectsTheNearestNode) {
  const auto X = lattice();
  const auto ids = select_region(Shape::box({4.1, 1.2, 0}, {4.2, 1.3, 0}), X, 2, 1.0);
  ASSERT_EQ(ids.size(), 1u);
  EXPECT_EQ(X[ids[0]].x, 4.5);
  EXPECT_EQ(X[ids[0]].y, 1.5);
}

TEST(RegionSelect, ABoxFartherThanASpacingSelectsNothing) {
  const auto X = lattice();
  EXPECT_TRUE(select_region(Shape::box({0, 4.6, 0}, {10, 5, 0}), X, 2, 1.0).empty());
  EXPECT_TRUE(select_region(Shape::box({20, 0, 0}, {21, 4, 0}), X, 2, 1.0).empty());
  // Other shapes keep selecting what they contain.
  EXPECT_TRUE(select_region(Shape::sphere({4, 3.9, 0}, 0.3), X, 2, 1.0).empty());
}

// The glass-branching demo's load strips (one fine spacing thick, on the plate's edges),
// smaller: at --coarsen 3 the strips lie between the coarse rows.
const std::string kDeck = R"(dimension: 2
plane: stress
thickness: 1.0e-3
spacing: 2.5e-4
horizon: 1.0e-3
materials:
  glass: {model: pmb, density: 2440, youngs_modulus: 72.0e9}
bodies:
  - {name: plate, material: glass, shape: {box: {min: [-0.005, -0.002], max: [0.005, 0.002]}}}
regions:
  top:    {box: {min: [-0.005, 0.00175], max: [0.005, 0.002]}}
  bottom: {box: {min: [-0.005, -0.002], max: [0.005, -0.00175]}}
loads:
  - {region: top,    traction: [0, 2.0e6]}
  - {region: bottom, traction: [0, -2.0e6]}
solver: {type: explicit, end_time: 1e-6}
)";

TEST(RegionSelect, CoarsenedTractionStripLoadsTheBoundaryLayer) {
  test::SingleThread one;
  for (double coarsen : {1.0, 1.5, 2.0, 3.0, 4.0}) {
    Config c = parse_deck(kDeck, "strip.yaml");
    RunOptions o;
    o.coarsen = coarsen;
    apply_run_options(c, o);
    System s = build_system(c);
    const Loads loads(c, s);
    loads.apply_forces(s, 0);
    const auto& P = s.particles;
    double top = -1, bottom = 1;
    for (const Vec3& x : P.X) top = std::max(top, x.y), bottom = std::min(bottom, x.y);
    double up = 0, down = 0;
    std::size_t loaded = 0, row = 0;
    for (std::size_t i = 0; i < P.size(); ++i) {
      if (P.X[i].y == top) ++row;
      if (P.b[i].y == 0) continue;
      ++loaded;
      // Only the outermost rows are loaded, up on top and down at the bottom.
      EXPECT_TRUE(P.b[i].y > 0 ? P.X[i].y == top : P.X[i].y == bottom) << "coarsen " << coarsen;
      (P.b[i].y > 0 ? up : down) += P.b[i].y * P.volume[i];
    }
    EXPECT_EQ(loaded, 2 * row) << "coarsen " << coarsen;
    // The total force: T times the loaded layer's area (its particles' cells: row x h x
    // thickness), within a spacing of the plate's width at any coarsening.
    const double h = c.spacing;
    EXPECT_NEAR(up, 2.0e6 * static_cast<double>(row) * h * 1.0e-3, 1e-9 * up) << "coarsen " << coarsen;
    EXPECT_NEAR(down, -up, 1e-9 * up);
    EXPECT_NEAR(up, 2.0e6 * 0.01 * 1.0e-3, 2.0e6 * h * 1.0e-3) << "coarsen " << coarsen;
  }
}

// A traction spread over a region many layers deep (the load's depth counts the
// region's layers along its normal): on a lattice at (k + 1/2) h with h = 0.01 the
// coordinates' X / h sit on half integers, where rounding each one alone let
// neighbouring layers collide (100 layers counted 97, the force 3 % high).
TEST(RegionSelect, TractionDepthCountsEveryLayerOfAHalfOffsetLattice) {
  test::SingleThread one;
  const std::string deck = R"(dimension: 2
plane: stress
thickness: 1.0e-3
spacing: 0.01
horizon: 0.0301
materials:
  m: {model: pmb, density: 1000, youngs_modulus: 1.0e9}
bodies:
  - {name: plate, material: m, shape: {box: {min: [0, 0], max: [2, 1]}}}
loads:
  - {region: all, traction: [0, 5.0e6]}
solver: {type: explicit, end_time: 1e-6}
)";
  Config c = parse_deck(deck, "deep.yaml");
  System s = build_system(c);
  const Loads loads(c, s);
  loads.apply_forces(s, 0);
  const auto& P = s.particles;
  double ymin = 1, ymax = 0, force = 0;
  for (std::size_t i = 0; i < P.size(); ++i) {
    ymin = std::min(ymin, P.X[i].y), ymax = std::max(ymax, P.X[i].y);
    force += P.b[i].y * P.volume[i];
  }
  ASSERT_NEAR(ymin, 0.005, 1e-12);  // the lattice this test is about
  ASSERT_EQ(P.size(), 20000u);
  // Depth 100 h = 1: the total force is T times the plate's width times its thickness.
  EXPECT_NEAR(force, 5.0e6 * 2.0 * 1.0e-3, 1e-9 * force);
}

}  // namespace
}  // namespace horizon
