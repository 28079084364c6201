#pragma once
// Linear solves K x = r of the Newton and Newmark iterations (K symmetric positive
// definite on the free dofs once rigid motions are constrained):
//   cg          Eigen's conjugate gradient on the assembled tangent, Jacobi preconditioner;
//   cholesky    SuiteSparse CHOLMOD's Cholesky through Eigen, supernodal or simplicial as
//               CHOLMOD judges (the symbolic analysis is kept while the sparsity pattern
//               stays the same);
//   matrix_free preconditioned CG on the TangentOperator product (no assembled matrix).
// CG iterations grow like sqrt(cond K), and cond K ~ delta^-2 (Parks, digest 004
// sec. 10.2, 10.6): direct solves pay on small and medium problems.
#include <Eigen/Core>
#include <memory>

#include "horizon/deck/config.hpp"
#include "horizon/solver/tangent.hpp"

namespace horizon {

struct LinearStats {
  int iterations = 0;          // CG iterations (1 for a direct solve)
  double residual = 0;         // |r - K x| / |r| reached (CG); 0 for direct
  double factor_fill = 0;      // cholesky: entries of the factor L
  bool ok = false;
};

class LinearSolver {
 public:
  explicit LinearSolver(LinearSolverKind kind);
  ~LinearSolver();
  LinearSolver(const LinearSolver&) = delete;
  LinearSolver& operator=(const LinearSolver&) = delete;

  LinearSolverKind kind() const { return kind_; }
  // Solves (K + diag(shift)) x = r; shift may be empty (Newmark adds kappa M).
  // tol: relative residual for CG. x receives the solution (started from zero).
  LinearStats solve(SparseMatrix& K, const Eigen::VectorXd& shift, const Eigen::VectorXd& r, Eigen::VectorXd& x,
                    double tol, int max_iterations);
  LinearStats solve(const TangentOperator& K, const Eigen::VectorXd& shift, const Eigen::VectorXd& r,
                    Eigen::VectorXd& x, double tol, int max_iterations);

 private:
  struct Direct;
  LinearSolverKind kind_;
  std::unique_ptr<Direct> direct_;
};

// Adds shift to the diagonal of K (entries present: every free dof's row holds its diagonal).
void add_to_diagonal(SparseMatrix& K, const Eigen::VectorXd& shift);

// Puts the dense BLAS under CHOLMOD on one thread, once per process. CHOLMOD's supernodal
// factorisation calls BLAS on its dense blocks, and OpenBLAS splits each call over its
// own threads (as many as OMP_NUM_THREADS or OPENBLAS_NUM_THREADS say), which changes the
// order of the sums: examples/plate_navier.yaml's state_crc32 differed between 1 and 2
// threads. Horizon's results do not depend on the thread count (docs/design.md), so the
// factorisation runs on one thread (HORIZON_BLAS_THREADS=N: N threads, the bits then
// depend on N; a bad value is an Error); the force passes and products keep OpenMP's threads.
void pin_blas_threads();

}  // namespace horizon
