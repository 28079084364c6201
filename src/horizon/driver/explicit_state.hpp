#pragma once
// The explicit run's state (driver/run.hpp ExplicitRun), shared by the files that make
// up the explicit run: run.cpp (set-up and steps), explicit_summary.cpp (history.csv and
// summary.json at the end). Not for other drivers.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fmt/format.h>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <omp.h>
#include <sstream>

#include "horizon/driver/run.hpp"
#include "horizon/core/interrupt.hpp"
#include "horizon/core/progress.hpp"
#include "horizon/core/version.hpp"
#include "horizon/damage/crack_angle.hpp"
#include "horizon/damage/crack_metrics.hpp"
#include "horizon/damage/crack_tracking.hpp"
#include "horizon/driver/exodus_output.hpp"
#include "horizon/driver/history_columns.hpp"
#include "horizon/driver/summary.hpp"
#include "horizon/fe/fe_region.hpp"
#include "horizon/loading/loads.hpp"
#include "horizon/output/atomic_file.hpp"
#include "horizon/output/checkpoint.hpp"
#include "horizon/output/pvd.hpp"
#include "horizon/output/vtu.hpp"
#include "horizon/parallel/checkpoint_stream.hpp"
#include "horizon/parallel/decomposition.hpp"
#include "horizon/parallel/lead_view.hpp"
#include "horizon/solver/backend.hpp"
#include "horizon/solver/explicit.hpp"
#include "horizon/solver/forces.hpp"
#include "horizon/thermal/heat.hpp"

namespace horizon {

// The stable step of the whole system (collective when decomposed; driver/check.cpp).
double whole_stable_step(const System& s);

// CPU time of the process so far, all threads [s] (driver/explicit_summary.cpp).
double cpu_seconds();

// The backend solver.backend (or --backend) names, over the solver's state; throws an
// Error naming the deck and the key for a run the backend cannot take (driver/backends.cpp).
std::unique_ptr<ExplicitBackend> make_backend(const Config& c, System& s, Loads& loads, ExplicitSolver& solver);
// The same refusals alone, before the first frame is written.
void check_backend(const Config& c, const System& s, const Loads& loads);
// "deck:line:column: solver.backend: NAME" or "deck: --backend NAME", for messages.
std::string backend_choice_prefix(const Config& c);

// The explicit run as an object: the constructor sets up the system, the solver and the
// output and writes the first frame; advance() takes steps; finish() writes history.csv
// and summary.json. run_deck is constructor, advance to the end, finish.
struct ExplicitRun::State {
  Config config;
  RunOptions options;
  std::chrono::steady_clock::time_point wall_start;
  System s;
  std::unique_ptr<Loads> loads;
  CheckReport check;
  std::filesystem::path dir;
  std::unique_ptr<PvdIndex> pvd;
  std::unique_ptr<ExodusOutput> exodus;  // output.format exodus or both
  std::unique_ptr<ExodusSchedule> exodus_files;  // output.exodus_files, on their own steps
  std::unique_ptr<ExplicitSolver> solver;
  // What takes the steps (solver/backend.hpp): the CPU backend over `solver`, or the flat
  // or CUDA backend over a copy of its state (solver.backend; driver/backends.cpp).
  std::unique_ptr<ExplicitBackend> backend;
  std::ostringstream history;
  double max_balance_error = 0;
  int frame_count = 0;
  std::unique_ptr<CrackTracker> crack;
  int64_t total = 0;
  bool adaptive = false;
  int adaptive_every = 1;
  double end_time = 0;
  double dt_nominal = 0, dt_min = 0, dt_max = 0;
  int64_t history_every = 1;
  int frames = 1;
  std::unique_ptr<Progress> progress;
  std::string status = "completed";
  int exit_code = 0;
  std::string message;
  int next_frame = 1;
  double cpu_start = 0;
  bool stopped = false;   // the loop has ended (end reached, interrupted, non-finite or stopped)
  bool finished = false;  // finish() has run
  nlohmann::ordered_json summary;
  // Coupled heat conduction (thermal/heat.hpp): after each mechanical step the temperature
  // advances time_scale times its step, in as many forward-Euler sub-steps as its stability
  // asks (one backward-Euler step when implicit); the next force pass sees the new thermal
  // strain (staggered, one-step lag).
  std::unique_ptr<HeatSolver> heat;
  double heat_stable = 0, heat_initial = 0;
  int heat_substeps = 1;
  // The thermal work by the trapezoidal rule (thermal/heat.hpp thermal_strain_work): a
  // heat step's change of the thermal strain is booked after the next force pass, which
  // is the first to see it, as the mean of its work at the force states before and after.
  std::vector<double> strain_change;
  double pending_work = 0;
  // A run split over MPI ranks (parallel/decomposition.hpp); null in serial runs. Rank 0
  // (lead) writes history.csv, summary.json, frames.pvd and the .pvtu of each frame; each
  // rank writes its own piece of every frame.
  std::unique_ptr<Decomposition> dd;
  bool lead = true;
  // With local particles (each rank holds only the particles it reads) rank 0 holds no
  // copy of the whole system (parallel/lead_view.hpp): `cracked` is the cracked particles
  // (damage >= kCrackDamage) of every rank, on rank 0 in global order, gathered by sync()
  // for the crack tracking and the summary's crack figures (they read no other particle:
  // damage/crack_metrics.hpp, crack_angle.hpp); empty on the other ranks.
  System cracked;
  std::size_t cracked_most = 0;  // the most particles `cracked` held
  bool local_particles() const { return dd && dd->local_particles && dd->size > 1; }
  // Before a history row, a frame, a checkpoint or the summary: the whole system's count of
  // broken bonds (s.broken) on every rank, and every particle's state on every rank
  // without local particles (gather_state); with local particles rank 0's `cracked`.
  void sync() {
    if (!dd) return;
    gather_state(s, *dd);
    if (local_particles()) {
      gather_cracked(s, dd.get(), kCrackDamage, cracked.particles);
      cracked_most = std::max(cracked_most, cracked.particles.size());
    }
  }
  // What the crack tracking reads after sync(): rank 0's cracked particles with local
  // particles (other ranks' figures are never written), else the system itself.
  const System& cracks() const { return local_particles() ? cracked : s; }

