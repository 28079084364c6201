#pragma once
// The ordinary history models (elastic_plastic, viscoelastic, microplastic) over flat arrays
// (kernels/flat_system.hpp FlatSystem::ordinary): the scalar general pass
// (solver/forces_ordinary.cpp) as row functions, one thread a particle, that the flat
// backend runs on the host's threads and the CUDA backend on the device.
//
// A pass is three rows (flat_ordinary_forces): y = X + u with this pass's s0 (pack_row);
// ordinary_row: the breaking sweep of row i (lanes::break_row: |Y|, breaking, the smallest
// stretch, the dilatation sum), then the model's row (ElasticPlastic::force_row,
// Viscoelastic::force_row, Microplastic::force_row: the force scalars q = t/|Y| and the
// ledger of the step), then
// the model's commit of the row (the explicit step commits after every pass: the history
// is written in place, ord6's LedgerRows::in_place); ordinary_sum_row: f_i = sum_j V_j
// (q_ij + q_ji) Y and the family contact (lanes::sum_row). Every sum is the AVX-512 lanes'
// (bond k of a row into lane (k - start) mod 8, kernels/lanes.hpp), the rare events (a
// bond breaking, the ledger's booking) in bond order, every expression operand by operand
// as material/models/ordinary_lanes_body.inc writes it: a flat run gives the CPU backend's
// bits on a machine whose rows run in the lanes (lanes::wide(); elsewhere the CPU's rows
// sum in bond order, and the two agree to round-off).
//
// The ledger's committed t_n and e_n are rebuilt from the previous pass as the lanes
// rebuild them (history_ledger.hpp LedgerRows::rebuild): e_n = |Y_n| - |xi|, t_n = q_n |Y_n|
// (for a bond broken in this pass, t_n itself, which the breaking sweep leaves in q). |Y|
// and q are kept in two copies, the last pass's and this one's (FlatOrdinary::current says
// which is the last pass's; the pass flips it at its end), so that a row reads the last
// pass's values however often it visits its bonds. The copy must start from a state the
// CPU's next pass would rebuild from (solver/flat_ordinary_copy.hpp).
#include <cstdint>

#include "horizon/core/portable.hpp"
#include "horizon/kernels/flat_system.hpp"
#include "horizon/kernels/lanes.hpp"
#include "horizon/kernels/microplastic.hpp"
#include "horizon/kernels/pals.hpp"
#include "horizon/kernels/ordinary.hpp"
#include "horizon/kernels/unified.hpp"

