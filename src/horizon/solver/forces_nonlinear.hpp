#pragma once
// The bond loops of Tupek's nonlinear ordinary solid with brittle bond failure
// (material/nonlinear_solid.hpp; docs/models.md sec. "Nonlinear solid").
//
// One force pass is two sweeps over the rows, each particle summing its own row in bond
// order (bit-identical on any number of threads):
//   1. bond strains eps_ij (stored per bond) and theta_i = sum_j phi omega eps V_j (eq. 6.8);
//   2. for each intact bond in tension, the symmetric pair criterion
//      s_ij + s_ji >= 2 beta/|xi|^2, s_ij = lambda_bar_i eps theta_i + mu_bar_i eps^2
//      (eqs. 6.5, 6.10/6.11 and the symmetrised form of sec. 6.1.3), computed from both
//      ends' theta of sweep 1, so both copies of a bond decide identically; then the force
//      f_i = sum_j (t_ij + t_ji) Y/|Y| V_j, t_ij = (lambda_bar_i theta_i + 2 mu_bar_i eps)
//      phi omega d eps/d|Y| (eq. 6.8).
// A bond that breaks in sweep 2 still carries its force in that pass (the force is then
// the exact gradient of the energy with the flags at the start of the pass) and is off
// from the next pass on; its instantaneous energy omega V_j s_ij (per unit V_i, eq. 6.5)
// goes to dissipated_at, and the strain energy reported for the pass is the one with
// the bond cut, so that elastic + kinetic + dissipated balances.
#include "horizon/solver/forces.hpp"
#include "horizon/solver/system.hpp"

namespace horizon {

// Model coefficients of a system whose materials are all nonlinear_solid: removes the
// bonds between different bodies (they interact by contact only), sets the normalised
// influence weights (in 2-D omega/thickness, so that omega V_j integrates over area),
// the Lame constants, beta and the contact data. Throws when nonlinear_solid is mixed
// with other models. setup_model calls it.
void setup_nonlinear(System& s, const std::vector<MaterialConfig>& materials, const Config& config);

// compute_forces for a nonlinear system (it dispatches here).
ForceStats compute_nonlinear_forces(System& s, bool energy);

// The stable time step from the current bond tangent stiffness (digest sec. 13.1):
// min_i sqrt(2 rho_i / sum_j K_ij), K_ij = d(t_ij + t_ji)/d|Y| V_j with the dilatation
// coupling bounded Gershgorin-wise, plus the contact springs. Uses the strains of the
// last force pass (at rest before the first). stable_time_step dispatches here.
double nonlinear_stable_time_step(const System& s);

}  // namespace horizon
