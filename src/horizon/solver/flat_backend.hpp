#pragma once
// The flat backend of explicit runs (solver.backend: flat, --backend flat; docs/design.md
// "Backends and portable kernels"): the run's state copied once into flat arrays
// (solver/flat_copy.hpp) and stepped there by the portable row functions of
// kernels/flat_system.hpp, many steps a call, on the host's threads. It is the CUDA
// backend without the device: the same copy, the same rows, the same write-back, the same
// refusals (the CUDA backend, driver/backends.cpp, derives from it and keeps the arrays
// on the GPU). The rows sum in the fast loops' lanes, so a run gives the CPU backend's
// bits: the state, the ledger, history.csv and the frames (tests/regression/test_backend.cpp);
// with damping, all but the last bits of the damped energy (summed per particle first).
#include <cstdint>
#include <string>
#include <vector>

#include "horizon/core/point4.hpp"
#include "horizon/core/vec3.hpp"

#include "horizon/solver/backend.hpp"
#include "horizon/solver/flat_copy.hpp"

namespace horizon {

// Why the flat (and CUDA) backend cannot take this run, or "" when it can (flat_unsupported).
std::string flat_backend_refusal(const System& s, const Loads& loads, double damping);

class FlatBackend : public ExplicitBackend {
 public:
  // After ExplicitSolver::initialize (or a restart's state): copies the System.
  FlatBackend(System& s, Loads& loads, ExplicitSolver& solver);
  const char* name() const override { return "flat"; }
  int64_t batch() const override { return int64_t{1} << 40; }
  // n steps over the copy; the solver's clock moves on by n. A state that turns
  // non-finite is stepped again from the System's copy one step at a time, so that the
  // System is left as ExplicitSolver::step leaves it (u and v of the start of the failing
  // step, the rest of its force pass) and NonFiniteState names that step and the first
  // particle, as step does.
  void advance(int64_t n, bool energy) override;
  void copy_fields() override;
  // The adaptive step: the nonlinear solid's over the copy (kernels::flat_tupek_stable_step,
  // the host's rows: the CPU backend's bits); other models copy the fields back first.
  bool stable_time_step(double& dt) override;

 protected:
  // Takes n steps over view_ (take_steps; the CUDA backend: on the device).
  void run_steps(int64_t n);
  virtual void take_steps(int64_t n);
  // After a force pass: the short-range contact of the pairs beyond the families (the
  // host's Verlet lists, state/short_range.hpp) added to view_'s f and energy, as
  // compute_forces adds them; contact_hook(this) for FlatRun::advance.
  void contact_pass();
  static void contact_hook(void* self) { static_cast<FlatBackend*>(self)->contact_pass(); }
  // Before step k of a run_steps call (storage_steps_ at its start): the loads' values
  // that vary, evaluated as ExplicitSolver::step evaluates them (Loads::prescribe_velocity
  // at t + dt/2, apply_constraints and apply_forces at t + dt, the critical stretches that
  // vary at t + dt, as step sets them before its force pass) into view_; step_hook for
  // FlatRun::advance. Whether there are any: varies().
  void prepare_step(int64_t k);
  bool varies() const {
    return storage_.vary_constraints || storage_.vary_forces || storage_.vary_critical_stretch;
  }
  static void step_hook(void* self, int64_t k) { static_cast<FlatBackend*>(self)->prepare_step(k); }
  // Brings storage_ up to date with the steps taken (the CUDA backend: copies back).
  virtual void fetch() {}
  // Whether a row has turned non-finite since the copy (the CUDA backend: the device's flag).
  virtual bool went_non_finite() { return storage_.nonfinite[0] != 0; }
  // storage_ was made again from the System (the CUDA backend: copies it to the device).
  virtual void upload() {}
  // view_.dt changed (the adaptive step; the CUDA backend: the device's copy of it).
  virtual void step_changed() {}

  System& s_;
  Loads& loads_;
  ExplicitSolver& solver_;
  FlatStorage storage_;
  kernels::FlatSystem view_;

 private:
  void copy_from_system();
  // The copy's state (not the ledger) into the System; the energy with `energy`.
  void write_state(bool energy);
  // The first particle whose u or v is not finite in storage_, or -1.
  int64_t first_non_finite() const;
  // The step of the steps to come: view_.dt (and the device's) set to dt.
  void set_step(double dt);
  bool energy_ = true;    // the last step computed what a CPU step with `energy` would
  // An ordinary model whose ledger holds its committed t_n, e_n in arrays (a restart): the
  // first step is the CPU's, then the copy (solver/flat_ordinary_copy.hpp flat_ordinary_ready).
  bool host_step_ = false;
  // The adaptive step (the solver's time a sum of steps, ExplicitSolver::fixed_step false):
  // the dt and start time of each step since the System's state (the last copy_fields),
  // so that a run of steps from it (prepare_step, the non-finite search) takes them again.
  bool adaptive_ = false;
  std::vector<double> step_dt_, step_t0_;
  std::vector<double> stable_S_;  // flat_tupek_stable_step's per-row sums
  std::vector<Point4> contact_y_;  // contact_pass's copies of y4 and f (Point4 is 32-byte aligned)
  std::vector<Vec3> contact_f_;
  std::vector<Vec3> b_at_copy_;  // force densities that vary: b at the last copy
  bool failed_ = false;
  bool fetched_ = true;  // storage_ holds the steps taken (fetch() since the last run_steps)
  int64_t system_steps_ = 0;   // the step count of the System's state (the last copy_fields)
  int64_t copied_at_ = 0;      // the step count when storage_ was copied from the System
  int64_t storage_steps_ = 0;  // the step count of storage_'s state   // a step turned the state non-finite: the System keeps what advance left
  uint64_t intact_at_copy_ = 0;  // intact bonds when storage_ was copied
  uint64_t broken_at_copy_ = 0;  // s.broken then
  double damped_at_copy_ = 0;    // the ledger's damped energy then
};

}  // namespace horizon
