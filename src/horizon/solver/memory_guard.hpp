#pragma once
// The memory a deck will need, estimated from the deck alone before anything is
// allocated, and the refusal of a deck that would not fit (DESIGN: "a deck whose
// particles or bonds would not fit in memory is refused before anything is allocated").
#include <cstddef>

#include "horizon/deck/config.hpp"

namespace horizon {

struct MemoryEstimate {
  double particles = 0;  // upper bound: every lattice point of every body's bounding box
  double bonds = 0;      // directed: particles x the lattice points of one family
  double bytes = 0;
};

// An upper bound from the bodies' bounding boxes, the spacing and the horizon. Doubles,
// so that a spacing of 1e-12 m gives a figure, not an overflow.
MemoryEstimate estimate_memory(const Config& config);

// The machine's physical memory [bytes] (or the address-space limit of the process,
// when one is set and smaller).
double machine_memory_bytes();

// Throws horizon::Error with the estimate and the limit when the estimate exceeds
// `limit_bytes` (0: machine_memory_bytes()).
void check_memory(const Config& config, double limit_bytes);

}  // namespace horizon