  void advance_heat() {
    // A prescribed field (thermal.conduction: false) is set by the solver's step itself.
    if (!heat || !s.heat.conduction) return;
    Ledger& g = solver->ledger();
    if (!strain_change.empty()) g.thermal_work += pending_work + 0.5 * thermal_strain_work(s, strain_change);
    const std::vector<double> before = s.thermal_strain;
    const double h = solver->dt() * config.thermal.time_scale / heat_substeps;
    for (int k = 0; k < heat_substeps; ++k) heat->step(h);
    strain_change.assign(s.thermal_strain.size(), 0.0);
    if (before.size() == s.thermal_strain.size())
      for (std::size_t i = 0; i < before.size(); ++i) strain_change[i] = s.thermal_strain[i] - before[i];
    pending_work = 0.5 * thermal_strain_work(s, strain_change);
  }

  // A staged run (Config::static_stage; driver/static_stage.cpp): the static stage runs
  // on this run's system and writers before the explicit stage's first step, writing its
  // load steps as output steps 1..N (history rows, frames, Exodus steps); the explicit
  // stage's start state is then step N + 1 and its step n step N + 1 + n (step_offset =
  // N + 1), Peridigm's count (Compression_QS_Explicit_MultiFreqOutput's gold). Sets
  // status, exit_code and stopped when a load step does not converge.
  void run_static_stage();
  int64_t step_offset = 0;
  nlohmann::ordered_json stage_summary;  // the static stage's figures, summary.json "static_stage"

