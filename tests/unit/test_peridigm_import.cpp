// The Peridigm importer's newer sections, each on a small deck written for the test with
// the native deck it must become: C-style function strings (and the `\{ \}` escapes of
// Peridigm's YAML decks), Contact, Compute Class Parameters and global outputs, the
// correspondence plasticity models and Rectangular_Plane bond filters; and the errors,
// with their line and column.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "horizon/core/error.hpp"
#include "horizon/core/expression.hpp"
#include "horizon/deck/deck.hpp"
#include "horizon/deck/peridigm/function_string.hpp"

namespace horizon {
namespace {

namespace fs = std::filesystem;

// A deck of two blocks of one point each (a Text File discretisation written beside it),
// with `extra` appended inside `Peridigm:` and `bc` as its Boundary Conditions.
std::string write_deck(const std::string& name, const std::string& extra, const std::string& bc = "",
                       const std::string& material = "") {
  // A folder per test: ctest runs the tests of this file in parallel processes.
  const fs::path dir = fs::temp_directory_path() / "horizon_peridigm_import" /
                       ::testing::UnitTest::GetInstance()->current_test_info()->name();
  fs::create_directories(dir);
  std::ofstream(dir / "points.txt") << "0 0 0 1 1\n1 0 0 1 1\n3 0 0 2 1\n4 0 0 2 1\n";
  const std::string mat = material.empty() ? "      Material Model: \"Elastic\"\n"
                                             "      Density: 7800.0\n"
                                             "      Bulk Modulus: 130.0e9\n"
                                             "      Shear Modulus: 78.0e9\n"
                                           : material;
  std::string text =
      "Peridigm:\n"
      "  Discretization:\n"
      "    Type: \"Text File\"\n"
      "    Input Mesh File: \"points.txt\"\n"
      "  Materials:\n"
      "    Steel:\n" +
      mat +
      "  Blocks:\n"
      "    All:\n"
      "      Block Names: \"block_1 block_2\"\n"
      "      Material: \"Steel\"\n"
      "      Horizon: 1.5\n" +
      (bc.empty() ? std::string() : "  Boundary Conditions:\n" + bc) +
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

std::string flow(const YAML::Node& n) {
  YAML::Emitter e;
  e.SetMapFormat(YAML::Flow);
  e.SetSeqFormat(YAML::Flow);
  e << n;
  return e.c_str();
}

std::string error_of(const std::string& path) {
  try {
    convert_peridigm_deck(path);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// --- function strings ---

double eval(const std::string& function_string, double t, double x = 0, double y = 0, double z = 0) {
  return Expression(peridigm::function_string_to_muparser(function_string))(t, x, y, z);
}

TEST(PeridigmImport, FunctionStringIfElse) {
  const std::string twist = " if(t <= 0.2)\\{ value = x*cos(1.5*t)-y*sin(1.5*t)-x; \\} else\\{ value = "
                            "x*cos(1.5*0.2)-y*sin(1.5*0.2)-x; \\} ";
  for (double t : {0.0, 0.1, 0.2, 0.5}) {
    const double tt = std::min(t, 0.2);
    EXPECT_DOUBLE_EQ(eval(twist, t, 2, 3), 2 * std::cos(1.5 * tt) - 3 * std::sin(1.5 * tt) - 2) << t;
  }
  // else if, locals, compound assignment, % and the <cmath> functions.
  const std::string s = "double r = sqrt(x*x + y*y); if (t < 1) { value = pow(r, 2); } else if (t < 2) "
                        "{ value = atan2(y, x); value *= 2; } else { value = fmod(7, 4) + fabs(-1) + 5 % 3; }";
  EXPECT_DOUBLE_EQ(eval(s, 0.5, 3, 4), 25.0);
  EXPECT_DOUBLE_EQ(eval(s, 1.5, 3, 4), 2 * std::atan2(4.0, 3.0));
  EXPECT_DOUBLE_EQ(eval(s, 2.5, 3, 4), 3 + 1 + 2);
  // C precedence: unary minus below ^, && below comparisons, !.
  EXPECT_DOUBLE_EQ(eval("-2^2", 0), -4.0);
  EXPECT_DOUBLE_EQ(eval("value = (t > 1 && !(t > 3)) ? 1 : 0;", 2), 1.0);
  EXPECT_DOUBLE_EQ(eval("value = (t > 1 && !(t > 3)) ? 1 : 0;", 4), 0.0);
  // A value set before an if without else keeps it on the other path.
  EXPECT_DOUBLE_EQ(eval("value = 1; if (t > 1) value = 2;", 0), 1.0);
  EXPECT_DOUBLE_EQ(eval("value = 1; if (t > 1) value = 2;", 2), 2.0);
}

TEST(PeridigmImport, FunctionStringErrorsHaveOffsets) {
  auto offset = [](const std::string& s) {
    try {
      peridigm::function_string_to_muparser(s);
    } catch (const peridigm::FunctionStringError& e) {
      return static_cast<long>(e.offset);
    }
    return -1L;
  };
  EXPECT_EQ(offset("value = foo(t);"), 8);          // unknown function
  EXPECT_EQ(offset("value = r;"), 8);               // unknown name
  EXPECT_EQ(offset("if (t > 1) { value = 1; }"), 13);  // set on one path only
  EXPECT_EQ(offset("value = (t;"), 10);             // missing ')'
  EXPECT_EQ(offset("x = 1; value = x;"), 0);        // inputs are read-only
}

TEST(PeridigmImport, YamlBraceEscapesKeepColumns) {
  // `\{` is a YAML error; each becomes " {" so the rest keeps its column.
  const std::string bc = "    Left: \"1\"\n"
                         "    D:\n"
                         "      Type: \"Prescribed Displacement\"\n"
                         "      Node Set: \"Left\"\n"
                         "      Coordinate: \"x\"\n"
                         "      Value: \" if(t <= 0.2)\\{ value = 1000*t; \\} else\\{ value = 200; \\} \"\n";
  const YAML::Node n = convert(write_deck("braces.yaml", "", bc));
  EXPECT_EQ(n["loads"][0]["displacement"][0].as<std::string>(), "(((t)<=0.2)?(1000*(t)):200)");
  EXPECT_EQ(n["loads"][0]["region"].as<std::string>(), "Left");
  // A mistake inside the string is reported at its own line and column in the deck.
  const std::string bad = "    Left: \"1\"\n"
                          "    D:\n"
                          "      Type: \"Prescribed Displacement\"\n"
                          "      Node Set: \"Left\"\n"
                          "      Coordinate: \"x\"\n"
                          "      Value: \" if(t <= 0.2)\\{ value = atan3(t); \\} else\\{ value = 200; \\} \"\n";
  const std::string e = error_of(write_deck("braces_bad.yaml", "", bad));
  EXPECT_NE(e.find("braces_bad.yaml:22:39: error:"), std::string::npos) << e;
  EXPECT_NE(e.find("unknown function 'atan3'"), std::string::npos) << e;
}

// --- contact ---

TEST(PeridigmImport, ContactInteractionsBecomePeridigmLaw) {
  const std::string contact = "  Contact:\n"
                              "    Search Radius: 0.01\n"
                              "    Search Frequency: 100\n"
                              "    Models:\n"
                              "      My Model:\n"
                              "        Contact Model: \"Short Range Force\"\n"
                              "        Contact Radius: 0.000775\n"
                              "        Spring Constant: 1.0e12\n"
                              "        Friction Coefficient: 0.3\n"
                              "    Interactions:\n"
                              "      Disk with Ball:\n"
                              "        First Block: \"block_1\"\n"
                              "        Second Block: \"block_2\"\n"
                              "        Contact Model: \"My Model\"\n";
  const YAML::Node n = convert(write_deck("contact.yaml", contact));
  // Both blocks named: every pair (Contact_Perforation's gold: a block touches itself too);
  // Peridigm's search radius and frequency kept.
  EXPECT_EQ(flow(n["contact"]),
            "{short_range: {law: peridigm, contact_radius: 0.000775, spring_constant: 1000000000000, friction: 0.3, "
            "search_radius: 0.01, search_every: 100}}");
  const Config c = parse_deck(convert_peridigm_deck(write_deck("contact.yaml", contact)), "c.yaml");
  EXPECT_EQ(c.contact.short_range.law, ShortRangeLaw::peridigm);
  EXPECT_TRUE(c.contact.short_range.pairs.empty());
  EXPECT_EQ(c.contact.short_range.search_radius, 0.01);
  EXPECT_EQ(c.contact.short_range.search_every, 100);
  // One block named of two: its self-contact alone.
  std::string self = contact;
  self.replace(self.find("\"block_2\""), 9, "\"block_1\"");
  EXPECT_EQ(flow(convert(write_deck("self.yaml", self))["contact"]["short_range"]["pairs"]), "[[block_1, block_1]]");
  // A search radius below the contact radius would miss touching pairs.
  std::string small = contact;
  small.replace(small.find("Search Radius: 0.01"), 19, "Search Radius: 0.0005");
  EXPECT_NE(error_of(write_deck("small.yaml", small)).find("must be at least the Contact Radius"), std::string::npos)
      << error_of(write_deck("small.yaml", small));
  // General Contact: every pair.
  std::string general = contact.substr(0, contact.find("      Disk with Ball")) +
                        "      General Contact:\n        Contact Model: \"My Model\"\n";
  EXPECT_FALSE(convert(write_deck("general.yaml", general))["contact"]["short_range"]["pairs"]);
  // A block the discretisation does not have, and a coefficient that varies in time.
  std::string wrong = contact;
  wrong.replace(wrong.find("\"block_2\""), 9, "\"block_7\"");
  EXPECT_NE(error_of(write_deck("wrong.yaml", wrong)).find("wrong.yaml:32:23: error:"), std::string::npos)
      << error_of(write_deck("wrong.yaml", wrong));
  // Omit Bonds Between Blocks: All keeps the blocks apart but for contact.
  {
    std::string path = write_deck("omit.yaml", contact), text;
    std::ifstream in(path);
    text.assign(std::istreambuf_iterator<char>(in), {});
    text.insert(text.find("  Materials:"), "    Omit Bonds Between Blocks: \"All\"\n");
    std::ofstream(path) << text;
    EXPECT_FALSE(convert(path)["bonds_between_bodies"].as<bool>());
    text.replace(text.find("\"All\""), 5, "\"Some\"");
    std::ofstream(path) << text;
    EXPECT_NE(error_of(path).find("None, All; found 'Some'"), std::string::npos) << error_of(path);
  }
  // A coefficient that varies in time (Time Dependent Short Range Force): its translation.
  std::string timed = contact;
  timed.replace(timed.find("0.3"), 3, "\"if(t < 1)\\{ value = 1; \\} else\\{ value = 0; \\}\"");
  const YAML::Node tn = convert(write_deck("timed.yaml", timed));
  EXPECT_EQ(tn["contact"]["short_range"]["friction"].as<std::string>(), "(((t)<1)?1:0)");
  const Config tc = parse_deck(convert_peridigm_deck(write_deck("timed.yaml", timed)), "t.yaml");
  ASSERT_TRUE(tc.contact.short_range.friction_in_time.has_value());
  EXPECT_EQ((*tc.contact.short_range.friction_in_time)(0.5), 1.0);
  EXPECT_EQ((*tc.contact.short_range.friction_in_time)(1.5), 0.0);
  // A string that does not set value on every path is an error naming the key.
  timed = contact;
  timed.replace(timed.find("0.3"), 3, "\"if(t < 1)\\{ value = 1; \\}\"");
  EXPECT_NE(error_of(write_deck("timed.yaml", timed)).find("cannot read the friction coefficient"), std::string::npos)
      << error_of(write_deck("timed.yaml", timed));
}

// --- compute classes and globals ---

TEST(PeridigmImport, ComputeClassesBecomeHistoryColumns) {
  const std::string bc = "    Probe Set: \"3 4\"\n";
  const std::string computes = "  Compute Class Parameters:\n"
                               "    Gage:\n"
                               "      Compute Class: \"Nearest_Point_Data\"\n"
                               "      X: 0.9\n"
                               "      Y: 0.0\n"
                               "      Z: 0.0\n"
                               "      Variable: \"Displacement\"\n"
                               "      Output Label: \"Gage_Displacement\"\n"
                               "      Verbose: true\n"
                               "    Reaction:\n"
                               "      Compute Class: \"Block_Data\"\n"
                               "      Calculation Type: \"Sum\"\n"
                               "      Block: \"block_2\"\n"
                               "      Variable: \"Force\"\n"
                               "      Output Label: \"Reaction\"\n"
                               "    Largest Volume:\n"
                               "      Compute Class: \"Node_Set_Data\"\n"
                               "      Calculation Type: \"Maximum\"\n"
                               "      Node Set: \"Probe Set\"\n"
                               "      Variable: \"Volume\"\n"
                               "      Output Label: \"Max_Volume\"\n"
                               "  Output:\n"
                               "    Output Filename: \"probes\"\n"
                               "    Output Frequency: 1\n"
                               "    Output Variables:\n"
                               "      Displacement: true\n"
                               "      Gage_Displacement: true\n"
                               "      Global_Kinetic_Energy: true\n"
                               "      Global_Linear_Momentum: true\n"
                               "      Global_Strain_Energy: false\n";
  const YAML::Node n = convert(write_deck("computes.yaml", computes, bc));
  EXPECT_EQ(flow(n["output"]["history_columns"]),
            "[{name: Global_Kinetic_Energy, quantity: kinetic_energy}, {name: Global_Linear_Momentum, quantity: "
            "linear_momentum}, {name: Gage_Displacement, quantity: displacement, nearest: [0.9, 0, 0]}, {name: "
            "Reaction, quantity: force, body: block_2, reduce: sum}, {name: Max_Volume, quantity: volume, region: "
            "Probe Set, reduce: max}]");
  EXPECT_EQ(flow(n["regions"]["Probe Set"]), "{points: [[3, 0, 0], [4, 0, 0]]}");
  // Von_Mises_Stress is the models' field of that name.
  std::string stress = computes;
  stress.replace(stress.find("\"Force\""), 7, "\"Von_Mises_Stress\"");
  EXPECT_EQ(flow(convert(write_deck("computes_vm.yaml", stress, bc))["output"]["history_columns"][3]),
            "{name: Reaction, field: von_mises_stress, body: block_2, reduce: sum}");
  // Surface_Correction_Factor is the shear correction's field (material/shear_correction.hpp).
  std::string factor = computes;
  factor.replace(factor.find("\"Force\""), 7, "\"Surface_Correction_Factor\"");
  EXPECT_EQ(flow(convert(write_deck("computes_scf.yaml", factor, bc))["output"]["history_columns"][3]),
            "{name: Reaction, field: shear_correction_factor, body: block_2, reduce: sum}");
  // An unknown variable is an error at its place.
  std::string wrong = computes;
  wrong.replace(wrong.find("\"Force\""), 7, "\"Neighborhood_Volume\"");
  const std::string e = error_of(write_deck("computes_bad.yaml", wrong, bc));
  EXPECT_NE(e.find("computes_bad.yaml:"), std::string::npos) << e;
  EXPECT_NE(e.find("Neighborhood_Volume"), std::string::npos) << e;
  // Peridigm's JIntegral class (PrecrackJIntegral) is refused as a class, its keys read.
  const std::string j = error_of(write_deck("computes_j.yaml", "  Compute Class Parameters:\n"
                                                                "    J Integral:\n"
                                                                "      Compute Class: \"JIntegral\"\n"
                                                                "      Block ID: 1\n"
                                                                "      dt: 1.0\n"));
  EXPECT_NE(j.find("computes_j.yaml:"), std::string::npos) << j;
  EXPECT_NE(j.find("JIntegral compute class is not mapped: Horizon computes no J-integral"), std::string::npos) << j;
}

// --- materials and bond filters ---

TEST(PeridigmImport, CorrespondencePlasticity) {
  const std::string mat = "      Material Model: \"Isotropic Hardening Correspondence\"\n"
                          "      Density: 7800.0\n"
                          "      Young's Modulus: 200.0e9\n"
                          "      Poisson's Ratio: 0.3\n"
                          "      Yield Stress: 250.0e6\n"
                          "      Hardening Modulus: 1.0e9\n"
                          "      Hourglass Coefficient: 0.02\n"
                          "      Enable Flaw: false\n"
                          "      Flaw Size: 0.1\n";
  const YAML::Node n = convert(write_deck("ihc.yaml", "", "", mat));
  EXPECT_EQ(flow(n["materials"]["All"]),
            "{model: correspondence, stress_law: hypoelastic_j2, plastic_return: peridigm, rotation_update: peridigm, "
            "stabilization_form: peridigm, "
            "stabilization: 0.02, "
            "yield_stress: 250000000, hardening_modulus: 1000000000, density: 7800, youngs_modulus: 200000000000, "
            "poissons_ratio: 0.29999999999999999, influence: constant}");
  // Enable Flaw needs the flaw's centre (its other keys too).
  std::string flaw = mat;
  flaw.replace(flaw.find("false"), 5, "true");
  const std::string e = error_of(write_deck("flaw.yaml", "", "", flaw));
  EXPECT_NE(e.find("Flaw Location X"), std::string::npos) << e;
  std::string epc = "      Material Model: \"Elastic Plastic Correspondence\"\n"
                    "      Density: 7800.0\n"
                    "      Young's Modulus: 200.0e9\n"
                    "      Poisson's Ratio: 0.3\n"
                    "      Yield Stress: 250.0e6\n"
                    "      Hardening Modulus: 1.0e9\n";
  // Hardening Modulus is not a key of Elastic Plastic Correspondence.
  EXPECT_NE(error_of(write_deck("epc.yaml", "", "", epc)).find("not a parameter of Material Model"), std::string::npos);
}

TEST(PeridigmImport, ShearCorrectionFactor) {
  // Apply Shear Correction Factor: shear_correction of lps and elastic_plastic
  // (material/shear_correction.hpp); another model's is an error at the key.
  const std::string elastic = "      Material Model: \"Elastic\"\n"
                              "      Density: 2200.0\n"
                              "      Bulk Modulus: 14.9e9\n"
                              "      Shear Modulus: 8.94e9\n"
                              "      Apply Shear Correction Factor: true\n";
  EXPECT_EQ(flow(convert(write_deck("scf.yaml", "", "", elastic))["materials"]["All"]),
            "{model: lps, density: 2200, bulk_modulus: 14900000000, shear_modulus: 8940000000, shear_correction: true, "
            "influence: constant}");
  std::string plastic = elastic;
  plastic.replace(plastic.find("\"Elastic\""), 9, "\"Elastic Plastic\"");
  plastic += "      Yield Stress: 1.0e8\n";
  EXPECT_EQ(flow(convert(write_deck("scf_ep.yaml", "", "", plastic))["materials"]["All"]["shear_correction"]), "true");
  std::string bond = elastic;
  bond.replace(bond.find("\"Elastic\""), 9, "\"Elastic Bond Based\"");
  const std::string e = error_of(write_deck("scf_bb.yaml", "", "", bond));
  EXPECT_NE(e.find("scf_bb.yaml:"), std::string::npos) << e;
  EXPECT_NE(e.find("Apply Shear Correction Factor: a shear correction of the Elastic and Elastic Plastic materials"),
            std::string::npos)
      << e;
}

TEST(PeridigmImport, RectangularPlaneBondFilterIsAPrecrack) {
  // PrecrackedPlate's filter: normal +y, bottom +x from (-10, 0, -10), 10 by 20.
  std::string path = write_deck("filter.yaml", "");
  std::string text;
  {
    std::ifstream in(path);
    text.assign(std::istreambuf_iterator<char>(in), {});
  }
  const std::string filter = "    Bond Filters:\n"
                             "      My Filter:\n"
                             "        Type: \"Rectangular_Plane\"\n"
                             "        Normal_X: 0.0\n        Normal_Y: 1.0\n        Normal_Z: 0.0\n"
                             "        Lower_Left_Corner_X: -10.0\n        Lower_Left_Corner_Y: 0.0\n"
                             "        Lower_Left_Corner_Z: -10.0\n"
                             "        Bottom_Unit_Vector_X: 1.0\n        Bottom_Unit_Vector_Y: 0.0\n"
                             "        Bottom_Unit_Vector_Z: 0.0\n"
                             "        Bottom_Length: 10\n        Side_Length: 20\n";
  text.insert(text.find("  Materials:"), filter);
  std::ofstream(path) << text;
  EXPECT_EQ(flow(convert(path)["precracks"]),
            "[{rectangle: {corner: [-10, 0, -10], normal: [0, 1, 0], bottom: [1, 0, 0], bottom_length: 10, "
            "side_length: 20}}]");
  // A bottom vector with a part along the normal (PrecrackedPlateTwoCracks): kept as given,
  // Peridigm's test weighs it (docs/peridigm.md "Round-off").
  text.replace(text.find("Bottom_Unit_Vector_Y: 0.0"), 25, "Bottom_Unit_Vector_Y: 4.0");
  std::ofstream(path) << text;
  EXPECT_EQ(flow(convert(path)["precracks"]),
            "[{rectangle: {corner: [-10, 0, -10], normal: [0, 1, 0], bottom: [1, 4, 0], bottom_length: 10, "
            "side_length: 20}}]");
  text.replace(text.find("Rectangular_Plane"), 17, "Disk");
  std::ofstream(path) << text;
  // A Disk filter reads its own keys (test_peridigm_filters.cpp): the rectangle's are errors.
  EXPECT_NE(error_of(path).find("Lower_Left_Corner_X"), std::string::npos) << error_of(path);
}

}  // namespace
}  // namespace horizon
