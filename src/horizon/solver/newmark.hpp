#pragma once
// Implicit dynamics: Newmark's method with beta = 1/4, gamma = 1/2 (average acceleration,
// unconditionally stable and energy-conserving for linear problems; Newmark 1959;
// Hughes, The Finite Element Method, 2000, sec. 9.1; Peridigm's "Implicit" solver,
// digest peridigm sec. 1.5):
//   u_{n+1} = u_n + dt v_n + dt^2/4 (a_n + a_{n+1}),   v_{n+1} = v_n + dt/2 (a_n + a_{n+1}),
// so a_{n+1} = (4/dt^2) (u_{n+1} - u_hat), u_hat = u_n + dt v_n + dt^2/4 a_n. Each step
// solves M (a_{n+1} + gamma_d v_{n+1}) = F(u_{n+1}) (gamma_d the deck's mass-proportional
// damping) by Newton with the tangent K + (4/dt^2)(1 + gamma_d dt/2) M (newton.hpp).
// The period elongation of the scheme is (omega dt)^2/12 to leading order (Hughes
// sec. 9.1.4), so a step ten times the explicit stable one keeps low modes accurate.
#include <vector>

#include "horizon/loading/loads.hpp"
#include "horizon/solver/explicit.hpp"
#include "horizon/solver/newton.hpp"

namespace horizon {

class NewmarkSolver {
 public:
  NewmarkSolver(System& s, Loads& loads, double dt, double damping, NewtonOptions options, int max_break_rounds);

  // Loads at t = 0, first forces and accelerations, the ledger's initial energies.
  void initialize();
  // Starts from a_0 = 0 instead of the equilibrium (f + b)/rho (solver.initial_acceleration:
  // zero, Peridigm's Implicit); call before initialize().
  void set_zero_initial_acceleration(bool zero) { zero_start_ = zero; }
  // One step with bond breaking (break, re-solve, until no bond breaks). Returns the
  // last Newton report; on failure the state is restored to the start of the step.
  SolveReport step();

  double time() const { return time_; }
  int64_t steps() const { return steps_; }
  double dt() const { return dt_; }
  const Ledger& ledger() const { return ledger_; }
  const DofMap& dofs() const { return dofs_; }
  int64_t newton_iterations() const { return newton_iterations_; }
  int64_t linear_iterations() const { return linear_iterations_; }

 private:
  System& s_;
  Loads& loads_;
  DofMap dofs_;
  double dt_, damping_;
  NewtonOptions options_;
  int max_break_rounds_;
  LinearSolver linear_;
  double time_ = 0;
  int64_t steps_ = 0;
  int64_t newton_iterations_ = 0, linear_iterations_ = 0;
  Eigen::VectorXd a_;  // acceleration of the free dofs
  bool zero_start_ = false;
  Ledger ledger_;
};

// Prescribed motion over [t0, t1]: velocity constraints advance u by h((t0+t1)/2)(t1-t0),
// then Loads::apply_constraints sets prescribed displacements and final velocities.
void advance_constraints(const Loads& loads, System& s, double t0, double t1);

}  // namespace horizon
