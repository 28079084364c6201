// Finite-element bodies made of a mesh's elements (fe/fe_region.hpp, BodyConfig::fe_mesh;
// docs/input.md "Finite-element bodies"). Checked here:
// - a bar 10 x 2 x 2 mm meshed by the test (Gmsh MSH 4.1 and Exodus II, hex8 and tet4,
//   regular and with jittered interior nodes) and pulled at one end through the mesh's
//   node sets: its element volumes add up to the bar's (1e-12 relative); on the regular
//   mesh its reaction history is the box FE bar's (the same elements built from the
//   lattice) to round-off; every mesh gives E * strain within 1 % (quasi-static loading,
//   the FePlasticity bar's ramp);
// - the patch test across the coupling: a meshed cube around a peridynamic core (mesh
//   nodes at the core's lattice points within the coupling zone, jittered away from it):
//   a uniform strain leaves no force on any interior degree of freedom (hex8, tet4);
// - errors: an element type the FE does not take, a block the mesh lacks, an inverted
//   element, each naming the deck's line:column and the mesh file; a particle inside a
//   mesh element off its nodes.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "../single_thread.hpp"
#include "horizon/core/error.hpp"
#include "horizon/deck/deck.hpp"
#include "horizon/driver/run.hpp"
#include "horizon/fe/fe_region.hpp"
#include "horizon/geometry/mesh.hpp"
#include "horizon/loading/loads.hpp"
#include "horizon/solver/forces.hpp"
#include "mesh_writers.hpp"
#include "verification_support.hpp"

