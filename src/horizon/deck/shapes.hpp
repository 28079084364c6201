#pragma once
// Shapes in the deck: a map with one key naming the kind (box, cylinder, disk, sphere,
// half_space, union, subtract). Used by bodies and regions.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "horizon/deck/reader.hpp"
#include "horizon/geometry/shape.hpp"

namespace horizon::deck {

Shape read_shape(const DeckContext& ctx, const Item& item);

// What a shape {mesh: {file, block | set, scale}} takes from its mesh file: the mesh, the
// chosen cells, the scale on its coordinates; the set when the shape names one.
struct MeshSelection {
  std::shared_ptr<const Mesh> mesh;
  std::string file;  // the mesh file's path as read
  std::vector<uint32_t> cells;
  double scale = 1;
  const MeshGroup* set = nullptr;
  YAML::Mark mark;   // of the mesh map, for messages
  std::string path;  // its key path
};
// The selection of a shape item that is {mesh: {...}} (read as read_shape reads it, the
// file read once per deck), or nullopt for any other shape.
std::optional<MeshSelection> read_mesh_selection(const DeckContext& ctx, const Item& item);

// A body needs a finite box to lay its lattice in: fails when the shape reaches to
// infinity along an axis of the deck (a half space, or a union containing one).
void check_bounded(const DeckContext& ctx, const Item& item, const Shape& shape);

}  // namespace horizon::deck
