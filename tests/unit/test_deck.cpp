// The deck reader: the demo deck parses into the expected Config, and every class of
// mistake is reported at the right line and column with a useful message.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <initializer_list>
#include <string>

#include "horizon/core/error.hpp"
#include "horizon/deck/deck.hpp"

namespace horizon {
namespace {

// The demo deck of the design, with every section present.
const char* const kDemoDeck = R"deck(dimension: 2
plane: stress
thickness: 1.0e-3
spacing: 2.5e-4
horizon: 1.0e-3
lattice_origin: [0, 0]
partial_volume: false
materials:
  glass:
    model: pmb
    density: 2440
    youngs_modulus: 72.0e9
    influence: constant
    damage: {critical_stretch: 2.7e-4}
bodies:
  - name: plate
    material: glass
    shape: {box: {min: [-0.05, -0.02], max: [0.05, 0.02]}}
precracks:
  - {from: [-0.05, 0.0], to: [0.0, 0.0]}
regions:
  top:    {box: {min: [-0.05, 0.0195], max: [0.05, 0.02]}}
  bottom: {box: {min: [-0.05, -0.02], max: [0.05, -0.0195]}}
  left:   {box: {min: [-0.05, -0.02], max: [-0.0495, 0.02]}}
  right:  {box: {min: [0.0495, -0.02], max: [0.05, 0.02]}}
  hole:   {disk: {center: [0.01, 0.0], radius: 0.002}}
no_fail_regions: [top, bottom]
initial_conditions:
  - {velocity: [0, "-20*min(t/1e-6,1)"]}
  - {region: hole, displacement: [1e-6, ~]}
loads:
  - {region: top, traction: [0, 2.0e6], normal: y}
  - {region: bottom, traction: [0, -2.0e6]}
  - {region: left, displacement: [0, null]}
  - {region: right, velocity: ["1e-3*t", null]}
  - {body_force: [0, -9.81e3]}
solver: {type: explicit, end_time: 43.0e-6, safety_factor: 0.8, time_step: 1e-8, damping: 0}
output: {directory: out/glass_branching, frames: 40, history_every: 10, progress_every: 0}
)deck";

// A small valid 2-D deck that the error tests below change one line of.
// Line numbers:  1 dimension, 2 plane, 3 spacing, 4 horizon_factor, 5 materials,
// 6 glass, 7 model, 8 density, 9 youngs_modulus, 10 bodies, 11 name, 12 material,
// 13 shape, 14 solver.
const char* const kSmallDeck = R"deck(dimension: 2
plane: stress
spacing: 1.0e-3
horizon_factor: 3
materials:
  glass:
    model: pmb
    density: 2440
    youngs_modulus: 72.0e9
bodies:
  - name: plate
    material: glass
    shape: {box: {min: [0, 0], max: [0.01, 0.01]}}
solver: {end_time: 1.0e-6}
)deck";

// kSmallDeck with line `line` (1-based) replaced by `text` (which may hold several lines).
std::string small_deck_with(int line, const std::string& text) {
  std::string deck = kSmallDeck, out;
  int n = 1;
  std::size_t start = 0;
  while (start < deck.size()) {
    const std::size_t end = deck.find('\n', start);
    const std::string current = deck.substr(start, end - start);
    out += (n == line ? text : current) + "\n";
    start = end + 1;
    ++n;
  }
  return out;
}

// Parses `deck`, expects a DeckError at line:column whose message holds every fragment.
void expect_error(const std::string& deck, int line, int column, std::initializer_list<std::string> fragments) {
  try {
    parse_deck(deck, "test.yaml");
    ADD_FAILURE() << "no error for deck:\n" << deck;
  } catch (const DeckError& e) {
    EXPECT_EQ(e.where().file, "test.yaml");
    EXPECT_EQ(e.where().line, line) << e.what();
    EXPECT_EQ(e.where().column, column) << e.what();
    for (const auto& f : fragments)
      EXPECT_NE(std::string(e.what()).find(f), std::string::npos) << "'" << f << "' not in: " << e.what();
    EXPECT_EQ(std::string(e.what()).rfind(
                  "test.yaml:" + std::to_string(line) + ":" + std::to_string(column) + ": error: ", 0),
              0u)
        << e.what();
  }
}

