// What lets more of Peridigm's own suite decks run unchanged (docs/peridigm.md):
// - a mesh found where Peridigm finds it, the working directory (its test scripts run
//   `cd np4; Peridigm ../deck.xml`), when the deck's folder does not hold it;
// - Peridigm's partitioned Exodus meshes (mesh.g.N.i, each piece with its node and element
//   number maps) merged by global id into the serial mesh's particles, in its order;
// - particles without neighbours (LPS: dilatation 0, no bond force; contact moves them);
// - a friction coefficient that is a function string of t (Time Dependent Short Range Force);
// - QuasiStatic's Adaptive Load-Stepping read (its Switch to Verlet: a staged run);
// - the CG path's dense solve of a small tangent CG cannot finish (singular, not symmetric:
//   PredictorFromPreviousSolver's finite-difference correspondence tangent of a body held
//   in y alone);
// - Apply Shear Correction Factor: the factor of each particle of a lattice cube
//   (material/shear_correction.hpp) as its closed forms give it.
#include <exodusII.h>
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "horizon/core/error.hpp"
#include "horizon/core/vec3.hpp"
#include "horizon/deck/deck.hpp"
#include "horizon/deck/peridigm/peridigm.hpp"
#include "horizon/driver/run.hpp"
#include "horizon/solver/forces.hpp"
#include "horizon/solver/linear.hpp"
#include "test_helpers.hpp"

