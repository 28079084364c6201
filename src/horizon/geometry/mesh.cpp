#include "horizon/geometry/mesh.hpp"

#include <exodusII.h>

#include <algorithm>
#include <array>
#include <cctype>
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
      throw MeshError(m.file + ": element " + std::to_string(e + 1) + " (" + cell_type_name(m.cell_type[e]) +
                      ") has no " + (m.dimension == 3 ? "volume" : "area") + " (degenerate or collapsed nodes)");
    }
  }
  for (auto& s : m.sets) {
    std::sort(s.members.begin(), s.members.end());
    s.members.erase(std::unique(s.members.begin(), s.members.end()), s.members.end());
  }
}

// ---------------------------------------------------------------- Gmsh MSH 4.1

// Gmsh element types (reference manual sec. 10.2 "MSH file format", element types):
// number of nodes, dimension and name; the linear volume/area ones map to cells.
struct GmshType {
  int nodes;
  int dim;
  const char* name;
};
const std::map<int, GmshType>& gmsh_types() {
  static const std::map<int, GmshType> t = {
      {1, {2, 1, "2-node line"}},          {2, {3, 2, "3-node triangle"}},       {3, {4, 2, "4-node quadrangle"}},
      {4, {4, 3, "4-node tetrahedron"}},   {5, {8, 3, "8-node hexahedron"}},     {6, {6, 3, "6-node prism"}},
      {7, {5, 3, "5-node pyramid"}},       {8, {3, 1, "3-node line"}},           {9, {6, 2, "6-node triangle"}},
      {10, {9, 2, "9-node quadrangle"}},   {11, {10, 3, "10-node tetrahedron"}}, {12, {27, 3, "27-node hexahedron"}},
      {13, {18, 3, "18-node prism"}},      {14, {14, 3, "14-node pyramid"}},     {15, {1, 0, "1-node point"}},
      {16, {8, 2, "8-node quadrangle"}},   {17, {20, 3, "20-node hexahedron"}},  {18, {15, 3, "15-node prism"}},
      {19, {13, 3, "13-node pyramid"}}};
  return t;
}
bool gmsh_cell(int type, CellType& out) {
  switch (type) {
    case 2: out = CellType::tri3; return true;
    case 3: out = CellType::quad4; return true;
    case 4: out = CellType::tet4; return true;
    case 5: out = CellType::hex8; return true;
    case 6: out = CellType::wedge6; return true;
    case 7: out = CellType::pyramid5; return true;
    default: return false;
  }
}

// Reads ASCII tokens (tracking lines) or binary values, the same calls for both.
class MshSource {
 public:
  MshSource(std::string path, std::string text) : path_(std::move(path)), text_(std::move(text)) {}

  [[noreturn]] void fail(const std::string& message) const {
    if (binary_) throw MeshError(path_ + ": byte " + std::to_string(pos_) + ": " + message);
    throw MeshError(path_ + ":" + std::to_string(line_) + ": " + message);
  }
  int line() const { return line_; }
  bool at_end() {
    skip_space();
    return pos_ >= text_.size();
  }
  void set_binary(bool b) { binary_ = b; }