TEST(Deck, DemoDeckParses) {
  const Config c = parse_deck(kDemoDeck, "demo.yaml");
  EXPECT_EQ(c.deck_file, "demo.yaml");
  EXPECT_EQ(c.dimension, 2);
  EXPECT_EQ(c.plane, PlaneMode::stress);
  EXPECT_DOUBLE_EQ(c.thickness, 1.0e-3);
  EXPECT_DOUBLE_EQ(c.area, 1.0);
  EXPECT_DOUBLE_EQ(c.spacing, 2.5e-4);
  EXPECT_DOUBLE_EQ(c.horizon, 1.0e-3);
  ASSERT_TRUE(c.lattice_origin.has_value());
  EXPECT_EQ(c.lattice_origin->x, 0.0);
  EXPECT_FALSE(c.partial_volume);
  EXPECT_TRUE(c.warnings.empty());

  ASSERT_EQ(c.materials.size(), 1u);
  const MaterialConfig& m = c.materials[0];
  EXPECT_EQ(m.name, "glass");
  EXPECT_EQ(m.model, "pmb");
  EXPECT_DOUBLE_EQ(m.density, 2440);
  EXPECT_DOUBLE_EQ(m.youngs_modulus, 72.0e9);
  // Bond-based in plane stress: nu = 1/3, so k = E / (3 (1 - 2 nu)) = E and
  // mu = E / (2 (1 + nu)) = 3 E / 8.
  EXPECT_DOUBLE_EQ(m.poissons_ratio, 1.0 / 3.0);
  EXPECT_NEAR(m.bulk_modulus, 72.0e9, 1e-3);
  EXPECT_NEAR(m.shear_modulus, 27.0e9, 1e-3);
  EXPECT_EQ(m.influence, InfluenceKind::constant);
  EXPECT_TRUE(m.damage.enabled);
  ASSERT_TRUE(m.damage.critical_stretch.has_value());
  EXPECT_DOUBLE_EQ(*m.damage.critical_stretch, 2.7e-4);
  EXPECT_FALSE(m.damage.fracture_energy.has_value());

  ASSERT_EQ(c.bodies.size(), 1u);
  EXPECT_EQ(c.bodies[0].name, "plate");
  EXPECT_EQ(c.bodies[0].material, "glass");
  EXPECT_EQ(c.bodies[0].shape.kind(), Shape::Kind::box);
  EXPECT_DOUBLE_EQ(c.bodies[0].shape.bounds().min.x, -0.05);
  EXPECT_DOUBLE_EQ(c.bodies[0].shape.bounds().max.y, 0.02);
  EXPECT_TRUE(c.bodies[0].shape.contains({0.0, 0.0, 0.0}));
  EXPECT_FALSE(c.bodies[0].shape.contains({0.0, 0.03, 0.0}));

  ASSERT_EQ(c.precracks.size(), 1u);
  ASSERT_EQ(c.precracks[0].points.size(), 2u);
  EXPECT_DOUBLE_EQ(c.precracks[0].points[0].x, -0.05);
  EXPECT_DOUBLE_EQ(c.precracks[0].points[1].x, 0.0);

  ASSERT_EQ(c.regions.size(), 5u);
  EXPECT_TRUE(c.regions.at("top").contains({0.0, 0.0199, 0.0}));
  EXPECT_FALSE(c.regions.at("top").contains({0.0, 0.0, 0.0}));
  EXPECT_TRUE(c.regions.at("hole").contains({0.011, 0.0, 0.0}));  // a disk at z = 0
  EXPECT_FALSE(c.regions.at("hole").contains({0.013, 0.0, 0.0}));
  EXPECT_EQ(c.no_fail_regions, (std::vector<std::string>{"top", "bottom"}));

  ASSERT_EQ(c.initial_conditions.size(), 2u);
  const auto& ic = c.initial_conditions[0];
  EXPECT_EQ(ic.region, "");
  ASSERT_TRUE(ic.velocity[1].has_value());
  EXPECT_DOUBLE_EQ((*ic.velocity[1])(0.5e-6), -10.0);
  EXPECT_DOUBLE_EQ((*ic.velocity[1])(2e-6), -20.0);
  EXPECT_DOUBLE_EQ((*ic.velocity[0])(1.0), 0.0);
  EXPECT_FALSE(ic.velocity[2].has_value());  // unused in 2-D
  EXPECT_FALSE(ic.displacement[0].has_value());
  EXPECT_EQ(c.initial_conditions[1].region, "hole");
  EXPECT_DOUBLE_EQ((*c.initial_conditions[1].displacement[0])(0), 1e-6);
  EXPECT_FALSE(c.initial_conditions[1].displacement[1].has_value());

  ASSERT_EQ(c.loads.size(), 5u);
  EXPECT_EQ(c.loads[0].kind, LoadKind::traction);
  EXPECT_EQ(c.loads[0].region, "top");
  EXPECT_EQ(c.loads[0].normal_axis, 1);
  EXPECT_DOUBLE_EQ((*c.loads[0].value[1])(0), 2.0e6);
  ASSERT_TRUE(c.loads[0].value[2].has_value());  // traction: unused component is zero
  EXPECT_DOUBLE_EQ((*c.loads[0].value[2])(0), 0.0);
  EXPECT_EQ(c.loads[1].normal_axis, -1);
  EXPECT_EQ(c.loads[2].kind, LoadKind::displacement);
  EXPECT_TRUE(c.loads[2].value[0].has_value());
  EXPECT_FALSE(c.loads[2].value[1].has_value());
  EXPECT_FALSE(c.loads[2].value[2].has_value());
  EXPECT_EQ(c.loads[3].kind, LoadKind::velocity);
  EXPECT_FALSE(c.loads[3].value[0]->is_constant());
  EXPECT_DOUBLE_EQ((*c.loads[3].value[0])(2.0), 2e-3);
  EXPECT_EQ(c.loads[4].kind, LoadKind::body_force);
  EXPECT_EQ(c.loads[4].region, "");
  EXPECT_DOUBLE_EQ((*c.loads[4].value[1])(0), -9.81e3);
  EXPECT_DOUBLE_EQ((*c.loads[4].value[2])(0), 0.0);

  EXPECT_DOUBLE_EQ(c.solver.end_time, 43.0e-6);
  EXPECT_DOUBLE_EQ(c.solver.safety_factor, 0.8);
  ASSERT_TRUE(c.solver.time_step.has_value());
  EXPECT_DOUBLE_EQ(*c.solver.time_step, 1e-8);
  EXPECT_DOUBLE_EQ(c.solver.damping, 0);
  EXPECT_EQ(c.output.directory, "out/glass_branching");
  EXPECT_EQ(c.output.frames, 40);
  EXPECT_EQ(c.output.history_every, 10);
  EXPECT_EQ(c.output.progress_every, 0);
}

