#include "horizon/deck/peridigm/exodus_discretization.hpp"

#include <filesystem>

#include "horizon/geometry/mesh.hpp"

namespace horizon::peridigm {

ExodusDiscretization read_exodus_discretization(const deck::DeckContext& ctx, const deck::Item& file_item,
                                                const std::string& folder) {
  const std::string name = deck::read_string(ctx, file_item);
  std::filesystem::path path = name;
  if (path.is_relative()) path = std::filesystem::path(folder) / path;
  Mesh mesh;
  try {
    mesh = read_exodus(path.string(), 3);
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
    out.points.push_back({mesh.centroid[c], mesh.measure[c], block_of[c]});
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
