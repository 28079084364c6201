#include "horizon/geometry/surface.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <unordered_map>

#include <fmt/format.h>

#include "horizon/geometry/gmsh_library.hpp"
#include "horizon/geometry/mesh.hpp"

namespace horizon {

namespace {

bool less_xy(const Vec3& a, const Vec3& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); }

// Twice the signed area of (p, q, r) in the xy-plane.
double orient_xy(const Vec3& p, const Vec3& q, double rx, double ry) {
  return (q.x - p.x) * (ry - p.y) - (q.y - p.y) * (rx - p.x);
}

// Six times the signed volume of (a, b, c, d).
double orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return dot(b - a, cross(c - a, d - a));
}

// The point of triangle abc closest to p (Ericson, Real-Time Collision Detection, 2005,
// sec. 5.1.5: the Voronoi regions of the vertices, the edges and the face).
Vec3 closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  const Vec3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

struct VecKey {
  std::size_t operator()(const Vec3& v) const {
    uint64_t h = 1469598103934665603ull;
    for (int k = 0; k < 3; ++k) {
      uint64_t bits;
      const double x = v[k] == 0 ? 0.0 : v[k];  // -0 and +0 are one coordinate
      std::memcpy(&bits, &x, sizeof bits);
      h = (h ^ bits) * 1099511628211ull;
    }
    return static_cast<std::size_t>(h ^ (h >> 32));
  }
};
struct VecEq {
  bool operator()(const Vec3& a, const Vec3& b) const { return a.x == b.x && a.y == b.y && a.z == b.z; }
};

// A uniform grid over a box: about `target` cells, shaped like the box (2-D: z ignored).
struct Grid {
  Vec3 lo;
  int n[3] = {1, 1, 1};
  double size[3] = {1, 1, 1};
  Grid(const Vec3& lo_in, const Vec3& hi, std::size_t target, int dims) : lo(lo_in) {
    double w[3];
    double vol = 1;
    for (int k = 0; k < dims; ++k) {
      w[k] = std::max(hi[k] - lo[k], 1e-300);
      vol *= w[k];
    }
    const double cell = std::pow(vol / static_cast<double>(std::max<std::size_t>(target, 1)), 1.0 / dims);
    for (int k = 0; k < dims; ++k) n[k] = static_cast<int>(std::clamp(std::ceil(w[k] / cell), 1.0, 1024.0));
    // A flat box (a degenerate surface) would ask for 1024 cells along every other
    // axis: halve the longest side until the count is near the target.
    auto count = [&] { return static_cast<double>(n[0]) * n[1] * n[2]; };
    while (count() > 8.0 * static_cast<double>(target) + 64) *std::max_element(n, n + dims) /= 2;
    for (int k = 0; k < dims; ++k) size[k] = w[k] / n[k];
  }
  int index(int k, double x) const {
    return std::clamp(static_cast<int>(std::floor((x - lo[k]) / size[k])), 0, n[k] - 1);
  }
};

}  // namespace

