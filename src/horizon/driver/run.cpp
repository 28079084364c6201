// The explicit run (driver/run.hpp ExplicitRun): set-up, steps, stop; run_deck. Its state
// is driver/explicit_state.hpp; its end (history.csv, summary.json) explicit_summary.cpp.
#include "horizon/driver/run.hpp"

#include <sched.h>

#include "horizon/driver/explicit_state.hpp"
#include "horizon/driver/history_columns.hpp"

namespace horizon {

namespace fs = std::filesystem;

// The cores in this process's CPU affinity mask (0 when unknown).
static int affinity_cores() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof(set), &set) != 0) return 0;
  return CPU_COUNT(&set);
}

ExplicitRun::ExplicitRun(Config config, const RunOptions& options) : st_(std::make_unique<State>()) {
  State& r = *st_;
  r.config = std::move(config);
  r.options = options;
  Config& c = r.config;
  if (c.solver.type != SolverType::explicit_dynamic)
    throw Error("a step-by-step run needs solver.type explicit; static and implicit_dynamic decks run to the end");
  r.lead = world_rank() == 0;
  if (!r.lead) r.options.quiet = true;
  apply_run_options(c, options);
  if (options.threads > 0) omp_set_num_threads(options.threads);
  // More threads than the cores this process may run on (mpirun binds each of 1 or 2
  // ranks to one core by default): the threads would share them. Said once, by rank 0.
  if (const int cores = affinity_cores(); r.lead && cores > 0 && omp_get_max_threads() > cores)
    fmt::print(stderr,
               "horizon: warning: {} threads but this process may run on {} core(s) only (CPU affinity); under "
               "mpirun give each rank its cores (--map-by slot:PE={} or --bind-to none)\n",
               omp_get_max_threads(), cores, omp_get_max_threads());
  // A staged run (static, then explicit: driver/static_stage.cpp) runs its static stage on
  // one rank's whole system: the static solver's split over ranks has limits of its own
  // (run_implicit.cpp), and a checkpoint holds the explicit stage alone.
  if (c.static_stage && world_size() > 1)
    throw Error(fmt::format("{}: a staged run (static, then explicit) runs on one rank; this run has {} ranks",
                            c.deck_file, world_size()));
  if (c.static_stage && options.restart)
    throw Error(fmt::format("{}: --restart continues single-solver explicit runs; this deck has stages "
                            "(static, then explicit)", c.deck_file));
  r.wall_start = std::chrono::steady_clock::now();
  r.dir = c.output.directory;
  prepare_output_directory(r.dir.string(), "frames");  // before the (long) set-up

  // An MPI build holds on each rank only the bond rows it computes when the deck allows
  // it (local_rows_allowed): the split is decided before the families are built, and the
  // run decomposed before any pass over the rows. Other decks are built whole on every
  // rank and decomposed below.
  // HORIZON_MPI_WHOLE_SYSTEM=1 builds the whole system on every rank as before local rows
  // existed (the same bits; for the memory comparison of docs/benchmarks.md).
  // On more than one rank, a deck that local_particles_allowed also holds only the
  // particles it reads (local particles; a restart too: each rank reads its particles'
  // entries of the checkpoint by global id); HORIZON_MPI_LOCAL_PARTICLES=0 keeps every particle
  // on every rank with local rows (the comparison of docs/benchmarks.md).
  // The flat and CUDA backends take one rank's whole system (driver/backends.cpp): an MPI
  // build does not decompose their runs on one rank and refuses them on more.
  const bool cpu_backend = c.solver.backend == "cpu";
  if (!cpu_backend && world_size() > 1)
    throw Error(fmt::format("{} cannot take a run over {} MPI ranks; run it on one rank (or with backend cpu)",
                            backend_choice_prefix(c), world_size()));
  const char* whole = std::getenv("HORIZON_MPI_WHOLE_SYSTEM");
  const char* particles_env = std::getenv("HORIZON_MPI_LOCAL_PARTICLES");
  const bool local_rows = cpu_backend && mpi_built() && !c.static_stage && local_rows_allowed(c) &&
                          !(whole && std::string(whole) == "1");
  const bool local_particles = local_rows && world_size() > 1 && local_particles_allowed(c) &&
                               !(particles_env && std::string(particles_env) == "0");
  if (local_particles) r.dd = std::make_unique<Decomposition>();
  r.s = local_particles ? build_system_split(c, *r.dd) : local_rows ? build_system_split(c) : build_system(c);
  if (local_rows) {
    if (const std::string why = distributed_limits(c, r.s, options); !why.empty())
      throw Error(fmt::format("{}: internal error: a deck built with local rows cannot be split: {}", c.deck_file, why));
    if (!r.dd) r.dd = std::make_unique<Decomposition>();
    r.dd->local_rows = true;
    decompose(r.s, *r.dd, c.spacing);
  }
  r.loads = std::make_unique<Loads>(c, r.s);
  r.loads->apply_initial_conditions(c, r.s);
  r.check = check_system(c, r.s);
  if (!options.quiet) fmt::print(stderr, "{}", format_check(c, r.check));

  r.pvd = std::make_unique<PvdIndex>((r.dir / "frames.pvd").string());
  if (c.output.writes_exodus()) r.exodus = std::make_unique<ExodusOutput>((r.dir / c.output.exodus_file).string());
  if (!c.output.exodus_files.empty()) {
    r.exodus_files = std::make_unique<ExodusSchedule>(c.output.exodus_files, r.dir, false, c);
    r.exodus_files->prepare(r.s);
  }

  r.solver = std::make_unique<ExplicitSolver>(r.s, *r.loads, r.check.dt, c.solver.damping);
  r.solver->set_peridigm_verlet(c.solver.peridigm_verlet);
  r.solver->initialize();
  if (cpu_backend && mpi_built() && !r.dd && !c.static_stage) {
    // An MPI build decomposes every run it can, on one rank too, so that one rank and
    // many give the same bits (parallel/decomposition.hpp); a deck it cannot split runs
    // serially on one rank and is refused on more.
    const std::string why = distributed_limits(c, r.s, options);
    if (why.empty()) {
      r.dd = std::make_unique<Decomposition>();
      decompose(r.s, *r.dd, c.spacing);
    } else if (world_size() > 1) {
      throw Error(fmt::format("{}: this deck cannot run on {} MPI ranks yet: {}; run it on one rank",
                              c.deck_file, world_size(), why));
    }
  }
  if (r.s.heat.active()) {
    r.heat = std::make_unique<HeatSolver>(r.s, c.thermal.integration);
    r.heat_stable = heat_stable_step(r.s);
    r.heat_initial = heat_content(r.s);
    const double h = r.check.dt * c.thermal.time_scale;
    if (c.thermal.integration == HeatIntegration::explicit_euler && c.thermal.conduction)
      r.heat_substeps = std::max(1, static_cast<int>(std::ceil(h / (c.solver.safety_factor * r.heat_stable))));
    if (!options.quiet && !c.thermal.conduction)
      fmt::print(stderr, "heat            no conduction: the prescribed temperature field at each step\n");
    else if (!options.quiet)
      fmt::print(stderr, "heat            {} Euler, {:.4e} s per step ({} x the mechanical step, {} sub-steps; "
                         "stable explicit heat step {:.4e} s)\n",
                 c.thermal.integration == HeatIntegration::implicit_euler ? "backward" : "forward", h,
                 c.thermal.time_scale, r.heat_substeps, r.heat_stable);
  }

  check_backend(c, r.s, *r.loads);  // before the first frame (the backend itself after a restart)

  // History columns: the ledger, damage, and the force each load applies.
  r.history << "time,step,dt,kinetic_energy,strain_energy,external_work,dissipated_energy,damped_energy,"
               "energy_balance_error,broken_bond_fraction,damage_max,damage_mean";
  for (const auto& L : r.loads->loads()) r.history << "," << L.name << "_fx," << L.name << "_fy," << L.name << "_fz";
  // Each projectile: position, velocity, acceleration, the contact force on it, and the
  // low-pass acceleration (the acceleration itself without a filter).
  for (const auto& p : r.loads->projectiles())
    for (const char* q : {"x", "y", "z", "vx", "vy", "vz", "ax", "ay", "az", "fx", "fy", "fz", "ax_filtered",
                          "ay_filtered", "az_filtered"})
      r.history << "," << p.config().name << "_" << q;
  // With two or more bodies (a projectile and its target), each body's centre-of-mass velocity.
  if (r.s.block_names.size() > 1)
    for (const auto& name : r.s.block_names) r.history << "," << name << "_vx," << name << "_vy," << name << "_vz";
  // Finite-element regions: the work of the force-based coupling (fe/fe_region.hpp).
  if (r.s.fe) r.history << ",fe_coupling_work";
  if (r.s.heat.active()) r.history << ",thermal_work,heat_time," << heat_history_header(r.s);
  r.history << history_columns_header(c) << "\n";  // the deck's probes (driver/history_columns.hpp)
  r.crack = std::make_unique<CrackTracker>(c);

  r.total = r.check.steps;
  // The adaptive step (models with ModelTraits::adaptive_time_step; the deck allows it for
  // no other): recomputed from the current bond stiffness every adaptive_every steps; the
  // run ends at end_time, frames fall due by time.
  r.adaptive = c.solver.adaptive_time_step;
  r.adaptive_every = std::max(1, c.solver.adaptive_every);
  r.end_time = c.solver.end_time;
  r.dt_nominal = r.dt_min = r.dt_max = r.check.dt;
  r.history_every = std::max(1, c.output.history_every);
  r.frames = std::max(1, c.output.frames);
  if (options.restart) {
    // The state of the checkpoint replaces the initial one; the index lists the frames
    // written before it (later ones, from an interrupted run, are written again).
    r.read_checkpoint(*options.restart);
    // Every rank holds the state of its particles now: the ghosts follow the loaded positions.
    if (r.dd) refresh_ghosts(r.s, *r.dd);
    if (r.lead) r.pvd->write();
    if (!options.quiet)
      fmt::print(stderr, "restart         from {} at step {}, t = {:.4e} s\n", *options.restart, r.solver->steps(),
                 r.solver->time());
  } else {
    // Local particles: the initial broken-bond count and rank 0's cracked particles (the
    // first row, the crack tracker's first record).
    if (r.local_particles()) r.sync();
    r.record_history();
    r.write_frame();
    if (r.exodus_files) r.exodus_files->write(r.s, r.dd.get(), r.solver->time(), 0);
    r.crack->record(r.cracks(), 0);
    // A staged run: the static stage, then the explicit stage's start state (written again
    // at the switch time, as Peridigm writes it).
    if (c.static_stage) r.run_static_stage();
  }

  // After the restart: a backend with its own copy of the state copies the restored one.
  r.backend = make_backend(c, r.s, *r.loads, *r.solver);
  if (!r.options.quiet && !cpu_backend) fmt::print(stderr, "backend         {}\n", r.backend->name());

  if (options.handle_signals) install_interrupt_handler();
  r.progress = std::make_unique<Progress>(r.total, static_cast<double>(r.s.bonds.size()), c.output.progress_every);
  if (!r.options.quiet && r.dd && r.dd->size > 1)
    fmt::print(stderr,
               "ranks           {} (recursive coordinate bisection; {} particles on rank 0, {} held {}, {} bonds held "
               "{})\n",
               r.dd->size, r.dd->owned.size(), r.s.particles.size(),
               r.dd->local_particles ? "(with its ghosts)" : "(every particle)", r.s.bonds.size(),
               r.dd->local_rows ? "(its rows)" : "(the whole system on every rank)");
  r.cpu_start = cpu_seconds();
  r.stopped = r.stopped || r.at_end();  // (a static stage that did not converge stopped the run)
}

