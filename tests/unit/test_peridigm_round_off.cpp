// Peridigm's golds to the last bit (docs/peridigm.md "Round-off"): decks whose .comp
// tolerances lie below one ulp of the values compared (ForceX 1e-9 absolute on 4.6e7,
// VelocityY 1e-16 on 1.8e6) match only when the arithmetic is Peridigm's:
// - a hexahedron's particle sits where Peridigm's 24-tetrahedron split puts it, rounded
//   as Peridigm rounds it (the DeformationGradient mesh's first element, whose centre the
//   gold holds);
// - solver.verlet: peridigm (the importer's choice for Verlet): the force pass reads
//   y = (X + u_n) + dt v_{n+1/2}, a = (f + b)/rho, and a prescribed displacement moves
//   through the drift at (g(t1) - g(t0)) (1/(t1 - t0)), its u accumulating (Compression_2x1x1's
//   gold ForceX at each step; the native Verlet's step 2 is 2.6e-4 off);
// - solver.positions: peridigm (the importer's choice for quasi-static solvers): the force
//   pass reads y = (X + u_n) + (u - u_n), u_n the load step's start (Pals_Simple_Shear's
//   gold forces to the bit at its steps t = 0.5 and 1, docs/peridigm.md);
// - a Rectangular_Plane bond filter is Peridigm's test with its bottom vector as given and
//   its 1e-15 tolerances (`precracks: [{rectangle: ...}]`).
#include <exodusII.h>
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "deck_test_support.hpp"
#include "horizon/core/vec3.hpp"
#include "horizon/deck/deck.hpp"
#include "horizon/family/precrack.hpp"
#include "horizon/solver/forces.hpp"
#include "test_helpers.hpp"

