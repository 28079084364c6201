#include "horizon/solver/flat_backend.hpp"

#include <algorithm>
#include <cmath>

#include "horizon/loading/loads.hpp"

namespace horizon {

std::string flat_backend_refusal(const System& s, const Loads& loads, double damping) {
  (void)damping;  // booked per particle (kernels::kick_row)
  return flat_unsupported(s, loads);
}

namespace {
uint64_t intact_bonds(const FlatStorage& c) {
  uint64_t n = 0;
  for (uint8_t f : c.intact) n += f != 0;
  return n;
}
}  // namespace

FlatBackend::FlatBackend(System& s, Loads& loads, ExplicitSolver& solver)
    : s_(s), loads_(loads), solver_(solver), system_steps_(solver.steps()) {
  copy_from_system();
  host_step_ = storage_.ordinary && !flat_ordinary_ready(s_);
}

void FlatBackend::run_steps(int64_t n) {
  if (!adaptive_) {
    take_steps(n);
    storage_steps_ += n;
    return;
  }
  for (int64_t k = 0; k < n; ++k) {  // each step with its own dt
    set_step(step_dt_[static_cast<std::size_t>(storage_steps_ - system_steps_)]);
    take_steps(1);
    ++storage_steps_;
  }
}

void FlatBackend::set_step(double dt) {
  if (view_.dt == dt) return;
  storage_.dt = view_.dt = dt;
  step_changed();
}

bool FlatBackend::stable_time_step(double& dt) {
  if (!storage_.tupek) {  // the System's state, for the models' own stable step
    copy_fields();
    return false;
  }
  if (!fetched_) fetch(), fetched_ = true;
  stable_S_.resize(storage_.n);
  dt = kernels::flat_tupek_stable_step(view_, stable_S_.data());
  return true;
}

void FlatBackend::take_steps(int64_t n) {
  const bool contact = s_.contact.enabled();
  if (varies())
    kernels::advance_flat(
        view_, n, [this, contact] { if (contact) contact_pass(); }, [this](int64_t k) { prepare_step(k); });
  else if (contact)
    kernels::advance_flat(view_, n, [this] { contact_pass(); });
  else
    kernels::advance_flat(view_, n);
}

void FlatBackend::prepare_step(int64_t k) {
  double dt = solver_.dt();
  const int64_t step = storage_steps_ + k;  // steps taken before this one
  double t0 = static_cast<double>(step) * dt, t1 = static_cast<double>(step + 1) * dt;  // t = n dt
  if (adaptive_) {  // the time a sum of steps (ExplicitSolver::step): t1 = t0 + dt
    const auto m = static_cast<std::size_t>(step - system_steps_);
    dt = step_dt_[m], t0 = step_t0_[m], t1 = t0 + dt;
  }
  const double half = 0.5 * dt;
  const auto& P = s_.particles;
  if (storage_.vary_constraints)
    for (const AppliedLoad& L : loads_.loads()) {
      const bool velocity = L.kind == LoadKind::velocity;
      if (!velocity && L.kind != LoadKind::displacement) continue;
      for (uint32_t i : L.particles) {
        const Vec3& x = P.X[i];
        for (int c = 0; c < 3; ++c) {
          if (!L.value[c]) continue;
          const Expression& g = *L.value[c];
          const std::size_t q = 3 * static_cast<std::size_t>(i) + static_cast<std::size_t>(c);
          if (velocity) {
            storage_.fixed_mid[q] = g(t0 + half, x.x, x.y, x.z);
            storage_.fixed_value[q] = g(t1, x.x, x.y, x.z);
          } else if (storage_.peridigm) {  // Loads::prescribe_increments(s, t1, t0)
            const double now = g(t1, x.x, x.y, x.z);
            storage_.fixed_v[q] = now - g(t0, x.x, x.y, x.z);
            storage_.fixed_rate[q] = 1.0 / (t1 - t0);
            storage_.fixed_value[q] = now;
          } else {
            const double now = g(t1, x.x, x.y, x.z);
            storage_.fixed_v[q] = dt > 0 ? (now - g(t1 - dt, x.x, x.y, x.z)) / dt : 0.0;
            storage_.fixed_value[q] = now;
          }
        }
      }
    }
  for (const auto& c : s_.critical_stretch_schedules) {  // ExplicitSolver::step, at the new time
    const double s0 = c.s0(t1);
    for (uint32_t i : c.particles) storage_.critical_stretch[i] = s0;
  }
  if (storage_.vary_forces) {
    loads_.apply_forces(s_, t1);  // the System's b: the same sums as the CPU's
    for (std::size_t i = 0; i < P.size(); ++i)
      storage_.b_next[3 * i] = P.b[i].x, storage_.b_next[3 * i + 1] = P.b[i].y, storage_.b_next[3 * i + 2] = P.b[i].z;
  }
}

void FlatBackend::contact_pass() {
  const uint64_t n = view_.n;
  contact_y_.resize(n);
  contact_f_.resize(n);
  for (uint64_t i = 0; i < n; ++i) {
    const double* y = view_.y4 + 4 * i;
    contact_y_[i] = {y[0], y[1], y[2], y[3]};
    contact_f_[i] = {view_.f[3 * i], view_.f[3 * i + 1], view_.f[3 * i + 2]};
  }
  // The energy of every pass (the flat rows compute it in every pass; the System takes it
  // only from the passes the CPU backend would have computed it in).
  s_.contact.add_forces(s_, contact_y_.data(), contact_f_.data(), view_.energy);
  for (uint64_t i = 0; i < n; ++i)
    view_.f[3 * i] = contact_f_[i].x, view_.f[3 * i + 1] = contact_f_[i].y, view_.f[3 * i + 2] = contact_f_[i].z;
}

void FlatBackend::copy_from_system() {
  // Force densities that vary: the System's b is the last prepared step's; the copy starts
  // from the b of the System's state (the last copy_fields).
  if (!b_at_copy_.empty()) s_.particles.b = b_at_copy_;
  storage_steps_ = copied_at_ = system_steps_;
  storage_ = flat_copy(s_, solver_.dt(), solver_.damping(), solver_.ledger().external_work, &loads_,
                       solver_.peridigm_verlet());
  view_ = storage_.view();
  intact_at_copy_ = intact_bonds(storage_);
  broken_at_copy_ = s_.broken;
  damped_at_copy_ = solver_.ledger().damped;
  if (storage_.vary_forces) b_at_copy_ = s_.particles.b;
}

int64_t FlatBackend::first_non_finite() const {
  const std::vector<double>& u = storage_.u;
  const std::vector<double>& v = storage_.v;
  for (std::size_t i = 0; i < storage_.n; ++i)
    if (!std::isfinite(v[3 * i] + v[3 * i + 1] + v[3 * i + 2] + u[3 * i] + u[3 * i + 1] + u[3 * i + 2]))
      return static_cast<int64_t>(i);
  return -1;
}

void FlatBackend::advance(int64_t n, bool energy) {
  if (host_step_ && n > 0) {  // an ordinary model's ledger in its arrays (a restart): one CPU step
    host_step_ = false;
    failed_ = true;  // (a step that throws leaves the System as the CPU leaves it)
    solver_.step(energy && n == 1);
    failed_ = false;
    system_steps_ = solver_.steps();
    if (storage_.vary_forces) b_at_copy_ = s_.particles.b;
    copy_from_system();
    upload();
    energy_ = energy && n == 1;
    if (--n == 0) return;
  }
  if (!solver_.fixed_step()) {  // the adaptive step: this call's steps with the solver's dt
    adaptive_ = true;
    double t = solver_.time();
    for (int64_t k = 0; k < n; ++k) {
      step_dt_.push_back(solver_.dt());
      step_t0_.push_back(t);
      t = t + solver_.dt();
    }
  }
  run_steps(n);
  fetched_ = false;  // the fields come back at copy_fields, when a frame or a row wants them
  if (!went_non_finite()) {
    solver_.advance_clock(n);
    energy_ = energy;
    return;
  }
  // Again from the System's state (the last copy_fields, perhaps some calls back), one step
  // at a time, to find the step that failed.
  const int64_t total = solver_.steps() + n - system_steps_;
  copy_from_system();
  upload();
  int64_t good = 0, bad = -1;
  for (; good < total; ++good) {
    run_steps(1);
    fetch();
    if ((bad = first_non_finite()) >= 0) break;
  }
  copy_from_system();
  upload();
  if (good > 0) run_steps(good);
  solver_.advance_clock(system_steps_ + good - solver_.steps());
  energy_ = false;
  fetched_ = false;
  copy_fields();
  if (bad < 0) {  // not again (the rows are deterministic): carry on
    run_steps(total - good);
    fetched_ = false;
    solver_.advance_clock(total - good);
    energy_ = energy;
    return;
  }
  // The failing step once more: ExplicitSolver::step restores u, v and its clock alone, so
  // the failing step's force pass stays in the System (f, damage, the intact flags, the
  // dissipation, the energy of a step with `energy`, s.time) and its ledger does not move.
  const std::vector<Vec3> u = s_.particles.u, v = s_.particles.v;
  run_steps(1);
  fetch();
  write_state(good + 1 == total && energy);
  s_.particles.u = u;
  s_.particles.v = v;
  s_.time = adaptive_ ? solver_.time() + solver_.dt() : static_cast<double>(solver_.steps() + 1) * solver_.dt();
  failed_ = true;  // copy_fields leaves the System as it is now
  const auto i = static_cast<std::size_t>(bad);
  throw NonFiniteState(i, s_.particles.X[i], solver_.steps() + 1);
}

void FlatBackend::write_state(bool energy) {
  flat_write_back(storage_, s_, energy);
  s_.broken = broken_at_copy_ + (intact_at_copy_ - intact_bonds(storage_));
}

void FlatBackend::copy_fields() {
  if (failed_) return;
  if (!fetched_) fetch(), fetched_ = true;
  write_state(energy_);
  if (adaptive_) {  // the System's state is storage_'s now: the logs start again
    const auto m = std::min(static_cast<std::ptrdiff_t>(storage_steps_ - system_steps_),
                            static_cast<std::ptrdiff_t>(step_dt_.size()));
    step_dt_.erase(step_dt_.begin(), step_dt_.begin() + m);
    step_t0_.erase(step_t0_.begin(), step_t0_.begin() + m);
  }
  system_steps_ = storage_steps_;
  if (storage_.vary_forces) b_at_copy_ = s_.particles.b;
  s_.time = solver_.time();
  s_.dt = solver_.dt();
  // The ledger as ExplicitSolver::step leaves it: the work and the dissipation of every
  // step, the stored and kinetic energies of the last step that computed them.
  Ledger& g = solver_.ledger();
  g.external_work = storage_.ledger[0];
  // The reactions of the copy's last step (none taken since the copy: the System's own,
  // e.g. after the CPU's first step of a restart).
  if (storage_steps_ != copied_at_) flat_write_reactions(storage_, loads_);
  g.dissipated = s_.dissipated();
  // The damped energy: per particle over the steps, then in index order (thread- and
  // device-independent; ExplicitSolver::step sums each step's terms first, so the last
  // bits may differ from the CPU backend's).
  if (!storage_.damped.empty()) {
    double d = 0;
    for (double t : storage_.damped) d += t;
    g.damped = damped_at_copy_ + d;
  }
  if (energy_) {
    g.strain = strain_energy(s_);
    solver_.update_kinetic();
  }
}

}  // namespace horizon