ClosedSurface::ClosedSurface(std::vector<Vec3> vertices, const std::vector<std::array<uint32_t, 3>>& triangles,
                             std::string file, double scale)
    : file_(std::move(file)), scale_(scale) {
  // One vertex per coordinate triple: files that repeat a corner for each triangle (STL)
  // share it, so that edges can be matched.
  std::unordered_map<Vec3, uint32_t, VecKey, VecEq> at;
  std::vector<uint32_t> remap(vertices.size());
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const auto [it, fresh] = at.emplace(vertices[i], static_cast<uint32_t>(v_.size()));
    if (fresh) v_.push_back(vertices[i]);
    remap[i] = it->second;
  }
  for (const auto& t : triangles) {
    std::array<uint32_t, 3> r{};
    for (int k = 0; k < 3; ++k) {
      if (t[k] >= remap.size()) throw SurfaceError(file_ + ": a triangle names vertex " + std::to_string(t[k]) + " of " + std::to_string(remap.size()));
      r[k] = remap[t[k]];
    }
    if (r[0] == r[1] || r[1] == r[2] || r[0] == r[2]) continue;  // collapsed: no area, no edges
    tri_.push_back(r);
  }
  if (tri_.empty()) throw SurfaceError(file_ + ": no triangles (a body needs a closed triangulated surface)");
  lo_ = hi_ = v_[tri_[0][0]];
  for (const auto& t : tri_)
    for (uint32_t i : t)
      for (int k = 0; k < 3; ++k) {
        lo_[k] = std::min(lo_[k], v_[i][k]);
        hi_[k] = std::max(hi_[k], v_[i][k]);
      }
  // As the primitives' faces (shape.cpp): relative to the size of the coordinates.
  tol_ = 1e-12 * (norm(hi_ - lo_) + std::max(norm(lo_), norm(hi_)));
  check_closed();
  check_self_intersection();

  // Triangles by xy cell, about one cell per triangle.
  const Grid g(lo_, hi_, tri_.size(), 2);
  nx_ = g.n[0];
  ny_ = g.n[1];
  cx_ = g.size[0];
  cy_ = g.size[1];
  std::vector<uint32_t> count(static_cast<std::size_t>(nx_) * ny_ + 1, 0);
  auto for_cells = [&](const std::array<uint32_t, 3>& t, auto&& f) {
    double xmin = v_[t[0]].x, xmax = xmin, ymin = v_[t[0]].y, ymax = ymin;
    for (uint32_t i : t) {
      xmin = std::min(xmin, v_[i].x), xmax = std::max(xmax, v_[i].x);
      ymin = std::min(ymin, v_[i].y), ymax = std::max(ymax, v_[i].y);
    }
    for (int j = g.index(1, ymin - tol_); j <= g.index(1, ymax + tol_); ++j)
      for (int i = g.index(0, xmin - tol_); i <= g.index(0, xmax + tol_); ++i) f(static_cast<std::size_t>(j) * nx_ + i);
  };
  for (const auto& t : tri_) for_cells(t, [&](std::size_t c) { ++count[c + 1]; });
  for (std::size_t c = 1; c < count.size(); ++c) count[c] += count[c - 1];
  cell_start_ = count;
  cell_tri_.resize(count.back());
  for (uint32_t t = 0; t < tri_.size(); ++t) for_cells(tri_[t], [&](std::size_t c) { cell_tri_[count[c]++] = t; });
}

std::string ClosedSurface::where(const Vec3& x) const {
  const Vec3 y = x / scale_;
  return fmt::format("({:.6g}, {:.6g}, {:.6g})", y.x, y.y, y.z);
}

void ClosedSurface::check_closed() const {
  std::vector<std::pair<uint32_t, uint32_t>> edges;
  edges.reserve(3 * tri_.size());
  for (const auto& t : tri_)
    for (int k = 0; k < 3; ++k) edges.emplace_back(std::minmax(t[k], t[(k + 1) % 3]));
  std::sort(edges.begin(), edges.end());
  // The message names the open edge that comes first by its corners' coordinates (not by
  // the file's vertex numbering).
  auto before = [&](const Vec3& a, const Vec3& b) { return a.x < b.x || (a.x == b.x && (a.y < b.y || (a.y == b.y && a.z < b.z))); };
  auto ordered = [&](std::pair<uint32_t, uint32_t> e) {
    return before(v_[e.second], v_[e.first]) ? std::make_pair(e.second, e.first) : e;
  };
  std::size_t odd = 0, first_count = 0;
  std::pair<uint32_t, uint32_t> first{};
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    if ((j - i) % 2 == 1) {
      const auto e = ordered(edges[i]);
      const bool earlier = odd == 0 || before(v_[e.first], v_[first.first]) ||
                           (!before(v_[first.first], v_[e.first]) && before(v_[e.second], v_[first.second]));
      if (earlier) first = e, first_count = j - i;
      ++odd;
    }
    i = j;
  }
  if (odd == 0) return;
  throw SurfaceError(file_ + ": the surface is open: the edge from " + where(v_[first.first]) + " to " +
                     where(v_[first.second]) + " belongs to " + std::to_string(first_count) +
                     (first_count == 1 ? " triangle" : " triangles") + " (" + std::to_string(odd) +
                     (odd == 1 ? " edge belongs" : " edges belong") +
                     " to an odd number of triangles, coordinates in the file's units); a body needs a closed surface");
}

