// The end of the explicit run (ExplicitRun::finish): history.csv and summary.json with
// the final figures, the run statistics, the crack and fracture figures.
#include <fmt/format.h>
#include <omp.h>
#include <sys/resource.h>
#include <zlib.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "horizon/damage/crack_angle.hpp"
#include "horizon/damage/crack_tracking.hpp"
#include "horizon/driver/explicit_state.hpp"
#include "horizon/fe/fe_region.hpp"
#include "horizon/parallel/lead_view.hpp"

namespace horizon {

namespace fs = std::filesystem;

// CPU time of the process so far (all threads) [s]: with the wall time, it tells how
// much of the machine a run had (benchmarks on shared machines).
double cpu_seconds() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return static_cast<double>(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
}

double peak_memory_bytes() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return static_cast<double>(ru.ru_maxrss) * 1024.0;
}

// state_digest of a run with local particles, on rank 0 (others get 0), without the
// whole state on rank 0: u, v and damage stream through it a slice of global ids at a
// time (parallel/lead_view.hpp) into three CRCs, joined as the CRC of u, then v, then
// damage of every particle (zlib crc32_combine). The one figure that reads every
// particle; at the end of the run only. Collective.
static uint32_t streamed_state_digest(const System& s, const Decomposition& d) {
  uLong crc[3] = {crc32(0L, Z_NULL, 0), crc32(0L, Z_NULL, 0), crc32(0L, Z_NULL, 0)};
  stream_on_lead(
      s, &d, 7,
      [&](uint32_t i, std::vector<double>& v) {
        const auto& P = s.particles;
        v.insert(v.end(), {P.u[i].x, P.u[i].y, P.u[i].z, P.v[i].x, P.v[i].y, P.v[i].z, P.damage[i]});
      },
      [&](std::size_t, const double* v) {
        static_assert(sizeof(Vec3) == 3 * sizeof(double));
        crc[0] = crc32(crc[0], reinterpret_cast<const Bytef*>(v), 3 * sizeof(double));
        crc[1] = crc32(crc[1], reinterpret_cast<const Bytef*>(v + 3), 3 * sizeof(double));
        crc[2] = crc32(crc[2], reinterpret_cast<const Bytef*>(v + 6), sizeof(double));
      });
  const auto n = static_cast<z_off_t>(d.global_particles);
  const uLong uv = crc32_combine(crc[0], crc[1], n * static_cast<z_off_t>(sizeof(Vec3)));
  return static_cast<uint32_t>(crc32_combine(uv, crc[2], n * static_cast<z_off_t>(sizeof(double))));
}

uint32_t state_digest(const System& s) {
  const auto& P = s.particles;
  uLong crc = crc32(0L, Z_NULL, 0);
  auto add = [&](const void* p, std::size_t bytes) {
    crc = crc32(crc, static_cast<const Bytef*>(p), static_cast<uInt>(bytes));
  };
  add(P.u.data(), P.u.size() * sizeof(Vec3));
  add(P.v.data(), P.v.size() * sizeof(Vec3));
  add(P.damage.data(), P.damage.size() * sizeof(double));
  return static_cast<uint32_t>(crc);
}

