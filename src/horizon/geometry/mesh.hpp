#pragma once
// Meshes as particle sources. A volume element (3-D: tetrahedron, hexahedron, wedge,
// pyramid; 2-D: triangle, quadrangle) becomes one particle at its centre of volume
// carrying the element's volume (area in 2-D) -- the convention of Peridigm's Exodus
// reader (Parks et al., Peridigm Users' Guide, SAND2012-7800, sec. "Mesh input").
// Element blocks (Exodus) or physical groups of the mesh's top dimension (Gmsh) are the
// blocks; node sets, side sets (Exodus) and lower-dimensional physical groups (Gmsh) are
// the sets. docs/input.md ("Meshes") describes the deck side.
#include <cstdint>
#include <string>
#include <vector>

#include "horizon/core/error.hpp"
#include "horizon/core/vec3.hpp"

namespace horizon {

// A mesh file that cannot be read; the message names the file and, where it applies,
// the line ("part.msh:12: ...").
class MeshError : public Error {
 public:
  using Error::Error;
};

// sphere: Exodus's one-node SPHERE element of meshfree meshes (Cubit's "sphere"
// meshes): the particle sits at its node and its volume is an element attribute.
enum class CellType { tri3, quad4, tet4, hex8, wedge6, pyramid5, sphere };

struct MeshGroup {
  std::string name;  // the group's name; its number as text when it has none
  int64_t id = 0;
  std::vector<uint32_t> members;  // cells (blocks) or nodes (sets), ascending
};

struct Mesh {
  std::string file;
  int dimension = 3;  // of the cells: 3 (volumes) or 2 (areas in the xy-plane)
  std::vector<Vec3> nodes;
  std::vector<CellType> cell_type;
  std::vector<std::vector<uint32_t>> cell_nodes;  // indices into nodes
  std::vector<int64_t> cell_tag;                  // the file's element numbers (Gmsh); empty: 1, 2, ...
  std::vector<Vec3> centroid;                     // centre of volume of each cell
  std::vector<double> measure;                    // volume (3-D) or area (2-D) of each cell
  std::vector<MeshGroup> blocks;                  // partition of the cells (or one block of all)
  std::vector<MeshGroup> sets;                    // node sets
  // Exodus: sets[0, node_sets) are its node sets, the rest its side sets (as node lists).
  std::size_t node_sets = 0;

  // The cells with at least one node in the set (the layer of elements touching it).
  std::vector<uint32_t> cells_touching(const MeshGroup& set) const;
  // A block or set by name, or by number written as text; nullptr when none matches.
  const MeshGroup* find_block(const std::string& key) const;
  const MeshGroup* find_set(const std::string& key) const;
};

// Gmsh .msh files of every version Gmsh writes (1, 2.2, 3, 4.0, 4.1; ASCII or binary),
// read by the Gmsh library (geometry/gmsh_library.hpp). `dimension` is the deck's (2 or
// 3): the cells are the elements of that dimension (higher-order ones by their corner
// nodes); the others serve only as sets.
Mesh read_gmsh(const std::string& path, int dimension);
// Throws MeshError unless the file starts as a Gmsh mesh does ($MeshFormat, or $NOD for
// MSH 1): Gmsh runs any other file as a .geo script, whose commands include shell ones.
void check_msh_header(const std::string& path);
// Exodus II through the Exodus library (Debian libexodusii-dev). SPHERE elements take
// their volume from the attribute named "volume", else from the second of two attributes
// (Cubit writes radius, volume), else from a single attribute.
Mesh read_exodus(const std::string& path, int dimension);
// Peridigm's partitioned copies of an Exodus mesh (SEACAS's decomposition: `path.N.i`,
// i = 0..N-1, each a valid Exodus file whose node and element number maps give the global
// ids): the pieces of the smallest N present in full beside `path`, in order of i; empty
// when there are none.
std::vector<std::string> exodus_pieces(const std::string& path);
// The one mesh the pieces make: nodes and elements merged by their global ids and
// ordered by them (a node on the border of two pieces is one node), blocks and node sets
// by their ids, the members of each the union of the pieces'.
Mesh read_exodus_pieces(const std::vector<std::string>& pieces, int dimension);
// The surface elements of an Exodus II mesh (TRI3, QUAD4, SHELL3, SHELL4, TRISHELL3
// blocks; other blocks are skipped) as polygons of their corner nodes, block by block in
// the file's order: a crack surface (Peridigm's `Exodus Mesh` bond filter, whose shell
// meshes are such files). Throws MeshError when the file holds none.
std::vector<std::vector<Vec3>> read_exodus_surface(const std::string& path);
// By extension: .msh is Gmsh; .exo, .e, .g, .ex2, .exii are Exodus.
Mesh read_mesh(const std::string& path, int dimension);

// Volume (or area) and centre of volume of one cell from its node coordinates (not for
// sphere cells, whose volume is not in their node).
void cell_geometry(CellType type, const std::vector<Vec3>& x, double& measure, Vec3& centroid);
const char* cell_type_name(CellType type);

}  // namespace horizon
