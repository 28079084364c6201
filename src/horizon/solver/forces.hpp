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

// Total strain energy sum_i W_i V_i [J] (after compute_forces(s, true)).
double strain_energy(const System& s);

}  // namespace horizon
