#include "horizon/geometry/lattice.hpp"

#include <cmath>
#include <unordered_set>

#include "horizon/core/error.hpp"

namespace horizon {

namespace {
// Integer lattice coordinates, to detect overlaps between bodies. Three full indices
// (an index may lie far from 0 when lattice_origin is far from the body).
struct LatticeKey {
  int64_t i, j, k;
  bool operator==(const LatticeKey&) const = default;
};
struct LatticeKeyHash {
  std::size_t operator()(const LatticeKey& p) const {
    const uint64_t h = static_cast<uint64_t>(p.i) * 0x9E3779B97F4A7C15ull ^
                       static_cast<uint64_t>(p.j) * 0xC2B2AE3D27D4EB4Full ^ static_cast<uint64_t>(p.k) * 0x165667B19E3779F9ull;
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};
LatticeKey pack(int64_t i, int64_t j, int64_t k) { return {i, j, k}; }

// Lattice coordinates beyond this are refused: their products with the spacing would
// lose the unit digit, and the casts below would overflow.
constexpr double kMaxIndex = 1e15;
}  // namespace

std::size_t fill_shape(Particles& particles, const Shape& shape, const LatticeSpec& spec, double density,
                       int32_t block, int32_t material) {
  if (shape.kind() == Shape::Kind::points) {
    // Listed particles: each point as given, with its own volume (no lattice).
    const auto& at = shape.point_list();
    const auto& vol = shape.point_volumes();
    for (std::size_t i = 0; i < at.size(); ++i)
      particles.add(at[i], i < vol.size() ? vol[i] : spec.cell_volume, density, block, material);
    return at.size();
  }
  const Box3 box = shape.bounds();
  const double h = spec.spacing;
  const int d = spec.dimension;
  for (int k = 0; k < d; ++k)
    if (!(std::abs(box.min[k]) < 1e100 && std::abs(box.max[k]) < 1e100))
      throw Error("a body's shape is unbounded (a half space must be intersected with a bounded shape)");

  // Lattice: x = origin + n*h. Default origin puts points at cell centres of a grid
  // that starts at the box minimum, so a box of length L holds L/h points exactly.
  Vec3 origin = spec.origin ? *spec.origin : box.min + Vec3{0.5 * h, 0.5 * h, 0.5 * h};
  int64_t lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  for (int k = 0; k < d; ++k) {
    const double from = (box.min[k] - origin[k]) / h, to = (box.max[k] - origin[k]) / h;
    if (!(std::abs(from) < kMaxIndex && std::abs(to) < kMaxIndex))
      throw Error("the lattice is too large: a body lies more than 1e15 spacings from the lattice origin");
    lo[k] = static_cast<int64_t>(std::floor(from)) - 1;
    hi[k] = static_cast<int64_t>(std::ceil(to)) + 1;
    const double count = static_cast<double>(hi[k] - lo[k]);
    if (count > 2e6) throw Error("the lattice is too large: more than 2e6 points along one axis");
  }
  // Particles already present on the same lattice are skipped (first body wins).
  std::unordered_set<LatticeKey, LatticeKeyHash> taken;
  // (A particle far off this lattice cannot coincide with one of its points: skipped.)
  for (std::size_t p = 0; p < particles.size(); ++p) {
    int64_t idx[3] = {0, 0, 0};
    bool near = true;
    for (int k = 0; k < d; ++k) {
      const double v = std::round((particles.X[p][k] - origin[k]) / h);
      near = near && std::abs(v) < kMaxIndex;
      if (near) idx[k] = static_cast<int64_t>(v);
    }
    if (near) taken.insert(pack(idx[0], idx[1], idx[2]));
  }

  std::size_t added = 0;
  for (int64_t k = lo[2]; k <= hi[2]; ++k)
    for (int64_t j = lo[1]; j <= hi[1]; ++j)
      for (int64_t i = lo[0]; i <= hi[0]; ++i) {
        Vec3 x{origin.x + static_cast<double>(i) * h, 0, 0};
        if (d > 1) x.y = origin.y + static_cast<double>(j) * h;
        if (d > 2) x.z = origin.z + static_cast<double>(k) * h;
        if (!shape.contains(x)) continue;
        if (!taken.insert(pack(i, j, k)).second) continue;
        particles.add(x, spec.cell_volume, density, block, material);
        ++added;
      }
  return added;
}

}  // namespace horizon