  void record_history() { record_history(solver->time(), step_offset + solver->steps(), solver->dt(), solver->ledger()); }
  void record_history(double time, int64_t step, double dt, const Ledger& g) {
    // Exact sums and maxima over the owned particles (driver/summary.hpp; collective when
    // decomposed); s.broken and s.initial_bonds count the whole system's bonds.
    const DamageStats dstat = damage_stats(s);
    const double dmax = dstat.max, dmean = dstat.mean;
    const double broken_fraction =
        s.initial_bonds ? static_cast<double>(s.broken) / static_cast<double>(s.initial_bonds) : 0.0;
    max_balance_error = std::max(max_balance_error, std::abs(g.balance_error()));
    history << fmt::format("{:.9e},{},{:.6e},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.6e},{:.6e},{:.6f},{:.9f}",
                           time, step, dt, g.kinetic, g.strain, g.external_work,
                           g.dissipated, g.damped, g.balance_error(), broken_fraction, dmax, dmean);
    for (const auto& L : loads->loads())
      history << fmt::format(",{:.9e},{:.9e},{:.9e}", L.reaction.x, L.reaction.y, L.reaction.z);
    for (const auto& p : loads->projectiles())
      for (const Vec3* q : {&p.x, &p.v, &p.a, &p.force, &p.a_filtered})
        history << fmt::format(",{:.9e},{:.9e},{:.9e}", q->x, q->y, q->z);
    if (s.block_names.size() > 1)
      for (const Vec3& v : body_velocities(s)) history << fmt::format(",{:.9e},{:.9e},{:.9e}", v.x, v.y, v.z);
    if (s.fe) history << fmt::format(",{:.9e}", s.fe->coupling_work);
    if (s.heat.active()) history << fmt::format(",{:.9e},{:.9e},", g.thermal_work, s.heat.time) << heat_history_row(s);
    history << history_columns_row(config, s) << "\n";
  }
  void write_frame() { write_frame(solver->time(), step_offset + solver->steps()); }
  void write_frame(double time, int64_t step) {
    if (exodus) exodus->write(s, dd.get(), time);  // output.format exodus or both
    if (!config.output.writes_vtu()) {
      ++frame_count;
      return;
    }
    const std::string base = fmt::format("frame_{:05d}", frame_count++);
    if (s.heat.active()) update_heat_flux(s);
    write_frame_files(dir.string(), base, make_frame(s, time, step), time, *pvd, dd.get());
  }
  bool at_end() const {
    return adaptive ? solver->time() >= end_time * (1 - 1e-12) : solver->steps() >= total;
  }

