// solver.type heat: nonlocal heat conduction alone (thermal/heat.hpp), frames, history
// and summary as the mechanical drivers write them.
#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <numeric>
#include <sstream>
#include <zlib.h>

#include "horizon/core/error.hpp"
#include "horizon/core/interrupt.hpp"
#include "horizon/driver/exodus_output.hpp"
#include "horizon/driver/run.hpp"
#include "horizon/driver/summary.hpp"
#include "horizon/output/atomic_file.hpp"
#include "horizon/output/pvd.hpp"
#include "horizon/output/vtu.hpp"
#include "horizon/parallel/decomposition.hpp"
#include "horizon/thermal/heat.hpp"

namespace horizon {

namespace fs = std::filesystem;

std::string heat_history_header(const System& s) {
  std::string h = "temperature_min,temperature_max,temperature_mean,heat_content,plastic_heat";
  for (const auto& bc : s.heat.boundary) h += "," + bc.name + "_heat";
  return h;
}

namespace {
// The lowest, highest and mean temperature. In a run split over MPI ranks each rank reads
// its owned particles (the others' temperatures are not kept current here), the minimum
// and maximum over the ranks, the mean from a grid sum (thermal/heat.cpp); serially every
// particle in index order.
void temperature_range(const System& s, double& lo, double& hi, double& mean) {
  const auto& T = s.heat.T;
  lo = 1e300, hi = -1e300, mean = 0;
  if (s.decomposition) {
    GridSum sum(s, 1);
    for (uint32_t i : s.owned) lo = std::min(lo, T[i]), hi = std::max(hi, T[i]), sum.add(0, T[i]);
    lo = min_over_ranks(lo);
    hi = -min_over_ranks(-hi);
    mean = sum.totals()[0] / static_cast<double>(std::max<uint64_t>(1, sum_over_ranks(s.owned.size())));
    return;
  }
  for (double v : T) lo = std::min(lo, v), hi = std::max(hi, v), mean += v;
  mean /= static_cast<double>(std::max<std::size_t>(1, T.size()));
}

// CRC-32 of every particle's temperature in global order (Particles::id): in a run split
// over MPI ranks each owner's values, gathered on every rank. The bits a heat run ends in,
// as state_crc32 for the mechanics. Collective when decomposed.
uint32_t temperature_crc32(const System& s) {
  std::vector<double> T = s.heat.T;
  if (s.decomposition) {
    std::vector<double> mine, ids;
    for (uint32_t i : s.owned) {
      mine.push_back(s.heat.T[i]);
      ids.push_back(static_cast<double>(s.particles.id.empty() ? i : s.particles.id[i]));  // exact below 2^53
    }
    const std::vector<double> all = allgather_values(mine), all_ids = allgather_values(ids);
    std::vector<std::size_t> order(all.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return all_ids[a] < all_ids[b]; });
    T.resize(all.size());
    for (std::size_t k = 0; k < order.size(); ++k) T[k] = all[order[k]];
  }
  uLong crc = crc32(0L, Z_NULL, 0);
  crc = crc32(crc, reinterpret_cast<const Bytef*>(T.data()), static_cast<uInt>(T.size() * sizeof(double)));
  return static_cast<uint32_t>(crc);
}
}  // namespace

std::string heat_history_row(const System& s) {
  double lo = 0, hi = 0, mean = 0;
  temperature_range(s, lo, hi, mean);
  std::string r = fmt::format("{:.9e},{:.9e},{:.9e},{:.9e},{:.9e}", lo, hi, mean, heat_content(s), s.heat.plastic_heat);
  for (const auto& bc : s.heat.boundary) r += fmt::format(",{:.9e}", bc.heat);
  return r;
}

