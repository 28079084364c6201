#include "horizon/damage/crack_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

namespace horizon {

namespace {
// Sideways unit vector in the x-y plane (cracks are tracked in 2-D projection).
Vec3 sideways(const Vec3& d) { return {-d.y, d.x, 0}; }
}  // namespace

CrackFront crack_front(const Particles& p, const Vec3& origin, const Vec3& direction, double threshold, double band) {
  CrackFront front;
  const Vec3 side = sideways(direction);
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.damage[i] < threshold) continue;
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
                                      double slice, double gap) {
  const Vec3 side = sideways(direction);
  std::map<int64_t, std::vector<double>> slices;  // slice index -> sideways offsets
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.damage[i] < threshold) continue;
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

}  // namespace horizon
