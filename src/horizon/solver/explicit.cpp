#include "horizon/solver/explicit.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "horizon/core/parallel_select.hpp"
#include "horizon/fe/fe_region.hpp"
#include "horizon/kernels/verlet.hpp"
#include "horizon/parallel/decomposition.hpp"
#include "horizon/solver/forces.hpp"
#include "horizon/thermal/heat.hpp"

namespace horizon {

double Ledger::balance_error() const {
  const double scale = std::max({std::abs(initial), std::abs(external_work), std::abs(thermal_work),
                                  std::abs(coupling_work), kinetic + strain + dissipated + damped, thermal_scale,
                                  1e-300});
  return (kinetic + strain + dissipated + damped - initial - external_work - thermal_work - coupling_work) / scale;
}

namespace {
std::string non_finite_message(std::size_t i, const Vec3& x, int64_t step) {
  std::ostringstream m;
  m.precision(6);
  m << "the state turned non-finite at step " << step << ": particle " << i << " at (" << x.x << ", " << x.y << ", "
    << x.z << "); try a smaller time step (solver.safety_factor) or check the loads";
  return m.str();
}
}  // namespace

NonFiniteState::NonFiniteState(std::size_t i, const Vec3& position, int64_t step)
    : Error(non_finite_message(i, position, step)), particle(i) {}

double kinetic_energy(const System& s) {
  const auto& P = s.particles;
  if (s.decomposition) {
    GridSum g(s, 1);
    for (uint32_t i : s.owned) g.add(0, kernels::kinetic(P.density[i], P.volume[i], P.v[i].x, P.v[i].y, P.v[i].z));
    return g.totals()[0];
  }
  double sum = 0;
  for (std::size_t i = 0; i < P.size(); ++i) sum += kernels::kinetic(P.density[i], P.volume[i], P.v[i].x, P.v[i].y, P.v[i].z);
  return sum;
}

ExplicitSolver::ExplicitSolver(System& s, Loads& loads, double dt, double damping)
    : s_(s), loads_(loads), dt_(dt), damping_(damping) {
  for (const auto& L : loads_.loads())
    if (L.kind != LoadKind::displacement && L.kind != LoadKind::velocity) has_forces_ = true;
  if (!loads_.projectiles().empty()) has_forces_ = true;  // their contact force densities
}

// The particles' and the rigid projectiles' kinetic energy.
void ExplicitSolver::update_kinetic() {
  ledger_.kinetic = kinetic_energy(s_);
  for (const auto& p : loads_.projectiles()) ledger_.kinetic += p.kinetic();
  if (s_.decomposition) ledger_.dissipated = s_.dissipated();  // see step()
}

void ExplicitSolver::initialize(double t0, double dt_before) {
  start_time_ = time_ = t0;
  s_.step_start_u.clear();  // a static stage's quasi-static positions end with it
  steps_ = 0;
  ledger_ = Ledger{};
  // Peridigm's Verlet applies a prescribed displacement as increments from the start, so
  // g(0) itself is never applied: u_n = u_0 + g(t_n) - g(0) (DeformationGradient_
  // PlaneStrainCompression's gold, g = x exp(0.0953 t/1e-8): u = x (e^0.00953 - 1) at 1e-9).
  // A staged run's explicit stage (dt_before > 0) starts from the static stage's u = g(t0).
  loads_.apply_constraints(s_, t0, dt_before, !(peridigm_ && dt_before == 0));
  loads_.apply_forces(s_, t0);
  for (auto& p : loads_.projectiles()) p.finish_step(p.x, p.force, 0, 0);
  s_.time = t0;
  s_.dt = 0;
  s_.model.commit_follows = true;  // (as in step(): the ordinary models keep no trial copies)
  compute_forces(s_, true);
  s_.model.commit_follows = false;
  commit_history(s_);
  u_before_ = s_.particles.u;
  loads_.update_reactions(s_, u_before_);
  ledger_.strain = strain_energy(s_);
  update_kinetic();
  ledger_.dissipated = s_.dissipated();
  ledger_.initial = ledger_.kinetic + ledger_.strain;
  // A later start (a staged run's explicit stage): the bonds broken before it are part of
  // the energy it starts with, so that its balance closes over the stage.
  if (t0 > 0) ledger_.initial += ledger_.dissipated;
}

void ExplicitSolver::advance_clock(int64_t n) {
  for (int64_t k = 0; k < n; ++k) {
    ++steps_;
    time_ = fixed_dt_ ? start_time_ + static_cast<double>(steps_) * dt_ : time_ + dt_;  // as step() does
  }
  s_.time = time_;
  s_.dt = dt_;
}

void ExplicitSolver::step(bool energy) {
  auto& P = s_.particles;
  // A decomposed run integrates its own particles alone (state/system.hpp).
  const std::vector<uint32_t>* own = s_.owned.empty() ? nullptr : &s_.owned;
  const std::size_t n = own ? own->size() : P.size();
  const double dt = dt_, half = 0.5 * dt, time_before = time_;
  parallel_copy(u_before_, P.u);
  parallel_copy(v_before_, P.v);
  if (has_forces_) parallel_copy(b_before_, P.b);
  // Rigid projectiles: half kick and drift with the contact force of the last pass
  // (contact/projectile.hpp); their state before the step, should it turn non-finite.
  auto& bodies = loads_.projectiles();
  const std::vector<Projectile> bodies_before = bodies;
  for (auto& p : bodies) {
    p.kick(half);
    p.drift(dt);
  }

  // Half kick and drift. a(n) = (f + b)/rho - gamma v.
  if (peridigm_) {
#pragma omp parallel for schedule(static)
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t i = own ? (*own)[k] : k;
      Vec3& v = P.v[i];
      v.x = kernels::peridigm_kick(v.x, P.f[i].x, P.b[i].x, P.density[i], half);
      v.y = kernels::peridigm_kick(v.y, P.f[i].y, P.b[i].y, P.density[i], half);
      v.z = kernels::peridigm_kick(v.z, P.f[i].z, P.b[i].z, P.density[i], half);
    }
  } else {
#pragma omp parallel for schedule(static)
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t i = own ? (*own)[k] : k;
      // kernels/verlet.hpp, one component at a time (Vec3's division multiplies by 1/rho).
      const double inv_rho = 1.0 / P.density[i];
      Vec3& v = P.v[i];
      v.x = kernels::half_kick(v.x, P.f[i].x, P.b[i].x, inv_rho, damping_, half);
      v.y = kernels::half_kick(v.y, P.f[i].y, P.b[i].y, inv_rho, damping_, half);
      v.z = kernels::half_kick(v.z, P.f[i].z, P.b[i].z, inv_rho, damping_, half);
    }
  }
  loads_.prescribe_velocity(s_, time_ + half);
  // A fixed step: t = n dt, as Peridigm reports it (its golds' times agree to the last bit:
  // ep_cube's 35,000 steps of 1e-6 end at 0.034999999999999996, where summing dt drifts
  // by 1.4e-14); an adaptive step (set_dt) is summed.
  // A staged run's explicit stage starts at start_time_ (0 otherwise): t = t0 + n dt.
  const double time_next = fixed_dt_ ? start_time_ + static_cast<double>(steps_ + 1) * dt : time_ + dt;
  if (peridigm_) {
    // The prescribed displacements' rates over the step, then y = (X + u_n) + dt v_{n+1/2}
    // apart from u_{n+1} = u_n + dt v_{n+1/2} (set_peridigm_verlet).
    loads_.prescribe_increments(s_, time_next, time_);
    s_.positions.resize(P.size());  // a decomposed run's ghosts: the exchange below
#pragma omp parallel for schedule(static)
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t i = own ? (*own)[k] : k;
      const Vec3 xu = P.X[i] + P.u[i];
      s_.positions[i] = {xu.x + dt * P.v[i].x, xu.y + dt * P.v[i].y, xu.z + dt * P.v[i].z};
    }
  }
