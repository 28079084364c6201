// Peridigm's `Discretization: Type: Exodus` (deck/peridigm/exodus_discretization.hpp) on
// small meshes the test writes through the Exodus library: one particle per element at
// its centre of volume with its volume (a sheared hexahedron and a tetrahedron: exact
// closed forms), SPHERE elements with their volume attribute, element blocks as block_<id>,
// and node sets as the particles whose element holds any node of the set (2 x 2 x 2 mesh),
// named nodelist_<id> when the mesh gives no name.
#include <exodusII.h>
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include "horizon/core/error.hpp"
#include "horizon/core/vec3.hpp"
#include "horizon/deck/peridigm/peridigm.hpp"

namespace horizon {
namespace {

namespace fs = std::filesystem;

struct Block {
  int id;
  const char* type;  // HEX8, TETRA, SPHERE
  int nodes_per;
  std::vector<int> conn;        // 1-based
  std::vector<double> attr;     // SPHERE: radius, volume per element
  std::string name;             // empty: none written
};
struct NodeSet {
  int id;
  std::vector<int> nodes;
  std::string name;
};

void write_mesh(const std::string& path, const std::vector<Vec3>& x, const std::vector<Block>& blocks,
                const std::vector<NodeSet>& sets) {
  int cpu_ws = sizeof(double), io_ws = sizeof(double);
  const int id = ex_create(path.c_str(), EX_CLOBBER, &cpu_ws, &io_ws);
  ASSERT_GE(id, 0);
  int64_t elems = 0;
  for (const auto& b : blocks) elems += b.nodes_per ? static_cast<int64_t>(b.conn.size() / static_cast<std::size_t>(b.nodes_per)) : 0;
  ASSERT_GE(ex_put_init(id, "test", 3, static_cast<int64_t>(x.size()), elems, static_cast<int64_t>(blocks.size()),
                        static_cast<int64_t>(sets.size()), 0),
            0);
  std::vector<double> cx, cy, cz;
  for (const auto& p : x) cx.push_back(p.x), cy.push_back(p.y), cz.push_back(p.z);
  ex_put_coord(id, cx.data(), cy.data(), cz.data());
  for (const auto& b : blocks) {
    const auto n = b.nodes_per ? static_cast<int64_t>(b.conn.size() / static_cast<std::size_t>(b.nodes_per)) : 0;
    const int nattr = b.attr.empty() ? 0 : static_cast<int>(b.attr.size() / static_cast<std::size_t>(n));
    ex_put_block(id, EX_ELEM_BLOCK, b.id, b.type, n, b.nodes_per, 0, 0, nattr);
    if (n > 0) ex_put_conn(id, EX_ELEM_BLOCK, b.id, b.conn.data(), nullptr, nullptr);
    if (nattr) ex_put_attr(id, EX_ELEM_BLOCK, b.id, b.attr.data());
    if (!b.name.empty()) ex_put_name(id, EX_ELEM_BLOCK, b.id, b.name.c_str());
  }
  for (const auto& s : sets) {
    ex_put_set_param(id, EX_NODE_SET, s.id, static_cast<int64_t>(s.nodes.size()), 0);
    ex_put_set(id, EX_NODE_SET, s.id, s.nodes.data(), nullptr);
    if (!s.name.empty()) ex_put_name(id, EX_NODE_SET, s.id, s.name.c_str());
  }
  ASSERT_GE(ex_close(id), 0);
}

// A Peridigm deck over `mesh` with one block group of `block_names`, fixing `sets` in x.
std::string deck(const std::string& block_names, const std::vector<std::string>& sets) {
  std::string d = R"(Peridigm:
  Discretization:
    Type: "Exodus"
    Input Mesh File: "mesh.g"
  Materials:
    Steel: {Material Model: "Elastic", Density: 7800.0, Bulk Modulus: 130.0e9, Shear Modulus: 78.0e9}
  Blocks:
    All:
      Block Names: ")" + block_names + R"("
      Material: "Steel"
      Horizon: 2.5
  Boundary Conditions:
)";
  int k = 0;
  for (const auto& s : sets)
    d += "    Fix" + std::to_string(k++) + ": {Type: \"Prescribed Displacement\", Node Set: \"" + s +
         "\", Coordinate: \"x\", Value: \"0.0\"}\n";
  d += R"(  Solver:
    Final Time: 1.0e-6
    Verlet: {Fixed dt: 1.0e-7}
)";
  return d;
}

struct Converted {
  std::vector<std::string> body_names;
  std::vector<std::vector<double>> rows;  // x y z volume, bodies in order
  YAML::Node regions;
};