namespace horizon {
namespace {

namespace fs = std::filesystem;
using test::error_of;
using test::index_of;
using test::run_and_read;
using test::write;

fs::path test_dir() { return test::fresh_test_dir("horizon_peridigm_round_off"); }

// Two points at x = -1 and +1 closing at 1 m/s each (Peridigm's Compression_2x1x1).
std::string two_points(const std::string& extra_output) {
  return R"(Peridigm:
  Discretization:
    Type: "PdQuickGrid"
    TensorProduct3DMeshGenerator:
      Type: "PdQuickGrid"
      X Origin: -2.0
      Y Origin: -0.5
      Z Origin: -0.5
      X Length: 4.0
      Y Length: 1.0
      Z Length: 1.0
      Number Points X: 2
      Number Points Y: 1
      Number Points Z: 1
  Materials:
    Steel: {Material Model: "Elastic", Density: 7800.0, Bulk Modulus: 130.0e9, Shear Modulus: 78.0e9}
  Blocks:
    All: {Block Names: "block_1", Material: "Steel", Horizon: 2.0}
  Boundary Conditions:
    Left: "1"
    Right: "2"
    Push Left: {Type: "Initial Velocity", Node Set: "Left", Coordinate: "x", Value: "1.0"}
    Push Right: {Type: "Initial Velocity", Node Set: "Right", Coordinate: "x", Value: "-1.0"}
  Solver:
    Initial Time: 0.0
    Final Time: 0.00005
    Verlet: {Fixed dt: 0.00001}
  Output:
    Output File Type: "ExodusII"
    Output Filename: "two"
    Output Frequency: 1
    Output Variables: {Displacement: true, Velocity: true, Force: true)" +
         extra_output + R"(}
)";
}

// Peridigm's gold (Compression_2x1x1_gold.e): the left point's ForceX at steps 1 to 5.
const double kGoldForceX[5] = {-23399999.999893505, -46448999.99984187, -68801265.00007577, -90121511.02513188,
                               -110089934.38470061};

TEST(PeridigmRoundOff, VerletIsPeridigmsArithmeticForImportedDecks) {
  const fs::path dir = test_dir();
  const std::string deck = write(dir / "two.yaml", two_points(""));
  const YAML::Node native = YAML::Load(convert_peridigm_deck(deck));
  EXPECT_EQ(native["solver"]["verlet"].as<std::string>(), "peridigm");
  const ExodusSeries r = run_and_read(deck, dir, "two.e");
  ASSERT_EQ(r.steps.size(), 6u);
  const std::size_t fx = index_of(r.layout.nodal, "ForceX");
  const std::size_t left = r.layout.points[0].x < 0 ? 0 : 1;
  for (int k = 0; k < 5; ++k)  // Peridigm's .comp: ForceX absolute 1e-9 (below an ulp here: exact)
    EXPECT_NEAR(r.steps[static_cast<std::size_t>(k) + 1].nodal[fx][left], kGoldForceX[k], 1e-9) << "step " << k + 1;

  // The same native deck with Horizon's own Verlet: y = X + u_{n+1} rounds otherwise, and
  // the gold's step 2 is 2.6e-4 away (the reason for the option).
  YAML::Node own = YAML::Load(convert_peridigm_deck(deck));
  own["solver"]["verlet"] = "horizon";
  const fs::path own_dir = dir / "own";
  fs::create_directories(own_dir);
  std::ofstream(own_dir / "deck.yaml") << YAML::Dump(own);
  const ExodusSeries h = run_and_read((own_dir / "deck.yaml").string(), own_dir, "two.e");
  ASSERT_EQ(h.steps.size(), 6u);
  EXPECT_GT(std::abs(h.steps[2].nodal[fx][left] - kGoldForceX[1]), 1e-5);
  EXPECT_NEAR(h.steps[2].nodal[fx][left], kGoldForceX[1], 1e-3);  // the same physics
}

TEST(PeridigmRoundOff, PrescribedDisplacementAccumulatesThroughTheDrift) {
  // Every point of the pair driven by g = 0.1 x t / 2e-8: u_n = u_{n-1} + dt (g(t_n) -
  // g(t_n-1)) (1/(t_n - t_n-1)) with t_n = n dt, to the last bit (DeformationGradient's
  // golds hold these displacements with 1e-16 absolute); the velocity written is the rate
  // plus the second half kick.
  const fs::path dir = test_dir();
  std::string text = two_points("");
  const std::string push = "    Push Left: {Type: \"Initial Velocity\", Node Set: \"Left\", Coordinate: \"x\", Value: \"1.0\"}\n"
                           "    Push Right: {Type: \"Initial Velocity\", Node Set: \"Right\", Coordinate: \"x\", Value: \"-1.0\"}\n";
  const std::string shear = "    All Points: \"1 2\"\n"
                            "    Shear: {Type: \"Prescribed Displacement\", Node Set: \"All Points\", Coordinate: \"x\", "
                            "Value: \"0.1*x*t/(2.0e-8)\"}\n";
  text.replace(text.find(push), push.size(), shear);
  const std::string deck = write(dir / "shear.yaml", text);
  const ExodusSeries r = run_and_read(deck, dir, "two.e");
  ASSERT_EQ(r.steps.size(), 6u);
  const std::size_t ux = index_of(r.layout.nodal, "DisplacementX");
  const double dt = 0.00001;
  for (std::size_t i = 0; i < 2; ++i) {
    const double x = r.layout.points[i].x;
    auto g = [&](double t) { return 0.1 * x * t / (2.0e-8); };
    double u = 0;
    bool differs_from_g = false;
    for (int n = 1; n <= 5; ++n) {
      const double t1 = n * dt, t0 = (n - 1) * dt;
      u = u + dt * ((g(t1) - g(t0)) * (1.0 / (t1 - t0)));
      EXPECT_EQ(r.steps[static_cast<std::size_t>(n)].nodal[ux][i], u) << "point " << i << " step " << n;
      differs_from_g = differs_from_g || u != g(t1);
    }
    EXPECT_TRUE(differs_from_g) << "the accumulated u equals g(t) at every step: the test shows nothing";
  }
}

TEST(PeridigmRoundOff, PrescribedDisplacementStartsFromTheInitialState) {
  // g = 1 + 100 t: Peridigm applies the increments from t = 0, so u_n = g(t_n) - g(0) =
  // 100 t_n (DeformationGradient_PlaneStrainCompression's gold, g = x exp(0.0953 t/1e-8),
  // moves its points by g(t) - g(0)); Horizon's own Verlet sets u = g(t), 1 + 100 t.
  const fs::path dir = test_dir();
  std::string text = two_points("");
  const std::string push = "    Push Left: {Type: \"Initial Velocity\", Node Set: \"Left\", Coordinate: \"x\", Value: \"1.0\"}\n";
  text.replace(text.find(push), push.size(),
               "    Move Left: {Type: \"Prescribed Displacement\", Node Set: \"Left\", Coordinate: \"x\", "
               "Value: \"1.0 + 100.0*t\"}\n");
  const std::string deck = write(dir / "offset.yaml", text);
  const ExodusSeries r = run_and_read(deck, dir, "two.e");
  ASSERT_EQ(r.steps.size(), 6u);
  const std::size_t ux = index_of(r.layout.nodal, "DisplacementX");
  const std::size_t left = r.layout.points[0].x < 0 ? 0 : 1;
  EXPECT_EQ(r.steps[0].nodal[ux][left], 0.0);
  for (std::size_t n = 1; n < 6; ++n)
    EXPECT_NEAR(r.steps[n].nodal[ux][left], 100.0 * static_cast<double>(n) * 0.00001, 1e-15) << n;
}

TEST(PeridigmRoundOff, VerletKeyIsChecked) {
  const fs::path dir = test_dir();
  const std::string base = "dimension: 3\nspacing: 1.0\nhorizon: 1.75\n"
                           "materials:\n  steel: {model: lps, density: 7800, bulk_modulus: 130.0e9, shear_modulus: 78.0e9}\n"
                           "bodies:\n  - {name: bar, material: steel, shape: {box: {min: [-1.5, -1, -1], max: [1.5, 1, 1]}}}\n";
  EXPECT_EQ(error_of(write(dir / "ok.yaml", base + "solver: {end_time: 1.0e-6, verlet: peridigm}\n")), "no error");
  EXPECT_NE(error_of(write(dir / "bad.yaml", base + "solver: {end_time: 1.0e-6, verlet: lammps}\n")).find("verlet"),
            std::string::npos);
  const std::string damped = error_of(write(dir / "damped.yaml", base + "solver: {end_time: 1.0e-6, verlet: peridigm, damping: 10}\n"));
  EXPECT_NE(damped.find("no damping"), std::string::npos) << damped;
  const std::string stat = error_of(write(dir / "static.yaml", base + "solver: {type: static, end_time: 1, verlet: peridigm}\n"));
  EXPECT_NE(stat.find("type: explicit only"), std::string::npos) << stat;
}

// Peridigm's quasi-static positions: with u_n = -y 1e-6 0.5 and u = -y 1e-6 (Pals_Simple_
// Shear's shear at t = 0.5 and 1, y = 5/14 as its mesh rounds it), (y + u_n) + (u - u_n) is
// 0.3571425 and y + u is 0.35714250000000003: the packing takes the former where
// System::step_start_u is set, and X + u without it. The key is static-only.
TEST(PeridigmRoundOff, QuasiStaticPositionsArePeridigms) {
  test::BlockSpec b;
  b.n = {2, 1, 1};
  b.spacing = 0.35714285714285715;
  b.horizon_factor = 1.5;
  System s = test::make_block(b, test::make_material("pmb", 1e9, 0.25));
  ASSERT_EQ(s.particles.size(), 2u);
  const std::size_t i = s.particles.X[0].x > 0 ? 0 : 1;
  const double x = s.particles.X[i].x;
  ASSERT_EQ(x, 0.35714285714285715);
  const double un = ((-x) * 1e-06) * 0.5, u = ((-x) * 1e-06) * 1.0;
  s.particles.u[i] = {u, 0, 0};
  pack_positions(s);
  EXPECT_EQ(s.model.packed[i].x, x + u);
  s.step_start_u.assign(2, Vec3{});
  s.step_start_u[i] = {un, 0, 0};
  pack_positions(s);
  EXPECT_EQ(s.model.packed[i].x, (x + un) + (u - un));
  EXPECT_EQ(s.model.packed[i].x, 0.3571425);
  EXPECT_NE(x + u, 0.3571425);

  const fs::path dir = test_dir();
  const std::string base = "dimension: 3\nspacing: 1.0\nhorizon: 1.75\n"
                           "materials:\n  steel: {model: lps, density: 7800, bulk_modulus: 130.0e9, shear_modulus: 78.0e9}\n"
                           "bodies:\n  - {name: bar, material: steel, shape: {box: {min: [-1.5, -1, -1], max: [1.5, 1, 1]}}}\n";
  EXPECT_EQ(error_of(write(dir / "qs.yaml", base + "solver: {type: static, end_time: 1, positions: peridigm}\n")), "no error");
  EXPECT_NE(error_of(write(dir / "qs_bad.yaml", base + "solver: {type: static, end_time: 1, positions: lammps}\n")).find("positions"),
            std::string::npos);
  const std::string expl = error_of(write(dir / "expl.yaml", base + "solver: {end_time: 1.0e-6, positions: peridigm}\n"));
  EXPECT_NE(expl.find("type: static only"), std::string::npos) << expl;
}

// One hexahedron of Peridigm's DeformationGradient mesh (its nodes as the mesh holds them).
TEST(PeridigmRoundOff, HexahedronCentreHasPeridigmsRounding) {
  const fs::path dir = test_dir();
  const double a = 0.55, b = 0.18333333333333335, c = 0.1833333333333333, d = 0.18333333333333332;
  const std::vector<double> x = {-a, -a, -a, -a, -b, -b, -d, -b};
  const std::vector<double> y = {-a, -a, -b, -b, -a, -a, -b, -c};
  const std::vector<double> z = {a, b, c, a, a, c, b, a};
  int cpu_ws = sizeof(double), io_ws = sizeof(double);
  const std::string mesh = (dir / "mesh.g").string();
  const int id = ex_create(mesh.c_str(), EX_CLOBBER, &cpu_ws, &io_ws);
  ASSERT_GE(id, 0);
  ASSERT_GE(ex_put_init(id, "hex", 3, 8, 1, 1, 1, 0), 0);
  ex_put_coord(id, x.data(), y.data(), z.data());
  ex_put_block(id, EX_ELEM_BLOCK, 1, "HEX8", 1, 8, 0, 0, 0);
  const std::vector<int> conn = {1, 2, 3, 4, 5, 6, 7, 8};
  ex_put_conn(id, EX_ELEM_BLOCK, 1, conn.data(), nullptr, nullptr);
  const int set_nodes[1] = {1};
  ex_put_set_param(id, EX_NODE_SET, 1, 1, 0);
  ex_put_set(id, EX_NODE_SET, 1, set_nodes, nullptr);
  ASSERT_GE(ex_close(id), 0);
  const std::string deck = write(dir / "deck.yaml", R"(Peridigm:
  Discretization: {Type: "Exodus", Input Mesh File: "mesh.g"}
  Materials:
    Steel: {Material Model: "Elastic", Density: 7800.0, Bulk Modulus: 130.0e9, Shear Modulus: 78.0e9}
  Blocks:
    All: {Block Names: "block_1", Material: "Steel", Horizon: 5.0}
  Solver:
    Final Time: 1.0e-8
    Verlet: {Fixed dt: 1.0e-9}
)");
  const YAML::Node native = YAML::Load(convert_peridigm_deck(deck));
  const YAML::Node p = native["bodies"][0]["shape"]["points"][0];
  // The gold's coordinates of this element (DeformationGradient_PureShear_gold.e, node 1);
  // the mean of the nodes, and the exact centre of volume, are (-11/30, -11/30, 11/30)
  // rounded: -0.3666666666666667 and 0.3666666666666667.
  EXPECT_EQ(p[0].as<double>(), -0.3666666666666665);
  EXPECT_EQ(p[1].as<double>(), -0.3666666666666666);
  EXPECT_EQ(p[2].as<double>(), 0.36666666666666653);
  const double edge = a - b;  // the exact volume, a cube of edge 11/30 to rounding
  EXPECT_NEAR(p[3].as<double>(), edge * edge * edge, 1e-15);
}

TEST(PeridigmRoundOff, RectangleIsPeridigmsPlaneTest) {
  // PrecrackedPlateTwoCracks's right filter: the plane y = 4 from (0, 4, -10), bottom
  // (1, 4, 0) (not a unit vector: d.bottom = d.x + 4 d.y), 10 along it, 20 along
  // bottom x normal = +z.
  Precrack c;
  c.rectangle = true;
  c.corner = {0, 4, -10};
  c.normal = {0, 1, 0};
  c.bottom = {1, 4, 0};
  c.bottom_length = 10;
  c.side_length = 20;
  auto bond = [&](double x0, double x1, double z = 0) {
    return crosses_rectangle({x0, 3.5, z}, {x1, 4.5, z}, c);
  };
  EXPECT_TRUE(bond(5, 5));
  EXPECT_TRUE(bond(0.5, -0.5));          // through the edge x = 0: d.bottom = 0 > -1e-15
  EXPECT_TRUE(bond(-4e-16, -4e-16));     // within the tolerance
  EXPECT_FALSE(bond(-2e-15, -2e-15));    // beyond it
  EXPECT_TRUE(bond(9.99, 9.99));
  EXPECT_FALSE(bond(10.5, 10.5));
  EXPECT_FALSE(bond(5, 5, -10.5));       // below the side's start (z = -10)
  EXPECT_FALSE(bond(5, 5, 10.5));        // beyond its end (z = 10)
  EXPECT_FALSE(crosses_rectangle({5, 3.5, 0}, {5, 3.9, 0}, c));  // short of the plane
  EXPECT_FALSE(crosses_rectangle({5, 4, 0}, {6, 4, 0}, c));      // in the plane: parallel
  // Either direction of a bond: the pair is cut when one direction crosses.
  EXPECT_TRUE(crosses({5, 3.5, 0}, {5, 4.5, 0}, c, 3) && crosses({5, 4.5, 0}, {5, 3.5, 0}, c, 3));
}

TEST(PeridigmRoundOff, RectangularPlaneFilterMapsToTheRectangle) {
  const fs::path dir = test_dir();
  std::string text = two_points("");
  const std::string disc = "      Number Points Z: 1\n";
  text.replace(text.find(disc), disc.size(),
               disc + "    Bond Filters:\n      Cut:\n        Type: \"Rectangular_Plane\"\n"
                      "        Normal_X: 1.0\n        Normal_Y: 0.0\n        Normal_Z: 0.0\n"
                      "        Lower_Left_Corner_X: 0.0\n        Lower_Left_Corner_Y: -1.0\n        Lower_Left_Corner_Z: -1.0\n"
                      "        Bottom_Unit_Vector_X: 4.0\n        Bottom_Unit_Vector_Y: 1.0\n        Bottom_Unit_Vector_Z: 0.0\n"
                      "        Bottom_Length: 2.0\n        Side_Length: 2.0\n");
  const YAML::Node native = YAML::Load(convert_peridigm_deck(write(dir / "cut.yaml", text)));
  const YAML::Node r = native["precracks"][0]["rectangle"];
  ASSERT_TRUE(r.IsMap()) << YAML::Dump(native["precracks"]);
  EXPECT_EQ(r["bottom"][0].as<double>(), 4.0);  // as given, not normalised
  EXPECT_EQ(r["bottom"][1].as<double>(), 1.0);
  EXPECT_EQ(r["corner"][1].as<double>(), -1.0);
  EXPECT_EQ(r["side_length"].as<double>(), 2.0);
}

}  // namespace
}  // namespace horizon
