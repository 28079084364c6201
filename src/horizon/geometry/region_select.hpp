#pragma once
// Which particles a region selects (docs/input.md, "Regions"). A region selects the
// particles it contains. A box region that contains none (a load strip one spacing thick
// that falls between the rows of a coarser lattice, `--coarsen`) selects instead the
// particles nearest to it: along each axis the lattice layer(s) nearest the box, among
// the particles less than one spacing from the box along every axis. Both layers are
// taken on a tie, so the choice does not depend on the order of the particles. A region
// that contains particles selects exactly those, so a deck that runs at its own spacing
// selects what it always did.
#include <cstdint>
#include <vector>

#include "horizon/core/vec3.hpp"
#include "horizon/geometry/shape.hpp"

namespace horizon {

// The particles of X that `region` contains, in index order.
std::vector<uint32_t> particles_inside(const Shape& region, const std::vector<Vec3>& X);

// Whether the nearest-layer rule applies to `region` (a box) at all.
bool selects_nearest_layer(const Shape& region);

// Per axis (the first `dimension`), the smallest distance from the box to a particle of X
// that lies less than `spacing` from it along every axis; +inf where no particle does. The
// minimum over every rank's particles is the whole system's (parallel/decomposition.hpp).
Vec3 nearest_layer_gaps(const Box3& box, const std::vector<Vec3>& X, int dimension, double spacing);

// The particles of X within `gaps` (as above, maybe taken over all ranks) of the box along
// every axis, to a millionth of a spacing: the nearest layer(s). Empty when a gap is
// infinite.
std::vector<uint32_t> particles_nearest(const Box3& box, const std::vector<Vec3>& X, int dimension, double spacing,
                                        const Vec3& gaps);

// The rule on one process' particles: inside, or (box, none inside) nearest.
std::vector<uint32_t> select_region(const Shape& region, const std::vector<Vec3>& X, int dimension, double spacing);

}  // namespace horizon
