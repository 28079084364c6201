#include "horizon/solver/static_driver.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "horizon/parallel/decomposition.hpp"
#include "horizon/solver/forces.hpp"
#include "horizon/thermal/heat.hpp"

namespace horizon {

bool uses_time(const Expression& e) {
  if (e.is_constant()) return false;
  const std::string& s = e.text();
  auto word = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
  for (std::size_t i = 0; i < s.size(); ++i)
    if (s[i] == 't' && (i == 0 || !word(s[i - 1])) && (i + 1 == s.size() || !word(s[i + 1]))) return true;
  return false;
}

void apply_static_loads(const Loads& loads, System& s, double t_previous, double t, double lambda) {
  auto& P = s.particles;
  std::fill(P.b.begin(), P.b.end(), Vec3{});
  const double mid = 0.5 * (t_previous + t);
  for (const auto& L : loads.loads()) {
    for (int c = 0; c < 3; ++c) {
      if (!L.value[c]) continue;
      const Expression& g = *L.value[c];
      const double factor = uses_time(g) ? 1.0 : lambda;
      for (uint32_t i : L.particles) {
        const Vec3& x = P.X[i];
        switch (L.kind) {
          case LoadKind::displacement:
            P.u[i][c] = factor * g(t, x.x, x.y, x.z);
            P.v[i][c] = 0;
            break;
          case LoadKind::velocity:
            P.u[i][c] += g(mid, x.x, x.y, x.z) * (t - t_previous);
            P.v[i][c] = 0;
            break;
          case LoadKind::traction:
          case LoadKind::body_force:
          case LoadKind::force:
          case LoadKind::pressure:
            P.b[i][c] += L.scale * factor * g(t, x.x, x.y, x.z);
            break;
        }
      }
    }
  }
}

StaticSolver::StaticSolver(System& s, Loads& loads, const SolverConfig& config)
    : s_(s),
      loads_(loads),
      config_(config),
      dofs_(make_dof_map(s, loads)),
      linear_(config.linear_solver),
      end_time_(config.end_time > 0 ? config.end_time : 1.0),
      step_(1.0 / std::max(1, config.load_steps)) {
  if (config.load_times.size() >= 2) {
    // Listed pseudo-times from 0: lambda_k = t_k / t_N (lambda_N = 1 exactly).
    times_ = config.load_times;
    end_time_ = times_.back();
    for (double t : times_) levels_.push_back(t / end_time_);
  } else {
    // Equal steps: lambda_k = k / N (as min(1, k step_)), t_k = k (end_time / N).
    const int n = std::max(1, config.load_steps);
    for (int k = 0; k <= n; ++k) {
      levels_.push_back(std::min(1.0, k * step_));
      times_.push_back(k * (end_time_ / n));
    }
  }
}

int64_t StaticSolver::step_below(double lambda) const {
  const auto n = static_cast<int64_t>(levels_.size()) - 1;
  int64_t k = std::upper_bound(levels_.begin(), levels_.end(), lambda) - levels_.begin() - 1;
  k = std::clamp<int64_t>(k, 0, n);
  if (k < n && levels_[k + 1] - lambda < 1e-9 * (levels_[k + 1] - levels_[k])) ++k;
  return k;
}

int64_t StaticSolver::step_at(double lambda) const {
  const auto n = static_cast<int64_t>(levels_.size()) - 1;
  if (config_.load_times.size() < 2) {
    // Equal steps: as Peridigm counts them (k = round(lambda N)).
    const double k = std::round(lambda / step_);
    return std::abs(lambda / step_ - k) < 1e-9 && k >= 0 && k <= n ? static_cast<int64_t>(k) : -1;
  }
  const int64_t k = step_below(lambda);
  const double gap = levels_[std::min(k + 1, n)] - levels_[std::max<int64_t>(k, 1) - 1];
  return std::abs(lambda - levels_[k]) < 1e-9 * gap ? k : -1;
}

double StaticSolver::time_at(double lambda) const {
  const int64_t k = step_at(lambda);
  if (k >= 0) return times_[k];
  return lambda * end_time_;
}

int64_t StaticSolver::load_step_at_time(double t) const {
  for (std::size_t k = 0; k < times_.size(); ++k)
    if (std::abs(times_[k] - t) <= 1e-12 * end_time_) return static_cast<int64_t>(k);
  return -1;
}

int64_t StaticSolver::load_step() const {
  const int64_t k = step_at(lambda_);
  return k > 0 ? k : -1;
}

void StaticSolver::initialize() {
  auto& P = s_.particles;
  std::fill(P.v.begin(), P.v.end(), Vec3{});
  apply_static_loads(loads_, s_, 0, 0, 0);
  {
    FixedBonds fixed(s_);
    s_.time = 0;
    s_.dt = 0;
    equilibrium_forces(s_, true);
  }
  commit_history(s_);
  loads_.update_reactions(s_, P.u);
  ledger_.strain = strain_energy(s_);
  ledger_.dissipated = s_.dissipated();
  ledger_.initial = ledger_.strain;
}

namespace {
// Work of the applied force densities over u0 -> u1 (trapezoidal in b).
// Split over ranks: the owned particles' terms, a GridSum total (parallel/decomposition.hpp).
double dead_load_work(const System& s, const std::vector<Vec3>& b0, const std::vector<Vec3>& u0) {
  const Particles& P = s.particles;
  if (s.decomposition) {
    GridSum g(s, 1);
    for (uint32_t i : s.owned) g.add(0, 0.5 * P.volume[i] * dot(P.b[i] + b0[i], P.u[i] - u0[i]));
    return g.totals()[0];
  }
  double w = 0;
  for (std::size_t i = 0; i < P.size(); ++i) w += 0.5 * P.volume[i] * dot(P.b[i] + b0[i], P.u[i] - u0[i]);
  return w;
}
double current_strain_energy(System& s) {
  FixedBonds fixed(s);
  equilibrium_forces(s, true);
  return strain_energy(s);
}
// What the history models would add to the ledger at a commit now (material/model.hpp).
double pending_dissipation(const System& s) {
  double sum = 0;
  for (const auto& m : s.models) sum += m->pending_dissipation(s);
  return sum;
}
}  // namespace

bool StaticSolver::solve_increment(double lambda, const std::vector<Vec3>& u_before,
                                   const std::vector<Vec3>& b_before) {
  auto& P = s_.particles;
  last_break_rounds_ = 0;
  last_iterations_ = 0;
  last_linear_iterations_ = 0;
  pending_work_ = 0;
  pending_released_ = 0;
  double U = 0, D = 0;
  std::vector<Vec3> u_prev;
  for (int round = 0;; ++round) {
    if (config_.method == StaticMethod::newton) {
      NewtonOptions o;
      o.linear_solver = config_.linear_solver;
      o.tangent = config_.tangent;
      o.tolerance = config_.tolerance;
      o.max_iterations = config_.max_iterations.value_or(30);
      last_ = newton_solve(s_, dofs_, o, linear_);
    } else {
      AdrOptions o;
      o.tolerance = config_.tolerance;
      o.max_iterations = config_.max_iterations.value_or(100000);
      last_ = adr_solve(s_, dofs_, o);
    }
    last_iterations_ += last_.iterations;
    last_linear_iterations_ += last_.linear_iterations;
    total_iterations_ += last_.iterations;
    total_linear_iterations_ += last_.linear_iterations;
    tangent_seconds_ += last_.tangent_seconds;
    solve_seconds_ += last_.solve_seconds;
    tangent_bytes_ = std::max(tangent_bytes_, last_.tangent_bytes);
    tangent_nonzeros_ = std::max(tangent_nonzeros_, last_.tangent_nonzeros);
    factor_fill_ = std::max(factor_fill_, last_.factor_fill);
    if (!last_.converged) {
      failure_ = "load factor " + std::to_string(lambda) + ": " + last_.failure;
      return false;
    }
    const double U_new = current_strain_energy(s_);
    const double D_new = pending_dissipation(s_);
    if (round == 0) {
      // The loading path of the increment, elastic up to its end: the work of the
      // constraints (trapezoidal in the reactions) and of the applied force densities.
      pending_work_ = loads_.update_reactions(s_, u_before) + dead_load_work(s_, b_before, u_before);
    } else {
      // Re-equilibration at fixed load after bonds broke: the constraints do not move;
      // the force densities work on the relaxation. The strain energy it releases beyond
      // what the broken bonds held is lost to the quasi-static idealisation (in the
      // experiment it becomes kinetic energy and then heat): the ledger's damped energy.
      const double w = dead_load_work(s_, P.b, u_prev) + loads_.update_reactions(s_, u_prev);
      pending_work_ += w;
      // A history model's plastic or viscous work in this re-settling is its own to
      // dissipate at the commit: not released energy as well.
      pending_released_ += U - U_new + w - (D_new - D);
    }
    U = U_new;
    D = D_new;
    if (round == config_.max_break_rounds) return true;  // what is still overstretched breaks at the next load
    // Quasi-static bond breaking: break what the equilibrium overstretches, re-solve.
    u_prev = P.u;
    const double D0 = s_.dissipated();
    if (!equilibrium_forces(s_, false)) return true;
    U -= s_.dissipated() - D0;  // the broken bonds' energy went to the dissipated energy
    last_break_rounds_ = round + 1;
  }
}

bool StaticSolver::advance() {
  auto& P = s_.particles;
  if (done()) return false;
  // The next nominal load step, and the increment towards it: that step's length, or
  // twice the last converged increment after cuts.
  const int64_t next = std::min<int64_t>(step_below(lambda_) + 1, static_cast<int64_t>(levels_.size()) - 1);
  const double target = levels_[next];
  const bool listed = config_.load_times.size() >= 2;
  const double nominal = listed ? levels_[next] - levels_[next - 1] : step_;
  // Listed steps differ in length: the last increment bounds this one only after a cut.
  const bool regrow = last_increment_ > 0 && (!listed || last_cut_);
  double increment = std::min(regrow ? 2 * last_increment_ : nominal, nominal);
  int cuts = 0;
  const std::vector<Vec3> u_before = P.u, b_before = P.b;
  // Peridigm's quasi-static positions: this step's forces read (X + u_n) + (u - u_n).
  if (config_.peridigm_positions) s_.step_start_u = u_before;
  const std::vector<uint8_t> intact_before = s_.bonds.intact;
  const std::vector<double> dissipated_before = s_.dissipated_at;
  const uint64_t broken_before = s_.broken;
  const std::vector<AppliedLoad> loads_before = loads_.loads();
  // A prescribed temperature field (thermal.conduction: false) takes its value at each
  // increment's time; the thermal work of its strain change is booked by the trapezoidal
  // rule over the force states of the two equilibria (thermal/heat.hpp thermal_strain_work).
  const bool temperature = s_.heat.active();
  const std::vector<double> strain_before = s_.thermal_strain;
  std::vector<Vec3> state_before;
  std::vector<double> scalar_before;
  if (temperature && s_.heat.expands) state_before = s_.model.force_state, scalar_before = s_.model.force_scalar;
  while (true) {
    double lambda = std::min(target, lambda_ + increment);
    // Listed steps: an increment that reaches its step ends on it (no round-off short of it).
    if (config_.load_times.size() >= 2 && target - lambda < 1e-9 * nominal) lambda = target;
    apply_static_loads(loads_, s_, time(), time_at(lambda), lambda);
    if (temperature) set_temperature_field(s_, time_at(lambda));
    s_.time = time_at(lambda);  // history models integrate over the pseudo-time step
    s_.dt = time_at(lambda) - time();
    if (solve_increment(lambda, u_before, b_before) && finite_state(s_)) {
      last_increment_ = lambda - lambda_;
      last_cut_ = cuts > 0 || lambda != target;
      lambda_ = std::abs(lambda - 1.0) < 1e-12 ? 1.0 : lambda;
      break;
    }
    // Restore the last converged state and halve the increment.
    P.u = u_before;
    P.b = b_before;
    s_.bonds.intact = intact_before;
    s_.dissipated_at = dissipated_before;
    s_.broken = broken_before;
    loads_.loads() = loads_before;
    if (temperature) set_temperature_field(s_, time());
    if (cuts == config_.max_step_cuts) {
      current_strain_energy(s_);
      failure_ += " (after " + std::to_string(cuts) + " step cuts)";
      return false;
    }
    ++cuts;
    ++total_cuts_;
    increment *= 0.5;
  }
  ++steps_;
  failure_.clear();
  if (temperature && s_.heat.expands) {
    // The energy scale of the thermal load (Ledger::thermal_scale): the body held at u = 0.
    const std::vector<Vec3> u = P.u;
    std::fill(P.u.begin(), P.u.end(), Vec3{});
    ledger_.thermal_scale = std::max(ledger_.thermal_scale, current_strain_energy(s_));
    P.u = u;
  }
  current_strain_energy(s_);  // the trial history of the converged state ...
  commit_history(s_);         // ... becomes the history (material/model.hpp)
  if (temperature && s_.heat.expands && strain_before.size() == s_.thermal_strain.size()) {
    std::vector<double> delta(strain_before.size());
    for (std::size_t i = 0; i < delta.size(); ++i) delta[i] = s_.thermal_strain[i] - strain_before[i];
    const double after = thermal_strain_work(s_, delta);
    std::swap(state_before, s_.model.force_state);
    std::swap(scalar_before, s_.model.force_scalar);
    const double before = thermal_strain_work(s_, delta);
    std::swap(state_before, s_.model.force_state);
    std::swap(scalar_before, s_.model.force_scalar);
    ledger_.thermal_work += 0.5 * (before + after);
  }
  ledger_.external_work += pending_work_;
  ledger_.damped += pending_released_;
  ledger_.strain = strain_energy(s_);
  ledger_.dissipated = s_.dissipated();
  return true;
}

}  // namespace horizon
