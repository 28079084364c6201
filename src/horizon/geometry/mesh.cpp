#include "horizon/geometry/mesh.hpp"

#include "horizon/geometry/gmsh_library.hpp"

#include <exodusII.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <unordered_map>

namespace horizon {

const char* cell_type_name(CellType type) {
  switch (type) {
    case CellType::tri3: return "triangle";
    case CellType::quad4: return "quadrangle";
    case CellType::tet4: return "tetrahedron";
    case CellType::hex8: return "hexahedron";
    case CellType::wedge6: return "wedge";
    case CellType::pyramid5: return "pyramid";
    case CellType::sphere: return "sphere";
  }
  return "cell";
}

namespace {

int cell_dimension(CellType t) { return (t == CellType::tri3 || t == CellType::quad4) ? 2 : 3; }

double tet_volume(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return std::abs(dot(b - a, cross(c - a, d - a))) / 6.0;
}

// Isoparametric quadrature of the volume and first moment: sum over points of |det J| w
// and x |det J| w. Exact for the trilinear hexahedron (det J is at most quadratic in each
// natural coordinate, x det J cubic: two Gauss points per axis integrate both exactly;
// Hughes, The Finite Element Method, 2000, sec. 3.8) and likewise for the bilinear quad.
void hex_geometry(const std::vector<Vec3>& x, double& V, Vec3& c) {
  static constexpr double s[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                     {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  const double g = 1.0 / std::sqrt(3.0);
  V = 0;
  c = {};
  for (int q = 0; q < 8; ++q) {
    const double p[3] = {s[q][0] * g, s[q][1] * g, s[q][2] * g};
    Vec3 d[3]{}, xq{};
    for (int a = 0; a < 8; ++a) {
      const double f[3] = {1 + s[a][0] * p[0], 1 + s[a][1] * p[1], 1 + s[a][2] * p[2]};
      xq += x[a] * (f[0] * f[1] * f[2] / 8);
      d[0] += x[a] * (s[a][0] * f[1] * f[2] / 8);
      d[1] += x[a] * (f[0] * s[a][1] * f[2] / 8);
      d[2] += x[a] * (f[0] * f[1] * s[a][2] / 8);
    }
    const double J = std::abs(dot(d[0], cross(d[1], d[2])));
    V += J;
    c += xq * J;
  }
  c = V > 0 ? c / V : c;
}

void quad_geometry(const std::vector<Vec3>& x, double& A, Vec3& c) {
  static constexpr double s[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  const double g = 1.0 / std::sqrt(3.0);
  A = 0;
  c = {};
  for (int q = 0; q < 4; ++q) {
    const double p[2] = {s[q][0] * g, s[q][1] * g};
    Vec3 d[2]{}, xq{};
    for (int a = 0; a < 4; ++a) {
      const double f[2] = {1 + s[a][0] * p[0], 1 + s[a][1] * p[1]};
      xq += x[a] * (f[0] * f[1] / 4);
      d[0] += x[a] * (s[a][0] * f[1] / 4);
      d[1] += x[a] * (f[0] * s[a][1] / 4);
    }
    const double J = norm(cross(d[0], d[1]));
    A += J;
    c += xq * J;
  }
  c = A > 0 ? c / A : c;
}

// The linear wedge: N = L_a(xi, eta) (1 -+ zeta)/2. det J is quadratic in (xi, eta) and in
// zeta, x det J cubic: Dunavant's 7-point degree-5 triangle rule (Dunavant 1985, IJNME 21,
// table for p = 5) times 2 Gauss points in zeta integrate both exactly.
void wedge_geometry(const std::vector<Vec3>& x, double& V, Vec3& c) {
  const double a1 = 0.059715871789770, b1 = 0.470142064105115, w1 = 0.132394152788506;
  const double a2 = 0.797426985353087, b2 = 0.101286507323456, w2 = 0.125939180544827;
  const double tri[7][3] = {{1.0 / 3, 1.0 / 3, 0.225}, {a1, b1, w1}, {b1, a1, w1}, {b1, b1, w1},
                            {a2, b2, w2},              {b2, a2, w2}, {b2, b2, w2}};
  const double g = 1.0 / std::sqrt(3.0);
  V = 0;
  c = {};
  for (const auto& t : tri) {
    for (double z : {-g, g}) {
      const double L[3] = {1 - t[0] - t[1], t[0], t[1]};
      const double dL[3][2] = {{-1, -1}, {1, 0}, {0, 1}};
      Vec3 d[3]{}, xq{};
      for (int a = 0; a < 6; ++a) {
        const int k = a % 3;
        const double h = a < 3 ? 0.5 * (1 - z) : 0.5 * (1 + z);
        const double dh = a < 3 ? -0.5 : 0.5;
        xq += x[a] * (L[k] * h);
        d[0] += x[a] * (dL[k][0] * h);
        d[1] += x[a] * (dL[k][1] * h);
        d[2] += x[a] * (L[k] * dh);
      }
      const double J = std::abs(dot(d[0], cross(d[1], d[2]))) * t[2] * 0.5;  // reference triangle area 1/2
      V += J;
      c += xq * J;
    }
  }
  c = V > 0 ? c / V : c;
}

}  // namespace

void cell_geometry(CellType type, const std::vector<Vec3>& x, double& measure, Vec3& centroid) {
  switch (type) {
    case CellType::tet4:
      measure = tet_volume(x[0], x[1], x[2], x[3]);
      centroid = (x[0] + x[1] + x[2] + x[3]) / 4.0;
      return;
    case CellType::tri3:
      measure = 0.5 * norm(cross(x[1] - x[0], x[2] - x[0]));
      centroid = (x[0] + x[1] + x[2]) / 3.0;
      return;
    case CellType::sphere:
      centroid = x[0];  // the volume comes with the element (read_exodus)
      return;
    case CellType::hex8: hex_geometry(x, measure, centroid); return;
    case CellType::quad4: quad_geometry(x, measure, centroid); return;
    case CellType::wedge6: wedge_geometry(x, measure, centroid); return;
    case CellType::pyramid5: {
      // Two tetrahedra on the base diagonal 0-2.
      const double v1 = tet_volume(x[0], x[1], x[2], x[4]);
      const double v2 = tet_volume(x[0], x[2], x[3], x[4]);
      measure = v1 + v2;
      const Vec3 c1 = (x[0] + x[1] + x[2] + x[4]) / 4.0;
      const Vec3 c2 = (x[0] + x[2] + x[3] + x[4]) / 4.0;
      centroid = measure > 0 ? (c1 * v1 + c2 * v2) / measure : c1;
      return;
    }
  }
}

std::vector<uint32_t> Mesh::cells_touching(const MeshGroup& set) const {
  std::vector<uint8_t> in(nodes.size(), 0);
  for (uint32_t n : set.members) in[n] = 1;
  std::vector<uint32_t> out;
  for (std::size_t e = 0; e < cell_nodes.size(); ++e) {
    for (uint32_t n : cell_nodes[e]) {
      if (in[n]) {
        out.push_back(static_cast<uint32_t>(e));
        break;
      }
    }
  }
  return out;
}

namespace {
const MeshGroup* find_group(const std::vector<MeshGroup>& groups, const std::string& key) {
  for (const auto& g : groups)
    if (g.name == key) return &g;
  for (const auto& g : groups)
    if (std::to_string(g.id) == key) return &g;
  return nullptr;
}

// Fills centroid and measure (sphere cells keep the measure their reader set); checks
// every cell has a volume.
void finish(Mesh& m) {
  const std::size_t n = m.cell_nodes.size();
  m.centroid.resize(n);
  m.measure.resize(n, 0.0);
  std::vector<Vec3> x;
  for (std::size_t e = 0; e < n; ++e) {
    x.clear();
    for (uint32_t k : m.cell_nodes[e]) x.push_back(m.nodes[k]);
    if (m.dimension == 2)
      for (auto& p : x) p.z = 0;
    cell_geometry(m.cell_type[e], x, m.measure[e], m.centroid[e]);
    if (!(m.measure[e] > 0) || !std::isfinite(m.measure[e])) {
      const int64_t tag = e < m.cell_tag.size() ? m.cell_tag[e] : static_cast<int64_t>(e + 1);
      throw MeshError(m.file + ": element " + std::to_string(tag) + " (" + cell_type_name(m.cell_type[e]) +
                      ") has no " + (m.dimension == 3 ? "volume" : "area") + " (degenerate or collapsed nodes)");
    }
  }
  for (auto& s : m.sets) {
    std::sort(s.members.begin(), s.members.end());
    s.members.erase(std::unique(s.members.begin(), s.members.end()), s.members.end());
  }
}

// ---------------------------------------------------------------- Gmsh, through its library

// Horizon's cell for a Gmsh element family: (dimension, corner nodes). Higher-order
// elements keep their corners (Gmsh lists them first, in the linear element's order:
// reference manual, "Node ordering").
bool gmsh_cell(int dim, int corners, CellType& out) {
  if (dim == 2 && corners == 3) out = CellType::tri3;
  else if (dim == 2 && corners == 4) out = CellType::quad4;
  else if (dim == 3 && corners == 4) out = CellType::tet4;
  else if (dim == 3 && corners == 8) out = CellType::hex8;
  else if (dim == 3 && corners == 6) out = CellType::wedge6;
  else if (dim == 3 && corners == 5) out = CellType::pyramid5;
  else return false;
  return true;
}

const char* entity_word(int dim) {
  static const char* const words[4] = {"point", "curve", "surface", "volume"};
  return dim >= 0 && dim < 4 ? words[dim] : "entity";
}

}  // namespace

const MeshGroup* Mesh::find_block(const std::string& key) const { return find_group(blocks, key); }
const MeshGroup* Mesh::find_set(const std::string& key) const { return find_group(sets, key); }

// Gmsh reads any file it is given: one that is not a mesh goes to its .geo interpreter,
// which runs commands (even shell commands). Only files that start as a mesh does go in.
void check_msh_header(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw MeshError("cannot open mesh '" + path + "': " + std::strerror(errno));
  char head[64] = {0};
  in.read(head, sizeof head - 1);
  std::string first(head, static_cast<std::size_t>(in.gcount()));
  first.erase(0, first.find_first_not_of(" \t\r\n"));
  first = first.substr(0, first.find_first_of(" \t\r\n"));
  if (first.empty()) throw MeshError(path + ": empty file (expected a Gmsh .msh file starting with $MeshFormat)");
  if (first != "$MeshFormat" && first != "$NOD")
    throw MeshError(path + ": not a Gmsh mesh: the file must start with $MeshFormat (MSH 2 and 4) or $NOD (MSH 1), found '" +
                    first.substr(0, 40) + "'");
}

Mesh read_gmsh(const std::string& path, int dimension) {
  check_msh_header(path);
  Mesh m;
  m.file = path;
  m.dimension = dimension;
  gmsh_library::Session gmsh;
  if (const std::string why = gmsh.merge(path); !why.empty()) throw MeshError(path + ": Gmsh cannot read it: " + why);

  std::vector<std::size_t> tags;
  std::vector<double> xyz;
  gmsh.nodes(tags, xyz);
  // Nodes in the order of their tags.
  std::vector<std::size_t> order(tags.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return tags[a] < tags[b]; });
  std::unordered_map<std::size_t, uint32_t> node_index;
  node_index.reserve(tags.size());
  for (std::size_t i : order) {
    if (!node_index.emplace(tags[i], static_cast<uint32_t>(m.nodes.size())).second) continue;  // on two entities
    m.nodes.push_back({xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]});
  }

  std::map<int, std::vector<uint32_t>> block_cells;                 // physical tag -> cells
  std::map<std::pair<int, int>, std::vector<uint32_t>> set_nodes;  // (dim, physical tag) -> nodes
  std::vector<uint32_t> nodes;
  for (const auto& [dim, tag] : gmsh.entities()) {
    const std::vector<int> phys = gmsh.physical_groups_of(dim, tag);
    for (const auto& b : gmsh.elements(dim, tag)) {
      const std::string where = " (" + std::string(entity_word(dim)) + " " + std::to_string(tag) + ")";
      if (b.dim > dimension) {
        throw MeshError(path + ": " + b.name + " elements" + where + " in a " + std::to_string(dimension) +
                        "-D deck (a 2-D deck reads triangles and quadrangles)");
      }
      CellType cell{};
      const bool is_cell = b.dim == dimension;
      if (is_cell && !gmsh_cell(b.dim, b.primary_nodes, cell)) {
        throw MeshError(path + ": " + b.name + " elements" + where +
                        " are not supported: Horizon reads triangles, quadrangles, tetrahedra, hexahedra, prisms and "
                        "pyramids (of any order: their corner nodes)");
      }
      const auto npe = static_cast<std::size_t>(b.nodes_per_element);
      const auto corners = static_cast<std::size_t>(b.primary_nodes);
      for (std::size_t e = 0; e < b.tags.size(); ++e) {
        nodes.clear();
        for (std::size_t k = 0; k < corners; ++k) {
          const auto it = node_index.find(b.nodes[e * npe + k]);
          if (it == node_index.end())
            throw MeshError(path + ": element " + std::to_string(b.tags[e]) + where + " names node " +
                            std::to_string(b.nodes[e * npe + k]) + ", which the file does not define");
          nodes.push_back(it->second);
        }
        if (is_cell) {
          const auto idx = static_cast<uint32_t>(m.cell_nodes.size());
          m.cell_type.push_back(cell);
          m.cell_nodes.push_back(nodes);
          m.cell_tag.push_back(static_cast<int64_t>(b.tags[e]));
          for (int p : phys) block_cells[p].push_back(idx);
        } else {
          for (int p : phys) {
            auto& s = set_nodes[{dim, p}];
            s.insert(s.end(), nodes.begin(), nodes.end());
          }
        }
      }
    }
  }
  if (m.cell_nodes.empty()) {
    throw MeshError(path + ": no " + std::to_string(dimension) + "-D elements (" +
                    (dimension == 3 ? "tetrahedra, hexahedra, prisms or pyramids" : "triangles or quadrangles") +
                    "); is the mesh " + std::to_string(dimension) + "-D?");
  }
  auto group_name = [&](int dim, int tag) {
    const std::string name = gmsh.physical_name(dim, tag);
    return name.empty() ? std::to_string(tag) : name;
  };
  for (auto& [tag, cells] : block_cells) m.blocks.push_back({group_name(dimension, tag), tag, cells});
  if (m.blocks.empty()) {
    MeshGroup all{"all", 0, {}};
    for (uint32_t e = 0; e < m.cell_nodes.size(); ++e) all.members.push_back(e);
    m.blocks.push_back(std::move(all));
  }
  for (auto& [key, members] : set_nodes) m.sets.push_back({group_name(key.first, key.second), key.second, members});
  finish(m);
  return m;
}

// ---------------------------------------------------------------- Exodus II

namespace {

class ExodusFile {
 public:
  explicit ExodusFile(const std::string& path) : path_(path) {
    if (!std::filesystem::exists(path)) throw MeshError("cannot open mesh '" + path + "': No such file or directory");
    ex_opts(0);  // errors come back as return codes, not messages on stderr
    int cpu_ws = sizeof(double), io_ws = 0;
    float version = 0;
    id_ = ex_open(path.c_str(), EX_READ, &cpu_ws, &io_ws, &version);
    if (id_ < 0) throw MeshError(path + ": not an Exodus II file (the Exodus library cannot open it)");
    ex_set_max_name_length(id_, 256);
  }
  ~ExodusFile() {
    if (id_ >= 0) ex_close(id_);
  }
  ExodusFile(const ExodusFile&) = delete;
  ExodusFile& operator=(const ExodusFile&) = delete;
  int id() const { return id_; }
  const std::string& path() const { return path_; }
  void check(int rc, const std::string& what) const {
    if (rc < 0) throw MeshError(path_ + ": cannot read " + what + " (Exodus error " + std::to_string(rc) + ")");
  }
  std::string name(ex_entity_type type, int64_t id) const {
    char buf[260] = {0};
    if (ex_get_name(id_, type, id, buf) < 0) return std::to_string(id);
    std::string s(buf);
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.pop_back();
    return s.empty() ? std::to_string(id) : s;
  }

