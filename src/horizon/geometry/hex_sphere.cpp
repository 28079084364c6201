#include "horizon/geometry/hex_sphere.hpp"

#include <algorithm>
#include <cmath>

namespace horizon {

namespace {

// The parametric signs of the corners in Exodus order.
constexpr int kSign[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                             {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};

Vec3 map_point(const Hex8& p, const double xi[3]) {
  Vec3 x{};
  for (int k = 0; k < 8; ++k) {
    const double n = (1 + kSign[k][0] * xi[0]) * (1 + kSign[k][1] * xi[1]) * (1 + kSign[k][2] * xi[2]) / 8;
    x = x + p[static_cast<std::size_t>(k)] * n;
  }
  return x;
}

// det of the map's Jacobian at xi.
double jacobian(const Hex8& p, const double xi[3]) {
  Vec3 d[3] = {};  // dx/dxi_a
  for (int k = 0; k < 8; ++k) {
    const double f[3] = {1 + kSign[k][0] * xi[0], 1 + kSign[k][1] * xi[1], 1 + kSign[k][2] * xi[2]};
    for (int a = 0; a < 3; ++a) {
      double g = kSign[k][a] / 8.0;
      for (int b = 0; b < 3; ++b)
        if (b != a) g *= f[b];
      d[a] = d[a] + p[static_cast<std::size_t>(k)] * g;
    }
  }
  return dot(d[0], cross(d[1], d[2]));
}

bool inside(const Vec3& x, const Vec3& c, double r2) {
  const Vec3 e = x - c;
  return dot(e, e) <= r2;
}

// The image of the parametric box [lo, hi] (per axis) as a hexahedron.
Hex8 sub_hex(const Hex8& p, const double lo[3], const double hi[3]) {
  Hex8 out;
  for (int k = 0; k < 8; ++k) {
    const double xi[3] = {kSign[k][0] < 0 ? lo[0] : hi[0], kSign[k][1] < 0 ? lo[1] : hi[1],
                          kSign[k][2] < 0 ? lo[2] : hi[2]};
    out[static_cast<std::size_t>(k)] = map_point(p, xi);
  }
  return out;
}

double sampled(const Hex8& p, const Vec3& c, double r2, int level, int levels, int samples) {
  bool all = true;
  for (const Vec3& x : p) all = all && inside(x, c, r2);
  if (all) return hex8_volume(p);
  if (level == levels) {
    // The midpoint rule on p's own map over n^3 parametric cells of side 2/n.
    const double w = std::pow(2.0 / samples, 3);
    double v = 0;
    for (int i = 0; i < samples; ++i)
      for (int j = 0; j < samples; ++j)
        for (int k = 0; k < samples; ++k) {
          const double xi[3] = {-1 + (2.0 * i + 1) / samples, -1 + (2.0 * j + 1) / samples,
                                -1 + (2.0 * k + 1) / samples};
          if (inside(map_point(p, xi), c, r2)) v += jacobian(p, xi) * w;
        }
    return v;
  }
  double v = 0;
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      for (int k = 0; k < 2; ++k) {
        const double lo[3] = {i - 1.0, j - 1.0, k - 1.0}, hi[3] = {i + 0.0, j + 0.0, k + 0.0};
        v += sampled(sub_hex(p, lo, hi), c, r2, level + 1, levels, samples);
      }
  return v;
}

// Branch and bound over p's parametric boxes (header).
bool meets(const Hex8& p, const Vec3& c, double r2, int depth) {
  Vec3 lo = p[0], hi = p[0];
  for (const Vec3& x : p) {
    if (inside(x, c, r2)) return true;
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], x[a]), hi[a] = std::max(hi[a], x[a]);
  }
  double d2 = 0;
  for (int a = 0; a < 3; ++a) {
    const double e = std::max({lo[a] - c[a], 0.0, c[a] - hi[a]});
    d2 += e * e;
  }
  if (d2 > r2) return false;
  if (depth == kHexSphereDepth) return true;
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      for (int k = 0; k < 2; ++k) {
        const double blo[3] = {i - 1.0, j - 1.0, k - 1.0}, bhi[3] = {i + 0.0, j + 0.0, k + 0.0};
        if (meets(sub_hex(p, blo, bhi), c, r2, depth + 1)) return true;
      }
  return false;
}

}  // namespace

double hex8_volume(const Hex8& p) {
  const double g = 1 / std::sqrt(3.0);
  double v = 0;
  for (int k = 0; k < 8; ++k) {
    const double xi[3] = {kSign[k][0] * g, kSign[k][1] * g, kSign[k][2] * g};
    v += jacobian(p, xi);
  }
  return v;
}

double hex_sphere_volume(const Hex8& p, const Vec3& centre, double radius, int levels, int samples) {
  return sampled(p, centre, radius * radius, 0, std::max(levels, 0), std::max(samples, 1));
}

bool hex_meets_sphere(const Hex8& p, const Vec3& centre, double radius) {
  return meets(p, centre, radius * radius, 0);
}

}  // namespace horizon
