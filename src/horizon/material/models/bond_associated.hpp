#pragma once
// The bond-associated correspondence model: the correspondence model's classical stress
// laws evaluated per bond, on a bond-level deformation gradient, instead of once per
// particle. docs/models/bond_associated.md has the equations, the keys and the tests.
//
// The bond-level deformation gradient of bond ij is the average of the two end gradients
// corrected along the bond (Breitzman and Dayal 2018, "Bond-level deformation gradients
// and energy averaging in peridynamics", JMPS; the bond-level kinematics of Behzadinasab
// and Foster's bond-associated correspondence, "A semi-Lagrangian constitutive
// correspondence framework for peridynamics", JMPS 2020):
//   Fbar = (F_i + F_j)/2,   F_ij = Fbar + (Y - Fbar xi) (x) xi/|xi|^2,
// with F_i = (sum_k omega V_k Y (x) xi) K_i^-1 the particle's nonlocal gradient (Silling
// et al. 2007, eq. 134). F_ij maps xi to Y exactly and equals F for every homogeneous
// deformation; a zero-energy mode of F_i (a Y - F_i xi that F_i cannot see) stretches the
// bonds along themselves, which F_ij sees: no stabilisation is needed (the point of the
// bond-associated models: Chen 2018, "Bond-associated deformation gradients for
// peridynamic correspondence model", Mech. Res. Commun.; Chen and Spencer 2019,
// "Peridynamic bond-associated correspondence model: stability and convergence
// properties", IJNME). Chen's own F_ij is the nonlocal gradient over a bond-associated
// horizon (the family of i within reach of j); Peridigm's Elastic Bond Associated
// Correspondence runs the averaged form above, which its gold fixes to round-off
// (docs/models/bond_associated.md).
//
// The energy is the family average of the bond energies (Breitzman and Dayal's energy
// averaging):
//   E = sum_i V_i W_i,   W_i = sum_j c_ij V_j W(F_ij),   c_ij = omega_ij / m_i,
//   m_i = sum_j omega_ij V_j,
// and the force state is its Frechet derivative (derived in docs/models/bond_associated.md):
//   T_ij = c_ij P_ij xi/|xi|^2 + omega_ij S_i K_i^-1 xi,
//   S_i = sum_j V_j (c_ij + c_ji)/2 P_ij (I - n (x) n),   n = xi/|xi|,
//   f_i = sum_j (T_ij - T_ji) V_j.
// The first term is the bond's own stress along the bond, the second carries the rest of
// it through both end gradients. In the bulk sum_j T_ij (x) xi V_j = P for a homogeneous
// deformation, and a fully prescribed homogeneous deformation carries the classical stress
// of the law exactly (tests/unit/test_bond_associated.cpp).
//
// `kinematics: semi_lagrangian` (rate-form laws only) writes the same terms on the current
// configuration, as Behzadinasab and Foster's semi-Lagrangian correspondence: the
// velocity gradient L_i = (sum_k omega V_k Ydot (x) Y) K_c,i^-1 with
// K_c,i = sum_k omega V_k Y (x) Y, the bond's L_ij = Lbar + (Ydot - Lbar Y) (x) Y/|Y|^2,
// and the forces with Y for xi, K_c for K and J_n sigma_ij for P, J_n = det V of the
// bond's committed step (the volume factor of Peridigm's Elastic Hypoelastic
// Correspondence, fitted from its gold: J of the step's end is 2e-4 off).
//
// Bonds of both directions must exist (one horizon for the material's bodies), and a bond
// carries no force while either end's shape tensor is refused.
#include "horizon/material/model.hpp"

namespace horizon {

ModelEntry bond_associated_model();

}  // namespace horizon
