#include "horizon/solver/memory_guard.hpp"

#include <fmt/format.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cmath>
#include <numbers>

#include "horizon/core/error.hpp"
#include "horizon/family/neighbors.hpp"

namespace horizon {

namespace {
// Bytes per particle and per directed bond of the largest run layout: the particle
// arrays, model arrays and force scratch (memory_estimate in system.cpp counts ~320 per
// particle), and per bond the neighbour, kind and intact flag (9), the general force
// pass's force state and reverse bond (32), a state-based |Y| (8), with room for a
// model's per-bond history. Generous on purpose: the guard is an upper bound.
constexpr double kBytesPerParticle = 512;
constexpr double kBytesPerBond = 64;
constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;
}  // namespace

MemoryEstimate estimate_memory(const Config& c) {
  MemoryEstimate e;
  const int d = c.dimension;
  const double h = c.spacing;
  for (const auto& body : c.bodies) {
    const Box3 box = body.shape.bounds();
    double points = 1;
    for (int k = 0; k < d; ++k) points *= std::max(0.0, (box.max[k] - box.min[k]) / h) + 3;
    e.particles += points;
  }
  // Lattice points within the family radius of one particle: the volume of the 1-, 2-
  // or 3-ball over the cell.
  const double r = family_radius(c.horizon, h, c.partial_volume.rule) / h + 1;
  const double family = d == 1 ? 2 * r : d == 2 ? std::numbers::pi * r * r : 4.0 / 3.0 * std::numbers::pi * r * r * r;
  e.bonds = e.particles * family;
  e.bytes = e.particles * kBytesPerParticle + e.bonds * kBytesPerBond;
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

void check_memory(const Config& c, double limit_bytes) {
  const bool machine = limit_bytes <= 0;
  const double limit = machine ? machine_memory_bytes() : limit_bytes;
  if (limit <= 0) return;  // the machine does not say
  const MemoryEstimate e = estimate_memory(c);
  // Particle indices are 32-bit (family/bonds.hpp): more particles cannot be built at all.
  if (e.particles >= 4.0e9) {
    throw Error(fmt::format("{}: the deck would make about {:.3g} particles (spacing {:g} m), more than the 4e9 a "
                            "run can index; use a larger spacing or smaller bodies",
                            c.deck_file, e.particles, c.spacing));
  }
  if (e.bytes <= limit) return;
  throw Error(fmt::format(
      "{}: the deck needs about {:.3g} GiB ({:.3g} particles, {:.3g} bonds at spacing {:g} m, horizon {:g} m), "
      "more than the {:.3g} GiB {}; coarsen it (a larger spacing, smaller bodies, --coarsen) or, if the "
      "estimate is too pessimistic, raise the limit with --max-memory <GiB>",
      c.deck_file, e.bytes / kGiB, e.particles, e.bonds, c.spacing, c.horizon, limit / kGiB,
      machine ? "of this machine's memory" : "allowed by --max-memory"));
}

}  // namespace horizon
