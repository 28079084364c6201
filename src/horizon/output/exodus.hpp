#pragma once
// Frames as one Exodus II file (through Debian's libexodusII), laid out as Peridigm writes
// its output (Peridigm Users' Guide, SAND2012-7800, "Output"; the layout of its
// regression golds): every particle is a node at its reference position and a one-node
// SPHERE element of its block's element block (block_1, block_2, ...); per-particle
// vectors are nodal variables (DisplacementX, ...), per-particle scalars element
// variables (Damage, Dilatation, ...), and whole-system numbers global variables
// (Global_Kinetic_Energy). Each frame is one time step.
//
// Written safely: the file is complete and readable after every frame (ex_update flushes
// the netCDF header and data once a frame's values are in), so an interrupted run leaves
// the frames written so far.
#include <memory>
#include <string>
#include <vector>

#include "horizon/core/vec3.hpp"

namespace horizon {

struct ExodusLayout {
  std::string title = "Horizon";
  std::vector<Vec3> points;              // reference positions, the nodes (particle order)
  std::vector<int> block;                // per point: index into block_names
  std::vector<std::string> block_names;  // element block k + 1 is block_names[k]
  std::vector<std::string> nodal, element, global;  // variable names
};

struct ExodusStep {
  double time = 0;
  std::vector<std::vector<double>> nodal;    // [variable][point]
  std::vector<std::vector<double>> element;  // [variable][point]
  std::vector<double> global;                // [variable]
};

class ExodusWriter {
 public:
  // Creates (or replaces) the file and writes the mesh and the variable names. Throws
  // OutputError naming the path.
  ExodusWriter(const std::string& path, const ExodusLayout& layout);
  ~ExodusWriter();
  ExodusWriter(const ExodusWriter&) = delete;
  ExodusWriter& operator=(const ExodusWriter&) = delete;
  // Writes one time step and flushes the file. Throws OutputError.
  void append(const ExodusStep& step);
  const ExodusLayout& layout() const { return layout_; }
  int steps() const { return steps_; }

 private:
  std::string path_;
  ExodusLayout layout_;
  std::vector<std::vector<std::size_t>> members_;  // per block: its points in order
  int id_ = -1;
  int steps_ = 0;
};

// An Exodus file of this layout read back (tests, tools): the layout and every step.
struct ExodusSeries {
  ExodusLayout layout;
  std::vector<ExodusStep> steps;
};
ExodusSeries read_exodus_series(const std::string& path);

}  // namespace horizon
