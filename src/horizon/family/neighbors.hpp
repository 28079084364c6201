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

// Partial-volume rule: the cell of a neighbour at distance r, of width `spacing`, is
// taken to lie inside the horizon sphere for the fraction
//   clamp((horizon + spacing/2 - r)/spacing, 0, 1)
// of its volume (the linear rule of Seleson 2014, "Improved one-point quadrature
// algorithms for two-dimensional peridynamic models", and of LAMMPS PERI). Families
// must reach horizon + spacing/2 for the rule to add the cells the sphere cuts; see
// partial_volume_radius.
void apply_partial_volume(Bonds& bonds, double horizon, double spacing);

// Search radius of the families: the horizon, or horizon + spacing/2 with partial volumes.
inline double family_radius(double horizon, double spacing, bool partial_volume) {
  return partial_volume ? horizon + 0.5 * spacing : horizon;
}

}  // namespace horizon