 private:
  std::string path_;
  int id_ = -1;
};

bool exodus_cell(std::string type, int nodes, CellType& out) {
  for (auto& ch : type) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
  auto starts = [&](const char* p) { return type.rfind(p, 0) == 0; };
  if (starts("SPHERE") && nodes == 1) out = CellType::sphere;
  else if (starts("TET") && nodes == 4) out = CellType::tet4;
  else if (starts("HEX") && nodes == 8) out = CellType::hex8;
  else if (starts("WEDGE") && nodes == 6) out = CellType::wedge6;
  else if (starts("PYRAMID") && nodes == 5) out = CellType::pyramid5;
  else if (starts("TRI") && nodes == 3) out = CellType::tri3;
  else if (starts("QUAD") && nodes == 4) out = CellType::quad4;
  else return false;
  return true;
}

// The volumes of a SPHERE block's elements: the attribute named "volume" (any case),
// else the second of two (Cubit's sphere meshes carry radius, volume), else the only one.
std::vector<double> sphere_volumes(const ExodusFile& f, int id, int n, int nattr, const std::string& block) {
  if (nattr < 1)
    throw MeshError(f.path() + ": SPHERE block " + block + " carries no attributes; its elements' volumes are an "
                                                           "element attribute (\"volume\", or radius and volume)");
  std::vector<std::string> names(static_cast<std::size_t>(nattr));
  {
    std::vector<std::vector<char>> buf(static_cast<std::size_t>(nattr), std::vector<char>(260, 0));
    std::vector<char*> ptr;
    for (auto& b : buf) ptr.push_back(b.data());
    if (ex_get_attr_names(f.id(), EX_ELEM_BLOCK, id, ptr.data()) >= 0)
      for (int a = 0; a < nattr; ++a) names[static_cast<std::size_t>(a)] = buf[static_cast<std::size_t>(a)].data();
  }
  int which = nattr == 2 ? 1 : 0;
  bool named = false;
  for (int a = 0; a < nattr; ++a) {
    std::string w = names[static_cast<std::size_t>(a)];
    for (auto& ch : w) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    if (w.rfind("volume", 0) == 0) which = a, named = true;
  }
  if (!named && nattr > 2)
    throw MeshError(f.path() + ": SPHERE block " + block + " carries " + std::to_string(nattr) +
                    " attributes and none is named \"volume\"");
  std::vector<double> attr(static_cast<std::size_t>(n) * static_cast<std::size_t>(nattr));
  f.check(ex_get_attr(f.id(), EX_ELEM_BLOCK, id, attr.data()), "the attributes of block " + block);
  std::vector<double> v(static_cast<std::size_t>(n));
  for (int e = 0; e < n; ++e) v[static_cast<std::size_t>(e)] = attr[static_cast<std::size_t>(e) * nattr + which];
  return v;
}

}  // namespace

namespace {

// read_exodus, and where `node_ids`/`cell_ids` are given, the file's node and element
// number maps (the global ids of a piece of a partitioned mesh) for its nodes and cells.
Mesh read_exodus_with_ids(const std::string& path, int dimension, std::vector<int64_t>* node_ids,
                          std::vector<int64_t>* cell_ids) {
  ExodusFile f(path);
  Mesh m;
  m.file = path;
  m.dimension = dimension;
  char title[MAX_LINE_LENGTH + 1] = {0};
  int ndim = 0, nnodes = 0, nelem = 0, nblk = 0, nns = 0, nss = 0;
  f.check(ex_get_init(f.id(), title, &ndim, &nnodes, &nelem, &nblk, &nns, &nss), "the header");
  if (ndim < dimension) {
    throw MeshError(path + ": a " + std::to_string(ndim) + "-D mesh in a " + std::to_string(dimension) + "-D deck");
  }
  std::vector<double> x(static_cast<std::size_t>(nnodes)), y(x.size()), z(x.size(), 0.0);
  f.check(ex_get_coord(f.id(), x.data(), ndim > 1 ? y.data() : nullptr, ndim > 2 ? z.data() : nullptr), "the coordinates");
  m.nodes.resize(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) m.nodes[i] = {x[i], ndim > 1 ? y[i] : 0.0, ndim > 2 ? z[i] : 0.0};

  std::vector<int> elem_map;
  if (node_ids) {
    std::vector<int> map(static_cast<std::size_t>(nnodes));
    if (nnodes > 0) f.check(ex_get_id_map(f.id(), EX_NODE_MAP, map.data()), "the node number map");
    node_ids->assign(map.begin(), map.end());
  }
  if (cell_ids) {
    elem_map.resize(static_cast<std::size_t>(nelem));
    if (nelem > 0) f.check(ex_get_id_map(f.id(), EX_ELEM_MAP, elem_map.data()), "the element number map");
    cell_ids->clear();
  }
  std::vector<int> ids(static_cast<std::size_t>(nblk));
  if (nblk > 0) f.check(ex_get_ids(f.id(), EX_ELEM_BLOCK, ids.data()), "the element block ids");
  std::size_t first_element = 0;  // the block's first element in the file's element order
  for (int id : ids) {
    char type[MAX_STR_LENGTH + 1] = {0};
    int n = 0, npe = 0, nedge = 0, nface = 0, nattr = 0;
    f.check(ex_get_block(f.id(), EX_ELEM_BLOCK, id, type, &n, &npe, &nedge, &nface, &nattr), "element block " + std::to_string(id));
    const std::size_t block_first = first_element;
    first_element += static_cast<std::size_t>(n);
    // A block without elements (a piece of a partitioned mesh that holds none of the
    // block's elements writes it as a 0-node NULL block) adds nothing, whatever its type.
    if (n == 0) continue;
    CellType cell{};
    if (!exodus_cell(type, npe, cell)) {
      throw MeshError(path + ": element block " + std::to_string(id) + " ('" + f.name(EX_ELEM_BLOCK, id) + "') has " +
                      std::to_string(npe) + "-node " + type +
                      " elements, which are not supported: Horizon reads TETRA4, HEX8, WEDGE6, PYRAMID5, SPHERE (3-D), TRI3, QUAD4 (2-D)");
    }
    std::vector<int> conn(static_cast<std::size_t>(n) * static_cast<std::size_t>(npe));
    f.check(ex_get_conn(f.id(), EX_ELEM_BLOCK, id, conn.data(), nullptr, nullptr), "the connectivity of block " + std::to_string(id));
    MeshGroup block{f.name(EX_ELEM_BLOCK, id), id, {}};
    if (cell_dimension(cell) != dimension) {
      if (cell_dimension(cell) > dimension) {
        throw MeshError(path + ": block " + block.name + " holds " + cell_type_name(cell) + " elements in a " +
                        std::to_string(dimension) + "-D deck");
      }
      continue;  // surface elements in a 3-D mesh: not particles
    }
    std::vector<double> sphere_volume;
    if (cell == CellType::sphere) sphere_volume = sphere_volumes(f, id, n, nattr, block.name);
    for (int e = 0; e < n; ++e) {
      if (cell == CellType::sphere) {
        m.measure.resize(m.cell_nodes.size() + 1, 0.0);
        m.measure.back() = sphere_volume[static_cast<std::size_t>(e)];
      }
      std::vector<uint32_t> nodes(static_cast<std::size_t>(npe));
      for (int k = 0; k < npe; ++k) {
        const int node = conn[static_cast<std::size_t>(e) * npe + k];
        if (node < 1 || node > nnodes) throw MeshError(path + ": block " + block.name + " names node " + std::to_string(node) + " of " + std::to_string(nnodes));
        nodes[static_cast<std::size_t>(k)] = static_cast<uint32_t>(node - 1);
      }
      block.members.push_back(static_cast<uint32_t>(m.cell_nodes.size()));
      if (cell_ids) {
        const std::size_t k = block_first + static_cast<std::size_t>(e);
        if (k >= elem_map.size()) throw MeshError(path + ": more elements in its blocks than its header counts");
        cell_ids->push_back(elem_map[k]);
      }
      m.cell_type.push_back(cell);
      m.cell_nodes.push_back(std::move(nodes));
    }
    m.blocks.push_back(std::move(block));
  }
  if (m.cell_nodes.empty()) throw MeshError(path + ": no " + std::to_string(dimension) + "-D elements");

  auto read_sets = [&](ex_entity_type type, int count) {
    if (count == 0) return;
    std::vector<int> set_ids(static_cast<std::size_t>(count));
    f.check(ex_get_ids(f.id(), type, set_ids.data()), "the set ids");
    for (int id : set_ids) {
      MeshGroup g{f.name(type, id), id, {}};
      std::vector<int> nodes;
      if (type == EX_NODE_SET) {
        int n = 0, ndf = 0;
        f.check(ex_get_set_param(f.id(), type, id, &n, &ndf), "node set " + std::to_string(id));
        nodes.resize(static_cast<std::size_t>(n));
        if (n > 0) f.check(ex_get_set(f.id(), type, id, nodes.data(), nullptr), "node set " + std::to_string(id));
      } else {
        int n = 0, ndf = 0, len = 0;
        f.check(ex_get_set_param(f.id(), type, id, &n, &ndf), "side set " + std::to_string(id));
        f.check(ex_get_side_set_node_list_len(f.id(), id, &len), "side set " + std::to_string(id));
        std::vector<int> counts(static_cast<std::size_t>(n));
        nodes.resize(static_cast<std::size_t>(len));
        if (n > 0) f.check(ex_get_side_set_node_list(f.id(), id, counts.data(), nodes.data()), "side set " + std::to_string(id));
      }
      for (int node : nodes) {
        if (node < 1 || node > nnodes) throw MeshError(path + ": set " + g.name + " names node " + std::to_string(node));
        g.members.push_back(static_cast<uint32_t>(node - 1));
      }
      m.sets.push_back(std::move(g));
    }
  };
  read_sets(EX_NODE_SET, nns);
  m.node_sets = m.sets.size();
  read_sets(EX_SIDE_SET, nss);
  finish(m);
  return m;
}

}  // namespace

Mesh read_exodus(const std::string& path, int dimension) { return read_exodus_with_ids(path, dimension, nullptr, nullptr); }

std::vector<std::string> exodus_pieces(const std::string& path) {
  namespace fs = std::filesystem;
  const fs::path base(path);
  const fs::path dir = base.has_parent_path() ? base.parent_path() : fs::path(".");
  const std::string stem = base.filename().string() + ".";
  std::map<int, std::set<int>> found;  // N -> the i of the pieces present
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.size() <= stem.size() || name.compare(0, stem.size(), stem) != 0) continue;
    const std::string tail = name.substr(stem.size());  // "N.i"
    const auto dot = tail.find('.');
    if (dot == std::string::npos || dot == 0 || dot + 1 == tail.size()) continue;
    const std::string a = tail.substr(0, dot), b = tail.substr(dot + 1);
    auto digits = [](const std::string& w) {
      return w.size() <= 6 && std::all_of(w.begin(), w.end(), [](char c) { return c >= '0' && c <= '9'; });
    };
    if (!digits(a) || !digits(b)) continue;
    found[std::stoi(a)].insert(std::stoi(b));
  }
  for (const auto& [n, pieces] : found) {  // the smallest complete set
    if (n < 1 || static_cast<int>(pieces.size()) != n || *pieces.rbegin() != n - 1) continue;
    std::vector<std::string> out;
    for (int i = 0; i < n; ++i) out.push_back((dir / (stem + std::to_string(n) + "." + std::to_string(i))).string());
    return out;
  }
  return {};
}

