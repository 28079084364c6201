// Listed points (the `points` shape): bodies made of given particles with their own
// volumes, regions that select given particles, and the errors for malformed lists.
// And the explicit run taken in pieces (driver::ExplicitRun) against run_deck.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "horizon/core/error.hpp"
#include "horizon/deck/deck.hpp"
#include "horizon/driver/run.hpp"
#include "horizon/solver/build.hpp"

namespace horizon {
namespace {

const char* const kPointsDeck = R"deck(dimension: 3
spacing: 1.0
horizon: 1.1
materials:
  steel: {model: lps, density: 7800, bulk_modulus: 130.0e9, shear_modulus: 78.0e9}
bodies:
  - name: bar
    material: steel
    shape: {points: [[-1, 0, 0, 1.0], [0, 0, 0, 2.0], [1, 0, 0, 3.0]]}
regions:
  ends: {points: [[-1, 0, 0], [1, 0, 0]]}
initial_conditions:
  - {region: ends, velocity: ["-x", 0, 0]}
solver: {type: explicit, end_time: 5.0e-5, time_step: 1.0e-5}
output: {directory: OUT, frames: 5, history_every: 1}
)deck";

std::string deck_text(const std::string& out) {
  std::string s = kPointsDeck;
  s.replace(s.find("OUT"), 3, out);
  return s;
}

TEST(Points, BodyOfListedPointsKeepsTheirVolumes) {
  const Config c = parse_deck(deck_text("out/unused"), "points.yaml");
  EXPECT_TRUE(c.warnings.empty()) << c.warnings.front();  // no "few lattice spacings" warning
  const System s = build_system(c);
  ASSERT_EQ(s.particles.size(), 3u);
  EXPECT_EQ(s.particles.volume[0], 1.0);
  EXPECT_EQ(s.particles.volume[1], 2.0);
  EXPECT_EQ(s.particles.volume[2], 3.0);
  EXPECT_EQ(s.particles.X[2].x, 1.0);
  EXPECT_EQ(s.bonds.size(), 4u);  // (-1,0), (0,1), both ways; -1 and 1 are 2 apart
  const Shape& ends = c.regions.at("ends");
  EXPECT_TRUE(ends.contains({-1, 0, 0}));
  EXPECT_TRUE(ends.contains({1, 0, 0}));
  EXPECT_FALSE(ends.contains({0, 0, 0}));
  EXPECT_FALSE(ends.contains({1 + 1e-6, 0, 0}));
}

TEST(Points, FileOfPoints) {
  const auto dir = std::filesystem::temp_directory_path() / "horizon_points_test";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "pts.txt") << "# x y z volume\n-1 0 0 1\n0 0 0 2\n\n1 0 0 3\n";
  std::string text = deck_text("out/unused");
  text.replace(text.find("[[-1, 0, 0, 1.0], [0, 0, 0, 2.0], [1, 0, 0, 3.0]]"),
               std::string("[[-1, 0, 0, 1.0], [0, 0, 0, 2.0], [1, 0, 0, 3.0]]").size(), "{file: pts.txt}");
  const Config c = parse_deck(text, (dir / "deck.yaml").string());
  const System s = build_system(c);
  ASSERT_EQ(s.particles.size(), 3u);
  EXPECT_EQ(s.particles.volume[2], 3.0);
}

void expect_error(const std::string& from, const std::string& to, const std::string& where, const std::string& what) {
  std::string text = deck_text("out/unused");
  ASSERT_NE(text.find(from), std::string::npos) << from;
  text.replace(text.find(from), from.size(), to);
  try {
    parse_deck(text, "points.yaml");
    FAIL() << "expected an error for " << to;
  } catch (const DeckError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(where), std::string::npos) << msg;
    EXPECT_NE(msg.find(what), std::string::npos) << msg;
  }
}

TEST(Points, Errors) {
  expect_error("[0, 0, 0, 2.0]", "[0, 0, 0]", "points.yaml:9:", "give a volume with every point or with none");
  expect_error("[[-1, 0, 0, 1.0], [0, 0, 0, 2.0], [1, 0, 0, 3.0]]", "[[-1, 0, 0], [0, 0, 0]]", "points.yaml:9:",
               "needs a volume with each point");
  expect_error("[0, 0, 0, 2.0]", "[0, 0]", "points.yaml:9:", "expected 3 coordinates, or 3 and a volume, found 2");
  expect_error("[0, 0, 0, 2.0]", "[0, 0, 0, -2.0]", "points.yaml:9:", "volume must be > 0");
  expect_error("{points: [[-1, 0, 0], [1, 0, 0]]}", "{points: {file: missing.txt}}", "points.yaml:11:",
               "cannot open the points file");
}

TEST(ExplicitRun, StepsInPiecesWriteWhatRunDeckWrites) {
  const auto base = std::filesystem::temp_directory_path() / "horizon_explicit_run_test";
  std::filesystem::remove_all(base);
  const std::string whole = (base / "whole").string(), pieces = (base / "pieces").string();
  RunOptions o;
  o.quiet = true;
  ASSERT_EQ(run_deck(parse_deck(deck_text(whole), "points.yaml"), o), 0);
  ExplicitRun run(parse_deck(deck_text(pieces), "points.yaml"), o);
  EXPECT_EQ(run.total_steps(), 5);
  EXPECT_EQ(run.advance(2), 2);
  EXPECT_EQ(run.advance(1), 1);
  EXPECT_FALSE(run.done());
  EXPECT_EQ(run.advance(100), 2);
  EXPECT_TRUE(run.done());
  EXPECT_EQ(run.finish(), 0);
  EXPECT_EQ(run.status(), "completed");
  auto read = [](const std::filesystem::path& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  };
  EXPECT_EQ(read(std::filesystem::path(whole) / "history.csv"), read(std::filesystem::path(pieces) / "history.csv"));
  for (int k = 0; k <= 5; ++k) {
    const std::string f = "frames/frame_0000" + std::to_string(k) + ".vtu";
    EXPECT_EQ(read(std::filesystem::path(whole) / f), read(std::filesystem::path(pieces) / f)) << f;
  }
  EXPECT_EQ(run.history_csv(), read(std::filesystem::path(pieces) / "history.csv"));
}

TEST(ExplicitRun, StopWritesAFinalFrame) {
  const auto dir = std::filesystem::temp_directory_path() / "horizon_explicit_run_stop";
  std::filesystem::remove_all(dir);
  RunOptions o;
  o.quiet = true;
  ExplicitRun run(parse_deck(deck_text(dir.string()), "points.yaml"), o);
  run.advance(2);
  run.stop("a test");
  EXPECT_TRUE(run.done());
  EXPECT_EQ(run.advance(1), 0);
  EXPECT_EQ(run.finish(), 0);
  EXPECT_EQ(run.status(), "stopped");
  EXPECT_EQ(run.summary()["steps"].get<int>(), 2);
  EXPECT_NE(run.summary()["message"].get<std::string>().find("a test"), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(dir / "summary.json"));
}

}  // namespace
}  // namespace horizon
