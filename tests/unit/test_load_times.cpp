// Static load steps of unequal length (solver.load_times, docs/input.md "Static solves";
// solver/static_driver.cpp) and Peridigm's QuasiStatic `Time Steps`, which map to them
// (docs/peridigm.md): the load steps end at the listed pseudo-times, a load without t is
// ramped by t_k / t_N, and the errors name the deck's line and column. Peridigm's solvers
// in sequence (solver.solver_starts: the start state written again) and its Verlet
// prescribed displacements (u = g(t) - g(0)).
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "horizon/deck/deck.hpp"
#include "horizon/driver/run.hpp"
#include "horizon/output/exodus.hpp"
#include "deck_test_support.hpp"

namespace horizon {
namespace {

namespace fs = std::filesystem;

fs::path test_dir() { return test::fresh_test_dir("horizon_load_times"); }
using test::error_of;
using test::index_of;
using test::write;

constexpr double kStrain = 1e-3;  // the end state's uniform strain

// A 1-D bar on [0, 1], 20 particles, horizon 3 spacings. Both end layers (4 particles,
// wider than the horizon) are prescribed: the left one by the ramped field kStrain x (no
// t: multiplied by the load factor t_k / t_N), the right one by the same field written in
// t, kStrain x t / t_N. The free particles between them have whole neighbourhoods in the
// bar, so the uniform strain is their equilibrium (each bond xi has its mirror -xi,
// stretched alike): at load step k every particle has u = kStrain x t_k / t_N, for any
// model (the closed form).
std::string bar_deck(const std::string& solver, double t_end) {
  return R"(dimension: 1
area: 1.0e-4
spacing: 0.05
horizon: 0.151
lattice_origin: [0.025]
materials:
  steel: {model: pmb, density: 7800, youngs_modulus: 200.0e9}
bodies:
  - {name: bar, material: steel, shape: {box: {min: [0.0], max: [1.0]}}}
regions:
  left: {box: {min: [-1.0], max: [0.2]}}
  right: {box: {min: [0.8], max: [2.0]}}
loads:
  - {region: left, displacement: ["1.0e-3*x"]}
  - {region: right, displacement: ["1.0e-3*x*t/)" +
         std::to_string(t_end) + R"("]}
)" + solver + R"(output:
  frames: 1
  exodus_files: [{file: bar.e}]
)";
}

TEST(LoadTimes, UnequalLoadStepsEndAtTheListedTimes) {
  const fs::path dir = test_dir();
  const std::vector<double> times = {0.0, 0.2, 1.0, 2.0};
  const std::string deck = write(
      dir / "bar.yaml", bar_deck("solver: {type: static, load_times: [0, 0.2, 1.0, 2.0], tolerance: 1.0e-12}\n", 2.0));
  const Config c = load_deck(deck);
  EXPECT_EQ(c.solver.load_steps, 3);
  EXPECT_DOUBLE_EQ(c.solver.end_time, 2.0);
  EXPECT_EQ(c.solver.load_times, times);
  const ExodusSeries r = test::run_and_read(deck, dir, "bar.e");
  ASSERT_EQ(r.steps.size(), 4u);
  const std::size_t ux = index_of(r.layout.nodal, "DisplacementX"), vx = index_of(r.layout.nodal, "VelocityX");
  ASSERT_EQ(r.layout.points.size(), 20u);
  for (std::size_t k = 0; k < times.size(); ++k) {
    EXPECT_EQ(r.steps[k].time, times[k]) << k;  // exactly the listed times
    for (std::size_t i = 0; i < r.layout.points.size(); ++i) {
      const double x = r.layout.points[i].x;
      // The closed form: u = kStrain x t_k / t_N (equal steps would give t = 2/3 at k = 1).
      EXPECT_NEAR(r.steps[k].nodal[ux][i], kStrain * x * times[k] / 2.0, 1e-12 * kStrain) << k << " " << i;
      // The quasi-static velocity: the step's displacement over its own time increment,
      // kStrain x / t_N at every step (steps of 0.2, 0.8 and 1.0).
      if (k > 0) {
        EXPECT_NEAR(r.steps[k].nodal[vx][i], kStrain * x / 2.0, 1e-10 * kStrain) << k << " " << i;
      }
    }
  }
}

TEST(LoadTimes, ErrorsNameTheirPlace) {
  const fs::path dir = test_dir();
  auto error = [&](const std::string& name, const std::string& solver) {
    return error_of(write(dir / (name + ".yaml"), bar_deck(solver, 2.0)));
  };
  // The solver line is line 16 of the deck.
  const std::string one = error("one", "solver: {type: static, load_times: [0]}\n");
  EXPECT_NE(one.find("one.yaml:16:"), std::string::npos) << one;
  EXPECT_NE(one.find("at least two pseudo-times"), std::string::npos) << one;
  const std::string start = error("start", "solver: {type: static, load_times: [0.1, 0.5, 1]}\n");
  EXPECT_NE(start.find("start.yaml:16:37"), std::string::npos) << start;
  EXPECT_NE(start.find("solver.load_times[0]"), std::string::npos) << start;
  EXPECT_NE(start.find("starts at pseudo-time 0"), std::string::npos) << start;
  const std::string back = error("back", "solver: {type: static, load_times: [0, 0.5, 0.5, 1]}\n");
  EXPECT_NE(back.find("back.yaml:16:45"), std::string::npos) << back;
  EXPECT_NE(back.find("solver.load_times[2]: expected a pseudo-time after the one before it (0.5), found 0.5"),
            std::string::npos)
      << back;
  const std::string word = error("word", "solver: {type: static, load_times: [0, one]}\n");
  EXPECT_NE(word.find("word.yaml:16:40"), std::string::npos) << word;
  const std::string scalar = error("scalar", "solver: {type: static, load_times: 1.0}\n");
  EXPECT_NE(scalar.find("a list of pseudo-times"), std::string::npos) << scalar;
  const std::string steps = error("steps", "solver: {type: static, load_times: [0, 1], load_steps: 2}\n");
  EXPECT_NE(steps.find("steps.yaml:16:44"), std::string::npos) << steps;
  EXPECT_NE(steps.find("give load_times or load_steps, not both"), std::string::npos) << steps;
  const std::string end = error("end", "solver: {type: static, end_time: 1, load_times: [0, 1]}\n");
  EXPECT_NE(end.find("give load_times or end_time, not both"), std::string::npos) << end;
  const std::string expl = error("expl", "solver: {type: explicit, end_time: 1.0e-6, load_times: [0, 1]}\n");
  EXPECT_NE(expl.find("solver.load_times: applies to type: static only"), std::string::npos) << expl;
}

// Peridigm: four points on a line, the last pulled by 0.001 t, every point held in y, z.
std::string peridigm_deck(const std::string& solvers) {
  return "Peridigm:\n"
         "  Discretization:\n    Type: \"Text File\"\n    Input Mesh File: \"points.txt\"\n"
         "  Materials:\n    Steel:\n      Material Model: \"Elastic\"\n      Density: 7800.0\n"
         "      Bulk Modulus: 130.0e9\n      Shear Modulus: 78.0e9\n"
         "  Blocks:\n    All:\n      Block Names: \"block_1\"\n      Material: \"Steel\"\n      Horizon: 1.5\n"
         "  Boundary Conditions:\n    Left: \"1\"\n    Right: \"4\"\n    Every: \"1 2 3 4\"\n"
         "    Hold:\n      Type: \"Prescribed Displacement\"\n      Node Set: \"Left\"\n      Coordinate: \"x\"\n"
         "      Value: \"0.0\"\n"
         "    Hold y:\n      Type: \"Prescribed Displacement\"\n      Node Set: \"Every\"\n      Coordinate: \"y\"\n"
         "      Value: \"0.0\"\n"
         "    Hold z:\n      Type: \"Prescribed Displacement\"\n      Node Set: \"Every\"\n      Coordinate: \"z\"\n"
         "      Value: \"0.0\"\n"
         "    Pull:\n      Type: \"Prescribed Displacement\"\n      Node Set: \"Right\"\n      Coordinate: \"x\"\n"
         "      Value: \"0.001*t\"\n" +
         solvers + "  Output:\n    Output Filename: \"qs\"\n    Output Frequency: 1\n";
}

std::string quasi_static(const std::string& times, const std::string& extra = "") {
  return "  Solver:\n    Initial Time: 0.0\n" + extra + "    QuasiStatic:\n      Time Steps: \"" + times +
         "\"\n      Maximum Solver Iterations: 10\n      Absolute Tolerance: 1.0e-3\n";
}

TEST(LoadTimes, PeridigmTimeStepsAreTheLoadTimes) {
  const fs::path dir = test_dir();
  write(dir / "points.txt", "0 0 0 1 1\n1 0 0 1 1\n2 0 0 1 1\n3 0 0 1 1\n");
  // Pals_Simple_Shear's form: leading dots, with a Final Time equal to the last.
  const std::string deck = write(dir / "qs.yaml", peridigm_deck(quasi_static("0.0 .25 .5  1.0 3", "    Final Time: 3.0\n")));
  const YAML::Node n = YAML::Load(convert_peridigm_deck(deck));
  ASSERT_TRUE(n["solver"]["load_times"].IsSequence());
  EXPECT_EQ(n["solver"]["load_times"].as<std::vector<double>>(), (std::vector<double>{0, 0.25, 0.5, 1.0, 3.0}));
  EXPECT_FALSE(n["solver"]["load_steps"]);
  EXPECT_FALSE(n["solver"]["end_time"]);
  // It runs: Peridigm's outputs at the listed times; the pulled point at 0.001 t_k.
  const ExodusSeries r = test::run_and_read(deck, dir, "qs.e");
  ASSERT_EQ(r.steps.size(), 5u);
  const std::size_t ux = index_of(r.layout.nodal, "DisplacementX");
  const std::vector<double> times = {0, 0.25, 0.5, 1.0, 3.0};
  for (std::size_t k = 0; k < times.size(); ++k) {
    EXPECT_EQ(r.steps[k].time, times[k]);
    EXPECT_NEAR(r.steps[k].nodal[ux][3], 0.001 * times[k], 1e-15);
  }
  // Without a Final Time the list's last time ends the solver (MultipleHorizons).
  const YAML::Node m = YAML::Load(convert_peridigm_deck(write(dir / "noend.yaml", peridigm_deck(quasi_static("0 0.1 0.5 1")))));
  EXPECT_EQ(m["solver"]["load_times"].as<std::vector<double>>(), (std::vector<double>{0, 0.1, 0.5, 1}));
  // Errors at the key's line (Time Steps is line 43 of these decks without a Final Time).
  auto bad = [&](const std::string& name, const std::string& solvers) {
    return error_of(write(dir / (name + ".yaml"), peridigm_deck(solvers)));
  };
  const std::string word = bad("word", quasi_static("0 0.5 x1"));
  EXPECT_NE(word.find("word.yaml:43:19"), std::string::npos) << word;
  EXPECT_NE(word.find("'x1' is not a number"), std::string::npos) << word;
  const std::string down = bad("down", quasi_static("0 0.5 0.25"));
  EXPECT_NE(down.find("0.25 does not come after 0.5"), std::string::npos) << down;
  EXPECT_NE(bad("single", quasi_static("0")).find("at least two times"), std::string::npos);
  EXPECT_NE(bad("late", quasi_static("0.5 1")).find("the first time 0.5 is not the solver's Initial Time 0"),
            std::string::npos);
  const std::string end = bad("end", quasi_static("0 0.5 1", "    Final Time: 2.0\n"));
  EXPECT_NE(end.find("the last time 1 is not the solver's Final Time 2"), std::string::npos) << end;
  std::string both = quasi_static("0 1");
  both.replace(both.find("      Maximum"), 0, "      Number of Load Steps: 2\n");
  EXPECT_NE(bad("both", both).find("give Time Steps or Number of Load Steps, not both"), std::string::npos);
}

TEST(LoadTimes, PeridigmSolversOfUnequalStepsBecomeOnePath) {
  const fs::path dir = test_dir();
  write(dir / "points.txt", "0 0 0 1 1\n1 0 0 1 1\n2 0 0 1 1\n3 0 0 1 1\n");
  // One load step to 1, then four to 2 (before: an error, "Horizon's load steps are
  // equal"), then a listed piece: one path through all their times.
  const std::string solvers =
      "  Solver1:\n    Initial Time: 0.0\n    Final Time: 1.0\n    QuasiStatic:\n      Number of Load Steps: 1\n"
      "  Solver2:\n    Initial Time: 1.0\n    Final Time: 2.0\n    QuasiStatic:\n      Number of Load Steps: 4\n"
      "  Solver3:\n    Initial Time: 2.0\n    QuasiStatic:\n      Time Steps: \"2.0 3.0\"\n";
  const YAML::Node n = YAML::Load(convert_peridigm_deck(write(dir / "three.yaml", peridigm_deck(solvers))));
  EXPECT_EQ(n["solver"]["load_times"].as<std::vector<double>>(),
            (std::vector<double>{0, 1, 1.25, 1.5, 1.75, 2, 3}));
}

TEST(LoadTimes, SolverStartsWriteTheStateAgain) {
  const fs::path dir = test_dir();
  // Two load steps to t = 2, a Peridigm solver starting at t = 1 (PredictorFromPreviousSolver).
  std::string deck = bar_deck("solver: {type: static, load_steps: 2, end_time: 2, solver_starts: [1], "
                              "tolerance: 1.0e-12}\n", 2.0);
  deck.replace(deck.find("[{file: bar.e}]"), 15, "[{file: bar.e}, {file: even.e, every: 2}]");
  const std::string path = write(dir / "starts.yaml", deck);
  const ExodusSeries r = test::run_and_read(path, dir, "bar.e");
  // t = 0, 1, 1 (the new solver's start), 2, as the gold's frames.
  ASSERT_EQ(r.steps.size(), 4u);
  const std::vector<double> times = {0, 1, 1, 2};
  for (std::size_t k = 0; k < 4; ++k) EXPECT_EQ(r.steps[k].time, times[k]) << k;
  const std::size_t ux = index_of(r.layout.nodal, "DisplacementX"), vx = index_of(r.layout.nodal, "VelocityX"),
                    fx = index_of(r.layout.nodal, "Force_DensityX");
  for (std::size_t i = 0; i < r.layout.points.size(); ++i) {
    const double x = r.layout.points[i].x;
    // The start state is the last step's (the same bits), at rest.
    EXPECT_EQ(r.steps[2].nodal[ux][i], r.steps[1].nodal[ux][i]) << i;
    EXPECT_EQ(r.steps[2].nodal[fx][i], r.steps[1].nodal[fx][i]) << i;
    EXPECT_EQ(r.steps[2].nodal[vx][i], 0.0) << i;
    // Around it the load steps' quasi-static velocity, kStrain x / 2.
    for (std::size_t k : {1u, 3u}) EXPECT_NEAR(r.steps[k].nodal[vx][i], kStrain * x / 2, 1e-10 * kStrain) << k;
    EXPECT_NEAR(r.steps[3].nodal[ux][i], kStrain * x, 1e-12 * kStrain) << i;
  }
  // The start counts as an output step: every 2 writes steps 0 and 2 (the start, t = 1),
  // not load step 2 (output step 3).
  const ExodusSeries e = read_exodus_series((dir / "out" / "even.e").string());
  ASSERT_EQ(e.steps.size(), 2u);
  EXPECT_EQ(e.steps[1].time, 1.0);
  EXPECT_EQ(e.steps[1].nodal[vx][5], 0.0);
  // Errors: not the end of a load step before the last; in a staged run's static stage.
  const std::string half = error_of(write(dir / "half.yaml", bar_deck("solver: {type: static, load_steps: 2, "
                                                                      "end_time: 2, solver_starts: [0.5]}\n", 2.0)));
  EXPECT_NE(half.find("half.yaml:16:"), std::string::npos) << half;
  EXPECT_NE(half.find("solver.solver_starts[0]: expected the end of a load step before the last"), std::string::npos)
      << half;
  const std::string last = error_of(write(dir / "last.yaml", bar_deck("solver: {type: static, load_times: [0, 1, 2], "
                                                                      "solver_starts: [2]}\n", 2.0)));
  EXPECT_NE(last.find("expected the end of a load step before the last"), std::string::npos) << last;
  const std::string staged = error_of(write(
      dir / "staged.yaml", bar_deck("solver:\n  - {type: static, load_steps: 2, end_time: 2, solver_starts: [1]}\n"
                                    "  - {type: explicit, end_time: 2.1, time_step: 1.0e-6}\n",
                                    2.0)));
  EXPECT_NE(staged.find("solver[0].solver_starts: not in a staged run's static stage"), std::string::npos) << staged;
  // The importer: QuasiStatic solvers in sequence give solver_starts at the later ones'
  // Initial Times.
  write(dir / "points.txt", "0 0 0 1 1\n1 0 0 1 1\n2 0 0 1 1\n3 0 0 1 1\n");
  const std::string solvers =
      "  Solver1:\n    Initial Time: 0.0\n    Final Time: 1.0\n    QuasiStatic:\n      Number of Load Steps: 1\n"
      "  Solver2:\n    Initial Time: 1.0\n    Final Time: 2.0\n    QuasiStatic:\n      Number of Load Steps: 1\n";
  const YAML::Node n = YAML::Load(convert_peridigm_deck(write(dir / "two.yaml", peridigm_deck(solvers))));
  EXPECT_EQ(n["solver"]["load_steps"].as<int>(), 2);
  EXPECT_EQ(n["solver"]["solver_starts"].as<std::vector<double>>(), (std::vector<double>{1.0}));
}

// Peridigm: a Verlet deck whose prescribed displacement is not 0 at t = 0
// (DeformationGradient_PlaneStrainCompression's x exp(0.0953 t / 1e-8)).
TEST(LoadTimes, PeridigmVerletDisplacementsMoveByTheirChangeSinceTheStart) {
  const fs::path dir = test_dir();
  write(dir / "points.txt", "0 0 0 1 1\n1 0 0 1 1\n2 0 0 1 1\n3 0 0 1 1\n");
  std::string deck = peridigm_deck("  Solver:\n    Final Time: 1.0e-5\n    Verlet:\n      Fixed dt: 1.0e-6\n");
  deck.replace(deck.find("\"0.001*t\""), 9, "\"(x+1)*exp(1.0e4*t)\"");
  const std::string path = write(dir / "verlet.yaml", deck);
  const YAML::Node n = YAML::Load(convert_peridigm_deck(path));
  // The pulled point (x = 3) moves by g(t) - g(0) through Peridigm's Verlet (its drift
  // moves a prescribed point by g(t1) - g(t0)); the text of g stays as written.
  EXPECT_EQ(n["solver"]["verlet"].as<std::string>(), "peridigm");
  EXPECT_EQ(n["loads"][2]["displacement"][0].as<std::string>(), "(x+1)*exp(1.0e4*t)");
  EXPECT_EQ(n["loads"][0]["displacement"][0].as<std::string>(), "0.0");
  const ExodusSeries r = test::run_and_read(path, dir, "qs.e");
  const std::size_t ux = index_of(r.layout.nodal, "DisplacementX");
  ASSERT_EQ(r.steps.size(), 11u);
  for (std::size_t k = 0; k < r.steps.size(); ++k)
    EXPECT_NEAR(r.steps[k].nodal[ux][3], 4 * (std::exp(1.0e4 * r.steps[k].time) - 1), 1e-14) << k;
  EXPECT_EQ(r.steps[0].nodal[ux][3], 0.0);
  // A QuasiStatic deck sets u = g(t) at its load steps: the text stays.
  const std::string qs = write(dir / "qs.yaml", deck.substr(0, deck.find("  Solver:")) +
                                                    "  Solver:\n    Final Time: 1.0\n    QuasiStatic:\n"
                                                    "      Number of Load Steps: 1\n" +
                                                    deck.substr(deck.find("  Output:")));
  EXPECT_EQ(YAML::Load(convert_peridigm_deck(qs))["loads"][2]["displacement"][0].as<std::string>(),
            "(x+1)*exp(1.0e4*t)");
}

}  // namespace
}  // namespace horizon
