#pragma once
// Small structured meshes of a box written by the tests themselves: Gmsh MSH 4.1 (ASCII
// or binary, after the Gmsh reference manual sec. 10.1) and Exodus II (through the Exodus
// library). Hexahedra, or each hexahedron split into six tetrahedra; interior nodes can be
// jittered (the cells still tile the box exactly). Physical groups / sets: the volume
// "block" and the faces "left" (x = min) and "right" (x = max).
#include <exodusII.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "horizon/core/vec3.hpp"

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

// Gmsh MSH 4.1: one volume entity (physical 1 "block"), two surface entities (physical 2
// "left", 3 "right"); every node in the volume's node block.
inline void write_msh(const BoxMesh& m, const std::string& path, bool binary) {
  std::ofstream out(path, std::ios::binary);
  out << "$MeshFormat\n4.1 " << (binary ? 1 : 0) << " 8\n";
  auto i32 = [&](int32_t v) { out.write(reinterpret_cast<const char*>(&v), 4); };
  auto u64 = [&](uint64_t v) { out.write(reinterpret_cast<const char*>(&v), 8); };
  auto f64 = [&](double v) { out.write(reinterpret_cast<const char*>(&v), 8); };
  if (binary) {
    i32(1);
    out << "\n";
  }
  out << "$EndMeshFormat\n";
  out << "$PhysicalNames\n3\n3 1 \"block\"\n2 2 \"left\"\n2 3 \"right\"\n$EndPhysicalNames\n";
  out << "$Entities\n";
  out.precision(17);
  if (binary) {
    u64(0), u64(0), u64(2), u64(1);
    for (int s = 1; s <= 2; ++s) {
      i32(s);
      for (int k = 0; k < 6; ++k) f64(0);
      u64(1), i32(s + 1), u64(0);
    }
    i32(1);
    for (int k = 0; k < 6; ++k) f64(0);
    u64(1), i32(1), u64(2), i32(1), i32(2);
    out << "\n";
  } else {
    out << "0 0 2 1\n1 0 0 0 0 0 0 1 2 0\n2 0 0 0 0 0 0 1 3 0\n1 0 0 0 0 0 0 1 1 2 1 2\n";
  }
  out << "$EndEntities\n$Nodes\n";
  const std::size_t n = m.nodes.size();
  if (binary) {
    u64(1), u64(n), u64(1), u64(n);
    i32(3), i32(1), i32(0), u64(n);
    for (std::size_t i = 0; i < n; ++i) u64(i + 1);
    for (const auto& x : m.nodes) f64(x.x), f64(x.y), f64(x.z);
    out << "\n";
  } else {
    out << "1 " << n << " 1 " << n << "\n3 1 0 " << n << "\n";
    for (std::size_t i = 0; i < n; ++i) out << i + 1 << "\n";
    for (const auto& x : m.nodes) out << x.x << " " << x.y << " " << x.z << "\n";
  }
  out << "$EndNodes\n$Elements\n";
  const std::size_t total = m.cells.size() + m.left.size() + m.right.size();
  const int cell_type = m.tets ? 4 : 5;
  struct Block {
    int dim, entity, type;
    const std::vector<std::vector<int64_t>>* elems;
  };
  const Block blocks[3] = {{3, 1, cell_type, &m.cells}, {2, 1, 3, &m.left}, {2, 2, 3, &m.right}};
  int64_t tag = 1;
  if (binary) {
    u64(3), u64(total), u64(1), u64(total);
  } else {
    out << "3 " << total << " 1 " << total << "\n";
  }
  for (const auto& b : blocks) {
    if (binary) {
      i32(b.dim), i32(b.entity), i32(b.type), u64(b.elems->size());
      for (const auto& e : *b.elems) {
        u64(static_cast<uint64_t>(tag++));
        for (int64_t v : e) u64(static_cast<uint64_t>(v));
      }
    } else {
      out << b.dim << " " << b.entity << " " << b.type << " " << b.elems->size() << "\n";
      for (const auto& e : *b.elems) {
        out << tag++;
        for (int64_t v : e) out << " " << v;
        out << "\n";
      }
    }
  }
  if (binary) out << "\n";
  out << "$EndElements\n";
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