TEST(Deck, SmallDeckUsesDefaults) {
  const Config c = parse_deck(kSmallDeck, "small.yaml");
  EXPECT_DOUBLE_EQ(c.horizon, 3.0e-3);
  EXPECT_DOUBLE_EQ(c.thickness, 1.0);
  EXPECT_FALSE(c.lattice_origin.has_value());
  EXPECT_FALSE(c.materials[0].damage.enabled);
  EXPECT_EQ(c.materials[0].influence, InfluenceKind::constant);
  EXPECT_FALSE(c.solver.time_step.has_value());
  EXPECT_DOUBLE_EQ(c.solver.safety_factor, 0.8);
  EXPECT_EQ(c.output.directory, "out");
  EXPECT_EQ(c.output.frames, 10);
  EXPECT_TRUE(c.loads.empty());
  EXPECT_TRUE(c.warnings.empty());
}

TEST(Deck, ThreeDimensionalDeck) {
  const Config c = parse_deck(R"deck(dimension: 3
spacing: 1.0e-3
horizon_factor: 3.015
partial_volume: true
lattice_origin: [0, 0, 0]
materials:
  steel:
    model: lps
    density: 7850
    youngs_modulus: 200e9
    poissons_ratio: 0.3
    influence: gaussian
    damage: {law: critical_stretch, fracture_energy: 1.0e4}
  rubber:
    model: lps
    density: 1100
    bulk_modulus: 2.0e9
    shear_modulus: 1.0e6
bodies:
  - material: steel
    shape:
      subtract:
        - {box: {min: [0, 0, 0], max: [0.1, 0.02, 0.02]}}
        - {cylinder: {center: [0.05, 0.01, 0.01], axis: z, length: 0.05, radius: 0.003}}
  - name: ball
    material: rubber
    shape: {union: [{sphere: {center: [0.2, 0, 0], radius: 0.01}}, {cylinder: {from: [0.2, 0, 0], to: [0.25, 0, 0], radius: 0.002}}]}
precracks:
  - polygon: [[0.05, 0, 0], [0.05, 0.01, 0], [0.05, 0.01, 0.02], [0.05, 0, 0.02]]
regions:
  far: {half_space: {point: [0.09, 0, 0], normal: [-1, 0, 0]}}
loads:
  - {region: far, traction: [1e6, 0, 0], normal: x}
solver: {end_time: 1e-5}
)deck",
                              "3d.yaml");
  EXPECT_EQ(c.dimension, 3);
  EXPECT_EQ(c.plane, PlaneMode::none);
  EXPECT_NEAR(c.horizon, 3.015e-3, 1e-15);
  EXPECT_TRUE(c.partial_volume);
  ASSERT_EQ(c.materials.size(), 2u);
  const MaterialConfig& steel = c.materials[0];
  EXPECT_EQ(steel.model, "lps");
  EXPECT_DOUBLE_EQ(steel.poissons_ratio, 0.3);
  EXPECT_NEAR(steel.bulk_modulus, 200e9 / (3 * 0.4), 1e-3);
  EXPECT_NEAR(steel.shear_modulus, 200e9 / 2.6, 1e-3);
  EXPECT_EQ(steel.influence, InfluenceKind::gaussian);
  ASSERT_TRUE(steel.damage.fracture_energy.has_value());
  EXPECT_DOUBLE_EQ(*steel.damage.fracture_energy, 1.0e4);
  const MaterialConfig& rubber = c.materials[1];
  // k and mu given: E = 9 k mu / (3 k + mu), nu = (3 k - 2 mu) / (2 (3 k + mu)).
  EXPECT_DOUBLE_EQ(rubber.bulk_modulus, 2.0e9);
  EXPECT_DOUBLE_EQ(rubber.shear_modulus, 1.0e6);
  EXPECT_NEAR(rubber.youngs_modulus, 9 * 2e9 * 1e6 / (6e9 + 1e6), 1e-3);
  EXPECT_NEAR(rubber.poissons_ratio, (6e9 - 2e6) / (2 * (6e9 + 1e6)), 1e-12);
  ASSERT_EQ(c.bodies.size(), 2u);
  EXPECT_EQ(c.bodies[0].name, "body1");
  EXPECT_TRUE(c.bodies[0].shape.contains({0.01, 0.01, 0.01}));
  EXPECT_FALSE(c.bodies[0].shape.contains({0.05, 0.01, 0.01}));  // inside the hole
  EXPECT_TRUE(c.bodies[1].shape.contains({0.24, 0, 0}));
  ASSERT_EQ(c.precracks[0].points.size(), 4u);
  EXPECT_DOUBLE_EQ(c.precracks[0].points[2].z, 0.02);
  EXPECT_TRUE(c.regions.at("far").contains({0.095, 0.3, -1}));
  EXPECT_EQ(c.loads[0].normal_axis, 0);
}