nlohmann::ordered_json heat_summary(const System& s, double heat_step, double stable_step, double initial_content,
                                    double moved) {
  nlohmann::ordered_json j;
  double lo = 0, hi = 0, mean = 0, supplied = s.heat.plastic_heat, largest = moved;
  temperature_range(s, lo, hi, mean);
  nlohmann::ordered_json b = nlohmann::ordered_json::object();
  for (const auto& bc : s.heat.boundary) {
    b[bc.name] = bc.heat;
    supplied += bc.heat;
    largest = std::max(largest, std::abs(bc.heat));
  }
  const double content = heat_content(s);
  j["time_step"] = heat_step;
  j["stable_time_step"] = stable_step;
  j["temperature_min"] = lo;
  j["temperature_max"] = hi;
  j["heat_content"] = content;
  j["heat_content_change"] = content - initial_content;
  j["plastic_heat"] = s.heat.plastic_heat;
  j["boundary_heat"] = b;
  // Conduction conserves heat: the change of content is what the boundaries and the
  // plastic work brought in (relative to the largest of them, of any one boundary's net,
  // or of the heat the boundaries moved particle by particle: a steady solve stores
  // nothing, and what a boundary brings in at one end it takes out at the other).
  const double scale =
      std::max({std::abs(content - initial_content), std::abs(supplied), largest, 1e-300});
  j["heat_balance_error"] = (content - initial_content - supplied) / scale;
  j["temperature_crc32"] = temperature_crc32(s);
  return j;
}

