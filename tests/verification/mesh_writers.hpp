#pragma once
// Small structured meshes of a box written by the tests themselves: Gmsh .msh (through
// the Gmsh library) and Exodus II (through the Exodus library). Hexahedra, or each hexahedron split into six tetrahedra; interior nodes can be
// jittered (the cells still tile the box exactly). Physical groups / sets: the volume
// "block" and the faces "left" (x = min) and "right" (x = max).
#include <exodusII.h>
#include <gmshc.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "horizon/core/vec3.hpp"
#include "horizon/geometry/gmsh_library.hpp"

namespace horizon::test {

struct BoxMesh {
  std::vector<Vec3> nodes;
  std::vector<std::vector<int64_t>> cells;  // 1-based node tags
  std::vector<std::vector<int64_t>> left, right;  // face elements (1-based)
  bool tets = false;
};

inline BoxMesh box_mesh(const Vec3& lo, const Vec3& hi, int nx, int ny, int nz, bool tets, double jitter = 0) {
  BoxMesh m;
  m.tets = tets;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  const double h[3] = {(hi.x - lo.x) / nx, (hi.y - lo.y) / ny, (hi.z - lo.z) / nz};
  auto tag = [&](int i, int j, int k) { return static_cast<int64_t>(1 + i + (nx + 1) * (j + (ny + 1) * k)); };
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) {
        Vec3 x{lo.x + i * h[0], lo.y + j * h[1], lo.z + k * h[2]};
        if (i == nx) x.x = hi.x;
        if (j == ny) x.y = hi.y;
        if (k == nz) x.z = hi.z;
        const bool interior = i > 0 && i < nx && j > 0 && j < ny && k > 0 && k < nz;
        if (interior && jitter > 0) x += Vec3{u(rng) * h[0], u(rng) * h[1], u(rng) * h[2]} * jitter;
        m.nodes.push_back(x);
      }
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const std::array<int64_t, 8> c = {tag(i, j, k),         tag(i + 1, j, k),     tag(i + 1, j + 1, k),
                                          tag(i, j + 1, k),     tag(i, j, k + 1),     tag(i + 1, j, k + 1),
                                          tag(i + 1, j + 1, k + 1), tag(i, j + 1, k + 1)};
        if (!tets) {
          m.cells.emplace_back(c.begin(), c.end());
        } else {
          // Six tetrahedra around the diagonal 0-6 (a conforming split when every cube
          // uses the same diagonal direction).
          static constexpr int t[6][4] = {{0, 1, 2, 6}, {0, 2, 3, 6}, {0, 3, 7, 6},
                                          {0, 7, 4, 6}, {0, 4, 5, 6}, {0, 5, 1, 6}};
          for (const auto& q : t) m.cells.push_back({c[q[0]], c[q[1]], c[q[2]], c[q[3]]});
        }
      }
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j) {
      m.left.push_back({tag(0, j, k), tag(0, j + 1, k), tag(0, j + 1, k + 1), tag(0, j, k + 1)});
      m.right.push_back({tag(nx, j, k), tag(nx, j + 1, k), tag(nx, j + 1, k + 1), tag(nx, j, k + 1)});
    }
  return m;
}