namespace horizon {
namespace {

namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// The working directory for one scope.
struct InDirectory {
  explicit InDirectory(const fs::path& d) : old(fs::current_path()) { fs::current_path(d); }
  ~InDirectory() { fs::current_path(old); }
  fs::path old;
};

// One Exodus file: nodes `x` (with their global ids), hexahedra in blocks (1-based
// local connectivity, with their global ids), node sets of local node numbers.
struct Piece {
  std::vector<Vec3> x;
  std::vector<int> node_ids;
  std::map<int, std::vector<std::vector<int>>> blocks;  // block id -> hexahedra
  std::vector<int> elem_ids;                             // in block order
  std::map<int, std::vector<int>> sets;                  // set id -> local nodes
};

void write_piece(const std::string& path, const Piece& p) {
  int cpu_ws = sizeof(double), io_ws = sizeof(double);
  const int id = ex_create(path.c_str(), EX_CLOBBER, &cpu_ws, &io_ws);
  ASSERT_GE(id, 0);
  int64_t elems = 0;
  for (const auto& [b, hexes] : p.blocks) elems += static_cast<int64_t>(hexes.size());
  ASSERT_GE(ex_put_init(id, "piece", 3, static_cast<int64_t>(p.x.size()), elems, static_cast<int64_t>(p.blocks.size()),
                        static_cast<int64_t>(p.sets.size()), 0),
            0);
  std::vector<double> cx, cy, cz;
  for (const auto& v : p.x) cx.push_back(v.x), cy.push_back(v.y), cz.push_back(v.z);
  ASSERT_GE(ex_put_coord(id, cx.data(), cy.data(), cz.data()), 0);
  for (const auto& [b, hexes] : p.blocks) {
    std::vector<int> conn;
    for (const auto& h : hexes) conn.insert(conn.end(), h.begin(), h.end());
    ASSERT_GE(ex_put_block(id, EX_ELEM_BLOCK, b, "HEX8", static_cast<int64_t>(hexes.size()), 8, 0, 0, 0), 0);
    ASSERT_GE(ex_put_conn(id, EX_ELEM_BLOCK, b, conn.data(), nullptr, nullptr), 0);
  }
  for (const auto& [s, nodes] : p.sets) {
    ASSERT_GE(ex_put_set_param(id, EX_NODE_SET, s, static_cast<int64_t>(nodes.size()), 0), 0);
    ASSERT_GE(ex_put_set(id, EX_NODE_SET, s, nodes.data(), nullptr), 0);
  }
  ASSERT_GE(ex_put_id_map(id, EX_NODE_MAP, p.node_ids.data()), 0);
  ASSERT_GE(ex_put_id_map(id, EX_ELEM_MAP, p.elem_ids.data()), 0);
  ASSERT_GE(ex_close(id), 0);
}

// A 3 x 2 x 1 mesh of unit hexahedra, slightly sheared (so every centre is distinct and
// not a round number), nodes numbered x fastest. Element (i, j) has global id
// 1 + i + 3 j; block 1 holds j = 0, block 2 j = 1. Node set 1: the x = 0 face; set 2: the
// node (1, 1, 1), shared by four elements.
struct Grid {
  static int node(int i, int j, int k) { return 1 + i + 4 * (j + 3 * k); }
  static Vec3 at(int i, int j, int k) { return {i + 0.1 * j + 0.05 * k, j + 0.02 * i, k + 0.03 * i * j}; }
  static std::vector<int> hex(int i, int j) {
    return {node(i, j, 0),     node(i + 1, j, 0),     node(i + 1, j + 1, 0), node(i, j + 1, 0),
            node(i, j, 1),     node(i + 1, j, 1),     node(i + 1, j + 1, 1), node(i, j + 1, 1)};
  }
  static std::vector<int> face_x0() {
    std::vector<int> f;
    for (int k = 0; k < 2; ++k)
      for (int j = 0; j < 3; ++j) f.push_back(node(0, j, k));
    return f;
  }
};

// The serial mesh, or (pieces > 1) its split by the elements' i: piece 0 holds i = 0 and
// the elements (1, 1), piece 1 the others, each with only the nodes its elements use,
// numbered locally in a scrambled order.
std::vector<Piece> grid_pieces(int pieces) {
  std::vector<std::vector<std::pair<int, int>>> owned(static_cast<std::size_t>(pieces));
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 3; ++i) {
      const int p = pieces == 1 ? 0 : ((i == 0 || (i == 1 && j == 1)) ? 0 : 1);
      owned[static_cast<std::size_t>(p)].push_back({i, j});
    }
  std::vector<Piece> out;
  for (const auto& elems : owned) {
    Piece p;
    std::set<int> used;
    for (auto [i, j] : elems)
      for (int n : Grid::hex(i, j)) used.insert(n);
    // Local numbering: the used global nodes in descending order (scrambled against ids).
    std::map<int, int> local;
    for (auto it = used.rbegin(); it != used.rend(); ++it) {
      local[*it] = static_cast<int>(p.node_ids.size()) + 1;
      p.node_ids.push_back(*it);
      const int g = *it - 1;
      p.x.push_back(Grid::at(g % 4, (g / 4) % 3, g / 12));
    }
    for (int b = 1; b <= 2; ++b)
      for (auto [i, j] : elems) {
        if (j + 1 != b) continue;
        std::vector<int> h;
        for (int n : Grid::hex(i, j)) h.push_back(local.at(n));
        p.blocks[b].push_back(h);
        p.elem_ids.push_back(1 + i + 3 * j);
      }
    for (int n : Grid::face_x0())
      if (local.count(n)) p.sets[1].push_back(local.at(n));
    if (local.count(Grid::node(1, 1, 1))) p.sets[2].push_back(local.at(Grid::node(1, 1, 1)));
    out.push_back(std::move(p));
  }
  return out;
}

std::string grid_deck(const std::string& mesh) {
  return R"(Peridigm:
  Discretization:
    Type: "Exodus"
    Input Mesh File: ")" + mesh + R"("
  Materials:
    Steel: {Material Model: "Elastic", Density: 7800.0, Bulk Modulus: 130.0e9, Shear Modulus: 78.0e9}
  Blocks:
    All:
      Block Names: "block_1 block_2"
      Material: "Steel"
      Horizon: 1.5
  Boundary Conditions:
    Fix: {Type: "Prescribed Displacement", Node Set: "nodelist_1", Coordinate: "x", Value: "0.0"}
    Pull: {Type: "Prescribed Displacement", Node Set: "nodelist_2", Coordinate: "y", Value: "t"}
  Solver:
    Final Time: 1.0e-6
    Verlet: {Fixed dt: 1.0e-7}
)";
}

YAML::Node convert(const fs::path& deck_dir, const std::string& text) {
  const fs::path file = deck_dir / "deck.yaml";
  std::ofstream(file) << text;
  return peridigm::to_native(YAML::LoadFile(file.string()), file.string());
}

// Bodies (name, rows of x y z volume) and regions as text: what must agree exactly.
std::string particles_of(const YAML::Node& native) {
  YAML::Emitter e;
  e << native["bodies"] << native["regions"];
  return e.c_str();
}

