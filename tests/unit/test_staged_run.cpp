// Staged runs (docs/input.md "Solver stages"; driver/static_stage.cpp): a static solve,
// then an explicit run from its last equilibrium with the velocity of its last load step,
// the output steps counted on across the stages; Exodus files' first_step and last_step;
// the Peridigm importer's mapping of a QuasiStatic solver followed by Verlet and of
// Initial/Final Output Step (docs/peridigm.md); the errors for what is not staged.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "horizon/core/error.hpp"
#include "horizon/deck/deck.hpp"
#include "horizon/driver/run.hpp"
#include "horizon/output/exodus.hpp"
#include "deck_test_support.hpp"

namespace horizon {
namespace {

namespace fs = std::filesystem;

fs::path test_dir() { return test::fresh_test_dir("horizon_staged_run"); }
using test::write;
using test::error_of;

constexpr double kT1 = 5e-5;  // the static stage's end
constexpr double kDt = 1e-7;  // the explicit stage's step

// Peridigm's Compression_QS_Explicit_3x2x2 in a native deck, smaller: 3 x 2 x 2 particles
// of spacing 1, the face x = -1 held, the face x = 1 pushed by ux = -0.01 t / T1 and free
// in y and z; 4 load steps to T1, then 20 explicit steps of 1e-7.
std::string staged_deck(const std::string& solver) {
  return R"(dimension: 3
spacing: 1.0
horizon: 1.75
lattice_origin: [-1, -0.5, -0.5]
materials:
  steel: {model: lps, density: 7800, bulk_modulus: 130.0e9, shear_modulus: 78.0e9}
bodies:
  - {name: bar, material: steel, shape: {box: {min: [-1.5, -1, -1], max: [1.5, 1, 1]}}}
regions:
  left: {box: {min: [-1.6, -2, -2], max: [-0.9, 2, 2]}}
  right: {box: {min: [0.9, -2, -2], max: [1.6, 2, 2]}}
loads:
  - {region: left, displacement: [0, 0, 0]}
  - {region: right, displacement: ["-0.01*t/5e-5", null, null]}
)" + solver + R"(output:
  frames: 2
  exodus_files:
    - {file: all.e}
    - {file: quasi.e, last_step: 4}
    - {file: late.e, every: 5, first_step: 5}
)";
}

const char* kStages = R"(solver:
  - {type: static, end_time: 5.0e-5, load_steps: 4, tolerance: 1.0e-12}
  - {type: explicit, end_time: 5.2e-5, time_step: 1.0e-7}
)";

// Nodal variable v of step k at particle i (DisplacementX = 0, VelocityX = 3, Force_DensityX = 6).
double at(const ExodusSeries& r, std::size_t k, int v, std::size_t i) {
  return r.steps[k].nodal[static_cast<std::size_t>(v)][i];
}

