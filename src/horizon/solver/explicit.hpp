#pragma once
// Explicit dynamics: velocity Verlet (Silling and Askari 2005; Peridigm's "Verlet"):
//   v(n+1/2) = v(n) + dt/2 a(n);  u(n+1) = u(n) + dt v(n+1/2);  forces;  v(n+1) = v(n+1/2) + dt/2 a(n+1)
// with optional mass-proportional damping for runs to rest, and an energy ledger.
#include <cstdint>
#include <vector>

#include "horizon/core/error.hpp"
#include "horizon/loading/loads.hpp"
#include "horizon/solver/build.hpp"

namespace horizon {

struct Ledger {
  double kinetic = 0;        // sum 1/2 rho V |v|^2
  double strain = 0;         // sum W V
  double external_work = 0;  // work of body forces, tractions and constraints
  double dissipated = 0;     // energy of broken bonds
  double damped = 0;         // energy removed by damping
  double initial = 0;        // kinetic + strain at t = 0
  // Energy the temperature put into the stored energy by changing the thermal strain at
  // fixed positions (coupled thermal runs; thermal/heat.hpp thermal_strain_work).
  double thermal_work = 0;
  // The work the force-based coupling of finite-element regions put in (fe/fe_region.hpp
  // coupling_work): it derives from no potential, so the ledger closes only with it.
  double coupling_work = 0;
  // Not a term: a further energy scale of the balance, the strain energy a prescribed
  // temperature's strain would store in the body held at u = 0 (static runs with
  // thermal.conduction: false). A free expansion stores none and its thermal work is the
  // round-off of the equilibrium's force states: judged against this, not against itself.
  double thermal_scale = 0;

  // (K + U + D + damped - initial - W_ext - W_thermal - W_coupling) relative to the
  // largest energy in play. Every term the run books is in it.
  double balance_error() const;
};

// A state turned non-finite: names the particle, its position and the step.
class NonFiniteState : public Error {
 public:
  NonFiniteState(std::size_t particle, const Vec3& position, int64_t step);
  std::size_t particle;
};

class ExplicitSolver {
 public:
  ExplicitSolver(System& s, Loads& loads, double dt, double damping);

  // Applies the loads at t = 0 and computes the first forces and energies.
  // initialize(t0, dt_before): starts at t0 instead (the explicit stage of a staged run,
  // driver/static_stage.cpp): the steps run from t0, t = t0 + n dt; prescribed velocities
  // are the displacements' rate over the dt_before that led to t0 (0: none); the ledger
  // starts there (its initial energy the state's kinetic plus strain energy).
  void initialize(double t0 = 0, double dt_before = 0);
  // One step. With `energy`, the ledger's strain energy is brought up to date.
  // On a non-finite state, u and v are restored to the start of the step and
  // NonFiniteState is thrown.
  void step(bool energy);

  double time() const { return time_; }
  int64_t steps() const { return steps_; }
  double dt() const { return dt_; }
  // Changes the step from the next step on (the adaptive step of the nonlinear solid).
  // The adaptive step: from now on the time is the sum of the steps (else n dt).
  void set_dt(double dt) {
    dt_ = dt;
    fixed_dt_ = false;
  }
  // No set_dt so far: t = t0 + steps dt (else the time is the sum of the steps).
  bool fixed_step() const { return fixed_dt_; }
  double damping() const { return damping_; }
  // solver.verlet: peridigm (docs/input.md): the step rounds as Peridigm's velocity Verlet
  // does (its users' guide and Peridigm_VerletSolver; fitted bit for bit to the golds of
  // its two-point decks, docs/peridigm.md "Round-off"): a = (f + b)/rho in both half kicks;
  // a prescribed displacement component moves at the rate (g(t_n+1) - g(t_n)) (1/(t_n+1 - t_n))
  // through the drift, so its u accumulates instead of being set to g(t), and its velocity
  // takes the second half kick; the force pass reads y = (X + u_n) + dt v_n+1/2
  // (System::positions) rather than X + u_n+1, whose roundings differ.
  void set_peridigm_verlet(bool on) { peridigm_ = on; }
  bool peridigm_verlet() const { return peridigm_; }
  // A backend that took n fixed steps over its own copy of the state (solver/backend.hpp):
  // the step count and the time move on as step() moves them (t = steps dt).
  void advance_clock(int64_t n);
  const Ledger& ledger() const { return ledger_; }
  Ledger& ledger() { return ledger_; }
  // Checkpoint and restart: time, step count, step and ledger.
  void checkpoint(StateArchive& a) {
    a.io("solver_time", time_);
    a.io("solver_steps", steps_);
    a.io("solver_dt", dt_);
    a.io("ledger", ledger_);
  }
  // Brings the kinetic energy up to date (strain energy is updated by step(true)).
  void update_kinetic();

 private:
  System& s_;
  Loads& loads_;
  double dt_, damping_;
  double time_ = 0, start_time_ = 0;
  int64_t steps_ = 0;
  bool fixed_dt_ = true;  // no set_dt: t = steps * dt
  Ledger ledger_;
  std::vector<Vec3> u_before_, v_before_, b_before_;
  std::vector<double> damped_terms_;  // per owned particle, a decomposed run with damping (step)
  bool has_forces_ = false;
  bool peridigm_ = false;  // set_peridigm_verlet
};

double kinetic_energy(const System& s);

}  // namespace horizon