ExplicitRun::~ExplicitRun() = default;

int64_t ExplicitRun::advance(int64_t n) {
  State& r = *st_;
  int64_t taken = 0;
  if (r.stopped) return 0;
  const Config& c = r.config;
  ExplicitSolver& solver = *r.solver;
  ExplicitBackend& backend = *r.backend;
  // A step with no event (history row, frame, Exodus step, checkpoint, the end): a backend that takes
  // several steps a call takes these together with the event's step that follows.
  auto quiet = [&](int64_t step) {
    return step < r.total && step % r.history_every != 0 &&
           step * r.frames < static_cast<int64_t>(r.next_frame) * r.total &&
           !(c.output.checkpoint_every > 0 && step % c.output.checkpoint_every == 0) &&
           !(r.exodus_files && r.exodus_files->due(r.step_offset + step));
  };
  try {
    while (taken < n && !r.at_end()) {
      int64_t batch = 1;  // the adaptive step and the heat coupling work between steps
      if (!r.adaptive && !r.heat)
        while (batch < backend.batch() && taken + batch < n && quiet(solver.steps() + batch)) ++batch;
      if (batch > 1) backend.advance(batch - 1, false);  // (the solver's step count moves on)
      const int64_t step = solver.steps() + 1;
      // An adaptive run ends by time: its step count (r.total, moved on below) is no end.
      bool last = !r.adaptive && step == r.total;
      if (r.adaptive) {
        if (solver.steps() % r.adaptive_every == 0) {
          double stable = 0;  // over the backend's copy (the flat backend), or the System's state
          if (!backend.stable_time_step(stable)) stable = whole_stable_step(r.s);
          r.dt_nominal = c.solver.safety_factor * stable;
        }
        double dt = r.dt_nominal;
        if (solver.time() + dt >= r.end_time * (1 - 1e-12)) dt = r.end_time - solver.time(), last = true;
        solver.set_dt(dt);
        r.dt_min = std::min(r.dt_min, r.dt_nominal);
        r.dt_max = std::max(r.dt_max, r.dt_nominal);
        r.total = std::max(r.total, step + 1);
      }
      const bool frame_due = r.adaptive ? last || (solver.time() + solver.dt()) * r.frames >= r.next_frame * r.end_time
                                        : step * r.frames >= static_cast<int64_t>(r.next_frame) * r.total;
      const bool history_due = step % r.history_every == 0 || last;
      const bool exodus_due = r.exodus_files && r.exodus_files->due(r.step_offset + step);
      backend.advance(1, history_due || frame_due || exodus_due);
      r.advance_heat();
      taken += batch;
      const bool checkpoint_due = c.output.checkpoint_every > 0 && solver.steps() % c.output.checkpoint_every == 0;
      if (history_due || frame_due || exodus_due || checkpoint_due) backend.copy_fields();
      if (history_due || frame_due || exodus_due) r.sync();
      if (history_due) {
        r.record_history();
        r.crack->record(r.cracks(), solver.time());
      }
      if (frame_due) {
        r.write_frame();
        ++r.next_frame;
      }
      if (exodus_due) {
        // velocity: verlet files; solver.verlet: peridigm's state holds the half kick already.
        r.exodus_files->set_verlet(r.loads.get(), solver.peridigm_verlet() ? 0.0 : solver.dt());
        r.exodus_files->write(r.s, r.dd.get(), solver.time(), r.step_offset + step);
      }
      if (c.output.checkpoint_every > 0 && solver.steps() % c.output.checkpoint_every == 0 && !r.at_end())
        r.write_checkpoint();
      if (!r.options.quiet) r.progress->update(solver.steps(), solver.time());
      const bool interrupted = r.options.handle_signals && interrupt_requested();
      if (r.dd ? any_rank(*r.dd, interrupted) : interrupted) {
        r.status = "interrupted";
        r.exit_code = interrupt_exit_code();
        r.message = fmt::format("{} at step {}, t = {:.4e} s; a final frame was written", interrupt_name(),
                                solver.steps(), solver.time());
        r.stopped = true;
        return taken;
      }
    }
  } catch (const NonFiniteState& e) {
    r.status = "non-finite";
    r.exit_code = 2;
    r.message = e.what();
    r.stopped = true;
    return taken;
  } catch (const OutputError& e) {
    // The frames listed in frames.pvd are complete (written under a temporary name and
    // renamed); the one that failed is not listed. No final frame: the disk said no.
    r.status = "output error";
    r.exit_code = 5;
    r.message = fmt::format("output error: {}; stopped at step {}, frames.pvd lists the {} complete frames", e.what(),
                            solver.steps(), r.pvd->entries().size());
    r.stopped = true;
    return taken;
  }
  if (r.at_end()) r.stopped = true;
  backend.copy_fields();  // the caller (the Python module) reads the System between calls
  return taken;
}

