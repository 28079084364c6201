#include "horizon/solver/conditioning.hpp"

#include <Eigen/CholmodSupport>
#include <Eigen/Eigenvalues>
#include <Spectra/SymEigsShiftSolver.h>
#include <Spectra/SymEigsSolver.h>
#include <algorithm>
#include <cmath>
#include <limits>

#include "horizon/solver/linear.hpp"

namespace horizon {

namespace {

// y = K x (the stored matrix is symmetric; the transposed view gives the parallel product).
class ProductOp {
 public:
  using Scalar = double;
  explicit ProductOp(const SparseMatrix& K) : K_(K) {}
  Eigen::Index rows() const { return K_.rows(); }
  Eigen::Index cols() const { return K_.cols(); }
  void perform_op(const double* x, double* y) const {
    Eigen::Map<const Eigen::VectorXd> xv(x, K_.cols());
    Eigen::Map<Eigen::VectorXd> yv(y, K_.rows());
    yv.noalias() = K_.transpose() * xv;
  }

 private:
  const SparseMatrix& K_;
};

// y = (K - sigma I)^-1 x by a sparse Cholesky factorisation (sigma = 0 here).
class ShiftInvertOp {
 public:
  using Scalar = double;
  explicit ShiftInvertOp(const SparseMatrix& K) : K_(K) { pin_blas_threads(); }
  Eigen::Index rows() const { return K_.rows(); }
  Eigen::Index cols() const { return K_.cols(); }
  void set_shift(double sigma) {
    llt_.setShift(-sigma);
    llt_.compute(K_);
    if (llt_.info() != Eigen::Success) throw std::invalid_argument("not positive definite");
  }
  void perform_op(const double* x, double* y) const {
    Eigen::Map<const Eigen::VectorXd> xv(x, K_.cols());
    Eigen::Map<Eigen::VectorXd> yv(y, K_.rows());
    yv = llt_.solve(xv);
  }

 private:
  const SparseMatrix& K_;
  Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower> llt_;
};

}  // namespace

ConditionEstimate estimate_condition(const SparseMatrix& K, double tol) {
  ConditionEstimate est;
  const Eigen::Index n = K.rows();
  if (n < 2) {
    est.message = "fewer than two unknowns";
    return est;
  }
  // 100 Lanczos vectors: the top of a PD spectrum is clustered (the symbol is flat near the
  // highest wave number), and a wide basis converges in fewer, cheaper restarts.
  const Eigen::Index ncv = std::min<Eigen::Index>(n, 100);
  {
    ProductOp op(K);
    Spectra::SymEigsSolver<ProductOp> eigs(op, 1, ncv);
    eigs.init();
    eigs.compute(Spectra::SortRule::LargestAlge, 2000, tol);
    est.products += static_cast<int>(eigs.num_operations());
    if (eigs.info() != Spectra::CompInfo::Successful) {
      est.message = "Lanczos did not converge for the largest eigenvalue";
      return est;
    }
    est.lambda_max = eigs.eigenvalues()[0];
  }
  try {
    ShiftInvertOp op(K);
    // Shift-invert converges in one restart: a narrow basis saves solves.
    Spectra::SymEigsShiftSolver<ShiftInvertOp> eigs(op, 1, std::min<Eigen::Index>(n, 20), 0.0);
    eigs.init();
    eigs.compute(Spectra::SortRule::LargestMagn, 2000, tol);
    est.solves += static_cast<int>(eigs.num_operations());
    if (eigs.info() != Spectra::CompInfo::Successful) {
      est.message = "Lanczos did not converge for the smallest eigenvalue";
      return est;
    }
    est.lambda_min = eigs.eigenvalues()[0];
  } catch (const std::invalid_argument&) {
    est.lambda_min = 0;
    est.condition = std::numeric_limits<double>::infinity();
    est.message = "the tangent is singular or indefinite (Cholesky failed): unconstrained rigid motion?";
    return est;
  }
  est.condition = est.lambda_min > 0 ? est.lambda_max / est.lambda_min : std::numeric_limits<double>::infinity();
  est.converged = true;
  return est;
}

double lowest_generalized_eigenvalue(const SparseMatrix& K, const Eigen::VectorXd& mass, double tol) {
  const Eigen::Index n = K.rows();
  if (n < 1 || mass.size() != n) return -1;
  const Eigen::VectorXd scale = mass.cwiseSqrt().cwiseInverse();
  SparseMatrix Kt = K.transpose();
  SparseMatrix S = 0.5 * (K + Kt);
  S = scale.asDiagonal() * S * scale.asDiagonal();
  if (n < 3) {
    const Eigen::MatrixXd dense(S);
    return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(dense, Eigen::EigenvaluesOnly).eigenvalues()[0];
  }
  try {
    ShiftInvertOp op(S);
    Spectra::SymEigsShiftSolver<ShiftInvertOp> eigs(op, 1, std::min<Eigen::Index>(n, 20), 0.0);
    eigs.init();
    eigs.compute(Spectra::SortRule::LargestMagn, 1000, tol);
    if (eigs.info() != Spectra::CompInfo::Successful) return -1;
    return eigs.eigenvalues()[0];
  } catch (const std::invalid_argument&) {
    return -1;
  }
}

}  // namespace horizon
