#pragma once
// Colour maps for rendered fields.
#include <cstdint>

namespace horizon {

struct Rgb {
  uint8_t r = 0, g = 0, b = 0;
  friend bool operator==(const Rgb&, const Rgb&) = default;
};

// Viridis (van der Walt & Smith, matplotlib 2015): perceptually uniform, readable in
// grey scale and by colour-blind viewers. t is clamped to [0, 1]; 0 is dark purple,
// 1 is yellow (#FDE725).
Rgb viridis(double t);

}  // namespace horizon
