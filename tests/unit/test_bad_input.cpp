// The bad-input table of docs/reliability.md, one test per row: each class of mistake in
// a deck ends in a horizon::Error whose message says where and what (the text the table
// quotes), never in a crash, a hang or a silent acceptance. The deck is read and set up
// as `horizon check` does (prepare_run: lattice, families, loads, initial conditions).
#include <gtest/gtest.h>

#include <string>

#include "horizon/core/error.hpp"
#include "horizon/deck/deck.hpp"
#include "horizon/driver/run.hpp"
#include "../single_thread.hpp"

namespace horizon {
namespace {

// A valid 2-D plate (40 x 20 particles) with two edge regions; each test changes a line.
const std::string kDeck = R"(dimension: 2
plane: stress
thickness: 1.0e-3
spacing: 5.0e-4
horizon_factor: 3
materials:
  glass: {model: pmb, density: 2440, youngs_modulus: 72.0e9}
bodies:
  - {name: plate, material: glass, shape: {box: {min: [0, 0], max: [0.02, 0.01]}}}
regions:
  left: {box: {min: [0, 0], max: [0.001, 0.01]}}
  right: {box: {min: [0.019, 0], max: [0.02, 0.01]}}
initial_conditions:
  - {velocity: ["10*x/0.02", 0]}
solver: {type: explicit, end_time: 1e-6}
output: {frames: 2}
)";

std::string with(const std::string& from, const std::string& to, std::string deck = kDeck) {
  const auto at = deck.find(from);
  if (at == std::string::npos) throw std::logic_error("test deck has no '" + from + "'");
  return deck.replace(at, from.size(), to);
}

std::string loads(const std::string& lines) { return with("solver:", "loads:\n" + lines + "solver:"); }

// The message of the error the deck ends in ("" when it is accepted).
std::string error_of(const std::string& deck, double memory_limit = 0) {
  const test::SingleThread one;
  try {
    Config c = parse_deck(deck, "bad.yaml");
    c.memory_limit_bytes = memory_limit;
    prepare_run(c);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

#define EXPECT_SAYS(message, text) EXPECT_NE((message).find(text), std::string::npos) << (message)

TEST(BadInput, TheBaseDeckIsValid) { EXPECT_EQ(error_of(kDeck), ""); }

TEST(BadInput, TypoInAKeySuggestsTheKey) {
  const std::string m = error_of(with("density:", "densty:"));
  EXPECT_SAYS(m, "bad.yaml:7:23: error: materials.glass.densty: unknown key 'densty'; did you mean 'density'?");
  EXPECT_SAYS(error_of(with("spacing:", "spaceing:")), "did you mean 'spacing'?");
  EXPECT_SAYS(error_of(with("model: pmb", "model: pbm")), "found 'pbm'; did you mean 'pmb'?");
}

TEST(BadInput, WrongTypesNameWhatWasExpected) {
  EXPECT_SAYS(error_of(with("density: 2440", "density: abc")),
              "bad.yaml:7:32: error: materials.glass.density: expected a number, found 'abc'");
  EXPECT_SAYS(error_of(with("density: 2440", "density: [1, 2]")), "expected a number, found a list of 2 items");
  EXPECT_SAYS(error_of(with("dimension: 2", "dimension: {a: 1}")), "dimension: expected one of 1, 2, 3, found a map");
  EXPECT_SAYS(error_of(with("frames: 2", "frames: 1e20")), "output.frames: expected a whole number, found '1e20'");
}

TEST(BadInput, NegativeZeroAndNonFiniteValuesAreRefused) {
  EXPECT_SAYS(error_of(with("density: 2440", "density: -2440")),
              "materials.glass.density: expected a number > 0, found -2440");
  EXPECT_SAYS(error_of(with("spacing: 5.0e-4", "spacing: 0")), "bad.yaml:4:10: error: spacing: expected a number > 0, found 0");
  EXPECT_SAYS(error_of(with("end_time: 1e-6", "end_time: -1")), "solver.end_time: expected a number > 0, found -1");
  EXPECT_SAYS(error_of(with("frames: 2", "frames: 0")), "output.frames: expected a whole number >= 1, found '0'");
  EXPECT_SAYS(error_of(with("72.0e9", ".nan")), "youngs_modulus: expected a number, found '.nan'");
  EXPECT_SAYS(error_of(with("72.0e9", ".inf")), "youngs_modulus: expected a number, found '.inf'");
  EXPECT_SAYS(error_of(with("dimension: 2", "dimension: 4")), "dimension: expected one of 1, 2, 3; found '4'");
}

TEST(BadInput, EmptyAndBinaryFiles) {
  EXPECT_SAYS(error_of(""), "bad.yaml:1:1: error: the deck is empty");
  EXPECT_SAYS(error_of("  \n# only a comment\n"), "the deck is empty");
  std::string binary;
  for (int k = 0; k < 1024; ++k) binary += static_cast<char>(k % 256);
  EXPECT_SAYS(error_of(binary), "found binary data (");
  EXPECT_SAYS(error_of("- a\n- b\n"), "expected the deck to be a map of 'key: value' lines (dimension, spacing, ...), "
                                      "found a list of 2 items");
}

TEST(BadInput, BrokenYamlNamesLineAndColumn) {
  EXPECT_SAYS(error_of(with("[0.02, 0.01]}}}", "[0.02, 0.01}}")), "bad.yaml:9:79: error: YAML syntax error: illegal flow end");
  EXPECT_SAYS(error_of(with("  glass:", "\tglass:")), "YAML syntax error");
  EXPECT_SAYS(error_of(std::string(100000, '[')), "YAML syntax error");
  EXPECT_SAYS(error_of(kDeck + "spacing: 1.0e-3\n"), "bad.yaml:17:1: error: spacing: duplicate key 'spacing' (first given at line 4)");
}

// A spacing of 1e-9 m over a 2 cm plate: 2e14 particles, refused before any allocation.
TEST(BadInput, HugeSizesAreRefusedBeforeAllocation) {
  EXPECT_SAYS(error_of(with("spacing: 5.0e-4", "spacing: 1.0e-9")),
              "bad.yaml: the deck would make about 2e+14 particles (spacing 1e-09 m), more than the 4e9 a run can index");
  const std::string m = error_of(with("horizon_factor: 3", "horizon_factor: 100000"));
  EXPECT_SAYS(m, "GiB (800 particles, 2.51e+13 bonds at spacing 0.0005 m, horizon 50 m), more than the");
  EXPECT_SAYS(m, "raise the limit with --max-memory <GiB>");
  EXPECT_SAYS(error_of(with("end_time: 1e-6", "end_time: 1e6")),
              "the run would take 1.22e+13 steps of 8.213e-08 s to end_time 1e+06 s, more than the 1e+12");
  // One particle, no bond: no stable time step (the run would have taken 0 steps of inf s).
  EXPECT_SAYS(error_of(with("max: [0.02, 0.01]}}}", "max: [0.0005, 0.0005]}}}")),
              "bad.yaml: the time step is inf: no particle has a bond that sets a stable step");
  EXPECT_SAYS(error_of(with("horizon_factor: 3", "horizon_factor: 3\nlattice_origin: [1e30, 0]")),
              "a body lies more than 1e15 spacings from the lattice origin");
}

// The limit is the option's (--max-memory): the same deck is refused under 0.5 MiB and
// accepted under the machine's memory.
TEST(BadInput, TheMemoryLimitIsAnOption) {
  const std::string m = error_of(kDeck, 0.5 * 1024.0 * 1024.0);
  EXPECT_SAYS(m, "more than the 0.000488 GiB allowed by --max-memory");
  EXPECT_EQ(error_of(kDeck, 0), "");
}

TEST(BadInput, ExpressionErrorsAndDivisionByZero) {
  EXPECT_SAYS(error_of(with("\"10*x/0.02\"", "\"10*x/\"")),
              "bad.yaml:14:17: error: initial_conditions[0].velocity[0]: cannot parse expression '10*x/': Unexpected end "
              "of expression at position 6");
  EXPECT_SAYS(error_of(with("\"10*x/0.02\"", "\"10*q\"")), "Unexpected token \"q\" found at position 3");
  EXPECT_SAYS(error_of(with("\"10*x/0.02\"", "\"1/0\"")),
              "bad.yaml:14:17: error: initial_conditions[0].velocity[0]: the expression '1/0' is infinite");
  EXPECT_SAYS(error_of(with("\"10*x/0.02\"", "\"sqrt(-1)\"")), "the expression 'sqrt(-1)' is not a number");
  EXPECT_SAYS(error_of(with("\"10*x/0.02\"", "\"1/(x-x)\"")),
              "bad.yaml: initial velocity x-component '1/(x-x)' is infinite at t = 0, (x, y, z) = (0.00025, 0.00025, 0)");
  EXPECT_SAYS(error_of(loads("  - {region: left, traction: [\"1/(y-y)\", 0]}\n")),
              "load left:traction x-component '1/(y-y)' is infinite");
}

TEST(BadInput, RegionSelectingNothing) {
  const std::string empty = with("right: {box: {min: [0.019, 0], max: [0.02, 0.01]}}", "right: {box: {min: [1, 1], max: [2, 2]}}");
  const std::string m = error_of(with("solver:", "loads:\n  - {region: right, velocity: [1, null]}\nsolver:", empty));
  EXPECT_SAYS(m, "bad.yaml: region 'right' contains no particle: it spans x: [1, 2], y: [1, 2], the particles span x: "
                 "[0.00025, 0.01975], y: [0.00025, 0.00975]");
  EXPECT_SAYS(error_of(with("  - {velocity: [\"10*x/0.02\", 0]}", "  - {region: right, velocity: [1, 0]}", empty)),
              "region 'right' contains no particle");
  EXPECT_SAYS(error_of(with("solver:", "no_fail_regions: [nowhere]\nsolver:")), "nowhere");
}

TEST(BadInput, ConflictingLoadsOnOneParticle) {
  EXPECT_SAYS(error_of(loads("  - {region: left, displacement: [0, null]}\n  - {region: left, displacement: [1e-6, null]}\n")),
              "bad.yaml: loads 'left:displacement' and 'left:displacement' both prescribe the x-component of particle 0 "
              "at (0.00025, 0.00025, 0) differently");
  EXPECT_SAYS(error_of(loads("  - {region: left, displacement: [0, null]}\n  - {region: all, velocity: [1, null]}\n")),
              "loads 'left:displacement' and 'all:velocity' both prescribe the x-component");
  // The same prescription twice (two clamped edges sharing corners) is no conflict, nor
  // are different components, nor a force on a constrained component (it goes into the
  // reaction).
  EXPECT_EQ(error_of(loads("  - {region: left, displacement: [0, 0]}\n  - {region: all, displacement: [0, null]}\n")), "");
  EXPECT_EQ(error_of(loads("  - {region: left, displacement: [0, null]}\n  - {region: left, velocity: [null, 1]}\n")), "");
  EXPECT_EQ(error_of(loads("  - {region: left, displacement: [0, null]}\n  - {region: left, traction: [1e6, 0]}\n")), "");
}

TEST(BadInput, PrecracksOutsideTheBody) {
  EXPECT_SAYS(error_of(with("regions:", "precracks:\n  - {from: [1, 1], to: [2, 2]}\nregions:")),
              "bad.yaml: precracks[0] (1, 1) - (2, 2) crosses no bond: it lies outside the bodies");
  EXPECT_SAYS(error_of(with("regions:", "precracks:\n  - {from: [0.01, 0.005], to: [0.01, 0.005]}\nregions:")),
              "precracks[0].to: the crack's ends 'from' and 'to' coincide");
  EXPECT_EQ(error_of(with("regions:", "precracks:\n  - {from: [0, 0.005], to: [0.01, 0.005]}\nregions:")), "");
}

}  // namespace
}  // namespace horizon
