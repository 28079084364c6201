#pragma once
// Families by cell-list search: O(N) time and memory. The family of i is every other
// particle j with |X_j - X_i| <= horizon (a relative tolerance of 1e-10 keeps lattice
// points that sit exactly on the horizon sphere). See docs/models.md.
#include "horizon/family/bonds.hpp"
#include "horizon/geometry/particles.hpp"

namespace horizon {

// Neighbour pairs within `radius`, in compressed rows, each row sorted by j.
// Reference data filled: length and volume = V_j; weight = 1; intact = 1.
Bonds find_neighbors(const std::vector<Vec3>& points, const std::vector<double>& volume, double radius);

// The same by brute force, O(N^2): the reference the cell list is tested against.
Bonds find_neighbors_brute_force(const std::vector<Vec3>& points, const std::vector<double>& volume,
                                 double radius);

// Partial-volume rule: a neighbour whose distance lies within half a spacing of the
// horizon contributes the fraction (horizon + spacing/2 - |xi|)/spacing of its volume
// (the linear rule of Parks et al., LAMMPS PERI). Volumes of other bonds are unchanged.
void apply_partial_volume(Bonds& bonds, double horizon, double spacing);

}  // namespace horizon