TEST(StagedRun, ExplicitStageStartsFromTheStaticEquilibriumWithItsLastVelocity) {
  const fs::path dir = test_dir();
  Config c = load_deck(write(dir / "staged.yaml", staged_deck(kStages)));
  ASSERT_TRUE(c.static_stage);
  EXPECT_EQ(c.solver.type, SolverType::explicit_dynamic);
  EXPECT_DOUBLE_EQ(c.solver.start_time, kT1);
  c.output.directory = (dir / "out").string();
  RunOptions o;
  o.quiet = true;
  ASSERT_EQ(run_deck(c, o), 0);
  const ExodusSeries r = read_exodus_series((dir / "out" / "all.e").string());
  // The load steps 0..4, the switch written again at T1, then the 20 explicit steps.
  ASSERT_EQ(r.steps.size(), 26u);
  for (std::size_t k = 0; k <= 4; ++k) EXPECT_NEAR(r.steps[k].time, kT1 * static_cast<double>(k) / 4, 1e-18);
  for (std::size_t n = 0; n <= 20; ++n) EXPECT_NEAR(r.steps[5 + n].time, kT1 + kDt * static_cast<double>(n), 1e-18);
  const std::size_t np = r.layout.points.size();
  ASSERT_EQ(np, 12u);
  double fmax = 0;
  for (std::size_t i = 0; i < np; ++i) fmax = std::max(fmax, std::abs(at(r, 4, 6, i)));
  ASSERT_GT(fmax, 0);
  const double h = kT1 / 4;
  for (std::size_t i = 0; i < np; ++i) {
    const double x = r.layout.points[i].x;
    const bool middle = std::abs(x) < 0.5, right = x > 0.5;
    for (int c3 = 0; c3 < 3; ++c3) {
      // The switch state is the static stage's last state, written twice (the prescribed
      // velocities recomputed from their function over the last increment: to round-off).
      for (int v : {0, 6}) EXPECT_EQ(at(r, 5, v + c3, i), at(r, 4, v + c3, i)) << i << " " << v + c3;
      EXPECT_NEAR(at(r, 5, 3 + c3, i), at(r, 4, 3 + c3, i), 1e-12 * (std::abs(at(r, 4, 3 + c3, i)) + 1)) << i;
      // Its velocity: the last load step's displacement over its time, at every particle.
      const double du = at(r, 4, c3, i) - at(r, 3, c3, i);
      EXPECT_NEAR(at(r, 4, 3 + c3, i), du / h, 1e-9 * (std::abs(du / h) + 1)) << i << " " << c3;
      // The static equilibrium: no net force on a free component (the middle column in
      // all three, the pushed face in y and z).
      if (middle || (right && c3 > 0)) {
        EXPECT_LT(std::abs(at(r, 4, 6 + c3, i)), 1e-9 * fmax) << i << " " << c3;
      }
      // The first explicit step is velocity Verlet from that state:
      // u1 = u0 + dt v0 + dt^2/(2 rho) f0 at free components.
      if (middle || (right && c3 > 0)) {
        const double u1 = at(r, 4, c3, i) + kDt * at(r, 4, 3 + c3, i) + kDt * kDt / (2 * 7800) * at(r, 4, 6 + c3, i);
        EXPECT_NEAR(at(r, 6, c3, i), u1, 1e-12 * std::max(1e-6, std::abs(u1))) << i << " " << c3;
      }
    }
    // The middle column moves on at the quasi-static velocity (about half the pushed
    // face's -200 m/s; the held face's y and z make it less): not at rest, which a start
    // from zero velocity would give.
    if (middle) {
      EXPECT_LT(at(r, 5, 3, i), -0.4 * 0.01 / kT1) << i;
      EXPECT_LT(at(r, 6, 0, i), at(r, 5, 0, i) - 0.4 * 0.01 / kT1 * kDt) << i;
    }
    // The prescribed displacement keeps following its function of t.
    if (right) {
      for (std::size_t k = 0; k < r.steps.size(); ++k)
        EXPECT_NEAR(at(r, k, 0, i), -0.01 * r.steps[k].time / kT1, 1e-15) << i << " " << k;
    }
  }
  // first_step / last_step: quasi.e holds the load steps 0..4; late.e the steps every 5
  // from 5 on: the switch (step 5) and the explicit steps 5, 10, 15, 20 (steps 10 ... 25).
  const ExodusSeries q = read_exodus_series((dir / "out" / "quasi.e").string());
  ASSERT_EQ(q.steps.size(), 5u);
  EXPECT_NEAR(q.steps.back().time, kT1, 1e-18);
  const ExodusSeries l = read_exodus_series((dir / "out" / "late.e").string());
  ASSERT_EQ(l.steps.size(), 5u);
  for (std::size_t k = 0; k < 5; ++k) EXPECT_NEAR(l.steps[k].time, kT1 + 5 * kDt * static_cast<double>(k), 1e-18);
}

