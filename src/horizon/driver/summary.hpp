#pragma once
// The part of summary.json every solver writes the same way: what ran, on what, and
// how it ended. Each driver adds its own figures after these.
#include <nlohmann/json.hpp>
#include <string>

#include "horizon/core/version.hpp"
#include "horizon/deck/config.hpp"
#include "horizon/solver/system.hpp"

namespace horizon {

struct DamageStats {
  double mean = 0, max = 0;
};

inline DamageStats damage_stats(const Particles& p) {
  DamageStats d;
  for (double v : p.damage) {
    d.mean += v;
    d.max = std::max(d.max, v);
  }
  d.mean /= static_cast<double>(std::max<std::size_t>(1, p.size()));
  return d;
}

inline nlohmann::ordered_json summary_header(const Config& config, const System& s, const std::string& status,
                                             const std::string& message, int64_t steps) {
  nlohmann::ordered_json j;
  j["horizon_version"] = version_string;
  j["deck"] = config.deck_file;
  j["status"] = status;
  if (!message.empty()) j["message"] = message;
  j["dimension"] = config.dimension;
  j["particles"] = s.particles.size();
  j["bonds"] = s.initial_bonds;
  j["steps"] = steps;
  return j;
}

}  // namespace horizon
