#pragma once
// The CUDA backend of explicit runs (issue 30 part B; docs/design.md, "Backends and
// portable kernels"): the flat state of kernels/flat_system.hpp held on the device, each
// stage of a step launched as one kernel of one thread a particle over the same portable
// row functions the host's advance_flat runs. Plain C++ here (no CUDA type), so that host
// code compiled by the host compiler can call it; built only with -DHORIZON_CUDA=ON.
//
// Compiled with nvcc 13.0 (sm_90) on a machine without a GPU: it has never run. The
// driver chooses it with solver.backend: cuda (driver/backends.cpp, over FlatBackend).
#include <cstdint>
#include <string>

#include "horizon/kernels/flat_system.hpp"

namespace horizon::cuda {

// Whether a CUDA device can be used; when not, `why` says why (for the skip message).
bool device_available(std::string& why);

// Copies a flat state to the device; advance() steps it there; download() copies the
// fields back into the same host arrays.
// The device's copy bandwidth, bytes read plus bytes written per second, of a
// device-to-device copy of `bytes` (the ceiling of a bandwidth-bound bond loop).
double copy_bandwidth(uint64_t bytes);

class FlatRun {
 public:
  explicit FlatRun(const kernels::FlatSystem& host);
  ~FlatRun();
  FlatRun(const FlatRun&) = delete;
  FlatRun& operator=(const FlatRun&) = delete;

  // `steps` explicit steps on the device (no copy back). With `after_forces`, after each
  // force pass the packed positions (y4), f and the energy are copied to the host arrays
  // the constructor copied from, after_forces(ctx) runs there (the host's short-range
  // contact pairs add to f and the energy) and f and the energy go back to the device.
  // With `before_step`, before_step(ctx, k) runs on the host before step k and the loads'
  // values it sets (fixed_value, fixed_mid, fixed_v, b_next, where present, and the critical
  // stretches when they vary in time) go to the device.
  void advance(int64_t steps, void (*after_forces)(void*) = nullptr, void* ctx = nullptr,
               void (*before_step)(void*, int64_t) = nullptr);
  // Waits for the device and copies u, v, f, the intact flags, damage, energy, the
  // dissipation, theta, P, the intact weights, the smallest stretches, the ledger (and the
  // nonlinear solid's bond strains and nonlocal damage) back to `host`
  // (the arrays the constructor copied from, or others of the same sizes).
  void download(const kernels::FlatSystem& host) const;
  // The step of the steps to come (the adaptive step).
  void set_dt(double dt);
  // The nonlinear solid's stable time step of the device's state
  // (kernels::flat_tupek_stable_step's rows and minimum, on the device; +inf for the
  // unified models, which have no such rows).
  double stable_time_step();
  // Whether a row's u or v has turned non-finite since the constructor (kernels'
  // FlatSystem::nonfinite; one byte copied back).
  bool nonfinite() const;
  // Seconds the device spent in advance() since the last call (CUDA events).
  double device_seconds();

 private:
  struct Impl;
  Impl* impl_;
};

}  // namespace horizon::cuda
