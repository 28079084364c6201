#pragma once
// The memory a deck will need, estimated from the deck alone before anything is
// allocated, and the refusal of a deck that would not fit (DESIGN: "a deck whose
// particles or bonds would not fit in memory is refused before anything is allocated").
#include <cstddef>
#include <cstdint>
#include <vector>

#include "horizon/deck/config.hpp"

namespace horizon {

struct MemoryEstimate {
  double particles = 0;  // upper bound: every lattice point of every body's bounding box
  double bonds = 0;      // directed: the bonds among those points (box_bonds)
  double bytes = 0;
};

// An upper bound from the bodies' bounding boxes, the spacing and the horizon (exact
// particle and bond counts for box bodies without precracks). Doubles, so that a spacing
// of 1e-12 m gives a figure, not an overflow.
MemoryEstimate estimate_memory(const Config& config);

// The lattice offsets (in spacings) of a family of `radius` spacings, as the neighbour
// search accepts them, the particle itself left out.
struct LatticeOffset {
  int64_t x = 0, y = 0, z = 0;
};
std::vector<LatticeOffset> family_offsets(int dimension, double radius);
// The directed bonds of a block of n[0] x n[1] x n[2] lattice points (the first
// `dimension` counts used) with a family of `radius` spacings: sum over the family's
// offsets o of prod_k max(0, n_k - |o_k|).
double box_bonds(const double n[3], int dimension, double radius);

// The machine's physical memory [bytes] (or the address-space limit of the process,
// when one is set and smaller).
double machine_memory_bytes();

// Throws horizon::Error with the estimate and the limit when the estimate exceeds
// `limit_bytes` (0: machine_memory_bytes()). `ranks` > 1: the figure of one of that many
// MPI ranks that hold their own bond rows only (parallel/decomposition.hpp, local rows):
// every particle, and the bonds / ranks (the neighbours' rows a state-based rank also
// holds are not counted).
void check_memory(const Config& config, double limit_bytes, int ranks = 1);

}  // namespace horizon
