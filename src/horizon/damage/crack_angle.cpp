#include "horizon/damage/crack_angle.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace horizon {

CrackAngle crack_angle(const Particles& p, const Vec3& tip, const Vec3& notch_direction, double threshold,
                       double r_min, double r_max, double step, double reach) {
  CrackAngle out;
  if (!(step > 0) || !(reach > 0)) return out;
  // Damaged particles ahead of the tip, in the plane, sorted by their distance from it.
  struct Candidate {
    double r, dx, dy, damage;
  };
  std::vector<Candidate> c;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.damage[i] < threshold) continue;
    const double dx = p.X[i].x - tip.x, dy = p.X[i].y - tip.y;
    if (dx * notch_direction.x + dy * notch_direction.y < 0) continue;
    const double r = std::sqrt(dx * dx + dy * dy);
    if (r > r_max + step) continue;
    c.push_back({r, dx, dy, p.damage[i]});
  }
  std::sort(c.begin(), c.end(), [](const Candidate& a, const Candidate& b) { return a.r < b.r; });

  // Follow the ridge ring by ring from the tip.
  double px = 0, py = 0, pr = 0;  // previous ridge point (the tip at first), its distance
  double sxx = 0, sxy = 0, syy = 0, mx = 0, my = 0;
  std::size_t next = 0;
  for (int k = 0;; ++k) {
    const double lo = k * step, hi = (k + 1) * step;
    if (lo > r_max || lo - pr >= reach) break;
    const Candidate* best = nullptr;
    for (; next < c.size() && c[next].r < hi; ++next) {
      const Candidate& q = c[next];
      if (q.r < lo) continue;
      const double ex = q.dx - px, ey = q.dy - py;
      if (ex * ex + ey * ey > reach * reach) continue;
      if (!best || q.damage > best->damage) best = &q;
    }
    if (!best) continue;
    px = best->dx, py = best->dy, pr = best->r;
    if (best->r < r_min || best->r > r_max) continue;
    sxx += px * px, sxy += px * py, syy += py * py, mx += px, my += py;
    ++out.points;
  }
  if (out.points < 3) return out;
  // Principal axis of the 2x2 second-moment matrix: the orthogonal least-squares line
  // through the tip (K. Pearson, Phil. Mag. 2 (1901) 559).
  const double phi = 0.5 * std::atan2(2 * sxy, sxx - syy);
  double ux = std::cos(phi), uy = std::sin(phi);
  if (ux * mx + uy * my < 0) ux = -ux, uy = -uy;
  const double dot = ux * notch_direction.x + uy * notch_direction.y;
  const double cross = notch_direction.x * uy - notch_direction.y * ux;  // z . (d x u)
  out.degrees = std::atan2(cross, dot) * 180.0 / std::numbers::pi;
  out.found = true;
  return out;
}

}  // namespace horizon
