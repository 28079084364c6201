#pragma once
// Where a crack is: measured from the damage field, for reports and tests.
#include <optional>

#include "horizon/core/vec3.hpp"
#include "horizon/geometry/particles.hpp"

namespace horizon {

struct CrackFront {
  bool found = false;
  Vec3 tip;            // damaged particle furthest along the crack direction
  double length = 0;   // distance of the tip from the origin, along the direction [m]
};

// The crack grows from `origin` (a precrack's tip) along `direction` (unit). A particle
// is cracked when its damage is at least `threshold`. Only particles ahead of the
// origin and within `band` of the crack line, measured sideways, are considered.
CrackFront crack_front(const Particles& p, const Vec3& origin, const Vec3& direction, double threshold, double band);

// Where the crack splits: the first distance along the direction from which four
// consecutive slices (of width `slice`) each hold two or more clusters of cracked
// particles separated sideways by more than `gap`. Because each crack face carries a
// damaged band, the branches are seen once they are `gap` apart, a little after they
// part. Empty if it never branches.
std::optional<double> branch_distance(const Particles& p, const Vec3& origin, const Vec3& direction, double threshold,
                                      double slice, double gap);

}  // namespace horizon
