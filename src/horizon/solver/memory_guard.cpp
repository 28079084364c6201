#include "horizon/solver/memory_guard.hpp"

#include <fmt/format.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numbers>

#include "horizon/core/error.hpp"
#include "horizon/family/neighbors.hpp"
#include "horizon/material/model.hpp"
#include "horizon/solver/build.hpp"

namespace horizon {

namespace {
// Bytes per particle: the particle arrays, model arrays and force scratch
// (memory_estimate in solver/build.cpp counts ~320), with room for a model's own per-particle
// state. Per directed bond (family/bonds.hpp): neighbour, kind and intact flag (9 bytes)
// and a state-based model's |Y| (8), which is all the unified models keep; a model on the
// general force pass adds the force state and reverse bond (32) and its own per-bond
// history (elastic_plastic 56, viscoelastic up to 104): 128 leaves room.
constexpr double kBytesPerParticle = 512;
constexpr double kBytesPerUnifiedBond = 17;
constexpr double kBytesPerBond = 128;
constexpr double kBytesPerKind = sizeof(BondKind) + sizeof(KindCoefficients) + 3 * sizeof(Point4);  // build.cpp kind_bytes
constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;
// Family offsets are counted one by one up to this radius [spacings]; beyond it the
// count is the ball's volume over the cell (its error is below 1 % there).
constexpr double kCountedRadius = 24;

// Lattice points of x = origin + m h within [lo, hi] (at least one).
double points_between(double lo, double hi, double origin, double h) {
  const double a = std::ceil((lo - origin) / h - 1e-9), b = std::floor((hi - origin) / h + 1e-9);
  return std::max(1.0, b - a + 1);
}
}  // namespace

std::vector<LatticeOffset> family_offsets(int dimension, double radius) {
  std::vector<LatticeOffset> out;
  // The neighbour search's acceptance, |xi|^2 <= r^2 (1 + 2e-10) (family/neighbors.cpp).
  const double r2 = radius * radius * (1 + 2e-10);
  const auto m = static_cast<int64_t>(std::floor(radius));
  const int64_t my = dimension > 1 ? m : 0, mz = dimension > 2 ? m : 0;
  for (int64_t z = -mz; z <= mz; ++z)
    for (int64_t y = -my; y <= my; ++y)
      for (int64_t x = -m; x <= m; ++x) {
        if (x == 0 && y == 0 && z == 0) continue;
        if (static_cast<double>(x * x + y * y + z * z) <= r2) out.push_back({x, y, z});
      }
  return out;
}

// The neighbours of an interior particle: counted, or for a large family the ball's
// volume over the cell.
static double interior_family(int dimension, double r) {
  if (r <= kCountedRadius) return static_cast<double>(family_offsets(dimension, r).size());
  return dimension == 1 ? 2 * r : dimension == 2 ? std::numbers::pi * r * r : 4.0 / 3.0 * std::numbers::pi * r * r * r;
}

double box_bonds(const double n[3], int dimension, double radius) {
  if (radius > kCountedRadius) {  // every particle with an interior family (an upper bound)
    double p = 1;
    for (int k = 0; k < dimension; ++k) p *= n[k];
    return p * interior_family(dimension, radius);
  }
  double bonds = 0;
  for (const LatticeOffset& o : family_offsets(dimension, radius)) {
    // The pairs (p, p + o) with both ends in the n[0] x n[1] x n[2] block.
    const int64_t c[3] = {o.x, o.y, o.z};
    double pairs = 1;
    for (int k = 0; k < dimension; ++k) pairs *= std::max(0.0, n[k] - static_cast<double>(std::llabs(c[k])));
    bonds += pairs;
  }
  return bonds;
}

MemoryEstimate estimate_memory(const Config& c) {
  MemoryEstimate e;
  const int d = c.dimension;
  const double h = c.spacing;
  // The family in spacings (family/neighbors.hpp: with the linear partial-volume rule it
  // reaches half a spacing beyond the horizon).
  const double radius = family_radius(c.horizon, h, c.partial_volume.rule) / h;
  double cloud_bonds = 0;  // bonds of listed points (their lengths rarely repeat)
  for (const auto& body : c.bodies) {
    if (body.shape.kind() == Shape::Kind::points) {
      // Listed particles, off any lattice: each with a full interior family.
      const double np = static_cast<double>(body.shape.point_list().size());
      e.particles += np;
      e.bonds += np * interior_family(d, radius);
      cloud_bonds += np * interior_family(d, radius);
      continue;
    }
    // The lattice points of the body's bounding box (geometry/lattice.cpp: the default
    // origin puts them at cell centres from the box minimum) and the bonds among them:
    // for each lattice offset o of the family, prod_k (n_k - |o_k|) pairs. Exact for a box,
    // an upper bound for any other shape (its particles are a subset of the box's).
    const Box3 box = body.shape.bounds();
    const Vec3 origin = c.lattice_origin ? *c.lattice_origin : box.min + Vec3{0.5 * h, 0.5 * h, 0.5 * h};
    double n[3] = {1, 1, 1}, points = 1;
    for (int k = 0; k < d; ++k) {
      const double span = (box.max[k] - box.min[k]) / h;
      n[k] = std::abs(span) < 1e15 ? points_between(box.min[k], box.max[k], origin[k], h) : HUGE_VAL;
      points *= n[k];
    }
    e.particles += points;
    e.bonds += std::isfinite(points) ? box_bonds(n, d, radius) : HUGE_VAL;
  }
  bool unified = true;
  for (const auto& m : c.materials) {
    const ModelEntry* entry = find_model(m.model);
    unified = unified && entry && entry->traits.unified;
  }
  e.bytes = e.particles * kBytesPerParticle + e.bonds * (unified ? kBytesPerUnifiedBond : kBytesPerBond);
  // Listed points are an irregular cloud at worst: every bond its own length, kept per bond
  // (8 bytes, family/bonds.hpp), or, where the deck needs kinds with lengths, about a kind
  // per bond (kBytesPerKind: its reference data and the force loops' tables).
  e.bytes += cloud_bonds * (kinds_need_lengths(c.materials, c) ? kBytesPerKind : sizeof(double));
  if (!std::isfinite(e.bytes)) e.bytes = e.particles = e.bonds = HUGE_VAL;
  return e;
}

double machine_memory_bytes() {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  double bytes = pages > 0 && page > 0 ? static_cast<double>(pages) * static_cast<double>(page) : 0;
  rlimit as{};
  if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY) {
    const double cap = static_cast<double>(as.rlim_cur);
    if (bytes == 0 || cap < bytes) bytes = cap;
  }
  return bytes;
}

