#include "horizon/solver/newton.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "horizon/parallel/decomposition.hpp"
#include "horizon/solver/forces.hpp"

namespace horizon {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Residual and the norm it is measured against, at the current u (forces computed).
struct Evaluation {
  Eigen::VectorXd R;
  double norm = 0, reference = 0;
};

Evaluation evaluate(System& s, const DofMap& d, const InertiaTerm* inertia) {
  equilibrium_forces(s, false);  // split over ranks: after the ghosts' displacements
  Evaluation e;
  e.R = gather_residual(s, d);
  keep_owned(s, d, e.R);  // split over ranks: a distributed vector (equilibrium.hpp)
  e.reference = load_norms(s, d).reference();
  if (inertia) {
    Eigen::VectorXd u = gather_displacement(s, d);
    keep_owned(s, d, u);
    Eigen::VectorXd m_a = inertia->mass.cwiseProduct(inertia->kappa * (u - inertia->u_hat) + inertia->g);
    keep_owned(s, d, m_a);
    e.R -= m_a;
    e.reference = std::max(e.reference, dof_norm(s, d, m_a));
  }
  e.norm = dof_norm(s, d, e.R);
  if (!std::isfinite(e.norm)) e.norm = std::numeric_limits<double>::infinity();
  return e;
}

}  // namespace

SolveReport newton_solve(System& s, const DofMap& d, const NewtonOptions& o, LinearSolver& linear) {
  SolveReport rep;
  FixedBonds fixed(s);
  Evaluation ev = evaluate(s, d, o.inertia);
  const bool unified = unified_form(s);
  if (!unified && o.linear_solver == LinearSolverKind::matrix_free) {
    rep.failure = "the matrix-free product needs the analytic tangent of the unified models (`horizon models`: Model::unified), which this run's models lack: use "
                  "solver.linear_solver cg or cholesky (the model's assembled tangent, or finite differences of the forces)";
    return rep;
  }
  // The round-off bound of the residual (needed only when the residual stagnates): from
  // the unified linearisation, or from the row sums of the last finite-difference tangent.
  double floor = -1;
  // A load-free problem (reference 0) is in equilibrium when the residual is 0 too.
  auto relative = [](const Evaluation& e) { return e.reference > 0 ? e.norm / e.reference : (e.norm > 0 ? 1.0 : 0.0); };
  Eigen::VectorXd shift;
  if (o.inertia) shift = o.inertia->kappa * o.inertia->mass;
  Eigen::VectorXd du;
  for (int it = 0;; ++it) {
    rep.residual = relative(ev);
    rep.residuals.push_back(rep.residual);
    if (rep.residual <= o.tolerance) {
      rep.converged = true;
      return rep;
    }
    if (!std::isfinite(ev.norm)) {
      rep.failure = "the residual turned non-finite";
      return rep;
    }
    if (it == o.max_iterations) {
      rep.failure = "no convergence in " + std::to_string(o.max_iterations) + " iterations";
      return rep;
    }
    rep.iterations = it + 1;

    // The tangent and the Newton direction K du = R.
    // Forcing term: solve just accurately enough that, were the problem linear, this
    // iteration would meet the tolerance; PD problems at small strain nearly are.
    const double eta = std::clamp(0.1 * o.tolerance / rep.residual, 1e-12, 1e-1);
    LinearStats ls;
    auto t0 = std::chrono::steady_clock::now();
    if (o.linear_solver == LinearSolverKind::matrix_free) {
      const TangentOperator K(s, d);
      rep.tangent_bytes = K.bytes();
      rep.tangent_seconds += seconds_since(t0);
      t0 = std::chrono::steady_clock::now();
      ls = linear.solve(K, shift, ev.R, du, eta, o.max_linear_iterations);
    } else {
      SparseMatrix K = solver_tangent(s, d, o.tangent);
      if (!unified) floor = round_off_residual(s, d, K);
      rep.tangent_nonzeros = static_cast<std::size_t>(K.nonZeros());
      rep.tangent_bytes = rep.tangent_nonzeros * (sizeof(double) + sizeof(int)) + (d.size() + 1) * sizeof(int);
      rep.tangent_seconds += seconds_since(t0);
      t0 = std::chrono::steady_clock::now();
      ls = linear.solve(K, shift, ev.R, du, eta, o.max_linear_iterations);
      rep.factor_fill = ls.factor_fill;
    }
    rep.solve_seconds += seconds_since(t0);
    rep.linear_iterations += ls.iterations;
    // Split over ranks, every rank takes the same branch: the finiteness of du is global.
    auto du_finite = [&] {
      const bool finite = du.allFinite();
      return s.decomposition ? !any_rank(*s.decomposition, !finite) : finite;
    };
    if (!ls.ok && !(du.size() && du_finite() && ls.iterations > 0)) {
      rep.failure = linear.kind() == LinearSolverKind::cholesky
                        ? "the tangent is not positive definite (Cholesky failed): is every rigid motion constrained?"
                        : "the linear solve failed";
      return rep;
    }

    // Backtracking line search on |R|.
    double alpha = 1;
    add_displacement(s, d, du, alpha);
    Evaluation trial = evaluate(s, d, o.inertia);
    // A full step that does not lower a residual already at round-off: converged, no
    // need to search (a tiny load reaches round-off in one iteration).
    if (!(trial.norm < ev.norm)) {
      if (floor < 0) floor = round_off_residual(s, d, linearize(s));
      if (ev.norm <= floor) {
        add_displacement(s, d, du, -alpha);
        equilibrium_forces(s, false);
        rep.converged = true;
        return rep;
      }
    }
    if (o.line_search) {
      double best_alpha = alpha, best = trial.norm;
      for (int h = 0; h < 8 && !(trial.norm <= (1 - 1e-4 * alpha) * ev.norm); ++h) {
        add_displacement(s, d, du, -0.5 * alpha);
        alpha *= 0.5;
        trial = evaluate(s, d, o.inertia);
        if (trial.norm < best) {
          best = trial.norm;
          best_alpha = alpha;
        }
      }
      if (alpha != best_alpha) {
        add_displacement(s, d, du, best_alpha - alpha);
        alpha = best_alpha;
        trial = evaluate(s, d, o.inertia);
      }
    }
    if (!(trial.norm < ev.norm)) {
      // No step along the Newton direction lowers the residual. Below the round-off of
      // the forces that is convergence (a tiny load, a tight tolerance); above, failure.
      // Either way the state goes back to the better iterate.
      add_displacement(s, d, du, -alpha);
      equilibrium_forces(s, false);
      if (floor < 0) floor = round_off_residual(s, d, linearize(s));
      if (ev.norm <= floor) {
        rep.converged = true;
        return rep;
      }
      rep.failure = fmt::format("the residual stopped decreasing at {:.3e} of the load, above the round-off "
                                "level {:.3e}",
                                rep.residual, ev.reference > 0 ? floor / ev.reference : floor);
      return rep;
    }
    ev = std::move(trial);
  }
}

}  // namespace horizon
