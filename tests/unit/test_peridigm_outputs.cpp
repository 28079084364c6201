// The Peridigm importer's output variables and the mappings that make Peridigm's suite
// decks match their golds (docs/peridigm.md), each on a small deck written for the test
// and checked against a closed form or a hand computation: Deformation_Gradient of a
// homogeneous deformation (exact), Lambda of the Elastic Plastic model after one step
// (Mitchell's return, SAND2011-3166, computed here bond by bond), compute classes as
// Exodus globals, Peridigm's int(T/dt) steps, the "1.0/zeta" influence function and the
// planar Elastic Bond Based solid.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "horizon/core/error.hpp"
#include "horizon/core/vec3.hpp"
#include "horizon/deck/deck.hpp"
#include "horizon/driver/run.hpp"
#include "horizon/output/exodus.hpp"
#include "deck_test_support.hpp"

namespace horizon {
namespace {

namespace fs = std::filesystem;

fs::path test_dir() { return test::fresh_test_dir("horizon_peridigm_outputs"); }
using test::write;
using test::error_of;
using test::run_and_read;
using test::index_of;

// The native deck's first material (materials are a map by name).
YAML::Node first_material(const YAML::Node& native) { return native["materials"].begin()->second; }

// The unit cube as PdQuickGrid's 2 x 2 x 2 cells (centres 0.25 and 0.75, volume 1/8), every
// particle bonded to the seven others (horizon 1.75), every particle's displacement
// prescribed by `ux`, `uy`, `uz`; a Verlet run of `steps` steps of 1e-7 s.
std::string cube_deck(const std::string& material, const std::string& ux, const std::string& uy,
                      const std::string& uz, int steps, const std::string& variables) {
  std::string bcs;
  for (const auto& [axis, value] : {std::pair{"x", ux}, std::pair{"y", uy}, std::pair{"z", uz}})
    bcs += std::string("    Move ") + axis + ":\n      Type: \"Prescribed Displacement\"\n      Node Set: \"All\"\n" +
           "      Coordinate: \"" + axis + "\"\n      Value: \"" + value + "\"\n";
  return "Peridigm:\n"
         "  Discretization:\n"
         "    Type: \"PdQuickGrid\"\n"
         "    NeighborhoodType: \"Spherical\"\n"
         "    TensorProduct3DMeshGenerator:\n"
         "      Type: \"PdQuickGrid\"\n"
         "      X Origin: 0.0\n      Y Origin: 0.0\n      Z Origin: 0.0\n"
         "      X Length: 1.0\n      Y Length: 1.0\n      Z Length: 1.0\n"
         "      Number Points X: 2\n      Number Points Y: 2\n      Number Points Z: 2\n"
         "  Materials:\n"
         "    Metal:\n" + material +
         "  Blocks:\n"
         "    All:\n"
         "      Block Names: \"block_1\"\n"
         "      Material: \"Metal\"\n"
         "      Horizon: 1.75\n"
         "  Boundary Conditions:\n"
         "    All: \"1 2 3 4 5 6 7 8\"\n" + bcs +
         "  Solver:\n"
         "    Final Time: " + std::to_string(steps) + ".0e-7\n"
         "    Verlet:\n"
         "      Fixed dt: 1.0e-7\n"
         "  Output:\n"
         "    Output Filename: \"cube\"\n"
         "    Output Frequency: 1\n"
         "    Output Variables:\n" + variables;
}

const char* kElastic = "      Material Model: \"Elastic\"\n      Density: 7800.0\n      Bulk Modulus: 130.0e9\n"
                       "      Shear Modulus: 60.0e9\n";

// F of a homogeneous deformation u = A X t/T is I + A t/T exactly, at every particle,
// whatever the family (material/nonlocal_gradient.hpp): the golds of Peridigm's six
// DeformationGradient decks are this, to 1e-14.
TEST(PeridigmOutputs, DeformationGradientOfAHomogeneousDeformationIsExact) {
  const fs::path dir = test_dir();
  const double A[3][3] = {{0.01, 0.02, -0.03}, {-0.015, 0.005, 0.01}, {0.02, -0.01, 0.025}};
  auto row = [&](int r) {
    return "(" + std::to_string(A[r][0]) + "*x + " + std::to_string(A[r][1]) + "*y + " + std::to_string(A[r][2]) +
           "*z)*t/4.0e-7";
  };
  const std::string deck =
      write(dir / "f.yaml", cube_deck(kElastic, row(0), row(1), row(2), 4, "      Deformation_Gradient: true\n"));
  const YAML::Node native = YAML::Load(convert_peridigm_deck(deck));
  ASSERT_EQ(native["output"]["exodus_files"][0]["variables"].size(), 1u);
  EXPECT_EQ(native["output"]["exodus_files"][0]["variables"][0].as<std::string>(), "Deformation_Gradient");
  const ExodusSeries r = run_and_read(deck, dir, "cube.e");
  ASSERT_EQ(r.steps.size(), 5u);
  const char* axes = "XYZ";
  for (const auto& step : r.steps) {
    const double s = step.time / 4.0e-7;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) {
        const std::size_t v = index_of(r.layout.element, std::string("Deformation_Gradient") + axes[a] + axes[b]);
        for (std::size_t i = 0; i < 8; ++i)
          EXPECT_NEAR(step.element[v][i], (a == b ? 1.0 : 0.0) + A[a][b] * s, 1e-14) << axes[a] << axes[b] << " " << i;
      }
  }
}

// Lambda after one step from the virgin state, by hand (Mitchell's backward-Euler return,
// SAND2011-3166, with omega = 1): per particle m = sum |xi|^2 V, e = |Y| - |xi|,
// theta = 3 sum |xi| e V / m, e^d = e - theta |xi| / 3, alpha = 15 mu / m, the trial
// norm ||t^d|| = alpha sqrt(sum (e^d)^2 V), and Peridigm's yield psi_0 = 25 sigma_y^2 /
// (8 pi delta^5); then d lambda = (||t^d|| / sqrt(2 psi_0) - 1) / alpha where positive.
TEST(PeridigmOutputs, LambdaOfElasticPlasticIsMitchellsPlasticMultiplier) {
  const fs::path dir = test_dir();
  const double K = 67549.0, mu = 25902.2, sy = 351.79, delta = 1.75, gamma = 0.02;
  const std::string material = "      Material Model: \"Elastic Plastic\"\n      Density: 2.7e-3\n"
                               "      Bulk Modulus: 67549.0\n      Shear Modulus: 25902.2\n"
                               "      Yield Stress: 351.79\n";
  // A simple shear with some stretch, reached in one step.
  const std::string deck = write(dir / "ep.yaml", cube_deck(material, "0.02*y*t/1.0e-7", "0.005*y*t/1.0e-7", "0.0", 1,
                                                            "      Lambda: true\n      Dilatation: true\n"));
  const YAML::Node native = YAML::Load(convert_peridigm_deck(deck));
  EXPECT_EQ(first_material(native)["yield_reference"].as<std::string>(), "continuum");
  EXPECT_EQ(native["output"]["exodus_files"][0]["variables"][0].as<std::string>(), "Lambda");
  const ExodusSeries r = run_and_read(deck, dir, "cube.e");
  ASSERT_EQ(r.steps.size(), 2u);
  const std::size_t lambda = index_of(r.layout.element, "Lambda");
  const double psi0 = 25 * sy * sy / (8 * std::numbers::pi * std::pow(delta, 5));
  (void)K;
  int plastic = 0;
  for (std::size_t i = 0; i < 8; ++i) {
    EXPECT_EQ(r.steps[0].element[lambda][i], 0.0);
    const Vec3 xi_i = r.layout.points[i];
    auto u = [&](const Vec3& X) { return Vec3{gamma * X.y, 0.005 * X.y, 0.0}; };
    double m = 0, sum = 0;
    std::vector<double> L, e;
    for (std::size_t j = 0; j < 8; ++j) {
      if (j == i) continue;
      const Vec3 xi = r.layout.points[j] - xi_i;
      const Vec3 Y = xi + u(r.layout.points[j]) - u(xi_i);
      L.push_back(norm(xi));
      e.push_back(norm(Y) - norm(xi));
      m += L.back() * L.back() * 0.125;
      sum += L.back() * e.back() * 0.125;
    }
    const double theta = 3 * sum / m;
    double n2 = 0;
    for (std::size_t k = 0; k < L.size(); ++k) {
      const double ed = e[k] - theta * L[k] / 3;
      n2 += ed * ed * 0.125;
    }
    const double alpha = 15 * mu / m;
    const double trial = alpha * std::sqrt(n2);
    const double expected = std::max(0.0, (trial / std::sqrt(2 * psi0) - 1) / alpha);
    if (expected > 0) ++plastic;
    EXPECT_NEAR(r.steps[1].element[lambda][i], expected, 1e-12 * expected + 1e-300) << i;
  }
  EXPECT_EQ(plastic, 8);  // the step yields everywhere: the test checks the return
}

// A compute class's Output Label named in an Output list is a global variable of its file
// (WaveInBar_MultiBlock's Volume_Block_1): here the sum of the eight volumes, 1.
TEST(PeridigmOutputs, ComputeClassesAreExodusGlobals) {
  const fs::path dir = test_dir();
  std::string text = cube_deck(kElastic, "0.0", "0.0", "0.001*x*t/1.0e-7", 2,
                               "      Displacement: true\n      Volume_Block_1: true\n      Top_Force: true\n");
  text.insert(text.find("  Output:"),
              "  Compute Class Parameters:\n"
              "    Volume Block 1:\n      Compute Class: \"Block_Data\"\n      Calculation Type: \"Sum\"\n"
              "      Block: \"block_1\"\n      Variable: \"Volume\"\n      Output Label: \"Volume_Block_1\"\n"
              "    Top Force:\n      Compute Class: \"Block_Data\"\n      Calculation Type: \"Sum\"\n"
              "      Block: \"block_1\"\n      Variable: \"Force\"\n      Output Label: \"Top_Force\"\n");
  const ExodusSeries r = run_and_read(write(dir / "cc.yaml", text), dir, "cube.e");
  ASSERT_EQ(r.steps.size(), 3u);
  const std::size_t v = index_of(r.layout.global, "Volume_Block_1");
  const std::size_t fz = index_of(r.layout.global, "Top_ForceZ");
  const std::size_t force = index_of(r.layout.nodal, "ForceZ");
  for (const auto& step : r.steps) {
    EXPECT_NEAR(step.global[v], 1.0, 1e-15);
    double total = 0;
    for (double f : step.nodal[force]) total += f;
    EXPECT_NEAR(step.global[fz], total, 1e-9 * (1 + std::abs(total)));
  }
}

// Peridigm's Verlet takes int(T/dt) steps: 1e-2/2e-5 is 499.99999999999994, so 499 steps,
// and its output every 50 steps ends at step 450, t = 0.009 (InitialDamage's gold).
TEST(PeridigmOutputs, VerletTakesPeridigmsWholeSteps) {
  const fs::path dir = test_dir();
  write(dir / "points.txt", "0 0 0 1 1\n1 0 0 1 1\n2 0 0 1 1\n3 0 0 1 1\n");
  const std::string deck = write(dir / "steps.yaml",
                                 "Peridigm:\n"
                                 "  Discretization:\n    Type: \"Text File\"\n    Input Mesh File: \"points.txt\"\n"
                                 "  Materials:\n    Steel: {Material Model: \"Elastic\", Density: 7800.0, "
                                 "Bulk Modulus: 130.0e9, Shear Modulus: 78.0e9}\n"
                                 "  Blocks:\n    All: {Block Names: \"block_1\", Material: \"Steel\", Horizon: 1.5}\n"
                                 "  Solver:\n    Final Time: 1.0e-2\n    Verlet:\n      Fixed dt: 2.0e-5\n"
                                 "  Output:\n    Output Filename: \"steps\"\n    Output Frequency: 50\n");
  const YAML::Node native = YAML::Load(convert_peridigm_deck(deck));
  EXPECT_DOUBLE_EQ(native["solver"]["end_time"].as<double>(), 499 * 2.0e-5);
  const ExodusSeries r = run_and_read(deck, dir, "steps.e");
  ASSERT_EQ(r.steps.size(), 10u);
  EXPECT_NEAR(r.steps.back().time, 0.009, 1e-17);
}

// "1.0/zeta" is omega = 1/|xi|: on a row of points 1 apart with horizon 1.5 the weighted
// volume sum omega |xi|^2 V is 1 at the ends and 2 inside (Compression_3x1x1_InfluenceFunction's
// gold: 3 on its three points with three neighbours). Horizon's `inverse` (delta/|xi|) gives
// 1.5 times that, and the same forces.
TEST(PeridigmOutputs, InverseLengthInfluenceGivesPeridigmsWeightedVolume) {
  const fs::path dir = test_dir();
  write(dir / "points.txt", "0 0 0 1 1\n1 0 0 1 1\n2 0 0 1 1\n3 0 0 1 1\n");
  const std::string text = "Peridigm:\n"
                           "  Discretization:\n    Type: \"Text File\"\n    Input Mesh File: \"points.txt\"\n"
                           "    Influence Function: \"1.0/zeta\"\n"
                           "  Materials:\n    Steel: {Material Model: \"Elastic\", Density: 7800.0, "
                           "Bulk Modulus: 130.0e9, Shear Modulus: 78.0e9}\n"
                           "  Blocks:\n    All: {Block Names: \"block_1\", Material: \"Steel\", Horizon: 1.5}\n"
                           "  Boundary Conditions:\n    Right: \"4\"\n"
                           "    Pull: {Type: \"Prescribed Displacement\", Node Set: \"Right\", Coordinate: \"x\", "
                           "Value: \"0.001*t/1.0e-5\"}\n"
                           "  Solver:\n    Final Time: 3.0e-5\n    Verlet:\n      Fixed dt: 1.0e-5\n"
                           "  Output:\n    Output Filename: \"w\"\n    Output Frequency: 1\n";
  const std::string deck = write(dir / "w.yaml", text);
  YAML::Node native = YAML::Load(convert_peridigm_deck(deck));
  EXPECT_EQ(first_material(native)["influence"].as<std::string>(), "inverse_length");
  const ExodusSeries r = run_and_read(deck, dir, "w.e");
  const std::size_t wv = index_of(r.layout.element, "Weighted_Volume");
  const std::vector<double> expected = {1, 2, 2, 1};
  for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR(r.steps[0].element[wv][i], expected[i], 1e-15);
  // The native deck with influence: inverse (delta/|xi|).
  native["materials"]["All"]["influence"] = "inverse";
  YAML::Emitter out;
  out << native;
  const fs::path other = dir / "other";
  fs::create_directories(other);
  fs::copy_file(dir / "points.txt", other / "points.txt");
  const ExodusSeries q = run_and_read(write(other / "native.yaml", out.c_str()), other, "w.e");
  ASSERT_EQ(q.steps.size(), r.steps.size());
  const std::size_t fx = index_of(r.layout.nodal, "Force_DensityX");
  for (std::size_t k = 0; k < r.steps.size(); ++k)
    for (std::size_t i = 0; i < 4; ++i) {
      EXPECT_NEAR(q.steps[k].element[wv][i], 1.5 * r.steps[k].element[wv][i], 1e-14);
      EXPECT_NEAR(q.steps[k].nodal[fx][i], r.steps[k].nodal[fx][i], 1e-9 * (1 + std::abs(r.steps[k].nodal[fx][i])));
    }
  EXPECT_GT(std::abs(r.steps.back().nodal[fx][3]), 1e3);  // the pull acts
}

// Peridigm's planar Elastic Bond Based solid: c = 12 K/(pi h delta^3) (both plane modes;
// fitted from both golds of ElasticBondBased2DPlaneStrain/PlaneStress).
TEST(PeridigmOutputs, PlanarBondBasedMicromodulus) {
  const fs::path dir = test_dir();
  write(dir / "points.txt", "0 0 0 1 1\n1 0 0 1 1\n0 1 0 1 1\n1 1 0 1 1\n");
  auto deck = [&](const std::string& name, const std::string& keys) {
    return write(dir / name,
                 "Peridigm:\n"
                 "  Discretization:\n    Type: \"Text File\"\n    Input Mesh File: \"points.txt\"\n"
                 "  Materials:\n    Plate:\n      Material Model: \"Elastic Bond Based\"\n      Density: 7800.0\n" +
                     keys +
                     "  Blocks:\n    All: {Block Names: \"block_1\", Material: \"Plate\", Horizon: 1.5}\n"
                     "  Solver:\n    Final Time: 1.0e-6\n    Verlet:\n      Fixed dt: 1.0e-7\n");
  };
  for (const char* mode : {"Plane Strain", "Plane Stress"}) {
    const YAML::Node n = YAML::Load(convert_peridigm_deck(
        deck("plane.yaml", "      Bulk Modulus: 200.0e9\n      " + std::string(mode) + ": true\n      Height: 0.25\n")));
    EXPECT_NEAR(first_material(n)["micromodulus"].as<double>(), 12 * 200e9 / (std::numbers::pi * 0.25 * 1.5 * 1.5 * 1.5),
                1e-3)
        << mode;
    EXPECT_FALSE(first_material(n)["bulk_modulus"]) << mode;
    EXPECT_NO_THROW(load_deck(deck("plane_loads.yaml", "      Bulk Modulus: 200.0e9\n      " + std::string(mode) +
                                                           ": true\n      Height: 0.25\n")));
  }
  EXPECT_NE(error_of(deck("h.yaml", "      Bulk Modulus: 200.0e9\n      Height: 0.25\n")).find("planar model only"),
            std::string::npos);
  EXPECT_NE(error_of(deck("g.yaml", "      Bulk Modulus: 200.0e9\n      Shear Modulus: 1.0e9\n"
                                    "      Plane Stress: true\n      Height: 0.25\n"))
                .find("Bulk Modulus alone"),
            std::string::npos);
}

// Lambda is undefined (NaN) at particles of other models: Peridigm leaves the variable out
// of their blocks (Bar_TwoBlocks_TwoDifferentMaterial_QS's gold). Two blocks of a row.
TEST(PeridigmOutputs, LambdaIsUndefinedOutsideElasticPlastic) {
  const fs::path dir = test_dir();
  write(dir / "points.txt", "0 0 0 1 1\n1 0 0 1 1\n2 0 0 2 1\n3 0 0 2 1\n");
  const std::string deck = write(
      dir / "two.yaml",
      "Peridigm:\n"
      "  Discretization:\n    Type: \"Text File\"\n    Input Mesh File: \"points.txt\"\n"
      "  Materials:\n"
      "    Soft: {Material Model: \"Elastic\", Density: 7800.0, Bulk Modulus: 130.0e9, Shear Modulus: 78.0e9}\n"
      "    Hard: {Material Model: \"Elastic Plastic\", Density: 7800.0, Bulk Modulus: 130.0e9, "
      "Shear Modulus: 78.0e9, Yield Stress: 1.0e9}\n"
      "  Blocks:\n    One: {Block Names: \"block_1\", Material: \"Soft\", Horizon: 1.5}\n"
      "    Two: {Block Names: \"block_2\", Material: \"Hard\", Horizon: 1.5}\n"
      "  Solver:\n    Final Time: 2.0e-6\n    Verlet:\n      Fixed dt: 1.0e-6\n"
      "  Output:\n    Output Filename: \"two\"\n    Output Variables:\n      Lambda: true\n");
  const ExodusSeries r = run_and_read(deck, dir, "two.e");
  const std::size_t lambda = index_of(r.layout.element, "Lambda");
  for (const auto& step : r.steps) {
    EXPECT_TRUE(std::isnan(step.element[lambda][0]));
    EXPECT_TRUE(std::isnan(step.element[lambda][1]));
    EXPECT_EQ(step.element[lambda][2], 0.0);
    EXPECT_EQ(step.element[lambda][3], 0.0);
  }
}

// Disable Plasticity: elastic_plastic with plasticity off, the LPS forces and Lambda 0 (the
// yield stress, 0 in BondBreakingInitialVelocity-EP, is not used). A pulled row of four
// points against the same row of Elastic material.
TEST(PeridigmOutputs, DisablePlasticityIsTheElasticPart) {
  const fs::path dir = test_dir();
  write(dir / "points.txt", "0 0 0 1 1\n1 0 0 1 1\n2 0 0 1 1\n3 0 0 1 1\n");
  auto deck = [&](const std::string& name, const std::string& material) {
    return write(dir / (name + ".yaml"),
                 "Peridigm:\n"
                 "  Discretization:\n    Type: \"Text File\"\n    Input Mesh File: \"points.txt\"\n"
                 "  Materials:\n    Steel: {" + material + ", Density: 7800.0, Bulk Modulus: 130.0e9, "
                 "Shear Modulus: 78.0e9}\n"
                 "  Blocks:\n    All: {Block Names: \"block_1\", Material: \"Steel\", Horizon: 1.5}\n"
                 "  Boundary Conditions:\n    Right: \"4\"\n"
                 "    Pull: {Type: \"Prescribed Displacement\", Node Set: \"Right\", Coordinate: \"x\", "
                 "Value: \"100.0*t\"}\n"
                 "  Solver:\n    Final Time: 3.0e-5\n    Verlet:\n      Fixed dt: 1.0e-5\n"
                 "  Output:\n    Output Filename: \"" + name + "\"\n    Output Variables:\n      Lambda: true\n");
  };
  const std::string off = deck("off", "Material Model: \"Elastic Plastic\", Disable Plasticity: true, Yield Stress: 0.0");
  const YAML::Node native = YAML::Load(convert_peridigm_deck(off));
  EXPECT_EQ(first_material(native)["model"].as<std::string>(), "elastic_plastic");
  EXPECT_EQ(first_material(native)["plasticity"].as<std::string>(), "off");
  const ExodusSeries r = run_and_read(off, dir, "off.e");
  const ExodusSeries e = run_and_read(deck("lps", "Material Model: \"Elastic\""), dir, "lps.e");
  const std::size_t lambda = index_of(r.layout.element, "Lambda"), fx = index_of(r.layout.nodal, "Force_DensityX");
  ASSERT_EQ(r.steps.size(), e.steps.size());
  for (std::size_t k = 0; k < r.steps.size(); ++k)
    for (std::size_t i = 0; i < 4; ++i) {
      EXPECT_EQ(r.steps[k].element[lambda][i], 0.0);
      EXPECT_NEAR(r.steps[k].nodal[fx][i], e.steps[k].nodal[fx][i], 1e-9 * std::abs(e.steps[k].nodal[fx][i]) + 1e-6);
    }
  EXPECT_GT(std::abs(r.steps.back().nodal[fx][3]), 1e6);  // the pull acts
}

// Peridigm's Verlet reports at a prescribed component the prescribed rate plus dt/2 (f + b)/rho
// (ElasticBondBased2DPlaneStrain's gold): the native `velocity: verlet`. A row of four points
// pulled at its right end at 100 m/s; the free points' velocities are the integrator's own.
TEST(PeridigmOutputs, VerletVelocityAtPrescribedComponents) {
  const fs::path dir = test_dir();
  write(dir / "points.txt", "0 0 0 1 1\n1 0 0 1 1\n2 0 0 1 1\n3 0 0 1 1\n");
  const std::string deck = write(
      dir / "pull.yaml",
      "Peridigm:\n"
      "  Discretization:\n    Type: \"Text File\"\n    Input Mesh File: \"points.txt\"\n"
      "  Materials:\n    Steel: {Material Model: \"Elastic\", Density: 7800.0, Bulk Modulus: 130.0e9, "
      "Shear Modulus: 78.0e9}\n"
      "  Blocks:\n    All: {Block Names: \"block_1\", Material: \"Steel\", Horizon: 1.5}\n"
      "  Boundary Conditions:\n    Right: \"4\"\n"
      "    Pull: {Type: \"Prescribed Displacement\", Node Set: \"Right\", Coordinate: \"x\", Value: \"100.0*t\"}\n"
      "  Solver:\n    Final Time: 3.0e-5\n    Verlet:\n      Fixed dt: 1.0e-5\n"
      "  Output:\n    Output Filename: \"pull\"\n    Output Frequency: 1\n");
  YAML::Node native = YAML::Load(convert_peridigm_deck(deck));
  EXPECT_EQ(native["output"]["exodus_files"][0]["velocity"].as<std::string>(), "verlet");
  const ExodusSeries r = run_and_read(deck, dir, "pull.e");
  ASSERT_EQ(r.steps.size(), 4u);
  const std::size_t vx = index_of(r.layout.nodal, "VelocityX"), ax = index_of(r.layout.nodal, "AccelerationX");
  EXPECT_EQ(r.steps[0].nodal[vx][3], 0.0);  // the initial state: no kick
  for (std::size_t k = 1; k < 4; ++k) {
    const double a = r.steps[k].nodal[ax][3];
    EXPECT_GT(std::abs(a), 1.0);
    EXPECT_NEAR(r.steps[k].nodal[vx][3], 100.0 + 0.5 * 1.0e-5 * a, 1e-9 * std::abs(a) + 1e-12) << k;
  }
  // velocity: state (the native default) reports the particle's velocity: under the
  // importer's solver.verlet: peridigm that is the kicked velocity itself (the file adds
  // nothing), the same bits at every point; under Horizon's own Verlet, the rate, and the
  // free points the same motion to round-off.
  native["output"]["exodus_files"][0].remove("velocity");
  EXPECT_EQ(native["solver"]["verlet"].as<std::string>(), "peridigm");
  auto run_native = [&](const std::string& name) {
    YAML::Emitter out;
    out << native;
    const fs::path other = dir / name;
    fs::create_directories(other);
    fs::copy_file(dir / "points.txt", other / "points.txt");
    return run_and_read(write(other / "native.yaml", out.c_str()), other, "pull.e");
  };
  const ExodusSeries q = run_native("state");
  for (std::size_t k = 1; k < 4; ++k)
    for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(q.steps[k].nodal[vx][i], r.steps[k].nodal[vx][i]) << k << " " << i;
  native["solver"]["verlet"] = "horizon";
  const ExodusSeries h = run_native("horizon");
  for (std::size_t k = 1; k < 4; ++k) {
    EXPECT_NEAR(h.steps[k].nodal[vx][3], 100.0, 1e-9);
    for (std::size_t i = 0; i < 3; ++i)
      EXPECT_NEAR(h.steps[k].nodal[vx][i], r.steps[k].nodal[vx][i], 1e-12 * (1 + std::abs(r.steps[k].nodal[vx][i])));
  }
}

// Contact_Force_Density: two points 0.19 apart, unbonded (horizon 0.1), inside the contact
// radius 0.2 of Peridigm's Short Range Force and at rest: each feels 2 x 9k/(pi delta^4) V
// (R_c - r)/delta away from the other (docs/peridigm.md "Contact"; Contact_2x1x1's gold
// fixes the factor 2), all of its force density, since no bond acts.
TEST(PeridigmOutputs, ContactForceDensityIsTheShortRangeForce) {
  const fs::path dir = test_dir();
  write(dir / "points.txt", "0 0 0 1 0.001\n0 0.19 0 1 0.001\n");
  const std::string deck = write(
      dir / "touch.yaml",
      "Peridigm:\n"
      "  Discretization:\n    Type: \"Text File\"\n    Input Mesh File: \"points.txt\"\n"
      "  Materials:\n    Copper: {Material Model: \"Elastic\", Density: 8960.0, Bulk Modulus: 140.0e9, "
      "Shear Modulus: 48.0e9}\n"
      "  Blocks:\n    All: {Block Names: \"block_1\", Material: \"Copper\", Horizon: 0.1}\n"
      "  Contact:\n    Search Radius: 1.0\n    Search Frequency: 1\n"
      "    Models:\n      Touch: {Contact Model: \"Short Range Force\", Contact Radius: 0.2, Spring Constant: 1.0e12, "
      "Horizon: 0.1}\n"
      "    Interactions:\n      General Contact: {Contact Model: \"Touch\"}\n"
      "  Solver:\n    Final Time: 1.0e-6\n    Verlet:\n      Fixed dt: 1.0e-6\n"
      "  Output:\n    Output Filename: \"touch\"\n    Output Frequency: 1\n"
      "    Output Variables:\n      Contact_Force_Density: true\n      Force_Density: true\n");
  YAML::Node native = YAML::Load(convert_peridigm_deck(deck));
  EXPECT_EQ(native["output"]["exodus_files"][0]["variables"][0].as<std::string>(), "Contact_Force_Density");
  const ExodusSeries r = run_and_read(deck, dir, "touch.e");
  ASSERT_EQ(r.steps.size(), 2u);
  const std::size_t cy = index_of(r.layout.nodal, "Contact_Force_DensityY"),
                    cx = index_of(r.layout.nodal, "Contact_Force_DensityX"),
                    fy = index_of(r.layout.nodal, "Force_DensityY");
  const double delta = 0.1, k = 1.0e12, V = 0.001;
  const double expected = 2 * 9 * k / (std::numbers::pi * std::pow(delta, 4)) * V * (0.2 - 0.19) / delta;
  const auto& s0 = r.steps[0];
  EXPECT_NEAR(s0.nodal[cy][0], -expected, 1e-12 * expected);  // pushed away from the other point
  EXPECT_NEAR(s0.nodal[cy][1], expected, 1e-12 * expected);
  EXPECT_EQ(s0.nodal[cx][0], 0.0);
  for (std::size_t i = 0; i < 2; ++i) EXPECT_EQ(s0.nodal[cy][i], s0.nodal[fy][i]) << i;
}

// A Body Force without t acts in full from t = 0 (Peridigm evaluates it at each step's time:
// CentrifugalLoad's gold has it in the t = 0 output): the native value is written in t.
TEST(PeridigmOutputs, BodyForceWithoutTimeIsConstant) {
  const fs::path dir = test_dir();
  write(dir / "points.txt", "0 0 0 1 1\n1 0 0 1 1\n2 0 0 1 1\n3 0 0 1 1\n");
  std::string bcs = "    Left: \"1\"\n    All: \"1 2 3 4\"\n"
                    "    Hold: {Type: \"Prescribed Displacement\", Node Set: \"Left\", Coordinate: \"x\", Value: \"0.0\"}\n"
                    "    Push: {Type: \"Body Force\", Node Set: \"All\", Coordinate: \"x\", Value: \"1.0e6\"}\n";
  for (const char* axis : {"y", "z"})
    bcs += std::string("    Hold ") + axis + ": {Type: \"Prescribed Displacement\", Node Set: \"All\", Coordinate: \"" +
           axis + "\", Value: \"0.0\"}\n";
  const std::string deck = write(
      dir / "qs.yaml",
      "Peridigm:\n"
      "  Discretization:\n    Type: \"Text File\"\n    Input Mesh File: \"points.txt\"\n"
      "  Materials:\n    Steel: {Material Model: \"Elastic\", Density: 7800.0, Bulk Modulus: 130.0e9, "
      "Shear Modulus: 78.0e9}\n"
      "  Blocks:\n    All: {Block Names: \"block_1\", Material: \"Steel\", Horizon: 1.5}\n"
      "  Boundary Conditions:\n" + bcs +
      "  Solver:\n    Final Time: 1.0\n    QuasiStatic:\n      Number of Load Steps: 2\n"
      "  Output:\n    Output Filename: \"qs\"\n    Output Frequency: 1\n");
  const YAML::Node native = YAML::Load(convert_peridigm_deck(deck));
  std::string written;
  for (const auto& load : native["loads"])
    if (load["body_force"]) written = load["body_force"][0].as<std::string>();
  EXPECT_EQ(written, "(1.0e6) + 0*t");
  const ExodusSeries r = run_and_read(deck, dir, "qs.e");
  ASSERT_EQ(r.steps.size(), 3u);
  const std::size_t bx = index_of(r.layout.nodal, "External_Force_DensityX"), ux = index_of(r.layout.nodal, "DisplacementX");
  for (const auto& step : r.steps)
    for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(step.nodal[bx][i], 1.0e6);
  // Not ramped: both load steps are at the full load's equilibrium.
  for (std::size_t i = 1; i < 4; ++i) {
    EXPECT_GT(r.steps[1].nodal[ux][i], 0.0);
    EXPECT_NEAR(r.steps[1].nodal[ux][i], r.steps[2].nodal[ux][i], 1e-12 * r.steps[2].nodal[ux][i]);
  }
}

// Peridigm's Implicit (Newmark, average acceleration) starts from a_0 = 0: a cube of eight
// bonded points (a row has no stiffness across it) under the same body force b falls rigidly as u_n = dt^2 (b/rho) (1/4 + n(n - 1)/2)
// (Body_Force_Implicit's gold: 0.0030025 at n = 25), not (b/rho) t^2/2 = 0.003125.
TEST(PeridigmOutputs, ImplicitStartsFromZeroAcceleration) {
  const fs::path dir = test_dir();
  write(dir / "points.txt", "0 0 0 1 1\n1 0 0 1 1\n0 1 0 1 1\n1 1 0 1 1\n0 0 1 1 1\n1 0 1 1 1\n0 1 1 1 1\n1 1 1 1 1\n");
  const std::string deck = write(
      dir / "fall.yaml",
      "Peridigm:\n"
      "  Discretization:\n    Type: \"Text File\"\n    Input Mesh File: \"points.txt\"\n"
      "  Materials:\n    Steel: {Material Model: \"Elastic\", Density: 1000.0, Bulk Modulus: 130.0e9, "
      "Shear Modulus: 78.0e9}\n"
      "  Blocks:\n    All: {Block Names: \"block_1\", Material: \"Steel\", Horizon: 1.5}\n"
      "  Boundary Conditions:\n    Both: \"1 2 3 4 5 6 7 8\"\n"
      "    Fall: {Type: \"Body Force\", Node Set: \"Both\", Coordinate: \"z\", Value: \"100.0\"}\n"
      "  Solver:\n    Final Time: 0.25\n    Implicit:\n      Fixed dt: 0.01\n      Beta: 0.25\n      Gamma: 0.5\n"
      "  Output:\n    Output Filename: \"fall\"\n    Output Frequency: 5\n");
  const YAML::Node native = YAML::Load(convert_peridigm_deck(deck));
  EXPECT_EQ(native["solver"]["initial_acceleration"].as<std::string>(), "zero");
  const ExodusSeries r = run_and_read(deck, dir, "fall.e");
  ASSERT_EQ(r.steps.size(), 6u);
  const std::size_t uz = index_of(r.layout.nodal, "DisplacementZ");
  for (std::size_t k = 0; k < r.steps.size(); ++k) {
    const double n = 5.0 * static_cast<double>(k);
    const double expected = k == 0 ? 0.0 : 1e-4 * 0.1 * (0.25 + n * (n - 1) / 2);
    for (std::size_t i = 0; i < 8; ++i) EXPECT_NEAR(r.steps[k].nodal[uz][i], expected, 1e-11 * expected + 1e-18) << k;
  }
}

// Native decks: an exodus_files variable Horizon does not know is an error at its place.
TEST(PeridigmOutputs, UnknownExodusVariableIsAnError) {
  const fs::path dir = test_dir();
  const std::string deck = write(dir / "native.yaml",
                                 "dimension: 3\n"
                                 "spacing: 1.0\n"
                                 "horizon: 1.1\n"
                                 "materials:\n"
                                 "  steel: {model: lps, density: 7800, bulk_modulus: 130.0e9, shear_modulus: 78.0e9}\n"
                                 "bodies:\n"
                                 "  - {name: bar, material: steel, shape: {points: [[0, 0, 0, 1.0], [1, 0, 0, 1.0]]}}\n"
                                 "solver: {type: explicit, end_time: 1.0e-6, time_step: 1.0e-7}\n"
                                 "output:\n"
                                 "  exodus_files:\n"
                                 "    - {file: a.e, every: 1, variables: [Lambda, Lamda]}\n");
  const std::string e = error_of(deck);
  EXPECT_NE(e.find("native.yaml:11:"), std::string::npos) << e;
  EXPECT_NE(e.find("unknown variable 'Lamda'"), std::string::npos) << e;
}

}  // namespace
}  // namespace horizon
