#pragma once
// Newton-Raphson on the free dofs with a backtracking line search:
//   K(u_k) du = R(u_k),  u_{k+1} = u_k + alpha du,
// K the tangent (tangent.hpp: analytic, assembled or matrix-free, or finite differences),
// R = (f + b) V the residual (equilibrium.hpp). alpha = 1, halved while the Armijo
// condition |R(u + alpha du)| <= (1 - 1e-4 alpha) |R(u)| fails (Dennis and Schnabel 1983,
// sec. 6.3, with the residual norm as merit function), at most 8 times.
// CG solves are inexact (Dembo, Eisenstat and Steihaug 1982): the relative residual of
// the linear solve is eta_k = 0.1 tolerance / (|R_k|/|R_ref|), in [1e-12, 0.1], i.e. the
// linear solve leaves 0.1 tolerance |R_ref|, so |R_{k+1}| ~ 0.1 tolerance |R_ref| + C |R_k|^2:
// one iteration on a linear problem, quadratic convergence down to the tolerance on a
// nonlinear one.
// Converged when |R| <= tolerance |R_ref| (equilibrium.hpp), or when no step lowers |R|
// any more and |R| is below the round-off bound of the forces (round_off_residual,
// tangent.hpp): a tiny load, or a tolerance tighter than the forces' digits.
// Bonds do not break during the iterations (FixedBonds); the caller breaks them between solves.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "horizon/deck/config.hpp"
#include "horizon/solver/equilibrium.hpp"
#include "horizon/solver/linear.hpp"

namespace horizon {

struct SolveReport {
  bool converged = false;
  int iterations = 0;                 // nonlinear iterations (Newton) or ADR iterations
  int64_t linear_iterations = 0;      // CG iterations summed over the Newton iterations
  double residual = 0;                // |R| / |R_ref| at the end
  std::vector<double> residuals;      // |R| / |R_ref| before each iteration and at the end
  std::string failure;                // why it did not converge
  double tangent_seconds = 0, solve_seconds = 0;
  std::size_t tangent_bytes = 0;      // memory of the assembled tangent (or the operator)
  std::size_t tangent_nonzeros = 0;
  double factor_fill = 0;             // cholesky: entries of L
};

// The inertia of a Newmark step, as a term of the residual on the free dofs:
//   R = (f + b) V - m o (kappa (u - u_hat) + g),   tangent K + kappa diag(m).
struct InertiaTerm {
  Eigen::VectorXd mass;   // nodal mass rho V per dof
  double kappa = 0;
  Eigen::VectorXd u_hat;  // displacement the inertia is measured from
  Eigen::VectorXd g;      // constant part (per unit mass)
};

struct NewtonOptions {
  LinearSolverKind linear_solver = LinearSolverKind::cg;
  TangentKind tangent = TangentKind::analytic;
  double tolerance = 1e-6;
  int max_iterations = 30;
  bool line_search = true;
  int max_linear_iterations = 20000;
  const InertiaTerm* inertia = nullptr;
};

// Solves for equilibrium at the current loads (b set, prescribed components of u set).
// linear: kept between calls so that CHOLMOD's symbolic analysis is reused.
SolveReport newton_solve(System& s, const DofMap& d, const NewtonOptions& o, LinearSolver& linear);

}  // namespace horizon
