#pragma once
// Where a crack is: measured from the damage field, for reports and tests.
#include <cstdint>
#include <optional>
#include <vector>

#include "horizon/core/vec3.hpp"
#include "horizon/geometry/particles.hpp"

namespace horizon {

struct CrackFront {
  bool found = false;
  Vec3 tip;            // damaged particle furthest along the crack direction
  double length = 0;   // distance of the tip from the origin, along the direction [m]
};

// The damaged path grown from a precrack's tip: 1 for each particle with damage >=
// `threshold` that is joined to the tip, 0 otherwise. The path starts at the cracked
// particles within `seed` of `origin` and spreads to cracked particles within `link` of a
// particle already on it (use link ~ 1.5 spacings: lattice diagonals join, a gap of one
// intact particle does not). Damage elsewhere (under an impactor, at a loaded edge) is
// not part of the crack and is left out.
std::vector<uint8_t> connected_crack(const Particles& p, const Vec3& origin, double threshold, double seed,
                                     double link);

// The crack grows from `origin` (a precrack's tip) along `direction` (unit). A particle
// is cracked when its damage is at least `threshold`. Only particles ahead of the
// origin and within `band` of the crack line, measured sideways, are considered, and,
// when `mask` is given, only those with mask[i] != 0 (e.g. from connected_crack).
CrackFront crack_front(const Particles& p, const Vec3& origin, const Vec3& direction, double threshold, double band,
                       const std::vector<uint8_t>* mask = nullptr);

// Where the crack splits: the first distance along the direction from which four
// consecutive slices (of width `slice`) each hold two or more clusters of cracked
// particles separated sideways by more than `gap`. Because each crack face carries a
// damaged band, the branches are seen once they are `gap` apart, a little after they
// part. Empty if it never branches.
// `mask`, when given, restricts the cracked particles as in crack_front.
std::optional<double> branch_distance(const Particles& p, const Vec3& origin, const Vec3& direction, double threshold,
                                      double slice, double gap, const std::vector<uint8_t>* mask = nullptr);

// Cracks crossing a line (thermal shock: the edge cracks seen at a depth below a quenched
// edge). The line is X[normal] = at; the points within `tol` of it are sorted along the
// axis `along`, and each run of consecutive points with damage >= `threshold` is one
// crack, at the damage-weighted mean of the run's positions; runs closer than `merge`
// count as one. `points` and `damage` are one per particle (a frame's points and field).
struct LineCracks {
  std::vector<double> positions;  // along the line, increasing [m]
  double mean_spacing = 0;        // (last - first)/(count - 1); 0 with fewer than two
  double median_spacing = 0;      // the median gap between neighbours (robust to a missing crack)
};
LineCracks cracks_across_line(const std::vector<Vec3>& points, const std::vector<double>& damage, int along,
                              int normal, double at, double tol, double threshold, double merge);

}  // namespace horizon
