#pragma once
// The force pass: bond breaking, damage, dilatation, then internal force densities.
#include "horizon/solver/system.hpp"

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

// Per-kind coefficients (ModelCoefficients::kind) and the damage totals from the
// bonds' reference data and the per-particle coefficients. setup_model calls it; call
// it again after changing either by hand.
void build_kind_coefficients(System& s, DamageMeasure measure);

// Recomputes the damage field's bookkeeping (per-particle totals and intact sums) from
// the bonds' intact flags. The force pass keeps it up to date as bonds break; call this
// after changing intact flags by hand.
void refresh_damage(System& s);

// The damage weight of i's intact bonds (intact == 1), summed afresh in the lanes of the
// bond loops. A row whose bonds broke in a pass takes it in place of its running sum, so
// that a particle whose every bond is broken has damage exactly 1 (the running sum's
// subtractions leave a rounding residue: 1.0000000000000007 on the glass demo).
double intact_damage_weight(const System& s, std::size_t i);

// phi_i = 1 - (intact weight) / (total weight), exactly 0 with every bond intact and
// exactly 1 with none (docs/models.md, damage).
inline double damage_of(double intact_weight, double total_weight) {
  return total_weight > 0 ? 1.0 - intact_weight / total_weight : 0.0;
}

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
// through commit_history (solver/system.hpp).

// Total strain energy sum_i W_i V_i [J] (after compute_forces(s, true)).
double strain_energy(const System& s);

}  // namespace horizon
