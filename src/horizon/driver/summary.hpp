#pragma once
// The part of summary.json every solver writes the same way: what ran, on what, and
// how it ended. Each driver adds its own figures after these.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "horizon/core/version.hpp"
#include "horizon/deck/config.hpp"
#include "horizon/loading/loads.hpp"
#include "horizon/parallel/decomposition.hpp"
#include "horizon/solver/explicit.hpp"
#include "horizon/solver/build.hpp"

namespace horizon {

struct DamageStats {
  double mean = 0, max = 0;
};

// The particles of the whole system: with local particles (parallel/decomposition.hpp)
// more than this rank holds.
inline std::size_t global_particle_count(const System& s) {
  const Decomposition* d = s.decomposition;
  return d && d->local_particles ? static_cast<std::size_t>(d->global_particles) : s.particles.size();
}

// Calls f(i) for each particle whose terms this rank adds to a global sum: its owned
// ones when the run is decomposed (GridSum adds the other ranks'), else every one.
template <class F>
void for_each_summed(const System& s, F f) {
  if (s.decomposition)
    for (uint32_t i : s.owned) f(i);
  else
    for (std::size_t i = 0; i < s.particles.size(); ++i) f(i);
}

// The mean and the largest damage of the whole system (history.csv's damage_mean and
// damage_max, summary.json's "damage"). The sum is an exact grid sum (GridSum::exact,
// parallel/decomposition.hpp) on every path, so the serial program and any rank count give
// the same bits without gathering the particles; the maximum is taken over the ranks.
// Collective when decomposed.
inline DamageStats damage_stats(const System& s) {
  const Particles& p = s.particles;
  GridSum sum = GridSum::exact(s, 1);
  double most = 0;
  for_each_summed(s, [&](std::size_t i) {
    sum.add(0, p.damage[i]);
    most = std::max(most, p.damage[i]);
  });
  DamageStats d;
  d.mean = sum.totals()[0] / static_cast<double>(std::max<std::size_t>(1, global_particle_count(s)));
  d.max = s.decomposition ? -min_over_ranks(-most) : most;  // damage >= 0: the maximum, exactly
  return d;
}

// Each body's centre-of-mass velocity, sum rho V v / sum rho V over its particles
// (history.csv's NAME_vx... columns and summary.json's "bodies"; a projectile's residual
// velocity). A body with no particles (an FE body) reads zero. Both sums are exact grid
// sums as in damage_stats. Collective when decomposed.
inline std::vector<Vec3> body_velocities(const System& s) {
  const Particles& p = s.particles;
  const std::size_t bodies = s.block_names.size();
  GridSum sum = GridSum::exact(s, static_cast<int>(4 * bodies));  // per body: momentum x, y, z and mass
  for_each_summed(s, [&](std::size_t i) {
    const auto b = static_cast<std::size_t>(p.block[i]);
    if (b >= bodies) return;
    const double m = p.density[i] * p.volume[i];
    sum.add(static_cast<int>(4 * b), p.v[i] * m);
    sum.add(static_cast<int>(4 * b + 3), m);
  });
  const std::vector<double> t = sum.totals();
  std::vector<Vec3> momentum(bodies);
  for (std::size_t b = 0; b < bodies; ++b)
    if (t[4 * b + 3] > 0) momentum[b] = Vec3{t[4 * b], t[4 * b + 1], t[4 * b + 2]} * (1.0 / t[4 * b + 3]);
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
  j["particles"] = global_particle_count(s);
  j["bonds"] = s.initial_bonds;
  j["steps"] = steps;
  return j;
}

// The terms Ledger::balance_error counts in this run, by their names in summary.json's
// `energy` (the projectiles' kinetic energy is in `kinetic`, the contact pair's work in
// `external_work`).
inline std::vector<std::string> balance_terms(const System& s) {
  std::vector<std::string> terms = {"kinetic", "strain", "dissipated", "damped", "initial", "external_work"};
  if (s.heat.active()) terms.push_back("thermal_work");
  if (s.fe) terms.push_back("fe_coupling_work");
  return terms;
}

// The state at the end of a run: the energy ledger, damage and the reaction of each load.
// Collective when decomposed (damage_stats, body_velocities); s.broken is the whole
// system's count then (gather_state).
inline void summary_state(nlohmann::ordered_json& j, const System& s, const Ledger& g, const Loads& loads,
                          double max_balance_error) {
  const DamageStats d = damage_stats(s);
  j["energy"] = {{"initial", g.initial},       {"kinetic", g.kinetic},       {"strain", g.strain},
                 {"external_work", g.external_work}, {"dissipated", g.dissipated}, {"damped", g.damped},
                 {"balance_error", g.balance_error()}, {"max_abs_balance_error", max_balance_error}};
  // The balance's other terms, where the run books them (Ledger::balance_error counts every
  // one): the thermal strain's work and the finite-element coupling's work; then the names
  // of the terms the balance counts in this run, and of those it leaves out (none).
  if (s.heat.active()) j["energy"]["thermal_work"] = g.thermal_work;
  if (s.fe) j["energy"]["fe_coupling_work"] = g.coupling_work;
  j["energy"]["balance_terms"] = balance_terms(s);
  j["energy"]["terms_left_out"] = nlohmann::ordered_json::array();
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
inline std::string energy_balance_warning(const Config& config, const System& s, double max_abs_balance_error) {
  const double limit = config.solver.energy_balance_warning;
  if (!(max_abs_balance_error > limit)) return "";
  return fmt::format("the energy balance error reached {:.3g} % of the largest energy, above "
                     "solver.energy_balance_warning ({:.3g} %): the results may be wrong (a time step too large "
                     "for the loads or the stiffness, or energy leaving the ledger); the balance counts {} "
                     "(summary.json energy.balance_terms) and leaves out none; history.csv has the error step by step",
                     100 * max_abs_balance_error, 100 * limit, fmt::join(balance_terms(s), ", "));
}

}  // namespace horizon
