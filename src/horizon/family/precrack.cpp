#include "horizon/family/precrack.hpp"

#include <algorithm>
#include <cmath>

namespace horizon {

namespace {

double orient2d(const Vec3& a, const Vec3& b, const Vec3& c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

bool crosses_segment(const Vec3& a, const Vec3& b, const Vec3& p, const Vec3& q) {
  const double o1 = orient2d(p, q, a), o2 = orient2d(p, q, b);
  if (!(o1 * o2 < 0)) return false;
  const double o3 = orient2d(a, b, p), o4 = orient2d(a, b, q);
  return o3 * o4 <= 0;
}

// `closed`: a crossing point on the polygon's boundary (within 1e-12 of its size) counts
// as inside. The facets of a surface are closed, so a bond through the edge two facets
// share is cut (Peridigm's Exodus Mesh filters cut those: QuadBondFilter's gold).
bool crosses_polygon(const Vec3& a, const Vec3& b, const std::vector<Vec3>& poly, bool closed = false) {
  // Plane normal by Newell's method (robust for any planar polygon).
  Vec3 n;
  for (std::size_t k = 0; k < poly.size(); ++k) {
    const Vec3& p = poly[k];
    const Vec3& q = poly[(k + 1) % poly.size()];
    n.x += (p.y - q.y) * (p.z + q.z);
    n.y += (p.z - q.z) * (p.x + q.x);
    n.z += (p.x - q.x) * (p.y + q.y);
  }
  const double da = dot(a - poly[0], n), db = dot(b - poly[0], n);
  if (!(da * db < 0)) return false;
  const Vec3 x = a + (b - a) * (da / (da - db));
  // Project on the plane's dominant axes and count crossings (even-odd rule).
  int drop = 0;
  if (std::abs(n.y) > std::abs(n[drop])) drop = 1;
  if (std::abs(n.z) > std::abs(n[drop])) drop = 2;
  const int u = (drop + 1) % 3, v = (drop + 2) % 3;
  if (closed) {
    double size = 0;
    for (const Vec3& p : poly) size = std::max(size, std::abs(p[u] - poly[0][u]) + std::abs(p[v] - poly[0][v]));
    const double tol = 1e-12 * size;
    for (std::size_t k = 0, m = poly.size() - 1; k < poly.size(); m = k++) {
      // Distance from x to the edge poly[m] -> poly[k] in the projection.
      const double ex = poly[k][u] - poly[m][u], ey = poly[k][v] - poly[m][v];
      const double px = x[u] - poly[m][u], py = x[v] - poly[m][v];
      const double len2 = ex * ex + ey * ey;
      const double w = len2 > 0 ? std::clamp((px * ex + py * ey) / len2, 0.0, 1.0) : 0.0;
      const double dx = px - w * ex, dy = py - w * ey;
      if (dx * dx + dy * dy <= tol * tol) return true;
    }
  }
  bool inside = false;
  for (std::size_t k = 0, m = poly.size() - 1; k < poly.size(); m = k++) {
    const Vec3& p = poly[k];
    const Vec3& q = poly[m];
    if ((p[v] > x[v]) != (q[v] > x[v]) && x[u] < (q[u] - p[u]) * (x[v] - p[v]) / (q[v] - p[v]) + p[u])
      inside = !inside;
  }
  return inside;
}

// A disk of radius r about c in the plane normal to n: a and b strictly on opposite
// sides of the plane, and the crossing point within r of c.
bool crosses_disk(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& n, double r) {
  const double da = dot(a - c, n), db = dot(b - c, n);
  if (!(da * db < 0)) return false;
  const Vec3 x = a + (b - a) * (da / (da - db));
  return norm(x - c) <= r;
}

bool crosses_surface(const Vec3& a, const Vec3& b, const Precrack& crack) {
  Vec3 lo, hi;
  for (int k = 0; k < 3; ++k) lo[k] = std::min(a[k], b[k]), hi[k] = std::max(a[k], b[k]);
  for (std::size_t f = 0; f < crack.facets.size(); ++f) {
    const auto& [flo, fhi] = crack.boxes[f];
    if (lo.x > fhi.x || hi.x < flo.x || lo.y > fhi.y || hi.y < flo.y || lo.z > fhi.z || hi.z < flo.z) continue;
    if (crosses_polygon(a, b, crack.facets[f], true)) return true;
  }
  return false;
}

}  // namespace

void set_facets(Precrack& crack, std::vector<std::vector<Vec3>> facets) {
  crack.facets = std::move(facets);
  crack.boxes.clear();
  for (const auto& f : crack.facets) {
    Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    for (const Vec3& p : f)
      for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
    crack.boxes.emplace_back(lo, hi);
  }
}

void bounding_box(const Precrack& crack, Vec3& lo, Vec3& hi) {
  lo = {1e300, 1e300, 1e300};
  hi = {-1e300, -1e300, -1e300};
  auto add = [&](const Vec3& p, double r) {
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k] - r), hi[k] = std::max(hi[k], p[k] + r);
  };
  for (const Vec3& p : crack.points) add(p, crack.radius);
  for (const auto& [flo, fhi] : crack.boxes) add(flo, 0), add(fhi, 0);
}

