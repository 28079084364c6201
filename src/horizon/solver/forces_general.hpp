#pragma once
// The general force pass: any mix of material models (material/model.hpp), none named.
//
//   1. Breaking: every intact bond whose stretch exceeds min(s0_i, s0_j) (the critical-
//      stretch law with compression, DamageConfig::alpha) breaks, both copies in the same
//      pass (the stretch is the same bits from either end); the energy it held, estimated
//      as (1/2) (T_ij . M) e V_i V_j from the force state of the last pass, goes to
//      dissipated_at. With break_after_force the bond still acts in this pass.
//   2. Force states: each model writes T_ij for the bonds of its particles
//      (Model::force_state); the unified models through their P/Q/R
//      coefficients, T_ij = omega (P_i |xi| + Q_i e + R_i e/|xi|) M.
//   3. Assembly: f_i = sum_j (T_ij - T_ji) V_j over the acting bonds (seed 003 eq. 33,
//      discrete form of digest sec. 9), V_j the partial-volume-scaled volume of i's
//      family, plus the short-range contact of family pairs and of the other pairs.
// Each particle's sums run over its own row in bond order: the same bits on any number
// of threads. The force state and the reverse-bond index cost 32 bytes per bond (16 in
// the scalar form below).
#include <cstdint>

#include "horizon/solver/build.hpp"

namespace horizon {

// Returns the directed bonds broken in this pass.
uint64_t general_forces(System& s, bool energy);

// The scalar form of the pass (solver/forces_ordinary.cpp): when every model writes its
// force states along the bonds (ModelTraits::ordinary or unified), one scalar per bond and
// two visits of each bond (breaking, the model's row; the sum), the same forces bit for
// bit. general_forces takes it by itself (scalar_general_pass); ordinary_forces expects
// what general_forces prepares (packed positions, reverse-bond index).
bool scalar_general_pass(const System& s);
uint64_t ordinary_forces(System& s, bool energy);
// The affine form (solver/forces_affine.cpp): when every model writes T_ij = omega (M_i xi
// + g_i Y) (ModelTraits::affine; the correspondence model), one record per particle and
// the pair form of the sum, with no force state per bond and no reverse-bond index.
bool affine_general_pass(const System& s);
uint64_t affine_forces(System& s, bool energy);
// Whether set_general_reference(true) holds.
bool general_reference();
// Tests: true makes general_forces take the vector form (Model::force_state) for every
// model, the reference the scalar form is checked against.
void set_general_reference(bool reference);

}  // namespace horizon
