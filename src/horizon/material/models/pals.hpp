#pragma once
// The position-aware linear solid (PALS) of J. A. Mitchell, S. A. Silling and D. J.
// Littlewood, "A position-aware linear solid constitutive model for peridynamics",
// J. Mech. Mater. Struct. 10(5):539-557, 2015 (Peridigm's "Pals"); influence functions
// after Seleson and Parks 2011. docs/models/pals.md has the equations and what was fitted.
//
// The LPS with two influence functions per particle, sigma (dilatation) and tau
// (deviatoric), each the given omega corrected by six Lagrange multipliers so that the
// particle's truncated family, near a surface as in the bulk, reproduces a homogeneous
// small strain exactly: with V_j the neighbour's volume and e = |Y| - |xi|,
//   theta_i = sum_j sigma_ij |xi| e V_j,        e^d = e - theta_i |xi| / 3,
//   W_i     = kappa theta_i^2 / 2 + mu sum_j tau_ij (e^d)^2 V_j,
//   t_ij    = dW_i/de_ij = kappa theta sigma |xi| + 2 mu tau e^d - (2 mu/3) S_i sigma |xi|,
//   S_i     = sum_j tau_ij e^d |xi| V_j     (0 for the LPS, not for PALS),
// and
//   sigma_ij = omega_s (1 + Lambda_i : xi (x) xi),  Lambda_i symmetric, from
//     sum_j sigma_ij xi (x) xi V_j = I               (theta = tr E for every small E);
//   tau_ij   = omega_d (1 + sum_k mu_ik g_k(xi)),   g_k = (xi . D_k . xi)^2 / |xi|^2, from
//     sum_j tau_ij g_k(xi_j) V_j = D_k : D_k        (W = mu D:D for each of six modes D_k:
//     the deviatoric uniaxial strains e_a (x) e_a - I/3 and the shears e_a (x) e_b + e_b (x) e_a).
// Each set is the minimiser of sum (sigma - omega)^2 / omega V under its constraints. The
// forms, the constraint modes and the multipliers' order (xx, yy, zz, xy, xz, yz) were
// identified against Peridigm's Pals_Simple_Shear gold (its Lagrange_Multiplier_* fields
// to 3e-11, forces to 4e-8, W to 1e-9; docs/models/pals.md), the paper being out of reach.
#include "horizon/material/model.hpp"

namespace horizon {

ModelEntry pals_model();

namespace pals {

// The six multipliers of one particle's family (xi_j, the bond's omega V_j): Lambda of
// sigma (xx, yy, zz, xy, xz, yz) or mu of tau (in the modes' order above). False where
// the family cannot carry the constraints (its 6 x 6 system is singular).
bool dilatation_multipliers(const std::vector<Vec3>& xi, const std::vector<double>& wv, double out[6]);
bool deviatoric_multipliers(const std::vector<Vec3>& xi, const std::vector<double>& wv, double out[6]);
// sigma/omega_s and tau/omega_d of a bond xi.
double dilatation_factor(const double lambda[6], const Vec3& xi);
double deviatoric_factor(const double mu[6], const Vec3& xi);

}  // namespace pals

}  // namespace horizon