TEST(StagedRun, StageErrorsNameTheirPlace) {
  const fs::path dir = test_dir();
  const std::string three = error_of(write(
      dir / "three.yaml",
      staged_deck("solver:\n  - {type: static}\n  - {type: explicit, end_time: 2}\n  - {type: explicit, end_time: 3}\n")));
  EXPECT_NE(three.find("three.yaml:16:"), std::string::npos) << three;
  EXPECT_NE(three.find("a list of two stages (a static solve, then an explicit run from its state), found a list of 3 items"), std::string::npos) << three;
  const std::string order = error_of(write(
      dir / "order.yaml", staged_deck("solver:\n  - {type: explicit, end_time: 1}\n  - {type: explicit, end_time: 2}\n")));
  EXPECT_NE(order.find("order.yaml:16:"), std::string::npos) << order;
  EXPECT_NE(order.find("the first stage must be type: static"), std::string::npos) << order;
  const std::string second = error_of(write(
      dir / "second.yaml", staged_deck("solver:\n  - {type: static}\n  - {type: implicit_dynamic, end_time: 2, time_step: 0.1}\n")));
  EXPECT_NE(second.find("the second stage must be type: explicit"), std::string::npos) << second;
  const std::string early = error_of(write(
      dir / "early.yaml", staged_deck("solver:\n  - {type: static, end_time: 2}\n  - {type: explicit, end_time: 1}\n")));
  EXPECT_NE(early.find("early.yaml:17:"), std::string::npos) << early;
  EXPECT_NE(early.find("expected a time after the static stage's end_time 2"), std::string::npos) << early;
  std::string deck = staged_deck(kStages);
  deck.replace(deck.find("last_step: 4"), 12, "first_step: 3, last_step: 2");
  const std::string range = error_of(write(dir / "range.yaml", deck));
  EXPECT_NE(range.find("a step number >= first_step (3)"), std::string::npos) << range;
}

// on_failure: explicit: a static stage whose increment fails (Newton held to one iteration,
// no cuts) hands over at once: the explicit stage runs from t = 0 to its end_time, its
// output steps counted from the switch (step 1), explicit_every taking over there: the
// pattern of Peridigm's Switch to Verlet (AdaptiveQuasiStaticSolver's gold: t = 9 dt,
// 19 dt, ... with Output Frequency 10).
TEST(StagedRun, StaticStageThatFailsSwitchesToExplicit) {
  const fs::path dir = test_dir();
  std::string deck = staged_deck(R"(solver:
  - {type: static, end_time: 2.0e-6, load_steps: 1, max_iterations: 1, max_step_cuts: 0, tolerance: 1.0e-12,
     on_failure: explicit}
  - {type: explicit, end_time: 2.0e-6, time_step: 1.0e-7}
)");
  deck.replace(deck.find("    - {file: all.e}"), 19, "    - {file: all.e, explicit_every: 5}");
  Config c = load_deck(write(dir / "switch.yaml", deck));
  ASSERT_TRUE(c.static_stage);
  EXPECT_TRUE(c.static_stage->switch_on_failure);
  c.output.directory = (dir / "out").string();
  RunOptions o;
  o.quiet = true;
  ASSERT_EQ(run_deck(c, o), 0);
  const ExodusSeries r = read_exodus_series((dir / "out" / "all.e").string());
  ASSERT_EQ(r.steps.size(), 5u);
  EXPECT_EQ(r.steps[0].time, 0.0);
  for (std::size_t k = 1; k < 5; ++k) EXPECT_NEAR(r.steps[k].time, kDt * (5.0 * static_cast<double>(k) - 1), 1e-18) << k;
  // The pushed face follows its function from t = 0 in the explicit stage.
  for (std::size_t i = 0; i < r.layout.points.size(); ++i) {
    if (r.layout.points[i].x > 0.5) {
      EXPECT_NEAR(at(r, 4, 0, i), -0.01 * r.steps[4].time / kT1, 1e-15);
    }
  }
  // Without on_failure the same failure stops the run (not converged, exit code 4).
  std::string stop = deck;
  const std::string clause = ",\n     on_failure: explicit";
  stop.replace(stop.find(clause), clause.size(), "");
  stop.replace(stop.find("end_time: 2.0e-6, time_step"), 17, "end_time: 3.0e-6,");  // (after the static end)
  Config s = load_deck(write(dir / "stop.yaml", stop));
  s.output.directory = (dir / "out_stop").string();
  EXPECT_EQ(run_deck(s, o), 4);
  // on_failure in a deck of one solver, explicit_every without stages: errors.
  const std::string alone = error_of(write(dir / "alone.yaml", staged_deck("solver: {type: static, on_failure: explicit}\n")));
  EXPECT_NE(alone.find("explicit applies to the static stage of a staged run"), std::string::npos) << alone;
  std::string every = staged_deck("solver: {type: static}\n");
  every.replace(every.find("    - {file: all.e}"), 19, "    - {file: all.e, explicit_every: 5}");
  const std::string lone = error_of(write(dir / "every.yaml", every));
  EXPECT_NE(lone.find("applies to staged runs"), std::string::npos) << lone;
}

