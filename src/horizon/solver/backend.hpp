#pragma once
// The backend seam of the explicit driver (issue 30; docs/design.md, "Backends and
// portable kernels"): the driver asks a backend to take steps and, before a history row,
// a frame, a checkpoint or the summary, to bring the System's fields up to date. The CPU
// backend is the explicit solver itself: its state is the System, so its copy is empty,
// and it takes one step at a time so that the driver's per-step work (progress, Ctrl-C,
// the heat coupling, the adaptive step) stays where it was. A backend that keeps the
// particles and bonds elsewhere (the CUDA backend of cuda/, over kernels/flat_system.hpp)
// takes many steps per call and copies the fields back only when asked.
#include <cstdint>
#include <memory>

#include "horizon/solver/explicit.hpp"

namespace horizon {

class ExplicitBackend {
 public:
  virtual ~ExplicitBackend() = default;
  virtual const char* name() const = 0;
  // The most steps one advance() may take; the driver never asks past its next event.
  virtual int64_t batch() const = 0;
  // Takes n >= 1 steps; with `energy` the ledger's energies are brought up to date at the
  // last one. Throws NonFiniteState as ExplicitSolver::step does.
  virtual void advance(int64_t n, bool energy) = 0;
  // Copies the fields a frame or a history row reads (u, v, f, damage, energy, the intact
  // flags, the ledger) into the System and the solver.
  virtual void copy_fields() = 0;
  // The adaptive step (solver.adaptive_time_step): the stable time step of the current
  // state into dt, computed over the backend's own copy (true), or false when the System
  // holds what the models' stable_time_step reads (the CPU backend; a backend without
  // rows for it copies the fields first) and the driver computes it there.
  virtual bool stable_time_step(double& dt) {
    (void)dt;
    return false;
  }
};

// Today's code path: ExplicitSolver::step, one step a call.
class CpuBackend final : public ExplicitBackend {
 public:
  explicit CpuBackend(ExplicitSolver& solver) : solver_(solver) {}
  const char* name() const override { return "cpu"; }
  int64_t batch() const override { return 1; }
  void advance(int64_t n, bool energy) override {
    for (int64_t k = 0; k < n; ++k) solver_.step(energy && k + 1 == n);
  }
  void copy_fields() override {}

 private:
  ExplicitSolver& solver_;
};

}  // namespace horizon