  // Checkpoint and restart (output/checkpoint.hpp): the run's whole state, the solver's,
  // the system's and the loads', and the output bookkeeping (history rows so far, frames
  // and the PVD index), so that a restart continues history.csv and frames.pvd without
  // a lost or repeated row or frame.
  void checkpoint(StateArchive& a) {
    a.check("run", std::string("explicit"), "a run of kind");
    solver->checkpoint(a);
    checkpoint_system(s, a);
    loads->checkpoint(a);
    std::string rows = history.str();
    a.io("history", rows);
    a.io("max_balance_error", max_balance_error);
    a.io("frame_count", frame_count);
    a.io("next_frame", next_frame);
    a.io("total", total);
    a.io("dt_nominal", dt_nominal);
    a.io("dt_min", dt_min);
    a.io("dt_max", dt_max);
    std::vector<double> times, crack_rows;
    std::string files;
    for (const auto& [t, f] : pvd->entries()) times.push_back(t), files += f + "\n";
    for (const auto& [t, l] : crack->history) crack_rows.push_back(t), crack_rows.push_back(l);
    a.io("pvd_times", times);
    a.io("pvd_files", files);
    a.io("crack_history", crack_rows);
    a.io("heat_initial", heat_initial);
    a.io_particles("heat_strain_change", strain_change);  // per particle: from the owners on ranks
    a.io("heat_pending_work", pending_work);
    if (!a.loading()) return;
    history = std::ostringstream();
    history << rows;
    std::vector<std::pair<double, std::string>> entries;
    std::size_t at = 0;
    for (double t : times) {
      const std::size_t end = files.find('\n', at);
      if (end == std::string::npos) throw Error("checkpoint: the frame index is shorter than its list of times");
      entries.emplace_back(t, files.substr(at, end - at));
      at = end + 1;
    }
    pvd->set_entries(std::move(entries));
    crack->history.clear();
    for (std::size_t k = 0; k + 1 < crack_rows.size(); k += 2) crack->history.emplace_back(crack_rows[k], crack_rows[k + 1]);
  }
  std::string checkpoint_path() const { return (dir / "checkpoint.hzc").string(); }
  // Also rewrites history.csv with the rows so far, so that a run killed later keeps on
  // disk what its checkpoint holds. On several ranks every rank lists the same records;
  // the per-particle and per-bond ones are gathered from their owners onto rank 0
  // (gather_checkpoint), which alone writes: one file of the global state, in index
  // order, the same bytes a run on any rank count would restart from.
  void write_checkpoint() {
    if (dd && dd->local_particles && dd->size > 1) {
      write_checkpoint_streamed();
      return;
    }
    sync();  // the global broken-bond count (and every particle's state) on every rank
    CheckpointWriter w;
    checkpoint(w);
    if (dd) gather_checkpoint(s, *dd, w);
    std::string failure;
    if (lead) {
      try {
        // history.csv first: once the checkpoint file is on disk, so are its rows.
        write_file_atomic((dir / "history.csv").string(), history.str());
        w.write(checkpoint_path());
      } catch (const OutputError& e) {
        failure = e.what();
      }
    }
    // Every rank stops on rank 0's output error (the loop's collectives stay matched).
    if (dd ? any_rank(*dd, !failure.empty()) : !failure.empty())
      throw OutputError(lead ? failure : "rank 0 could not write the checkpoint");
  }
  // Local particles: no rank holds the whole file (parallel/checkpoint_stream.hpp): rank 0
  // writes the records as they come from the owners, in windows of global ids.
  void write_checkpoint_streamed() {
    s.broken = global_broken_bonds(s, *dd);  // the file's count is the whole system's
    CheckpointWriter records(CheckpointWriter::Keep::list);
    checkpoint(records);
    // Every record goes to rank 0's file as the run lists it (no copy of the state).
    auto send = [&](CheckpointStream* out) {
      CheckpointSender sender(s, *dd, records, out);
      checkpoint(sender);
      sender.end();
    };
    std::string failure;
    bool streamed = false;
    if (lead) {
      try {
        // history.csv first: once the checkpoint file is on disk, so are its rows.
        write_file_atomic((dir / "history.csv").string(), history.str());
        write_file_atomic(checkpoint_path(), [&](std::ostream& o) {
          streamed = true;
          CheckpointStream out(&o);
          send(&out);
        });
      } catch (const OutputError& e) {
        failure = e.what();
      }
      if (!streamed) {  // the file could not be opened: rank 0 still takes its part
        CheckpointStream none(nullptr);
        send(&none);
      }
    } else {
      send(nullptr);
    }
    if (any_rank(*dd, !failure.empty())) throw OutputError(lead ? failure : "rank 0 could not write the checkpoint");
  }
  void read_checkpoint(const std::string& path) {
    try {
      CheckpointReader in(path);
      if (dd && dd->local_particles && dd->size > 1) {
        // Each rank reads the entries of the particles and rows it holds.
        CheckpointWriter mine(CheckpointWriter::Keep::list);
        checkpoint(mine);
        pick_local_entries(s, *dd, mine, in);
      } else if (dd && dd->local_rows) {
        // The file holds the whole system's bonds: each rank keeps its own rows.
        CheckpointWriter mine(CheckpointWriter::Keep::list);
        checkpoint(mine);
        keep_local_bonds(s, *dd, mine.bond_records(), in);
      }
      checkpoint(in);
      in.finish();
    } catch (const Error& e) {
      throw Error(fmt::format("{}: --restart: {}", config.deck_file, e.what()));
    }
    steps_at_start = solver->steps();
  }
  int64_t steps_at_start = 0;  // a restart's first step - 1
};

}  // namespace horizon