TEST(Deck, OneDimensionalDeckAndHorizonWarning) {
  const Config c = parse_deck(R"deck(dimension: 1
area: 1.0e-4
spacing: 1.0e-3
horizon: 2.0e-3
materials:
  bar: {model: pmb, density: 1000, bulk_modulus: 1e9}
bodies:
  - {name: bar, material: bar, shape: {box: {min: [0], max: [1]}}}
regions:
  end: {box: {min: [0.999], max: [1]}}
loads:
  - {region: end, velocity: [1]}
solver: {end_time: 1e-3}
)deck",
                              "1d.yaml");
  EXPECT_DOUBLE_EQ(c.area, 1.0e-4);
  // PMB in 1-D: nu = 1/4, E = 3 k (1 - 2 nu) = 1.5 k.
  EXPECT_DOUBLE_EQ(c.materials[0].poissons_ratio, 0.25);
  EXPECT_NEAR(c.materials[0].youngs_modulus, 1.5e9, 1e-3);
  EXPECT_FALSE(c.loads[0].value[1].has_value());
  ASSERT_EQ(c.warnings.size(), 1u);
  EXPECT_NE(c.warnings[0].find("1d.yaml:4:10: warning: horizon"), std::string::npos) << c.warnings[0];
  EXPECT_NE(c.warnings[0].find("only 2 lattice spacings"), std::string::npos) << c.warnings[0];
}

TEST(Deck, LoadDeckReadsFileAndNamesMissingOne) {
  const std::string path = ::testing::TempDir() + "/horizon_test_deck.yaml";
  {
    std::ofstream out(path);
    out << kSmallDeck;
  }
  const Config c = load_deck(path);
  EXPECT_EQ(c.deck_file, path);
  EXPECT_EQ(c.bodies[0].name, "plate");
  try {
    load_deck("/nonexistent/deck.yaml");
    ADD_FAILURE() << "no error for a missing file";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/deck.yaml"), std::string::npos) << e.what();
  }
}

// --- One test per class of mistake -------------------------------------------------

TEST(DeckErrors, UnknownKeySuggestsClosest) {
  expect_error(small_deck_with(9, "    youngs_modlus: 72.0e9"), 9, 5,
               {"materials.glass.youngs_modlus", "unknown key 'youngs_modlus'", "did you mean 'youngs_modulus'?"});
  // A case/underscore variant is recognised too.
  expect_error(small_deck_with(9, "    YoungsModulus: 72.0e9"), 9, 5, {"did you mean 'youngs_modulus'?"});
  // Nothing close: list the valid keys.
  expect_error(small_deck_with(14, "solver: {end_time: 1.0e-6, colour: red}"), 14, 28,
               {"solver.colour", "unknown key 'colour'", "valid keys here: type, end_time"});
}

TEST(DeckErrors, WrongType) {
  expect_error(small_deck_with(8, "    density: heavy"), 8, 14,
               {"materials.glass.density", "expected a number", "found 'heavy'"});
  expect_error(small_deck_with(14, "solver: [1.0e-6]"), 14, 9, {"solver: expected a map", "found a list of 1 item"});
  expect_error(std::string(kSmallDeck) + "loads: {region: top}\n", 15, 8, {"loads: expected a list", "found a map"});
  expect_error(small_deck_with(8, "    density: 2*1220"), 8, 14,
               {"expected a number", "found '2*1220'", "expressions in t, x, y, z are allowed only in loads"});
  expect_error(small_deck_with(8, "    density: 2440 kg/m^3"), 8, 14, {"found '2440 kg/m^3'", "SI units"});
}

TEST(DeckErrors, MissingRequiredKeyPointsAtParent) {
  // Without density, the error points at the key of the map that lacks it.
  expect_error(small_deck_with(8, ""), 6, 3, {"materials.glass", "missing required key 'density'", "kg/m^3"});
  expect_error(small_deck_with(3, ""), 1, 1, {"missing required key 'spacing'"});
  expect_error(small_deck_with(14, "solver: {safety_factor: 0.5}"), 14, 1, {"solver: missing required key 'end_time'"});
}

TEST(DeckErrors, NegativeDensity) {
  expect_error(small_deck_with(8, "    density: -2440"), 8, 14,
               {"materials.glass.density", "expected a number > 0", "found -2440"});
}

TEST(DeckErrors, PoissonRatioAtOrAboveOneHalf) {
  expect_error(small_deck_with(7, "    model: lps\n    poissons_ratio: 0.5"), 8, 21,
               {"materials.glass.poissons_ratio", "(-1, 0.5)", "found 0.5", "incompressible"});
  // Derived from two moduli: E > 3 mu means nu > 1/2.
  expect_error(small_deck_with(7, "    model: lps\n    shear_modulus: 10.0e9"), 8, 20,
               {"materials.glass.shear_modulus", "imply poissons_ratio = 2.6", "outside (-1, 0.5)"});
}

TEST(DeckErrors, PmbRejectsAForeignPoissonRatio) {
  expect_error(small_deck_with(7, "    model: pmb\n    poissons_ratio: 0.25"), 8, 21,
               {"materials.glass.poissons_ratio", "bond-based", "1/3 in 2-D plane stress", "model: lps"});
}

