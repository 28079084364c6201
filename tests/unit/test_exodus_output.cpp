// Exodus II output (output/exodus.hpp, driver/exodus_output.hpp; output.format: exodus):
// the writer's file read back by the reader gives every variable at every time exactly;
// the file is readable after each frame while the writer is still open (what an
// interrupted run leaves); a run with output.format exodus writes Peridigm's variable
// names with the initial velocities, volumes and kinetic energy of its deck.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "horizon/core/error.hpp"
#include "horizon/deck/deck.hpp"
#include "horizon/driver/run.hpp"
#include "horizon/output/exodus.hpp"

namespace horizon {
namespace {

namespace fs = std::filesystem;

TEST(ExodusOutput, WriterReadBackEveryVariableEveryTime) {
  const fs::path dir = fs::temp_directory_path() / "horizon_exodus_writer";
  fs::remove_all(dir);
  ExodusLayout layout;
  layout.points = {{0, 0, 0}, {1, 0, 0}, {2, 0.5, 0}, {3, 0, 1}, {4, 1, 1}};
  layout.block = {0, 1, 0, 1, 1};  // interleaved: elements are grouped by block in the file
  layout.block_names = {"block_1", "block_7"};
  layout.nodal = {"DisplacementX", "VelocityY", "Force_DensityZ"};
  layout.element = {"Damage", "Weighted_Volume"};
  layout.global = {"Global_Kinetic_Energy"};
  std::vector<ExodusStep> steps;
  for (int k = 0; k < 3; ++k) {
    ExodusStep s;
    s.time = 0.25 * k + 1e-7;
    for (int v = 0; v < 3; ++v) {
      s.nodal.emplace_back();
      for (int i = 0; i < 5; ++i) s.nodal.back().push_back(1.0 / (1 + i + 10 * v + 100 * k) - 0.3);
    }
    for (int v = 0; v < 2; ++v) {
      s.element.emplace_back();
      for (int i = 0; i < 5; ++i) s.element.back().push_back(std::sqrt(2.0 + i + 5 * v + 50 * k));
    }
    s.global = {3.5e-3 * (k + 1)};
    steps.push_back(s);
  }
  const std::string path = (dir / "out.e").string();
  {
    ExodusWriter w(path, layout);
    w.append(steps[0]);
    w.append(steps[1]);
    // Readable after each frame, before the writer closes (an interrupted run's file).
    const ExodusSeries partial = read_exodus_series(path);
    EXPECT_EQ(partial.steps.size(), 2u);
    w.append(steps[2]);
  }
  const ExodusSeries r = read_exodus_series(path);
  EXPECT_EQ(r.layout.points.size(), 5u);
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(r.layout.points[i].x, layout.points[i].x);
    EXPECT_EQ(r.layout.points[i].y, layout.points[i].y);
    EXPECT_EQ(r.layout.points[i].z, layout.points[i].z);
  }
  EXPECT_EQ(r.layout.block, layout.block);
  EXPECT_EQ(r.layout.block_names, layout.block_names);
  EXPECT_EQ(r.layout.nodal, layout.nodal);
  EXPECT_EQ(r.layout.element, layout.element);
  EXPECT_EQ(r.layout.global, layout.global);
  ASSERT_EQ(r.steps.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(r.steps[k].time, steps[k].time);
    EXPECT_EQ(r.steps[k].nodal, steps[k].nodal) << "step " << k;
    EXPECT_EQ(r.steps[k].element, steps[k].element) << "step " << k;
    EXPECT_EQ(r.steps[k].global, steps[k].global) << "step " << k;
  }
}

TEST(ExodusOutput, RunWritesPeridigmVariables) {
  const fs::path dir = fs::temp_directory_path() / "horizon_exodus_run";
  fs::remove_all(dir);
  const std::string deck = R"(dimension: 3
spacing: 1.0
horizon: 1.1
materials:
  steel: {model: lps, density: 7800, bulk_modulus: 130.0e9, shear_modulus: 78.0e9}
bodies:
  - name: block_3
    material: steel
    shape: {points: [[-1, 0, 0, 1.0], [0, 0, 0, 2.0], [1, 0, 0, 3.0]]}
regions:
  ends: {points: [[-1, 0, 0], [1, 0, 0]]}
initial_conditions:
  - {region: ends, velocity: ["-x", 0, 0]}
solver: {type: explicit, end_time: 5.0e-5, time_step: 1.0e-5}
output: {directory: )" + dir.string() + R"(, frames: 5, history_every: 1, format: exodus, exodus_file: bar.e}
)";
  RunOptions o;
  o.quiet = true;
  ASSERT_EQ(run_deck(parse_deck(deck, "bar.yaml"), o), 0);
  EXPECT_FALSE(fs::exists(dir / "frames" / "frame_00000.vtu"));
  const ExodusSeries r = read_exodus_series((dir / "bar.e").string());
  ASSERT_EQ(r.steps.size(), 6u);
  for (std::size_t k = 0; k < 6; ++k) EXPECT_NEAR(r.steps[k].time, 1e-5 * static_cast<double>(k), 1e-18);
  EXPECT_EQ(r.layout.block_names, (std::vector<std::string>{"block_3"}));
  auto nodal = [&](const std::string& n) {
    return static_cast<std::size_t>(std::find(r.layout.nodal.begin(), r.layout.nodal.end(), n) - r.layout.nodal.begin());
  };
  auto element = [&](const std::string& n) {
    return static_cast<std::size_t>(std::find(r.layout.element.begin(), r.layout.element.end(), n) -
                                    r.layout.element.begin());
  };
  for (const char* n : {"DisplacementX", "DisplacementZ", "VelocityX", "Force_DensityY", "ForceZ"})
    ASSERT_LT(nodal(n), r.layout.nodal.size()) << n;
  for (const char* n : {"Element_Id", "Block_Id", "Volume", "Damage", "Dilatation", "Weighted_Volume",
                        "Number_Of_Neighbors"})
    ASSERT_LT(element(n), r.layout.element.size()) << n;
  const ExodusStep& s0 = r.steps[0];
  EXPECT_EQ(s0.nodal[nodal("VelocityX")], (std::vector<double>{1, 0, -1}));  // velocity -x
  EXPECT_EQ(s0.nodal[nodal("DisplacementX")], (std::vector<double>{0, 0, 0}));
  EXPECT_EQ(s0.element[element("Volume")], (std::vector<double>{1, 2, 3}));
  EXPECT_EQ(s0.element[element("Element_Id")], (std::vector<double>{1, 2, 3}));
  EXPECT_EQ(s0.element[element("Block_Id")], (std::vector<double>{3, 3, 3}));
  EXPECT_EQ(s0.element[element("Number_Of_Neighbors")], (std::vector<double>{1, 2, 1}));
  ASSERT_EQ(r.layout.global, (std::vector<std::string>{"Global_Kinetic_Energy"}));
  EXPECT_DOUBLE_EQ(s0.global[0], 0.5 * 7800 * (1.0 * 1 + 3.0 * 1));
  // The ends move towards each other: the last step's displacements are of opposite sign.
  const auto& u = r.steps[5].nodal[nodal("DisplacementX")];
  EXPECT_GT(u[0], 0);
  EXPECT_LT(u[2], 0);
}

TEST(ExodusOutput, DeckErrors) {
  const std::string base = R"(dimension: 3
spacing: 1.0
horizon: 1.1
materials:
  steel: {model: lps, density: 7800, bulk_modulus: 130.0e9, shear_modulus: 78.0e9}
bodies:
  - {name: bar, material: steel, shape: {points: [[-1, 0, 0, 1.0], [0, 0, 0, 2.0]]}}
solver: {type: explicit, end_time: 5.0e-5, time_step: 1.0e-5}
)";
  auto error = [&](const std::string& output) {
    try {
      parse_deck(base + "output: " + output + "\n", "bar.yaml");
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error("{format: exdous}").find("bar.yaml:9:"), std::string::npos);
  EXPECT_NE(error("{exodus_file: a.e}").find("applies with format: exodus or both only"), std::string::npos);
  EXPECT_NE(error("{format: exodus, exodus_file: sub/a.e}").find("a file name"), std::string::npos);
  EXPECT_NE(error("{format: exodus, checkpoint: {every: 2}}").find("not written with checkpoints"), std::string::npos);
}

}  // namespace
}  // namespace horizon
