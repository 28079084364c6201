// Thermal expansion in imported Peridigm decks (docs/peridigm.md, "Thermal Expansion
// Coefficient") and the native prescribed temperature field it maps to (thermal.conduction:
// false, docs/input.md): the mapping itself, a free cube heated in a quasi-static run against
// the closed form u = alpha dT (x - x_0) (Kilic and Madenci 2010: the bond's mechanical
// stretch s - alpha dT vanishes), a bond held at both ends that a cooling breaks when
// alpha |dT| reaches the critical stretch, and the errors.
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

fs::path test_dir() { return test::fresh_test_dir("horizon_peridigm_thermal"); }
using test::write;
using test::error_of;
using test::run_and_read;
using test::index_of;

// A 3 x 3 x 3 PdQuickGrid cube (spacing 1, centres -1, 0, 1), the rigid-body modes held as
// in Peridigm's ThermalExpansionCube (node 1 at (-1, -1, -1) fixed, the three axes through
// it held across), the whole body at T = 273 + 1000 t; `extra_bcs` adds conditions.
std::string cube_deck(const std::string& material, const std::string& extra_bcs, const std::string& solver) {
  std::string all;
  for (int i = 1; i <= 27; ++i) all += (i > 1 ? " " : "") + std::to_string(i);
  std::string bcs = "    X Axis: \"1 2 3\"\n    Y Axis: \"1 4 7\"\n    Z Axis: \"1 10 19\"\n    All: \"" + all + "\"\n";
  for (const auto& [set, axes] : {std::pair{"X Axis", "yz"}, std::pair{"Y Axis", "xz"}, std::pair{"Z Axis", "xy"}})
    for (const char* a = axes; *a; ++a)
      bcs += std::string("    Hold ") + set + " " + *a + ": {Type: \"Prescribed Displacement\", Node Set: \"" + set +
             "\", Coordinate: \"" + *a + "\", Value: \"0.0\"}\n";
  bcs += "    Heat: {Type: \"Prescribed Temperature\", Node Set: \"All\", Value: \"273.0+1000.0*t\"}\n" + extra_bcs;
  return "Peridigm:\n"
         "  Discretization:\n"
         "    Type: \"PdQuickGrid\"\n"
         "    NeighborhoodType: \"Spherical\"\n"
         "    TensorProduct3DMeshGenerator:\n"
         "      Type: \"PdQuickGrid\"\n"
         "      X Origin: -1.5\n      Y Origin: -1.5\n      Z Origin: -1.5\n"
         "      X Length: 3.0\n      Y Length: 3.0\n      Z Length: 3.0\n"
         "      Number Points X: 3\n      Number Points Y: 3\n      Number Points Z: 3\n"
         "  Materials:\n"
         "    Steel: {" + material + "}\n"
         "  Blocks:\n"
         "    All: {Block Names: \"block_1\", Material: \"Steel\", Horizon: 1.75}\n"
         "  Boundary Conditions:\n" + bcs + solver +
         "  Output:\n"
         "    Output Filename: \"cube\"\n"
         "    Output Frequency: 1\n"
         "    Output Variables: {Displacement: true, Temperature: true, Temperature_Change: true}\n";
}

const char* kSteel = "Density: 7800.0, Bulk Modulus: 130.0e9, Shear Modulus: 78.0e9, "
                     "Thermal Expansion Coefficient: 1.0e-5";
const std::string kElasticSteel = std::string("Material Model: \"Elastic\", ") + kSteel;
const char* kQuasiStatic = "  Solver:\n    Final Time: 1.0\n    QuasiStatic:\n      Number of Load Steps: 2\n";

TEST(PeridigmThermal, ExpansionAndPrescribedTemperatureMapToAPrescribedField) {
  const fs::path dir = test_dir();
  const std::string deck = write(dir / "cube.yaml", cube_deck(kElasticSteel, "", kQuasiStatic));
  const YAML::Node native = YAML::Load(convert_peridigm_deck(deck));
  const YAML::Node mat = native["materials"]["All"];
  EXPECT_EQ(mat["thermal"]["expansion"].as<double>(), 1.0e-5);
  EXPECT_EQ(mat["thermal"]["reference_temperature"].as<std::string>(), "initial");
  const YAML::Node th = native["thermal"];
  ASSERT_TRUE(th.IsMap());
  EXPECT_FALSE(th["conduction"].as<bool>());
  EXPECT_EQ(th["initial_temperature"].as<double>(), 0.0);
  ASSERT_EQ(th["boundary"].size(), 1u);
  EXPECT_EQ(th["boundary"][0]["region"].as<std::string>(), "All");
  EXPECT_EQ(th["boundary"][0]["temperature"].as<std::string>(), "273.0+1000.0*t");
  EXPECT_EQ(native["regions"]["All"]["points"].size(), 27u);
}

