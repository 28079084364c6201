#include "horizon/solver/flat_copy.hpp"


#include "horizon/loading/loads.hpp"
#include "horizon/material/models/nonlinear_solid.hpp"
#include "horizon/state/model_set.hpp"

namespace horizon {

std::string flat_unsupported(const System& s, const Loads& loads) {
  // The unified models' rows, or the nonlinear solid's (a model that owns its pass and
  // shares a run with no other: material/models/nonlinear_solid.cpp).
  if (s.models.owner() ? !nonlinear_state(s) : !s.models.all_unified() && !flat_ordinary_model(s)) {
    // The correspondence model's affine pass (kernels/flat_affine.hpp), or its reason.
    const std::string why = flat_affine_model(s) ? flat_affine_unsupported(s) : "no";
    if (why == "no")
      return "a model without flat rows (the unified models, nonlinear_solid, elastic_plastic, viscoelastic, "
             "microplastic, pals and correspondence have them)";
    if (!why.empty()) return why;
  }
  if (std::string why = flat_ordinary_unsupported(s); !why.empty()) return why;
  if (s.one_way_bonds) return "bodies of different horizons (one-way bonds: the general force pass)";
  if (!loads.projectiles().empty()) return "projectiles";
  for (const AppliedLoad& L : loads.loads()) {
    if (L.indenter) return "the indenter " + L.name;
    if (L.support >= 0 || !L.share.empty()) return "the support " + L.name;
  }
  if (!s.thermal_strain.empty() || !s.critical_stretch_factor.empty()) return "temperature";
  // Short-range contact: the host's pair lists between the flat passes (FlatBackend);
  // friction reads the System's velocities, which the copy does not keep up to date.
  if (s.contact.enabled() && s.contact.config().law == ShortRangeLaw::peridigm && s.contact.config().friction > 0)
    return "short-range contact with friction (contact.short_range.friction)";
  if (s.decomposition) return "a run over several ranks";
  if (s.fe_coupling) return "finite-element regions";
  // An irregular cloud: the pmb and lps rows finish each bond from its own |xi|
  // (kernels::flat_kind); every other model reads kinds with their lengths, which
  // setup_model gives it on a cloud (solver/build.cpp kinds_need_lengths, expand_kinds),
  // as the CPU's passes read them. A System that kept bonds without kinds for such a model
  // (built in code, not by a deck) is refused rather than read with lengths of 0.
  if (s.bonds.length_per_bond && !s.models.all_unified())
    return "bonds without kinds (an irregular cloud) for a model other than pmb and lps";
  if (s.model.kind.size() != s.bonds.kinds.size()) return "no force pass yet";
  return "";
}

namespace {
std::vector<double> flat3(const std::vector<Vec3>& a) {
  std::vector<double> out(3 * a.size());
  for (std::size_t i = 0; i < a.size(); ++i) out[3 * i] = a[i].x, out[3 * i + 1] = a[i].y, out[3 * i + 2] = a[i].z;
  return out;
}
void unflat3(const std::vector<double>& a, std::vector<Vec3>& out) {
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = {a[3 * i], a[3 * i + 1], a[3 * i + 2]};
}
}  // namespace

FlatStorage flat_copy(const System& s, double dt, double damping, double external_work, const Loads* loads,
                      bool peridigm) {
  const auto& P = s.particles;
  const auto& B = s.bonds;
  const auto& M = s.model;
  FlatStorage c;
  c.n = P.size();
  c.state_based = M.state_based;
  c.break_after = M.break_after_force;
  if (B.length_per_bond) {  // an irregular cloud: each bond's own |xi| (flat_kind)
    c.length_of = B.lengths;
    c.contact_from_length = s.contact.acts_on_family();
    c.contact_fraction = c.contact_from_length ? s.contact.config().reference_fraction : 0.0;
    c.contact_cutoff = s.contact.cutoff();
  }
  c.dim = M.dim, c.dt = dt, c.damping = damping;
  c.offset = B.offset, c.nbr = B.nbr, c.kind = B.kind, c.intact = B.intact;
  c.kinds.resize(M.kind.size());
  for (std::size_t k = 0; k < M.kind.size(); ++k) {
    const KindCoefficients& kc = M.kind[k];
    c.kinds[k] = {kc.length, kc.inv_length, kc.pair, kc.contact_d2, kc.damage, kc.wv, kc.contact_d, kc.contact_k};
  }
  c.r_of = M.deformed_length;
  c.r_of.resize(B.size(), 1.0);
  c.X = flat3(P.X), c.u = flat3(P.u), c.v = flat3(P.v), c.f = flat3(P.f), c.b = flat3(P.b);
  c.density = P.density, c.volume = P.volume, c.no_fail = P.no_fail;
  c.no_fail.resize(c.n, 0);
  c.critical_stretch = M.critical_stretch, c.alpha = M.alpha, c.min_stretch = M.min_stretch;
  c.alpha.resize(c.n, 0);
  c.min_stretch.resize(c.n, 0);
  c.min_stretch_next.assign(c.n, 0);
  c.dilatation_coef = M.dilatation_coef, c.Q = M.deviatoric_coef, c.R = M.pair_coef;
  c.weighted_volume = M.weighted_volume, c.theta = M.theta, c.P = M.P;
  c.theta.resize(c.n, 0);
  c.P.resize(c.n, 0);
  c.intact_weight = M.intact_weight, c.damage_total = M.damage_total;
  c.damage = P.damage, c.energy = P.energy, c.dissipated = s.dissipated_at;
  c.energy.resize(c.n, 0);
  c.dissipated.resize(c.n, 0);
  c.y4.assign(4 * c.n, 0);
  c.broken.assign(c.n, 0);
  // The loads: each constraint's components and values per particle, the particles whose
  // work ExplicitSolver::step books (b != 0, b held fixed, or constrained), the entries of
  // Loads::update_reactions in its order.
  std::vector<uint8_t> track(c.n, 0);
  for (std::size_t i = 0; i < P.size(); ++i)
    if (P.b[i].x != 0 || P.b[i].y != 0 || P.b[i].z != 0) track[i] = 1;
  if (loads) {
    for (std::size_t l = 0; l < loads->loads().size(); ++l) {
      const AppliedLoad& L = loads->loads()[l];
      const bool velocity = L.kind == LoadKind::velocity;
      bool varies = false;
      for (const auto& e : L.value) varies = varies || (e && !e->is_constant());
      if (!velocity && L.kind != LoadKind::displacement) {
        c.has_forces = true;
        if (varies) {
          c.vary_forces = true;
          for (uint32_t i : L.particles) track[i] = 1;  // their b may be 0 now and not later
        }
        continue;
      }
      c.vary_constraints = c.vary_constraints || varies;
      if (c.fixed.empty()) c.fixed.assign(c.n, 0), c.fixed_value.assign(3 * c.n, 0);
      uint8_t mask = 0;
      for (int k = 0; k < 3; ++k)
        if (L.value[k]) mask |= static_cast<uint8_t>(1u << k);
      for (std::size_t m = 0; m < L.particles.size(); ++m) {
        const uint32_t i = L.particles[m];
        track[i] = 1;
        for (int k = 0; k < 3; ++k)
          if ((mask >> k) & 1u) {
            c.fixed[i] |= static_cast<uint8_t>(1u << (velocity ? k : 3 + k));
            c.fixed_value[3 * i + k] = (*L.value[k])(0.0);  // a constant, or set before each step
          }
        c.entry_load.push_back(static_cast<uint32_t>(l));
        c.entry_index.push_back(static_cast<uint32_t>(m));
        c.entry_slot.push_back(i);  // the particle for now; its place in `tracked` below
        c.entry_mask.push_back(mask);
        const Vec3 r = m < L.reaction_old.size() ? L.reaction_old[m] : Vec3{};
        c.entry_reaction.insert(c.entry_reaction.end(), {r.x, r.y, r.z});
      }
    }
  }
  std::vector<uint32_t> slot(c.n, 0);
  for (std::size_t i = 0; i < c.n; ++i)
    if (track[i]) slot[i] = static_cast<uint32_t>(c.tracked.size()), c.tracked.push_back(static_cast<uint32_t>(i));
  for (uint32_t& e : c.entry_slot) e = slot[e];
  c.u_before.assign(3 * c.tracked.size(), 0);
  c.v_before.assign(3 * c.tracked.size(), 0);
  c.ledger = {external_work};
  if (damping > 0) c.damped.assign(c.n, 0), c.speed2_before.assign(c.n, 0);
  if (peridigm) {
    // The displacements' increments and rates are the step's (prepare_step, every step).
    c.peridigm = true;
    c.positions.assign(3 * c.n, 0);
    if (loads)
      for (const AppliedLoad& L : loads->loads())
        if (L.kind == LoadKind::displacement && !L.particles.empty()) c.vary_constraints = true;
    if (c.vary_constraints) c.fixed_rate.assign(3 * c.n, 0);
  }
  if (c.vary_constraints) c.fixed_mid = c.fixed_value, c.fixed_v.assign(3 * c.n, 0);
  if (c.vary_forces) c.b_next = c.b, c.b_before.assign(3 * c.tracked.size(), 0);
  c.vary_critical_stretch = !s.critical_stretch_schedules.empty();
  if (const NonlinearState* N = nonlinear_state(s)) {
    c.tupek = true;
    c.tupek_exponent_two = N->failure_exponent_two;
    c.tupek_contact = s.contact.enabled();
    c.eps = N->bond_strain;
    c.eps.resize(B.size(), 0);
    c.seth_m = N->m, c.lambda_bar = N->lambda_bar, c.mu_bar = N->mu_bar, c.beta = N->beta;
    c.compression_only = N->compression_only, c.failure_scale = N->failure_scale;
    c.nonlocal_damage = N->nonlocal_damage;
    c.nonlocal_damage.resize(c.n, 0);
    c.contact_stiffness = N->contact_stiffness;
    c.contact_stiffness.resize(c.n, 0);
    c.theta = N->theta;  // theta_phi (the model arrays' theta is not the nonlinear solid's)
    c.theta.resize(c.n, 0);
    c.dim = N->dimension;
  }
  c.ordinary = flat_ordinary_copy(s, dt);  // (null but for elastic_plastic, viscoelastic, microplastic, pals)
  if (flat_affine_model(s)) c.affine = flat_affine_copy(s);
  return c;
}

kernels::FlatSystem FlatStorage::view() {
  kernels::FlatSystem s;
  s.n = n, s.nb = nbr.size(), s.nkinds = kinds.size(), s.state_based = state_based, s.dim = dim, s.dt = dt, s.damping = damping;
  s.break_after = break_after;
  s.length_of = length_of.empty() ? nullptr : length_of.data();
  s.contact_from_length = contact_from_length, s.contact_fraction = contact_fraction, s.contact_cutoff = contact_cutoff;
  s.offset = offset.data(), s.nbr = nbr.data(), s.kind = kind.data(), s.intact = intact.data();
  s.kinds = kinds.data(), s.r_of = r_of.data();
  s.X = X.data(), s.u = u.data(), s.v = v.data(), s.f = f.data(), s.b = b.data();
  s.density = density.data(), s.volume = volume.data(), s.critical_stretch = critical_stretch.data();
  s.alpha = alpha.data(), s.no_fail = no_fail.data(), s.min_stretch = min_stretch.data();
  s.min_stretch_next = min_stretch_next.data(), s.dilatation_coef = dilatation_coef.data(), s.Q = Q.data();
  s.R = R.data(), s.weighted_volume = weighted_volume.data(), s.theta = theta.data(), s.P = P.data();
  s.intact_weight = intact_weight.data(), s.damage_total = damage_total.data(), s.damage = damage.data();
  s.energy = energy.data(), s.dissipated = dissipated.data(), s.y4 = y4.data(), s.broken = broken.data();
  s.fixed = fixed.empty() ? nullptr : fixed.data(), s.fixed_value = fixed_value.empty() ? nullptr : fixed_value.data();
  s.ntracked = tracked.size(), s.tracked = tracked.data(), s.u_before = u_before.data(), s.v_before = v_before.data();
  s.has_forces = has_forces, s.nentries = entry_slot.size(), s.entry_slot = entry_slot.data();
  s.entry_mask = entry_mask.data(), s.entry_reaction = entry_reaction.data(), s.ledger = ledger.data();
  s.damped = damped.empty() ? nullptr : damped.data(), s.speed2_before = speed2_before.data();
  auto or_null = [](std::vector<double>& a) { return a.empty() ? nullptr : a.data(); };
  s.fixed_mid = or_null(fixed_mid), s.fixed_v = or_null(fixed_v), s.b_next = or_null(b_next);
  s.b_before = or_null(b_before);
  s.peridigm = peridigm, s.positions = or_null(positions), s.fixed_rate = or_null(fixed_rate);
  s.nonfinite = nonfinite.data();
  s.tupek = tupek, s.tupek_exponent_two = tupek_exponent_two, s.tupek_contact = tupek_contact;
  s.eps = or_null(eps), s.seth_m = or_null(seth_m), s.lambda_bar = or_null(lambda_bar), s.mu_bar = or_null(mu_bar);
  s.beta = or_null(beta), s.failure_scale = or_null(failure_scale), s.nonlocal_damage = or_null(nonlocal_damage);
  s.contact_stiffness = or_null(contact_stiffness);
  s.critical_stretch_varies = vary_critical_stretch;
  s.compression_only = compression_only.empty() ? nullptr : compression_only.data();
  s.ordinary = ordinary ? &ordinary->view : nullptr;
  s.correspondence = affine.on;
  if (affine.on) s.affine = affine.view();
  return s;
}

void flat_write_back(const FlatStorage& c, System& s, bool energy) {
  auto& P = s.particles;
  unflat3(c.u, P.u);
  unflat3(c.v, P.v);
  unflat3(c.f, P.f);
  if (c.peridigm) {  // the positions of the last pass (System::positions)
    s.positions.resize(P.size());
    unflat3(c.positions, s.positions);
  }
  P.damage = c.damage;
  if (energy) P.energy = c.energy;
  s.bonds.intact = c.intact;
  s.dissipated_at = c.dissipated;
  s.model.intact_weight = c.intact_weight;
  flat_affine_write_back(c.affine, s);  // the correspondence model's state (when it is the run's)
  if (NonlinearState* N = c.tupek ? nonlinear_state(s) : nullptr) {
    // What NonlinearSolid::force_pass leaves in its state (the model arrays' theta, P and
    // smallest stretches are not its own: left as they are).
    N->theta = c.theta;
    N->bond_strain = c.eps;
    N->nonlocal_damage = c.nonlocal_damage;
    return;
  }
  if (c.ordinary) flat_ordinary_write_back(*c.ordinary, s);
  s.model.min_stretch = c.min_stretch;
  if (c.vary_critical_stretch) s.model.critical_stretch = c.critical_stretch;  // s0 at the last step's time
  s.model.theta = c.theta;
  s.model.P = c.P;
}

}  // namespace horizon

