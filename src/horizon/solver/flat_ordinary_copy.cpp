#include "horizon/solver/flat_ordinary_copy.hpp"

#include <algorithm>

#include "horizon/family/bond_helpers.hpp"
#include "horizon/state/model_set.hpp"
#include "horizon/material/models/ordinary_flat.hpp"
#include "horizon/material/models/viscoelastic.hpp"
#include "horizon/material/constants.hpp"

namespace horizon {

namespace {
OrdinaryModelState state_of(const System& s) {
  for (std::size_t m = 0; m < s.models.size(); ++m) {
    OrdinaryModelState o = ordinary_model_state(const_cast<Model&>(s.models[m]));
    if (o.kind != OrdinaryModelState::none) return o;
  }
  return {};
}
}  // namespace

bool flat_ordinary_model(const System& s) { return state_of(s).kind != OrdinaryModelState::none; }

std::string flat_ordinary_unsupported(const System& s) {
  const OrdinaryModelState o = state_of(s);
  if (o.kind == OrdinaryModelState::none) return "";
  const char* name = o.kind == OrdinaryModelState::elastic_plastic ? "elastic_plastic"
                     : o.kind == OrdinaryModelState::viscoelastic  ? "viscoelastic"
                     : o.kind == OrdinaryModelState::microplastic  ? "microplastic"
                                                                   : "pals";
  if (s.models.size() != 1)
    return std::string("model ") + name + " with other materials (the flat rows take one material of elastic_plastic, "
           "viscoelastic, microplastic or pals)";
  return "";
}

bool flat_ordinary_ready(const System& s) {
  const OrdinaryModelState o = state_of(s);
  if (o.kind == OrdinaryModelState::none) return true;
  if (!o.ledger)  // pals: no ledger; the last pass a pass of the lanes (its |Y| and q kept)
    return s.model.plain_scalar_pass == s.model.passes && s.model.deformed_length.size() == s.bonds.size() &&
           s.model.force_scalar.size() == s.bonds.size();
  const HistoryLedger& L = *o.ledger;
  return !L.fresh && !L.in_place && !L.zero_committed && L.committed_plain && L.committed_pass == s.model.passes &&
         s.model.deformed_length.size() == s.bonds.size() && s.model.force_scalar.size() == s.bonds.size();
}

std::shared_ptr<FlatOrdinaryStorage> flat_ordinary_copy(const System& s, double dt) {
  const OrdinaryModelState o = state_of(s);
  if (o.kind == OrdinaryModelState::none) return nullptr;
  const auto& B = s.bonds;
  const auto& M = s.model;
  const std::size_t nb = B.size();
  auto c = std::make_shared<FlatOrdinaryStorage>();
  kernels::FlatOrdinary& v = c->view;
  v.model = static_cast<int>(o.kind);  // (1, 2, 3: FlatOrdinary::model)
  v.dim = o.dim;
  v.contact = s.contact.acts_on_family();
  v.dev_factor = lps_deviatoric_factor(o.dim);
  v.mu = o.mu;
  for (const BondKind& bk : B.kinds) c->omega.push_back(bk.weight), c->vj.push_back(bk.volume * bk.fraction);
  c->r[0] = M.deformed_length, c->q[0] = M.force_scalar;  // (the last pass's copy: current = 0)
  c->r[0].resize(nb, 1.0), c->q[0].resize(nb, 0.0);
  c->r[1].assign(nb, 0.0), c->q[1].assign(nb, 0.0);
  c->rev = reverse_bonds(B, false);
  if (o.ledger) {
    const HistoryLedger& L = *o.ledger;
    c->booked.assign(L.booked.committed(), L.booked.committed() + L.booked.size());
    c->pending_set = L.pending_set, c->pending_amount = L.pending_amount;
    c->stored = L.stored;
  }
  if (o.kind == OrdinaryModelState::elastic_plastic) {
    v.bulk = o.bulk, v.yield = o.yield, v.hardening = o.hardening, v.yield_volume = o.yield_volume;
    v.plastic = o.plastic;
    c->ep.assign(o.ep->committed(), o.ep->committed() + o.ep->size());
    c->eps_p = *o.eps_p, c->lambda = *o.lambda, c->theta = *o.theta, c->shear_factor = *o.shear_factor;
    c->flowed = *o.flowed, c->yielded = *o.yielded;
  } else if (o.kind == OrdinaryModelState::microplastic) {
    v.micro_c = o.micro_c, v.yield_stretch = o.yield_stretch;
    c->sbar.assign(o.sbar->committed(), o.sbar->committed() + o.sbar->size());
  } else if (o.kind == OrdinaryModelState::pals) {
    v.kappa = o.kappa;
    for (const BondKind& bk : B.kinds) c->pals_kinds.push_back({bk.length, bk.volume, bk.fraction});
    c->sigma = *o.sigma, c->tau = *o.pals_tau, c->theta = *o.theta;
  } else {
    v.bulk_elastic = o.bulk_elastic, v.dilatation_shear = o.dilatation_shear, v.lambda_inf = o.lambda_inf;
    v.branches = o.branches;
    for (int b = 0; b < o.branches; ++b) {
      const SlsStep st = sls_step(dt, o.tau[b]);  // (Viscoelastic::begin_rows: the pass's dt)
      v.branch_lambda[b] = o.branch_lambda[b], v.decay[b] = st.decay, v.from_old[b] = st.from_old;
      v.from_new[b] = st.from_new;
      c->back[b].assign(o.back[b]->committed(), o.back[b]->committed() + o.back[b]->size());
      if (o.dilatation_shear != 0) c->theta_back[b] = *o.theta_back[b];
    }
    c->theta = *o.theta_row, c->dissipated_density = *o.dissipated;
    if (o.dilatation_shear != 0) c->theta_strain = *o.theta_strain;
  }
  c->point();
  return c;
}

void FlatOrdinaryStorage::point() {
  kernels::FlatOrdinary& v = view;
  auto p = [](auto& a) { return a.empty() ? nullptr : a.data(); };
  v.omega = p(omega), v.vj = p(vj), v.rev = p(rev), v.current = p(current);
  for (int b = 0; b < 2; ++b) v.r[b] = p(r[b]), v.q[b] = p(q[b]);
  v.booked = p(booked), v.pending_set = p(pending_set), v.pending_amount = p(pending_amount);
  v.stored = p(stored), v.theta = p(theta), v.ep = p(ep), v.eps_p = p(eps_p), v.lambda = p(lambda);
  v.shear_factor = p(shear_factor), v.flowed = p(flowed), v.yielded = p(yielded);
  v.dissipated_density = p(dissipated_density), v.theta_strain = p(theta_strain);
  for (int b = 0; b < kernels::kFlatBranches; ++b) v.back[b] = p(back[b]), v.theta_back[b] = p(theta_back[b]);
  v.sbar = p(sbar);
  v.pals_kinds = p(pals_kinds), v.sigma = p(sigma), v.tau = p(tau);
}

void flat_ordinary_write_back(const FlatOrdinaryStorage& c, System& s) {
  OrdinaryModelState o = state_of(s);
  if (o.kind == OrdinaryModelState::none) return;
  auto& M = s.model;
  M.deformed_length = c.r[c.current[0]];  // the last pass's copy
  M.force_scalar = c.q[c.current[0]];
  if (o.kind == OrdinaryModelState::pals) {  // no ledger, no history: theta, the pass's marks
    *o.theta = c.theta;
    M.plain_scalar_pass = M.passes;
    return;
  }
  // The ledger as HistoryLedger::commit_bonds leaves it after a pass of the lanes without a
  // thermal strain, written in place: t_n and e_n to be rebuilt from this |Y| and q.
  HistoryLedger& L = *o.ledger;
  std::copy(c.booked.begin(), c.booked.end(), L.booked.committed());
  L.pending_set = c.pending_set, L.pending_amount = c.pending_amount;
  L.stored = c.stored, L.stored_trial = c.stored;
  std::fill(L.loss_trial.begin(), L.loss_trial.end(), 0.0);
  L.force.release(), L.extension.release();
  L.fresh = false, L.in_place = false, L.zero_committed = false, L.kept_trial = false;
  L.virtual_committed = true, L.committed_plain = true;
  L.committed_pass = M.passes, M.plain_scalar_pass = M.passes;
  L.system = &s;
  if (o.kind == OrdinaryModelState::elastic_plastic) {
    std::copy(c.ep.begin(), c.ep.end(), o.ep->committed());
    *o.eps_p = c.eps_p, *o.eps_p_trial = c.eps_p, *o.lambda = c.lambda, *o.lambda_trial = c.lambda;
    *o.theta = c.theta, *o.flowed = c.flowed, *o.yielded = c.yielded;
    *o.yield_flags_stale = false;
  } else if (o.kind == OrdinaryModelState::microplastic) {
    std::copy(c.sbar.begin(), c.sbar.end(), o.sbar->committed());
  } else {
    for (int b = 0; b < o.branches; ++b) {
      std::copy(c.back[b].begin(), c.back[b].end(), o.back[b]->committed());
      if (o.dilatation_shear != 0) *o.theta_back[b] = c.theta_back[b], *o.theta_back_trial[b] = c.theta_back[b];
    }
    *o.theta_row = c.theta, *o.theta_row_trial = c.theta, *o.dissipated = c.dissipated_density;
    if (o.dilatation_shear != 0) *o.theta_strain = c.theta_strain, *o.theta_strain_trial = c.theta_strain;
  }
}

}  // namespace horizon
