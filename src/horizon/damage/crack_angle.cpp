#include "horizon/damage/crack_angle.hpp"

#include <cmath>
#include <numbers>

namespace horizon {

CrackAngle crack_angle(const Particles& p, const Vec3& tip, const Vec3& notch_direction, double threshold,
                       double r_min, double r_max) {
  CrackAngle out;
  double sxx = 0, sxy = 0, syy = 0, mx = 0, my = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.damage[i] < threshold) continue;
    const Vec3 d = p.X[i] - tip;
    const double r = std::sqrt(d.x * d.x + d.y * d.y);
    if (r < r_min || r > r_max) continue;
    if (d.x * notch_direction.x + d.y * notch_direction.y < 0) continue;
    sxx += d.x * d.x, sxy += d.x * d.y, syy += d.y * d.y, mx += d.x, my += d.y;
    ++out.points;
  }
  if (out.points < 3) return out;
  // Principal axis of the 2x2 second-moment matrix (a line through the tip).
  const double phi = 0.5 * std::atan2(2 * sxy, sxx - syy);
  double ux = std::cos(phi), uy = std::sin(phi);
  if (ux * mx + uy * my < 0) ux = -ux, uy = -uy;
  const double dot = ux * notch_direction.x + uy * notch_direction.y;
  const double cross = ux * notch_direction.y - uy * notch_direction.x;
  out.degrees = std::atan2(std::abs(cross), dot) * 180.0 / std::numbers::pi;
  out.found = true;
  return out;
}

}  // namespace horizon
