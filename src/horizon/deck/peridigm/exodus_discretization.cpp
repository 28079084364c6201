#include "horizon/deck/peridigm/exodus_discretization.hpp"
#include "horizon/deck/peridigm/sections.hpp"

#include <cmath>
#include <filesystem>

#include "horizon/geometry/mesh.hpp"

namespace horizon::peridigm {

namespace {

// Peridigm's centre of a hexahedron: the volume-weighted centre of the 24 tetrahedra
// that join each face's triangles (its edges and the mean of its four nodes) to the mean
// of the eight nodes. Inferred from Peridigm's golds, not its code: on the distorted
// hexahedra of its CentrifugalLoad mesh this rule gives the gold's coordinates to 9e-15,
// while the exact centre of volume (geometry/mesh.cpp) is up to 2e-6 away. The volume
// of this split is the trilinear element's exact volume (a bilinear face encloses what
// its four triangles through the face's mean node do), so the volume is mesh.cpp's.
Vec3 peridigm_hex_centre(const std::vector<Vec3>& x, const std::vector<uint32_t>& n) {
  static constexpr int faces[6][4] = {{0, 1, 2, 3}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  Vec3 centre{};
  for (uint32_t k : n) centre += x[k];
  centre = centre / 8.0;
  double volume = 0;
  Vec3 moment{};
  for (const auto& f : faces) {
    const Vec3 fc = (x[n[f[0]]] + x[n[f[1]]] + x[n[f[2]]] + x[n[f[3]]]) / 4.0;
    for (int k = 0; k < 4; ++k) {
      const Vec3& a = x[n[f[k]]];
      const Vec3& b = x[n[f[(k + 1) % 4]]];
      const double v = std::abs(dot(a - centre, cross(b - centre, fc - centre))) / 6.0;
      volume += v;
      moment += (a + b + fc + centre) * (v / 4.0);
    }
  }
  return volume > 0 ? moment / volume : centre;
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
    const Vec3 x = mesh.cell_type[c] == CellType::hex8 ? peridigm_hex_centre(mesh.nodes, mesh.cell_nodes[c])
                                                        : mesh.centroid[c];
    out.points.push_back({x, mesh.measure[c], block_of[c]});
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
