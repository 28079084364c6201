#pragma once
// The force pass: bond breaking, damage, dilatation, then internal force densities.
// (build_kind_coefficients, refresh_damage and strain_energy, which it used to declare,
// are the state's: state/system.hpp.)
#include "horizon/solver/build.hpp"

namespace horizon {

struct ForceStats {
  uint64_t broken = 0;  // directed bonds broken in this pass
};

// Computes particles.f (internal force density) from the current displacements.
// Bonds whose stretch exceeds the smaller critical stretch of their two ends break
// first (irreversibly, both directions in the same pass, since the stretch is computed
// bit-identically from either end), and the energy they held goes to dissipated_at.
// When `energy` is set, particles.energy receives the strain energy density W_i.
// Each particle's sums run over its own row in a fixed order: results do not depend
// on the number of threads.
ForceStats compute_forces(System& s, bool energy);

// Which implementation of the bond loops runs: the widest the CPU has (automatic:
// AVX-512, else AVX2, else scalar), at most AVX2, or the portable scalar one. All give
// the same bits; tests compare them. general: the general force pass of
// solver/forces_general.hpp even when every model is unified (tests compare it with the
// fast loops: the same forces to round-off, summed in another order).
enum class KernelPath { automatic, avx2, scalar, general };
void set_kernel_path(KernelPath path);
const char* kernel_path_name();  // "avx512", "avx2" or "scalar": what runs now

// The two passes of compute_forces for state-based models, exposed for the kernel
// benchmarks (bench/bench_kernels.cpp): pass 1 breaks bonds and sums the dilatation,
// pass 2 sums the force. compute_forces is what solvers call.
uint64_t state_based_dilatation_pass(System& s);
void state_based_force_pass(System& s, bool energy);

// Packs the current positions with each particle's critical stretch for this pass into
// model.packed (s0_i = critical_stretch_i - alpha_i min_stretch_i; +inf in no-fail
// regions), and sizes the force pass's scratch.
void pack_positions(System& s);

// The models' trial history becomes their history (material/model.hpp). Solvers call it
// through commit_history (state/system.hpp).

}  // namespace horizon