void check_memory(const Config& c, double limit_bytes, int ranks) {
  const bool machine = limit_bytes <= 0;
  const double limit = machine ? machine_memory_bytes() : limit_bytes;
  if (limit <= 0) return;  // the machine does not say
  MemoryEstimate e = estimate_memory(c);
  if (ranks > 1 && std::isfinite(e.bytes)) {
    const double bond_bytes = e.bytes - e.particles * kBytesPerParticle;
    e.bonds /= ranks;
    e.bytes = e.particles * kBytesPerParticle + bond_bytes / ranks;
  }
  // Particle indices are 32-bit (family/bonds.hpp): more particles cannot be built at all.
  if (e.particles >= 4.0e9) {
    throw Error(fmt::format("{}: the deck would make about {:.3g} particles (spacing {:g} m), more than the 4e9 a "
                            "run can index; use a larger spacing or smaller bodies",
                            c.deck_file, e.particles, c.spacing));
  }
  if (e.bytes <= limit) return;
  throw Error(fmt::format(
      "{}: the deck needs about {:.3g} GiB{} ({:.3g} particles, {:.3g} bonds at spacing {:g} m, horizon {:g} m), "
      "more than the {:.3g} GiB {}; coarsen it (a larger spacing, smaller bodies, --coarsen) or, if the "
      "estimate is too pessimistic, raise the limit with --max-memory <GiB>",
      c.deck_file, e.bytes / kGiB, ranks > 1 ? fmt::format(" per rank on {} ranks", ranks) : std::string(), e.particles, e.bonds, c.spacing, c.horizon, limit / kGiB,
      machine ? "of this machine's memory" : "allowed by --max-memory"));
}

}  // namespace horizon