void ClosedSurface::check_self_intersection() const {
  // Triangles by 3-D cell; then every edge against the triangles near it.
  const Grid g(lo_, hi_, 2 * tri_.size(), 3);
  std::vector<std::vector<uint32_t>> cells(static_cast<std::size_t>(g.n[0]) * g.n[1] * g.n[2]);
  auto range = [&](const Vec3& a, const Vec3& b, int lo[3], int hi[3]) {
    for (int k = 0; k < 3; ++k) {
      lo[k] = g.index(k, std::min(a[k], b[k]));
      hi[k] = g.index(k, std::max(a[k], b[k]));
    }
  };
  auto cell = [&](int i, int j, int k) { return (static_cast<std::size_t>(k) * g.n[1] + j) * g.n[0] + i; };
  for (uint32_t t = 0; t < tri_.size(); ++t) {
    Vec3 a = v_[tri_[t][0]], b = a;
    for (uint32_t i : tri_[t])
      for (int k = 0; k < 3; ++k) a[k] = std::min(a[k], v_[i][k]), b[k] = std::max(b[k], v_[i][k]);
    int lo[3], hi[3];
    range(a, b, lo, hi);
    for (int k = lo[2]; k <= hi[2]; ++k)
      for (int j = lo[1]; j <= hi[1]; ++j)
        for (int i = lo[0]; i <= hi[0]; ++i) cells[cell(i, j, k)].push_back(t);
  }
  std::vector<std::pair<uint32_t, uint32_t>> edges;
  for (const auto& t : tri_)
    for (int k = 0; k < 3; ++k) edges.emplace_back(std::minmax(t[k], t[(k + 1) % 3]));
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  std::vector<uint32_t> seen(tri_.size(), UINT32_MAX);
  for (uint32_t e = 0; e < edges.size(); ++e) {
    const uint32_t iu = edges[e].first, iv = edges[e].second;
    const Vec3 &u = v_[iu], &v = v_[iv];
    int lo[3], hi[3];
    range(u, v, lo, hi);
    for (int k = lo[2]; k <= hi[2]; ++k)
      for (int j = lo[1]; j <= hi[1]; ++j)
        for (int i = lo[0]; i <= hi[0]; ++i)
          for (uint32_t t : cells[cell(i, j, k)]) {
            if (seen[t] == e) continue;
            seen[t] = e;
            const auto& T = tri_[t];
            if (T[0] == iu || T[1] == iu || T[2] == iu || T[0] == iv || T[1] == iv || T[2] == iv) continue;
            const Vec3 &a = v_[T[0]], &b = v_[T[1]], &c = v_[T[2]];
            // u and v strictly on two sides of the triangle's plane (coplanar and touching
            // ends do not count), and the segment meets the closed triangle: on a surface
            // that does not cross itself an edge meets a triangle only at a shared corner,
            // so meeting its inside, an edge or a corner of it is a crossing.
            const double len = std::max({norm(v - u), norm(b - a), norm(c - b), norm(a - c)});
            const double eps = 1e-10 * len * len * len;
            const double s1 = orient3d(a, b, c, u), s2 = orient3d(a, b, c, v);
            if (!((s1 > eps && s2 < -eps) || (s1 < -eps && s2 > eps))) continue;
            const double t1 = orient3d(u, v, a, b), t2 = orient3d(u, v, b, c), t3 = orient3d(u, v, c, a);
            if (!((t1 >= -eps && t2 >= -eps && t3 >= -eps) || (t1 <= eps && t2 <= eps && t3 <= eps))) continue;
            throw SurfaceError(file_ + ": the surface intersects itself: the edge from " + where(u) + " to " + where(v) +
                               " passes through the triangle " + where(a) + ", " + where(b) + ", " + where(c) +
                               " (coordinates in the file's units); a body needs a surface that does not cross itself");
          }
  }
}