// Free expansion: every bond's stretch is alpha dT, its mechanical stretch 0, so the cube
// is at rest without force at u = alpha (T - T(0)) (x - x_1) (Kilic and Madenci 2010;
// docs/models/heat.md). T(0) = 273 is the reference (Peridigm's Temperature_Change).
// The LPS (Elastic). The correspondence model (Elastic Correspondence) keeps Peridigm's
// rate form, which takes each load step's thermal strain increment out of its strain
// increment dt d = (F - F_n) F^-1: stress-free when F = F_n / (1 - alpha dT_step), so after
// k steps u = ((1 - alpha dT_step)^-k - 1)(x - x_1) (ThermalExpansionCubeElasticCorrespondence's
// gold: 0.999^-n; `rate_form`).
void free_cube(const std::string& material, bool rate_form = false) {
  const fs::path dir = test_dir();
  // Peridigm's iteration limit of ThermalExpansionCubeElasticCorrespondence, which the
  // importer raises to 30: Horizon's Newton, to 1e-12 with a finite-difference tangent,
  // needs more here, and a cut step would change the rate form's answer.
  const std::string solver = rate_form ? std::string(kQuasiStatic) + "      Maximum Solver Iterations: 10\n" : kQuasiStatic;
  const std::string deck = write(dir / "cube.yaml", cube_deck(material, "", solver));
  const ExodusSeries r = run_and_read(deck, dir, "cube.e");
  ASSERT_EQ(r.steps.size(), 3u);
  const std::size_t T = index_of(r.layout.nodal, "Temperature"), dT = index_of(r.layout.nodal, "Temperature_Change");
  const std::size_t ux = index_of(r.layout.nodal, "DisplacementX"), fx = index_of(r.layout.nodal, "Force_DensityX");
  for (std::size_t k = 0; k < 3; ++k) {
    const double t = 0.5 * static_cast<double>(k), change = 1000.0 * t;
    for (std::size_t i = 0; i < 27; ++i) {
      EXPECT_DOUBLE_EQ(r.steps[k].nodal[T][i], 273.0 + change);
      EXPECT_NEAR(r.steps[k].nodal[dT][i], change, 1e-12);
      for (int c = 0; c < 3; ++c) {
        const double stretch = rate_form ? std::pow(1.0 - 1.0e-5 * 500.0, -static_cast<double>(k)) - 1.0 : 1.0e-5 * change;
        const double expected = stretch * (r.layout.points[i][c] + 1.0);
        EXPECT_NEAR(r.steps[k].nodal[ux + static_cast<std::size_t>(c)][i], expected, 1e-12) << k << " " << i;
        // At rest without force: the forces are round-off of the bulk modulus's 1e11.
        EXPECT_NEAR(r.steps[k].nodal[fx + static_cast<std::size_t>(c)][i], 0.0, 1e-2);
      }
    }
  }
  // The ledger closes against the thermal load's own scale (Ledger::thermal_scale: the
  // energy its strain stores in the held body), not against its round-off thermal work.
  const YAML::Node summary = YAML::LoadFile((dir / "out" / "summary.json").string());
  EXPECT_LT(summary["energy"]["max_abs_balance_error"].as<double>(), 1e-6);
  EXPECT_EQ(summary["solver"]["step_cuts"].as<int>(), 0);
}

TEST(PeridigmThermal, FreeCubeExpandsByAlphaDeltaTInAQuasiStaticRun) {
  free_cube(std::string("Material Model: \"Elastic\", ") + kSteel);
}

// Elastic Plastic Correspondence with expansion takes the total form j2 (Peridigm's
// refuses the key): the multiplicative split F = F_e (1 + alpha dT) I, stress-free at this
// F, which the nonlocal gradient of a homogeneous deformation gives exactly.
TEST(PeridigmThermal, FreeCorrespondenceCubeExpandsByAlphaDeltaT) {
  free_cube(std::string("Material Model: \"Elastic Plastic Correspondence\", Yield Stress: 1.0e12, ") + kSteel);
}

