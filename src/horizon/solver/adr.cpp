#include "horizon/solver/adr.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "horizon/core/error.hpp"
#include "horizon/parallel/decomposition.hpp"
#include "horizon/solver/conditioning.hpp"
#include "horizon/solver/forces.hpp"
#include "horizon/solver/tangent.hpp"

namespace horizon {

namespace {
// A run split over ranks with a model outside the unified form that splits its own pass
// (a structure, ModelTraits::structural and rows_local): each rank's rows of the model's
// assembled tangent are the serial rows bit for bit for its owned dofs (the model sums
// them from the terms it evaluates for its targets, over the ghosts' current positions,
// in the serial order), while the other rows read state this rank does not keep. The
// owned rows' entries of every rank, gathered on every rank: the serial tangent (each
// entry from one rank, summed there as serially), for the fictitious mass and the lowest
// eigenvalue that sets the damping. O(nonzeros) on every rank, once per solve. Collective.
SparseMatrix gather_owned_rows(const System& s, const DofMap& d, const SparseMatrix& K) {
  std::vector<double> mine;
  for (int c = 0; c < K.outerSize(); ++c)
    for (SparseMatrix::InnerIterator it(K, c); it; ++it)
      if (s.decomposition->owns(d.particle[static_cast<std::size_t>(it.row())]))
        mine.insert(mine.end(), {static_cast<double>(it.row()), static_cast<double>(it.col()), it.value()});
  const std::vector<double> all = allgather_values(mine);
  std::vector<Eigen::Triplet<double, int>> triplets;
  triplets.reserve(all.size() / 3);
  for (std::size_t q = 0; q + 2 < all.size(); q += 3)
    triplets.emplace_back(static_cast<int>(all[q]), static_cast<int>(all[q + 1]), all[q + 2]);
  SparseMatrix whole(K.rows(), K.cols());
  whole.setFromTriplets(triplets.begin(), triplets.end());
  return whole;
}
}  // namespace

SolveReport adr_solve(System& s, const DofMap& d, const AdrOptions& o) {
  SolveReport rep;
  FixedBonds fixed(s);
  const auto t0 = std::chrono::steady_clock::now();
  const Eigen::Index n = static_cast<Eigen::Index>(d.size());
  Eigen::VectorXd volume(n);
  for (Eigen::Index k = 0; k < n; ++k) volume[k] = s.particles.volume[d.particle[static_cast<std::size_t>(k)]];

  equilibrium_forces(s, false);  // split over ranks: after the ghosts' displacements
  // Fictitious mass (eq. 21) from the tangent's row sums at the starting state.
  // Models outside the unified bond form: the row sums of the model's own analytic
  // tangent (Model::stiffness), or of the finite-difference one.
  Eigen::VectorXd bound;
  bool structure = false;
  for (std::size_t m = 0; m < s.models.size(); ++m) structure = structure || s.models[m].traits().structural;
  SparseMatrix K;
  if (unified_form(s)) {
    bound = stiffness_row_bound(s, d, linearize(s));
  } else if (s.decomposition) {
    // Split over ranks (driver/run_implicit.cpp allows models that split their own pass
    // with ADR): the model's analytic tangent, its owned rows gathered, then as
    // solver_tangent (loose dofs held).
    if (!model_tangent(s, d, K))
      throw Error("internal error: a static solve split over ranks needs the model's analytic tangent");
    K = gather_owned_rows(s, d, K);
    hold_loose_dofs(K);
    bound = row_abs_sums(s, d, K);
  } else {
    K = solver_tangent(s, d, TangentKind::analytic);
    bound = row_abs_sums(s, d, K);
  }
  Eigen::VectorXd lambda = 0.25 * bound;
  double floor = 0;
  {
    double xmax = 0;
    for (const auto& x : s.particles.X) xmax = std::max({xmax, std::abs(x.x), std::abs(x.y), std::abs(x.z)});
    if (s.decomposition) {
      floor = std::numeric_limits<double>::epsilon() * xmax * dof_norm(s, d, bound.cwiseProduct(volume));
    } else {
      double sum = 0;
      for (Eigen::Index k = 0; k < n; ++k) sum += std::pow(bound[k] * volume[k], 2);
      floor = std::numeric_limits<double>::epsilon() * xmax * std::sqrt(sum);  // as round_off_residual
    }
  }
  for (Eigen::Index k = 0; k < n; ++k)
    if (!(lambda[k] > 0)) lambda[k] = 1;  // a dof without bonds: no stiffness, no force
  // Structures (beams, plates, shells): the local estimate below saturates on the
  // fourth-order bending operator (its highest modes dominate the local quotient), so the
  // damping is fixed for the solve at critical damping of the lowest mode of the
  // fictitious dynamics, c = 2 sqrt(omega_min^2), omega_min^2 the lowest eigenvalue of
  // K x = omega^2 Lambda V x (Underwood 1983, "Dynamic relaxation", in Computational
  // Methods for Transient Analysis, ch. 5, eq. for the optimal damping c = 2 omega_0;
  // Kilic and Madenci 2010 eq. 19 estimate the same omega_0 by the Rayleigh quotient).
  double fixed_damping = -1;
  if (structure && K.rows() > 0) {
    // Rounded to 24 significant bits: CHOLMOD's supernodal factorisation (BLAS) sums in
    // an order that depends on the BLAS threads, i.e. on the cores the process may use
    // (under mpirun, its binding: 1 and 2 ranks are bound, 3 not), so the last bits of
    // the estimate do; rounded, the damping and every iterate are the same on any rank
    // count (the damping is an estimate: 6e-8 of it changes nothing but the bits).
    double w2 = lowest_generalized_eigenvalue(K, lambda.cwiseProduct(volume));
    if (w2 > 0) {
      int e = 0;
      const double m = std::frexp(w2, &e);
      w2 = std::ldexp(std::round(std::ldexp(m, 24)), e - 24);
    }
    if (w2 > 0) {
      // With a unit step the central-difference scheme damps a mode of frequency^2 w2'
      // at the rate c/2 only while w2' <= 2 + sqrt(4 - c^2); the Gerschgorin mass leaves
      // w2' <= 4, attained by the alternating mode of a bending stencil (1 -4 6 -4 1),
      // which then oscillates undamped (characteristic root -1). The mass is scaled up
      // by 4 / (2 + sqrt(4 - c^2)) (a fraction c^2/16 for a small c) to keep it damped.
      const double c = std::min(2.0 * std::sqrt(w2), 1.99);
      const double scale = 4 / (2 + std::sqrt(4 - c * c));
      lambda *= scale;
      fixed_damping = std::min(2.0 * std::sqrt(w2 / scale), 1.99);
    }
  }
  rep.tangent_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  auto relative = [&](const Eigen::VectorXd& R) {
    const double ref = load_norms(s, d).reference();
    const double r = dof_norm(s, d, R);
    return ref > 0 ? r / ref : (r > 0 ? 1.0 : 0.0);
  };
  // Stagnation below the round-off bound of the forces (tangent.hpp) is convergence: the
  // smallest residual has not improved for `patience` iterations and is below the bound.
  const int patience = 500;
  double best_abs = std::numeric_limits<double>::infinity();
  int best_at = 0;
  // Split over ranks: distributed vectors (equilibrium.hpp), the owned dofs alone are
  // updated; every sum is a GridSum, so the iterates are the same on any rank count.
  Eigen::VectorXd R = gather_residual(s, d);
  keep_owned(s, d, R);
  Eigen::VectorXd F = R.cwiseQuotient(volume);  // force density
  Eigen::VectorXd u = gather_displacement(s, d);
  Eigen::VectorXd v = 0.5 * F.cwiseQuotient(lambda);  // eq. 18
  Eigen::VectorXd F_old(n);
  rep.residual = relative(R);
  rep.residuals.push_back(rep.residual);
  const int record_every = 100;
  for (int it = 1; it <= o.max_iterations; ++it) {
    if (rep.residual <= o.tolerance) break;
    u += v;
    scatter_displacement(s, d, u);
    equilibrium_forces(s, false);
    F_old = F;
    R = gather_residual(s, d);
    keep_owned(s, d, R);
    F = R.cwiseQuotient(volume);
    rep.iterations = it;
    rep.residual = relative(R);
    if (it % record_every == 0) rep.residuals.push_back(rep.residual);
    if (!std::isfinite(rep.residual)) {
      rep.failure = "the residual turned non-finite";
      return rep;
    }
    if (rep.residual <= o.tolerance) break;
    const double r_abs = dof_norm(s, d, R);
    if (r_abs < best_abs) {
      best_abs = r_abs;
      best_at = it;
    } else if (it - best_at > patience && best_abs <= floor) {
      rep.converged = true;  // at round-off
      break;
    }
    // Damping from the Rayleigh quotient of the local diagonal stiffness (eq. 19-20).
    double num = 0, den = 0;
    if (fixed_damping >= 0) {
      // a fixed damping needs no estimate
    } else if (s.decomposition) {
      GridSum g(s, 2);
      for (Eigen::Index k = 0; k < n; ++k) {
        if (!s.decomposition->owns(d.particle[static_cast<std::size_t>(k)])) continue;
        g.add(1, u[k] * u[k]);
        if (v[k] != 0) g.add(0, u[k] * u[k] * (-(F[k] - F_old[k]) / (lambda[k] * v[k])));
      }
      const std::vector<double> t = g.totals();
      num = t[0];
      den = t[1];
    } else {
      for (Eigen::Index k = 0; k < n; ++k) {
        den += u[k] * u[k];
        if (v[k] != 0) num += u[k] * u[k] * (-(F[k] - F_old[k]) / (lambda[k] * v[k]));
      }
    }
    const double c = fixed_damping >= 0                ? fixed_damping
                     : (den > 0 && num > 0) ? std::min(2.0 * std::sqrt(num / den), 1.99)
                                            : 0.0;
    v = ((2 - c) * v + 2 * F.cwiseQuotient(lambda)) / (2 + c);  // eq. 16
  }
  rep.residuals.push_back(rep.residual);
  rep.converged = rep.converged || rep.residual <= o.tolerance;
  if (!rep.converged) rep.failure = "no convergence in " + std::to_string(o.max_iterations) + " iterations";
  rep.solve_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return rep;
}

}  // namespace horizon