// Peridigm: a QuasiStatic solver followed by Verlet becomes the native stages; Initial and
// Final Output Step become first_step and last_step.
const char* kPoints = "0 0 0 1 1\n1 0 0 1 1\n2 0 0 1 1\n3 0 0 1 1\n";

std::string peridigm_deck(const std::string& solvers, const std::string& outputs) {
  return "Peridigm:\n"
         "  Discretization:\n    Type: \"Text File\"\n    Input Mesh File: \"points.txt\"\n"
         "  Materials:\n    Steel:\n      Material Model: \"Elastic\"\n      Density: 7800.0\n"
         "      Bulk Modulus: 130.0e9\n      Shear Modulus: 78.0e9\n"
         "  Blocks:\n    All:\n      Block Names: \"block_1\"\n      Material: \"Steel\"\n      Horizon: 1.5\n"
         "  Boundary Conditions:\n    Left: \"1\"\n    Right: \"4\"\n"
         "    Pull:\n      Type: \"Prescribed Displacement\"\n      Node Set: \"Right\"\n      Coordinate: \"x\"\n"
         "      Value: \"0.001*t\"\n" +
         solvers + outputs;
}

const char* kQsThenVerlet =
    "  Solver1:\n    Initial Time: 0.0\n    Final Time: 1.0e-3\n"
    "    QuasiStatic:\n      Number of Load Steps: 2\n      Absolute Tolerance: 1.0e-2\n"
    "      Maximum Solver Iterations: 10\n"
    "  Solver2:\n    Initial Time: 1.0e-3\n    Final Time: 2.0e-3\n    Verlet:\n      Fixed dt: 1.0e-4\n";

const char* kTwoOutputs =
    "  Output1:\n    Output Filename: \"qs\"\n    Output Frequency: 1\n    Final Output Step: 2\n"
    "  Output2:\n    Output Filename: \"explicit\"\n    Output Frequency: 4\n    Initial Output Step: 3\n";

TEST(StagedRun, PeridigmQuasiStaticThenVerletMapsToStages) {
  const fs::path dir = test_dir();
  write(dir / "points.txt", kPoints);
  const std::string deck = write(dir / "staged.yaml", peridigm_deck(kQsThenVerlet, kTwoOutputs));
  const YAML::Node n = YAML::Load(convert_peridigm_deck(deck));
  const YAML::Node s = n["solver"];
  ASSERT_TRUE(s.IsSequence());
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[0]["type"].as<std::string>(), "static");
  EXPECT_EQ(s[0]["load_steps"].as<int>(), 2);
  EXPECT_DOUBLE_EQ(s[0]["end_time"].as<double>(), 1e-3);
  EXPECT_EQ(s[1]["type"].as<std::string>(), "explicit");
  EXPECT_DOUBLE_EQ(s[1]["time_step"].as<double>(), 1e-4);
  // int((T - t0)/dt) whole steps from t0: (2e-3 - 1e-3)/1e-4 = 10.000000000000002, 10.
  EXPECT_DOUBLE_EQ(s[1]["end_time"].as<double>(), 1e-3 + 10 * 1e-4);
  const YAML::Node f = n["output"]["exodus_files"];
  ASSERT_EQ(f.size(), 2u);
  EXPECT_EQ(f[0]["last_step"].as<int>(), 2);
  EXPECT_FALSE(f[0]["first_step"]);
  EXPECT_EQ(f[1]["first_step"].as<int>(), 3);
  EXPECT_EQ(f[1]["every"].as<int>(), 4);
  const Config c = load_deck(deck);
  ASSERT_TRUE(c.static_stage);
  EXPECT_DOUBLE_EQ(c.solver.start_time, 1e-3);
  // What stays one solver a deck: a QuasiStatic solver after the Verlet stage, and a
  // Final Output Step before the Initial one, are errors.
  const std::string again = error_of(write(
      dir / "again.yaml",
      peridigm_deck(std::string(kQsThenVerlet) +
                        "  Solver3:\n    Initial Time: 2.0e-3\n    Final Time: 3.0e-3\n    QuasiStatic:\n"
                        "      Number of Load Steps: 1\n",
                    kTwoOutputs)));
  EXPECT_NE(again.find("a QuasiStatic solver after the Verlet one that follows a QuasiStatic one"), std::string::npos)
      << again;
  std::string backwards = kTwoOutputs;
  backwards.replace(backwards.find("Initial Output Step: 3"), 22, "Initial Output Step: 3\n    Final Output Step: 1");
  const std::string bad = error_of(write(dir / "bad.yaml", peridigm_deck(kQsThenVerlet, backwards)));
  EXPECT_NE(bad.find("a step number >= the Initial Output Step (3)"), std::string::npos) << bad;
}