int ExplicitRun::finish() {
  State& r = *st_;
  if (r.finished) return r.exit_code;
  r.stopped = true;
  r.finished = true;
  if (r.backend) r.backend->copy_fields();  // the final frame and the summary read the System
  const Config& config = r.config;
  const RunOptions& options = r.options;
  System& s = r.s;
  ExplicitSolver& solver = *r.solver;
  const fs::path& dir = r.dir;
  const std::string& status = r.status;
  const std::string& message = r.message;
  auto& crack = *r.crack;
  if (!options.quiet) r.progress->finish();
  r.sync();
  if ((r.exit_code != 0 && r.exit_code != 5) || status == "stopped") {
    // The last good state (restored by the solver on a non-finite step) as the final frame.
    solver.update_kinetic();
    r.record_history();
    r.write_frame();
  }
  if (options.handle_signals) clear_interrupt();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - r.wall_start).count();
  const double loop_time = r.progress->elapsed();
  const double loop_cpu_time = cpu_seconds() - r.cpu_start;

  // After an output error, history and summary are tried once (they are small) and their
  // failure only reported.
  auto write_result = [&](const std::string& name, const std::string& text) {
    if (!r.lead) return;
    write_result_file((dir / name).string(), text, r.exit_code == 5);
  };
  write_result("history.csv", r.history.str());

  // Summary: final figures and run statistics.
  const Ledger& g = solver.ledger();
  // The crack figures read the cracked particles alone (rank 0's with local particles).
  const System& o = r.cracks();
  nlohmann::ordered_json j = summary_header(config, s, status, message, solver.steps());
  j["time_step"] = solver.dt();
  if (r.adaptive) j["time_step_range"] = {r.dt_min, r.dt_max};
  j["time"] = solver.time();
  if (!r.stage_summary.empty()) j["static_stage"] = r.stage_summary;  // a staged run's first stage
  j["threads"] = omp_get_max_threads();
  j["ranks"] = r.dd ? r.dd->size : 1;
  j["backend"] = r.backend ? r.backend->name() : "cpu";  // solver.backend (solver/backend.hpp)
  j["state_crc32"] = r.local_particles() ? streamed_state_digest(s, *r.dd) : state_digest(s);
  if (r.dd) {
    // Halo traffic per rank and step (docs/benchmarks.md), from every rank.
    const std::vector<HaloStats> hs = gather_halo_stats(*r.dd);
    // The bond rows each rank holds and its peak resident memory.
    const std::vector<uint64_t> held = gather_on_lead(s.bonds.size());
    // The particles each rank integrates and those it holds (with its ghosts).
    const std::vector<uint64_t> owned = gather_on_lead(r.dd->owned.size());
    const std::vector<uint64_t> particles_held = gather_on_lead(s.particles.size());
    // Local particles with short-range contact: the contact ghosts each rank holds
    // outside its system (parallel/decomposition.hpp ContactGhosts), now and at most.
    const std::vector<uint64_t> contact_ghosts = gather_on_lead(r.dd->contact.id.size());
    const std::vector<uint64_t> contact_ghosts_most = gather_on_lead(r.dd->contact.most);
    const std::vector<uint64_t> rss = gather_on_lead(static_cast<uint64_t>(peak_memory_bytes()));
    nlohmann::ordered_json h = nlohmann::ordered_json::array();
    for (std::size_t k = 0; k < hs.size(); ++k) {
      const double steps = static_cast<double>(std::max<uint64_t>(1, hs[k].steps));
      h.push_back({{"rank", k},
                   {"particles", owned[k]},
                   {"particles_held", particles_held[k]},
                   {"contact_ghosts", contact_ghosts[k]},
                   {"contact_ghosts_most", contact_ghosts_most[k]},
                   {"bonds_held", held[k]},
                   {"peak_memory_bytes", rss[k]},
                   {"messages_per_step", static_cast<double>(hs[k].messages) / steps},
                   {"bytes_per_step", static_cast<double>(hs[k].bytes) / steps},
                   {"ghost_rebuilds", hs[k].rebuilds}});
    }
    j["halo"] = h;
    j["bonds_local"] = r.dd->local_rows;
    j["particles_local"] = r.dd->local_particles;
    // With local particles rank 0 holds no copy of the whole system (parallel/lead_view.hpp):
    // the most cracked particles it gathered for the crack figures.
    if (r.local_particles()) j["lead_cracked_particles_most"] = r.cracked_most;
  }
  j["wall_time_s"] = wall;
  j["loop_time_s"] = loop_time;
  j["loop_cpu_time_s"] = loop_cpu_time;
  j["bond_updates_per_second"] =
      loop_time > 0 ? static_cast<double>(checkpoint_bond_count(s)) * static_cast<double>(solver.steps() - r.steps_at_start) / loop_time : 0.0;
  j["peak_memory_bytes"] = peak_memory_bytes();
  if (s.fe) {
    j["fe"] = {{"elements", s.fe->elements()},
               {"element", s.fe->nodes_per_element == 8 ? "hex8" : "tet4"},
               {"nodes", s.fe->nodes()},
               {"shared_nodes", s.fe->shared_nodes()},
               {"coupling_work", s.fe->coupling_work}};
  }
  summary_state(j, s, g, *r.loads, r.max_balance_error);
  if (r.dd && (r.dd->local_particles || r.dd->size > 1)) {
    // Local particles, or a run on several ranks (a model's fields hold its owned
    // particles' values only): the models' dissipation parts (summary_state's sum, in the
    // same global order) from every owner's field values streamed through rank 0.
    std::vector<ModelField> fields;
    for (const auto& m : s.models) m->fields(s, fields);
    nlohmann::ordered_json parts = nlohmann::ordered_json::object();
    std::vector<std::string> done;
    for (const auto& f : fields) {
      if (!f.dissipation_part || std::find(done.begin(), done.end(), f.name) != done.end()) continue;
      done.push_back(f.name);
      double sum = 0.0;
      stream_on_lead(
          s, r.dd.get(), 2,
          [&](uint32_t i, std::vector<double>& v) {
            v.push_back(i < f.values.size() ? f.values[i] : 0.0);
            v.push_back(s.particles.volume[i]);
          },
          [&](std::size_t, const double* v) { sum += v[0] * v[1]; });
      parts[f.name] = sum;
    }
    if (!parts.empty()) j["energy"]["dissipated_parts"] = parts;
  }
  if (!r.loads->projectiles().empty()) {
    nlohmann::ordered_json pj = nlohmann::ordered_json::object();
    for (const auto& p : r.loads->projectiles()) {
      const Vec3 v0 = p.config().velocity;
      pj[p.config().name] = {{"mass", p.mass()},
                             {"position", {p.x.x, p.x.y, p.x.z}},
                             {"velocity", {p.v.x, p.v.y, p.v.z}},
                             {"initial_speed", norm(v0)},
                             {"final_speed", norm(p.v)},
                             {"impulse", {p.impulse.x, p.impulse.y, p.impulse.z}},
                             {"peak_force", p.peak_force},
                             {"peak_acceleration", p.peak_acceleration},
                             {"peak_filtered_acceleration", p.peak_filtered_acceleration},
                             {"filter_cutoff", p.config().filter_cutoff},
                             {"contact_start", p.contact_start},
                             {"contact_end", p.contact_end},
                             {"penalty_energy", p.penalty_energy}};
    }
    j["projectiles"] = pj;
  }
  if (r.heat) {
    j["thermal"] = heat_summary(s, solver.dt() * config.thermal.time_scale, r.heat_stable, r.heat_initial);
    j["energy"]["thermal_work"] = g.thermal_work;
    if (config.dimension == 2 && s.initial_bonds > 0) {
      nlohmann::ordered_json e = edge_cracks(config, s, r.dd.get());  // collective
      if (r.lead) j["thermal"]["edge_cracks"] = std::move(e);
    }
  }
  // The crack path and front at the end, for the crack and fracture figures below.
  const std::vector<uint8_t> on = crack.active ? crack.path(o) : std::vector<uint8_t>{};
  const CrackFront f = crack.active ? crack.front(o, on) : CrackFront{};
  if (crack.active) {
    const auto branch = branch_distance(o.particles, crack.origin, crack.direction, kCrackDamage, config.spacing,
                                        2.0 * config.horizon, &on);
    nlohmann::ordered_json cj;
    cj["origin"] = {crack.origin.x, crack.origin.y, crack.origin.z};
    cj["length"] = f.found ? f.length : 0.0;
    cj["damage_threshold"] = kCrackDamage;
    cj["tip"] = {f.tip.x, f.tip.y, f.tip.z};
    // Speed before branching: fit over the growth from 2 horizons to the branch point.
    const double l_end = branch ? *branch : (f.found ? f.length : 0.0);
    cj["speed_before_branching"] = fitted_speed(crack.history, 2 * config.horizon, l_end);
    if (branch) {
      cj["branch_distance"] = *branch;
      const Vec3 at = crack.origin + crack.direction * *branch;
      cj["branch_point"] = {at.x, at.y, at.z};
      double t_branch = 0;
      for (const auto& [t, l] : crack.history)
        if (l >= *branch) {
          t_branch = t;
          break;
        }
      cj["branch_time"] = t_branch;
    } else {
      cj["branch_distance"] = nullptr;
    }
    j["crack"] = cj;
  }
  if (s.models.owner() || crack.active) {
    // Tupek's fracture figures (thesis Table 6.1 and 6.2), for any model that breaks bonds
    // from a precrack: dissipated energy per unit thickness (2-D), the crack length from
    // the first precrack's tip, their ratio, and the angle each precrack's crack leaves its
    // tip at (damage/crack_angle.hpp: a line fitted to the damage ridge 2 to 8 horizons
    // from the tip).
    nlohmann::ordered_json fj;
    const double per = config.dimension == 2 ? 1.0 / config.thickness : 1.0;
    fj["dissipated_energy"] = g.dissipated;
    fj["dissipated_energy_per_thickness"] = g.dissipated * per;
    if (crack.active) {
      const double len = f.found ? f.length : 0.0;
      fj["crack_length"] = len;
      fj["energy_per_crack_length"] = len > 0 ? g.dissipated * per / len : 0.0;
    }
    // crack_angles_deg: |angle| from the notch direction (Tupek's Table 6.2 figure);
    // crack_angles_signed_deg: counter-clockwise positive, so that the side the crack
    // turns to can be checked (Kalthoff: + for a notch along +x above the struck strip).
    nlohmann::ordered_json angles = nlohmann::ordered_json::array(), signed_angles = angles;
    for (const auto& pc : config.precracks) {
      if (pc.points.size() < 2) continue;
      Vec3 d = pc.points[1] - pc.points[0];
      d.z = 0;
      if (norm(d) == 0) continue;
      const CrackAngle a = crack_angle(o.particles, pc.points[1], d / norm(d), kCrackDamage, 2 * config.horizon,
                                       8 * config.horizon, config.spacing, config.horizon);
      angles.push_back(a.found ? nlohmann::ordered_json(std::abs(a.degrees)) : nlohmann::ordered_json(nullptr));
      signed_angles.push_back(a.found ? nlohmann::ordered_json(a.degrees) : nlohmann::ordered_json(nullptr));
    }
    fj["crack_angles_deg"] = angles;
    fj["crack_angles_signed_deg"] = signed_angles;
    j["fracture"] = fj;
  }
  const std::string energy_warning = energy_balance_warning(config, s, r.max_balance_error);
  if (!energy_warning.empty()) j["warnings"] = {energy_warning};
  write_result("summary.json", j.dump(2) + "\n");
  r.summary = j;

  if (!energy_warning.empty() && r.lead) fmt::print(stderr, "horizon: warning: {}\n", energy_warning);
  if (!options.quiet) {
    fmt::print(stderr, "{} in {} ({} steps, {:.3g} bond updates/s); output in {}\n", status, format_duration(wall),
               solver.steps(), j["bond_updates_per_second"].get<double>(), dir.string());
  }
  // A run stopped by its caller says so in summary.json; quiet runs leave stderr alone.
  if (!message.empty() && r.lead && !(options.quiet && status == "stopped")) fmt::print(stderr, "horizon: {}\n", message);
  return r.exit_code;
}


}  // namespace horizon
