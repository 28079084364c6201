#include "horizon/geometry/lattice.hpp"

#include <cmath>
#include <unordered_set>

#include "horizon/core/error.hpp"

namespace horizon {

namespace {
// Integer lattice coordinates packed into one key, to detect overlaps between bodies.
uint64_t pack(int64_t i, int64_t j, int64_t k) {
  constexpr int64_t kBias = 1 << 20;
  return (static_cast<uint64_t>(i + kBias) << 42) | (static_cast<uint64_t>(j + kBias) << 21) |
         static_cast<uint64_t>(k + kBias);
}
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
    lo[k] = static_cast<int64_t>(std::floor((box.min[k] - origin[k]) / h)) - 1;
    hi[k] = static_cast<int64_t>(std::ceil((box.max[k] - origin[k]) / h)) + 1;
    const double count = static_cast<double>(hi[k] - lo[k]);
    if (count > 2e6) throw Error("the lattice is too large: more than 2e6 points along one axis");
  }
  // Particles already present on the same lattice are skipped (first body wins).
  std::unordered_set<uint64_t> taken;
  auto lattice_index = [&](const Vec3& x, int k) { return std::llround((x[k] - origin[k]) / h); };
  for (std::size_t p = 0; p < particles.size(); ++p)
    taken.insert(pack(lattice_index(particles.X[p], 0), d > 1 ? lattice_index(particles.X[p], 1) : 0,
                      d > 2 ? lattice_index(particles.X[p], 2) : 0));

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
