#include "horizon/driver/run.hpp"

#include <fmt/format.h>
#include <omp.h>
#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "horizon/core/interrupt.hpp"
#include "horizon/core/progress.hpp"
#include "horizon/core/version.hpp"
#include "horizon/driver/summary.hpp"
#include "horizon/damage/crack_angle.hpp"
#include "horizon/damage/crack_metrics.hpp"
#include "horizon/loading/loads.hpp"
#include "horizon/output/atomic_file.hpp"
#include "horizon/output/pvd.hpp"
#include "horizon/output/vtu.hpp"
#include "horizon/solver/explicit.hpp"

namespace horizon {

namespace fs = std::filesystem;

void apply_run_options(Config& c, const RunOptions& o) {
  if (o.output_dir) c.output.directory = *o.output_dir;
  if (o.end_time) c.solver.end_time = *o.end_time;
  if (o.max_memory_gib > 0) c.memory_limit_bytes = o.max_memory_gib * 1024.0 * 1024.0 * 1024.0;
  if (o.coarsen != 1) {
    c.spacing *= o.coarsen;
    c.horizon *= o.coarsen;
    if (c.solver.time_step) *c.solver.time_step *= o.coarsen;
  }
}

double run_time_step(const Config& c, const System& s) {
  return c.solver.time_step ? *c.solver.time_step : c.solver.safety_factor * stable_time_step(s);
}

int64_t step_count(const Config& c, double dt) {
  if (!(dt > 0 && std::isfinite(dt))) {
    throw Error(fmt::format("{}: the time step is {}: no particle has a bond that sets a stable step (a body of a "
                            "single particle, or bodies thinner than a spacing apart from each other?); check the "
                            "bodies, the spacing and the horizon",
                            c.deck_file, dt));
  }
  const double steps = std::ceil(c.solver.end_time / dt - 1e-9);
  if (!(steps <= kMaxSteps)) {
    throw Error(fmt::format("{}: the run would take {:.3g} steps of {:.4g} s to end_time {:.4g} s, more than the "
                            "{:g} a run may take; check solver.end_time and solver.time_step (units: seconds)",
                            c.deck_file, steps, dt, c.solver.end_time, kMaxSteps));
  }
  return static_cast<int64_t>(steps);
}

CheckReport check_system(const Config& c, const System& s) {
  CheckReport r;
  r.particles = s.particles.size();
  r.bonds = s.bonds.size();
  r.precrack_bonds = s.precrack_bonds;
  r.memory_bytes = memory_estimate(s);
  r.stable_dt = stable_time_step(s);
  if (c.solver.type == SolverType::static_equilibrium) {
    r.dt = c.solver.end_time / c.solver.load_steps;  // pseudo-time per load step
    r.steps = c.solver.load_steps;
  } else {
    r.dt = run_time_step(c, s);  // implicit dynamics requires solver.time_step (deck check)
    r.steps = step_count(c, r.dt);
  }
  return r;
}

PreparedRun prepare_run(const Config& c) {
  PreparedRun u;
  u.system = build_system(c);
  u.loads = Loads(c, u.system);
  u.loads.apply_initial_conditions(c, u.system);
  u.check = check_system(c, u.system);
  return u;
}

std::string format_check(const Config& c, const CheckReport& r) {
  std::ostringstream o;
  o << fmt::format("deck            {}\n", c.deck_file);
  o << fmt::format("dimension       {}{}\n", c.dimension,
                   c.dimension == 2 ? (c.plane == PlaneMode::stress ? " (plane stress)" : " (plane strain)") : "");
  o << fmt::format("particles       {}\n", r.particles);
  o << fmt::format("bonds           {} directed ({:.1f} per particle), {} cut by precracks\n", r.bonds,
                   r.particles ? static_cast<double>(r.bonds) / static_cast<double>(r.particles) : 0.0,
                   r.precrack_bonds);
  o << fmt::format("memory          {:.1f} MiB (estimate)\n", static_cast<double>(r.memory_bytes) / (1 << 20));
  if (c.solver.type == SolverType::static_equilibrium) {
    o << fmt::format("solver          static, {}\n",
                     c.solver.method == StaticMethod::adr ? "adaptive dynamic relaxation" : "Newton-Raphson");
    o << fmt::format("load steps      {} to pseudo-time {:.4g} (tolerance {:.1e})\n", r.steps, c.solver.end_time,
                     c.solver.tolerance);
    return o.str();
  }
  o << fmt::format("stable step     {:.4e} s (Silling-Askari bound)\n", r.stable_dt);
  if (c.solver.type == SolverType::implicit_dynamic)
    o << fmt::format("time step       {:.4e} s (implicit Newmark, {:.1f} x the stable step)\n", r.dt,
                     r.dt / r.stable_dt);
  else
    o << fmt::format("time step       {:.4e} s{}\n", r.dt,
                     c.solver.time_step ? " (fixed)" : fmt::format(" (safety factor {})", c.solver.safety_factor));
  o << fmt::format("steps           {} to t = {:.4e} s\n", r.steps, c.solver.end_time);
  return o.str();
}

Frame make_frame(const System& s, double time, int64_t step) {
  const auto& P = s.particles;
  Frame f;
  f.time = time;
  f.step = step;
  f.dimension = s.dimension;
  f.points = P.X;
  auto vec = [&](const std::string& name, const std::vector<Vec3>& v) {
    FrameField ff{name, 3, {}};
    ff.data.reserve(3 * v.size());
    for (const auto& x : v) ff.data.insert(ff.data.end(), {x.x, x.y, x.z});
    f.fields.push_back(std::move(ff));
  };
  auto scal = [&](const std::string& name, auto get) {
    FrameField ff{name, 1, {}};
    ff.data.resize(P.size());
    for (std::size_t i = 0; i < P.size(); ++i) ff.data[i] = get(i);
    f.fields.push_back(std::move(ff));
  };
  vec("displacement", P.u);
  vec("velocity", P.v);
  vec("force_density", P.f);
  scal("damage", [&](std::size_t i) { return P.damage[i]; });
  scal("energy_density", [&](std::size_t i) { return P.energy[i]; });
  scal("block", [&](std::size_t i) { return static_cast<double>(P.block[i]); });
  scal("volume", [&](std::size_t i) { return P.volume[i]; });
  // The models' own fields (material/model.hpp), once per name: a run with two materials
  // of one model writes its fields once.
  std::vector<ModelField> extra;
  for (const auto& m : s.models) m->fields(s, extra);
  for (auto& mf : extra) {
    bool seen = false;
    for (const auto& ff : f.fields) seen = seen || ff.name == mf.name;
    if (seen || mf.values.size() != P.size()) continue;
    f.fields.push_back(FrameField{mf.name, 1, std::move(mf.values)});
  }
  return f;
}

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

namespace {

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
double fitted_speed(const std::vector<std::pair<double, double>>& h, double l0, double l1) {
  double n = 0, st = 0, sl = 0, stt = 0, stl = 0;
  for (const auto& [t, l] : h)
    if (l >= l0 && l <= l1) {
      n += 1;
      st += t;
      sl += l;
      stt += t * t;
      stl += t * l;
    }
  if (n < 3) return 0;
  const double den = n * stt - st * st;
  return den > 0 ? (n * stl - st * sl) / den : 0;
}

}  // namespace

int run_deck(Config config, const RunOptions& options) {
  if (config.solver.type != SolverType::explicit_dynamic) return run_implicit_deck(std::move(config), options);
  apply_run_options(config, options);
  if (options.threads > 0) omp_set_num_threads(options.threads);
  const auto wall_start = std::chrono::steady_clock::now();
  const fs::path dir = config.output.directory;
  prepare_output_directory(dir.string(), "frames");  // before the (long) set-up

  System s = build_system(config);
  Loads loads(config, s);
  loads.apply_initial_conditions(config, s);
  const CheckReport check = check_system(config, s);
  if (!options.quiet) fmt::print(stderr, "{}", format_check(config, check));

  PvdIndex pvd((dir / "frames.pvd").string());

  ExplicitSolver solver(s, loads, check.dt, config.solver.damping);
  solver.initialize();

  // History columns: the ledger, damage, and the force each load applies.
  std::ostringstream history;
  history << "time,step,dt,kinetic_energy,strain_energy,external_work,dissipated_energy,damped_energy,"
             "energy_balance_error,broken_bond_fraction,damage_max,damage_mean";
  for (const auto& L : loads.loads()) history << "," << L.name << "_fx," << L.name << "_fy," << L.name << "_fz";
  history << "\n";
  double max_balance_error = 0;
  auto record_history = [&]() {
    const Ledger& g = solver.ledger();
    const DamageStats dstat = damage_stats(s.particles);
    const double dmax = dstat.max, dmean = dstat.mean;
    const double broken_fraction =
        s.initial_bonds ? static_cast<double>(s.broken) / static_cast<double>(s.initial_bonds) : 0.0;
    max_balance_error = std::max(max_balance_error, std::abs(g.balance_error()));
    history << fmt::format("{:.9e},{},{:.6e},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.6e},{:.6e},{:.6f},{:.9f}",
                           solver.time(), solver.steps(), solver.dt(), g.kinetic, g.strain, g.external_work,
                           g.dissipated, g.damped, g.balance_error(), broken_fraction, dmax, dmean);
    for (const auto& L : loads.loads())
      history << fmt::format(",{:.9e},{:.9e},{:.9e}", L.reaction.x, L.reaction.y, L.reaction.z);
    history << "\n";
  };
  int frame_count = 0;
  auto write_frame = [&]() {
    const std::string name = fmt::format("frames/frame_{:05d}.vtu", frame_count++);
    write_vtu((dir / name).string(), make_frame(s, solver.time(), solver.steps()));
    pvd.add(solver.time(), name);
    pvd.write();
  };
  CrackTracker crack(config);

  int64_t total = check.steps;
  // The adaptive step (models with ModelTraits::adaptive_time_step; the deck allows it for
  // no other): recomputed from the current bond stiffness every adaptive_every steps; the
  // run ends at end_time, frames fall due by time.
  const bool adaptive = config.solver.adaptive_time_step;
  const int adaptive_every = std::max(1, config.solver.adaptive_every);
  const double end_time = config.solver.end_time;
  double dt_nominal = check.dt, dt_min = check.dt, dt_max = check.dt;
  const int64_t history_every = std::max(1, config.output.history_every);
  const int frames = std::max(1, config.output.frames);
  record_history();
  write_frame();
  crack.record(s, 0);

  install_interrupt_handler();
  Progress progress(total, static_cast<double>(s.bonds.size()), config.output.progress_every);
  std::string status = "completed";
  int exit_code = 0;
  std::string message;
  int next_frame = 1;
  const double cpu_start = cpu_seconds();
  try {
    while (adaptive ? solver.time() < end_time * (1 - 1e-12) : solver.steps() < total) {
      const int64_t step = solver.steps() + 1;
      bool last = step == total;
      if (adaptive) {
        if (solver.steps() % adaptive_every == 0)
          dt_nominal = config.solver.safety_factor * stable_time_step(s);
        double dt = dt_nominal;
        if (solver.time() + dt >= end_time * (1 - 1e-12)) dt = end_time - solver.time(), last = true;
        solver.set_dt(dt);
        dt_min = std::min(dt_min, dt_nominal);
        dt_max = std::max(dt_max, dt_nominal);
        total = std::max(total, step + 1);
      }
      const bool frame_due = adaptive ? last || (solver.time() + solver.dt()) * frames >= next_frame * end_time
                                      : step * frames >= static_cast<int64_t>(next_frame) * total;
      const bool history_due = step % history_every == 0 || last;
      solver.step(history_due || frame_due);
      if (history_due) {
        record_history();
        crack.record(s, solver.time());
      }
      if (frame_due) {
        write_frame();
        ++next_frame;
      }
      if (!options.quiet) progress.update(solver.steps(), solver.time());
      if (interrupt_requested()) {
        status = "interrupted";
        exit_code = interrupt_exit_code();
        message = fmt::format("{} at step {}, t = {:.4e} s; a final frame was written", interrupt_name(),
                              solver.steps(), solver.time());
        break;
      }
    }
  } catch (const NonFiniteState& e) {
    status = "non-finite";
    exit_code = 2;
    message = e.what();
  } catch (const OutputError& e) {
    // The frames listed in frames.pvd are complete (written under a temporary name and
    // renamed); the one that failed is not listed. No final frame: the disk said no.
    status = "output error";
    exit_code = 5;
    message = fmt::format("output error: {}; stopped at step {}, frames.pvd lists the {} complete frames", e.what(),
                          solver.steps(), pvd.entries().size());
  }
  if (!options.quiet) progress.finish();
  if (exit_code != 0 && exit_code != 5) {
    // The last good state (restored by the solver on a non-finite step) as the final frame.
    solver.update_kinetic();
    record_history();
    write_frame();
  }
  clear_interrupt();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  const double loop_time = progress.elapsed();
  const double loop_cpu_time = cpu_seconds() - cpu_start;

  // After an output error, history and summary are tried once (they are small) and their
  // failure only reported.
  auto write_result = [&](const std::string& name, const std::string& text) {
    try {
      write_file_atomic((dir / name).string(), text);
    } catch (const OutputError& e) {
      if (exit_code != 5) throw;
      fmt::print(stderr, "horizon: {}\n", e.what());
    }
  };
  write_result("history.csv", history.str());

  // Summary: final figures and run statistics.
  const Ledger& g = solver.ledger();
  nlohmann::ordered_json j = summary_header(config, s, status, message, solver.steps());
  j["time_step"] = solver.dt();
  if (adaptive) j["time_step_range"] = {dt_min, dt_max};
  j["time"] = solver.time();
  j["threads"] = omp_get_max_threads();
  j["wall_time_s"] = wall;
  j["loop_time_s"] = loop_time;
  j["loop_cpu_time_s"] = loop_cpu_time;
  j["bond_updates_per_second"] =
      loop_time > 0 ? static_cast<double>(s.bonds.size()) * static_cast<double>(solver.steps()) / loop_time : 0.0;
  j["peak_memory_bytes"] = peak_memory_bytes();
  summary_state(j, s, g, loads, max_balance_error);
  // The crack path and front at the end, for the crack and fracture figures below.
  const std::vector<uint8_t> on = crack.active ? crack.path(s) : std::vector<uint8_t>{};
  const CrackFront f = crack.active ? crack.front(s, on) : CrackFront{};
  if (crack.active) {
    const auto branch = branch_distance(s.particles, crack.origin, crack.direction, kCrackDamage, config.spacing,
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
      const CrackAngle a = crack_angle(s.particles, pc.points[1], d / norm(d), kCrackDamage, 2 * config.horizon,
                                       8 * config.horizon, config.spacing, config.horizon);
      angles.push_back(a.found ? nlohmann::ordered_json(std::abs(a.degrees)) : nlohmann::ordered_json(nullptr));
      signed_angles.push_back(a.found ? nlohmann::ordered_json(a.degrees) : nlohmann::ordered_json(nullptr));
    }
    fj["crack_angles_deg"] = angles;
    fj["crack_angles_signed_deg"] = signed_angles;
    j["fracture"] = fj;
  }
  const std::string energy_warning = energy_balance_warning(config, max_balance_error);
  if (!energy_warning.empty()) j["warnings"] = {energy_warning};
  write_result("summary.json", j.dump(2) + "\n");

  if (!energy_warning.empty()) fmt::print(stderr, "horizon: warning: {}\n", energy_warning);
  if (!options.quiet) {
    fmt::print(stderr, "{} in {} ({} steps, {:.3g} bond updates/s); output in {}\n", status, format_duration(wall),
               solver.steps(), j["bond_updates_per_second"].get<double>(), dir.string());
  }
  if (!message.empty()) fmt::print(stderr, "horizon: {}\n", message);
  return exit_code;
}

}  // namespace horizon