#pragma omp parallel for schedule(static)
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = own ? (*own)[k] : k;
    Vec3& u = P.u[i];
    u.x = kernels::drift(u.x, P.v[i].x, dt);
    u.y = kernels::drift(u.y, P.v[i].y, dt);
    u.z = kernels::drift(u.z, P.v[i].z, dt);
  }

  ++steps_;
  time_ = time_next;
  loads_.apply_constraints(s_, time_, dt, !peridigm_);  // prescribed displacements (velocities follow below)
  loads_.apply_forces(s_, time_);
  s_.time = time_;
  s_.dt = dt;
  if (s_.decomposition) halo_exchange(s_, *s_.decomposition);  // the ghosts' displacements
  if (peridigm_ && s_.decomposition) exchange_ghost_values(*s_.decomposition, s_.positions);
  // Critical stretches that vary in time, at the new time: bonds break before the force
  // pass against s0(t_{n+1}) (Peridigm evaluates its damage model before the forces).
  for (const auto& c : s_.critical_stretch_schedules) {
    const double s0 = c.s0(time_);
    for (uint32_t i : c.particles) s_.model.critical_stretch[i] = s0;
  }
  // A prescribed temperature field (thermal.conduction: false) at the new time, before the
  // force pass, as Peridigm evaluates its temperature condition (ThermalExpansionBondFailure's
  // gold); its strain change is booked as thermal work by the trapezoidal rule over the
  // force states of this pass and the one before (thermal/heat.hpp thermal_strain_work).
  std::vector<double> strain_change;
  double thermal_before = 0;
  if (s_.heat.active() && !s_.heat.conduction) {
    strain_change = s_.thermal_strain;
    set_temperature_field(s_, time_);
    if (strain_change.size() == s_.thermal_strain.size()) {
      for (std::size_t i = 0; i < strain_change.size(); ++i) strain_change[i] = s_.thermal_strain[i] - strain_change[i];
      thermal_before = thermal_strain_work(s_, strain_change);
    } else {
      strain_change.clear();
    }
  }
  // The history of this pass is committed before the next one: the ordinary models keep
  // no trial copy of their ledger's force states (history_ledger.hpp LedgerRows).
  s_.model.commit_follows = true;
  compute_forces(s_, energy);
  s_.model.commit_follows = false;
  if (!strain_change.empty()) ledger_.thermal_work += 0.5 * (thermal_before + thermal_strain_work(s_, strain_change));
  commit_history_with_heat(s_);  // history models (plasticity, viscosity) accept this step

  // Second half kick; damping taken implicitly on the half step so it stays stable.
  const double damp = 1.0 / (1.0 + damping_ * half);
  double damped = 0;
  bool finite = true;
  // A decomposed run keeps each owned particle's damped energy and sums them through
  // GridSum (the same total at any rank and thread count); the serial sum is a reduction.
  const bool grid_damped = damping_ > 0 && s_.decomposition;
  if (grid_damped) damped_terms_.assign(n, 0.0);