TEST(PeridigmRuns, PartitionedMeshIsTheSerialMesh) {
  const fs::path serial = fresh_dir("horizon_pdruns_serial"), parts = fresh_dir("horizon_pdruns_parts");
  write_piece((serial / "mesh.g").string(), grid_pieces(1)[0]);
  const auto pieces = grid_pieces(2);
  ASSERT_EQ(pieces[0].elem_ids.size(), 3u);  // (0,0) in block 1; (0,1), (1,1) in block 2
  for (std::size_t i = 0; i < pieces.size(); ++i)
    write_piece((parts / ("mesh.g.2." + std::to_string(i))).string(), pieces[i]);
  const YAML::Node a = convert(serial, grid_deck("mesh.g"));
  const YAML::Node b = convert(parts, grid_deck("mesh.g"));
  ASSERT_EQ(a["bodies"].size(), 2u);
  EXPECT_EQ(a["bodies"][0]["shape"]["points"].size(), 3u);
  EXPECT_EQ(a["bodies"][1]["shape"]["points"].size(), 3u);
  // The same particles, volumes, order and node sets, to the last bit.
  EXPECT_EQ(particles_of(a), particles_of(b));
  // nodelist_2 (one node, in both pieces) is the four elements around it.
  EXPECT_EQ(b["regions"]["nodelist_2"]["points"].size(), 4u);
  EXPECT_EQ(b["regions"]["nodelist_1"]["points"].size(), 2u);

  // An incomplete set of pieces is not a mesh: the error names the deck's line.
  fs::remove(parts / "mesh.g.2.1");
  try {
    convert(parts, grid_deck("mesh.g"));
    FAIL() << "expected an error";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("deck.yaml:4:"), std::string::npos) << m;
    EXPECT_NE(m.find("mesh.g.N.i"), std::string::npos) << m;
  }
}

TEST(PeridigmRuns, MeshIsFoundInTheWorkingDirectory) {
  // Peridigm's test scripts: `cd np1; Peridigm ../deck.yaml`, the mesh in np1/.
  const fs::path top = fresh_dir("horizon_pdruns_cwd");
  fs::create_directories(top / "np1");
  write_piece((top / "np1" / "mesh.g").string(), grid_pieces(1)[0]);
  {
    InDirectory in(top / "np1");
    const YAML::Node n = convert(top, grid_deck("mesh.g"));
    EXPECT_EQ(n["bodies"].size(), 2u);
  }
  // From elsewhere the mesh is nowhere: the error names both places looked at.
  {
    InDirectory in(top);
    try {
      convert(top, grid_deck("mesh.g"));
      FAIL() << "expected an error";
    } catch (const Error& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("deck.yaml:4:"), std::string::npos) << m;
      EXPECT_NE(m.find("no such file"), std::string::npos) << m;
    }
  }
  // A mesh beside the deck comes first (the working directory holds another).
  write_piece((top / "mesh.g").string(), grid_pieces(1)[0]);
  {
    InDirectory in(top / "np1");
    fs::remove(top / "np1" / "mesh.g");
    EXPECT_EQ(convert(top, grid_deck("mesh.g"))["bodies"].size(), 2u);
  }
}

constexpr double kH = 1e-3, kDelta = 1.0e-3, kSpring = 1e9, kPi = 3.14159265358979323846;

// Two one-particle LPS bodies 2h apart with a horizon of h: neither has a neighbour
// (Peridigm's Contact_2x1x1), and Peridigm's short-range force between them.
Config isolated_pair(const ShortRangeContactConfig& contact) {
  Config c;
  c.dimension = 3;
  c.spacing = kH;
  c.horizon = kDelta;
  c.lattice_origin = Vec3{};
  c.materials = {test::make_material("lps", 130e9, 0.25)};
  for (int k = 0; k < 2; ++k) {
    const double x = 2 * k * kH;
    c.bodies.push_back(BodyConfig{"b" + std::to_string(k), "solid",
                                  Shape::box({x - 0.5 * kH, -0.5 * kH, -0.5 * kH}, {x + 0.5 * kH, 0.5 * kH, 0.5 * kH})});
  }
  c.contact.short_range = contact;
  c.solver.time_step = 1e-9;
  c.solver.end_time = 1e-8;
  return c;
}

ShortRangeContactConfig peridigm_law(double radius) {
  ShortRangeContactConfig c;
  c.enabled = true;
  c.law = ShortRangeLaw::peridigm;
  c.contact_radius = radius;
  c.spring_constant = kSpring;
  return c;
}