TEST(PeridigmThermal, FreeCorrespondenceCubeExpandsInRateForm) {
  free_cube(std::string("Material Model: \"Elastic Correspondence\", Hourglass Coefficient: 0.05, ") + kSteel, true);
}

// Two points bonded along y, both held, cooled as T = 10 - 2.1e5 t from T(0) = 10 by Verlet
// steps of 1e-3: the bond's mechanical stretch is -alpha dT = 2.1 t, and it breaks at the
// first step where that exceeds the critical stretch 0.05 (t = 0.024: 0.0504; at 0.023 it
// is 0.0483). Its Damage is then 1 (ThermalExpansionBondFailure, in small).
TEST(PeridigmThermal, HeldBondBreaksWhenTheCoolingStretchesIt) {
  const fs::path dir = test_dir();
  write(dir / "points.txt", "0 0 0 1 1\n0 1 0 1 1\n");
  auto deck_text = [](const std::string& damage_alpha) {
    std::string bcs = "    Both: \"1 2\"\n"
                      "    Cool: {Type: \"Prescribed Temperature\", Node Set: \"Both\", Value: \"10.0 - 2.1e5*t\"}\n";
    for (const char* a : {"x", "y", "z"})
      bcs += std::string("    Hold ") + a + ": {Type: \"Prescribed Displacement\", Node Set: \"Both\", Coordinate: \"" +
             a + "\", Value: \"0.0\"}\n";
    return "Peridigm:\n"
           "  Discretization:\n    Type: \"Text File\"\n    Input Mesh File: \"points.txt\"\n"
           "  Materials:\n    Steel: {Material Model: \"Elastic\", Density: 7800.0, Bulk Modulus: 130.0e9, "
           "Shear Modulus: 60.0e9, Thermal Expansion Coefficient: 1.0e-5}\n"
           "  Damage Models:\n    Stretch: {Damage Model: \"Critical Stretch\", Critical Stretch: 0.05, "
           "Thermal Expansion Coefficient: " + damage_alpha + "}\n"
           "  Blocks:\n    All: {Block Names: \"block_1\", Material: \"Steel\", Damage Model: \"Stretch\", "
           "Horizon: 1.5}\n"
           "  Boundary Conditions:\n" + bcs +
           "  Solver:\n    Final Time: 0.03\n    Verlet:\n      Fixed dt: 1.0e-3\n"
           "  Output:\n    Output Filename: \"bond\"\n    Output Frequency: 1\n"
           "    Output Variables: {Damage: true, Temperature_Change: true}\n";
  };
  const std::string deck = write(dir / "bond.yaml", deck_text("1.0e-5"));
  const ExodusSeries r = run_and_read(deck, dir, "bond.e");
  ASSERT_GE(r.steps.size(), 29u);
  const std::size_t damage = index_of(r.layout.element, "Damage"), dT = index_of(r.layout.nodal, "Temperature_Change");
  for (std::size_t k = 0; k < r.steps.size(); ++k) {
    const double t = r.steps[k].time;
    EXPECT_NEAR(t, 1e-3 * static_cast<double>(k), 1e-15);
    EXPECT_NEAR(r.steps[k].nodal[dT][0], -2.1e5 * t, 1e-9);
    EXPECT_EQ(r.steps[k].element[damage][0], k >= 24 ? 1.0 : 0.0) << k;
  }
  // The damage model's coefficient must be the material's (Horizon's bonds break on the
  // mechanical stretch of the material's thermal strain).
  const std::string other = write(dir / "other.yaml", deck_text("2.0e-5"));
  const std::string e = error_of(other);
  EXPECT_NE(e.find("other.yaml:"), std::string::npos) << e;
  EXPECT_NE(e.find("differs from the block's material's Thermal Expansion Coefficient"), std::string::npos) << e;
}

TEST(PeridigmThermal, InitialTemperatureOfPartOfTheBodyIsAnError) {
  const fs::path dir = test_dir();
  const std::string deck = write(
      dir / "part.yaml",
      cube_deck(kElasticSteel, "    Corner: \"1\"\n    Warm: {Type: \"Initial Temperature\", Node Set: \"Corner\", Value: \"300.0\"}\n",
                kQuasiStatic));
  const std::string e = error_of(deck);
  EXPECT_NE(e.find("part.yaml:"), std::string::npos) << e;
  EXPECT_NE(e.find("holds 1 of 27"), std::string::npos) << e;
}