bool ClosedSurface::contains(const Vec3& p) const {
  // Bounding-box prefilter (written so that NaN is outside).
  for (int k = 0; k < 3; ++k)
    if (!(p[k] >= lo_[k] - tol_ && p[k] <= hi_[k] + tol_)) return false;
  const int i = std::clamp(static_cast<int>(std::floor((p.x - lo_.x) / cx_)), 0, nx_ - 1);
  const int j = std::clamp(static_cast<int>(std::floor((p.y - lo_.y) / cy_)), 0, ny_ - 1);
  const std::size_t c = static_cast<std::size_t>(j) * nx_ + i;
  int crossings = 0;
  for (uint32_t n = cell_start_[c]; n < cell_start_[c + 1]; ++n) {
    const auto& t = tri_[cell_tri_[n]];
    const Vec3* w[3] = {&v_[t[0]], &v_[t[1]], &v_[t[2]]};
    // On the surface (a face, an edge or a vertex, any orientation): inside.
    bool near = true;
    for (int k = 0; k < 3 && near; ++k) {
      const double mn = std::min({(*w[0])[k], (*w[1])[k], (*w[2])[k]}), mx = std::max({(*w[0])[k], (*w[1])[k], (*w[2])[k]});
      near = p[k] >= mn - tol_ && p[k] <= mx + tol_;
    }
    if (near && norm(closest_on_triangle(p, *w[0], *w[1], *w[2]) - p) <= tol_) return true;
    // The ray from p along +z: does it cross this triangle, with the tie rule?
    double lambda[3];
    bool hit = true;
    for (int k = 0; k < 3 && hit; ++k) {
      const Vec3* a = w[(k + 1) % 3];
      const Vec3* b = w[(k + 2) % 3];  // the edge opposite vertex k
      if (less_xy(*b, *a)) std::swap(a, b);
      const double f = orient_xy(*a, *b, p.x, p.y);
      const double s = orient_xy(*a, *b, w[k]->x, w[k]->y);
      if (s == 0) hit = false;  // no area seen from above: the ray runs along it
      else hit = s > 0 ? f >= 0 : f < 0;
      lambda[k] = hit ? f / s : 0;
    }
    if (!hit) continue;
    const double z = lambda[0] * w[0]->z + lambda[1] * w[1]->z + lambda[2] * w[2]->z;
    if (z > p.z) ++crossings;
  }
  return crossings % 2 == 1;
}

double ClosedSurface::volume() const {
  double v = 0;
  for (const auto& t : tri_) v += dot(v_[t[0]], cross(v_[t[1]], v_[t[2]]));
  return std::abs(v) / 6;
}

double ClosedSurface::area() const {
  double a = 0;
  for (const auto& t : tri_) a += norm(cross(v_[t[1]] - v_[t[0]], v_[t[2]] - v_[t[0]]));
  return a / 2;
}

ClosedSurface read_surface(const std::string& path, double scale) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (auto& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  // Gmsh 4.8 reads these three by their own readers; it reads files of other names
  // (.off, .obj among them) as .geo scripts, which run commands: those are refused.
  static const std::vector<std::string> kKnown = {".stl", ".ply", ".msh"};
  if (std::find(kKnown.begin(), kKnown.end(), ext) == kKnown.end())
    throw SurfaceError("surface '" + path + "': unknown extension '" + ext + "' (.stl, ASCII or binary; also .ply and .msh)");
  if (!std::filesystem::exists(path)) throw SurfaceError("cannot open surface '" + path + "': No such file or directory");
  if (ext == ".msh") check_msh_header(path);
  gmsh_library::Session gmsh;
  if (const std::string why = gmsh.merge(path); !why.empty()) throw SurfaceError(path + ": Gmsh cannot read it: " + why);
  std::vector<std::size_t> tags;
  std::vector<double> xyz;
  gmsh.nodes(tags, xyz);
  std::unordered_map<std::size_t, uint32_t> index;
  std::vector<Vec3> vertices;
  for (std::size_t i = 0; i < tags.size(); ++i) {
    if (index.emplace(tags[i], static_cast<uint32_t>(vertices.size())).second)
      vertices.push_back(Vec3{xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]} * scale);
  }
  std::vector<std::array<uint32_t, 3>> triangles;
  for (const auto& [dim, tag] : gmsh.entities(2)) {
    for (const auto& b : gmsh.elements(dim, tag)) {
      if (b.dim != 2 || (b.primary_nodes != 3 && b.primary_nodes != 4)) continue;
      const auto npe = static_cast<std::size_t>(b.nodes_per_element);
      for (std::size_t e = 0; e < b.tags.size(); ++e) {
        uint32_t c[4] = {0, 0, 0, 0};
        for (int k = 0; k < b.primary_nodes; ++k) {
          const auto it = index.find(b.nodes[e * npe + static_cast<std::size_t>(k)]);
          if (it == index.end()) throw SurfaceError(path + ": element " + std::to_string(b.tags[e]) + " names a node the file does not define");
          c[k] = it->second;
        }
        triangles.push_back({c[0], c[1], c[2]});
        if (b.primary_nodes == 4) triangles.push_back({c[0], c[2], c[3]});
      }
    }
  }
  if (triangles.empty()) throw SurfaceError(path + ": no triangles (a body needs a closed triangulated surface)");
  return ClosedSurface(std::move(vertices), triangles, path, scale);
}

}  // namespace horizon