namespace horizon::verification {
namespace {

constexpr double kE = 70e9, kL = 10e-3, kA = 4e-6;
constexpr double kEps = 1e-3, kT = 100e-6;  // strain reached by a sin^2 ramp in kT

// The bar's deck: `shape` the body's shape, `left`/`right` the regions at its ends.
std::string bar_deck(const std::string& shape, const std::string& left, const std::string& right) {
  return fmt::format(R"deck(
dimension: 3
spacing: 1.0e-3
horizon: 3.0e-3
lattice_origin: [0, 0, 0]
materials:
  al: {{model: pmb, density: 2700, youngs_modulus: {E}}}
bodies:
  - {{name: bar, material: al, discretization: fe, shape: {shape}}}
regions:
  left: {left}
  right: {right}
loads:
  - {{region: left, displacement: [0, null, null]}}
  - {{region: right, displacement: ["{U}*sin(pi*t/(2*{T}))^2", null, null]}}
solver: {{end_time: {T}, safety_factor: 0.8}}
)deck",
                     fmt::arg("E", kE), fmt::arg("shape", shape), fmt::arg("left", left), fmt::arg("right", right),
                     fmt::arg("U", kEps * kL), fmt::arg("T", kT));
}

std::string box_bar(const char* element) {
  return bar_deck(fmt::format("{{box: {{min: [0, 0, 0], max: [{}, 2.0e-3, 2.0e-3]}}}}, element: {}", kL, element),
                  "{box: {min: [-1, -1, -1], max: [0.5e-3, 1, 1]}}", "{box: {min: [9.5e-3, -1, -1], max: [1, 1, 1]}}");
}

std::string mesh_bar(const std::string& file) {
  return bar_deck("{mesh: {file: " + file + ", block: block}}", "{mesh: {file: " + file + ", set: left}}",
                  "{mesh: {file: " + file + ", set: right}}");
}

struct BarRun {
  std::vector<double> eps, sigma;  // per step: end strain, bar stress (left reaction / A)
  double volume = 0;               // sum of the element volumes
  std::size_t elements = 0;
};

BarRun run_bar(const std::string& deck, const std::string& name) {
  test::SingleThread one;
  Simulation sim(parse_deck(deck, name));
  BarRun r;
  r.elements = sim.system.fe->elements();
  for (double v : sim.system.fe->volume) r.volume += v;
  const AppliedLoad* left = nullptr;
  for (const auto& L : sim.loads.loads())
    if (L.name.rfind("left", 0) == 0) left = &L;
  const std::size_t probe = sim.nearest({kL, 1e-3, 1e-3});
  while (sim.solver->time() < sim.config.solver.end_time) {
    sim.solver->step(false);
    r.eps.push_back(sim.system.particles.u[probe].x / kL);
    r.sigma.push_back(-left->reaction.x / kA);
  }
  return r;
}

// Largest relative error of the stress against E eps at strains through the ramp.
double worst_against_hooke(const BarRun& r, std::string& where) {
  double worst = 0;
  for (double target : {0.2e-3, 0.4e-3, 0.6e-3, 0.8e-3, 0.95e-3}) {
    std::size_t k = 0;
    while (k + 2 < r.eps.size() && r.eps[k + 1] < target) ++k;
    const double t = (target - r.eps[k]) / (r.eps[k + 1] - r.eps[k]);
    const double s = r.sigma[k] + t * (r.sigma[k + 1] - r.sigma[k]);
    const double err = s / (kE * target) - 1;
    where += fmt::format(" {:.2g}: {:+.1e}", target, err);
    worst = std::max(worst, std::abs(err));
  }
  return worst;
}

TEST(FeMesh, MeshedBarMatchesTheBoxBarAndHookesLaw) {
  const auto dir = output_dir("fe_mesh_bar");
  struct Case {
    const char* file;
    bool tets, exodus;
    double jitter;
  };
  const Case cases[] = {{"hex.msh", false, false, 0.0},
                        {"tet.msh", true, false, 0.0},
                        {"hex_jitter.exo", false, true, 0.25},
                        {"tet_jitter.msh", true, false, 0.25}};
  const BarRun box_hex = run_bar(box_bar("hex8"), "box_hex.yaml");
  const BarRun box_tet = run_bar(box_bar("tet4"), "box_tet.yaml");
  for (const auto& c : cases) {
    // 10 x 2 x 2 cells of the lattice spacing, the nodes on the lattice (lattice_origin 0).
    const test::BoxMesh m = test::box_mesh({0, 0, 0}, {kL, 2e-3, 2e-3}, 10, 2, 2, c.tets, c.jitter);
    const std::string path = (dir / c.file).string();
    if (c.exodus) {
      ASSERT_TRUE(test::write_exodus(m, path));
    } else {
      test::write_msh(m, path, false);
    }
    const BarRun r = run_bar(mesh_bar(path), std::string(c.file) + ".yaml");
    ASSERT_EQ(r.elements, m.cells.size()) << c.file;
    ASSERT_GT(r.eps.size(), 100u) << c.file;
    const double vol = std::abs(r.volume / (kL * kA) - 1);
    std::string where;
    const double hooke = worst_against_hooke(r, where);
    std::string vs_box = "";
    double box_diff = 0;
    if (c.jitter == 0) {
      // The same elements as the box body on the lattice: the same history.
      const BarRun& b = c.tets ? box_tet : box_hex;
      ASSERT_EQ(b.sigma.size(), r.sigma.size()) << c.file;
      double peak = 0;
      for (std::size_t k = 0; k < b.sigma.size(); ++k) {
        peak = std::max(peak, std::abs(b.sigma[k]));
        box_diff = std::max(box_diff, std::abs(r.sigma[k] - b.sigma[k]));
      }
      box_diff /= peak;
      vs_box = fmt::format("; largest |stress - box FE bar's| / peak stress {:.1e}", box_diff);
      EXPECT_LT(box_diff, 1e-9) << c.file;
    }
    report(fmt::format("fe_mesh_bar_{}", c.file), hooke,
           fmt::format("meshed FE bar {} ({} elements, jitter {}): volume - L A = {:.1e} relative; stress / (E eps) - 1 "
                       "at strain{}{}",
                       c.file, r.elements, c.jitter, vol, where, vs_box));
    EXPECT_LT(vol, 1e-12) << c.file;
    EXPECT_LT(hooke, 0.01) << c.file;
  }
}

// The cube of the patch test: nodes at 0.5 + i mm (i = 0..19), the lattice of a
// peridynamic core box [8, 12]^3 mm (particles at 8.5 ... 11.5 mm). Nodes farther than
// the coupling zone (the ghosts within a horizon of the core and their elements: 4.5 to
// 15.5 mm) and off the outer faces are jittered by up to 0.2 spacings.
std::string write_cube(const std::filesystem::path& dir, bool tets) {
  test::BoxMesh m = test::box_mesh({0.5e-3, 0.5e-3, 0.5e-3}, {19.5e-3, 19.5e-3, 19.5e-3}, 19, 19, 19, tets, 0);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-0.2e-3, 0.2e-3);
  for (auto& x : m.nodes) {
    bool face = false, zone = true;
    for (int k = 0; k < 3; ++k) {
      face = face || x[k] < 0.6e-3 || x[k] > 19.4e-3;
      zone = zone && x[k] > 4.4e-3 && x[k] < 15.6e-3;
    }
    if (!face && !zone) x += Vec3{u(rng), u(rng), u(rng)};
  }
  const std::string path = (dir / (tets ? "cube_tet.msh" : "cube_hex.msh")).string();
  test::write_msh(m, path, true);
  return path;
}

