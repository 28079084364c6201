#pragma once
// The direction a crack leaves a notch at, from the damage field: for the Kalthoff-Winkler
// test (Tupek thesis sec. 6.2.2, Table 6.2; experiment: Kalthoff, Int. J. Fract. 27 (1985)),
// measured automatically.
#include "horizon/core/vec3.hpp"
#include "horizon/geometry/particles.hpp"

namespace horizon {

struct CrackAngle {
  bool found = false;
  // Angle from notch_direction to the crack line, counter-clockwise positive (towards
  // z x notch_direction), in (-180, 180]; |degrees| is the angle of Tupek's Table 6.2.
  double degrees = 0;
  std::size_t points = 0;  // ridge points in the fit
};

// The crack path is followed from `tip` outwards as a ridge of the damage field: in
// each ring [k step, (k + 1) step) around the tip, among the particles with damage >=
// threshold that lie ahead of the tip ((x - tip) . notch_direction >= 0) and within
// `reach` of the previous ridge point, the most damaged one is the next ridge point (the
// first is searched within `reach` of the tip). A ring without such a particle is
// skipped; the path ends once a gap reaches `reach`. The line through `tip` that best fits
// (orthogonal least squares: principal direction of sum (x - tip)(x - tip)^T, in the plane
// z = const) the ridge points whose distance from the tip lies in [r_min, r_max] gives the
// angle; it is oriented towards those points. Following the most damaged particle, one per
// ring, keeps the diffuse damage beside a crack and damage elsewhere (under the impact,
// at the far edge) out of the fit; at least 3 points are needed.
CrackAngle crack_angle(const Particles& p, const Vec3& tip, const Vec3& notch_direction, double threshold,
                       double r_min, double r_max, double step, double reach);

}  // namespace horizon
