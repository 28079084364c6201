// The Peridigm importer's Pals, Linear LPS Partial Volume and Elastic Partial Volume
// materials (docs/peridigm.md), each on a small deck written for the test with the native
// material it must become, and the errors with their line and column; and a Pals deck run
// through to an Exodus file with Pals' own variables (Lagrange_Multiplier_*, ...).
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "horizon/core/error.hpp"
#include "horizon/deck/deck.hpp"

namespace horizon {
namespace {

namespace fs = std::filesystem;

// Eight points of a 2 x 2 x 2 cube of side 1 (one block, a Text File beside the deck)
// and the given material.
std::string write_deck(const std::string& name, const std::string& material, const std::string& extra = "") {
  const fs::path dir = fs::temp_directory_path() / "horizon_peridigm_pals" /
                       ::testing::UnitTest::GetInstance()->current_test_info()->name();
  fs::create_directories(dir);
  std::ofstream pts(dir / "points.txt");
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) pts << i << " " << j << " " << k << " 1 1\n";
  pts.close();
  const std::string text = "Peridigm:\n"
                           "  Discretization:\n"
                           "    Type: \"Text File\"\n"
                           "    Input Mesh File: \"points.txt\"\n"
                           "  Materials:\n"
                           "    Steel:\n" +
                           material +
                           "      Density: 7800.0\n"
                           "      Bulk Modulus: 130.0e9\n"
                           "      Shear Modulus: 78.0e9\n"
                           "  Blocks:\n"
                           "    All:\n"
                           "      Block Names: \"block_1\"\n"
                           "      Material: \"Steel\"\n"
                           "      Horizon: 1.5\n"
                           "  Solver:\n"
                           "    Final Time: 1.0e-5\n"
                           "    Verlet:\n"
                           "      Fixed dt: 1.0e-6\n" +
                           extra;
  const fs::path path = dir / name;
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
  return "";
}

TEST(PeridigmPals, PalsWithItsInfluenceFunctions) {
  const YAML::Node n = convert(write_deck("pals.yaml",
                                          "      Material Model: Pals\n"
                                          "      Dilatation Influence Function: One\n"
                                          "      Deviatoric Influence Function: \"1.0/zeta\"\n"
                                          "      Hourglass Coefficient: 0.02\n"));
  const YAML::Node m = n["materials"]["All"];
  EXPECT_EQ(m["model"].as<std::string>(), "pals");
  EXPECT_EQ(m["dilatation_influence"].as<std::string>(), "constant");
  EXPECT_EQ(m["deviatoric_influence"].as<std::string>(), "inverse_length");
  EXPECT_FALSE(m["stabilization"]);  // Hourglass Coefficient: read, no effect
  // Defaults: the deck's influence function (One).
  const YAML::Node d = convert(write_deck("plain.yaml", "      Material Model: \"Pals\"\n"));
  EXPECT_EQ(d["materials"]["All"]["model"].as<std::string>(), "pals");
  EXPECT_FALSE(d["materials"]["All"]["dilatation_influence"]);
  // An influence function Horizon does not map: the error names the key's line.
  const std::string e = error_of(write_deck("parabolic.yaml", "      Material Model: Pals\n"
                                                              "      Dilatation Influence Function: Parabolic Decay\n"));
  EXPECT_NE(e.find("parabolic.yaml:8:38:"), std::string::npos) << e;
  EXPECT_NE(e.find("Dilatation Influence Function: expected One or \"1.0/zeta\""), std::string::npos) << e;
  // The influence functions belong to Pals.
  const std::string other = error_of(write_deck("elastic.yaml", "      Material Model: Elastic\n"
                                                                "      Deviatoric Influence Function: One\n"));
  EXPECT_NE(other.find("not a parameter of Material Model 'Elastic'"), std::string::npos) << other;
}

TEST(PeridigmPals, PartialVolumeModels) {
  EXPECT_EQ(convert(write_deck("llps.yaml", "      Material Model: \"Linear LPS Partial Volume\"\n"))["materials"]["All"]
                ["model"]
                    .as<std::string>(),
            "linear_lps");
  EXPECT_EQ(convert(write_deck("epv.yaml", "      Material Model: \"Elastic Partial Volume\"\n"))["materials"]["All"]
                ["model"]
                    .as<std::string>(),
            "lps");
}

TEST(PeridigmPals, PalsVariablesAreExodusFileVariables) {
  const YAML::Node n = convert(write_deck("vars.yaml", "      Material Model: Pals\n",
                                          "  Output:\n"
                                          "    Output Filename: vars\n"
                                          "    Output Frequency: 5\n"
                                          "    Output Variables:\n"
                                          "      Displacement: true\n"
                                          "      Lagrange_Multiplier_Dilatation_1: true\n"
                                          "      Deviatoric_Normalization: true\n"));
  const YAML::Node vars = n["output"]["exodus_files"][0]["variables"];
  ASSERT_TRUE(vars && vars.IsSequence());
  ASSERT_EQ(vars.size(), 2u);
  EXPECT_EQ(vars[0].as<std::string>(), "Lagrange_Multiplier_Dilatation_1");
  EXPECT_EQ(vars[1].as<std::string>(), "Deviatoric_Normalization");
}

}  // namespace
}  // namespace horizon
