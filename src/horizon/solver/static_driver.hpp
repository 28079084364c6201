#pragma once
// Quasi-static loading: equilibrium at a sequence of load levels, with automatic step
// cutting and quasi-static bond breaking.
//
// Load path. The pseudo-time runs from 0 to solver.end_time (default 1) in load_steps
// equal increments; step k evaluates the loads at t_k = end_time k / load_steps. A load
// component written without t (a number, or an expression in x, y, z only) is ramped:
// multiplied by the load factor lambda_k = k / load_steps. One written in t is taken as
// written, so a deck can shape a non-proportional path. Velocity constraints advance the
// displacement by v dt of pseudo-time. With solver.load_times (0 = t_0 < ... < t_N, steps
// of any length: Peridigm's QuasiStatic `Time Steps`) step k is at t_k and its load factor
// is lambda_k = t_k / t_N, so lambda stays the pseudo-time over the end time throughout.
//
// Each increment is solved by Newton (newton.hpp) or ADR (adr.hpp) with the bond set
// fixed; then the bonds that the equilibrium overstretches break (compute_forces), and
// the body is re-equilibrated at the same load, until no bond breaks (Peridigm digest
// sec. 1.12 item 6: its quasi-static solver lacks this). An increment that does not
// converge is restored and halved, up to max_step_cuts times; after a converged half the
// increment doubles back towards the nominal one. Reactions per constraint are minus the
// residual on its components (Loads::update_reactions).
//
// Ledger: the external work is that of the loading path (trapezoidal over the increment,
// up to the first equilibrium) plus the work of the force densities while the body
// re-equilibrates after bonds break; the strain energy such a re-equilibration releases
// beyond the broken bonds' own energy is lost to the quasi-static idealisation (kinetic
// energy, then heat, in the experiment) and is booked as damped energy.
#include <string>
#include <vector>

#include "horizon/deck/config.hpp"
#include "horizon/loading/loads.hpp"
#include "horizon/solver/adr.hpp"
#include "horizon/solver/explicit.hpp"
#include "horizon/solver/newton.hpp"

namespace horizon {

// True when the expression's text names the variable t.
bool uses_time(const Expression& e);

// Loads of a static solve at pseudo-time t with load factor lambda (see above);
// t_previous is the pseudo-time of the last converged state (velocity constraints).
void apply_static_loads(const Loads& loads, System& s, double t_previous, double t, double lambda);

class StaticSolver {
 public:
  StaticSolver(System& s, Loads& loads, const SolverConfig& config);

  // The state at load factor 0: forces, energies, reactions.
  void initialize();
  // Advances to the next converged increment (a nominal load step, or part of one after
  // cuts). False when an increment failed after max_step_cuts halvings; the state is
  // then the last converged one and failure() says why.
  bool advance();
  bool done() const { return lambda_ >= 1.0 - 1e-12; }

  double lambda() const { return lambda_; }
  double time() const { return time_at(lambda_); }
  // The pseudo-time of load factor lambda: k (end_time / load_steps) at a nominal load step
  // k, as Peridigm reports its load steps (ThermalExpansionCube's gold: 2880 = 8 x 360,
  // where 0.8 x 3600 is 2879.9999999999995), or the listed t_k (load_times); lambda
  // end_time between them (cut steps).
  double time_at(double lambda) const;
  // The load step k whose nominal load factor lambda is (1..load_steps), or -1 between
  // load steps (the parts of a cut increment).
  int64_t load_step() const;
  // The load step that ends at pseudo-time t (within 1e-12 end_time), or -1.
  int64_t load_step_at_time(double t) const;
  double increment() const { return last_increment_; }
  int64_t steps() const { return steps_; }                   // converged increments
  const SolveReport& last_report() const { return last_; }   // the last solve of the last increment
  int last_break_rounds() const { return last_break_rounds_; }
  int last_iterations() const { return last_iterations_; }   // over the increment's solves
  int64_t last_linear_iterations() const { return last_linear_iterations_; }
  int64_t total_iterations() const { return total_iterations_; }
  int64_t total_linear_iterations() const { return total_linear_iterations_; }
  int total_cuts() const { return total_cuts_; }
  const std::string& failure() const { return failure_; }
  const Ledger& ledger() const { return ledger_; }
  const DofMap& dofs() const { return dofs_; }
  double tangent_seconds() const { return tangent_seconds_; }
  double solve_seconds() const { return solve_seconds_; }
  std::size_t tangent_bytes() const { return tangent_bytes_; }
  std::size_t tangent_nonzeros() const { return tangent_nonzeros_; }
  double factor_fill() const { return factor_fill_; }

 private:
  bool solve_increment(double lambda, const std::vector<Vec3>& u_before, const std::vector<Vec3>& b_before);
  // The nominal load step at or just below lambda (within 1e-9 of a step of the next one).
  int64_t step_below(double lambda) const;
  // The nominal load step lambda is at (within 1e-9 of a step), or -1.
  int64_t step_at(double lambda) const;

  System& s_;
  Loads& loads_;
  SolverConfig config_;
  DofMap dofs_;
  LinearSolver linear_;
  double end_time_;
  double lambda_ = 0, step_ = 0, last_increment_ = 0;
  bool last_cut_ = false;  // the last increment was cut, or ended short of its load step
  // The nominal load steps: load factor levels_[k] at pseudo-time times_[k], k = 0..N.
  std::vector<double> levels_, times_;
  int64_t steps_ = 0;
  SolveReport last_;
  int last_break_rounds_ = 0, last_iterations_ = 0;
  int64_t last_linear_iterations_ = 0;
  int64_t total_iterations_ = 0, total_linear_iterations_ = 0;
  int total_cuts_ = 0;
  double tangent_seconds_ = 0, solve_seconds_ = 0, factor_fill_ = 0;
  std::size_t tangent_bytes_ = 0, tangent_nonzeros_ = 0;
  std::string failure_;
  Ledger ledger_;
  double pending_work_ = 0, pending_released_ = 0;  // of the increment being solved
};

}  // namespace horizon