bool crosses_rectangle(const Vec3& a, const Vec3& b, const Precrack& crack) {
  const Vec3& n = crack.normal;
  const Vec3& r0 = crack.corner;
  const double num = (r0.x - a.x) * n.x + (r0.y - a.y) * n.y + (r0.z - a.z) * n.z;
  const double den = (b.x - a.x) * n.x + (b.y - a.y) * n.y + (b.z - a.z) * n.z;
  if (std::abs(den) < 1e-14) return false;  // parallel to the plane
  const double t = num / den;
  if (!(t >= 0.0 && t <= 1.0)) return false;
  const Vec3 x{a.x + t * (b.x - a.x), a.y + t * (b.y - a.y), a.z + t * (b.z - a.z)};
  const Vec3 d{x.x - r0.x, x.y - r0.y, x.z - r0.z};
  const Vec3& ub = crack.bottom;
  const Vec3 ua = cross(ub, n);
  const double along_side = d.x * ua.x + d.y * ua.y + d.z * ua.z;
  const double along_bottom = d.x * ub.x + d.y * ub.y + d.z * ub.z;
  const double zero = 1e-15, one = 1.0 + zero;
  return -zero < along_side && along_side / crack.side_length < one && -zero < along_bottom &&
         along_bottom / crack.bottom_length < one;
}

bool crosses(const Vec3& a, const Vec3& b, const Precrack& crack, int dimension) {
  // Peridigm tests each neighbour list's direction; a bond here is one pair, cut when
  // either direction crosses (no pair of Peridigm's suite crosses one way only).
  if (crack.rectangle) return dimension == 3 && (crosses_rectangle(a, b, crack) || crosses_rectangle(b, a, crack));
  if (dimension == 3) {
    if (!crack.facets.empty()) return crosses_surface(a, b, crack);
    if (crack.radius > 0) return !crack.points.empty() && crosses_disk(a, b, crack.points[0], crack.normal, crack.radius);
    return crack.points.size() >= 3 && crosses_polygon(a, b, crack.points);
  }
  return crack.points.size() == 2 && crosses_segment(a, b, crack.points[0], crack.points[1]);
}

std::size_t cut_bonds(Bonds& bonds, const std::vector<Vec3>& X, const std::vector<Precrack>& cracks, int dimension) {
  if (cracks.empty()) return 0;
  return rewrite_bonds(bonds, [&](std::size_t i, uint64_t k) {
    bool cut = false, keep = true;
    for (const auto& c : cracks)
      if (crosses(X[i], X[bonds.nbr[k]], c, dimension)) {
        cut = true;
        keep = keep && c.keep_broken;
        if (!keep) break;
      }
    return !cut ? BondAction::keep : keep ? BondAction::keep_broken : BondAction::drop;
  });
}

}  // namespace horizon