void mesh_patch_test(bool tets) {
  test::SingleThread one;
  const std::string file = write_cube(output_dir("fe_mesh_patch"), tets);
  const std::string deck = fmt::format(R"deck(
dimension: 3
spacing: 1.0e-3
horizon: 3.0e-3
materials:
  al: {{model: pmb, density: 2700, youngs_modulus: 68.9e9}}
bodies:
  - {{name: core, material: al, shape: {{box: {{min: [8.0e-3, 8.0e-3, 8.0e-3], max: [12.0e-3, 12.0e-3, 12.0e-3]}}}}}}
  - {{name: outer, material: al, discretization: fe, shape: {{mesh: {{file: {}}}}}}}
solver: {{end_time: 1.0e-6}}
)deck",
                                       file);
  System s = build_system(parse_deck(deck, "mesh_patch.yaml"));
  ASSERT_TRUE(s.fe);
  const FeRegion& fe = *s.fe;
  auto& P = s.particles;
  const double G[3][3] = {{1.0e-4, 2.0e-5, -1.0e-5}, {2.0e-5, -3.0e-5, 1.5e-5}, {-1.0e-5, 1.5e-5, 5.0e-5}};
  for (std::size_t i = 0; i < P.size(); ++i)
    for (int r = 0; r < 3; ++r) P.u[i][r] = G[r][0] * P.X[i].x + G[r][1] * P.X[i].y + G[r][2] * P.X[i].z;
  compute_forces(s, true);
  const double scale = 68.9e9 * 1.0e-4 * 1.0e-6;  // E |G| h^2
  double worst_pd = 0, worst_fe = 0, worst_jittered = 0;
  std::size_t pd = 0, fe_owned = 0;
  for (std::size_t i = 0; i < P.size(); ++i) {
    bool face = false, zone = true;
    for (int k = 0; k < 3; ++k) {
      face = face || P.X[i][k] < 0.6e-3 || P.X[i][k] > 19.4e-3;
      zone = zone && P.X[i][k] > 4.4e-3 && P.X[i][k] < 15.6e-3;
    }
    if (face) continue;  // the outer faces carry the uniform stress's traction
    const double f = norm(P.f[i]) * P.volume[i] / scale;
    if (fe.owned_particle[i]) {
      worst_fe = std::max(worst_fe, f);
      if (!zone) worst_jittered = std::max(worst_jittered, f);
      ++fe_owned;
    } else {
      worst_pd = std::max(worst_pd, f);
      ++pd;
    }
  }
  const char* el = tets ? "tet4" : "hex8";
  report(fmt::format("fe_mesh_patch_{}", el), std::max(worst_pd, worst_fe),
         fmt::format("patch test, meshed {} cube (jittered outside the coupling zone) around a PD core ({} particles, "
                     "{} FE-owned inner nodes, {} elements, {} shared nodes): largest force / (E |grad u| h^2): "
                     "particles {:.1e}, FE nodes {:.1e} (jittered ones {:.1e})",
                     el, pd, fe_owned, fe.elements(), fe.shared_nodes(), worst_pd, worst_fe, worst_jittered));
  EXPECT_EQ(pd, 64u);
  // The core's particles that are nodes of a kept element: all but the 2 x 2 x 2 inner
  // ones, whose elements are all peridynamic (left out).
  EXPECT_EQ(fe.shared_nodes(), 56u);
  EXPECT_LT(worst_pd, 1e-9);
  EXPECT_LT(worst_fe, 1e-9);
}

TEST(FeMesh, PatchTestAcrossTheCouplingMeshedHex8) { mesh_patch_test(false); }
TEST(FeMesh, PatchTestAcrossTheCouplingMeshedTet4) { mesh_patch_test(true); }

