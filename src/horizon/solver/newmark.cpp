#include "horizon/solver/newmark.hpp"

#include <cmath>

#include "horizon/parallel/decomposition.hpp"
#include "horizon/solver/forces.hpp"
#include "horizon/thermal/heat.hpp"

namespace horizon {

void advance_constraints(const Loads& loads, System& s, double t0, double t1) {
  auto& P = s.particles;
  const double mid = 0.5 * (t0 + t1);
  for (const auto& L : loads.loads()) {
    if (L.kind != LoadKind::velocity) continue;
    for (uint32_t i : L.particles)
      for (int c = 0; c < 3; ++c)
        if (L.value[c]) P.u[i][c] += (*L.value[c])(mid, P.X[i].x, P.X[i].y, P.X[i].z) * (t1 - t0);
  }
  loads.apply_constraints(s, t1, t1 - t0);
}

NewmarkSolver::NewmarkSolver(System& s, Loads& loads, double dt, double damping, NewtonOptions options,
                             int max_break_rounds)
    : s_(s),
      loads_(loads),
      dofs_(make_dof_map(s, loads)),
      dt_(dt),
      damping_(damping),
      options_(options),
      max_break_rounds_(max_break_rounds),
      linear_(options.linear_solver) {}

void NewmarkSolver::initialize() {
  auto& P = s_.particles;
  loads_.apply_constraints(s_, 0.0, 0.0);
  loads_.apply_forces(s_, 0.0);
  s_.time = 0;
  s_.dt = 0;
  equilibrium_forces(s_, true);  // split over ranks: after the ghosts' displacements
  commit_history(s_);
  loads_.update_reactions(s_, P.u);
  a_.resize(static_cast<Eigen::Index>(dofs_.size()));
  for (std::size_t k = 0; k < dofs_.size(); ++k) {
    const uint32_t i = dofs_.particle[k];
    const int c = dofs_.component[k];
    a_[static_cast<Eigen::Index>(k)] =
        zero_start_ ? 0.0 : (P.f[i][c] + P.b[i][c]) / P.density[i] - damping_ * P.v[i][c];
  }
  // Split over ranks: distributed vectors (equilibrium.hpp), other ranks' dofs 0, so that
  // their displacements stay as they are and their velocities are not integrated here.
  keep_owned(s_, dofs_, a_);
  ledger_.strain = strain_energy(s_);
  ledger_.kinetic = kinetic_energy(s_);
  ledger_.dissipated = s_.dissipated();
  ledger_.initial = ledger_.kinetic + ledger_.strain;
}

SolveReport NewmarkSolver::step() {
  auto& P = s_.particles;
  const double dt = dt_, t1 = time_ + dt;
  const std::vector<Vec3> u_before = P.u, v_before = P.v, b_before = P.b;
  const std::vector<uint8_t> intact_before = s_.bonds.intact;
  const std::vector<double> dissipated_before = s_.dissipated_at;
  const uint64_t broken_before = s_.broken;

  advance_constraints(loads_, s_, time_, t1);
  loads_.apply_forces(s_, t1);
  // A prescribed temperature field (thermal.conduction: false) at the step's end; its
  // strain change is booked as thermal work by the trapezoidal rule over the force states
  // of the last step's pass (at u_n, before the predictor moves it) and of this step's.
  std::vector<double> strain_change;
  double thermal_before = 0;
  if (s_.heat.active()) {
    strain_change = s_.thermal_strain;
    set_temperature_field(s_, t1);
    if (strain_change.size() == s_.thermal_strain.size()) {
      for (std::size_t i = 0; i < strain_change.size(); ++i) strain_change[i] = s_.thermal_strain[i] - strain_change[i];
      thermal_before = thermal_strain_work(s_, strain_change);
    } else {
      strain_change.clear();
    }
  }
  s_.time = t1;
  s_.dt = dt;
  const Eigen::VectorXd u_n = gather_displacement(s_, dofs_);
  Eigen::VectorXd v_n(u_n.size());
  for (std::size_t k = 0; k < dofs_.size(); ++k)
    v_n[static_cast<Eigen::Index>(k)] = v_before[dofs_.particle[k]][dofs_.component[k]];
  keep_owned(s_, dofs_, v_n);

  const double alpha = 4.0 / (dt * dt);
  InertiaTerm inertia;
  inertia.mass = nodal_mass(s_, dofs_);
  inertia.kappa = alpha * (1 + damping_ * dt / 2);
  inertia.u_hat = u_n + dt * v_n + (dt * dt / 4) * a_;
  inertia.g = damping_ * (v_n + (dt / 2) * a_);
  NewtonOptions o = options_;
  o.inertia = &inertia;
  // Predictor: a_{n+1} = a_n.
  scatter_displacement(s_, dofs_, inertia.u_hat + (dt * dt / 4) * a_);

  SolveReport rep;
  for (int round = 0;; ++round) {
    rep = newton_solve(s_, dofs_, o, linear_);
    newton_iterations_ += rep.iterations;
    linear_iterations_ += rep.linear_iterations;
    if (!rep.converged) break;
    // Break the bonds the converged state overstretches; re-solve until none breaks.
    if (!equilibrium_forces(s_, false)) break;
    if (round + 1 >= max_break_rounds_) break;
  }
  if (!rep.converged || !finite_state(s_)) {
    P.u = u_before;
    P.v = v_before;
    P.b = b_before;
    s_.bonds.intact = intact_before;
    s_.dissipated_at = dissipated_before;
    s_.broken = broken_before;
    if (s_.heat.active()) set_temperature_field(s_, time_);
    {
      FixedBonds fixed(s_);
      equilibrium_forces(s_, true);
    }
    if (rep.converged) rep.failure = "the state turned non-finite";
    rep.converged = false;
    return rep;
  }

  const Eigen::VectorXd u1 = gather_displacement(s_, dofs_);
  const Eigen::VectorXd a1 = alpha * (u1 - inertia.u_hat);
  const Eigen::VectorXd v1 = v_n + (dt / 2) * (a_ + a1);
  a_ = a1;
  for (std::size_t k = 0; k < dofs_.size(); ++k) P.v[dofs_.particle[k]][dofs_.component[k]] = v1[static_cast<Eigen::Index>(k)];
  {
    FixedBonds fixed(s_);
    equilibrium_forces(s_, true);
  }
  commit_history(s_);
  if (!strain_change.empty()) ledger_.thermal_work += 0.5 * (thermal_before + thermal_strain_work(s_, strain_change));
  time_ = t1;
  ++steps_;

  // Ledger: work of the constraints and of the applied force densities (trapezoidal),
  // energy taken by the damping (trapezoidal in gamma M v^2).
  double work = loads_.update_reactions(s_, u_before, &v_before, dt);
  double damped = 0;
  if (s_.decomposition) {  // the owned particles' terms, GridSum totals
    GridSum g(s_, 2);
    for (uint32_t i : s_.owned) {
      g.add(0, 0.5 * P.volume[i] * dot(P.b[i] + b_before[i], P.u[i] - u_before[i]));
      if (damping_ > 0)
        g.add(1, 0.5 * dt * damping_ * P.density[i] * P.volume[i] *
                     (loads_.free_speed2(i, P.v[i]) + loads_.free_speed2(i, v_before[i])));
    }
    const std::vector<double> t = g.totals();
    work += t[0];
    damped = t[1];
  } else {
    for (std::size_t i = 0; i < P.size(); ++i) {
      work += 0.5 * P.volume[i] * dot(P.b[i] + b_before[i], P.u[i] - u_before[i]);
      if (damping_ > 0)
        damped += 0.5 * dt * damping_ * P.density[i] * P.volume[i] *
                  (loads_.free_speed2(i, P.v[i]) + loads_.free_speed2(i, v_before[i]));
    }
  }
  ledger_.external_work += work;
  ledger_.damped += damped;
  ledger_.dissipated = s_.dissipated();
  ledger_.strain = strain_energy(s_);
  ledger_.kinetic = kinetic_energy(s_);
  return rep;
}

}  // namespace horizon
