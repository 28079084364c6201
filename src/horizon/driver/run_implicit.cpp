// `horizon run` for solver.type static and implicit_dynamic: the same outputs as the
// explicit driver (frames, history.csv, summary.json), from the static load stepping
// (solver/static_driver.hpp) or the Newmark solver (solver/newmark.hpp).
#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "horizon/core/error.hpp"
#include "horizon/core/interrupt.hpp"
#include "horizon/core/progress.hpp"
#include "horizon/core/version.hpp"
#include "horizon/driver/exodus_output.hpp"
#include "horizon/driver/history_columns.hpp"
#include "horizon/driver/summary.hpp"
#include "horizon/driver/run.hpp"
#include "horizon/driver/model_list.hpp"
#include "horizon/loading/loads.hpp"
#include "horizon/material/stress_field.hpp"
#include "horizon/output/atomic_file.hpp"
#include "horizon/output/pvd.hpp"
#include "horizon/output/vtu.hpp"
#include "horizon/parallel/decomposition.hpp"
#include "horizon/solver/conditioning.hpp"
#include "horizon/solver/forces.hpp"
#include "horizon/solver/newmark.hpp"
#include "horizon/solver/static_driver.hpp"

namespace horizon {

namespace fs = std::filesystem;

namespace {

const char* linear_name(LinearSolverKind k) {
  switch (k) {
    case LinearSolverKind::cg: return "cg";
    case LinearSolverKind::cholesky: return "cholesky";
    case LinearSolverKind::matrix_free: return "matrix_free";
  }
  return "";
}

// What one row of history.csv needs beyond the ledger.
struct Row {
  double time = 0, dt = 0, lambda = 0, residual = 0;
  int64_t step = 0, iterations = 0, linear_iterations = 0;
  int break_rounds = 0;
};

}  // namespace

// Local rows on several ranks: each particle's tensor from the rank that owns it (its
// row is held there alone), on rank 0 in index order; other ranks get an empty vector.
// Collective.
static std::vector<SymTensor> gather_row_tensors(const System& s, const Decomposition& d,
                                                 const std::vector<SymTensor>& mine) {
  std::vector<SymTensor> whole;
  for (std::size_t c = 0; c < 6; ++c) {
    std::vector<double> a(mine.size());
    for (std::size_t i = 0; i < mine.size(); ++i) a[i] = mine[i][c];
    const std::vector<double> w = gather_on_lead(s, d, a);
    if (d.rank != 0) continue;
    whole.resize(w.size());
    for (std::size_t i = 0; i < w.size(); ++i) whole[i][c] = w[i];
  }
  return whole;
}

// Why this implicit deck cannot be split over ranks beyond distributed_limits (run.hpp); empty when it can.
static std::string implicit_distributed_limits(const Config& c, const System& s) {
  const SolverConfig& sc = c.solver;
  // The models first: a model outside the unified form is split only when it is a
  // structure that splits its own pass (ModelTraits::structural and rows_local), solved by
  // ADR (solver/adr.cpp gathers the owned rows of its tangent); no other setting splits it.
  if (!unified_form(s)) {
    bool structures = true;
    for (const auto& m : s.models) structures = structures && m->traits().structural && m->traits().rows_local;
    if (structures && sc.type == SolverType::static_equilibrium && sc.method == StaticMethod::adr &&
        sc.tangent == TangentKind::analytic && !sc.condition_number)
      return "";
    return "static and implicit solves are split over ranks for the unified models only (" +
           model_list([](const ModelTraits& t) { return t.unified; }) +
           "), whose tangent is applied row by row, and for structures (" +
           model_list([](const ModelTraits& t) { return t.structural && t.rows_local; }) + ") with solver.method: adr";
  }
  const bool newton = sc.type == SolverType::implicit_dynamic || sc.method == StaticMethod::newton;
  if (newton && sc.linear_solver != LinearSolverKind::matrix_free)
    return fmt::format("solver.linear_solver {} assembles the whole tangent on one rank; on several ranks use "
                       "linear_solver: matrix_free{}",
                       linear_name(sc.linear_solver), sc.type == SolverType::static_equilibrium ? " (or method: adr)" : "");
  if (sc.condition_number) return "solver.condition_number assembles the whole tangent on one rank";
  return "";
}

int run_implicit_deck(Config config, const RunOptions& options) {
  apply_run_options(config, options);
  if (options.threads > 0) omp_set_num_threads(options.threads);
  const auto wall_start = std::chrono::steady_clock::now();
  const SolverConfig& sc = config.solver;
  const bool is_static = sc.type == SolverType::static_equilibrium;

  // Contact forces depend on the positions outside the bond list: neither the tangent nor
  // the static load path has them yet.
  if (config.contact.short_range.enabled || !config.contact.indenters.empty())
    throw Error("contact (short-range or rigid indenters) is available with solver type explicit only");
  const fs::path dir = config.output.directory;
  prepare_output_directory(dir.string(), "frames");  // before the (long) set-up
  // An MPI build holds on each rank only the bond rows it computes when the deck allows it
  // (local_rows_allowed: unified models, matrix-free Newton or ADR), as the explicit driver
  // does; every particle stays on every rank (the distributed vectors are indexed by the
  // global DofMap). HORIZON_MPI_WHOLE_SYSTEM=1 builds the whole system (the same bits).
  const char* whole = std::getenv("HORIZON_MPI_WHOLE_SYSTEM");
  const bool local_rows = mpi_built() && local_rows_allowed(config) && !(whole && std::string(whole) == "1");
  System s = local_rows ? build_system_split(config) : build_system(config);
  std::unique_ptr<Decomposition> dd;
  if (local_rows) {  // decomposed before anything reads the rows (Loads, the solvers)
    std::string why = distributed_limits(config, s, options);
    if (why.empty()) why = implicit_distributed_limits(config, s);
    if (!why.empty())
      throw Error(fmt::format("{}: internal error: a deck built with local rows cannot be split: {}", config.deck_file,
                              why));
    dd = std::make_unique<Decomposition>();
    dd->local_rows = true;
    decompose(s, *dd, config.spacing);
  }
  Loads loads(config, s);
  loads.apply_initial_conditions(config, s);
  // An MPI build splits a static or implicit solve over its ranks when it can
  // (docs/design.md, "Static and implicit solves on several ranks"), on one rank too, so
  // that any rank count gives the same bits; rank 0 alone writes the output, from every
  // particle's state gathered.
  const bool lead = world_rank() == 0;
  RunOptions opts = options;
  if (!lead) opts.quiet = true;
  if (mpi_built() && !dd) {
    std::string why = distributed_limits(config, s, options);
    if (why.empty()) why = implicit_distributed_limits(config, s);
    if (why.empty()) {
      dd = std::make_unique<Decomposition>();
      decompose(s, *dd, config.spacing);
    } else if (world_size() > 1) {
      throw Error(fmt::format("{}: this deck cannot run on {} MPI ranks yet: {}; run it on one rank",
                              config.deck_file, world_size(), why));
    }
  }
  // Every particle's state on this rank, before anything reads the whole body.
  auto sync = [&] {
    if (dd) gather_state(s, *dd);
  };
  // The stable explicit step (for the print): a decomposed run's owned particles, the minimum over ranks.
  double stable_dt = 0;
  if (!is_static) stable_dt = dd ? min_over_ranks(stable_time_step(s)) : stable_time_step(s);
  if (!opts.quiet) {
    fmt::print(stderr, "deck            {}\n", config.deck_file);
    fmt::print(stderr, "particles       {}\n", s.particles.size());
    if (dd && dd->local_rows && dd->size > 1)
      fmt::print(stderr, "bonds           {} directed (local rows: rank 0 holds {})\n", s.initial_bonds,
                 s.bonds.size());
    else
      fmt::print(stderr, "bonds           {} directed\n", s.initial_bonds);
    if (is_static) {
      fmt::print(stderr, "solver          static, {}{}, {} load steps, tolerance {:.1e}\n",
                 sc.method == StaticMethod::newton ? "newton" : "adr",
                 sc.method == StaticMethod::newton ? std::string(", ") + linear_name(sc.linear_solver) : "",
                 sc.load_steps, sc.tolerance);
    } else {
      fmt::print(stderr, "solver          implicit_dynamic (Newmark, average acceleration), {}, dt {:.4e} s "
                         "({:.1f} x the stable explicit step)\n",
                 linear_name(sc.linear_solver), *sc.time_step, *sc.time_step / stable_dt);
    }
  }

  PvdIndex pvd((dir / "frames.pvd").string());

  NewtonOptions newton;
  newton.linear_solver = sc.linear_solver;
  newton.tangent = sc.tangent;
  newton.tolerance = sc.tolerance;
  newton.max_iterations = sc.max_iterations.value_or(30);
  std::unique_ptr<StaticSolver> statics;
  std::unique_ptr<NewmarkSolver> dynamics;
  if (is_static) {
    statics = std::make_unique<StaticSolver>(s, loads, sc);
    statics->initialize();
  } else {
    dynamics = std::make_unique<NewmarkSolver>(s, loads, *sc.time_step, sc.damping, newton, sc.max_break_rounds);
    dynamics->set_zero_initial_acceleration(sc.zero_initial_acceleration);
    dynamics->initialize();
  }
  const DofMap& dofs = is_static ? statics->dofs() : dynamics->dofs();
  auto ledger = [&]() -> const Ledger& { return is_static ? statics->ledger() : dynamics->ledger(); };

  // Condition number of the tangent at the initial state (solver.condition_number).
  nlohmann::ordered_json condition;
  if (sc.condition_number) {
    const auto t0 = std::chrono::steady_clock::now();
    SparseMatrix K;
    {
      FixedBonds fixed(s);
      compute_forces(s, false);
      K = solver_tangent(s, dofs, sc.tangent);
    }
    if (!is_static) {
      Eigen::VectorXd shift = (4.0 / (*sc.time_step * *sc.time_step)) * nodal_mass(s, dofs);
      add_to_diagonal(K, shift);
    }
    const ConditionEstimate c = estimate_condition(K);
    condition["of"] = is_static ? "K" : "K + 4 M / dt^2";
    condition["lambda_min"] = c.lambda_min;
    condition["lambda_max"] = c.lambda_max;
    condition["condition_number"] = c.condition;
    condition["seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!c.message.empty()) condition["message"] = c.message;
    if (!opts.quiet) {
      if (c.converged)
        fmt::print(stderr, "condition       {:.4e} (lambda {:.4e} .. {:.4e})\n", c.condition, c.lambda_min,
                   c.lambda_max);
      else
        fmt::print(stderr, "condition       not estimated: {}\n", c.message);
    }
  }

  std::ostringstream history;
  history << "time,step,dt,kinetic_energy,strain_energy,external_work,dissipated_energy,damped_energy,"
             "energy_balance_error,broken_bond_fraction,damage_max";
  for (const auto& L : loads.loads()) history << "," << L.name << "_fx," << L.name << "_fy," << L.name << "_fz";
  // The mean displacement of each constrained region (load-displacement curves).
  auto is_constraint = [](const AppliedLoad& L) {
    return L.kind == LoadKind::displacement || L.kind == LoadKind::velocity;
  };
  for (const auto& L : loads.loads())
    if (is_constraint(L)) history << "," << L.name << "_ux," << L.name << "_uy," << L.name << "_uz";
  history << ",load_factor,iterations,linear_iterations,residual,break_rounds" << history_columns_header(config) << "\n";
  double max_balance_error = 0;
  auto record_history = [&](const Row& r) {
    const Ledger& g = ledger();
    double dmax = 0;
    for (double d : s.particles.damage) dmax = std::max(dmax, d);
    const double broken_fraction =
        s.initial_bonds ? static_cast<double>(s.broken) / static_cast<double>(s.initial_bonds) : 0.0;
    max_balance_error = std::max(max_balance_error, std::abs(g.balance_error()));
    history << fmt::format("{:.9e},{},{:.6e},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.6e},{:.6e},{:.6f}", r.time, r.step,
                           r.dt, g.kinetic, g.strain, g.external_work, g.dissipated, g.damped, g.balance_error(),
                           broken_fraction, dmax);
    for (const auto& L : loads.loads())
      history << fmt::format(",{:.9e},{:.9e},{:.9e}", L.reaction.x, L.reaction.y, L.reaction.z);
    for (const auto& L : loads.loads()) {
      if (!is_constraint(L)) continue;
      Vec3 mean;
      for (uint32_t i : L.particles) mean += s.particles.u[i];
      mean = mean / static_cast<double>(std::max<std::size_t>(1, L.particles.size()));
      history << fmt::format(",{:.9e},{:.9e},{:.9e}", mean.x, mean.y, mean.z);
    }
    history << fmt::format(",{:.9e},{},{},{:.3e},{}", r.lambda, r.iterations, r.linear_iterations, r.residual,
                           r.break_rounds)
            << history_columns_row(config, s) << "\n";
  };
  int frame_count = 0;
  // Collective (the stress of rows held elsewhere is gathered); rank 0 alone writes.
  // output.format exodus or both: one time step of the Exodus file per frame.
  std::unique_ptr<ExodusOutput> exodus;
  if (config.output.writes_exodus())
    exodus = std::make_unique<ExodusOutput>((dir / config.output.exodus_file).string(), true);
  // output.exodus_files: each on its own steps (static: load steps).
  std::unique_ptr<ExodusSchedule> exodus_files;
  if (!config.output.exodus_files.empty()) {
    exodus_files = std::make_unique<ExodusSchedule>(config.output.exodus_files, dir, true, config);
    exodus_files->prepare(s);
  }
  auto write_frame = [&](double time, int64_t step) {
    if (exodus) exodus->write(s, dd.get(), time);
    if (!config.output.writes_vtu()) return;
    std::vector<SymTensor> sigma;
    // Stress from the nonlocal deformation gradient and Hooke's law (material/stress_field.hpp);
    // a thin structure reports its section fields (deflection, curvature, moment) instead.
    if (config.structure.kind == StructureKind::none) {
      sigma = stress_field(s, config.materials, config.plane);
      // Local rows: a particle's stress reads its own row, held by its owner alone.
      if (dd && dd->local_rows && dd->size > 1) sigma = gather_row_tensors(s, *dd, sigma);
    }
    if (!lead) return;
    const std::string name = fmt::format("frames/frame_{:05d}.vtu", frame_count++);
    Frame f = make_frame(s, time, step);
    if (config.structure.kind == StructureKind::none) {
      const char* names[6] = {"stress_xx", "stress_yy", "stress_zz", "stress_xy", "stress_yz", "stress_xz"};
      const int shown[3][6] = {{0, -1, -1, -1, -1, -1}, {0, 1, 3, -1, -1, -1}, {0, 1, 2, 3, 4, 5}};
      for (int c : shown[config.dimension - 1]) {
        if (c < 0) continue;
        FrameField ff{names[c], 1, std::vector<double>(sigma.size())};
        for (std::size_t i = 0; i < sigma.size(); ++i) ff.data[i] = sigma[i][static_cast<std::size_t>(c)];
        f.fields.push_back(std::move(ff));
      }
      FrameField vm{"von_mises", 1, std::vector<double>(sigma.size())};
      for (std::size_t i = 0; i < sigma.size(); ++i) vm.data[i] = von_mises(sigma[i]);
      f.fields.push_back(std::move(vm));
    }
    write_vtu((dir / name).string(), f);
    pvd.add(time, name);
    pvd.write();
  };

  sync();
  record_history(Row{});
  write_frame(0, 0);
  if (exodus_files) exodus_files->write(s, dd.get(), 0, 0);
  int64_t exodus_written = 0;  // static: the last load step the schedule saw
  // static: the load steps after which a Peridigm solver starts (solver_starts), and how
  // many have been written (each one more Exodus step).
  std::vector<int64_t> start_steps;
  int64_t starts_passed = 0;
  if (is_static)
    for (double t : sc.solver_starts) start_steps.push_back(statics->load_step_at_time(t));
  install_interrupt_handler();
  const int frames = std::max(1, config.output.frames);
  const int64_t total = is_static ? sc.load_steps : step_count(config, *sc.time_step);
  Progress progress(total, static_cast<double>(s.bonds.size()), config.output.progress_every);
  std::string status = "completed", message;
  int exit_code = 0;
  int next_frame = 1;
  int64_t steps = 0;
  double time = 0;
  try {
  while (true) {
    Row row;
    if (is_static) {
      if (statics->done()) break;
      const double time_before = statics->time();
      // A Peridigm solver starting after this load step (solver_starts): its start frame
      // holds fields as of the step before it (ExodusOutput::hold_fields).
      if (exodus_files && !start_steps.empty()) exodus_files->hold_fields(s);
      std::vector<Vec3> u_before;
      if (exodus || exodus_files) u_before = s.particles.u;
      if (!statics->advance()) {
        status = "not converged";
        exit_code = 4;
        message = statics->failure();
        break;
      }
      steps = statics->steps();
      time = statics->time();
      if (exodus) exodus->set_step_velocity(s.particles.u, u_before, time - time_before);
      if (exodus_files) exodus_files->set_step_velocity(s.particles.u, u_before, time - time_before);
      if (exodus) exodus->set_iterations(statics->last_iterations());
      if (exodus_files) exodus_files->set_iterations(statics->last_iterations());
      row = {time, statics->increment() * sc.end_time, statics->lambda(), statics->last_report().residual, steps,
             statics->last_iterations(), statics->last_linear_iterations(), statics->last_break_rounds()};
      sync();
      record_history(row);
      if (statics->lambda() * frames >= next_frame - 1e-9) {
        write_frame(time, steps);
        while (statics->lambda() * frames >= next_frame - 1e-9) ++next_frame;
      }
      if (exodus_files) {
        // At the end of a load step (a cut increment's parts end between them).
        const int64_t k = statics->load_step();
        if (k > exodus_written) {
          exodus_written = k;
          if (exodus_files->due(k + starts_passed)) exodus_files->write(s, dd.get(), time, k + starts_passed);
          // Peridigm writes the state again at a new solver's start, as one more output
          // step (PredictorFromPreviousSolver's golds: t = 0, 1, 1, 2 for Solver1 0..1
          // and Solver2 1..2): the later load steps count one on.
          if (std::find(start_steps.begin(), start_steps.end(), k) != start_steps.end()) {
            ++starts_passed;
            exodus_files->write_solver_start(s, dd.get(), time, k + starts_passed);
          }
        }
      }
      if (!opts.quiet) progress.update(static_cast<int64_t>(std::lround(statics->lambda() * sc.load_steps)), time);
    } else {
      if (dynamics->steps() >= total) break;
      const SolveReport rep = dynamics->step();
      if (!rep.converged) {
        status = "not converged";
        exit_code = 4;
        message = fmt::format("step {}, t = {:.4e} s: {}", dynamics->steps() + 1, dynamics->time() + dynamics->dt(),
                              rep.failure);
        break;
      }
      steps = dynamics->steps();
      time = dynamics->time();
      row = {time, dynamics->dt(), 0, rep.residual, steps, rep.iterations, rep.linear_iterations, 0};
      if (exodus) exodus->set_iterations(rep.iterations);
      if (exodus_files) exodus_files->set_iterations(rep.iterations);
      const int64_t every = std::max(1, config.output.history_every);
      const bool history_due = steps % every == 0 || steps == total;
      const bool frame_due = steps * frames >= static_cast<int64_t>(next_frame) * total;
      const bool exodus_due = exodus_files && exodus_files->due(steps);
      if (history_due || frame_due || exodus_due) sync();
      if (history_due) record_history(row);
      if (frame_due) {
        write_frame(time, steps);
        ++next_frame;
      }
      if (exodus_due) exodus_files->write(s, dd.get(), time, steps);
      if (!opts.quiet) progress.update(steps, time);
    }
    if (dd ? any_rank(*dd, interrupt_requested()) : interrupt_requested()) {
      status = "interrupted";
      exit_code = interrupt_exit_code();
      message = fmt::format("{} at step {}; a final frame was written", interrupt_name(), steps);
      break;
    }
  }
  } catch (const OutputError& e) {
    // As in the explicit run: the frames listed in frames.pvd are complete, the failed one
    // is not listed, and no final frame is tried.
    status = "output error";
    exit_code = 5;
    message = fmt::format("output error: {}; stopped at step {}, frames.pvd lists the {} complete frames", e.what(),
                          steps, pvd.entries().size());
  }
  if (!opts.quiet) progress.finish();
  sync();
  if (exit_code != 0 && exit_code != 5) write_frame(time, steps);
  clear_interrupt();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  // After an output error, history and summary are tried once (they are small) and their
  // failure only reported.
  auto write_result = [&](const std::string& name, const std::string& text) {
    if (!lead) return;
    write_result_file((dir / name).string(), text, exit_code == 5);
  };
  write_result("history.csv", history.str());

  const Ledger& g = ledger();
  nlohmann::ordered_json j = summary_header(config, s, status, message, steps);
  j["time_step"] = is_static ? sc.end_time / sc.load_steps : *sc.time_step;
  j["time"] = time;
  j["threads"] = omp_get_max_threads();
  j["ranks"] = dd ? dd->size : 1;
  if (dd) {  // the bonds each rank holds (local rows: its rows; else the whole system)
    const std::vector<uint64_t> held = gather_on_lead(static_cast<uint64_t>(s.bonds.size()));
    if (lead) j["bonds_held"] = held;
  }
  j["state_crc32"] = state_digest(s);
  j["wall_time_s"] = wall;
  j["loop_time_s"] = progress.elapsed();
  j["peak_memory_bytes"] = peak_memory_bytes();
  summary_state(j, s, g, loads, max_balance_error);
  nlohmann::ordered_json sj;
  sj["type"] = is_static ? "static" : "implicit_dynamic";
  sj["dofs"] = dofs.size();
  if (is_static) {
    sj["method"] = sc.method == StaticMethod::newton ? "newton" : "adr";
    if (sc.method == StaticMethod::newton) sj["linear_solver"] = linear_name(sc.linear_solver);
    sj["load_factor"] = statics->lambda();
    sj["iterations"] = statics->total_iterations();
    sj["linear_iterations"] = statics->total_linear_iterations();
    sj["step_cuts"] = statics->total_cuts();
    sj["tangent_seconds"] = statics->tangent_seconds();
    sj["solve_seconds"] = statics->solve_seconds();
    sj["tangent_bytes"] = statics->tangent_bytes();
    sj["tangent_nonzeros"] = statics->tangent_nonzeros();
    sj["tangent_bytes_per_bond"] =
        s.bonds.size() ? static_cast<double>(statics->tangent_bytes()) / static_cast<double>(s.bonds.size()) : 0.0;
    if (statics->factor_fill() > 0) sj["cholesky_factor_nonzeros"] = statics->factor_fill();
  } else {
    sj["linear_solver"] = linear_name(sc.linear_solver);
    sj["iterations"] = dynamics->newton_iterations();
    sj["linear_iterations"] = dynamics->linear_iterations();
  }
  if (!condition.empty()) sj["condition"] = condition;
  j["solver"] = sj;
  const std::string energy_warning = energy_balance_warning(config, s, max_balance_error);
  if (!energy_warning.empty()) j["warnings"] = {energy_warning};
  write_result("summary.json", j.dump(2) + "\n");
  if (!energy_warning.empty() && lead) fmt::print(stderr, "horizon: warning: {}\n", energy_warning);

  if (!opts.quiet) {
    fmt::print(stderr, "{} in {} ({} {}); output in {}\n", status, format_duration(wall), steps,
               is_static ? "load increments" : "steps", dir.string());
  }
  if (!message.empty() && lead) fmt::print(stderr, "horizon: {}\n", message);
  return exit_code;
}

}  // namespace horizon
