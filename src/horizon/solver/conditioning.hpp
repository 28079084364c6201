#pragma once
// Condition number of the tangent, kappa = lambda_max / lambda_min (2-norm, K symmetric
// positive definite), from its extreme eigenvalues by implicitly restarted Lanczos
// (Spectra's SymEigsSolver): lambda_max directly, lambda_min as the largest eigenvalue
// of K^-1 (shift-invert at 0, K^-1 applied by a CHOLMOD Cholesky factorisation).
// For the PD operators kappa ~ delta^-2 with weak dependence on the spacing (Parks,
// digest 004 sec. 10.2-10.5): CG iterations grow like sqrt(kappa).
#include <string>

#include "horizon/solver/tangent.hpp"

namespace horizon {

struct ConditionEstimate {
  double lambda_min = 0;
  double lambda_max = 0;
  double condition = 0;  // lambda_max / lambda_min; +inf when K is singular
  bool converged = false;
  int products = 0;      // products K x of the Lanczos iterations for lambda_max
  int solves = 0;        // solves K^-1 x for lambda_min
  std::string message;   // why the estimate failed, when it did
};

// K symmetric (the lower triangle is used for the factorisation). tol: relative accuracy
// of the Ritz values.
ConditionEstimate estimate_condition(const SparseMatrix& K, double tol = 1e-6);

// The lowest eigenvalue of the generalised problem K x = lambda M x, M = diag(mass) > 0,
// i.e. of the symmetric M^-1/2 K_s M^-1/2 with K_s = (K + K^T)/2, by Lanczos with
// shift-invert at 0 (a CHOLMOD factorisation of the scaled matrix). ADR's damping on
// structures uses it (adr.hpp). Returns a negative value when the scaled matrix is not
// positive definite or Lanczos does not converge.
double lowest_generalized_eigenvalue(const SparseMatrix& K, const Eigen::VectorXd& mass, double tol = 1e-4);

}  // namespace horizon