  // The next whitespace-delimited word (ASCII headers and section names).
  std::string word() {
    skip_space();
    if (pos_ >= text_.size()) fail("unexpected end of file");
    const std::size_t start = pos_;
    while (pos_ < text_.size() && !std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
    return text_.substr(start, pos_ - start);
  }
  // The rest of the current line (a quoted name).
  std::string rest_of_line() {
    const std::size_t start = pos_;
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
    return text_.substr(start, pos_ - start);
  }
  // Exactly one line end (before binary data, where whitespace skipping could eat data).
  void newline() {
    if (pos_ < text_.size() && text_[pos_] == '\r') ++pos_;
    if (pos_ >= text_.size() || text_[pos_] != '\n') fail("expected the end of the line");
    ++pos_;
    ++line_;
  }
  // After a binary block, the newline before the $End marker.
  void end_line() {
    while (pos_ < text_.size() && (text_[pos_] == '\n' || text_[pos_] == '\r' || text_[pos_] == ' ')) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
  }

  int64_t integer(const char* what) {
    if (binary_) {
      int32_t v;
      raw(&v, sizeof v, what);
      return v;
    }
    return parse_integer(word(), what);
  }
  int64_t size(const char* what) {
    if (binary_) {
      uint64_t v;
      raw(&v, sizeof v, what);
      if (v > (uint64_t{1} << 40)) fail(std::string("implausible ") + what + " " + std::to_string(v));
      return static_cast<int64_t>(v);
    }
    const int64_t v = parse_integer(word(), what);
    if (v < 0) fail(std::string("expected a count for ") + what + ", found " + std::to_string(v));
    return v;
  }
  double real(const char* what) {
    if (binary_) {
      double v;
      raw(&v, sizeof v, what);
      return v;
    }
    const std::string w = word();
    char* end = nullptr;
    const double v = std::strtod(w.c_str(), &end);
    if (end != w.c_str() + w.size() || !std::isfinite(v)) fail(std::string("expected a number for ") + what + ", found '" + w + "'");
    return v;
  }
  void expect(const std::string& marker) {
    const std::string w = word();
    if (w != marker) fail("expected " + marker + ", found '" + w.substr(0, 40) + "'");
  }

 private:
  void skip_space() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
  }
  int64_t parse_integer(const std::string& w, const char* what) const {
    char* end = nullptr;
    const long long v = std::strtoll(w.c_str(), &end, 10);
    if (w.empty() || end != w.c_str() + w.size()) fail(std::string("expected a whole number for ") + what + ", found '" + w.substr(0, 40) + "'");
    return v;
  }
  void raw(void* out, std::size_t n, const char* what) {
    if (pos_ + n > text_.size()) fail(std::string("unexpected end of file reading ") + what);
    std::memcpy(out, text_.data() + pos_, n);
    pos_ += n;
  }

  std::string path_;
  std::string text_;
  std::size_t pos_ = 0;
  int line_ = 1;
  bool binary_ = false;
};

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw MeshError("cannot open mesh '" + path + "': " + std::strerror(errno));
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

const MeshGroup* Mesh::find_block(const std::string& key) const { return find_group(blocks, key); }
const MeshGroup* Mesh::find_set(const std::string& key) const { return find_group(sets, key); }