// Gmsh's C API (gmshc.h) through the library Horizon loads on first use: the tests do
// not link libgmsh, whose start-up (about 1 s: OpenCASCADE, FLTK, X11) every test
// process would pay. GMSH(gmshModelAdd, "box") calls gmshModelAdd("box", &ierr) and
// throws when Gmsh reports an error. Call it inside a gmsh_library::Session.
#define GMSH(f, ...)                                                                                   \
  do {                                                                                                 \
    int gmsh_ierr = 0;                                                                                 \
    reinterpret_cast<decltype(&::f)>(::horizon::gmsh_library::symbol(#f))(__VA_ARGS__ __VA_OPT__(, ) & gmsh_ierr); \
    if (gmsh_ierr != 0) throw std::runtime_error(#f " failed: " + ::horizon::test::gmsh_last_error()); \
  } while (0)

inline std::string gmsh_last_error() {
  char* text = nullptr;
  int ierr = 0;
  reinterpret_cast<decltype(&::gmshLoggerGetLastError)>(gmsh_library::symbol("gmshLoggerGetLastError"))(&text, &ierr);
  std::string s = text ? text : "";
  if (text) reinterpret_cast<decltype(&::gmshFree)>(gmsh_library::symbol("gmshFree"))(text);
  return s;
}

// Gmsh .msh through the Gmsh library, in any version it writes (Mesh.MshFileVersion: 1,
// 2.2, 3, 4, 4.1) and encoding (Mesh.Binary): one discrete volume entity (physical 1
// "block"), two discrete surface entities (physical 2 "left", 3 "right"); node tags
// 1..n, the cells first (element tags 1..), then the faces.
inline void write_msh(const BoxMesh& m, const std::string& path, bool binary, double version = 4.1) {
  gmsh_library::Session session;
  GMSH(gmshModelAdd, "box");
  GMSH(gmshModelAddDiscreteEntity, 3, 1, nullptr, 0);
  GMSH(gmshModelAddDiscreteEntity, 2, 1, nullptr, 0);
  GMSH(gmshModelAddDiscreteEntity, 2, 2, nullptr, 0);
  std::vector<std::size_t> tags;
  std::vector<double> xyz;
  for (std::size_t i = 0; i < m.nodes.size(); ++i) {
    tags.push_back(i + 1);
    xyz.insert(xyz.end(), {m.nodes[i].x, m.nodes[i].y, m.nodes[i].z});
  }
  GMSH(gmshModelMeshAddNodes, 3, 1, tags.data(), tags.size(), xyz.data(), xyz.size(), nullptr, 0);
  std::size_t next = 1;
  auto add = [&](int entity, int type, const std::vector<std::vector<int64_t>>& elems) {
    std::vector<std::size_t> etags, enodes;
    for (const auto& e : elems) {
      etags.push_back(next++);
      for (int64_t v : e) enodes.push_back(static_cast<std::size_t>(v));
    }
    // The entity's dimension is the element type's.
    GMSH(gmshModelMeshAddElementsByType, entity, type, etags.data(), etags.size(), enodes.data(), enodes.size());
  };
  add(1, m.tets ? 4 : 5, m.cells);  // Gmsh types: 4 tetrahedron, 5 hexahedron, 3 quadrangle
  add(1, 3, m.left);
  add(2, 3, m.right);
  const struct {
    int dim, entity, tag;
    const char* name;
  } groups[3] = {{3, 1, 1, "block"}, {2, 1, 2, "left"}, {2, 2, 3, "right"}};
  for (const auto& g : groups) {
    int entity = g.entity;
    GMSH(gmshModelAddPhysicalGroup, g.dim, &entity, 1, g.tag);
    GMSH(gmshModelSetPhysicalName, g.dim, g.tag, g.name);
  }
  GMSH(gmshOptionSetNumber, "Mesh.MshFileVersion", version);
  GMSH(gmshOptionSetNumber, "Mesh.Binary", binary ? 1.0 : 0.0);
  GMSH(gmshWrite, path.c_str());
}

// Exodus II: element block 1 "block"; node sets 1 "left" and 2 "right".
inline bool write_exodus(const BoxMesh& m, const std::string& path) {
  int cpu_ws = sizeof(double), io_ws = sizeof(double);
  const int id = ex_create(path.c_str(), EX_CLOBBER, &cpu_ws, &io_ws);
  if (id < 0) return false;
  const auto n = static_cast<int64_t>(m.nodes.size());
  ex_put_init(id, "box", 3, n, static_cast<int64_t>(m.cells.size()), 1, 2, 0);
  std::vector<double> x, y, z;
  for (const auto& p : m.nodes) x.push_back(p.x), y.push_back(p.y), z.push_back(p.z);
  ex_put_coord(id, x.data(), y.data(), z.data());
  const int npe = m.tets ? 4 : 8;
  ex_put_block(id, EX_ELEM_BLOCK, 1, m.tets ? "TETRA" : "HEX8", static_cast<int64_t>(m.cells.size()), npe, 0, 0, 0);
  std::vector<int> conn;
  for (const auto& c : m.cells)
    for (int64_t v : c) conn.push_back(static_cast<int>(v));
  ex_put_conn(id, EX_ELEM_BLOCK, 1, conn.data(), nullptr, nullptr);
  ex_put_name(id, EX_ELEM_BLOCK, 1, "block");
  int set_id = 1;
  for (const auto* face : {&m.left, &m.right}) {
    std::vector<int> nodes;
    for (const auto& e : *face)
      for (int64_t v : e) nodes.push_back(static_cast<int>(v));
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    ex_put_set_param(id, EX_NODE_SET, set_id, static_cast<int64_t>(nodes.size()), 0);
    ex_put_set(id, EX_NODE_SET, set_id, nodes.data(), nullptr);
    ex_put_name(id, EX_NODE_SET, set_id, set_id == 1 ? "left" : "right");
    ++set_id;
  }
  return ex_close(id) >= 0;
}

}  // namespace horizon::test