TEST(PeridigmRuns, ParticlesWithoutNeighboursTakeContactAlone) {
  const Config c = isolated_pair(peridigm_law(2.5 * kH));
  PreparedRun run = prepare_run(c);  // refused before: "particle 0 has no neighbours"
  System& s = run.system;
  EXPECT_EQ(s.bonds.size(), 0u);
  EXPECT_EQ(run.check.isolated, 2u);
  EXPECT_NE(format_check(c, run.check).find("2 particle(s) have no neighbours"), std::string::npos);
  compute_forces(s, true);
  // Peridigm's force at r = 2h < R_c, and nothing from a bond; dilatation and weighted
  // volume 0 (Contact_2x1x1's gold), the strain energy finite. Each particle receives
  // Peridigm's c = 9k/(pi delta^4) from both contact lists (docs/peridigm.md "Contact").
  const double f = 2 * 9 * kSpring / (kPi * std::pow(kDelta, 4)) * s.particles.volume[1] * (0.5 * kH) / kDelta;
  EXPECT_NEAR(s.particles.f[0].x, -f, 1e-12 * f);
  EXPECT_NEAR(s.particles.f[1].x, f, 1e-12 * f);
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(s.model.weighted_volume[i], 0.0);
    EXPECT_EQ(s.model.theta[i], 0.0);
  }
  EXPECT_TRUE(std::isfinite(strain_energy(s)));
  // A model whose rows divide by the weighted volume still refuses it.
  Config ep = c;
  ep.materials = {test::make_material("elastic_plastic", 130e9, 0.25)};
  ep.materials[0].parameters["yield_stress"] = 1e8;
  EXPECT_THROW(prepare_run(ep), Error);
}

TEST(PeridigmRuns, FrictionCoefficientInTime) {
  // mu(t) = 1 up to t = 4e-5, then 0: Contact_Friction_Time_Dependent_Coefficient's string.
  ShortRangeContactConfig law = peridigm_law(2.5 * kH);
  Config c = isolated_pair(law);
  System s = build_system(c);
  s.particles.v[1] = {0.0, 3.0, 0.0};  // slides along +y past particle 0
  const YAML::Node native = [] {
    const fs::path dir = fresh_dir("horizon_pdruns_friction");
    const std::string deck = R"(<ParameterList>
  <ParameterList name="Discretization">
    <Parameter name="Type" type="string" value="Text File"/>
    <Parameter name="Input Mesh File" type="string" value="points.txt"/>
  </ParameterList>
  <ParameterList name="Materials">
    <ParameterList name="Steel">
      <Parameter name="Material Model" type="string" value="Elastic"/>
      <Parameter name="Density" type="double" value="7800.0"/>
      <Parameter name="Bulk Modulus" type="double" value="130.0e9"/>
      <Parameter name="Shear Modulus" type="double" value="78.0e9"/>
    </ParameterList>
  </ParameterList>
  <ParameterList name="Blocks">
    <ParameterList name="All">
      <Parameter name="Block Names" type="string" value="block_1 block_2"/>
      <Parameter name="Material" type="string" value="Steel"/>
      <Parameter name="Horizon" type="double" value="0.001"/>
    </ParameterList>
  </ParameterList>
  <ParameterList name="Contact">
    <Parameter name="Search Radius" type="double" value="0.01"/>
    <Parameter name="Search Frequency" type="int" value="100"/>
    <ParameterList name="Models">
      <ParameterList name="My Contact Model">
        <Parameter name="Contact Model" type="string" value="Time Dependent Short Range Force"/>
        <Parameter name="Contact Radius" type="double" value="0.0025"/>
        <Parameter name="Spring Constant" type="double" value="1.0e9"/>
        <Parameter name="Friction Coefficient" type="string" value=" if(t &lt;= 4.00e-5)\{ value = 1.0; \} else\{ value = 0.0; \} "/>
      </ParameterList>
    </ParameterList>
    <ParameterList name="Interactions">
      <ParameterList name="One with two">
        <Parameter name="First Block" type="string" value="block_1"/>
        <Parameter name="Second Block" type="string" value="block_2"/>
        <Parameter name="Contact Model" type="string" value="My Contact Model"/>
      </ParameterList>
    </ParameterList>
  </ParameterList>
  <ParameterList name="Solver">
    <Parameter name="Final Time" type="double" value="1.0e-4"/>
    <ParameterList name="Verlet">
      <Parameter name="Fixed dt" type="double" value="1.0e-5"/>
    </ParameterList>
  </ParameterList>
</ParameterList>
)";
    std::ofstream(dir / "points.txt") << "0 0 0 1 1e-9\n0.002 0 0 2 1e-9\n";
    std::ofstream(dir / "deck.xml") << deck;
    return YAML::Load(convert_peridigm_deck((dir / "deck.xml").string()));
  }();
  const std::string mu = native["contact"]["short_range"]["friction"].as<std::string>();
  law.friction_in_time = Expression(mu);
  law.friction = 1;
  s.contact.setup(law, kH, kDelta);
  const double fn = 2 * 9 * kSpring / (kPi * std::pow(kDelta, 4)) * s.particles.volume[1] * (0.5 * kH) / kDelta;
  s.time = 4e-5;  // mu = 1: particle 1 is held back by mu fn
  compute_forces(s, false);
  EXPECT_NEAR(s.particles.f[1].y, -fn, 1e-12 * fn) << mu;
  s.time = 4.1e-5;  // mu = 0
  compute_forces(s, false);
  EXPECT_EQ(s.particles.f[1].y, 0.0) << mu;
  EXPECT_NEAR(s.particles.f[1].x, fn, 1e-12 * fn);
}