int run_heat_deck(Config config, const RunOptions& options) {
  apply_run_options(config, options);
  if (options.threads > 0) omp_set_num_threads(options.threads);
  const auto wall_start = std::chrono::steady_clock::now();
  // Split over MPI ranks as a coupled run is (driver/run.cpp): each rank advances its owned
  // temperatures and receives its ghosts', the backward-Euler step a distributed conjugate
  // gradient (thermal/heat.cpp). An MPI build decomposes on one rank too, so that one rank
  // and many give the same bits; on more than one it holds local particles (the rows of
  // its owned particles and the particles they read; HORIZON_MPI_LOCAL_PARTICLES=0 keeps
  // every particle). Rank 0 writes the history and summary; every rank its own piece of
  // each frame.
  // Finite-element regions are not split (as in a coupled run): one rank only.
  std::unique_ptr<Decomposition> dd;
  const char* particles_env = std::getenv("HORIZON_MPI_LOCAL_PARTICLES");
  Config as_explicit = config;  // local particles where an explicit run of the deck would hold them
  as_explicit.solver.type = SolverType::explicit_dynamic;
  const bool local = mpi_built() && world_size() > 1 && local_particles_allowed(as_explicit) &&
                     !(particles_env && std::string(particles_env) == "0");
  if (mpi_built()) dd = std::make_unique<Decomposition>();
  System s = local ? build_system_split(config, *dd) : build_system(config);
  if (s.fe) {
    if (world_size() > 1)
      throw Error(fmt::format("{}: finite-element regions are not split over ranks; run this deck on one rank",
                              config.deck_file));
    dd.reset();
  }
  if (dd) {
    dd->local_rows = local;
    decompose(s, *dd, config.spacing);
  }
  const bool lead = world_rank() == 0;
  RunOptions opts = options;
  if (!lead) opts.quiet = true;
  const double stable = heat_stable_step(s);
  const bool steady = config.thermal.integration == HeatIntegration::steady;
  const bool implicit = config.thermal.integration != HeatIntegration::explicit_euler;
  const double dt = config.solver.time_step ? *config.solver.time_step : config.solver.safety_factor * stable;
  if (!implicit && dt > stable)
    throw Error(fmt::format("solver.time_step {:.4e} s exceeds the stable step of the explicit heat solver, {:.4e} s; "
                            "use a smaller step or thermal.integration: implicit",
                            dt, stable));
  const int64_t total = static_cast<int64_t>(std::ceil(config.solver.end_time / dt - 1e-9));
  if (!opts.quiet) {
    fmt::print(stderr, "deck            {}\n", config.deck_file);
    fmt::print(stderr, "particles       {}\n", dd && dd->local_particles ? dd->global_particles : s.particles.size());
    fmt::print(stderr, "bonds           {} directed\n", s.initial_bonds);
    fmt::print(stderr, "solver          heat, {}\n",
               steady ? "steady solves" : implicit ? "backward Euler" : "forward Euler");
    fmt::print(stderr, "stable step     {:.4e} s (explicit heat)\n", stable);
    fmt::print(stderr, "time step       {:.4e} s, {} steps to t = {:.4e} s\n", dt, total, config.solver.end_time);
  }
  const fs::path dir = config.output.directory;
  if (lead) fs::create_directories(dir / "frames");
  if (dd) any_rank(*dd, false);  // a barrier: the directory exists
  PvdIndex pvd((dir / "frames.pvd").string());
  std::ostringstream history;
  history << "time,step," << heat_history_header(s) << "\n";
  int frame_count = 0;
  const double initial_content = heat_content(s);
  auto write_frame = [&](double t, int64_t step) {
    update_heat_flux(s);
    const std::string base = fmt::format("frame_{:05d}", frame_count++);
    write_frame_files(dir.string(), base, make_frame(s, t, step), t, pvd, dd.get());
  };
  HeatSolver solver(s, config.thermal.integration);
  history << fmt::format("{:.9e},0,", 0.0) << heat_history_row(s) << "\n";
  write_frame(0, 0);
  // output.exodus_files: each at step 0 and at the steps its `every` divides (a steady
  // run's steps are its load steps: Peridigm's ImplicitDiffusion output).
  std::unique_ptr<ExodusSchedule> exodus_files;
  if (!config.output.exodus_files.empty()) {
    exodus_files = std::make_unique<ExodusSchedule>(config.output.exodus_files, dir, false, config);
    exodus_files->write(s, dd.get(), 0, 0);
  }
  const int frames = std::max(1, config.output.frames);
  const int64_t history_every = std::max(1, config.output.history_every);
  int next_frame = 1;
  if (options.handle_signals) install_interrupt_handler();
  std::string status = "completed";
  int exit_code = 0;
  int64_t step = 0;
  std::string message;
  try {
  while (step < total) {
    const double h = std::min(dt, config.solver.end_time - s.heat.time);
    solver.step(h > 0 ? h : dt);
    ++step;
    if (step % history_every == 0 || step == total)
      history << fmt::format("{:.9e},{},", s.heat.time, step) << heat_history_row(s) << "\n";
    if (step * frames >= static_cast<int64_t>(next_frame) * total) {
      write_frame(s.heat.time, step);
      ++next_frame;
    }
    if (exodus_files && exodus_files->due(step)) exodus_files->write(s, dd.get(), s.heat.time, step);
    const bool interrupted = options.handle_signals && interrupt_requested();
    if (dd ? any_rank(*dd, interrupted) : interrupted) {
      status = "interrupted";
      exit_code = interrupt_exit_code();
      message = fmt::format("{} at step {}; a final frame was written", interrupt_name(), step);
      write_frame(s.heat.time, step);
      break;
    }
  }
  } catch (const OutputError& e) {
    // The frames listed in frames.pvd are complete; the failed one is not listed.
    status = "output error";
    exit_code = 5;
    message = fmt::format("output error: {}; stopped at step {}, frames.pvd lists the {} complete frames", e.what(),
                          step, pvd.entries().size());
  }
  if (options.handle_signals) clear_interrupt();
  if (lead) write_result_file((dir / "history.csv").string(), history.str(), exit_code == 5);
  nlohmann::ordered_json j = summary_header(config, s, status, message, step);
  j["time"] = s.heat.time;
  j["wall_time_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  j["ranks"] = dd ? dd->size : 1;
  if (dd) {
    // The particles each rank holds (local particles: its owned ones and those their rows read).
    const std::vector<uint64_t> held = gather_on_lead(s.particles.size());
    j["particles"] = dd->local_particles ? dd->global_particles : s.particles.size();
    j["particles_local"] = dd->local_particles;
    j["particles_held"] = held;
  }
  j["thermal"] = heat_summary(s, dt, stable, initial_content, solver.moved());
  // (the improved quadrature's BiCGSTAB iterations under the same name)
  if (implicit) j["thermal"]["cg_iterations_last_step"] = solver.iterations();
  if (lead) write_result_file((dir / "summary.json").string(), j.dump(2) + "\n", exit_code == 5);
  if (!opts.quiet) fmt::print(stderr, "{}: {} heat steps; output in {}\n", status, step, dir.string());
  if (!message.empty() && lead) fmt::print(stderr, "horizon: {}\n", message);
  return exit_code;
}

}  // namespace horizon