// Native decks: a prescribed field (conduction: false) needs no conductivity or specific
// heat and runs with the static solver; it takes temperature conditions only; with
// conduction the static solver is still refused, and the conduction keys are required.
TEST(PeridigmThermal, NativePrescribedFieldKeys) {
  const fs::path dir = test_dir();
  auto deck = [&](const std::string& name, const std::string& material_thermal, const std::string& thermal) {
    return write(dir / name,
                 "dimension: 3\nspacing: 1.0\nhorizon: 1.1\n"
                 "materials:\n"
                 "  steel: {model: lps, density: 7800, bulk_modulus: 130.0e9, shear_modulus: 78.0e9, thermal: " +
                     material_thermal + "}\n"
                 "regions:\n  left: {points: [[0, 0, 0]]}\n"
                 "bodies:\n"
                 "  - {name: bar, material: steel, shape: {points: [[0, 0, 0, 1.0], [1, 0, 0, 1.0]]}}\n"
                 "loads:\n  - {region: left, displacement: [0, 0, 0]}\n"
                 "solver: {type: static, load_steps: 1}\n"
                 "thermal: " + thermal + "\n");
  };
  EXPECT_EQ(error_of(deck("ok.yaml", "{expansion: 1.0e-5, reference_temperature: initial}",
                          "{conduction: false, initial_temperature: 300}")),
            "no error");
  std::string e = error_of(deck("flux.yaml", "{expansion: 1.0e-5, reference_temperature: 300}",
                                "{conduction: false, initial_temperature: 300, boundary: [{region: left, flux: 1.0}]}"));
  EXPECT_NE(e.find("flux and convection need conduction"), std::string::npos) << e;
  e = error_of(deck("conducts.yaml", "{conductivity: 50, specific_heat: 500}", "{initial_temperature: 300}"));
  EXPECT_NE(e.find("thermal.conduction: false"), std::string::npos) << e;
  EXPECT_NE(e.find("static"), std::string::npos) << e;
  e = error_of(deck("missing.yaml", "{expansion: 1.0e-5, reference_temperature: 300}",
                    "{conduction: true, initial_temperature: 300}"));
  EXPECT_NE(e.find("expected conductivity"), std::string::npos) << e;
}

// Implicit dynamics (Newmark) with a prescribed field: a bar of two points heated at
// 1e5 K/s from rest springs apart; the thermal work of each step (trapezoidal over the
// force states before and after it) closes the ledger K + U = W_thermal.
TEST(PeridigmThermal, NewmarkBooksTheThermalWork) {
  const fs::path dir = test_dir();
  const std::string deck = write(
      dir / "bar.yaml",
      "dimension: 3\nspacing: 1.0\nhorizon: 1.1\n"
      "materials:\n"
      "  steel: {model: lps, density: 7800, bulk_modulus: 130.0e9, shear_modulus: 78.0e9, "
      "thermal: {expansion: 1.0e-5, reference_temperature: initial}}\n"
      "regions:\n  left: {points: [[0, 0, 0]]}\n"
      "bodies:\n  - {name: bar, material: steel, shape: {points: [[0, 0, 0, 1.0], [1, 0, 0, 1.0]]}}\n"
      "loads:\n  - {region: left, displacement: [0, 0, 0]}\n  - {region: all, displacement: [null, 0, 0]}\n"
      "solver: {type: implicit_dynamic, end_time: 3.0e-4, time_step: 1.0e-4}\n"
      "thermal: {conduction: false, initial_temperature: 300, boundary: [{region: all, temperature: \"300 + 1.0e5*t\"}]}\n");
  Config c = load_deck(deck);
  c.output.directory = (dir / "out").string();
  RunOptions o;
  o.quiet = true;
  ASSERT_EQ(run_deck(c, o), 0);
  const YAML::Node energy = YAML::LoadFile((dir / "out" / "summary.json").string())["energy"];
  EXPECT_GT(energy["thermal_work"].as<double>(), 0.0);
  EXPECT_GT(energy["kinetic"].as<double>(), 0.0);
  EXPECT_LT(energy["max_abs_balance_error"].as<double>(), 1e-8);
}

}  // namespace
}  // namespace horizon