// One 6-node prism (Gmsh type 6) in a block "block": an element type the FE does not take.
std::string write_prism(const std::filesystem::path& dir) {
  const std::string path = (dir / "prism.msh").string();
  std::ofstream out(path);
  out << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n3 1 \"block\"\n$EndPhysicalNames\n"
         "$Entities\n0 0 0 1\n1 0 0 0 1 1 1 1 1 0\n$EndEntities\n"
         "$Nodes\n1 6 1 6\n3 1 0 6\n1\n2\n3\n4\n5\n6\n0 0 0\n1e-3 0 0\n0 1e-3 0\n0 0 1e-3\n1e-3 0 1e-3\n0 1e-3 1e-3\n"
         "$EndNodes\n$Elements\n1 1 1 1\n3 1 6 1\n1 1 2 3 4 5 6\n$EndElements\n";
  return path;
}

TEST(FeMesh, DeckErrorsNameTheKeyAndTheMeshFile) {
  const auto dir = output_dir("fe_mesh_errors");
  auto fails_with = [](const std::string& text, const std::vector<std::string>& expected) {
    try {
      build_system(parse_deck(text, "bad.yaml"));
      ADD_FAILURE() << "no error; expected " << expected.front();
    } catch (const Error& e) {
      for (const auto& x : expected) EXPECT_NE(std::string(e.what()).find(x), std::string::npos) << e.what();
    }
  };
  const std::string head =
      "dimension: 3\nspacing: 1.0e-3\nhorizon: 3.0e-3\nmaterials:\n  al: {model: pmb, density: 2700, "
      "youngs_modulus: 68.9e9}\nbodies:\n";
  const std::string tail = "}}}\nsolver: {end_time: 1e-6}\n";
  // A prism.
  const std::string prism = write_prism(dir);
  fails_with(head + "  - {name: a, material: al, discretization: fe, shape: {mesh: {file: " + prism + tail,
             {"bad.yaml:7:63: error: bodies[0].shape.mesh: element 1 of the mesh " + prism + " is a wedge;",
              "8-node hexahedra (hex8) and 4-node tetrahedra (tet4) only"});
  // A block the mesh lacks.
  const test::BoxMesh hex = test::box_mesh({0, 0, 0}, {4e-3, 2e-3, 2e-3}, 4, 2, 2, false);
  const std::string good = (dir / "hex.msh").string();
  test::write_msh(hex, good, false);
  fails_with(head + "  - {name: a, material: al, discretization: fe, shape: {mesh: {file: " + good +
                 ", block: plate" + tail,
             {"bad.yaml:7:", "bodies[0].shape.mesh.block: the mesh " + good + " has no block 'plate'; its blocks: block"});
  // An inverted hexahedron: element 3's bottom and top faces swapped.
  test::BoxMesh inv = hex;
  std::swap_ranges(inv.cells[2].begin(), inv.cells[2].begin() + 4, inv.cells[2].begin() + 4);
  const std::string inverted = (dir / "inverted.msh").string();
  test::write_msh(inv, inverted, false);
  fails_with(head + "  - {name: a, material: al, discretization: fe, shape: {mesh: {file: " + inverted + tail,
             {"bad.yaml:7:63: error: bodies[0].shape.mesh: element 3 (hex8) of the mesh " + inverted +
              " is inverted or degenerate"});
  // element: names the other type.
  fails_with(head + "  - {name: a, material: al, discretization: fe, element: tet4, shape: {mesh: {file: " + good +
                 tail,
             {"bad.yaml:7:58: error: bodies[0].element: the mesh " + good + " holds hex8 elements"});
  // A peridynamic particle inside a kept element off its nodes (the core's default
  // lattice sits half a spacing off the mesh's nodes).
  fails_with(head + "  - {name: core, material: al, shape: {box: {min: [0, 0, 0], max: [1.0e-3, 1.0e-3, 1.0e-3]}}}\n" +
                 "  - {name: a, material: al, discretization: fe, shape: {mesh: {file: " + good + tail,
             {"body 'a' (finite elements from the mesh " + good + "): the particle at (0.0005, 0.0005, 0.0005) of body "
              "'core' lies in element 1 of the mesh but at none of its nodes"});
}

}  // namespace
}  // namespace horizon::verification
