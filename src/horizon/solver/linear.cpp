#include "horizon/solver/linear.hpp"

#include <Eigen/CholmodSupport>
#include <Eigen/Dense>
#include <Eigen/IterativeLinearSolvers>
#include <dlfcn.h>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <string>

#include "horizon/core/error.hpp"

namespace horizon {

struct LinearSolver::Direct {
  // CHOLMOD chooses: supernodal (dense BLAS blocks) when the factor is dense enough to
  // pay (3-D state-based tangents), simplicial otherwise (2-D, small bodies), which avoids BLAS threads.
  Eigen::CholmodDecomposition<SparseMatrix, Eigen::Lower> llt;
  uint64_t pattern = 0;  // checksum of the analysed sparsity pattern
  bool analysed = false;
};

LinearSolver::LinearSolver(LinearSolverKind kind) : kind_(kind) {}
LinearSolver::~LinearSolver() = default;

void add_to_diagonal(SparseMatrix& K, const Eigen::VectorXd& shift) {
  if (shift.size() == 0) return;
  for (int c = 0; c < K.outerSize(); ++c)
    for (SparseMatrix::InnerIterator it(K, c); it; ++it)
      if (it.row() == c) it.valueRef() += shift[c];
}

void pin_blas_threads() {
  // HORIZON_BLAS_THREADS=N gives BLAS N threads instead: faster factorisations of large 3-D
  // tangents, whose last bits then depend on N. Looked up at run time: which BLAS
  // libblas.so.3 is comes from Debian's alternatives, and the reference BLAS (no threads)
  // has no such function.
  static const int threads = [] {
    int n = 1;
    if (const char* env = std::getenv("HORIZON_BLAS_THREADS"); env && *env) {
      const std::string v = env;
      std::size_t used = 0;
      try {
        n = std::stoi(v, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != v.size() || n < 1)
        throw Error("HORIZON_BLAS_THREADS=" + v + ": expected a whole number of threads, at least 1");
    }
    using SetThreads = void (*)(int);
    if (auto* set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"))) set(n);
    return n;
  }();
  (void)threads;
}

namespace {

// The largest system the CG path may finish with a dense solve (about 2 s of a complete
// orthogonal decomposition at 3000 unknowns; 1029 for a 343-particle body).
constexpr Eigen::Index kDenseFallbackDofs = 3000;

uint64_t pattern_checksum(const SparseMatrix& K) {
  uint64_t h = 1469598103934665603ull ^ static_cast<uint64_t>(K.rows());
  auto mix = [&h](uint64_t v) { h = (h ^ v) * 1099511628211ull; };
  for (Eigen::Index c = 0; c <= K.outerSize(); ++c) mix(static_cast<uint64_t>(K.outerIndexPtr()[c]));
  for (Eigen::Index k = 0; k < K.nonZeros(); ++k) mix(static_cast<uint64_t>(K.innerIndexPtr()[k]));
  return h;
}

// Preconditioned conjugate gradient (Hestenes-Stiefel) with a Jacobi preconditioner.
// dot: the inner product (a GridSum over the owned dofs when the run is split over ranks,
// equilibrium.hpp); rows: then the owned dofs, the only entries updated (the others stay
// 0), else null and every entry is (Eigen's vector operations, the serial bits).
LinearStats pcg(const std::function<void(const Eigen::VectorXd&, Eigen::VectorXd&)>& apply,
                const std::function<double(const Eigen::VectorXd&, const Eigen::VectorXd&)>& dot,
                const std::vector<Eigen::Index>* rows, const Eigen::VectorXd& diag, const Eigen::VectorXd& r,
                Eigen::VectorXd& x, double tol, int max_iterations) {
  LinearStats st;
  const Eigen::Index n = r.size();
  x = Eigen::VectorXd::Zero(n);
  auto norm = [&](const Eigen::VectorXd& v) { return rows ? std::sqrt(dot(v, v)) : v.norm(); };
  const double rnorm = norm(r);
  if (rnorm == 0) {
    st.ok = true;
    return st;
  }
  Eigen::VectorXd inv = diag.unaryExpr([](double v) { return v > 0 ? 1.0 / v : 1.0; });
  Eigen::VectorXd res = r, z = inv.cwiseProduct(res), p = z, q(n);
  if (rows) {  // the entries of other ranks' dofs stay 0
    z.setZero();
    for (Eigen::Index k : *rows) z[k] = inv[k] * res[k];
    p = z;
  }
  double rz = rows ? dot(res, z) : res.dot(z);
  for (int it = 1; it <= max_iterations; ++it) {
    apply(p, q);
    const double pq = rows ? dot(p, q) : p.dot(q);
    if (!(pq > 0)) break;  // not positive definite along p
    const double alpha = rz / pq;
    if (rows) {
      for (Eigen::Index k : *rows) {
        x[k] += alpha * p[k];
        res[k] -= alpha * q[k];
      }
    } else {
      x += alpha * p;
      res -= alpha * q;
    }
    st.iterations = it;
    st.residual = norm(res) / rnorm;
    if (st.residual <= tol) {
      st.ok = true;
      return st;
    }
    if (rows) {
      for (Eigen::Index k : *rows) z[k] = inv[k] * res[k];
    } else {
      z = inv.cwiseProduct(res);
    }
    const double rz_new = rows ? dot(res, z) : res.dot(z);
    const double beta = rz_new / rz;
    if (rows) {
      for (Eigen::Index k : *rows) p[k] = z[k] + beta * p[k];
    } else {
      p = z + beta * p;
    }
    rz = rz_new;
  }
  st.ok = std::isfinite(st.residual) && st.residual <= tol;
  return st;
}

}  // namespace

LinearStats LinearSolver::solve(SparseMatrix& K, const Eigen::VectorXd& shift, const Eigen::VectorXd& r,
                                Eigen::VectorXd& x, double tol, int max_iterations) {
  add_to_diagonal(K, shift);
  LinearStats st;
  if (kind_ == LinearSolverKind::cholesky) {
    if (!direct_) direct_ = std::make_unique<Direct>();
    pin_blas_threads();
    const uint64_t pattern = pattern_checksum(K);
    if (!direct_->analysed || pattern != direct_->pattern) {
      direct_->llt.analyzePattern(K);
      direct_->pattern = pattern;
      direct_->analysed = true;
    }
    direct_->llt.factorize(K);
    st.factor_fill = direct_->llt.cholmod().lnz;
    if (direct_->llt.info() != Eigen::Success) return st;  // not positive definite
    x = direct_->llt.solve(r);
    st.iterations = 1;
    st.ok = x.allFinite();
    return st;
  }
  // The matrix holds K^T (tangent.hpp), so the parallel row-major product of the
  // transposed view gives K x; Eigen's CG does the same for Lower|Upper.
  // A small system (kDenseFallbackDofs unknowns at most) gets 2n CG iterations, more than
  // CG needs in exact arithmetic (n), and where they do not reach the tolerance, the dense
  // solve below: CG stalls on a tangent that is singular or nearly so (a body held in one
  // direction alone: PredictorFromPreviousSolver's decks fix y only, so x and z translate
  // freely, and CG ran 20,000 iterations of about 1e6 entries per Newton iteration, 79 % of
  // the run under perf). Larger systems keep the given iteration limit.
  const Eigen::Index n = K.rows();
  const bool small = n > 0 && n <= kDenseFallbackDofs;
  Eigen::ConjugateGradient<SparseMatrix, Eigen::Lower | Eigen::Upper, Eigen::DiagonalPreconditioner<double>> cg;
  cg.setTolerance(tol);
  cg.setMaxIterations(small ? std::min<Eigen::Index>(max_iterations, 2 * n) : max_iterations);
  cg.compute(K);
  x = cg.solve(r);
  st.iterations = static_cast<int>(cg.iterations());
  st.residual = cg.error();
  st.ok = cg.info() == Eigen::Success && x.allFinite();
  if (small && !st.ok) {
    // The minimum-norm least-squares solution (a complete orthogonal decomposition, rank
    // revealing): for a singular K and a residual with no part along its null space (the
    // internal forces of a free motion balance), the solution CG converges to from 0 in
    // exact arithmetic. The matrix holds K^T (above).
    // Pivots below 1e-8 of the largest count as zero: a finite-difference tangent (the
    // correspondence models') leaves its rigid modes at round-off of the difference
    // quotient, not at 0, and solving along them would add a large free motion (the
    // displacements of PredictorFromPreviousSolver drifted 6e-3 along z, 250 times the
    // gold's largest, with Eigen's default threshold of n eps).
    const Eigen::MatrixXd D = Eigen::MatrixXd(K).transpose();
    Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod;
    cod.setThreshold(1e-8);
    cod.compute(D);
    x = cod.solve(r);
    const double rn = r.norm();
    st.residual = rn > 0 ? (D * x - r).norm() / rn : 0.0;
    st.iterations += 1;
    st.ok = x.allFinite();
  }
  return st;
}

LinearStats LinearSolver::solve(const TangentOperator& K, const Eigen::VectorXd& shift, const Eigen::VectorXd& r,
                                Eigen::VectorXd& x, double tol, int max_iterations) {
  Eigen::VectorXd diag = K.diagonal();
  if (shift.size()) diag += shift;
  auto apply = [&](const Eigen::VectorXd& p, Eigen::VectorXd& q) {
    K.apply(p, q);
    if (shift.size()) q += shift.cwiseProduct(p);
  };
  // Split over ranks: distributed vectors (equilibrium.hpp), the same iterates on any
  // number of ranks.
  const std::vector<Eigen::Index> rows = owned_dofs(K.system(), K.dofs());
  auto dot = [&](const Eigen::VectorXd& a, const Eigen::VectorXd& b) { return dof_dot(K.system(), K.dofs(), a, b); };
  return pcg(apply, dot, K.system().decomposition ? &rows : nullptr, diag, r, x, tol, max_iterations);
}

}  // namespace horizon