Converted convert(const fs::path& dir, const std::string& text) {
  const fs::path file = dir / "deck.yaml";
  std::ofstream(file) << text;
  const YAML::Node native = peridigm::to_native(YAML::LoadFile(file.string()), file.string());
  Converted c;
  for (const auto& b : native["bodies"]) {
    c.body_names.push_back(b["name"].as<std::string>());
    for (const auto& r : b["shape"]["points"])
      c.rows.push_back({r[0].as<double>(), r[1].as<double>(), r[2].as<double>(), r[3].as<double>()});
  }
  c.regions = native["regions"];
  return c;
}

// A region's points, rounded to 1e-12 (the hexahedron's centre comes from Gauss
// quadrature: exact to rounding).
std::set<std::vector<double>> region_points(const YAML::Node& region) {
  std::set<std::vector<double>> out;
  auto r12 = [](const YAML::Node& v) { return std::round(v.as<double>() * 1e12) / 1e12; };
  for (const auto& r : region["points"]) out.insert({r12(r[0]), r12(r[1]), r12(r[2])});
  return out;
}

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

TEST(ExodusDiscretization, HexAndTetCentroidsAndVolumesExact) {
  const fs::path dir = fresh_dir("horizon_exodus_disc_cells");
  // A sheared hexahedron (a parallelepiped: edges a, b, c from the origin o): volume
  // |a . (b x c)|, centre o + (a + b + c)/2. Beside it a tetrahedron: volume
  // |det|/6, centre the mean of its nodes.
  const Vec3 o{1, 2, 3}, a{2, 0, 0}, b{0.5, 3, 0}, c{0.25, 0.5, 4};
  const Vec3 t0{10, 0, 0}, t1{13, 0, 0}, t2{10, 2, 0}, t3{10.5, 0.5, 5};
  std::vector<Vec3> x = {o, o + a, o + a + b, o + b, o + c, o + a + c, o + a + b + c, o + b + c, t0, t1, t2, t3};
  write_mesh((dir / "mesh.g").string(), x,
             {{1, "HEX8", 8, {1, 2, 3, 4, 5, 6, 7, 8}, {}, ""}, {3, "TETRA", 4, {9, 10, 11, 12}, {}, "tets"}},
             {{1, {1}, ""}});
  const Converted cv = convert(dir, deck("block_1 tets", {"nodelist_1"}));
  ASSERT_EQ(cv.body_names, (std::vector<std::string>{"block_1", "block_3"}));
  ASSERT_EQ(cv.rows.size(), 2u);
  const Vec3 hc = o + (a + b + c) / 2.0;
  const double hv = std::abs(dot(a, cross(b, c)));
  EXPECT_NEAR(cv.rows[0][0], hc.x, 1e-14 * 10);
  EXPECT_NEAR(cv.rows[0][1], hc.y, 1e-14 * 10);
  EXPECT_NEAR(cv.rows[0][2], hc.z, 1e-14 * 10);
  EXPECT_NEAR(cv.rows[0][3], hv, 1e-13 * hv);
  const Vec3 tc = (t0 + t1 + t2 + t3) / 4.0;
  const double tv = std::abs(dot(t1 - t0, cross(t2 - t0, t3 - t0))) / 6.0;  // = 3*2*5/6 = 5
  EXPECT_DOUBLE_EQ(tv, 5.0);
  EXPECT_NEAR(cv.rows[1][0], tc.x, 1e-14 * 10);
  EXPECT_NEAR(cv.rows[1][1], tc.y, 1e-14);
  EXPECT_NEAR(cv.rows[1][2], tc.z, 1e-14);
  EXPECT_NEAR(cv.rows[1][3], tv, 1e-13 * tv);
  // nodelist_1 = node 1: only the hexahedron holds it.
  EXPECT_EQ(region_points(cv.regions["nodelist_1"]).size(), 1u);
}