TEST(DeckErrors, HorizonBelowSpacing) {
  expect_error(small_deck_with(4, "horizon: 5.0e-4"), 4, 10,
               {"horizon", "at least one spacing (1.0e-3)", "found 5.0e-4"});
  expect_error(small_deck_with(4, "horizon_factor: 0.5"), 4, 17, {"horizon_factor", "at least 1", "found 0.5"});
}

TEST(DeckErrors, BadEnumListsValidValues) {
  expect_error(small_deck_with(2, "plane: stres"), 2, 8,
               {"plane", "expected one of stress, strain", "found 'stres'", "did you mean 'stress'?"});
  expect_error(small_deck_with(7, "    model: bond"), 7, 12, {"materials.glass.model", "expected one of pmb, lps"});
  expect_error(small_deck_with(14, "solver: {type: implicit, end_time: 1.0e-6}"), 14, 16,
               {"solver.type", "expected one of explicit", "found 'implicit'"});
}

TEST(DeckErrors, BadExpressionPointsAtItsComponent) {
  std::string deck = std::string(kSmallDeck) + "regions:\n  top: {box: {min: [0, 0.009], max: [0.01, 0.01]}}\n" +
                     "loads:\n  - {region: top, velocity: [\"1e-3*t+\", null]}\n";
  expect_error(deck, 18, 30, {"loads[0].velocity[0]", "cannot parse expression '1e-3*t+'"});
}

TEST(DeckErrors, WrongVectorLength) {
  expect_error(small_deck_with(13, "    shape: {box: {min: [0, 0, 0], max: [0.01, 0.01]}}"), 13, 24,
               {"bodies[0].shape.box.min", "expected 2 components", "2-D deck", "found 3"});
}

TEST(DeckErrors, UnknownMaterialListsDefinedOnes) {
  expect_error(small_deck_with(12, "    material: glas"), 12, 15,
               {"bodies[0].material", "unknown material 'glas'", "did you mean 'glass'?", "defined materials: glass"});
}

TEST(DeckErrors, UnknownRegionListsDefinedOnes) {
  std::string deck = std::string(kSmallDeck) + "regions:\n  top: {box: {min: [0, 0.009], max: [0.01, 0.01]}}\n" +
                     "loads:\n  - {region: topp, traction: [0, 1e6]}\n";
  expect_error(deck, 18, 14,
               {"loads[0].region", "unknown region 'topp'", "did you mean 'top'?",
                "(defined regions: top; 'all' means every particle)"});
  deck = std::string(kSmallDeck) + "no_fail_regions: [edge]\n";
  expect_error(deck, 15, 19, {"no_fail_regions[0]", "unknown region 'edge'", "no regions are defined"});
  deck = std::string(kSmallDeck) + "no_fail_regions: [all]\n";
  expect_error(deck, 15, 19, {"no_fail_regions[0]", "every bond unbreakable", "damage"});
}

TEST(DeckErrors, YamlSyntaxError) {
  expect_error(small_deck_with(13, "    shape: {box: {min: [0, 0], max: [0.01, 0.01]}"), 14, 1, {"YAML syntax error"});
  expect_error("dimension: 2\n  plane: stress\n", 2, 8, {"YAML syntax error"});
}

TEST(DeckErrors, BothHorizonAndFactor) {
  expect_error(small_deck_with(4, "horizon_factor: 3\nhorizon: 3.0e-3"), 5, 1,
               {"give only one of 'horizon', 'horizon_factor'", "found both 'horizon_factor' and 'horizon'"});
  expect_error(small_deck_with(4, ""), 1, 1, {"missing required key", "'horizon', 'horizon_factor'"});
}

// --- Further rules ------------------------------------------------------------------

TEST(DeckErrors, DimensionSpecificKeys) {
  expect_error(small_deck_with(1, "dimension: 3"), 2, 1, {"plane: applies to 2-D decks only", "dimension: 3"});
  expect_error(small_deck_with(2, "plane: stress\narea: 1e-6"), 3, 1, {"area: applies to 1-D decks only"});
  expect_error(small_deck_with(2, ""), 1, 1, {"missing required key 'plane'"});
  expect_error(small_deck_with(1, "dimension: 4"), 1, 12, {"dimension", "expected one of 1, 2, 3", "found '4'"});
}

TEST(DeckErrors, DuplicateKey) {
  expect_error(small_deck_with(9, "    youngs_modulus: 72.0e9\n    density: 2500"), 10, 5,
               {"materials.glass.density", "duplicate key 'density'", "line 8"});
}

TEST(DeckErrors, EmptyDeckAndNonMapDeck) {
  expect_error("# nothing here\n", 1, 1, {"the deck is empty"});
  expect_error("- a\n- b\n", 1, 1, {"expected the deck to be a map", "found a list of 2 items"});
}

