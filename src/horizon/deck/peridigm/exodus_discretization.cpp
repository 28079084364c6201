#include "horizon/deck/peridigm/exodus_discretization.hpp"
#include "horizon/deck/peridigm/sections.hpp"

#include <cmath>
#include <filesystem>

#include "horizon/geometry/mesh.hpp"

namespace horizon::peridigm {

namespace {

// A tetrahedron's volume a . (b x c) / 6 with a, b, c its edges from p0, the triple product
// summed in that order (the rounding Peridigm's golds hold; |.| for a node order that
// turns it inside out).
double tet_volume(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& p3) {
  const Vec3 a = p1 - p0, b = p2 - p0, c = p3 - p0;
  return std::abs((a.x * (b.y * c.z - b.z * c.y) + a.y * (b.z * c.x - b.x * c.z) + a.z * (b.x * c.y - b.y * c.x)) / 6.0);
}

struct CellPoint {
  Vec3 centre;
  double volume;
};

// Peridigm's particle of a hexahedron (its users' guide: "the volume and centroid of each
// element"; the rule is Peridigm's GeometryUtils, read for the formula): each face is
// split into four triangles joining consecutive face nodes to the face's barycentre
// (the mean of its four nodes), each triangle makes a tetrahedron with the hexahedron's
// centre (the mean of the barycentres of faces 0123 and 4567), and the particle sits at
// the volume-weighted mean of the 24 tetrahedra's centroids with their summed volume.
// The order of the faces, of the triangles and of each sum is part of the rule: the
// golds hold the coordinates that follow to the last bit (DeformationGradient,
// ElasticPlasticCorrespondenceFullyPrescribedTension: all 27 and 384 centres), and the
// velocities their prescribed displacements give differ by 30 ulps when one coordinate
// is an ulp off (docs/peridigm.md "Round-off"). The volume is the trilinear element's.
CellPoint peridigm_hex_point(const std::vector<Vec3>& x, const std::vector<uint32_t>& n) {
  // Per face: its nodes (the barycentre's sum order) and its four triangles' edges, each
  // tetrahedron's vertices in the order (edge start, edge end, barycentre, centre).
  struct Face {
    int nodes[4];
    int edges[4][2];
  };
  static constexpr Face faces[6] = {{{0, 1, 4, 5}, {{1, 0}, {5, 1}, {4, 5}, {0, 4}}},
                                    {{1, 2, 5, 6}, {{2, 1}, {6, 2}, {5, 6}, {1, 5}}},
                                    {{2, 3, 6, 7}, {{3, 2}, {7, 3}, {6, 7}, {2, 6}}},
                                    {{0, 3, 4, 7}, {{0, 3}, {3, 7}, {7, 4}, {4, 0}}},
                                    {{0, 1, 2, 3}, {{0, 1}, {1, 2}, {2, 3}, {3, 0}}},
                                    {{4, 5, 6, 7}, {{5, 4}, {4, 7}, {7, 6}, {6, 5}}}};
  auto node = [&](int k) -> const Vec3& { return x[n[static_cast<std::size_t>(k)]]; };
  Vec3 bary[6];
  for (int f = 0; f < 6; ++f) {
    const int* q = faces[f].nodes;
    bary[f] = (node(q[0]) + node(q[1]) + node(q[2]) + node(q[3])) * 0.25;
  }
  const Vec3 centre = (bary[4] + bary[5]) * 0.5;
  double volume = 0;
  Vec3 moment{};
  for (int f = 0; f < 6; ++f)
    for (const auto& e : faces[f].edges) {
      const Vec3 &p0 = node(e[0]), &p1 = node(e[1]);
      const double v = tet_volume(p0, p1, bary[f], centre);
      volume += v;
      moment += (p0 + p1 + bary[f] + centre) * 0.25 * v;
    }
  // Divided component by component (Vec3's division multiplies by 1/volume).
  return {volume > 0 ? Vec3{moment.x / volume, moment.y / volume, moment.z / volume} : centre, volume};
}

}  // namespace

ExodusDiscretization read_exodus_discretization(const deck::DeckContext& ctx, const deck::Item& file_item,
                                                const std::string& folder) {
  const std::string name = deck::read_string(ctx, file_item);
  const auto candidates = deck_file_candidates(folder, name);
  std::filesystem::path path = resolve_deck_file(folder, name);
  Mesh mesh;
  try {
    std::error_code ec;
    std::vector<std::string> pieces;
    if (!std::filesystem::exists(path, ec)) {
      // No serial mesh anywhere: Peridigm's partitioned copies (np4/mesh.g.4.0..3), which
      // Horizon merges and splits over its own ranks.
      for (const auto& c : candidates)
        if (pieces.empty()) pieces = exodus_pieces(c);
    }
    if (!pieces.empty()) {
      mesh = read_exodus_pieces(pieces, 3);
    } else {
      if (!std::filesystem::exists(path, ec)) {
        std::string looked;
        for (const auto& c : candidates) looked += (looked.empty() ? "" : ", ") + c;
        ctx.fail(file_item.mark, file_item.path + ": cannot open mesh '" + name + "': no such file, nor its partitioned "
                                 "pieces '" + name + ".N.i' (looked for " + looked + ")");
      }
      mesh = read_exodus(path.string(), 3);
    }
  } catch (const MeshError& e) {
    ctx.fail(file_item.mark, file_item.path + ": " + e.what());
  }
  ExodusDiscretization out;
  std::vector<int> block_of(mesh.cell_nodes.size(), 0);
  for (const auto& b : mesh.blocks) {
    for (uint32_t c : b.members) block_of[c] = static_cast<int>(b.id);
    // The mesh reader names a block without a name by its id.
    if (b.name != std::to_string(b.id) && b.name != "block_" + std::to_string(b.id))
      out.block_names[b.name] = static_cast<int>(b.id);
  }
  for (std::size_t c = 0; c < mesh.cell_nodes.size(); ++c) {
    if (block_of[c] < 1)
      ctx.fail(file_item.mark, file_item.path + ": " + path.string() + ": element block ids must be >= 1 to name "
                                                                       "Peridigm's block_<id>");
    // Hexahedra and tetrahedra as Peridigm places and weighs them (the same volumes as
    // geometry/mesh.cpp's to round-off; these are the golds' bits); spheres carry theirs.
    const auto& nodes = mesh.cell_nodes[c];
    if (mesh.cell_type[c] == CellType::hex8) {
      const CellPoint p = peridigm_hex_point(mesh.nodes, nodes);
      out.points.push_back({p.centre, p.volume, block_of[c]});
    } else if (mesh.cell_type[c] == CellType::tet4) {
      const Vec3 &a = mesh.nodes[nodes[0]], &b = mesh.nodes[nodes[1]], &d = mesh.nodes[nodes[2]], &e = mesh.nodes[nodes[3]];
      out.points.push_back({(a + b + d + e) * 0.25, tet_volume(a, b, d, e), block_of[c]});
    } else {
      out.points.push_back({mesh.centroid[c], mesh.measure[c], block_of[c]});
    }
  }
  for (std::size_t s = 0; s < mesh.node_sets; ++s) {
    const MeshGroup& set = mesh.sets[s];
    std::vector<int> ids;
    for (uint32_t c : mesh.cells_touching(set)) ids.push_back(static_cast<int>(c) + 1);
    if (set.name != std::to_string(set.id)) out.node_sets[set.name] = ids;
    out.node_sets["nodelist_" + std::to_string(set.id)] = std::move(ids);
  }
  return out;
}

}  // namespace horizon::peridigm
