#pragma once
// Horizon's one door to the Gmsh library (Debian libgmsh-dev, Gmsh's C API, gmshc.h):
// mesh files (.msh of every version Gmsh writes) and triangulated surfaces (.stl, ...)
// are read by Gmsh itself. docs/design.md ("Mesh input") says why it is reached this way:
//
// - Loaded on first use (dlopen), not linked: libgmsh pulls OpenCASCADE, FLTK and X11
//   (about 90 shared libraries); linked, they would cost every `horizon` process about
//   1 s and 50 MB at start-up, meshes or not (docs/benchmarks.md, "Gmsh").
// - Gmsh's state is global (one set of models and options per process): a Session holds
//   a process-wide lock from gmshInitialize to gmshFinalize, so two threads never share
//   it, and leaves nothing behind for a Python session that imports Gmsh itself. Where
//   such a session is open in the same library (Gmsh >= 4.9 says so), Horizon reads in a
//   model of its own and leaves theirs as it was.
// - gmshInitialize changes process state that Horizon owns: it sets OpenMP's thread
//   count to 1, the locale from the environment and the stack limit to unlimited. The
//   Session restores all three when it ends.
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace horizon::gmsh_library {

// The elements of one type in one entity, as Gmsh's API gives them.
struct ElementBlock {
  int type = 0;           // Gmsh element type number (reference manual, "MSH file format")
  std::string name;       // e.g. "Tetrahedron 10"
  int dim = 0;
  int order = 1;
  int nodes_per_element = 0;
  int primary_nodes = 0;  // corner nodes, listed first in each element's nodes
  std::vector<std::size_t> tags;   // element tags
  std::vector<std::size_t> nodes;  // nodes_per_element node tags per element
};

// One use of the Gmsh library: locks it, initializes it quietly (General.Terminal 0),
// and on destruction finalizes it and restores the process state it changed. A call
// Gmsh refuses throws horizon::Error with Gmsh's message; the caller names the file.
class Session {
 public:
  // Throws horizon::Error when the library cannot be loaded (the message names the
  // library looked for and the package that holds it).
  Session();
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  // gmshMerge: reads a file into the current model. Returns Gmsh's error message, empty
  // when it read the file.
  std::string merge(const std::string& path);
  void set_number(const char* option, double value);

  std::vector<std::pair<int, int>> entities(int dim = -1);  // (dim, tag)
  std::vector<int> physical_groups_of(int dim, int tag);
  std::string physical_name(int dim, int tag);
  // Every node of the model: its tag and x, y, z.
  void nodes(std::vector<std::size_t>& tags, std::vector<double>& xyz);
  std::vector<ElementBlock> elements(int dim, int tag);

 private:
  void end();  // finalize, restore, unlock
  struct State;
  State* saved_;
};

// Where the library is looked for (its soname, fixed when Horizon is configured).
const char* library_name();
// Any function of Gmsh's C API by name, for callers that need more than the Session
// offers (the tests write their meshes through it); cast it to decltype(&::gmshName).
void* symbol(const char* name);

}  // namespace horizon::gmsh_library
