#include "horizon/family/neighbors.hpp"

#include <algorithm>
#include <cmath>

#include "horizon/core/error.hpp"

namespace horizon {

namespace {

constexpr double kRadiusTolerance = 1e-10;

// Grid of cubic cells of edge >= radius covering the points: each point's neighbours
// lie in its own cell or the adjacent ones.
struct CellGrid {
  Vec3 lo;
  double edge = 1;
  int64_t n[3] = {1, 1, 1};
  std::vector<uint64_t> start;   // per cell, into order (counting sort)
  std::vector<uint32_t> order;   // point indices sorted by cell

  int64_t coord(double x, int k) const {
    return std::clamp<int64_t>(static_cast<int64_t>((x - lo[k]) / edge), 0, n[k] - 1);
  }
  int64_t cell(const Vec3& p) const { return (coord(p.z, 2) * n[1] + coord(p.y, 1)) * n[0] + coord(p.x, 0); }
};

CellGrid make_grid(const std::vector<Vec3>& points, double radius) {
  CellGrid g;
  Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  for (const auto& p : points)
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }
  g.lo = lo;
  // A little wider than the accepted radius (radius * (1 + kRadiusTolerance)): a
  // neighbour accepted through the tolerance must never land two cells away through
  // round-off in the cell coordinates (a lattice with horizon = m spacings and a
  // non-zero origin lost its on-sphere neighbours that way).
  g.edge = radius * (1 + 100 * kRadiusTolerance);
  // Keep the cell count proportional to N even for a sparse cloud in a big box.
  const double max_cells = 8.0 * static_cast<double>(points.size()) + 64;
  for (;;) {
    double cells = 1;
    for (int k = 0; k < 3; ++k) {
      g.n[k] = std::max<int64_t>(1, static_cast<int64_t>((hi[k] - lo[k]) / g.edge) + 1);
      cells *= static_cast<double>(g.n[k]);
    }
    if (cells <= max_cells) break;
    g.edge *= 1.5;
  }
  const std::size_t ncell = static_cast<std::size_t>(g.n[0] * g.n[1] * g.n[2]);
  g.start.assign(ncell + 1, 0);
  std::vector<uint32_t> cell_of(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    cell_of[i] = static_cast<uint32_t>(g.cell(points[i]));
    ++g.start[cell_of[i] + 1];
  }
  for (std::size_t c = 0; c < ncell; ++c) g.start[c + 1] += g.start[c];
  g.order.resize(points.size());
  std::vector<uint64_t> fill(g.start.begin(), g.start.end() - 1);
  for (std::size_t i = 0; i < points.size(); ++i) g.order[fill[cell_of[i]]++] = static_cast<uint32_t>(i);
  return g;
}

// Calls visit(j) for every j != i within radius of points[i].
template <class Visit>
void for_each_neighbor(const CellGrid& g, const std::vector<Vec3>& points, std::size_t i, double r2, Visit visit) {
  const Vec3& p = points[i];
  const int64_t c[3] = {g.coord(p.x, 0), g.coord(p.y, 1), g.coord(p.z, 2)};
  for (int64_t z = std::max<int64_t>(0, c[2] - 1); z <= std::min(g.n[2] - 1, c[2] + 1); ++z)
    for (int64_t y = std::max<int64_t>(0, c[1] - 1); y <= std::min(g.n[1] - 1, c[1] + 1); ++y)
      for (int64_t x = std::max<int64_t>(0, c[0] - 1); x <= std::min(g.n[0] - 1, c[0] + 1); ++x) {
        const int64_t cell = (z * g.n[1] + y) * g.n[0] + x;
        for (uint64_t s = g.start[cell]; s < g.start[cell + 1]; ++s) {
          const uint32_t j = g.order[s];
          if (j != i && norm2(points[j] - p) <= r2) visit(j);
        }
      }
}

void fill_reference_data(Bonds& b, const std::vector<Vec3>& points, const std::vector<double>& volume) {
  const std::size_t n = b.particles();
  b.length.resize(b.size());
  b.volume.resize(b.size());
  b.weight.assign(b.size(), 1.0);
  b.intact.assign(b.size(), 1);
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i)
    for (uint64_t k = b.begin(i); k < b.end(i); ++k) {
      b.length[k] = norm(points[b.nbr[k]] - points[i]);
      b.volume[k] = volume[b.nbr[k]];
    }
}

}  // namespace

Bonds find_neighbors(const std::vector<Vec3>& points, const std::vector<double>& volume, double radius) {
  if (points.size() >= (1ull << 32)) throw Error("more than 2^32 particles on one process");
  const double r2 = radius * radius * (1 + 2 * kRadiusTolerance);
  const CellGrid g = make_grid(points, radius);
  const std::size_t n = points.size();
  Bonds b;
  b.offset.assign(n + 1, 0);
  // Pass 1 counts, pass 2 fills: no per-particle allocation, memory exactly O(bonds).
#pragma omp parallel for schedule(dynamic, 1024)
  for (std::size_t i = 0; i < n; ++i) {
    uint64_t count = 0;
    for_each_neighbor(g, points, i, r2, [&](uint32_t) { ++count; });
    b.offset[i + 1] = count;
  }
  for (std::size_t i = 0; i < n; ++i) b.offset[i + 1] += b.offset[i];
  b.nbr.resize(b.offset[n]);
#pragma omp parallel for schedule(dynamic, 1024)
  for (std::size_t i = 0; i < n; ++i) {
    uint64_t k = b.offset[i];
    for_each_neighbor(g, points, i, r2, [&](uint32_t j) { b.nbr[k++] = j; });
    std::sort(b.nbr.begin() + static_cast<int64_t>(b.offset[i]), b.nbr.begin() + static_cast<int64_t>(k));
  }
  fill_reference_data(b, points, volume);
  return b;
}

Bonds find_neighbors_brute_force(const std::vector<Vec3>& points, const std::vector<double>& volume,
                                 double radius) {
  const double r2 = radius * radius * (1 + 2 * kRadiusTolerance);
  Bonds b;
  b.offset.push_back(0);
  for (std::size_t i = 0; i < points.size(); ++i) {
    for (std::size_t j = 0; j < points.size(); ++j)
      if (j != i && norm2(points[j] - points[i]) <= r2) b.nbr.push_back(static_cast<uint32_t>(j));
    b.offset.push_back(b.nbr.size());
  }
  fill_reference_data(b, points, volume);
  return b;
}

void apply_partial_volume(Bonds& bonds, double horizon, double spacing) {
  for (std::size_t k = 0; k < bonds.size(); ++k) {
    const double r = bonds.length[k];
    if (r > horizon - 0.5 * spacing) bonds.volume[k] *= std::clamp((horizon + 0.5 * spacing - r) / spacing, 0.0, 1.0);
  }
}

}  // namespace horizon
