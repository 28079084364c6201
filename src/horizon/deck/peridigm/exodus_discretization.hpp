#pragma once
// Peridigm's `Discretization: Type: Exodus` (Peridigm Users' Guide, SAND2012-7800,
// "Discretization"): each element of the serial Exodus mesh becomes one particle at its
// centre carrying the element's volume (hex8, tet4, ...: geometry/mesh.hpp; a hex8's
// centre by Peridigm's rule, exodus_discretization.cpp; SPHERE elements: at the node, with
// the volume attribute); element block <id> is Peridigm's `block_<id>`;
// a node set is the particles whose element holds any of its nodes, named by its name in
// the mesh or, without one, `nodelist_<id>`. Horizon splits the particles over its MPI
// ranks itself, so Peridigm's partitioned copies (.g.N.i) are never read.
#include <map>
#include <string>
#include <vector>

#include "horizon/core/vec3.hpp"
#include "horizon/deck/reader.hpp"

namespace horizon::peridigm {

struct ExodusDiscretization {
  struct Point {
    Vec3 x;
    double volume = 0;
    int block = 1;  // the element block's id
  };
  std::vector<Point> points;  // element order (Peridigm's global ids: index + 1)
  // Node sets by name (nodelist_<id>, and the mesh's own name where it has one): the
  // 1-based ids of the particles whose element holds a node of the set.
  std::map<std::string, std::vector<int>> node_sets;
  // Element blocks by their name in the mesh, where they have one: block id.
  std::map<std::string, int> block_names;
};

// Reads the mesh named by `file_item` (relative to `folder`); a mesh that cannot be read
// is an error at the item's line and column naming the mesh's own problem.
ExodusDiscretization read_exodus_discretization(const deck::DeckContext& ctx, const deck::Item& file_item,
                                                const std::string& folder);

}  // namespace horizon::peridigm