Mesh read_gmsh(const std::string& path, int dimension) {
  MshSource in(path, read_file(path));
  Mesh m;
  m.file = path;
  m.dimension = dimension;
  std::map<std::pair<int, int64_t>, std::string> physical_names;           // (dim, tag) -> name
  std::map<std::pair<int, int64_t>, std::vector<int64_t>> entity_physicals;  // (dim, entity) -> physical tags
  std::unordered_map<int64_t, uint32_t> node_index;
  std::map<int64_t, std::vector<uint32_t>> block_cells;                   // physical tag -> cells
  std::map<std::pair<int, int64_t>, std::vector<uint32_t>> set_nodes;      // (dim, physical tag) -> nodes
  bool binary_file = false;
  bool have_format = false, have_nodes = false, have_elements = false;
  std::set<std::string> skipped_types;

  while (!in.at_end()) {
    const std::string section = in.word();
    if (section.size() < 2 || section[0] != '$') in.fail("expected a section such as $MeshFormat, found '" + section.substr(0, 40) + "'");
    const std::string name = section.substr(1);
    const std::string end = "$End" + name;
    if (name == "MeshFormat") {
      const std::string version = in.word();
      if (version != "4.1") {
        in.fail("MSH format version " + version +
                " is not supported; Horizon reads version 4.1 (Gmsh: -format msh41, or Mesh.MshFileVersion = 4.1)");
      }
      const int64_t file_type = in.integer("the file type");
      const int64_t data_size = in.integer("the data size");
      if (file_type != 0 && file_type != 1) in.fail("file type must be 0 (ASCII) or 1 (binary), found " + std::to_string(file_type));
      if (data_size != 8) in.fail("data size must be 8, found " + std::to_string(data_size));
      if (file_type == 1) {
        in.newline();  // exactly one newline precedes the binary one
        binary_file = true;
        in.set_binary(true);
        if (in.integer("the endianness check") != 1) in.fail("binary mesh of the other byte order");
        in.set_binary(false);
        in.end_line();
      }
      in.expect(end);
      have_format = true;
      continue;
    }
    if (!have_format) in.fail("the file must start with $MeshFormat (is this a Gmsh .msh file?)");
    if (name == "PhysicalNames") {
      const int64_t n = in.size("the number of physical names");
      for (int64_t i = 0; i < n; ++i) {
        const int dim = static_cast<int>(in.integer("a physical group's dimension"));
        const int64_t tag = in.integer("a physical group's tag");
        std::string rest = in.rest_of_line();
        const auto a = rest.find('"'), b = rest.rfind('"');
        if (a == std::string::npos || b == a) in.fail("expected a quoted physical name");
        physical_names[{dim, tag}] = rest.substr(a + 1, b - a - 1);
      }
      in.expect(end);
      continue;
    }
    // The sections below are binary in a binary file.
    const bool is_binary_section = name == "Entities" || name == "Nodes" || name == "Elements";
    if (!is_binary_section) {
      // Sections Horizon does not use ($PartitionedEntities, $NodeData, ...): skip.
      while (in.word() != end) {
      }
      continue;
    }
    auto read_section = [&](auto&& body) {
      if (binary_file) {
        in.newline();
        in.set_binary(true);
      }
      body();
      in.set_binary(false);
      in.end_line();
      in.expect(end);
    };
    if (name == "Entities") {
      read_section([&] {
        int64_t count[4];
        for (auto& c : count) c = in.size("the number of entities");
        for (int dim = 0; dim < 4; ++dim) {
          for (int64_t e = 0; e < count[dim]; ++e) {
            const int64_t tag = in.integer("an entity tag");
            for (int k = 0; k < (dim == 0 ? 3 : 6); ++k) in.real("an entity's bounding box");
            const int64_t nphys = in.size("the number of physical tags");
            auto& phys = entity_physicals[{dim, tag}];
            for (int64_t p = 0; p < nphys; ++p) phys.push_back(in.integer("a physical tag"));
            if (dim > 0) {
              const int64_t nb = in.size("the number of bounding entities");
              for (int64_t b = 0; b < nb; ++b) in.integer("a bounding entity");
            }
          }
        }
      });
      continue;
    }
    if (name == "Nodes") {
      read_section([&] {
        const int64_t blocks = in.size("the number of node blocks");
        const int64_t total = in.size("the number of nodes");
        in.size("the smallest node tag");
        in.size("the largest node tag");
        m.nodes.reserve(static_cast<std::size_t>(total));
        for (int64_t b = 0; b < blocks; ++b) {
          in.integer("a node block's dimension");
          in.integer("a node block's entity");
          const int64_t parametric = in.integer("the parametric flag");
          const int64_t n = in.size("the number of nodes in a block");
          std::vector<int64_t> tags(static_cast<std::size_t>(n));
          for (auto& t : tags) t = in.size("a node tag");
          for (int64_t i = 0; i < n; ++i) {
            Vec3 x;
            x.x = in.real("a node coordinate");
            x.y = in.real("a node coordinate");
            x.z = in.real("a node coordinate");
            for (int64_t p = 0; p < parametric; ++p) in.real("a parametric coordinate");
            if (!node_index.emplace(tags[static_cast<std::size_t>(i)], static_cast<uint32_t>(m.nodes.size())).second)
              in.fail("node " + std::to_string(tags[static_cast<std::size_t>(i)]) + " appears twice");
            m.nodes.push_back(x);
          }
        }
        if (static_cast<int64_t>(m.nodes.size()) != total)
          in.fail("the $Nodes header counts " + std::to_string(total) + " nodes, the blocks hold " + std::to_string(m.nodes.size()));
      });
      have_nodes = true;
      continue;
    }
    // $Elements
    if (!have_nodes) in.fail("$Elements before $Nodes");
    read_section([&] {
      const int64_t blocks = in.size("the number of element blocks");
      in.size("the number of elements");
      in.size("the smallest element tag");
      in.size("the largest element tag");
      std::vector<uint32_t> nodes;
      for (int64_t b = 0; b < blocks; ++b) {
        const int dim = static_cast<int>(in.integer("an element block's dimension"));
        const int64_t entity = in.integer("an element block's entity");
        const int64_t type = in.integer("an element type");
        const int64_t n = in.size("the number of elements in a block");
        const auto t = gmsh_types().find(static_cast<int>(type));
        if (t == gmsh_types().end()) in.fail("element type " + std::to_string(type) + " is not supported");
        CellType cell{};
        const bool is_cell = dim == dimension && gmsh_cell(static_cast<int>(type), cell);
        if (dim > dimension) {
          in.fail(std::string(t->second.name) + " elements in a " + std::to_string(dimension) +
                  "-D deck (a 2-D deck reads triangles and quadrangles)");
        }
        if (dim == dimension && !is_cell) {
          in.fail(std::string(t->second.name) + " elements are not supported: Horizon reads linear elements (triangles, quadrangles, tetrahedra, hexahedra, prisms, "
                  "pyramids); mesh with Mesh.ElementOrder = 1");
        }
        const auto phys_it = entity_physicals.find({dim, entity});
        static const std::vector<int64_t> kNone;
        const std::vector<int64_t>& phys = phys_it == entity_physicals.end() ? kNone : phys_it->second;
        for (int64_t e = 0; e < n; ++e) {
          in.size("an element tag");
          nodes.clear();
          for (int k = 0; k < t->second.nodes; ++k) {
            const int64_t tag = in.size("an element's node");
            const auto it = node_index.find(tag);
            if (it == node_index.end()) in.fail("element names node " + std::to_string(tag) + ", which $Nodes does not define");
            nodes.push_back(it->second);
          }
          if (is_cell) {
            const auto idx = static_cast<uint32_t>(m.cell_nodes.size());
            m.cell_type.push_back(cell);
            m.cell_nodes.push_back(nodes);
            for (int64_t p : phys) block_cells[p].push_back(idx);
          } else {
            for (int64_t p : phys) {
              auto& s = set_nodes[{dim, p}];
              s.insert(s.end(), nodes.begin(), nodes.end());
            }
          }
        }
      }
    });
    have_elements = true;
  }
  if (!have_format) throw MeshError(path + ": empty file (expected a Gmsh .msh file starting with $MeshFormat)");
  if (!have_elements) throw MeshError(path + ": no $Elements section");
  if (m.cell_nodes.empty()) {
    throw MeshError(path + ": no " + std::to_string(dimension) + "-D elements (" +
                    (dimension == 3 ? "tetrahedra, hexahedra, prisms or pyramids" : "triangles or quadrangles") +
                    "); is the mesh " + std::to_string(dimension) + "-D?");
  }
  auto group_name = [&](int dim, int64_t tag) {
    const auto it = physical_names.find({dim, tag});
    return it == physical_names.end() ? std::to_string(tag) : it->second;
  };
  for (auto& [tag, cells] : block_cells) m.blocks.push_back({group_name(dimension, tag), tag, cells});
  if (m.blocks.empty()) {
    MeshGroup all{"all", 0, {}};
    for (uint32_t e = 0; e < m.cell_nodes.size(); ++e) all.members.push_back(e);
    m.blocks.push_back(std::move(all));
  }
  for (auto& [key, nodes] : set_nodes) m.sets.push_back({group_name(key.first, key.second), key.second, nodes});
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

Mesh read_exodus(const std::string& path, int dimension) {
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

  std::vector<int> ids(static_cast<std::size_t>(nblk));
  if (nblk > 0) f.check(ex_get_ids(f.id(), EX_ELEM_BLOCK, ids.data()), "the element block ids");
  for (int id : ids) {
    char type[MAX_STR_LENGTH + 1] = {0};
    int n = 0, npe = 0, nedge = 0, nface = 0, nattr = 0;
    f.check(ex_get_block(f.id(), EX_ELEM_BLOCK, id, type, &n, &npe, &nedge, &nface, &nattr), "element block " + std::to_string(id));
    CellType cell{};
    if (!exodus_cell(type, npe, cell)) {
      throw MeshError(path + ": element block " + std::to_string(id) + " ('" + f.name(EX_ELEM_BLOCK, id) + "') has " +
                      std::to_string(npe) + "-node " + type +
                      " elements, which are not supported: Horizon reads TETRA4, HEX8, WEDGE6, PYRAMID5, SPHERE (3-D), TRI3, QUAD4 (2-D)");
    }
    if (n == 0) continue;
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

Mesh read_mesh(const std::string& path, int dimension) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (auto& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  if (ext == ".msh") return read_gmsh(path, dimension);
  if (ext == ".exo" || ext == ".e" || ext == ".g" || ext == ".ex2" || ext == ".exii") return read_exodus(path, dimension);
  throw MeshError("mesh '" + path + "': unknown extension '" + ext + "' (.msh for Gmsh; .exo, .e, .g, .ex2 for Exodus II)");
}

}  // namespace horizon