TEST(PeridigmRuns, AdaptiveLoadSteppingIsReadSwitchToVerletIsStaged) {
  const fs::path dir = fresh_dir("horizon_pdruns_adaptive");
  std::ofstream(dir / "points.txt") << "0 0 0 1 1\n1 0 0 1 1\n2 0 0 1 1\n";
  auto deck = [](const std::string& extra) {
    return std::string(R"(Peridigm:
  Discretization: {Type: "Text File", Input Mesh File: "points.txt"}
  Materials:
    Steel: {Material Model: "Elastic", Density: 7800.0, Bulk Modulus: 130.0e9, Shear Modulus: 78.0e9}
  Blocks:
    All: {Block Names: "block_1", Material: "Steel", Horizon: 1.5}
  Boundary Conditions:
    Left: "1"
    Right: "3"
    Hold: {Type: "Prescribed Displacement", Node Set: "Left", Coordinate: "x", Value: "0.0"}
    Pull: {Type: "Prescribed Displacement", Node Set: "Right", Coordinate: "x", Value: "0.001*t"}
  Solver:
    Final Time: 1.0
    QuasiStatic:
      Number of Load Steps: 2
      Maximum Solver Iterations: 10
      Adaptive Load-Stepping:
        Maximum load step reductions in one step: 1
        Maximum total load step reductions: 5
        Reduce all remaining load steps: true
        Adaptive output frequency: true
)") + extra;
  };
  const YAML::Node n = convert(dir, deck(""));
  EXPECT_EQ(n["solver"]["type"].as<std::string>(), "static");
  EXPECT_EQ(n["solver"]["load_steps"].as<int>(), 2);
  // Switch to Verlet is a staged run (tests/unit/test_staged_run.cpp); both Safety Factor
  // and Fixed dt in it are an error at the second.
  const YAML::Node sw = convert(dir, deck("        Switch to Verlet: {Safety Factor: 0.6, Output Frequency: 10}\n"));
  EXPECT_EQ(sw["solver"][0]["on_failure"].as<std::string>(), "explicit");
  try {
    convert(dir, deck("        Switch to Verlet: {Fixed dt: 1.0e-6, Safety Factor: 0.6}\n"));
    FAIL() << "expected an error";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("deck.yaml:22:"), std::string::npos) << m;
    EXPECT_NE(m.find("give Fixed dt or Safety Factor, not both"), std::string::npos) << m;
  }
}

TEST(PeridigmRuns, SmallTangentCgCannotFinishIsSolvedDense) {
  // A free chain of 40 unit springs (the Laplacian: singular, its null space the uniform
  // translation) made slightly unsymmetric, as a finite-difference tangent is: CG does
  // not converge on it; the dense solve returns K x = r with no translation added.
  const int n = 40;
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i + 1 < n; ++i) {
    t.emplace_back(i, i, 1.0), t.emplace_back(i + 1, i + 1, 1.0);
    t.emplace_back(i, i + 1, -1.0 + 1e-3 * (i % 3)), t.emplace_back(i + 1, i, -1.0 - 1e-3 * (i % 3));
  }
  SparseMatrix K(n, n);
  K.setFromTriplets(t.begin(), t.end());
  // The diagonal keeps each column's sum 0: the translation stays in the null space of
  // the stored matrix's transpose (the solve's K, linear.cpp).
  for (int c = 0; c < n; ++c) {
    double sum = 0;
    for (SparseMatrix::InnerIterator it(K, c); it; ++it)
      if (it.row() != c) sum += it.value();
    K.coeffRef(c, c) = -sum;
  }
  const Eigen::MatrixXd Kt = Eigen::MatrixXd(K).transpose();  // the operator solved
  // A residual in the operator's range (a free body's balanced forces): that of a
  // displacement with no translation, which is then the minimum-norm solution.
  Eigen::VectorXd x_true(n);
  for (int i = 0; i < n; ++i) x_true[i] = std::sin(0.3 * i) * (i - 19.5);
  x_true.array() -= x_true.mean();
  const Eigen::VectorXd r = Kt * x_true;
  Eigen::VectorXd x;
  LinearSolver cg(LinearSolverKind::cg);
  SparseMatrix work = K;
  const LinearStats st = cg.solve(work, Eigen::VectorXd(), r, x, 1e-12, 20000);
  ASSERT_TRUE(st.ok);
  EXPECT_EQ(st.iterations, 2 * n + 1);  // 2n CG iterations, then the dense solve
  EXPECT_LT((Kt * x - r).norm(), 1e-10 * r.norm());
  EXPECT_LT((x - x_true).norm(), 1e-9 * x_true.norm());  // no translation added
}

