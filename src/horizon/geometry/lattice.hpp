#pragma once
// Fills shapes with a uniform lattice of particles (simple cubic in 3-D, square in
// 2-D, evenly spaced in 1-D). Each particle carries the volume of its lattice cell.
#include <optional>

#include "horizon/core/vec3.hpp"
#include "horizon/geometry/particles.hpp"
#include "horizon/geometry/shape.hpp"

namespace horizon {

struct LatticeSpec {
  int dimension = 3;
  double spacing = 0;
  double cell_volume = 0;           // spacing^d times thickness (2-D) or area (1-D)
  std::optional<Vec3> origin;       // a lattice point; default: cell centres from the box min
};

// Appends the lattice points of `shape` that no earlier particle already occupies
// (bodies listed first win where shapes overlap). Returns how many were added.
std::size_t fill_shape(Particles& particles, const Shape& shape, const LatticeSpec& spec, double density,
                       int32_t block, int32_t material);

}  // namespace horizon
