// Smoke test of the examples: every examples/*.yaml runs through the `horizon` binary at
// half resolution (--coarsen 2) and its summary.json holds sane figures. Most decks run
// only a few dozen steps (--end-time); those in kFullRuns run to their own end time,
// because their figure of interest needs the whole run (a crack that has to grow).
// Output goes under the build tree; the frames are deleted when a test passes. A warning
// in a run's output or summary.json fails the test unless the deck's header comment
// explains it (explained_warnings). ChecksAtEveryCoarsening runs `horizon check` on every
// deck at --coarsen 1.5, 2, 3 and 4.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "horizon/deck/deck.hpp"
#include "horizon/driver/run.hpp"
#include "horizon/solver/build.hpp"
#include "../test_paths.hpp"

namespace fs = std::filesystem;

namespace horizon {
namespace {

constexpr double kCoarsen = 2;
constexpr int kShortRunSteps = 40;  // steps of a short run

// Figures checked on full runs, per example (measured at --coarsen 2; docs/verification.md).
struct FullRun {
  double min_crack_length = 0;  // [m]
  double max_crack_speed = 0;   // [m/s], the Rayleigh speed: no crack runs faster
};
const std::map<std::string, FullRun> kFullRuns = {
    // Glass, Ha and Bobaru 2010: at --coarsen 2 the crack runs 47.8 mm from the notch tip
    // (to 2 mm from the right edge) at 1350 m/s before branching at 21.5 mm.
    {"glass_branching", {0.02, 3058.0}},
};

std::vector<std::string> example_names() {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(fs::path(HORIZON_SOURCE_DIR) / "examples"))
    if (e.path().extension() == ".yaml") names.push_back(e.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

int run_binary(const std::string& args, std::string& output) {
  const std::string cmd = std::string(HORIZON_BINARY) + " " + args + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return -1;
  char buf[4096];
  while (std::fgets(buf, sizeof buf, p)) output += buf;
  const int status = pclose(p);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string quoted(const fs::path& p) { return "'" + p.string() + "'"; }

// The warnings a deck's leading comment explains, one line each:
//   # Expected warning "<part of its text>": why the run warns and why that is fine.
std::vector<std::string> explained_warnings(const fs::path& deck) {
  std::vector<std::string> parts;
  std::ifstream in(deck);
  const std::string marker = "expected warning \"";
  for (std::string line; std::getline(in, line) && line.rfind('#', 0) == 0;) {
    std::string lower = line;
    for (char& ch : lower) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    const auto at = lower.find(marker);
    if (at == std::string::npos) continue;
    const auto from = at + marker.size(), to = line.find('"', from);
    if (to != std::string::npos && to > from) parts.push_back(line.substr(from, to - from));
  }
  return parts;
}

// Fails on each warning in a run's output or summary.json that the deck does not explain.
void expect_no_unexplained_warning(const fs::path& deck, const std::string& output, const nlohmann::json& summary) {
  const std::vector<std::string> explained = explained_warnings(deck);
  auto check = [&](const std::string& text) {
    for (const auto& part : explained)
      if (text.find(part) != std::string::npos) return;
    ADD_FAILURE() << deck.filename().string() << ": a warning its header comment does not explain (add a line '# "
                  << "Expected warning \"<text>\": why' if it is meant): " << text;
  };
  std::istringstream lines(output);
  for (std::string line; std::getline(lines, line);)
    if (line.find("warning:") != std::string::npos) check(line);
  if (summary.contains("warnings"))
    for (const auto& w : summary["warnings"]) check(w.get<std::string>());
}

class Examples : public ::testing::TestWithParam<std::string> {};

TEST_P(Examples, RunsAtHalfResolution) {
  const std::string name = GetParam();
  const fs::path deck = fs::path(HORIZON_SOURCE_DIR) / "examples" / (name + ".yaml");
  const fs::path out = fs::path(HORIZON_BINARY).parent_path() / "test-output" / "examples" / name;
  fs::remove_all(out);

  // The coarsened system, built here too, for its particle count and time step.
  Config config = load_deck(deck.string());
  RunOptions options;
  options.coarsen = kCoarsen;
  apply_run_options(config, options);
  const System s = build_system(config);
  const double dt = run_time_step(config, s);
  const auto full = kFullRuns.find(name);
  const bool full_run = full != kFullRuns.end();
  // Half a step short of kShortRunSteps steps, so that the rounding of the printed time
  // cannot add a step.
  const double end_time =
      full_run ? config.solver.end_time : std::min(config.solver.end_time, (kShortRunSteps - 0.5) * dt);

  std::string args = fmt::format("run {} -o {} --coarsen {} -q", quoted(deck), quoted(out), kCoarsen);
  if (!full_run) args += fmt::format(" --end-time {:.9e}", end_time);
  std::string output;
  ASSERT_EQ(run_binary(args, output), 0) << output;

  std::ifstream in(out / "summary.json");
  ASSERT_TRUE(in) << "no summary.json in " << out;
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j["status"], "completed");
  expect_no_unexplained_warning(deck, output, j);
  EXPECT_EQ(j["particles"].get<std::size_t>(), s.particles.size());
  EXPECT_GT(j["particles"].get<std::size_t>(), 0u);
  if (j.contains("fe"))  // finite-element bodies: a deck of elements only has no bond
    EXPECT_GT(j["fe"]["elements"].get<std::size_t>() + j["bonds"].get<std::size_t>(), 0u);
  else
    EXPECT_GT(j["bonds"].get<std::size_t>(), 0u);
  EXPECT_GE(j["steps"].get<int64_t>(), 1);
  EXPECT_NEAR(j["time"].get<double>(), end_time, dt);
  const auto& e = j["energy"];
  for (const char* key : {"initial", "kinetic", "strain", "external_work", "dissipated", "damped", "balance_error"})
    EXPECT_TRUE(std::isfinite(e[key].get<double>())) << key;
  // summary.json names the terms the balance counts, each of them a figure of `energy`:
  // the FE coupling's work among them in a deck with elements; none left out.
  ASSERT_TRUE(e.contains("balance_terms"));
  std::set<std::string> terms;
  for (const auto& name : e["balance_terms"]) {
    terms.insert(name.get<std::string>());
    EXPECT_TRUE(e.contains(name.get<std::string>()) && std::isfinite(e[name.get<std::string>()].get<double>())) << name;
  }
  EXPECT_EQ(terms.count("fe_coupling_work"), j.contains("fe") ? 1u : 0u);
  EXPECT_TRUE(e["terms_left_out"].empty()) << e["terms_left_out"];
  // Energy is kept. At half resolution the largest |balance error| is the O(dt^2) error
  // of velocity Verlet in the first steps after a sudden load (measured: block_tension
  // 1.9e-2, elastic_impact 1.9e-2, glass_branching 1.4e-2, wave_in_bar 2.0e-3; each falls
  // 4x when the step is halved). A term missing from the ledger would show as more.
  // Damage lies in [0, 1] exactly (the glass demo once reached 1.0000000000000007).
  EXPECT_GE(j["damage"]["mean"].get<double>(), 0.0);
  EXPECT_LE(j["damage"]["max"].get<double>(), 1.0);
  const double max_error = e["max_abs_balance_error"];
  EXPECT_LT(max_error, 0.03) << "energy ledger out of balance";
  EXPECT_TRUE(fs::exists(out / "history.csv"));
  EXPECT_TRUE(fs::exists(out / "frames.pvd"));
  std::printf("[ figure ] %s at --coarsen 2: %zu particles, %lld steps, max |balance error| %.2e, wall %.2f s\n",
              name.c_str(), j["particles"].get<std::size_t>(), static_cast<long long>(j["steps"].get<int64_t>()),
              max_error, j["wall_time_s"].get<double>());

  if (full_run) {
    ASSERT_TRUE(j.contains("crack")) << "a deck with a precrack and damage reports its crack";
    const double length = j["crack"]["length"], speed = j["crack"]["speed_before_branching"];
    std::printf("[ figure ] %s: crack length %.4f m, speed before branching %.0f m/s\n", name.c_str(), length, speed);
    EXPECT_GT(length, full->second.min_crack_length);
    EXPECT_GT(speed, 0.0);
    EXPECT_LT(speed, full->second.max_crack_speed);
  }
  if (!HasFailure()) fs::remove_all(out / "frames");
}

// Every deck passes `horizon check` (the set-up: lattice, bonds, regions, loads; no step)
// at each of these coarsenings: `--coarsen` promises a quick look at any deck, and a load
// strip one spacing thick keeps selecting its boundary layer on the coarse lattice
// (geometry/region_select.hpp).
constexpr double kCheckCoarsenings[] = {1.5, 2, 3, 4};

// The coarsenings a deck cannot take by design, and why (each is refused with a message
// that says so, which the test checks).
struct NotCoarsenable {
  double coarsen;
  const char* message;  // part of the refusal
};
const std::multimap<std::string, NotCoarsenable> kNotCoarsenable = {
    // Structures' supports must lie on a line of nodes (the model mirrors the plate across
    // it with ghost nodes): their spans, 40 (double_torsion) and 80 (plate_navier) fine
    // spacings, are whole numbers of coarse spacings at 2 and 4 only.
    {"double_torsion", {1.5, "no node lies on it"}},
    {"double_torsion", {3, "no node lies on it"}},
    {"plate_navier", {1.5, "no node lies on it"}},
    {"plate_navier", {3, "no node lies on it"}},
    // A cylindrical shell's circumference must be a whole number of spacings (the lattice
    // closes on itself): 128 fine spacings around are not a multiple of 1.5 or 3.
    {"pinched_tube", {1.5, "must be a whole number of spacings"}},
    {"pinched_tube", {3, "must be a whole number of spacings"}},
    // Hexahedra need two node layers through the plate (10 mm at 2 mm, 12.5 mm at 2.5 mm):
    // at 4 coarse spacings it holds one.
    {"center_cracked_plate", {4, "an element needs two"}},
    {"plate_perforation_coupled", {4, "an element needs two"}},
    // The 4 mm gauge body is one coarse spacing at 4 x 1 mm: its lattice points are taken
    // by the bodies beside it, and a body with no particle is refused.
    {"plastic_necking_bar", {4, "contains no lattice point"}},
};

TEST_P(Examples, ChecksAtEveryCoarsening) {
  const std::string name = GetParam();
  const fs::path deck = fs::path(HORIZON_SOURCE_DIR) / "examples" / (name + ".yaml");
  for (double coarsen : kCheckCoarsenings) {
    const char* refusal = nullptr;
    const auto [from, to] = kNotCoarsenable.equal_range(name);
    for (auto it = from; it != to; ++it)
      if (it->second.coarsen == coarsen) refusal = it->second.message;
    std::string output;
    const int rc = run_binary(fmt::format("check {} --coarsen {}", quoted(deck), coarsen), output);
    if (refusal) {
      EXPECT_NE(rc, 0) << name << " at --coarsen " << coarsen << " is listed as refused but passes";
      EXPECT_NE(output.find(refusal), std::string::npos) << output;
    } else {
      EXPECT_EQ(rc, 0) << name << " at --coarsen " << coarsen << ":\n" << output;
    }
  }
}

std::string test_name(const ::testing::TestParamInfo<std::string>& info) {
  std::string n = info.param;
  for (char& ch : n)
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  return n;
}

INSTANTIATE_TEST_SUITE_P(AllExamples, Examples, ::testing::ValuesIn(example_names()), test_name);

}  // namespace
}  // namespace horizon
