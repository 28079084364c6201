// Mesh input (geometry/mesh.hpp; docs/input.md "Meshes"): a box meshed by the test as
// Gmsh .msh (every version Gmsh writes, through the Gmsh library) and Exodus II gives
// particles at the element centres
// carrying the element volumes -- the box's volume to 1e-12 relative, also for distorted
// hexahedra and tetrahedra -- and, meshed with cubes of the lattice spacing, the very
// particles of Horizon's own lattice and the same static tension result. Bad meshes are
// errors naming the deck's line and column and the mesh file.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include <fmt/format.h>

#include <omp.h>

#include "horizon/core/error.hpp"
#include "horizon/geometry/gmsh_library.hpp"
#include "horizon/geometry/mesh.hpp"
#include "horizon/solver/static_driver.hpp"
#include "../single_thread.hpp"
#include "mesh_writers.hpp"
#include "verification_support.hpp"

namespace horizon::verification {
namespace {

constexpr double h = 1e-3;
const Vec3 kLo{0, 0, 0};
const Vec3 kHi{12 * h, 4 * h, 4 * h};
constexpr double kBoxVolume = 12 * 4 * 4 * h * h * h;

double total_volume(const Mesh& m) {
  double v = 0;
  for (double x : m.measure) v += x;
  return v;
}

TEST(MeshInput, VolumesTileTheBox) {
  const auto dir = output_dir("mesh_volumes");
  struct Case {
    const char* name;
    bool tets, binary, exodus;
    double jitter;
  };
  const Case cases[] = {{"hex.msh", false, false, false, 0},       {"hex_bin.msh", false, true, false, 0},
                        {"hex_jitter.msh", false, false, false, 0.3}, {"tet_jitter.msh", true, false, false, 0.3},
                        {"hex.exo", false, false, true, 0},       {"tet_jitter.exo", true, false, true, 0.3}};
  for (const auto& c : cases) {
    const test::BoxMesh box = test::box_mesh(kLo, kHi, 12, 4, 4, c.tets, c.jitter);
    const std::string path = (dir / c.name).string();
    if (c.exodus) {
      ASSERT_TRUE(test::write_exodus(box, path));
    } else {
      test::write_msh(box, path, c.binary);
    }
    const Mesh m = read_mesh(path, 3);
    ASSERT_EQ(m.cell_nodes.size(), box.cells.size()) << c.name;
    const double rel = std::abs(total_volume(m) / kBoxVolume - 1);
    report(std::string("mesh_volume_") + c.name, rel,
           fmt::format("mesh {}: {} elements, total volume - box volume = {:.1e} relative", c.name,
                       m.cell_nodes.size(), rel));
    EXPECT_LT(rel, 1e-12) << c.name;
    // The sets: 'left' and 'right' each touch one layer of cells (hexahedra: 4 x 4).
    const MeshGroup* left = m.find_set("left");
    ASSERT_NE(left, nullptr) << c.name;
    EXPECT_EQ(left->members.size(), 25u) << c.name;
    if (!c.tets) {
      EXPECT_EQ(m.cells_touching(*left).size(), 16u) << c.name;
    }
    ASSERT_NE(m.find_block("block"), nullptr) << c.name;
  }
}

// A distorted hexahedron's volume against its split into tetrahedra when its faces are
// planar (a parallelepiped sheared in two directions): the trilinear quadrature and the
// split agree, and the centre of volume is the node average.
TEST(MeshInput, CellGeometry) {
  const Vec3 a{1e-3, 0, 0}, b{0.3e-3, 2e-3, 0}, c{0.2e-3, -0.4e-3, 1.5e-3}, o{0.1, 0.2, 0.3};
  const std::vector<Vec3> hex = {o, o + a, o + a + b, o + b, o + c, o + a + c, o + a + b + c, o + b + c};
  double V;
  Vec3 centre;
  cell_geometry(CellType::hex8, hex, V, centre);
  const double exact = std::abs(dot(a, cross(b, c)));
  EXPECT_NEAR(V / exact, 1.0, 1e-13);
  EXPECT_LT(norm(centre - (o + (a + b + c) * 0.5)), 1e-15);
  // A wedge is half of it.
  const std::vector<Vec3> wedge = {o, o + a, o + b, o + c, o + a + c, o + b + c};
  cell_geometry(CellType::wedge6, wedge, V, centre);
  EXPECT_NEAR(V / (0.5 * exact), 1.0, 1e-13);
  EXPECT_LT(norm(centre - (o + (a + b) / 3.0 + c * 0.5)), 1e-15);
  // A pyramid over the base o, o+a, o+a+b, o+b with apex o+c: one third of base x height.
  const std::vector<Vec3> pyramid = {o, o + a, o + a + b, o + b, o + c};
  cell_geometry(CellType::pyramid5, pyramid, V, centre);
  EXPECT_NEAR(V / (exact / 3.0), 1.0, 1e-13);
  const std::vector<Vec3> quad = {o, o + a, o + a + b, o + b};
  cell_geometry(CellType::quad4, quad, V, centre);
  EXPECT_NEAR(V / norm(cross(a, b)), 1.0, 1e-13);
}

std::string tension_deck(const std::string& body, const std::string& left, const std::string& right) {
  return "dimension: 3\nspacing: 1.0e-3\nhorizon: 3.0e-3\n"
         "materials:\n  steel: {model: pmb, density: 8000, youngs_modulus: 200.0e9}\n"
         "bodies:\n  - {name: bar, material: steel, shape: " + body + "}\n"
         "regions:\n  left: " + left + "\n  right: " + right + "\n"
         "loads:\n  - {region: left, displacement: [0, 0, 0]}\n"
         "  - {region: right, displacement: [1.0e-6, 0, 0]}\n"
         "solver: {type: static, method: newton, linear_solver: cholesky, tolerance: 1.0e-12}\n";
}

struct TensionRun {
  std::size_t particles = 0;
  double volume = 0;
  double force = 0;  // the right end's reaction along x [N]
  std::vector<Vec3> X, u;
};

TensionRun run_tension(const std::string& deck_text, const std::string& deck_path) {
  test::SingleThread one;
  Config config = parse_deck(deck_text, deck_path);
  System system = build_system(config);
  Loads loads(config, system);
  StaticSolver solver(system, loads, config.solver);
  loads.apply_initial_conditions(config, system);
  solver.initialize();
  while (!solver.done()) EXPECT_TRUE(solver.advance()) << solver.failure();
  TensionRun r;
  r.particles = system.particles.size();
  for (double v : system.particles.volume) r.volume += v;
  for (const auto& L : loads.loads())
    if (L.name == "right:displacement") r.force = L.reaction.x;
  r.X = system.particles.X;
  r.u = system.particles.u;
  return r;
}

// The same bar from the lattice and from meshes. Hexahedra of the lattice spacing put the
// particles where the lattice does (to round-off in the centres) with the same volumes:
// the end force agrees to 1e-9. Jittered tetrahedra (six per cube, interior nodes moved
// by up to 0.3 spacings) are a different discretisation of the same body; their end
// force is compared with a stated tolerance.
TEST(MeshInput, StaticTensionMatchesLattice) {
  const auto dir = output_dir("mesh_tension");
  const std::string deck = (dir / "deck.yaml").string();
  const TensionRun lattice =
      run_tension(tension_deck("{box: {min: [0, 0, 0], max: [0.012, 0.004, 0.004]}}",
                               "{box: {min: [0, 0, 0], max: [0.001, 0.004, 0.004]}}",
                               "{box: {min: [0.011, 0, 0], max: [0.012, 0.004, 0.004]}}"),
                  deck);
  test::write_msh(test::box_mesh(kLo, kHi, 12, 4, 4, false), (dir / "hex.msh").string(), false);
  ASSERT_TRUE(test::write_exodus(test::box_mesh(kLo, kHi, 12, 4, 4, false), (dir / "hex.exo").string()));
  test::write_msh(test::box_mesh(kLo, kHi, 12, 4, 4, true, 0.3), (dir / "tet.msh").string(), false);
  auto mesh_deck = [&](const std::string& file) {
    return tension_deck("{mesh: {file: " + file + ", block: block}}", "{mesh: {file: " + file + ", set: left}}",
                        "{mesh: {file: " + file + ", set: right}}");
  };
  const TensionRun hex = run_tension(mesh_deck("hex.msh"), deck);
  const TensionRun exo = run_tension(mesh_deck("hex.exo"), deck);
  const TensionRun tet = run_tension(mesh_deck("tet.msh"), deck);

  ASSERT_EQ(hex.particles, lattice.particles);
  ASSERT_EQ(exo.particles, lattice.particles);
  double dx = 0, du = 0, umax = 0;
  for (std::size_t i = 0; i < lattice.particles; ++i) {
    dx = std::max({dx, norm(hex.X[i] - lattice.X[i]), norm(exo.X[i] - lattice.X[i])});
    du = std::max({du, norm(hex.u[i] - lattice.u[i]), norm(exo.u[i] - lattice.u[i])});
    umax = std::max(umax, norm(lattice.u[i]));
  }
  EXPECT_LT(dx, 1e-12 * h);
  EXPECT_NEAR(hex.volume / kBoxVolume, 1.0, 1e-12);
  EXPECT_NEAR(tet.volume / kBoxVolume, 1.0, 1e-12);
  const double hex_rel = std::abs(hex.force / lattice.force - 1);
  const double exo_rel = std::abs(exo.force / lattice.force - 1);
  const double tet_rel = tet.force / lattice.force - 1;
  report("mesh_tension_hex", hex_rel,
         fmt::format("PMB bar 12 x 4 x 4 mm, end displacement 1 um: lattice end force {:.2f} N; Gmsh hexahedra "
                     "{:.1e} relative, Exodus hexahedra {:.1e}, max |u_mesh - u_lattice| / max |u| = {:.1e}",
                     lattice.force, hex_rel, exo_rel, du / umax));
  report("mesh_tension_tet", tet_rel,
         fmt::format("the same bar from {} jittered tetrahedra: end force {:.2f} N, {:+.1f} % against the lattice",
                     tet.particles, tet.force, 100 * tet_rel));
  EXPECT_LT(hex_rel, 1e-9);
  EXPECT_LT(exo_rel, 1e-9);
  EXPECT_LT(du / umax, 1e-9);
  EXPECT_LT(std::abs(tet_rel), 0.08);
}

// A 2-D deck reads triangles and quadrangles in the xy-plane: a 6 x 4 mm rectangle as
// squares of the spacing gives the lattice's particles with area x thickness; split into
// triangles, the same total; a curve group selects the elements along an edge.
TEST(MeshInput, PlaneMeshesOfTrianglesAndQuadrangles) {
  const auto dir = output_dir("mesh_2d");
  for (bool triangles : {false, true}) {
    const std::string path = (dir / (triangles ? "tri.msh" : "quad.msh")).string();
    {
      std::ofstream out(path);
      out.precision(17);
      out << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
      out << "$PhysicalNames\n2\n2 1 \"plate\"\n1 2 \"left\"\n$EndPhysicalNames\n";
      out << "$Entities\n0 1 1 0\n1 0 0 0 0 0 0 1 2 0\n1 0 0 0 0 0 0 1 1 0\n$EndEntities\n";
      const int nx = 6, ny = 4;
      const int nodes = (nx + 1) * (ny + 1);
      out << "$Nodes\n1 " << nodes << " 1 " << nodes << "\n2 1 0 " << nodes << "\n";
      for (int i = 1; i <= nodes; ++i) out << i << "\n";
      for (int j = 0; j <= ny; ++j)
        for (int i = 0; i <= nx; ++i) out << i * 1e-3 << " " << j * 1e-3 << " 0\n";
      auto tag = [&](int i, int j) { return 1 + i + (nx + 1) * j; };
      const int cells = triangles ? 2 * nx * ny : nx * ny;
      out << "$EndNodes\n$Elements\n2 " << cells + ny << " 1 " << cells + ny << "\n";
      out << "2 1 " << (triangles ? 2 : 3) << " " << cells << "\n";
      int t = 1;
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
          if (triangles) {
            out << t++ << " " << tag(i, j) << " " << tag(i + 1, j) << " " << tag(i + 1, j + 1) << "\n";
            out << t++ << " " << tag(i, j) << " " << tag(i + 1, j + 1) << " " << tag(i, j + 1) << "\n";
          } else {
            out << t++ << " " << tag(i, j) << " " << tag(i + 1, j) << " " << tag(i + 1, j + 1) << " " << tag(i, j + 1) << "\n";
          }
        }
      out << "1 1 1 " << ny << "\n";
      for (int j = 0; j < ny; ++j) out << t++ << " " << tag(0, j) << " " << tag(0, j + 1) << "\n";
      out << "$EndElements\n";
    }
    const std::string deck = "dimension: 2\nplane: stress\nthickness: 2.0e-3\nspacing: 1.0e-3\nhorizon: 3.0e-3\n"
                             "materials:\n  steel: {model: pmb, density: 8000, youngs_modulus: 200.0e9}\n"
                             "bodies:\n  - {name: plate, material: steel, shape: {mesh: {file: " + path + ", block: plate}}}\n"
                             "regions:\n  left: {mesh: {file: " + path + ", set: left}}\n"
                             "solver: {end_time: 1.0e-6}\n";
    Config config = parse_deck(deck, (dir / "deck.yaml").string());
    const System s = build_system(config);
    double volume = 0;
    for (double v : s.particles.volume) volume += v;
    EXPECT_EQ(s.particles.size(), triangles ? 48u : 24u);
    EXPECT_NEAR(volume / (6e-3 * 4e-3 * 2e-3), 1.0, 1e-12) << path;
    for (const auto& x : s.particles.X) EXPECT_EQ(x.z, 0.0);
    std::size_t left = 0;
    for (const auto& x : s.particles.X) left += config.regions.at("left").contains(x) ? 1 : 0;
    EXPECT_EQ(left, triangles ? 8u : 4u) << path;  // the column of elements along x = 0
    if (!triangles) {
      for (const auto& x : s.particles.X) {
        const double fx = x.x / 1e-3 - 0.5, fy = x.y / 1e-3 - 0.5;
        EXPECT_NEAR(fx, std::round(fx), 1e-9);  // at the lattice's cell centres
        EXPECT_NEAR(fy, std::round(fy), 1e-9);
      }
    }
  }
}

// Every .msh version and encoding Gmsh 4.8 writes (4.1, 2.2 and 3 ASCII and binary, 4.0
// and 1 ASCII only), of one box meshed by the Gmsh library in
// the test (tetrahedra; physical groups: the volume "block", the faces "left" x = 0 and
// "right" x = 2), reads to the same nodes, cells, blocks and sets as the 4.1 binary file
// (MSH 1 keeps no group names: its groups are named by their numbers);
// the mesh made second-order (10-node tetrahedra) reads to the same cells, by their
// corner nodes.
TEST(MeshInput, EveryGmshVersionReadsTheSame) {
  const auto dir = output_dir("mesh_gmsh_versions");
  struct Written {
    std::string name;
    double version;
    bool binary;
  };
  const std::vector<Written> files = {{"v41_bin.msh", 4.1, true}, {"v41.msh", 4.1, false}, {"v22.msh", 2.2, false},
                                      {"v22_bin.msh", 2.2, true}, {"v40.msh", 4.0, false},
                                      {"v3.msh", 3.0, false},     {"v3_bin.msh", 3.0, true},  {"v1.msh", 1.0, false}};
  {
    gmsh_library::Session session;
    GMSH(gmshModelAdd, "box");
    GMSH(gmshModelOccAddBox, 0, 0, 0, 2e-3, 1e-3, 1e-3, 1);
    GMSH(gmshModelOccSynchronize);
    // OpenCASCADE numbers a box's faces x = 0, x = dx, y = 0, ... (checked below).
    const struct {
      int dim, entity, tag;
      const char* name;
    } groups[3] = {{3, 1, 5, "block"}, {2, 1, 6, "left"}, {2, 2, 7, "right"}};
    for (const auto& g : groups) {
      int entity = g.entity;
      GMSH(gmshModelAddPhysicalGroup, g.dim, &entity, 1, g.tag);
      GMSH(gmshModelSetPhysicalName, g.dim, g.tag, g.name);
    }
    GMSH(gmshOptionSetNumber, "Mesh.MeshSizeMax", 0.4e-3);
    GMSH(gmshModelMeshGenerate, 3);
    for (const auto& f : files) {
      GMSH(gmshOptionSetNumber, "Mesh.MshFileVersion", f.version);
      GMSH(gmshOptionSetNumber, "Mesh.Binary", f.binary ? 1.0 : 0.0);
      GMSH(gmshWrite, (dir / f.name).string().c_str());
    }
    GMSH(gmshModelMeshSetOrder, 2);
    GMSH(gmshOptionSetNumber, "Mesh.MshFileVersion", 4.1);
    GMSH(gmshOptionSetNumber, "Mesh.Binary", 1.0);
    GMSH(gmshWrite, (dir / "order2.msh").string().c_str());
  }
  // Gmsh sets OpenMP's thread count to 1 when it starts; the Session restores it.
  const int threads = omp_get_max_threads();
  const Mesh ref = read_mesh((dir / files[0].name).string(), 3);
  EXPECT_EQ(omp_get_max_threads(), threads);
  ASSERT_GT(ref.cell_nodes.size(), 20u);
  ASSERT_EQ(ref.blocks.size(), 1u);
  EXPECT_EQ(ref.blocks[0].name, "block");
  EXPECT_EQ(ref.blocks[0].members.size(), ref.cell_nodes.size());
  ASSERT_EQ(ref.sets.size(), 2u);
  EXPECT_EQ(ref.sets[0].name, "left");
  EXPECT_EQ(ref.sets[1].name, "right");
  for (const auto& set : ref.sets) {
    const double x = set.name == "left" ? 0 : 2e-3;
    EXPECT_GE(set.members.size(), 4u);
    for (uint32_t n : set.members) EXPECT_EQ(ref.nodes[n].x, x) << set.name;
  }
  EXPECT_NEAR(total_volume(ref) / 2e-9, 1.0, 1e-12);
  // Gmsh writes ASCII coordinates with 16 significant digits: they come back to the last
  // bit or two of the binary files' (the reference is binary 4.1).
  const double digits = 1e-15 * 2e-3;
  auto same = [&](const Mesh& m, const std::string& name, bool by_corners) {
    if (!by_corners) {
      ASSERT_EQ(m.nodes.size(), ref.nodes.size()) << name;
      for (std::size_t i = 0; i < ref.nodes.size(); ++i) EXPECT_LE(norm(m.nodes[i] - ref.nodes[i]), digits) << name;
    }
    ASSERT_EQ(m.cell_nodes.size(), ref.cell_nodes.size()) << name;
    for (std::size_t e = 0; e < ref.cell_nodes.size(); ++e) {
      ASSERT_EQ(m.cell_type[e], ref.cell_type[e]) << name;
      ASSERT_EQ(m.cell_nodes[e].size(), ref.cell_nodes[e].size()) << name;
      for (std::size_t k = 0; k < ref.cell_nodes[e].size(); ++k)
        ASSERT_LE(norm(m.nodes[m.cell_nodes[e][k]] - ref.nodes[ref.cell_nodes[e][k]]), digits) << name << " cell " << e;
    }
    auto groups = [&](const std::vector<MeshGroup>& a, const std::vector<MeshGroup>& b, bool nodes) {
      ASSERT_EQ(a.size(), b.size()) << name;
      for (std::size_t g = 0; g < a.size(); ++g) {
        // MSH 1 has no physical names: its groups go by their numbers.
        EXPECT_EQ(a[g].name, name == "v1.msh" ? std::to_string(b[g].id) : b[g].name) << name;
        EXPECT_EQ(a[g].id, b[g].id) << name;
        ASSERT_EQ(a[g].members.size(), b[g].members.size()) << name << " " << a[g].name;
        for (std::size_t k = 0; k < a[g].members.size(); ++k) {
          if (nodes) EXPECT_LE(norm(m.nodes[a[g].members[k]] - ref.nodes[b[g].members[k]]), digits) << name;
          else EXPECT_EQ(a[g].members[k], b[g].members[k]) << name;
        }
      }
    };
    groups(m.blocks, ref.blocks, false);
    groups(m.sets, ref.sets, true);
  };
  for (std::size_t i = 1; i < files.size(); ++i) {
    const Mesh m = read_mesh((dir / files[i].name).string(), 3);
    same(m, files[i].name, false);
  }
  const Mesh quadratic = read_mesh((dir / "order2.msh").string(), 3);
  EXPECT_GT(quadratic.nodes.size(), ref.nodes.size());  // the mid-edge nodes, read and unused
  same(quadratic, "order2.msh", true);
}

// Errors name the deck's line and column, the mesh file and, where it applies, the
// element or the Gmsh entity; Gmsh's own message when it cannot read the file.
TEST(MeshInput, ErrorsNameDeckAndMeshFile) {
  const auto dir = output_dir("mesh_errors");
  const std::string deck = (dir / "deck.yaml").string();
  auto error_of = [&](const std::string& text) -> std::string {
    try {
      parse_deck(text, deck);
    } catch (const Error& e) {
      return e.what();
    }
    return "no error";
  };
  const std::string box = "{box: {min: [0, 0, 0], max: [0.001, 0.004, 0.004]}}";
  // Missing file: the deck's line 7 (the body), column of the file name.
  std::string msg = error_of(tension_deck("{mesh: {file: nowhere.msh}}", box, box));
  EXPECT_NE(msg.find("deck.yaml:7:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("nowhere.msh"), std::string::npos) << msg;
  EXPECT_NE(msg.find("No such file"), std::string::npos) << msg;

  // A second-order tetrahedron (type 11) reads as its corners; in a 2-D deck it is a
  // volume element where areas are expected: the message names the Gmsh volume.
  {
    std::ofstream out(dir / "tet10.msh");
    out << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 10 1 10\n3 1 0 10\n";
    for (int i = 1; i <= 10; ++i) out << i << "\n";
    for (int i = 0; i < 10; ++i) out << (i % 2) << " " << (i % 3) << " " << (i % 5) << "\n";
    out << "$EndNodes\n$Elements\n1 1 1 1\n3 1 11 1\n1 1 2 3 4 5 6 7 8 9 10\n$EndElements\n";
  }
  const Mesh tet10 = read_mesh((dir / "tet10.msh").string(), 3);
  ASSERT_EQ(tet10.cell_nodes.size(), 1u);
  EXPECT_EQ(tet10.cell_nodes[0], (std::vector<uint32_t>{0, 1, 2, 3}));
  EXPECT_NEAR(tet10.measure[0], 1.0, 1e-15);  // corners (0,0,0) (1,1,1) (0,2,2) (1,0,3)
  try {
    read_mesh((dir / "tet10.msh").string(), 2);
    ADD_FAILURE() << "a tetrahedron read in 2-D";
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find("tet10.msh: Tetrahedron 10 elements (volume 1) in a 2-D deck"), std::string::npos)
        << e.what();
  }

  // A malformed number: Gmsh's message, after the file's name.
  {
    std::ofstream out(dir / "bad.msh");
    out << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 1 1 1\n3 1 0 1\n1\n0 zero 0\n$EndNodes\n";
  }
  msg = error_of(tension_deck("{mesh: {file: bad.msh}}", box, box));
  EXPECT_NE(msg.find("deck.yaml:7:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("bad.msh: Gmsh cannot read it: Could not read nodes"), std::string::npos) << msg;

  // A mesh of no volume elements.
  {
    std::ofstream out(dir / "v2.msh");
    out << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n";
  }
  msg = error_of(tension_deck("{mesh: {file: v2.msh}}", box, box));
  EXPECT_NE(msg.find("v2.msh: no 3-D elements"), std::string::npos) << msg;

  // A Gmsh script named .msh is not given to Gmsh (it would run its commands).
  {
    std::ofstream out(dir / "script.msh");
    out << "System \"touch " << (dir / "ran").string() << "\";\n";
  }
  msg = error_of(tension_deck("{mesh: {file: script.msh}}", box, box));
  EXPECT_NE(msg.find("script.msh: not a Gmsh mesh: the file must start with $MeshFormat"), std::string::npos) << msg;
  EXPECT_FALSE(std::filesystem::exists(dir / "ran"));

  // Unknown block and set names list the ones the mesh has; a set cannot be a body.
  test::write_msh(test::box_mesh(kLo, kHi, 12, 4, 4, false), (dir / "hex.msh").string(), false);
  msg = error_of(tension_deck("{mesh: {file: hex.msh, block: steel}}", box, box));
  EXPECT_NE(msg.find("deck.yaml:7:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("no block 'steel'; its blocks: block"), std::string::npos) << msg;
  msg = error_of(tension_deck("{box: {min: [0, 0, 0], max: [0.012, 0.004, 0.004]}}",
                              "{mesh: {file: hex.msh, set: top}}", box));
  EXPECT_NE(msg.find("deck.yaml:9:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("its sets: left, right"), std::string::npos) << msg;
  msg = error_of(tension_deck("{mesh: {file: hex.msh, set: left}}", box, box));
  EXPECT_NE(msg.find("belongs under regions"), std::string::npos) << msg;
  msg = error_of(tension_deck("{mesh: {file: hex.msh, colour: red}}", box, box));
  EXPECT_NE(msg.find("colour"), std::string::npos) << msg;
  // Not an Exodus file.
  {
    std::ofstream out(dir / "junk.exo");
    out << "junk\n";
  }
  msg = error_of(tension_deck("{mesh: {file: junk.exo}}", box, box));
  EXPECT_NE(msg.find("not an Exodus II file"), std::string::npos) << msg;
}

}  // namespace
}  // namespace horizon::verification