Mesh read_exodus_pieces(const std::vector<std::string>& pieces, int dimension) {
  if (pieces.empty()) throw MeshError("no pieces of a partitioned Exodus mesh to read");
  struct Cell {
    CellType type{};
    std::vector<int64_t> nodes;  // global node ids
    double measure = 0;          // sphere cells: their volume attribute
  };
  struct Group {
    std::string name;
    std::set<int64_t> members;  // global ids: elements (blocks) or nodes (sets)
  };
  std::map<int64_t, Vec3> nodes;
  std::map<int64_t, Cell> cells;
  std::map<int64_t, Group> blocks, node_sets, side_sets;
  for (const auto& piece : pieces) {
    std::vector<int64_t> nid, cid;
    const Mesh m = read_exodus_with_ids(piece, dimension, &nid, &cid);
    for (std::size_t k = 0; k < m.nodes.size(); ++k) {
      const auto [it, fresh] = nodes.emplace(nid[k], m.nodes[k]);
      // A node on the border of two pieces is in both, at one place.
      if (!fresh && norm(it->second - m.nodes[k]) > 1e-12 * (1 + norm(m.nodes[k])))
        throw MeshError(piece + ": node " + std::to_string(nid[k]) + " is at another place than in " + pieces[0] +
                        "'s set of pieces (the pieces are not of one mesh)");
    }
    for (const auto& b : m.blocks) {
      Group& g = blocks[b.id];
      if (g.name.empty()) g.name = b.name;
      for (uint32_t c : b.members) {
        Cell cell{m.cell_type[c], {}, m.measure[c]};
        for (uint32_t k : m.cell_nodes[c]) cell.nodes.push_back(nid[k]);
        if (!cells.emplace(cid[c], std::move(cell)).second)
          throw MeshError(piece + ": element " + std::to_string(cid[c]) + " is in two pieces");
        g.members.insert(cid[c]);
      }
    }
    for (std::size_t s = 0; s < m.sets.size(); ++s) {
      Group& g = (s < m.node_sets ? node_sets : side_sets)[m.sets[s].id];
      if (g.name.empty()) g.name = m.sets[s].name;
      for (uint32_t k : m.sets[s].members) g.members.insert(nid[k]);
    }
  }
  // Nodes and elements in the order of their global ids (Peridigm's element ids).
  Mesh out;
  out.file = pieces[0];
  out.dimension = dimension;
  std::map<int64_t, uint32_t> node_index, cell_index;
  for (const auto& [id, x] : nodes) {
    node_index[id] = static_cast<uint32_t>(out.nodes.size());
    out.nodes.push_back(x);
  }
  for (const auto& [id, c] : cells) {
    cell_index[id] = static_cast<uint32_t>(out.cell_nodes.size());
    std::vector<uint32_t> conn;
    for (int64_t n : c.nodes) conn.push_back(node_index.at(n));
    out.cell_type.push_back(c.type);
    out.cell_nodes.push_back(std::move(conn));
    out.cell_tag.push_back(id);
    out.measure.push_back(c.type == CellType::sphere ? c.measure : 0.0);
  }
  for (const auto& [id, g] : blocks) {
    MeshGroup b{g.name, id, {}};
    for (int64_t c : g.members) b.members.push_back(cell_index.at(c));
    std::sort(b.members.begin(), b.members.end());
    out.blocks.push_back(std::move(b));
  }
  auto add_sets = [&](const std::map<int64_t, Group>& sets) {
    for (const auto& [id, g] : sets) {
      MeshGroup s{g.name, id, {}};
      for (int64_t n : g.members) s.members.push_back(node_index.at(n));
      out.sets.push_back(std::move(s));
    }
  };
  add_sets(node_sets);
  out.node_sets = out.sets.size();
  add_sets(side_sets);
  finish(out);
  return out;
}

