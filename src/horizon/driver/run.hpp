#pragma once
// `horizon run` and `horizon check` as library calls: deck -> system -> solver -> writers.
#include <cstdint>
#include <optional>
#include <nlohmann/json.hpp>
#include <string>

#include "horizon/deck/config.hpp"
#include "horizon/output/frame.hpp"
#include "horizon/solver/system.hpp"

namespace horizon {

struct RunOptions {
  std::optional<std::string> output_dir;  // overrides output.directory
  double coarsen = 1;                     // spacing and horizon times this (smoke tests, quick looks)
  std::optional<double> end_time;         // overrides solver.end_time
  bool quiet = false;                     // no progress line
  int threads = 0;                        // 0: OpenMP's default
};

struct CheckReport {
  std::size_t particles = 0;
  std::size_t bonds = 0;             // directed
  std::size_t precrack_bonds = 0;    // directed bonds removed by precracks
  std::size_t memory_bytes = 0;
  double stable_dt = 0;
  double dt = 0;                     // the step the run will use
  double heat_stable_dt = 0;         // the explicit heat stable step (thermal runs; 0 otherwise)
  int64_t steps = 0;
};

// Applies the command-line overrides to a deck.
void apply_run_options(Config& config, const RunOptions& options);

// The time step a run uses: solver.time_step, or the stable step times the safety factor.
double run_time_step(const Config& config, const System& s);

CheckReport check_system(const Config& config, const System& s);
std::string format_check(const Config& config, const CheckReport& r);

// Runs the deck and writes frames, history.csv and summary.json into the output
// directory. Returns the process exit code: 0 done, 2 non-finite state, 4 a static or
// implicit solve did not converge, 130 interrupted.
int run_deck(Config config, const RunOptions& options);

// The same for solver.type static and implicit_dynamic (driver/run_implicit.cpp).
int run_implicit_deck(Config config, const RunOptions& options);

// The same for solver.type heat (driver/run_heat.cpp).
int run_heat_deck(Config config, const RunOptions& options);

// The thermal columns of history.csv (after the mechanical ones in coupled runs), and the
// thermal part of summary.json (driver/run_heat.cpp).
std::string heat_history_header(const System& s);
std::string heat_history_row(const System& s);
nlohmann::ordered_json heat_summary(const System& s, double heat_step, double stable_step, double initial_content);

// Shared by the drivers: the output frame of the current state, and the peak resident
// memory of the process [bytes].
Frame make_frame(const System& s, double time, int64_t step);
double peak_memory_bytes();

}  // namespace horizon