TEST(ExodusDiscretization, NodeSetIsTheElementsHoldingItsNodes) {
  const fs::path dir = fresh_dir("horizon_exodus_disc_sets");
  // 2 x 2 x 2 unit hexahedra; nodes numbered x fastest (3 x 3 x 3).
  std::vector<Vec3> x;
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) x.push_back({double(i), double(j), double(k)});
  auto node = [](int i, int j, int k) { return 1 + i + 3 * (j + 3 * k); };
  std::vector<int> conn;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i)
        for (int v : {node(i, j, k), node(i + 1, j, k), node(i + 1, j + 1, k), node(i, j + 1, k),
                      node(i, j, k + 1), node(i + 1, j, k + 1), node(i + 1, j + 1, k + 1), node(i, j + 1, k + 1)})
          conn.push_back(v);
  std::vector<int> face;  // the x = 0 face: 9 nodes
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j) face.push_back(node(0, j, k));
  write_mesh((dir / "mesh.g").string(), x, {{1, "HEX8", 8, conn, {}, ""}},
             {{1, {node(0, 0, 0)}, ""},            // a corner: one element
              {2, {node(1, 1, 1)}, ""},            // the centre: all eight
              {3, face, "Min X"},                  // a face: the four elements at x < 1
              {7, {node(2, 1, 0), node(2, 2, 0)}, ""}});  // an edge of the x = 2, z = 0 corner: two
  const Converted cv = convert(dir, deck("block_1", {"nodelist_1", "nodelist_2", "Min X", "nodelist_3", "nodelist_7"}));
  ASSERT_EQ(cv.rows.size(), 8u);
  for (const auto& r : cv.rows) EXPECT_NEAR(r[3], 1.0, 1e-14);
  // Element e's centre: (i + 0.5, j + 0.5, k + 0.5), the first at (0.5, 0.5, 0.5).
  EXPECT_EQ(region_points(cv.regions["nodelist_1"]), (std::set<std::vector<double>>{{0.5, 0.5, 0.5}}));
  EXPECT_EQ(region_points(cv.regions["nodelist_2"]).size(), 8u);
  const auto min_x = region_points(cv.regions["Min X"]);
  EXPECT_EQ(min_x.size(), 4u);
  for (const auto& p : min_x) EXPECT_EQ(p[0], 0.5);
  EXPECT_EQ(region_points(cv.regions["nodelist_3"]), min_x);  // the name and nodelist_<id> alike
  EXPECT_EQ(region_points(cv.regions["nodelist_7"]),
            (std::set<std::vector<double>>{{1.5, 0.5, 0.5}, {1.5, 1.5, 0.5}}));
}

TEST(ExodusDiscretization, SphereElementsCarryTheirVolumeAttribute) {
  const fs::path dir = fresh_dir("horizon_exodus_disc_spheres");
  const std::vector<Vec3> x = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  // Cubit's sphere meshes: attributes radius, volume (no names).
  write_mesh((dir / "mesh.g").string(), x,
             {{1, "SPHERE", 1, {1, 2}, {0.5, 0.125, 0.6, 0.216}, ""}, {2, "SPHERE", 1, {3}, {0.7, 0.343}, ""}},
             {{4, {3}, ""}});
  const Converted cv = convert(dir, deck("block_1 block_2", {"nodelist_4"}));
  ASSERT_EQ(cv.rows.size(), 3u);
  EXPECT_EQ(cv.body_names, (std::vector<std::string>{"block_1", "block_2"}));
  EXPECT_EQ(cv.rows[0], (std::vector<double>{0, 0, 0, 0.125}));
  EXPECT_EQ(cv.rows[1], (std::vector<double>{1, 0, 0, 0.216}));
  EXPECT_EQ(cv.rows[2], (std::vector<double>{2, 0, 0, 0.343}));
  EXPECT_EQ(region_points(cv.regions["nodelist_4"]), (std::set<std::vector<double>>{{2, 0, 0}}));
}

// A piece of a partitioned mesh writes a block it holds no element of as a 0-node NULL
// block (Peridigm's ElasticBondAssociatedCorrespondenceFullyPrescribedTension.g.4.0): an
// empty block adds nothing, whatever its type; a NULL block with elements stays an error.
TEST(ExodusDiscretization, EmptyNullBlockOfAPieceAddsNothing) {
  const fs::path dir = fresh_dir("horizon_exodus_disc_null");
  const std::vector<Vec3> x = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  write_mesh((dir / "mesh.g").string(), x,
             {{1, "HEX8", 8, {1, 2, 3, 4, 5, 6, 7, 8}, {}, ""}, {2, "NULL", 0, {}, {}, ""}}, {{1, {1}, ""}});
  const Converted cv = convert(dir, deck("block_1", {"nodelist_1"}));
  ASSERT_EQ(cv.rows.size(), 1u);
  EXPECT_NEAR(cv.rows[0][0], 0.5, 1e-15);
  EXPECT_NEAR(cv.rows[0][3], 1.0, 1e-15);
  EXPECT_EQ(cv.body_names, (std::vector<std::string>{"block_1"}));
}

TEST(ExodusDiscretization, ErrorsNameTheDeckLine) {
  const fs::path dir = fresh_dir("horizon_exodus_disc_errors");
  // No mesh file: the deck's line of Input Mesh File.
  try {
    convert(dir, deck("block_1", {}));
    FAIL() << "expected an error";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("deck.yaml:4:"), std::string::npos) << m;
    EXPECT_NE(m.find("mesh.g"), std::string::npos) << m;
  }
  // A node set the mesh does not have.
  write_mesh((dir / "mesh.g").string(), {{0, 0, 0}}, {{1, "SPHERE", 1, {1}, {0.5, 0.125}, ""}}, {{1, {1}, ""}});
  try {
    convert(dir, deck("block_1", {"nodelist_2"}));
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("nodelist_1"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace horizon