std::vector<std::vector<Vec3>> read_exodus_surface(const std::string& path) {
  ExodusFile f(path);
  char title[MAX_LINE_LENGTH + 1] = {0};
  int ndim = 0, nnodes = 0, nelem = 0, nblk = 0, nns = 0, nss = 0;
  f.check(ex_get_init(f.id(), title, &ndim, &nnodes, &nelem, &nblk, &nns, &nss), "the header");
  if (ndim != 3) throw MeshError(path + ": a crack surface must be a 3-D mesh, found a " + std::to_string(ndim) + "-D one");
  std::vector<double> x(static_cast<std::size_t>(nnodes)), y(x.size()), z(x.size());
  f.check(ex_get_coord(f.id(), x.data(), y.data(), z.data()), "the coordinates");
  std::vector<int> ids(static_cast<std::size_t>(nblk));
  if (nblk > 0) f.check(ex_get_ids(f.id(), EX_ELEM_BLOCK, ids.data()), "the element block ids");
  std::vector<std::vector<Vec3>> facets;
  for (int id : ids) {
    char type[MAX_STR_LENGTH + 1] = {0};
    int n = 0, npe = 0, nedge = 0, nface = 0, nattr = 0;
    f.check(ex_get_block(f.id(), EX_ELEM_BLOCK, id, type, &n, &npe, &nedge, &nface, &nattr), "element block " + std::to_string(id));
    std::string t = type;
    for (auto& ch : t) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
    const bool surface = ((t.rfind("TRI", 0) == 0 || t.rfind("QUAD", 0) == 0 || t.rfind("SHELL", 0) == 0) &&
                          (npe == 3 || npe == 4));
    if (!surface || n == 0) continue;
    std::vector<int> conn(static_cast<std::size_t>(n) * static_cast<std::size_t>(npe));
    f.check(ex_get_conn(f.id(), EX_ELEM_BLOCK, id, conn.data(), nullptr, nullptr), "the connectivity of block " + std::to_string(id));
    for (int e = 0; e < n; ++e) {
      std::vector<Vec3> poly;
      for (int k = 0; k < npe; ++k) {
        const int node = conn[static_cast<std::size_t>(e) * npe + k];
        if (node < 1 || node > nnodes) throw MeshError(path + ": block " + std::to_string(id) + " names node " + std::to_string(node) + " of " + std::to_string(nnodes));
        const auto i = static_cast<std::size_t>(node - 1);
        poly.push_back({x[i], y[i], z[i]});
      }
      facets.push_back(std::move(poly));
    }
  }
  if (facets.empty()) throw MeshError(path + ": no surface elements (TRI3, QUAD4, SHELL3, SHELL4)");
  return facets;
}

Mesh read_mesh(const std::string& path, int dimension) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (auto& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  if (ext == ".msh") return read_gmsh(path, dimension);
  if (ext == ".exo" || ext == ".e" || ext == ".g" || ext == ".ex2" || ext == ".exii") return read_exodus(path, dimension);
  throw MeshError("mesh '" + path + "': unknown extension '" + ext + "' (.msh for Gmsh; .exo, .e, .g, .ex2 for Exodus II)");
}

}  // namespace horizon