namespace horizon {

void flat_write_reactions(const FlatStorage& c, Loads& loads) {
  auto& all = loads.loads();
  std::vector<Vec3> sum(all.size());
  std::vector<uint8_t> constraint(all.size(), 0);
  for (std::size_t e = 0; e < c.entry_slot.size(); ++e) {
    const uint32_t l = c.entry_load[e], m = c.entry_slot[e], i = c.tracked[m];
    AppliedLoad& L = all[l];
    Vec3 r{c.entry_reaction[3 * e], c.entry_reaction[3 * e + 1], c.entry_reaction[3 * e + 2]};
    if (c.entry_index[e] < L.reaction_old.size()) L.reaction_old[c.entry_index[e]] = r;
    // The inertial part, as Loads::update_reactions adds it after keeping reaction_old.
    const double mass = 1.0 * c.density[i] * c.volume[i];
    for (int k = 0; k < 3; ++k)
      if ((c.entry_mask[e] >> k) & 1u) r[k] += mass * (c.v[3 * i + k] - c.v_before[3 * m + k]) / c.dt;
    sum[l] += r;
    constraint[l] = 1;
  }
  for (std::size_t l = 0; l < all.size(); ++l)
    if (constraint[l]) all[l].reaction = sum[l];
  // Force loads that vary: their applied force now, sum b V (Loads::update_reactions).
  if (c.b_next.empty()) return;
  for (AppliedLoad& L : all) {
    if (L.indenter || L.kind == LoadKind::displacement || L.kind == LoadKind::velocity) continue;
    Vec3 r;
    for (uint32_t i : L.particles) r += Vec3{c.b[3 * i], c.b[3 * i + 1], c.b[3 * i + 2]} * c.volume[i];
    L.reaction = r;
  }
}

}  // namespace horizon
