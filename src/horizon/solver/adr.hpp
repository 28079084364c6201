#pragma once
// Adaptive dynamic relaxation (Kilic and Madenci 2010, "An adaptive dynamic relaxation
// method for quasi-static simulations using the peridynamic theory", Theor. Appl.
// Fract. Mech. 53, 194-204). The static problem F(u) = 0 (F = f + b, force density) is
// the steady state of the damped fictitious dynamics  Lambda u'' + c Lambda u' = F(u),
// integrated with a unit time step (their eq. 16-18):
//   u'^{n+1/2} = ((2 - c_n) u'^{n-1/2} + 2 Lambda^{-1} F^n) / (2 + c_n),   u^{n+1} = u^n + u'^{n+1/2},
//   u'^{1/2} = Lambda^{-1} F^0 / 2.
// Fictitious diagonal mass (eq. 21, the Gerschgorin bound with dt = 1):
//   lambda_ii >= (1/4) sum_j |K_ij|,
// taken from stiffness_row_bound (tangent.hpp) at the start of each solve. Damping from
// the Rayleigh quotient of the local diagonal stiffness (eq. 19-20):
//   c_n = 2 sqrt( u^T 1K u / u^T u ),  1K_ii = -(F_i^n - F_i^{n-1}) / (lambda_ii u'_i^{n-1/2}),
// set to 0 when the quotient is negative. Structures (a model with
// ModelTraits::structural: beams, plates, shells): that local quotient is dominated by the
// highest modes of the fourth-order bending operator and saturates, so the damping is
// fixed per solve (per load increment) at critical damping of the lowest mode,
// c = 2 omega_0, omega_0^2 the lowest eigenvalue of K x = omega^2 Lambda V x from a
// shift-invert Lanczos estimate on the model's analytic tangent (Underwood 1983, "Dynamic
// relaxation", Computational Methods for Transient Analysis, ch. 5: c = 2 omega_0 is the
// optimal damping), and Lambda is scaled up by 4/(2 + sqrt(4 - c^2)) so that the
// alternating mode the Gerschgorin bound admits at omega^2 = 4 is damped (adr.cpp). The
// local estimate is kept when the scaled tangent is not positive definite. Converged when |R| <= tolerance |R_ref|
// (equilibrium.hpp), R = F V on the free dofs.
#include "horizon/solver/newton.hpp"

namespace horizon {

struct AdrOptions {
  double tolerance = 1e-6;
  int max_iterations = 100000;
};

SolveReport adr_solve(System& s, const DofMap& d, const AdrOptions& o);

}  // namespace horizon