TEST(DeckErrors, ShapeMistakes) {
  expect_error(small_deck_with(13, "    shape: {box: {min: [0, 0], max: [0.01, 0.01]}, sphere: {}}"), 13, 52,
               {"bodies[0].shape", "exactly one key", "union"});
  expect_error(small_deck_with(13, "    shape: {boxx: {min: [0, 0], max: [0.01, 0.01]}}"), 13, 13,
               {"unknown shape 'boxx'", "did you mean 'box'?"});
  expect_error(small_deck_with(13, "    shape: {box: {min: [0, 0.02], max: [0.01, 0.01]}}"), 13, 40,
               {"bodies[0].shape.box.max", "min < max", "along y"});
  expect_error(small_deck_with(13, "    shape: {half_space: {point: [0, 0], normal: [1, 0]}}"), 13, 12,
               {"bodies[0].shape", "must be bounded"});
  expect_error(small_deck_with(13, "    shape: {sphere: {center: [0, 0], radius: 0}}"), 13, 46,
               {"bodies[0].shape.sphere.radius", "expected a number > 0"});
}

TEST(DeckErrors, LoadMistakes) {
  const std::string base = std::string(kSmallDeck) + "regions:\n  top: {box: {min: [0, 0.009], max: [0.01, 0.01]}}\n";
  expect_error(base + "loads:\n  - {region: top, traction: [0, null]}\n", 18, 33,
               {"loads[0].traction[1]", "cannot be left free"});
  expect_error(base + "loads:\n  - {region: top, traction: [0, 1], velocity: [0, 0]}\n", 18, 37,
               {"loads[0]", "give only one of", "found both 'traction' and 'velocity'"});
  expect_error(base + "loads:\n  - {traction: [0, 1]}\n", 18, 5, {"loads[0]", "missing required key 'region'"});
  expect_error(base + "loads:\n  - {region: top, traction: [0, 1], normal: z}\n", 18, 45,
               {"loads[0].normal", "expected one of x, y", "found 'z'"});
  expect_error(base + "regions2: {}\n", 17, 1, {"unknown key 'regions2'", "did you mean 'regions'?"});
}

TEST(DeckErrors, PrecrackMustSuitTheDimension) {
  expect_error(std::string(kSmallDeck) + "precracks:\n  - {polygon: [[0, 0], [1, 0], [1, 1]]}\n", 16, 6,
               {"precracks[0].polygon", "2-D deck a precrack is a segment"});
}

// --- Static and implicit solvers (solver section) ---------------------------------

TEST(Deck, StaticSolverKeys) {
  const Config c = parse_deck(
      small_deck_with(14, "solver: {type: static, method: adr, tolerance: 1.0e-8, max_iterations: 5000, "
                          "load_steps: 20, max_step_cuts: 3, max_break_rounds: 50, condition_number: true}"),
      "static.yaml");
  EXPECT_EQ(c.solver.type, SolverType::static_equilibrium);
  EXPECT_EQ(c.solver.method, StaticMethod::adr);
  EXPECT_DOUBLE_EQ(c.solver.tolerance, 1e-8);
  ASSERT_TRUE(c.solver.max_iterations.has_value());
  EXPECT_EQ(*c.solver.max_iterations, 5000);
  EXPECT_EQ(c.solver.load_steps, 20);
  EXPECT_EQ(c.solver.max_step_cuts, 3);
  EXPECT_EQ(c.solver.max_break_rounds, 50);
  EXPECT_TRUE(c.solver.condition_number);
  EXPECT_DOUBLE_EQ(c.solver.end_time, 1.0) << "a static solve's pseudo-time defaults to 1";

  const Config n = parse_deck(
      small_deck_with(14, "solver: {type: static, linear_solver: cholesky, tangent: finite_difference, end_time: 5}"),
      "newton.yaml");
  EXPECT_EQ(n.solver.method, StaticMethod::newton);
  EXPECT_EQ(n.solver.linear_solver, LinearSolverKind::cholesky);
  EXPECT_EQ(n.solver.tangent, TangentKind::finite_difference);
  EXPECT_DOUBLE_EQ(n.solver.end_time, 5);
  EXPECT_FALSE(n.solver.max_iterations.has_value());
  EXPECT_EQ(n.solver.load_steps, 1);
  EXPECT_FALSE(n.solver.condition_number);
}

TEST(Deck, ImplicitDynamicSolverKeys) {
  const Config c = parse_deck(
      small_deck_with(14, "solver: {type: implicit_dynamic, end_time: 1.0e-5, time_step: 1.0e-7, damping: 10, "
                          "linear_solver: matrix_free}"),
      "implicit.yaml");
  EXPECT_EQ(c.solver.type, SolverType::implicit_dynamic);
  ASSERT_TRUE(c.solver.time_step.has_value());
  EXPECT_DOUBLE_EQ(*c.solver.time_step, 1e-7);
  EXPECT_DOUBLE_EQ(c.solver.damping, 10);
  EXPECT_EQ(c.solver.linear_solver, LinearSolverKind::matrix_free);
  // The explicit default is unchanged.
  EXPECT_EQ(parse_deck(kSmallDeck, "small.yaml").solver.type, SolverType::explicit_dynamic);
}

