#pragma once
// The crack figures of a run's summary (driver/explicit_summary.cpp): the crack grown
// from the first precrack, tracked over the run (CrackTracker), its speed, and the edge
// cracks of a thermal shock. They read the damage field alone (damage/crack_metrics.hpp).
#include <cstdint>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "horizon/damage/crack_metrics.hpp"
#include "horizon/deck/config.hpp"
#include "horizon/state/system.hpp"

namespace horizon {

struct Decomposition;

// Crack tracking for decks with precracks: the front of the damage grown from the
// first precrack's second point, along that precrack. A particle is cracked at damage
// >= kCrackDamage; the crack is the cracked particles joined to the precrack's tip
// (within one horizon of it) through hops of at most 1.5 spacings (connected_crack), so
// damage elsewhere (under an impactor) does not count. Its length is the furthest such
// particle's distance from the tip, measured along the precrack's direction.
constexpr double kCrackDamage = 0.35;

struct CrackTracker {
  bool active = false;
  Vec3 origin, direction;
  double band = 0, seed = 0, link = 0;
  std::vector<std::pair<double, double>> history;  // (time, length)

  std::vector<uint8_t> path(const System& s) const {
    return connected_crack(s.particles, origin, kCrackDamage, seed, link);
  }
  CrackFront front(const System& s, const std::vector<uint8_t>& on) const {
    return crack_front(s.particles, origin, direction, kCrackDamage, band, &on);
  }

  CrackTracker(const Config& c) {
    bool damage = false;
    for (const auto& m : c.materials) damage = damage || m.damage.enabled;
    if (!damage || c.precracks.empty() || c.precracks[0].points.size() < 2) return;
    const auto& pts = c.precracks[0].points;
    origin = pts[1];
    direction = pts[1] - pts[0];
    direction.z = 0;
    if (norm(direction) == 0) return;
    direction = direction / norm(direction);
    band = 1e300;
    seed = c.horizon;
    link = 1.5 * c.spacing;
    active = true;
  }
  void record(const System& s, double t) {
    if (!active) return;
    const CrackFront f = front(s, path(s));
    history.emplace_back(t, f.found ? f.length : 0.0);
  }
};

// Least-squares slope of length against time over samples with t in [t0, t1].
double fitted_speed(const std::vector<std::pair<double, double>>& h, double l0, double l1);

// Thermal shock figures (2-D): for each thermal boundary condition, the cracks crossing
// the lattice row 2 horizons inside its layer (damage >= kCrackDamage; cracks closer than
// 2 horizons count as one), their positions along the layer and their spacing
// (damage/crack_metrics.hpp, cracks_across_line).
// Every particle is read once, streamed through rank 0 in global order (stream_on_lead:
// O(N / ranks) held there, collective): first each layer's extent and mean position and the
// body's centre, then, on rank 0, the particles of each measuring row (a lattice row: small
// by nature), whose damage decides where a crack crosses. Returns the figures on rank 0
// (an empty object elsewhere).
nlohmann::ordered_json edge_cracks(const Config& c, const System& s, const Decomposition* d);

}  // namespace horizon