namespace horizon::kernels {

constexpr int kFlatBranches = 3;  // viscoelastic's Maxwell branches at most (kMaxViscousBranches)

// A kind as kernels::pals_row reads it (the host's BondKind's members of that name).
struct FlatPalsKind {
  double length, volume, fraction;
};

struct FlatOrdinary {
  int model = 0;  // 1: elastic_plastic; 2: viscoelastic; 3: microplastic; 4: pals
  int dim = 3;
  bool contact = false;  // the family's short-range contact (a kind's contact distance)
  // Per kind: omega and V_j (System::model.kind_rows' y and w).
  const double* omega = nullptr;
  const double* vj = nullptr;
  // Per bond, two copies: |Y| and q = t/|Y| (System::model's deformed_length and
  // force_scalar) of the last pass, r[*current] and q[*current], and of this pass, the
  // other copy. Then the reverse bond, the ledger's booked flags (written in place) and
  // pending bookings.
  double* r[2] = {};
  double* q[2] = {};
  uint8_t* current = nullptr;  // one byte: 0 or 1
  const uint64_t* rev = nullptr;
  uint8_t* booked = nullptr;
  uint8_t* pending_set = nullptr;
  double* pending_amount = nullptr;
  // Per particle: the ledger's committed stored energy density W, and theta of the last
  // pass (elastic_plastic: its dilatation output; viscoelastic: theta_n of e^d_n).
  double* stored = nullptr;
  double* theta = nullptr;
  double dev_factor = 0;  // lps_deviatoric_factor(d): alpha m / mu
  // elastic_plastic (material/models/elastic_plastic.cpp): per bond e^dp; per particle
  // eps_p, lambda, the shear correction factor, whether the row flowed in its last pass
  // (the host row's guess, which decides a pending booking's flag: ep_flat_row) and
  // whether it ever flowed.
  double* ep = nullptr;
  double* eps_p = nullptr;
  double* lambda = nullptr;
  const double* shear_factor = nullptr;
  uint8_t* flowed = nullptr;
  uint8_t* yielded = nullptr;
  double bulk = 0, mu = 0, yield = 0, hardening = 0, yield_volume = 0;
  bool plastic = true;
  // viscoelastic (material/models/viscoelastic.cpp): per bond each branch's back
  // extension; per particle the dissipated energy density (its output) and, in plane
  // strain, theta and each branch's back dilatation; the branches' step coefficients.
  double* back[kFlatBranches] = {};
  double* dissipated_density = nullptr;
  double* theta_strain = nullptr;  // plane strain: theta_ (dilatation_shear != 0)
  double* theta_back[kFlatBranches] = {};
  int branches = 0;
  double bulk_elastic = 0, dilatation_shear = 0, lambda_inf = 1;
  double branch_lambda[kFlatBranches] = {}, decay[kFlatBranches] = {}, from_old[kFlatBranches] = {},
         from_new[kFlatBranches] = {};
  // microplastic (material/models/microplastic.cpp): per bond the plastic stretch sbar
  // (written in place); the micromodulus c and the yield stretch s_Y.
  double* sbar = nullptr;
  double micro_c = 0, yield_stretch = 0;
  // pals (material/models/pals.cpp): per kind {|xi|, V, fraction} (kernels::pals_row's
  // kind), per bond sigma and tau, kappa (mu above); theta per particle is its output.
  const FlatPalsKind* pals_kinds = nullptr;
  const double* sigma = nullptr;
  const double* tau = nullptr;
  double kappa = 0;
};

// The breaking sweep of row i (lanes::break_row): |Y| of every bond (into this pass's copy),
// breaking, the smallest stretch, the energy of the broken bonds and the
// damage; returns sum_j omega V_j |xi| e over the bonds that act in this pass.
template <bool kAfter>
HORIZON_HD inline double ordinary_break_row(const FlatSystem& s, const FlatOrdinary& o, uint64_t i) {
  const double* pi = s.y4 + 4 * i;
  double th[kLanes] = {}, sm[kLanes];
  for (int l = 0; l < kLanes; ++l) sm[l] = INFINITY;
  double lost = 0;
  uint64_t broken = 0;
  const int last = *o.current;
  double* r_now = o.r[1 - last];
  const double* r_last = o.r[last];
  double* q_last = o.q[last];
  for_each_lane(s.offset[i], s.offset[i + 1], [&](uint64_t k, int l) {
    const Kind& kc = s.kinds[s.kind[k]];
    const double* pj = s.y4 + 4 * static_cast<uint64_t>(s.nbr[k]);
    const double r = bond_length(pj[0] - pi[0], pj[1] - pi[1], pj[2] - pi[2]);
    r_now[k] = r;
    if (!s.intact[k]) return;
    const double e = r - kc.length, stretch = e * kc.inv_length;
    sm[l] = stretch < sm[l] ? stretch : sm[l];
    const bool brk = breaks(stretch, pi[3], pj[3]);
    if (kAfter || !brk) th[l] += dilatation_term(kc.wv, kc.length, e);
    if (brk) {  // (1/2) t_old e V_j, t_old = q_old |Y_old|, left in q for the model's booking
      s.intact[k] = kAfter ? 2 : 0;
      ++broken;
      const double t_old = q_last[k] * r_last[k];
      q_last[k] = t_old;
      if (r > 0) lost += 0.5 * t_old * e * o.vj[s.kind[k]];
      s.intact_weight[i] -= kc.damage;
    }
  });
  finish_breaks(s, i, broken, lost);
  s.min_stretch_next[i] = lane_min(sm);
  return lane_total(th);
}

// The sums of one visit of an elastic-plastic row (lanes::RowSums).
struct EpSums {
  double norm = 0, dev = 0, work = 0, booked = 0;
  bool inelastic = false;
};

// One visit of elastic_plastic's row i (ordinary_lanes_body.inc ep_body): with kNorm the
// trial deviatoric extension e^d - e^dp_n and its weighted norm, with kForce the return's
// scaling beta of it, e^dp (written where beta != 1), the force states, the step's work
// with the rebuilt t_n, e_n, and the ledger's bookings. `revisit`: a second force visit of
// the pass (the first, taken with beta = 1, booked the bonds broken since the commit and
// left their pending flags set, which this one drops, as the host row's second visit does).
template <bool kNorm, bool kForce>
HORIZON_HD inline EpSums ep_visit(const FlatSystem& s, const FlatOrdinary& o, uint64_t i, double theta_d, double beta,
                                  double alpha, double p_coef, bool revisit) {
  EpSums out;
  double nrm[kLanes] = {}, dev[kLanes] = {}, work[kLanes] = {};
  const int last = *o.current;
  const double* r_now = o.r[1 - last];
  const double* r_last = o.r[last];
  const double* q_last = o.q[last];
  double* q_now = o.q[1 - last];
  const double rest = 1.0 - beta;
  const LedgerBonds ledger{nullptr, o.booked, o.booked, o.pending_set, o.pending_amount};
  for_each_lane(s.offset[i], s.offset[i + 1], [&](uint64_t k, int l) {
    const uint32_t kd = s.kind[k];
    const Kind& kc = s.kinds[kd];
    const double L = kc.length, r = r_now[k], e = r - L;
    const uint8_t live = s.intact[k];
    double t = 0.0;
    if (live) {
      const double ep = o.ep[k];
      const double ede = (e - theta_d * L) - ep;  // deviatoric_extension(e, theta, L, d) - e^dp_n
      if constexpr (kNorm) nrm[l] += kc.wv * ede * ede;  // weighted_square
      if constexpr (kForce) {
        const double elastic = beta * ede;  // ep_bond
        if (beta != 1.0) o.ep[k] = ep + rest * ede;
        dev[l] += kc.wv * elastic * elastic;
        t = p_coef * o.omega[kd] * L + alpha * o.omega[kd] * elastic;  // ordinary_force_scalar
      }
    }
    if constexpr (kForce) {
      const double vj = o.vj[kd];
      const uint8_t was = o.booked[k];
      // t_n rebuilt: q_n |Y_n|, or for a bond broken since the commit, the t_n the sweep
      // left in q (a revisit finds it booked by the first visit, its pending flag set).
      const double qo = q_last[k], ro = r_last[k];
      const double of = (revisit ? o.pending_set[k] != 0 : bond_booked_now(live, was)) ? qo : qo * ro;
      work[l] += 0.5 * (of + t) * (e - (ro - L)) * vj;  // trapezoid_work
      if (!live && of != 0.0) out.inelastic = true;   // it acted at the start of the step
      if (bond_booked_now(live, was) || o.pending_set[k])
        if (ledger_book_bond(ledger, k, live, was, qo, r, e, vj, out.booked)) out.inelastic = true;
      q_now[k] = live ? t / r : 0.0;
    }
  });
  out.norm = lane_total(nrm), out.dev = lane_total(dev), out.work = lane_total(work);
  return out;
}

// elastic_plastic's row (ElasticPlastic::force_row): the trial norm, the return, the forces
// and the ledger, then the commit of the row. As the host row, a row that did not flow in
// its last pass is taken as elastic first (beta = 1: one visit for the norm and the forces)
// and visited again only if the return then scales it; a row that flowed takes a norm visit
// and a force visit. Every written value is the two-visit one either way.
HORIZON_HD inline void ep_flat_row(const FlatSystem& s, const FlatOrdinary& o, uint64_t i, double dilatation_sum) {
  const int dim = o.dim;
  const double m = s.weighted_volume[i];
  const double alpha = o.shear_factor[i] * o.dev_factor * o.mu / m;
  const double mu = o.shear_factor[i] * o.mu;
  const double theta = dim * dilatation_sum / m;
  o.theta[i] = theta;
  // theta |xi| / d as (theta / d) |xi| (the lanes' rounding).
  const double theta_d = theta / dim;
  const double p_coef = dim * o.bulk * theta / m;  // t^i = (d k' theta/m) omega |xi|
  const bool guess_elastic = !o.flowed[i];
  const EpSums first = guess_elastic ? ep_visit<true, true>(s, o, i, theta_d, 1.0, alpha, p_coef, false)
                                     : ep_visit<true, false>(s, o, i, theta_d, 1.0, alpha, p_coef, false);
  const double n2 = first.norm * (alpha * alpha);
  const ReturnMap rm = o.plastic ? ep_return_map(n2, o.yield_volume > 0 ? o.yield_volume : m, dim, mu, o.yield,
                                                 o.hardening, o.eps_p[i])
                                 : ReturnMap{};
  const double beta = rm.scale;
  o.flowed[i] = rm.plastic_strain > 0;
  if (beta != 1.0) o.yielded[i] = 1;
  o.eps_p[i] = o.eps_p[i] + rm.plastic_strain;  // (the commit: eps_p = eps_p_trial)
  o.lambda[i] = o.lambda[i] + plastic_multiplier_step(beta, alpha);
  EpSums sums = first;
  if (!guess_elastic || beta != 1.0) {
    sums = ep_visit<false, true>(s, o, i, theta_d, beta, alpha, p_coef, guess_elastic);
    if (guess_elastic) sums.booked = first.booked, sums.inelastic = sums.inelastic || first.inelastic;
  }
  const bool inelastic = rm.plastic_strain > 0 || sums.inelastic;
  const double W = 0.5 * o.bulk * theta * theta + 0.5 * alpha * sums.dev;
  const double loss = inelastic ? inelastic_loss(sums.work, W - o.stored[i], sums.booked) : 0.0;
  o.stored[i] = W;
  s.energy[i] = W;
  if (loss != 0) s.dissipated[i] += loss * s.volume[i];
}

// viscoelastic's row (Viscoelastic::force_row with ordinary_lanes_body.inc ves_body): the
// pressure, e^d, the branches' back extensions, the forces and the ledger, then the commit.
HORIZON_HD inline void ves_flat_row(const FlatSystem& s, const FlatOrdinary& o, uint64_t i, double dilatation_sum) {
  const uint64_t first = s.offset[i], last = s.offset[i + 1];
  const int dim = o.dim, nbranch = o.branches;
  const double m = s.weighted_volume[i];
  const double alpha = o.dev_factor * o.mu / m;
  const double theta = dim * dilatation_sum / m;
  // p_i = k' theta, or in plane strain k theta + (mu/3) [lambda_inf theta + sum_b lambda_b
  // (theta - theta^b_b)] (Viscoelastic::pressure), the back dilatations committed at once.
  double pressure = o.bulk_elastic * theta, dil_springs = 0;
  if (o.dilatation_shear != 0) {
    double relaxing = o.lambda_inf * theta;
    dil_springs = o.lambda_inf * theta * theta;
    for (int b = 0; b < nbranch; ++b) {
      const double back =
          sls_back_extension(o.decay[b], o.from_old[b], o.from_new[b], o.theta_back[b][i], o.theta_strain[i], theta);
      o.theta_back[b][i] = back;
      relaxing += o.branch_lambda[b] * (theta - back);
      dil_springs += o.branch_lambda[b] * (theta - back) * (theta - back);
    }
    o.theta_strain[i] = theta;
    pressure = pressure + o.dilatation_shear * relaxing;
  }
  const double theta_old = o.theta[i];
  o.theta[i] = theta;
  const double p_coef = dim * pressure / m;
  // theta |xi| / d as (theta / d) |xi|, likewise theta_n (the lanes' rounding).
  const double theta_d = theta / dim, theta_old_d = theta_old / dim;
  double stored[kLanes] = {}, work[kLanes] = {};
  double booked = 0;
  const LedgerBonds ledger{nullptr, o.booked, o.booked, o.pending_set, o.pending_amount};
  const int cur = *o.current;
  const double* r_now = o.r[1 - cur];
  const double* r_last = o.r[cur];
  const double* q_last = o.q[cur];
  double* q_now = o.q[1 - cur];
  for_each_lane(first, last, [&](uint64_t k, int l) {
    const uint32_t kd = s.kind[k];
    const Kind& kc = s.kinds[kd];
    const double L = kc.length, omega = o.omega[kd], vj = o.vj[kd];
    const double r = r_now[k], e = r - L;
    const uint8_t live = s.intact[k];
    const double ed = e - theta_d * L;  // deviatoric_extension
    const uint8_t was = o.booked[k];
    // t_n rebuilt: q_n |Y_n|, or for a bond broken since the commit, the t_n the sweep left in q.
    const double qo = q_last[k], ro = r_last[k];
    const double of = bond_booked_now(live, was) ? qo : qo * ro, oe = ro - L;
    const double ed_old = oe - theta_old_d * L;  // e^d_n, as the last pass computed it
    double dev = o.lambda_inf * ed, springs = o.lambda_inf * ed * ed;
    for (int b = 0; b < nbranch; ++b) {
      const double back = sls_back_extension(o.decay[b], o.from_old[b], o.from_new[b], o.back[b][k], ed_old, ed);
      if (live) o.back[b][k] = back;
      const double qb = ed - back;
      dev = dev + o.branch_lambda[b] * qb;
      springs = springs + o.branch_lambda[b] * qb * qb;
    }
    double t = 0.0;
    if (live) {
      stored[l] += kc.wv * springs;
      t = p_coef * omega * L + alpha * omega * dev;  // ordinary_force_scalar
    }
    work[l] += 0.5 * (of + t) * (e - oe) * vj;  // trapezoid_work
    if (bond_booked_now(live, was) || o.pending_set[k]) ledger_book_bond(ledger, k, live, was, qo, r, e, vj, booked);
    q_now[k] = live ? t / r : 0.0;
  });
  const double W = 0.5 * o.bulk_elastic * theta * theta + 0.5 * o.dilatation_shear * dil_springs +
                   0.5 * alpha * lane_total(stored);
  const double loss = inelastic_loss(lane_total(work), W - o.stored[i], booked);
  o.stored[i] = W;
  s.energy[i] = W;
  if (loss != 0) {
    s.dissipated[i] += loss * s.volume[i];
    o.dissipated_density[i] += loss;
  }
}

// microplastic's row (Microplastic::force_row with ordinary_lanes_body.inc micro_body,
// kernels/microplastic.hpp): each bond's return map (sbar written in place where the bond
// acts), t = omega (c/2)(s - sbar), W_i, the step's work with the rebuilt t_n, e_n, the
// ledger's bookings, then the commit (Microplastic::commit: the ledger's loss).
HORIZON_HD inline void micro_flat_row(const FlatSystem& s, const FlatOrdinary& o, uint64_t i) {
  double W[kLanes] = {}, work[kLanes] = {};
  double booked = 0;
  bool inelastic = false;
  const LedgerBonds ledger{nullptr, o.booked, o.booked, o.pending_set, o.pending_amount};
  const int cur = *o.current;
  const double* r_now = o.r[1 - cur];
  const double* r_last = o.r[cur];
  const double* q_last = o.q[cur];
  double* q_now = o.q[1 - cur];
  const double c = o.micro_c, yield = o.yield_stretch;
  for_each_lane(s.offset[i], s.offset[i + 1], [&](uint64_t k, int l) {
    const uint32_t kd = s.kind[k];
    const Kind& kc = s.kinds[kd];
    const double L = kc.length, vj = o.vj[kd];
    const double r = r_now[k], e = r - L;
    const uint8_t live = s.intact[k];
    double t = 0.0;
    if (live) {
      const double stretch = e / L, sbar_old = o.sbar[k];
      const double sbar = microplastic_return(stretch, sbar_old, yield);
      o.sbar[k] = sbar;
      if (sbar != sbar_old) inelastic = true;
      const double plastic_free = stretch - sbar;
      t = o.omega[kd] * 0.5 * c * plastic_free;  // microplastic_force_scalar
      W[l] += 0.5 * t * plastic_free * L * vj;    // microplastic_bond_energy
    }
    const uint8_t was = o.booked[k];
    // t_n rebuilt: q_n |Y_n|, or for a bond broken since the commit, the t_n the sweep left in q.
    const double qo = q_last[k], ro = r_last[k];
    const double of = bond_booked_now(live, was) ? qo : qo * ro;
    work[l] += 0.5 * (of + t) * (e - (ro - L)) * vj;  // trapezoid_work
    if (!live && of != 0.0) inelastic = true;         // it acted at the start of the step
    if (bond_booked_now(live, was) || o.pending_set[k])
      if (ledger_book_bond(ledger, k, live, was, qo, r, e, vj, booked)) inelastic = true;
    q_now[k] = live && r > 0 ? t / r : 0.0;
  });
  const double Wi = lane_total(W);
  const double loss = inelastic ? inelastic_loss(lane_total(work), Wi - o.stored[i], booked) : 0.0;
  o.stored[i] = Wi;
  s.energy[i] = Wi;
  if (loss != 0) s.dissipated[i] += loss * s.volume[i];
}

// pals' row (Pals::force_row): kernels::pals_row in bond order on this pass's |Y| (PALS
// keeps no history and no ledger: the breaking sweep books its broken bonds' energy).
HORIZON_HD inline void pals_flat_row(const FlatSystem& s, const FlatOrdinary& o, uint64_t i) {
  PalsRow<FlatPalsKind> a;
  a.kinds = o.pals_kinds, a.kind = s.kind, a.intact = s.intact, a.r = o.r[1 - *o.current];
  a.sigma = o.sigma, a.tau = o.tau, a.q = o.q[1 - *o.current];
  a.kappa = o.kappa, a.mu = o.mu;
  const PalsSums sums = pals_row(a, s.offset[i], s.offset[i + 1]);
  o.theta[i] = sums.theta;
  s.energy[i] = sums.W;
}

// Pass 1 of row i: the breaking sweep, then the model's row and its commit.
template <bool kAfter>
HORIZON_HD inline void ordinary_row_of(const FlatSystem& s, uint64_t i) {
  const FlatOrdinary& o = *s.ordinary;
  const double dilatation = ordinary_break_row<kAfter>(s, o, i);
  if (o.model == 1)
    ep_flat_row(s, o, i, dilatation);
  else if (o.model == 2)
    ves_flat_row(s, o, i, dilatation);
  else if (o.model == 3)
    micro_flat_row(s, o, i);
  else
    pals_flat_row(s, o, i);
}

// Pass 2 of row i (lanes::sum_row): f_i = sum_j V_j (q_ij + q_ji) Y over the acting bonds,
// plus the family contact (its energy added to W_i); with break_after, the bonds broken
// in this pass are off after it.
template <bool kAfter>
HORIZON_HD inline void ordinary_sum_row_of(const FlatSystem& s, uint64_t i) {
  const FlatOrdinary& o = *s.ordinary;
  const double* pi = s.y4 + 4 * i;
  const double* q = o.q[1 - *o.current];  // this pass's
  double fx[kLanes] = {}, fy[kLanes] = {}, fz[kLanes] = {}, en[kLanes] = {};
  for_each_lane(s.offset[i], s.offset[i + 1], [&](uint64_t k, int l) {
    const double* pj = s.y4 + 4 * static_cast<uint64_t>(s.nbr[k]);
    const double Yx = pj[0] - pi[0], Yy = pj[1] - pi[1], Yz = pj[2] - pi[2];
    const uint8_t live = s.intact[k];
    if (live) {
      const double vj = o.vj[s.kind[k]], qij = q[k], qji = q[o.rev[k]];
      fx[l] += vj * (qij * Yx + qji * Yx);
      fy[l] += vj * (qij * Yy + qji * Yy);
      fz[l] += vj * (qij * Yz + qji * Yz);
    }
    if (o.contact) {  // every family pair, intact or broken (state/system.hpp family_contact)
      const Kind& kc = s.kinds[s.kind[k]];
      double a, w;
      if (contact_coefficient(kc.contact_d2, kc.contact_d, kc.contact_k, Yx * Yx + Yy * Yy + Yz * Yz, a, w)) {
        fx[l] += a * Yx;
        fy[l] += a * Yy;
        fz[l] += a * Yz;
        en[l] += w;
      }
    }
    if (kAfter && live == 2) s.intact[k] = 0;
  });
  s.f[3 * i] = lane_total(fx), s.f[3 * i + 1] = lane_total(fy), s.f[3 * i + 2] = lane_total(fz);
  s.energy[i] += lane_total(en);
}

HORIZON_HD inline void ordinary_row(const FlatSystem& s, uint64_t i) {
  if (s.break_after) ordinary_row_of<true>(s, i);
  else ordinary_row_of<false>(s, i);
}
HORIZON_HD inline void ordinary_sum_row(const FlatSystem& s, uint64_t i) {
  if (s.break_after) ordinary_sum_row_of<true>(s, i);
  else ordinary_sum_row_of<false>(s, i);
}

// After a pass (one thread): this pass's |Y| and q become the last pass's.
HORIZON_HD inline void flip_ordinary(const FlatSystem& s) {
  s.ordinary->current[0] = static_cast<uint8_t>(1 - s.ordinary->current[0]);
}

// The pass on the host (flat_forces when FlatSystem::ordinary is set).
inline void flat_ordinary_forces(const FlatSystem& s) {
  const uint64_t n = s.n;
  HORIZON_FLAT_ROWS
  for (uint64_t i = 0; i < n; ++i) pack_row(s, i);
  if (s.break_after) {
    HORIZON_FLAT_ROWS
    for (uint64_t i = 0; i < n; ++i) ordinary_row_of<true>(s, i);
    HORIZON_FLAT_ROWS
    for (uint64_t i = 0; i < n; ++i) ordinary_sum_row_of<true>(s, i);
  } else {
    HORIZON_FLAT_ROWS
    for (uint64_t i = 0; i < n; ++i) ordinary_row_of<false>(s, i);
    HORIZON_FLAT_ROWS
    for (uint64_t i = 0; i < n; ++i) ordinary_sum_row_of<false>(s, i);
  }
  flip_ordinary(s);
}

}  // namespace horizon::kernels
