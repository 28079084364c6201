#pragma once
// `horizon run` and `horizon check` as library calls: deck -> system -> solver -> writers.
#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <nlohmann/json.hpp>
#include <string>

#include "horizon/deck/config.hpp"
#include "horizon/loading/loads.hpp"
#include "horizon/output/frame.hpp"
#include "horizon/solver/build.hpp"

namespace horizon {

struct RunOptions {
  std::optional<std::string> output_dir;  // overrides output.directory
  double coarsen = 1;                     // spacing and horizon times this (smoke tests, quick looks)
  std::optional<double> end_time;         // overrides solver.end_time
  bool quiet = false;                     // no progress line
  int threads = 0;                        // 0: OpenMP's default
  bool handle_signals = true;             // Ctrl-C ends the run cleanly (off for the Python module)
  double max_memory_gib = 0;              // the memory guard's limit; 0: the machine's memory
  // A checkpoint (output/checkpoint.hpp) to continue from: explicit runs only; the deck
  // must build the same particles, bonds and materials.
  std::optional<std::string> restart;
  // --backend: overrides solver.backend (cpu, flat or cuda; solver/backend.hpp).
  std::optional<std::string> backend;
};

struct CheckReport {
  std::size_t particles = 0;
  std::size_t bonds = 0;             // directed
  std::size_t precrack_bonds = 0;    // directed bonds removed by precracks
  std::size_t isolated = 0;          // particles without a bond (loads and contact move them alone)
  std::size_t memory_bytes = 0;
  double stable_dt = 0;
  double dt = 0;                     // the step the run will use
  double heat_stable_dt = 0;         // the explicit heat stable step (thermal runs; 0 otherwise)
  int64_t steps = 0;
  // Finite-element bodies (fe/fe_region.hpp): elements, nodes, nodes shared with particles.
  std::size_t fe_elements = 0, fe_nodes = 0, fe_shared_nodes = 0;
  int fe_nodes_per_element = 0;
};

// Applies the command-line overrides to a deck.
void apply_run_options(Config& config, const RunOptions& options);

// The time step a run uses: solver.time_step, or the stable step times the safety factor.
double run_time_step(const Config& config, const System& s);

CheckReport check_system(const Config& config, const System& s);

// The steps of a run of step dt to solver.end_time. More than kMaxSteps (a trillion,
// months of computing for the smallest deck) is an error: a unit mistake in end_time or
// time_step, not a run.
inline constexpr double kMaxSteps = 1e12;
int64_t step_count(const Config& config, double dt);

// Everything a run does before its first step, as `horizon check` does it: the system
// (after the memory guard, solver/memory_guard.hpp), the loads and initial conditions,
// the time step. Throws horizon::Error for a deck that cannot run.
struct PreparedRun {
  System system;
  Loads loads;
  CheckReport check;
};
PreparedRun prepare_run(const Config& config);
std::string format_check(const Config& config, const CheckReport& r);

// Runs the deck and writes frames, history.csv and summary.json into the output
// directory. Returns the process exit code: 0 done, 2 non-finite state, 4 a static or
// implicit solve did not converge, 130 interrupted.
int run_deck(Config config, const RunOptions& options);

class Loads;
struct Ledger;

// An explicit run taken step by step (what run_deck does, in pieces, for callers that
// look at the state between steps: the Python module). The constructor builds the
// system, applies the initial conditions and writes the first frame; advance() takes up
// to n steps, writing history rows and frames as they fall due; finish() writes the
// final frame of a run that did not reach its end, history.csv and summary.json, and
// returns the exit code run_deck would. run_deck is exactly this with one advance().
class ExplicitRun {
 public:
  ExplicitRun(Config config, const RunOptions& options);
  ~ExplicitRun();
  ExplicitRun(const ExplicitRun&) = delete;
  ExplicitRun& operator=(const ExplicitRun&) = delete;

  // Takes up to n steps; fewer when the run ends (end time, non-finite state, Ctrl-C).
  // Returns the steps taken.
  int64_t advance(int64_t n);
  // Ends the run here (status "stopped"); finish() then writes a final frame.
  void stop(const std::string& reason);
  int finish();

  bool done() const;      // no more steps will be taken
  bool finished() const;  // finish() has run
  const System& system() const;
  System& system();
  const Config& config() const;
  const Ledger& ledger() const;
  const Loads& loads() const;
  double time() const;
  double dt() const;
  int64_t steps() const;
  int64_t total_steps() const;
  const std::string& status() const;
  int exit_code() const;
  std::string history_csv() const;              // the rows so far, header first
  const nlohmann::ordered_json& summary() const;  // after finish()
  std::string output_directory() const;

 private:
  struct State;
  std::unique_ptr<State> st_;
};

// The same for solver.type static and implicit_dynamic (driver/run_implicit.cpp).
int run_implicit_deck(Config config, const RunOptions& options);

// The same for solver.type heat (driver/run_heat.cpp).
int run_heat_deck(Config config, const RunOptions& options);

// The thermal columns of history.csv (after the mechanical ones in coupled runs), and the
// thermal part of summary.json (driver/run_heat.cpp).
std::string heat_history_header(const System& s);
std::string heat_history_row(const System& s);
// `moved`: the heat the boundaries moved in absolute value (HeatSolver::moved), a scale of
// the balance besides the net figures (0: none).
nlohmann::ordered_json heat_summary(const System& s, double heat_step, double stable_step, double initial_content,
                                    double moved = 0);

// Why an explicit deck cannot be split over MPI ranks yet (parallel/decomposition.hpp),
// or "" when it can.
std::string distributed_limits(const Config& config, const System& s, const RunOptions& options);
// CRC-32 of every particle's displacement, velocity and damage, in index order
// (summary.json state_crc32: equal digests, equal final states, bit for bit).
uint32_t state_digest(const System& s);

// Shared by the drivers: the output frame of the current state, and the peak resident
// memory of the process [bytes].
Frame make_frame(const System& s, double time, int64_t step);
double peak_memory_bytes();
// Writes frame `f` named `base` under dir/frames and adds it to `pvd` at `time`: one .vtu
// serially (dd null); on ranks each rank its owned particles' piece and rank 0, once every
// piece is complete, the .pvtu index. Collective when decomposed.
void write_frame_files(const std::string& dir, const std::string& base, const Frame& f, double time,
                       class PvdIndex& pvd, const struct Decomposition* dd);

}  // namespace horizon
