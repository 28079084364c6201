#include "horizon/geometry/region_select.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace horizon {

namespace {
// Distance from x to [lo, hi]; 0 inside.
double gap(double x, double lo, double hi) { return std::max({lo - x, x - hi, 0.0}); }

// Whether particle x lies less than one spacing from the box along every axis.
bool near_box(const Box3& box, const Vec3& x, int dimension, double spacing) {
  for (int k = 0; k < dimension; ++k)
    if (!(gap(x[k], box.min[k], box.max[k]) < spacing)) return false;
  return true;
}
}  // namespace

std::vector<uint32_t> particles_inside(const Shape& region, const std::vector<Vec3>& X) {
  std::vector<uint32_t> ids;
  for (std::size_t i = 0; i < X.size(); ++i)
    if (region.contains(X[i])) ids.push_back(static_cast<uint32_t>(i));
  return ids;
}

bool selects_nearest_layer(const Shape& region) { return region.kind() == Shape::Kind::box; }

Vec3 nearest_layer_gaps(const Box3& box, const std::vector<Vec3>& X, int dimension, double spacing) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  Vec3 g{inf, inf, inf};
  for (int k = dimension; k < 3; ++k) g[k] = 0;  // axes the deck does not have
  for (const Vec3& x : X)
    if (near_box(box, x, dimension, spacing))
      for (int k = 0; k < dimension; ++k) g[k] = std::min(g[k], gap(x[k], box.min[k], box.max[k]));
  return g;
}

std::vector<uint32_t> particles_nearest(const Box3& box, const std::vector<Vec3>& X, int dimension, double spacing,
                                        const Vec3& gaps) {
  std::vector<uint32_t> ids;
  for (int k = 0; k < dimension; ++k)
    if (!std::isfinite(gaps[k])) return ids;
  // Layers of one lattice lie a spacing apart: a millionth of it tells the nearest layer
  // from the next one, and keeps both of two layers equally near (a tie) despite rounding.
  const double tie = 1e-6 * spacing;
  for (std::size_t i = 0; i < X.size(); ++i) {
    if (!near_box(box, X[i], dimension, spacing)) continue;
    bool nearest = true;
    for (int k = 0; k < dimension && nearest; ++k) nearest = gap(X[i][k], box.min[k], box.max[k]) <= gaps[k] + tie;
    if (nearest) ids.push_back(static_cast<uint32_t>(i));
  }
  return ids;
}

std::vector<uint32_t> select_region(const Shape& region, const std::vector<Vec3>& X, int dimension, double spacing) {
  std::vector<uint32_t> ids = particles_inside(region, X);
  if (!ids.empty() || !selects_nearest_layer(region)) return ids;
  const Box3 box = region.bounds();
  return particles_nearest(box, X, dimension, spacing, nearest_layer_gaps(box, X, dimension, spacing));
}

}  // namespace horizon
