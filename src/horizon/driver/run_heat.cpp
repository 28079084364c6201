// solver.type heat: nonlocal heat conduction alone (thermal/heat.hpp), frames, history
// and summary as the mechanical drivers write them.
#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "horizon/core/error.hpp"
#include "horizon/core/interrupt.hpp"
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
}  // namespace

std::string heat_history_row(const System& s) {
  double lo = 0, hi = 0, mean = 0;
  temperature_range(s, lo, hi, mean);
  std::string r = fmt::format("{:.9e},{:.9e},{:.9e},{:.9e},{:.9e}", lo, hi, mean, heat_content(s), s.heat.plastic_heat);
  for (const auto& bc : s.heat.boundary) r += fmt::format(",{:.9e}", bc.heat);
  return r;
}

nlohmann::ordered_json heat_summary(const System& s, double heat_step, double stable_step, double initial_content) {
  nlohmann::ordered_json j;
  double lo = 0, hi = 0, mean = 0, supplied = s.heat.plastic_heat;
  temperature_range(s, lo, hi, mean);
  nlohmann::ordered_json b = nlohmann::ordered_json::object();
  for (const auto& bc : s.heat.boundary) {
    b[bc.name] = bc.heat;
    supplied += bc.heat;
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
  // plastic work brought in (relative to the largest of them).
  const double scale = std::max({std::abs(content - initial_content), std::abs(supplied), 1e-300});
  j["heat_balance_error"] = (content - initial_content - supplied) / scale;
  return j;
}

int run_heat_deck(Config config, const RunOptions& options) {
  apply_run_options(config, options);
  // Heat conduction alone runs in one process; coupled to an explicit run it splits over
  // ranks (driver/run.cpp).
  if (world_size() > 1)
    throw Error(fmt::format("{}: solver.type heat runs on one MPI rank (its coupled form, a thermal section in an "
                            "explicit run, splits over ranks); run it on one rank",
                            config.deck_file));
  if (options.threads > 0) omp_set_num_threads(options.threads);
  const auto wall_start = std::chrono::steady_clock::now();
  System s = build_system(config);
  const double stable = heat_stable_step(s);
  const bool implicit = config.thermal.integration == HeatIntegration::implicit_euler;
  const double dt = config.solver.time_step ? *config.solver.time_step : config.solver.safety_factor * stable;
  if (!implicit && dt > stable)
    throw Error(fmt::format("solver.time_step {:.4e} s exceeds the stable step of the explicit heat solver, {:.4e} s; "
                            "use a smaller step or thermal.integration: implicit",
                            dt, stable));
  const int64_t total = static_cast<int64_t>(std::ceil(config.solver.end_time / dt - 1e-9));
  if (!options.quiet) {
    fmt::print(stderr, "deck            {}\n", config.deck_file);
    fmt::print(stderr, "particles       {}\n", s.particles.size());
    fmt::print(stderr, "bonds           {} directed\n", s.bonds.size());
    fmt::print(stderr, "solver          heat, {} Euler\n", implicit ? "backward" : "forward");
    fmt::print(stderr, "stable step     {:.4e} s (explicit heat)\n", stable);
    fmt::print(stderr, "time step       {:.4e} s, {} steps to t = {:.4e} s\n", dt, total, config.solver.end_time);
  }
  const fs::path dir = config.output.directory;
  fs::create_directories(dir / "frames");
  PvdIndex pvd((dir / "frames.pvd").string());
  std::ostringstream history;
  history << "time,step," << heat_history_header(s) << "\n";
  int frame_count = 0;
  const double initial_content = heat_content(s);
  auto write_frame = [&](double t, int64_t step) {
    update_heat_flux(s);
    const std::string name = fmt::format("frames/frame_{:05d}.vtu", frame_count++);
    write_vtu((dir / name).string(), make_frame(s, t, step));
    pvd.add(t, name);
    pvd.write();
  };
  HeatSolver solver(s, config.thermal.integration);
  history << fmt::format("{:.9e},0,", 0.0) << heat_history_row(s) << "\n";
  write_frame(0, 0);
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
    if (options.handle_signals && interrupt_requested()) {
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
  write_result_file((dir / "history.csv").string(), history.str(), exit_code == 5);
  nlohmann::ordered_json j = summary_header(config, s, status, message, step);
  j["time"] = s.heat.time;
  j["wall_time_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  j["thermal"] = heat_summary(s, dt, stable, initial_content);
  write_result_file((dir / "summary.json").string(), j.dump(2) + "\n", exit_code == 5);
  if (!options.quiet) fmt::print(stderr, "{}: {} heat steps; output in {}\n", status, step, dir.string());
  if (!message.empty()) fmt::print(stderr, "horizon: {}\n", message);
  return exit_code;
}

}  // namespace horizon