TEST(PeridigmRuns, ShearCorrectionFactorOfALatticeCube) {
  // A 5^3 cube of unit spacing, delta = 1.01: the six nearest neighbours. s = 1/(1 -
  // |dev S|^2/((2/3) m^2)) with S = sum xi (x) xi: inside S = 2 I and at a corner S = I
  // (isotropic, s = 1); a face's middle S = diag(2, 2, 1), s = 25/24; an edge's middle
  // S = diag(1, 1, 2), m = 4, |dev S|^2 = 2/3: s = 16/15.
  const fs::path dir = fresh_dir("horizon_pdruns_scf");
  std::ofstream points(dir / "points.txt");
  for (int k = 0; k < 5; ++k)
    for (int j = 0; j < 5; ++j)
      for (int i = 0; i < 5; ++i) points << i << " " << j << " " << k << " 1 1\n";
  points.close();
  std::ofstream(dir / "deck.xml") << R"(<ParameterList>
  <ParameterList name="Discretization">
    <Parameter name="Type" type="string" value="Text File"/>
    <Parameter name="Input Mesh File" type="string" value="points.txt"/>
  </ParameterList>
  <ParameterList name="Materials">
    <ParameterList name="Glass">
      <Parameter name="Material Model" type="string" value="Elastic"/>
      <Parameter name="Density" type="double" value="2200.0"/>
      <Parameter name="Bulk Modulus" type="double" value="14.9e9"/>
      <Parameter name="Shear Modulus" type="double" value="8.94e9"/>
      <Parameter name="Apply Shear Correction Factor" type="bool" value="true"/>
    </ParameterList>
  </ParameterList>
  <ParameterList name="Blocks">
    <ParameterList name="All">
      <Parameter name="Block Names" type="string" value="block_1"/>
      <Parameter name="Material" type="string" value="Glass"/>
      <Parameter name="Horizon" type="double" value="1.01"/>
    </ParameterList>
  </ParameterList>
  <ParameterList name="Solver">
    <Parameter name="Final Time" type="double" value="1.0e-6"/>
    <ParameterList name="Verlet">
      <Parameter name="Fixed dt" type="double" value="1.0e-6"/>
    </ParameterList>
  </ParameterList>
</ParameterList>
)";
  const std::string native = convert_peridigm_deck((dir / "deck.xml").string());
  const Config c = parse_deck(native, (dir / "deck.yaml").string());
  const System s = build_system(c);
  std::vector<ModelField> fields;
  for (const auto& m : s.models) m->fields(s, fields);
  const ModelField* f = nullptr;
  for (const auto& x : fields)
    if (x.name == "shear_correction_factor") f = &x;
  ASSERT_NE(f, nullptr) << native;
  auto at = [&](double x, double y, double z) {
    for (std::size_t i = 0; i < s.particles.size(); ++i)
      if (s.particles.X[i].x == x && s.particles.X[i].y == y && s.particles.X[i].z == z) return f->values[i];
    ADD_FAILURE() << x << " " << y << " " << z;
    return 0.0;
  };
  EXPECT_NEAR(at(2, 2, 2), 1.0, 1e-15);
  EXPECT_NEAR(at(0, 0, 0), 1.0, 1e-15);
  EXPECT_NEAR(at(2, 2, 4), 25.0 / 24.0, 1e-15);
  EXPECT_NEAR(at(0, 0, 2), 16.0 / 15.0, 1e-15);
}

}  // namespace
}  // namespace horizon
