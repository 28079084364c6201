#pragma once
// The direction a crack leaves a notch at, from the damage field: for the Kalthoff-Winkler
// test (Tupek thesis sec. 6.2.2, Table 6.2), measured automatically.
#include "horizon/core/vec3.hpp"
#include "horizon/geometry/particles.hpp"

namespace horizon {

struct CrackAngle {
  bool found = false;
  double degrees = 0;     // angle between the notch direction and the crack line, in [0, 180]
  std::size_t points = 0; // damaged particles in the fit
};

// Fits a line through `tip` to the particles with damage >= threshold whose distance
// from the tip lies in [r_min, r_max] and that lie ahead of the tip
// ((x - tip) . notch_direction >= 0): the principal direction of sum (x - tip)(x - tip)^T
// in the plane z = const (2-D), oriented along the mean of x - tip. The angle is measured
// from notch_direction (unit).
CrackAngle crack_angle(const Particles& p, const Vec3& tip, const Vec3& notch_direction, double threshold,
                       double r_min, double r_max);

}  // namespace horizon