// Switch to Verlet: the static stage with on_failure: explicit, then its Verlet fallback to
// the same Final Time; its Output Frequency the lists' explicit_every.
TEST(StagedRun, PeridigmSwitchToVerletMapsToOnFailure) {
  const fs::path dir = test_dir();
  write(dir / "points.txt", kPoints);
  const std::string solver =
      "  Solver:\n    Initial Time: 0.0\n    Final Time: 5.0e-3\n"
      "    QuasiStatic:\n      Number of Load Steps: 1\n      Absolute Tolerance: 1.0e-3\n"
      "      Maximum Solver Iterations: 2\n"
      "      Adaptive Load-Stepping:\n        Maximum load step reductions in one step: 1\n"
      "        Maximum total load step reductions: 5\n"
      "        Switch to Verlet:\n          Safety Factor: 0.6\n          Output Frequency: 10\n";
  const std::string output = "  Output1:\n    Output Filename: \"adaptive\"\n    Output Frequency: 1\n";
  const std::string deck = write(dir / "switch.yaml", peridigm_deck(solver, output));
  const YAML::Node n = YAML::Load(convert_peridigm_deck(deck));
  const YAML::Node s = n["solver"];
  ASSERT_TRUE(s.IsSequence());
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[0]["type"].as<std::string>(), "static");
  EXPECT_EQ(s[0]["on_failure"].as<std::string>(), "explicit");
  EXPECT_EQ(s[0]["max_iterations"].as<int>(), 2);
  EXPECT_EQ(s[0]["max_step_cuts"].as<int>(), 1);  // Maximum load step reductions in one step
  EXPECT_EQ(s[1]["type"].as<std::string>(), "explicit");
  EXPECT_DOUBLE_EQ(s[1]["safety_factor"].as<double>(), 0.6);
  EXPECT_DOUBLE_EQ(s[1]["end_time"].as<double>(), 5e-3);
  EXPECT_EQ(n["output"]["exodus_files"][0]["every"].as<int>(), 1);
  EXPECT_EQ(n["output"]["exodus_files"][0]["explicit_every"].as<int>(), 10);
  EXPECT_TRUE(load_deck(deck).static_stage->switch_on_failure);
  // A solver after one that switches is an error.
  const std::string after = error_of(write(
      dir / "after.yaml",
      peridigm_deck(solver + "  Solver2:\n    Initial Time: 5.0e-3\n    Final Time: 6.0e-3\n    Verlet:\n"
                             "      Fixed dt: 1.0e-4\n",
                    output)));
  EXPECT_NE(after.find("Switch to Verlet is staged alone"), std::string::npos) << after;
}

}  // namespace
}  // namespace horizon