TEST(DeckErrors, StaticSolverMistakes) {
  // Misspelt keys and values suggest the closest.
  expect_error(small_deck_with(14, "solver: {type: static, metod: newton}"), 14, 24,
               {"solver.metod", "unknown key 'metod'", "did you mean 'method'?"});
  expect_error(small_deck_with(14, "solver: {type: static, method: newtn}"), 14, 32,
               {"solver.method", "expected one of newton, adr", "did you mean 'newton'?"});
  expect_error(small_deck_with(14, "solver: {type: static, linear_solver: cholesky_}"), 14, 39,
               {"solver.linear_solver", "expected one of cg, cholesky, matrix_free", "did you mean 'cholesky'?"});
  expect_error(small_deck_with(14, "solver: {type: statik}"), 14, 16,
               {"solver.type", "expected one of explicit, static, implicit_dynamic", "did you mean 'static'?"});
  // Keys of one solver type are errors in the others.
  expect_error(small_deck_with(14, "solver: {end_time: 1.0e-6, method: newton}"), 14, 28,
               {"solver.method", "applies to type: static only", "this deck has type: explicit"});
  expect_error(small_deck_with(14, "solver: {type: static, safety_factor: 0.5}"), 14, 24,
               {"solver.safety_factor", "applies to type: explicit and heat only", "this deck has type: static"});
  expect_error(small_deck_with(14, "solver: {type: static, method: adr, linear_solver: cg}"), 14, 37,
               {"solver.linear_solver", "applies to method: newton only"});
  expect_error(small_deck_with(14, "solver: {type: implicit_dynamic, end_time: 1.0e-6}"), 14, 1,
               {"solver: missing required key 'time_step'"});
  // Impossible values.
  expect_error(small_deck_with(14, "solver: {type: static, tolerance: 2}"), 14, 35,
               {"solver.tolerance", "expected a number in (0, 1)", "found 2"});
  expect_error(small_deck_with(14, "solver: {type: static, load_steps: 0}"), 14, 36,
               {"solver.load_steps", "a whole number >= 1"});
  expect_error(small_deck_with(14, "solver: {type: static, linear_solver: matrix_free, tangent: finite_difference}"),
               14, 61, {"solver.tangent", "finite-difference tangent is assembled"});
}

}  // namespace

// Tupek's nonlinear solid (docs/input.md, model nonlinear_solid).
namespace {
const char* const kTupekDeck = R"deck(dimension: 2
plane: stress
spacing: 1.0e-3
horizon: 3.0e-3
materials:
  pmma:
    model: nonlinear_solid
    seth_hill_m: -0.25
    density: 1180
    youngs_modulus: 3.5e9
    poissons_ratio: 0.35
    damage: {law: energy, fracture_energy: 400, broken_bonds: off}
  al: {model: tupek, fracture: false, density: 2700, youngs_modulus: 70e9, poissons_ratio: 0.33}
bodies:
  - {name: plate, material: pmma, shape: {box: {min: [0, 0], max: [0.01, 0.01]}}}
  - {name: ball, material: al, shape: {box: {min: [0.012, 0], max: [0.014, 0.002]}}}
solver: {end_time: 1.0e-6, adaptive_time_step: true, adaptive_every: 3}
)deck";
}  // namespace

TEST(Deck, NonlinearSolidDeck) {
  const Config c = parse_deck(kTupekDeck, "tupek.yaml");
  ASSERT_EQ(c.materials.size(), 2u);
  EXPECT_EQ(c.materials[0].model, "nonlinear_solid");
  EXPECT_EQ(c.materials[0].influence, InfluenceKind::tupek);
  EXPECT_EQ(c.materials[0].parameters.at("seth_hill_m"), -0.25);
  EXPECT_TRUE(c.materials[0].damage.energy_law);
  EXPECT_FALSE(c.materials[0].damage.broken_bonds_compression);
  EXPECT_EQ(*c.materials[0].damage.fracture_energy, 400);
  EXPECT_EQ(c.materials[1].model, "nonlinear_solid");  // "tupek" is an alias
  EXPECT_EQ(c.materials[1].parameters.at("fracture"), 0);
  EXPECT_EQ(c.materials[1].parameters.at("seth_hill_m"), 0);  // default: the log strain
  EXPECT_TRUE(c.solver.adaptive_time_step);
  EXPECT_EQ(c.solver.adaptive_every, 3);
}

TEST(DeckErrors, NonlinearSolidMistakes) {
  auto with = [](const std::string& from, const std::string& to) {
    std::string d = kTupekDeck;
    d.replace(d.find(from), from.size(), to);
    return d;
  };
  // Mixing with pmb/lps is an error at the second material's model.
  expect_error(with("model: tupek, fracture: false,", "model: lps,"), 13, 15,
               {"materials.al.model", "cannot share a run", "nonlinear_solid"});
  // Critical stretch is not the nonlinear solid's law.
  expect_error(with("law: energy", "law: critical_stretch"), 12, 19, {"law: energy", "thesis eq. 6.10"});
  // A typo in broken_bonds suggests the closest word.
  expect_error(with("broken_bonds: off", "broken_bonds: compresion_only"), 12, 63, {"compression_only"});
  // The bond-failure-energy exponent: read, and refused outside [0, 2].
  EXPECT_EQ(parse_deck(with("broken_bonds: off", "broken_bonds: off, failure_length_exponent: 0"), "t.yaml")
                .materials[0]
                .damage.failure_length_exponent,
            0.0);
  expect_error(with("broken_bonds: off", "broken_bonds: off, failure_length_exponent: 3"), 12, 93,
               {"failure_length_exponent", "[0, 2]", "found 3"});
  // Model-specific keys on other models.
  expect_error(with("  al: {model: tupek, fracture: false,", "  al: {model: lps, fracture: false,"), 13, 20,
               {"materials.al.fracture", "applies to model nonlinear_solid only"});
  // Other influence functions are refused.
  expect_error(with("    seth_hill_m: -0.25", "    influence: linear"), 8, 16, {"takes influence tupek"});
  // fracture: false with a damage map.
  expect_error(with("    seth_hill_m: -0.25", "    fracture: false"), 8, 5, {"fracture: false suppresses"});
  // adaptive_every without adaptive_time_step.
  expect_error(with("adaptive_time_step: true, ", ""), 17, 28, {"adaptive_every", "adaptive_time_step: true"});
}

