// Peridigm's Diffusion material and ImplicitDiffusion solver (docs/peridigm.md, "Diffusion
// material"): the mapping to a material of heat alone with thermal.integration: steady, a
// run of a small slab against the closed form (a linear temperature between two held
// layers; with Use Improved Quadrature no flux divergence anywhere, Peridigm's
// DiffusionImprovedQuadrature gold in small), and the errors.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "horizon/core/error.hpp"
#include "horizon/deck/deck.hpp"
#include "horizon/driver/run.hpp"
#include "horizon/output/exodus.hpp"
#include "deck_test_support.hpp"

namespace horizon {
namespace {

namespace fs = std::filesystem;

using test::error_of;
using test::index_of;
using test::run_and_read;
using test::write;

fs::path test_dir() { return test::fresh_test_dir("horizon_peridigm_diffusion"); }

// A 12 x 3 x 3 PdQuickGrid slab of spacing 1/12 on [0, 1] x [0, 1/4]^2, horizon three
// spacings; the three layers at each end held at 273 + 10 x t, the whole slab at 273 at
// t = 0. `material` is the Diffusion material's extra keys, `solver` the Solver list.
std::string slab_deck(const std::string& material, const std::string& solver) {
  std::string left, right, all;
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 12; ++i) {
        const std::string id = std::to_string(1 + i + 12 * (j + 3 * k));
        all += (all.empty() ? "" : " ") + id;
        if (i < 3) left += (left.empty() ? "" : " ") + id;
        if (i > 8) right += (right.empty() ? "" : " ") + id;
      }
  return "Peridigm:\n"
         "  Discretization:\n"
         "    Type: \"PdQuickGrid\"\n"
         "    NeighborhoodType: \"Spherical\"\n"
         "    TensorProduct3DMeshGenerator:\n"
         "      Type: \"PdQuickGrid\"\n"
         "      X Origin: 0.0\n      Y Origin: 0.0\n      Z Origin: 0.0\n"
         "      X Length: 1.0\n      Y Length: 0.25\n      Z Length: 0.25\n"
         "      Number Points X: 12\n      Number Points Y: 3\n      Number Points Z: 3\n"
         "  Materials:\n"
         "    Heat: {Material Model: \"Diffusion\", Coefficient: 2.0" + material + "}\n"
         "  Blocks:\n"
         "    All: {Block Names: \"block_1\", Material: \"Heat\", Horizon: 0.25001}\n"
         "  Boundary Conditions:\n"
         "    Left: \"" + left + "\"\n"
         "    Right: \"" + right + "\"\n"
         "    Everything: \"" + all + "\"\n"
         "    Hot Left: {Type: \"Prescribed Temperature\", Node Set: \"Left\", Value: \"273.0 + 10.0*x*t\"}\n"
         "    Hot Right: {Type: \"Prescribed Temperature\", Node Set: \"Right\", Value: \"273.0 + 10.0*x*t\"}\n"
         "    Start: {Type: \"Initial Temperature\", Node Set: \"Everything\", Value: \"273.0\"}\n" +
         solver +
         "  Output:\n"
         "    Output Filename: \"slab\"\n"
         "    Output Frequency: 1\n"
         "    Output Variables: {Flux_Divergence: true, Temperature: true, Number_Of_Neighbors: true}\n";
}

const char* kDiffusionSolver =
    "  Solver:\n    Initial Time: 0.0\n    Final Time: 1.0\n"
    "    Solve For Displacement: false\n    Solve For Temperature: true\n    Solve For Pressure: false\n"
    "    ImplicitDiffusion: {Number of Load Steps: 2, Relative Tolerance: 1.0e-9, Maximum Solver Iterations: 10}\n";

TEST(PeridigmDiffusion, DiffusionMaterialMapsToAHeatMaterialAndASteadyHeatRun) {
  const fs::path dir = test_dir();
  const std::string deck = write(dir / "slab.yaml", slab_deck(", Use Improved Quadrature: true", kDiffusionSolver));
  const YAML::Node native = YAML::Load(convert_peridigm_deck(deck));
  const YAML::Node mat = native["materials"]["All"];
  EXPECT_FALSE(mat["model"]);  // heat alone
  EXPECT_FALSE(mat["influence"]);
  EXPECT_EQ(mat["thermal"]["conductivity"].as<double>(), 2.0);
  const YAML::Node th = native["thermal"];
  EXPECT_FALSE(th["conduction"]);  // conducting (the default)
  EXPECT_EQ(th["integration"].as<std::string>(), "steady");
  EXPECT_EQ(th["quadrature"].as<std::string>(), "improved");
  EXPECT_EQ(th["initial_temperature"].as<std::string>(), "273.0");
  ASSERT_EQ(th["boundary"].size(), 2u);
  EXPECT_EQ(native["solver"]["type"].as<std::string>(), "heat");
  EXPECT_EQ(native["solver"]["time_step"].as<double>(), 0.5);
  EXPECT_EQ(native["solver"]["end_time"].as<double>(), 1.0);
  const YAML::Node files = native["output"]["exodus_files"];
  ASSERT_EQ(files.size(), 1u);
  EXPECT_EQ(files[0]["variables"][0].as<std::string>(), "Flux_Divergence");
  // Without the option: the one-point quadrature (no quadrature key).
  const std::string plain = write(dir / "plain.yaml", slab_deck("", kDiffusionSolver));
  EXPECT_FALSE(YAML::Load(convert_peridigm_deck(plain))["thermal"]["quadrature"]);
}

// The steady temperature between the held layers is linear, 273 + 10 x t, at every free
// particle (their families are whole along x, so any quadrature integrates xi_x to 0
// there). The flux divergence vanishes at the free particles (the steady balance); at the
// held ones it vanishes with the improved quadrature (it integrates xi over the whole
// ball) and not with the one-point rule (the end layers' one-sided families).
void slab_run(bool improved) {
  const fs::path dir = test_dir();
  const std::string deck =
      write(dir / "slab.yaml", slab_deck(improved ? ", Use Improved Quadrature: true" : "", kDiffusionSolver));
  const ExodusSeries r = run_and_read(deck, dir, "slab.e");
  ASSERT_EQ(r.steps.size(), 3u);
  const std::size_t T = index_of(r.layout.nodal, "Temperature"), D = index_of(r.layout.nodal, "Flux_Divergence");
  const std::size_t N = index_of(r.layout.element, "Number_Of_Neighbors");
  // kappa = 6 k/(pi delta^4) (inverse kernel, continuum); the scale of a divergence here.
  const double scale = 6 * 2.0 / (3.14159 * std::pow(0.25001, 4)) * 10;
  double held_divergence = 0;
  for (std::size_t s = 0; s < 3; ++s) {
    const double t = 0.5 * static_cast<double>(s);
    EXPECT_DOUBLE_EQ(r.steps[s].time, t);
    for (std::size_t i = 0; i < r.layout.points.size(); ++i) {
      const double x = r.layout.points[i].x;
      EXPECT_NEAR(r.steps[s].nodal[T][i], 273.0 + 10.0 * x * t, 1e-10) << s << " " << i;
      const bool held = x < 0.25 || x > 0.75;
      if (!held || improved) {
        EXPECT_NEAR(r.steps[s].nodal[D][i], 0.0, 1e-10 * scale) << s << " " << i;
      }
      if (held) held_divergence = std::max(held_divergence, std::abs(r.steps[s].nodal[D][i]));
    }
  }
  if (!improved) {
    EXPECT_GT(held_divergence, 1e-3 * scale);
  }
  // The corner particle's family within 3 spacings on the 12 x 3 x 3 grid: offsets
  // (a, b, c), 0 <= a <= 3, 0 <= b, c <= 2, a^2 + b^2 + c^2 <= 9, but itself: 26.
  EXPECT_EQ(r.steps[0].element[N][0], 26.0);
}

TEST(PeridigmDiffusion, SlabIsLinearWithTheImprovedQuadrature) { slab_run(true); }
TEST(PeridigmDiffusion, SlabIsLinearWithTheOnePointQuadrature) { slab_run(false); }

TEST(PeridigmDiffusion, Errors) {
  const fs::path dir = test_dir();
  auto error = [&](const std::string& material, const std::string& solver) {
    return error_of(write(dir / "bad.yaml", slab_deck(material, solver)));
  };
  EXPECT_EQ(error("", kDiffusionSolver), "no error");
  EXPECT_NE(error("", "  Solver: {Final Time: 1.0, Verlet: {Fixed dt: 0.1}}\n")
                .find("a Diffusion material runs with the ImplicitDiffusion solver only"),
            std::string::npos);
  EXPECT_NE(error(", Density: 1.0", kDiffusionSolver).find("Density"), std::string::npos);
  std::string solver = kDiffusionSolver;
  solver.replace(solver.find("Solve For Displacement: false"), 29, "Solve For Displacement: true");
  EXPECT_NE(error("", solver).find("it solves for the temperature alone"), std::string::npos);
  solver = kDiffusionSolver;
  solver.replace(solver.find("Solve For Pressure: false"), 25, "Solve For Pressure: true");
  EXPECT_NE(error("", solver).find("Solve For Pressure: true is not supported"), std::string::npos);
  // The ImplicitDiffusion solver with a mechanical material.
  std::string mech = slab_deck("", kDiffusionSolver);
  const std::string diffusion = "Material Model: \"Diffusion\", Coefficient: 2.0";
  mech.replace(mech.find(diffusion), diffusion.size(),
               "Material Model: \"Elastic\", Density: 1.0, Bulk Modulus: 1.0, Shear Modulus: 1.0");
  EXPECT_NE(error_of(write(dir / "mech.yaml", mech)).find("the ImplicitDiffusion solver needs a Diffusion material"),
            std::string::npos);
  // Coefficient is required, and belongs to Diffusion alone.
  std::string missing = slab_deck("", kDiffusionSolver);
  missing.replace(missing.find(", Coefficient: 2.0"), 18, "");
  EXPECT_NE(error_of(write(dir / "missing.yaml", missing)).find("Coefficient"), std::string::npos);
  // Peridigm's Multiphysics (a fluid pressure coupled to the mechanics): named, not mapped.
  std::string multiphysics = slab_deck("", kDiffusionSolver);
  multiphysics.replace(multiphysics.find("Peridigm:\n"), 10, "Peridigm:\n  Multiphysics: 1\n");
  EXPECT_NE(error_of(write(dir / "multiphysics.yaml", multiphysics)).find("Peridigm's Multiphysics"),
            std::string::npos);
}

}  // namespace
}  // namespace horizon
