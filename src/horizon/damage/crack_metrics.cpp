#include "horizon/damage/crack_metrics.hpp"

#include "horizon/core/cell_key.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <unordered_map>
#include <vector>

namespace horizon {

namespace {
// Sideways unit vector in the x-y plane (cracks are tracked in 2-D projection).
Vec3 sideways(const Vec3& d) { return {-d.y, d.x, 0}; }
}  // namespace

std::vector<uint8_t> connected_crack(const Particles& p, const Vec3& origin, double threshold, double seed,
                                     double link) {
  std::vector<uint8_t> on(p.size(), 0);
  // Cell lists of the cracked particles, cells of edge `link` (a neighbour within `link`
  // lies in the same or an adjacent cell).
  auto cell_of = [&](const Vec3& x) {
    return std::array<int64_t, 3>{cell_coord(x.x, link), cell_coord(x.y, link), cell_coord(x.z, link)};
  };
  std::unordered_map<uint64_t, std::vector<std::size_t>> cells;
  std::vector<std::size_t> stack;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.damage[i] < threshold) continue;
    const auto c = cell_of(p.X[i]);
    cells[pack_cell(c[0], c[1], c[2])].push_back(i);
    if (norm(p.X[i] - origin) <= seed) {
      on[i] = 1;
      stack.push_back(i);
    }
  }
  const double link2 = link * link;
  while (!stack.empty()) {
    const std::size_t i = stack.back();
    stack.pop_back();
    const auto c = cell_of(p.X[i]);
    for (int64_t a = -1; a <= 1; ++a)
      for (int64_t b = -1; b <= 1; ++b)
        for (int64_t d = -1; d <= 1; ++d) {
          const auto it = cells.find(pack_cell(c[0] + a, c[1] + b, c[2] + d));
          if (it == cells.end()) continue;
          for (const std::size_t j : it->second) {
            if (on[j]) continue;
            const Vec3 r = p.X[j] - p.X[i];
            if (dot(r, r) > link2) continue;
            on[j] = 1;
            stack.push_back(j);
          }
        }
  }
  return on;
}

CrackFront crack_front(const Particles& p, const Vec3& origin, const Vec3& direction, double threshold, double band,
                       const std::vector<uint8_t>* mask) {
  CrackFront front;
  const Vec3 side = sideways(direction);
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.damage[i] < threshold) continue;
    if (mask && !(*mask)[i]) continue;
    const Vec3 r = p.X[i] - origin;
    const double along = dot(r, direction);
    if (along < 0 || std::abs(dot(r, side)) > band) continue;
    if (!front.found || along > front.length) {
      front.found = true;
      front.length = along;
      front.tip = p.X[i];
    }
  }
  return front;
}

std::optional<double> branch_distance(const Particles& p, const Vec3& origin, const Vec3& direction, double threshold,
                                      double slice, double gap, const std::vector<uint8_t>* mask) {
  const Vec3 side = sideways(direction);
  std::map<int64_t, std::vector<double>> slices;  // slice index -> sideways offsets
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.damage[i] < threshold) continue;
    if (mask && !(*mask)[i]) continue;
    const Vec3 r = p.X[i] - origin;
    const double along = dot(r, direction);
    if (along < 0) continue;
    slices[static_cast<int64_t>(std::floor(along / slice))].push_back(dot(r, side));
  }
  auto clusters = [&](std::vector<double>& ys) {
    std::sort(ys.begin(), ys.end());
    int count = ys.empty() ? 0 : 1;
    for (std::size_t k = 1; k < ys.size(); ++k)
      if (ys[k] - ys[k - 1] > gap) ++count;
    return count;
  };
  // The branch starts at the first slice from which `kRun` consecutive slices are all
  // split; shorter split runs are noise (a rough crack face, a stray broken bond).
  constexpr int kRun = 4;
  int run = 0;
  int64_t first = 0, previous = 0;
  for (auto& [index, ys] : slices) {
    const bool split = clusters(ys) >= 2;
    if (split && run > 0 && index == previous + 1) {
      ++run;
    } else if (split) {
      run = 1;
      first = index;
    } else {
      run = 0;
    }
    previous = index;
    if (run >= kRun) return static_cast<double>(first) * slice;
  }
  return std::nullopt;
}

LineCracks cracks_across_line(const std::vector<Vec3>& points, const std::vector<double>& damage, int along,
                              int normal, double at, double tol, double threshold, double merge) {
  std::vector<std::pair<double, double>> line;  // (position, damage)
  for (std::size_t i = 0; i < points.size(); ++i)
    if (std::abs(points[i][normal] - at) <= tol) line.emplace_back(points[i][along], damage[i]);
  std::sort(line.begin(), line.end());
  LineCracks out;
  double sum = 0, weight = 0;
  auto close = [&]() {
    if (weight <= 0) return;
    const double x = sum / weight;
    if (!out.positions.empty() && x - out.positions.back() < merge)
      out.positions.back() = 0.5 * (out.positions.back() + x);
    else
      out.positions.push_back(x);
    sum = weight = 0;
  };
  for (const auto& [x, d] : line) {
    if (d >= threshold) {
      sum += x * d, weight += d;
    } else if (weight > 0) {
      close();
    }
  }
  close();
  if (out.positions.size() >= 2) {
    out.mean_spacing = (out.positions.back() - out.positions.front()) / static_cast<double>(out.positions.size() - 1);
    std::vector<double> gaps;
    for (std::size_t k = 1; k < out.positions.size(); ++k) gaps.push_back(out.positions[k] - out.positions[k - 1]);
    std::sort(gaps.begin(), gaps.end());
    const std::size_t m = gaps.size();
    out.median_spacing = m % 2 ? gaps[m / 2] : 0.5 * (gaps[m / 2 - 1] + gaps[m / 2]);
  }
  return out;
}

}  // namespace horizon