TEST(DeckErrors, AdaptiveStepNeedsNonlinearSolid) {
  expect_error(small_deck_with(14, "solver: {end_time: 1.0e-6, adaptive_time_step: true}"), 14, 48,
               {"solver.adaptive_time_step", "nonlinear_solid"});
}

}  // namespace horizon

namespace horizon {
namespace {

// The thermal parts of the deck (deck/thermal.cpp, docs/input.md "thermal").

// `deck` with the line `line` (exact text) replaced by `text`.
std::string small_deck_with_text(const std::string& deck, const std::string& line, const std::string& text) {
  const std::size_t at = deck.find(line + "\n");
  return at == std::string::npos ? deck : deck.substr(0, at) + text + deck.substr(at + line.size());
}
const char* const kThermalMaterial = "    youngs_modulus: 72.0e9\n    thermal: {conductivity: 1.0, specific_heat: 800}";

TEST(DeckThermal, HeatRunParses) {
  std::string deck = small_deck_with(9, kThermalMaterial);
  deck = small_deck_with_text(deck, "solver: {end_time: 1.0e-6}",
                              "regions:\n  left: {box: {min: [0, 0], max: [0.001, 0.01]}}\n"
                              "thermal:\n  initial_temperature: \"300 + 10*x\"\n  kernel: constant\n"
                              "  calibration: discrete\n  integration: implicit\n  boundary:\n"
                              "    - {region: left, temperature: 273}\n"
                              "    - {region: all, convection: {coefficient: 10, ambient: 293}, normal: y}\n"
                              "solver: {type: heat, end_time: 1.0, time_step: 0.1}");
  const Config c = parse_deck(deck, "test.yaml");
  EXPECT_TRUE(c.thermal.enabled);
  EXPECT_EQ(c.solver.type, SolverType::heat);
  EXPECT_EQ(c.thermal.kernel, HeatKernel::constant);
  EXPECT_EQ(c.thermal.calibration, HeatCalibration::discrete);
  EXPECT_EQ(c.thermal.integration, HeatIntegration::implicit_euler);
  ASSERT_EQ(c.thermal.boundary.size(), 2u);
  EXPECT_EQ(c.thermal.boundary[1].normal_axis, 1);
  EXPECT_DOUBLE_EQ(c.thermal.initial_temperature(0, 0.01, 0, 0), 300.1);
  EXPECT_DOUBLE_EQ(c.materials[0].thermal.conductivity, 1.0);
  EXPECT_DOUBLE_EQ(c.materials[0].thermal.plastic_heat_fraction, 0.9);
}

TEST(DeckThermal, Errors) {
  // A thermal section needs every material's thermal map.
  expect_error(small_deck_with(14, "thermal: {initial_temperature: 300}\nsolver: {end_time: 1.0e-6}"), 7, 5,
               {"materials.glass", "needs a thermal map"});
  // A thermal map needs the section.
  expect_error(small_deck_with(9, kThermalMaterial), 10, 14, {"materials.glass.thermal", "thermal section"});
  // Unknown keys suggest the closest.
  expect_error(small_deck_with(9, "    youngs_modulus: 72.0e9\n    thermal: {conductivty: 1.0, specific_heat: 800}"),
               10, 15, {"conductivty", "did you mean 'conductivity'?"});
  std::string deck = small_deck_with(9, kThermalMaterial);
  deck = small_deck_with_text(deck, "solver: {end_time: 1.0e-6}",
                              "thermal: {initial_temperature: 300, kernal: constant}\nsolver: {end_time: 1.0e-6}");
  expect_error(deck, 15, 37, {"did you mean 'kernel'?"});
  // solver.type heat without a thermal section.
  expect_error(small_deck_with(14, "solver: {type: heat, end_time: 1.0}"), 14, 16, {"needs a thermal section"});
  // Implicit heat without a step.
  deck = small_deck_with(9, kThermalMaterial);
  deck = small_deck_with_text(deck, "solver: {end_time: 1.0e-6}",
                              "thermal: {initial_temperature: 300, integration: implicit}\n"
                              "solver: {type: heat, end_time: 1.0}");
  expect_error(deck, 15, 50, {"implicit needs solver.time_step"});
  // A bad expression names its place.
  deck = small_deck_with(9, kThermalMaterial);
  deck = small_deck_with_text(deck, "solver: {end_time: 1.0e-6}",
                              "thermal: {initial_temperature: \"300 +* x\"}\nsolver: {end_time: 1.0e-6}");
  expect_error(deck, 15, 32, {"thermal.initial_temperature"});
}

}  // namespace
}  // namespace horizon
