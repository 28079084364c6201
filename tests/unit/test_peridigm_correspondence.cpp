// Peridigm's correspondence materials through the importer (docs/peridigm.md): the native
// keys they map to, and runs on PdQuickGrid's 2 x 2 x 2 cube with every particle's motion
// prescribed (a uniaxial strain u_y = 0.001 y t/T in 4 Verlet steps) checked against the
// closed forms of the rate form (material/classical/hypoelastic.hpp):
//   F_n = 1 + 0.001 n/4 along y, D_n = (F_n - F_n-1)/(dt F_n), V_yy = prod (1 + dt D_n),
//   Cauchy_StressYY = E sum dt D_n (nu = 0), Hourglass_Force_Density 0 (homogeneous);
// and the flaw: the particle at its centre yields at sigma_y (1 - m), the others not.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "horizon/deck/deck.hpp"
#include "horizon/driver/run.hpp"
#include "horizon/output/exodus.hpp"
#include "deck_test_support.hpp"

namespace horizon {
namespace {

namespace fs = std::filesystem;

fs::path test_dir() { return test::fresh_test_dir("horizon_peridigm_correspondence"); }
using test::write;
using test::index_of;

// The unit cube as 2 x 2 x 2 cells (centres 0.25 and 0.75), every particle bonded to the
// seven others (horizon 1.75), u = (0, 0.001 y t/T, 0) prescribed everywhere, T = 4e-7 s
// in steps of 1e-7.
std::string cube_deck(const std::string& material, const std::string& variables) {
  std::string bcs;
  for (const auto& [axis, value] : {std::pair{"x", "0.0"}, std::pair{"y", "0.001*y*t/4.0e-7"}, std::pair{"z", "0.0"}})
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
         "    Final Time: 4.0e-7\n"
         "    Verlet:\n"
         "      Fixed dt: 1.0e-7\n"
         "  Output:\n"
         "    Output Filename: \"cube\"\n"
         "    Output Frequency: 1\n"
         "    Output Variables:\n" + variables;
}

ExodusSeries run_and_read(const std::string& deck, const fs::path& dir) {
  Config c = load_deck(deck);
  c.output.directory = (dir / "out").string();
  RunOptions o;
  o.quiet = true;
  EXPECT_EQ(run_deck(c, o), 0);
  return read_exodus_series((dir / "out" / "cube.e").string());
}

constexpr double kE = 200e9;
const char* kElasticCorrespondence =
    "      Material Model: \"Elastic Correspondence\"\n      Density: 7800.0\n      Young's Modulus: 200.0e9\n"
    "      Poisson's Ratio: 0.0\n      Hourglass Coefficient: 0.04\n";

TEST(PeridigmCorrespondence, ImportMapsToTheRateFormAndTheHourglassForce) {
  const fs::path dir = test_dir();
  const YAML::Node native =
      YAML::Load(convert_peridigm_deck(write(dir / "e.yaml", cube_deck(kElasticCorrespondence, "      Cauchy_Stress: true\n"))));
  const YAML::Node m = native["materials"].begin()->second;
  EXPECT_EQ(m["model"].as<std::string>(), "correspondence");
  EXPECT_EQ(m["stress_law"].as<std::string>(), "hypoelastic");
  EXPECT_EQ(m["stabilization_form"].as<std::string>(), "peridigm");
  EXPECT_EQ(m["rotation_update"].as<std::string>(), "peridigm");
  EXPECT_DOUBLE_EQ(m["stabilization"].as<double>(), 0.04);
  EXPECT_EQ(native["output"]["exodus_files"][0]["variables"][0].as<std::string>(), "Cauchy_Stress");

  const std::string flaw =
      "      Material Model: \"Isotropic Hardening Correspondence\"\n      Density: 7800.0\n"
      "      Young's Modulus: 200.0e9\n      Poisson's Ratio: 0.0\n      Yield Stress: 250.0e6\n"
      "      Hardening Modulus: 0.0\n      Enable Flaw: true\n      Flaw Location X: 0.25\n"
      "      Flaw Location Y: 0.5\n      Flaw Location Z: -1.0\n      Flaw Size: 0.2\n      Flaw Magnitude: 0.5\n";
  const YAML::Node f = YAML::Load(convert_peridigm_deck(write(dir / "f.yaml", cube_deck(flaw, "      Volume: true\n"))))
                           ["materials"]
                               .begin()
                               ->second;
  EXPECT_EQ(f["stress_law"].as<std::string>(), "hypoelastic_j2");
  EXPECT_EQ(f["plastic_return"].as<std::string>(), "peridigm");
  EXPECT_DOUBLE_EQ(f["flaw_x"].as<double>(), 0.25);
  EXPECT_DOUBLE_EQ(f["flaw_y"].as<double>(), 0.5);
  EXPECT_DOUBLE_EQ(f["flaw_z"].as<double>(), -1.0);
  EXPECT_DOUBLE_EQ(f["flaw_size"].as<double>(), 0.2);
  EXPECT_DOUBLE_EQ(f["flaw_magnitude"].as<double>(), 0.5);
}

// Viscoplastic Needleman Correspondence: its keys map to stress_law viscoplastic_needleman
// (Needleman 1988's flow stress, classical/hypoelastic.hpp); a missing one is named.
TEST(PeridigmCorrespondence, NeedlemanMapsToTheViscoplasticLaw) {
  const fs::path dir = test_dir();
  const std::string vp =
      "      Material Model: \"Viscoplastic Needleman Correspondence\"\n      Density: 7800.0\n"
      "      Young's Modulus: 211.0e9\n      Poisson's Ratio: 0.0\n      Hourglass Coefficient: 0.0\n"
      "      Yield Stress: 460.0e6\n      Strain Hardening Exponent: 0.1\n      Rate Hardening Exponent: 0.01\n"
      "      Reference Strain Rate: 0.001\n      Reference Strain 0: 0.00218\n      Reference Strain 1: 0.436\n"
      "      Enable Flaw: true\n      Flaw Location X: 0.0\n      Flaw Location Y: 0.5\n"
      "      Flaw Location Z: 0.0\n      Flaw Size: 0.751\n      Flaw Magnitude: 0.2\n";
  const YAML::Node m =
      YAML::Load(convert_peridigm_deck(write(dir / "vp.yaml", cube_deck(vp, "      Von_Mises_Stress: true\n"))))["materials"]
          .begin()
          ->second;
  EXPECT_EQ(m["stress_law"].as<std::string>(), "viscoplastic_needleman");
  EXPECT_DOUBLE_EQ(m["yield_stress"].as<double>(), 460e6);
  EXPECT_DOUBLE_EQ(m["strain_hardening_exponent"].as<double>(), 0.1);
  EXPECT_DOUBLE_EQ(m["rate_hardening_exponent"].as<double>(), 0.01);
  EXPECT_DOUBLE_EQ(m["reference_strain_rate"].as<double>(), 0.001);
  EXPECT_DOUBLE_EQ(m["reference_strain"].as<double>(), 0.00218);
  EXPECT_DOUBLE_EQ(m["softening_strain"].as<double>(), 0.436);
  EXPECT_DOUBLE_EQ(m["flaw_magnitude"].as<double>(), 0.2);
  EXPECT_DOUBLE_EQ(m["flaw_y"].as<double>(), 0.5);
  EXPECT_FALSE(m["hardening_modulus"]);
  std::string missing = vp;
  missing.erase(missing.find("      Reference Strain 1"), std::string("      Reference Strain 1: 0.436\n").size());
  const std::string e = test::error_of(write(dir / "vp2.yaml", cube_deck(missing, "      Volume: true\n")));
  EXPECT_NE(e.find("Reference Strain 1"), std::string::npos) << e;
}

// Elastic Correspondence with a Thermal Expansion Coefficient keeps its rate form.
TEST(PeridigmCorrespondence, ExpandingElasticCorrespondenceKeepsTheRateForm) {
  const fs::path dir = test_dir();
  const std::string mat = std::string(kElasticCorrespondence) + "      Thermal Expansion Coefficient: 10.0e-6\n";
  const YAML::Node m =
      YAML::Load(convert_peridigm_deck(write(dir / "th.yaml", cube_deck(mat, "      Volume: true\n"))))["materials"]
          .begin()
          ->second;
  EXPECT_EQ(m["stress_law"].as<std::string>(), "hypoelastic");
  EXPECT_DOUBLE_EQ(m["thermal"]["expansion"].as<double>(), 10e-6);
}

TEST(PeridigmCorrespondence, UniaxialStrainFollowsTheRateForm) {
  const fs::path dir = test_dir();
  const std::string deck = write(dir / "e.yaml", cube_deck(kElasticCorrespondence,
                                                           "      Cauchy_Stress: true\n      Left_Stretch_Tensor: true\n"
                                                           "      Rotation_Tensor: true\n      Hourglass_Force_Density: true\n"
                                                           "      Unrotated_Rate_Of_Deformation: true\n"));
  const ExodusSeries r = run_and_read(deck, dir);
  ASSERT_EQ(r.steps.size(), 5u);
  const std::size_t s = index_of(r.layout.element, "Cauchy_StressYY"), v = index_of(r.layout.element, "Left_Stretch_TensorYY"),
                    q = index_of(r.layout.element, "Rotation_TensorXX"),
                    d = index_of(r.layout.element, "Unrotated_Rate_Of_DeformationYY");
  double V = 1, sigma = 0;
  for (std::size_t n = 1; n < r.steps.size(); ++n) {
    const double F = 1 + 0.001 * static_cast<double>(n) / 4, D = (0.001 / 4) / (1e-7 * F);
    V *= 1 + 1e-7 * D;
    sigma += kE * 1e-7 * D;
    for (std::size_t i = 0; i < 8; ++i) {
      EXPECT_NEAR(r.steps[n].element[s][i], sigma, 1e-9 * sigma) << n << " " << i;
      EXPECT_NEAR(r.steps[n].element[v][i], V, 1e-14) << n << " " << i;
      EXPECT_NEAR(r.steps[n].element[q][i], 1.0, 1e-14);
      EXPECT_NEAR(r.steps[n].element[d][i], D, 1e-8 * D);
    }
    for (const char* c : {"X", "Y", "Z"}) {
      const std::size_t h = index_of(r.layout.nodal, std::string("Hourglass_Force_Density") + c);
      // C_hg c = 0.04 x 18 k/(pi delta^4) = 2.3e9 N/m^6 on bonds of unit length: round-off.
      for (std::size_t i = 0; i < 8; ++i) EXPECT_LT(std::abs(r.steps[n].nodal[h][i]), 1e-3);
    }
  }
}

TEST(PeridigmCorrespondence, FlawYieldsAtItsCentreOnly) {
  const fs::path dir = test_dir();
  // sigma_y = 250 MPa, the flaw at the particle (0.25, 0.25, 0.25) with m = 0.5, s = 0.2:
  // its yield stress 125 MPa, the others' 250 (1 - 0.5 exp(-0.25/0.04)) > 249 MPa, while
  // the elastic stress reaches E 0.001 = 200 MPa (nu = 0: von Mises = sigma_yy).
  const std::string flaw =
      "      Material Model: \"Isotropic Hardening Correspondence\"\n      Density: 7800.0\n"
      "      Young's Modulus: 200.0e9\n      Poisson's Ratio: 0.0\n      Yield Stress: 250.0e6\n"
      "      Hardening Modulus: 0.0\n      Enable Flaw: true\n      Flaw Location X: 0.25\n"
      "      Flaw Location Y: 0.25\n      Flaw Location Z: 0.25\n      Flaw Size: 0.2\n      Flaw Magnitude: 0.5\n";
  const ExodusSeries r =
      run_and_read(write(dir / "f.yaml", cube_deck(flaw, "      Von_Mises_Stress: true\n      Equivalent_Plastic_Strain: true\n")), dir);
  ASSERT_EQ(r.steps.size(), 5u);
  const auto& last = r.steps.back();
  const std::size_t vm = index_of(r.layout.element, "Von_Mises_Stress"), ep = index_of(r.layout.element, "Equivalent_Plastic_Strain");
  double sigma = 0;
  for (int n = 1; n <= 4; ++n) sigma += kE * (0.001 / 4) / (1 + 0.001 * n / 4);
  int yielded = 0;
  for (std::size_t i = 0; i < 8; ++i) {
    const bool centre = std::abs(r.layout.points[i].x - 0.25) + std::abs(r.layout.points[i].y - 0.25) + std::abs(r.layout.points[i].z - 0.25) < 1e-12;
    if (centre) {
      ++yielded;
      EXPECT_NEAR(last.element[vm][i], 125e6, 1e-6 * 125e6);
      EXPECT_GT(last.element[ep][i], 0.0);
    } else {
      EXPECT_NEAR(last.element[vm][i], sigma, 1e-9 * sigma);
      EXPECT_EQ(last.element[ep][i], 0.0);
    }
  }
  EXPECT_EQ(yielded, 1);
}

}  // namespace
}  // namespace horizon
