// The Peridigm importer's solver, output, path and node-set options that Peridigm's own
// test suite uses (docs/peridigm.md), each on a small deck written for the test: NOX's
// quasi-static options, several solvers in sequence, several output lists (each its own
// Exodus file and frequency, run and read back), files named relative to Peridigm's npN
// run folder, node-set lists counted from 0, and repeated XML parameters.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <fstream>
#include <string>

#include "horizon/core/error.hpp"
#include "horizon/deck/deck.hpp"
#include "horizon/driver/run.hpp"
#include "horizon/output/exodus.hpp"

namespace horizon {
namespace {

namespace fs = std::filesystem;

fs::path test_dir() {
  const fs::path dir = fs::temp_directory_path() / "horizon_peridigm_suite" /
                       ::testing::UnitTest::GetInstance()->current_test_info()->name();
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// Four points on the x axis, 1 apart (one block), as a Text File beside the deck.
const char* kPoints = "0 0 0 1 1\n1 0 0 1 1\n2 0 0 1 1\n3 0 0 1 1\n";

// A deck with the given Solver and Output sections (and node sets), its mesh named `mesh`.
std::string deck_text(const std::string& solver_and_output, const std::string& mesh = "points.txt",
                      const std::string& sets = "    Left: \"1\"\n    Right: \"4\"\n") {
  return "Peridigm:\n"
         "  Discretization:\n"
         "    Type: \"Text File\"\n"
         "    Input Mesh File: \"" + mesh + "\"\n"
         "  Materials:\n"
         "    Steel:\n"
         "      Material Model: \"Elastic\"\n"
         "      Density: 7800.0\n"
         "      Bulk Modulus: 130.0e9\n"
         "      Shear Modulus: 78.0e9\n"
         "  Blocks:\n"
         "    All:\n"
         "      Block Names: \"block_1\"\n"
         "      Material: \"Steel\"\n"
         "      Horizon: 1.5\n"
         "  Boundary Conditions:\n" + sets +
         "    Pull:\n"
         "      Type: \"Prescribed Displacement\"\n"
         "      Node Set: \"Right\"\n"
         "      Coordinate: \"x\"\n"
         "      Value: \"0.001*t\"\n"
         "    Hold:\n"
         "      Type: \"Prescribed Displacement\"\n"
         "      Node Set: \"Left\"\n"
         "      Coordinate: \"x\"\n"
         "      Value: \"0.0\"\n" +
         solver_and_output;
}

std::string write(const fs::path& path, const std::string& text) {
  std::ofstream(path) << text;
  return path.string();
}

YAML::Node convert(const std::string& path) { return YAML::Load(convert_peridigm_deck(path)); }

std::string error_of(const std::string& path) {
  try {
    convert_peridigm_deck(path);
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

const char* kNoxSolver =
    "  Solver:\n"
    "    Initial Time: 0.0\n"
    "    Final Time: 1.0\n"
    "    Peridigm Preconditioner: \"Block 3x3\"\n"
    "    NOXQuasiStatic:\n"
    "      Nonlinear Solver: \"Line Search Based\"\n"
    "      Number of Load Steps: 2\n"
    "      Max Solver Iterations: 40\n"
    "      Relative Tolerance: 1.0e-9\n"
    "      Max Age Of Prec: 100\n"
    "      Direction:\n"
    "        Method: \"Newton\"\n"
    "        Newton:\n"
    "          Linear Solver:\n"
    "            Jacobian Operator: \"Matrix-Free\"\n"
    "            Preconditioner: \"User Defined\"\n"
    "      Line Search:\n"
    "        Method: \"Polynomial\"\n";

TEST(PeridigmSuiteOptions, NoxQuasiStaticOptionsMapToNewton) {
  const fs::path dir = test_dir();
  write(dir / "points.txt", kPoints);
  const YAML::Node n = convert(write(dir / "nox.yaml", deck_text(kNoxSolver)));
  const YAML::Node s = n["solver"];
  EXPECT_EQ(s["type"].as<std::string>(), "static");
  EXPECT_EQ(s["method"].as<std::string>(), "newton");
  EXPECT_EQ(s["positions"].as<std::string>(), "peridigm");  // Peridigm's quasi-static rounding
  EXPECT_EQ(s["load_steps"].as<int>(), 2);
  EXPECT_EQ(s["max_iterations"].as<int>(), 40);
  EXPECT_DOUBLE_EQ(s["tolerance"].as<double>(), 1e-12);  // tighter than 1e-9: kept
  EXPECT_DOUBLE_EQ(s["end_time"].as<double>(), 1.0);
  // Nonlinear CG and a trust region are accepted as Newton; a Relative Tolerance below
  // 1e-12 tightens the native tolerance.
  std::string cg = kNoxSolver;
  cg.replace(cg.find("\"Line Search Based\""), 19, "\"Inexact Trust Region Based\"");
  cg.replace(cg.find("\"Newton\"\n        Newton"), 8, "\"NonlinearCG\"");
  cg.replace(cg.find("1.0e-9"), 6, "1.0e-14");
  const YAML::Node c = convert(write(dir / "cg.yaml", deck_text(cg)));
  EXPECT_DOUBLE_EQ(c["solver"]["tolerance"].as<double>(), 1e-14);
  // A method Horizon does not map is an error at its line.
  std::string bad = kNoxSolver;
  bad.replace(bad.find("\"Block 3x3\""), 11, "\"Block 4x4\"");
  const std::string e = error_of(write(dir / "bad.yaml", deck_text(bad)));
  EXPECT_NE(e.find("bad.yaml:32:"), std::string::npos) << e;
  EXPECT_NE(e.find("Block 3x3"), std::string::npos) << e;
  std::string tensor = kNoxSolver;
  tensor.replace(tensor.find("\"Line Search Based\""), 19, "\"Tensor Based\"");
  EXPECT_NE(error_of(write(dir / "tensor.yaml", deck_text(tensor))).find("Line Search Based"), std::string::npos);
}

TEST(PeridigmSuiteOptions, SolversInSequenceBecomeOneRun) {
  const fs::path dir = test_dir();
  write(dir / "points.txt", kPoints);
  auto quasi_static = [](const std::string& name, double t0, double t1, int steps, const std::string& extra = "") {
    return "  " + name + ":\n    Initial Time: " + std::to_string(t0) + "\n    Final Time: " + std::to_string(t1) +
           "\n" + extra + "    QuasiStatic:\n      Number of Load Steps: " + std::to_string(steps) +
           "\n      Maximum Solver Iterations: 10\n      Absolute Tolerance: 1.0e-3\n";
  };
  const YAML::Node n = convert(write(
      dir / "two.yaml",
      deck_text(quasi_static("Solver1", 0, 1, 1) +
                quasi_static("Solver2", 1, 3, 2, "    Initialize Predictor From Previous Solver: true\n"))));
  EXPECT_EQ(n["solver"]["type"].as<std::string>(), "static");
  EXPECT_EQ(n["solver"]["load_steps"].as<int>(), 3);
  EXPECT_DOUBLE_EQ(n["solver"]["end_time"].as<double>(), 3.0);
  // Pieces that are not one run are errors naming both solvers.
  const std::string gap =
      error_of(write(dir / "gap.yaml", deck_text(quasi_static("Solver1", 0, 1, 1) + quasi_static("Solver2", 2, 3, 1))));
  EXPECT_NE(gap.find("Solver2 cannot continue Solver1"), std::string::npos) << gap;
  EXPECT_NE(gap.find("Initial Time 2"), std::string::npos) << gap;
  // Load steps of other lengths: one path through their times (solver.load_times).
  const YAML::Node uneven = convert(
      write(dir / "uneven.yaml", deck_text(quasi_static("Solver1", 0, 1, 1) + quasi_static("Solver2", 1, 2, 4))));
  EXPECT_EQ(uneven["solver"]["load_times"].as<std::vector<double>>(), (std::vector<double>{0, 1, 1.25, 1.5, 1.75, 2}));
  EXPECT_FALSE(uneven["solver"]["load_steps"]);
  // (A Verlet solver after a QuasiStatic one is a staged run: tests/unit/test_staged_run.cpp.)
  const std::string mixed = error_of(write(
      dir / "mixed.yaml", deck_text("  Solver1:\n    Final Time: 1.0\n    Verlet:\n      Fixed dt: 1.0e-3\n" +
                                    quasi_static("Solver2", 1, 2, 1))));
  EXPECT_NE(mixed.find("a QuasiStatic solver after a Verlet one"), std::string::npos) << mixed;
}

TEST(PeridigmSuiteOptions, OutputListsAreExodusFilesWithTheirFrequencies) {
  const fs::path dir = test_dir();
  write(dir / "points.txt", kPoints);
  const std::string outputs =
      "  Solver:\n    Final Time: 1.0e-5\n    Verlet:\n      Fixed dt: 1.0e-6\n"
      "  Output1:\n    Output Filename: \"every_five\"\n    Output Frequency: 5\n"
      "    Output Variables:\n      Displacement: true\n"
      "  Output_2:\n    Output Filename: \"every_two\"\n    Output Frequency: 2\n"
      "    Output Variables:\n      Global_Kinetic_Energy: true\n      Velocity: true\n"
      "  Output Data:\n    Output Filename: \"every_step\"\n"
      "    Output Variables:\n      Global_Kinetic_Energy: true\n";
  const std::string deck = write(dir / "outputs.yaml", deck_text(outputs));
  const YAML::Node n = convert(deck);
  ASSERT_EQ(n["output"]["exodus_files"].size(), 3u);
  EXPECT_EQ(n["output"]["exodus_files"][1]["file"].as<std::string>(), "every_two.e");
  EXPECT_EQ(n["output"]["exodus_files"][1]["every"].as<int>(), 2);
  EXPECT_EQ(n["output"]["directory"].as<std::string>(), "out/every_five");
  EXPECT_EQ(n["output"]["history_columns"].size(), 1u);  // one Global_Kinetic_Energy column
  // A list of global variables alone is Peridigm's history file, .h.
  EXPECT_EQ(n["output"]["exodus_files"][2]["file"].as<std::string>(), "every_step.h");
  // Run it: each file holds the initial state and every N-th step, at t = n dt.
  Config c = load_deck(deck);
  c.output.directory = (dir / "out").string();
  RunOptions o;
  o.quiet = true;
  ASSERT_EQ(run_deck(c, o), 0);
  for (const auto& [file, every] : {std::pair{"every_five.e", 5}, std::pair{"every_two.e", 2}, std::pair{"every_step.h", 1}}) {
    const ExodusSeries r = read_exodus_series((dir / "out" / file).string());
    ASSERT_EQ(r.steps.size(), static_cast<std::size_t>(10 / every + 1)) << file;
    for (std::size_t k = 0; k < r.steps.size(); ++k)
      EXPECT_NEAR(r.steps[k].time, 1e-6 * static_cast<double>(k) * every, 1e-18) << file;
  }
  // Two lists writing one file is an error.
  std::string twice = outputs;
  twice.replace(twice.find("every_two"), 9, "every_five");
  EXPECT_NE(error_of(write(dir / "twice.yaml", deck_text(twice))).find("a second output list writes 'every_five.e'"),
            std::string::npos);
}

TEST(PeridigmSuiteOptions, StaticOutputListCountsLoadSteps) {
  const fs::path dir = test_dir();
  write(dir / "points.txt", kPoints);
  const std::string solver =
      "  Solver:\n    Final Time: 4.0\n    QuasiStatic:\n      Number of Load Steps: 4\n"
      "  Output:\n    Output Filename: \"qs\"\n    Output Frequency: 2\n";
  // Every point held in y and z: a line of points has no stiffness across it.
  std::string sets = "    Left: \"1\"\n    Right: \"4\"\n    All: \"1 2 3 4\"\n";
  for (const char* axis : {"y", "z"})
    sets += std::string("    Hold ") + axis + ":\n      Type: \"Prescribed Displacement\"\n      Node Set: \"All\"\n" +
            "      Coordinate: \"" + axis + "\"\n      Value: \"0.0\"\n";
  Config c = load_deck(write(dir / "qs.yaml", deck_text(solver, "points.txt", sets)));
  c.output.directory = (dir / "out").string();
  RunOptions o;
  o.quiet = true;
  ASSERT_EQ(run_deck(c, o), 0);
  const ExodusSeries r = read_exodus_series((dir / "out" / "qs.e").string());
  ASSERT_EQ(r.steps.size(), 3u);  // load steps 0, 2, 4
  EXPECT_DOUBLE_EQ(r.steps[1].time, 2.0);
  EXPECT_DOUBLE_EQ(r.steps[2].time, 4.0);
  // Peridigm's Radius (the sphere of the volume, 1 here) and the Newton iterations.
  const auto radius = std::find(r.layout.element.begin(), r.layout.element.end(), "Radius") - r.layout.element.begin();
  ASSERT_LT(static_cast<std::size_t>(radius), r.layout.element.size());
  EXPECT_DOUBLE_EQ(r.steps[0].element[static_cast<std::size_t>(radius)][0], std::cbrt(3 / (4 * std::numbers::pi)));
  ASSERT_EQ(r.layout.global, (std::vector<std::string>{"Global_Kinetic_Energy", "Nonlinear_Solver_Iterations"}));
  EXPECT_EQ(r.steps[0].global[1], 0.0);
  EXPECT_GE(r.steps[2].global[1], 1.0);
}

TEST(PeridigmSuiteOptions, FilesNamedFromPeridigmsRunFolder) {
  const fs::path dir = test_dir();
  write(dir / "points.txt", kPoints);
  write(dir / "left.txt", "# a comment line, as in Peridigm's node-set files\n1\n");
  const std::string solver = "  Solver:\n    Final Time: 1.0e-5\n    Verlet:\n      Fixed dt: 1.0e-6\n";
  // "../points.txt" from the deck's folder names nothing; from an npN/ folder below it, the
  // deck's own points.txt.
  const YAML::Node n = convert(write(dir / "up.yaml", deck_text(solver, "../points.txt",
                                                                "    Left: \"../left.txt\"\n    Right: \"4\"\n")));
  EXPECT_EQ(n["bodies"][0]["shape"]["points"].size(), 4u);
  EXPECT_EQ(n["regions"]["Left"]["points"].size(), 1u);
  // The deck's folder comes first: a file there wins.
  fs::create_directories(dir / "sub");
  write(dir / "sub" / "points.txt", "0 0 0 1 1\n1 0 0 1 1\n2 0 0 1 1\n3 0 0 1 1\n4 0 0 1 1\n");
  write(dir / "sub" / "left.txt", "1\n");
  const YAML::Node m = convert(write(dir / "sub" / "here.yaml", deck_text(solver, "points.txt")));
  EXPECT_EQ(m["bodies"][0]["shape"]["points"].size(), 5u);
  // Neither: the error names the deck's folder's candidate.
  const std::string e = error_of(write(dir / "none.yaml", deck_text(solver, "../nowhere.txt")));
  EXPECT_NE(e.find("cannot open the text-file discretisation"), std::string::npos) << e;
}

TEST(PeridigmSuiteOptions, NodeSetsCountFromZeroWhenOneHoldsZero) {
  const fs::path dir = test_dir();
  write(dir / "points.txt", kPoints);
  const std::string solver = "  Solver:\n    Final Time: 1.0e-5\n    Verlet:\n      Fixed dt: 1.0e-6\n";
  const YAML::Node one = convert(write(dir / "one.yaml", deck_text(solver)));
  EXPECT_DOUBLE_EQ(one["regions"]["Right"]["points"][0][0].as<double>(), 3.0);  // id 4: x = 3
  const YAML::Node zero =
      convert(write(dir / "zero.yaml", deck_text(solver, "points.txt", "    Left: \"0\"\n    Right: \"3\"\n")));
  EXPECT_DOUBLE_EQ(zero["regions"]["Left"]["points"][0][0].as<double>(), 0.0);   // id 0: the first point
  EXPECT_DOUBLE_EQ(zero["regions"]["Right"]["points"][0][0].as<double>(), 3.0);  // id 3: the fourth
  const std::string e = error_of(write(dir / "range.yaml", deck_text(solver, "points.txt", "    Left: \"0\"\n    Right: \"4\"\n")));
  EXPECT_NE(e.find("node id 4 is out of range: the discretisation has nodes 0 to 3"), std::string::npos) << e;
}

TEST(PeridigmSuiteOptions, RepeatedXmlParameters) {
  const fs::path dir = test_dir();
  write(dir / "points.txt", kPoints);
  auto xml = [](const std::string& repeat) {
    return std::string(
               "<ParameterList>\n"
               "  <ParameterList name=\"Discretization\">\n"
               "    <Parameter name=\"Type\" type=\"string\" value=\"Text File\"/>\n"
               "    <Parameter name=\"Input Mesh File\" type=\"string\" value=\"points.txt\"/>\n"
               "  </ParameterList>\n"
               "  <ParameterList name=\"Materials\">\n"
               "    <ParameterList name=\"Steel\">\n"
               "      <Parameter name=\"Material Model\" type=\"string\" value=\"Elastic\"/>\n"
               "      <Parameter name=\"Density\" type=\"double\" value=\"7800.0\"/>\n"
               "      <Parameter name=\"Bulk Modulus\" type=\"double\" value=\"130.0e9\"/>\n"
               "      <Parameter name=\"Shear Modulus\" type=\"double\" value=\"78.0e9\"/>\n") +
           repeat +
           "    </ParameterList>\n"
           "  </ParameterList>\n"
           "  <ParameterList name=\"Blocks\">\n"
           "    <ParameterList name=\"All\">\n"
           "      <Parameter name=\"Block Names\" type=\"string\" value=\"block_1\"/>\n"
           "      <Parameter name=\"Material\" type=\"string\" value=\"Steel\"/>\n"
           "      <Parameter name=\"Horizon\" type=\"double\" value=\"1.5\"/>\n"
           "    </ParameterList>\n"
           "  </ParameterList>\n"
           "  <ParameterList name=\"Solver\">\n"
           "    <Parameter name=\"Final Time\" type=\"double\" value=\"1.0e-5\"/>\n"
           "    <ParameterList name=\"Verlet\">\n"
           "      <Parameter name=\"Fixed dt\" type=\"double\" value=\"1.0e-6\"/>\n"
           "    </ParameterList>\n"
           "  </ParameterList>\n"
           "</ParameterList>\n";
  };
  // The same value twice is the one parameter (Peridigm's reader keeps one).
  const YAML::Node n =
      convert(write(dir / "same.xml", xml("      <Parameter name=\"Density\" type=\"double\" value=\"7800.0\"/>\n")));
  EXPECT_DOUBLE_EQ(n["materials"]["All"]["density"].as<double>(), 7800.0);
  // Two values: an error at the second, naming the first's line.
  const std::string e =
      error_of(write(dir / "two.xml", xml("      <Parameter name=\"Density\" type=\"double\" value=\"8000.0\"/>\n")));
  EXPECT_NE(e.find("two.xml:12:"), std::string::npos) << e;
  EXPECT_NE(e.find("given twice in this list with different values ('7800.0' at line 9"), std::string::npos) << e;
}

}  // namespace
}  // namespace horizon