void ExplicitRun::stop(const std::string& reason) {
  State& r = *st_;
  if (r.stopped) return;
  r.status = "stopped";
  r.message = fmt::format("stopped at step {}, t = {:.4e} s ({}); a final frame was written", r.solver->steps(),
                          r.solver->time(), reason);
  r.stopped = true;
}

bool ExplicitRun::done() const { return st_->stopped; }
bool ExplicitRun::finished() const { return st_->finished; }
const System& ExplicitRun::system() const { return st_->s; }
System& ExplicitRun::system() { return st_->s; }
const Config& ExplicitRun::config() const { return st_->config; }
const Ledger& ExplicitRun::ledger() const { return st_->solver->ledger(); }
const Loads& ExplicitRun::loads() const { return *st_->loads; }
double ExplicitRun::time() const { return st_->solver->time(); }
double ExplicitRun::dt() const { return st_->solver->dt(); }
int64_t ExplicitRun::steps() const { return st_->solver->steps(); }
int64_t ExplicitRun::total_steps() const { return st_->total; }
const std::string& ExplicitRun::status() const { return st_->status; }
std::string ExplicitRun::history_csv() const { return st_->history.str(); }
const nlohmann::ordered_json& ExplicitRun::summary() const { return st_->summary; }
std::string ExplicitRun::output_directory() const { return st_->dir.string(); }
int ExplicitRun::exit_code() const { return st_->exit_code; }

int run_deck(Config config, const RunOptions& options) {
  if (options.restart && config.solver.type != SolverType::explicit_dynamic)
    throw Error(fmt::format("{}: --restart continues explicit runs only (solver.type explicit)", config.deck_file));
  if (config.solver.type == SolverType::heat) return run_heat_deck(std::move(config), options);
  if (config.solver.type != SolverType::explicit_dynamic) return run_implicit_deck(std::move(config), options);
  ExplicitRun run(std::move(config), options);
  run.advance(std::numeric_limits<int64_t>::max());
  return run.finish();
}

}  // namespace horizon
