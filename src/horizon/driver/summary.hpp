#pragma once
// The part of summary.json every solver writes the same way: what ran, on what, and
// how it ended. Each driver adds its own figures after these.
#include <fmt/format.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "horizon/core/version.hpp"
#include "horizon/deck/config.hpp"
#include "horizon/loading/loads.hpp"
#include "horizon/solver/explicit.hpp"
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

// Each body's centre-of-mass velocity, sum rho V v / sum rho V over its particles
// (history.csv's NAME_vx... columns and summary.json's "bodies"; a projectile's residual
// velocity). A body with no particles (an FE body) reads zero.
inline std::vector<Vec3> body_velocities(const System& s) {
  const Particles& p = s.particles;
  std::vector<Vec3> momentum(s.block_names.size());
  std::vector<double> mass(s.block_names.size(), 0.0);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto b = static_cast<std::size_t>(p.block[i]);
    if (b >= mass.size()) continue;
    const double m = p.density[i] * p.volume[i];
    momentum[b] += p.v[i] * m;
    mass[b] += m;
  }
  for (std::size_t b = 0; b < mass.size(); ++b)
    if (mass[b] > 0) momentum[b] = momentum[b] * (1.0 / mass[b]);
  return momentum;
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

// The state at the end of a run: the energy ledger, damage and the reaction of each load.
inline void summary_state(nlohmann::ordered_json& j, const System& s, const Ledger& g, const Loads& loads,
                          double max_balance_error) {
  const DamageStats d = damage_stats(s.particles);
  j["energy"] = {{"initial", g.initial},       {"kinetic", g.kinetic},       {"strain", g.strain},
                 {"external_work", g.external_work}, {"dissipated", g.dissipated}, {"damped", g.damped},
                 {"balance_error", g.balance_error()}, {"max_abs_balance_error", max_balance_error}};
  // The parts of the dissipated energy that models report as fields of accumulated
  // density [J/m^3] (ModelField::dissipation_part), in J.
  {
    std::vector<ModelField> fields;
    for (const auto& m : s.models) m->fields(s, fields);
    nlohmann::ordered_json parts = nlohmann::ordered_json::object();
    for (const auto& f : fields) {
      // Once per name (as the frames): each field holds every particle of its model.
      if (!f.dissipation_part || parts.contains(f.name)) continue;
      double sum = 0.0;
      for (std::size_t i = 0; i < f.values.size() && i < s.particles.size(); ++i)
        sum += f.values[i] * s.particles.volume[i];
      parts[f.name] = sum;
    }
    if (!parts.empty()) j["energy"]["dissipated_parts"] = parts;
  }
  j["damage"] = {{"mean", d.mean},
                 {"max", d.max},
                 {"broken_bonds", s.broken},
                 {"broken_fraction", s.initial_bonds ? static_cast<double>(s.broken) / static_cast<double>(s.initial_bonds) : 0.0}};
  nlohmann::ordered_json reactions = nlohmann::ordered_json::object();
  for (const auto& L : loads.loads()) reactions[L.name] = {L.reaction.x, L.reaction.y, L.reaction.z};
  j["loads"] = reactions;
  if (s.block_names.size() > 1) {
    nlohmann::ordered_json bodies = nlohmann::ordered_json::object();
    const std::vector<Vec3> v = body_velocities(s);
    for (std::size_t b = 0; b < v.size(); ++b) bodies[s.block_names[b]] = {{"velocity", {v[b].x, v[b].y, v[b].z}}};
    j["bodies"] = bodies;
  }
}

// The warning of a run whose largest |energy balance error| (Ledger::balance_error, a
// fraction of the largest energy in play) exceeded solver.energy_balance_warning; empty
// when it did not. The drivers print it and list it under "warnings" in summary.json.
inline std::string energy_balance_warning(const Config& config, double max_abs_balance_error) {
  const double limit = config.solver.energy_balance_warning;
  if (!(max_abs_balance_error > limit)) return "";
  return fmt::format("the energy balance error reached {:.3g} % of the largest energy, above "
                     "solver.energy_balance_warning ({:.3g} %): the results may be wrong (a time step too large "
                     "for the loads or the stiffness, or energy leaving the ledger); history.csv has the error "
                     "step by step",
                     100 * max_abs_balance_error, 100 * limit);
}

}  // namespace horizon