#pragma omp parallel for schedule(static) reduction(&& : finite) reduction(+ : damped)
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = own ? (*own)[k] : k;
    const Vec3 vh = P.v[i];
    const double h = half / P.density[i];
    const Vec3 v = peridigm_ ? Vec3{kernels::peridigm_kick(vh.x, P.f[i].x, P.b[i].x, P.density[i], half),
                                    kernels::peridigm_kick(vh.y, P.f[i].y, P.b[i].y, P.density[i], half),
                                    kernels::peridigm_kick(vh.z, P.f[i].z, P.b[i].z, P.density[i], half)}
                             : Vec3{kernels::second_half_kick(vh.x, P.f[i].x, P.b[i].x, h, damp),
                                    kernels::second_half_kick(vh.y, P.f[i].y, P.b[i].y, h, damp),
                                    kernels::second_half_kick(vh.z, P.f[i].z, P.b[i].z, h, damp)};
    if (damping_ > 0) {
      const double term = P.density[i] * P.volume[i] * damping_ * half *
                          (loads_.free_speed2(i, v) + loads_.free_speed2(i, v_before_[i]));
      if (grid_damped) damped_terms_[k] = term;
      else damped += term;
    }
    P.v[i] = v;
    finite = finite && std::isfinite(v.x + v.y + v.z + P.u[i].x + P.u[i].y + P.u[i].z);
  }
  if (grid_damped) {
    GridSum g(s_, 1);
    for (double t : damped_terms_) g.add(0, t);
    damped = g.totals()[0];
  }
  if (s_.decomposition) finite = !any_rank(*s_.decomposition, !finite);
  if (!finite) {
    std::size_t bad = 0;
    for (std::size_t i = 0; i < P.size(); ++i)
      if ((s_.owned.empty() || s_.decomposition->owns(i)) &&
          !std::isfinite(P.v[i].x + P.v[i].y + P.v[i].z + P.u[i].x + P.u[i].y + P.u[i].z)) {
        bad = i;
        break;
      }
    P.u = u_before_;
    P.v = v_before_;
    bodies = bodies_before;
    time_ = time_before;
    --steps_;
    throw NonFiniteState(bad, P.X[bad], steps_ + 1);
  }
  // Peridigm's prescribed components keep the second half kick (set_peridigm_verlet).
  loads_.apply_constraints(s_, time_, dt, !peridigm_);

  // The projectiles' second half kick with the new contact force. The work of the contact
  // pair (on the particles through b, on the body here) enters external_work: it is minus
  // the change of the penalty energy, and the body's kinetic energy is in the ledger's.
  double body_work = 0;
  for (std::size_t k = 0; k < bodies.size(); ++k) {
    bodies[k].kick(half);
    body_work += bodies[k].finish_step(bodies_before[k].x, bodies_before[k].force, dt, time_);
  }

  // Work of the applied force densities (trapezoidal in b) and of the constraints.
  double work = loads_.update_reactions(s_, u_before_, &v_before_, dt);
  if (has_forces_) {
    // Only the loaded particles add work; the threads find them (the others' terms are
    // zeros, which leave the serial sum's bits as they are).
    auto nonzero = [](const Vec3& a) { return a.x != 0 || a.y != 0 || a.z != 0; };
    const std::vector<uint32_t> loaded = parallel_select(n, [&](std::size_t k) {
      const std::size_t i = own ? (*own)[k] : k;
      return nonzero(P.b[i]) || nonzero(b_before_[i]);
    });
    GridSum w(s_, 1);
    for (uint32_t k : loaded) {
      const std::size_t i = own ? (*own)[k] : k;
      w.add(0, 0.5 * P.volume[i] * dot(P.b[i] + b_before_[i], P.u[i] - u_before_[i]));
    }
    work += w.totals()[0];
  }
  ledger_.external_work += work + body_work;
  ledger_.damped += damped;
  // A decomposed run sums the dissipation (a GridSum over every particle that lost a bond:
  // a collective and ~20 ns a term) only when the ledger is read, at the steps with
  // `energy` (history rows, frames, the last step); the serial sum stays every step.
  if (!s_.decomposition) ledger_.dissipated = s_.dissipated();
  if (energy) {
    ledger_.strain = strain_energy(s_);
    update_kinetic();
    // The coupling's account is brought up to date by the same force pass (fe_region.hpp).
    if (s_.fe) ledger_.coupling_work = s_.fe->coupling_work;
  }
}

}  // namespace horizon
