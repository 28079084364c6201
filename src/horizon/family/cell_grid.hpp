#pragma once
// Uniform grid of cubic cells for fixed-radius neighbour searches: each point's
// neighbours within `radius` lie in its own cell or the 26 adjacent ones. Used by the
// family search (neighbors.cpp) and the contact search (contact/short_range.cpp).
#include <algorithm>
#include <cstdint>
#include <vector>

#include "horizon/core/vec3.hpp"

namespace horizon {

struct CellGrid {
  Vec3 lo;
  double edge = 1;
  int64_t n[3] = {1, 1, 1};
  std::vector<uint64_t> start;  // per cell, into order (counting sort)
  std::vector<uint32_t> order;  // point indices sorted by cell

  int64_t coord(double x, int k) const {
    return std::clamp<int64_t>(static_cast<int64_t>((x - lo[k]) / edge), 0, n[k] - 1);
  }
  int64_t cell(const Vec3& p) const { return (coord(p.z, 2) * n[1] + coord(p.y, 1)) * n[0] + coord(p.x, 0); }

  // Cells of edge >= min_edge covering the points; the edge grows when the box is
  // sparse, so the cell count stays proportional to the number of points.
  template <class Get>
  static CellGrid build(std::size_t count, Get point, double min_edge) {
    CellGrid g;
    Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    for (std::size_t i = 0; i < count; ++i) {
      const Vec3 p = point(i);
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], p[k]);
        hi[k] = std::max(hi[k], p[k]);
      }
    }
    g.lo = lo;
    g.edge = min_edge;
    const double max_cells = 8.0 * static_cast<double>(count) + 64;
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
    std::vector<uint32_t> cell_of(count);
    for (std::size_t i = 0; i < count; ++i) {
      cell_of[i] = static_cast<uint32_t>(g.cell(point(i)));
      ++g.start[cell_of[i] + 1];
    }
    for (std::size_t c = 0; c < ncell; ++c) g.start[c + 1] += g.start[c];
    g.order.resize(count);
    std::vector<uint64_t> fill(g.start.begin(), g.start.end() - 1);
    for (std::size_t i = 0; i < count; ++i) g.order[fill[cell_of[i]]++] = static_cast<uint32_t>(i);
    return g;
  }

  // Calls visit(j) for every point j (j may equal the query's own index) in the cells
  // around p: the candidates within one edge of p.
  template <class Visit>
  void for_each_candidate(const Vec3& p, Visit visit) const {
    const int64_t c[3] = {coord(p.x, 0), coord(p.y, 1), coord(p.z, 2)};
    for (int64_t z = std::max<int64_t>(0, c[2] - 1); z <= std::min(n[2] - 1, c[2] + 1); ++z)
      for (int64_t y = std::max<int64_t>(0, c[1] - 1); y <= std::min(n[1] - 1, c[1] + 1); ++y) {
        // The three cells along x are contiguous in `order`: one scan.
        const int64_t row = (z * n[1] + y) * n[0];
        const uint64_t from = start[static_cast<std::size_t>(row + std::max<int64_t>(0, c[0] - 1))];
        const uint64_t to = start[static_cast<std::size_t>(row + std::min(n[0] - 1, c[0] + 1) + 1)];
        for (uint64_t s = from; s < to; ++s) visit(order[s]);
      }
  }
};

}  // namespace horizon
