#pragma once
// The per-bond and per-particle work of the ordinary history models (elastic_plastic,
// viscoelastic: Model::force_row of the scalar general pass, solver/forces_ordinary.cpp)
// as device-portable functions (core/portable.hpp, issue 30). The models call these; each
// keeps the models' operations in their order, so their answers keep their bits. The
// energy ledger's per-bond booking (material/models/history_ledger.hpp HistoryLedger::Row,
// the lanes' rare path) is here too, over plain arrays (ledger_open_bond, ledger_book_bond),
// so that the flat rows (kernels/flat_ordinary.hpp) book as the host's rows do.
//
// Both models (Silling et al. 2007, seed 003 sec. 15-16; Mitchell 2011):
//   e^d = e - theta |xi| / d                 (deviatoric extension; seed 003 sec. 15)
//   t   = (d p / m) omega |xi| + alpha omega (deviatoric part)
// with p = k' theta (elastic_plastic) or the relaxing pressure (viscoelastic).
#include <cstdint>

#include "horizon/core/portable.hpp"
#include "horizon/kernels/unified.hpp"

namespace horizon::kernels {

// e^d = e - theta |xi| / d (seed 003 sec. 15; digest sec. 8).
HORIZON_HD inline double deviatoric_extension(double e, double theta, double length, int dimension) {
  return e - theta * length / dimension;
}

// t = p_coef omega |xi| + alpha omega dev, p_coef = d p / m (eq. 121-123 of seed 003).
HORIZON_HD inline double ordinary_force_scalar(double p_coef, double omega, double length, double alpha, double dev) {
  return p_coef * omega * length + alpha * omega * dev;
}

// The work of a bond over a step by the trapezoidal rule: (t_n + t_n+1)/2 (e_n+1 - e_n) V_j
// (material/models/history_ledger.hpp); a bond that no longer acts has t_n+1 = 0.
HORIZON_HD inline double trapezoid_work(double t_old, double t_new, double e_new, double e_old, double volume) {
  return 0.5 * (t_old + t_new) * (e_new - e_old) * volume;
}
HORIZON_HD inline double released_work(double t_old, double e_new, double e_old, double volume) {
  return 0.5 * t_old * (e_new - e_old) * volume;
}

// omega V_j x^2: a bond's term of a weighted norm ||x||_w^2.
HORIZON_HD inline double weighted_square(double wv, double x) { return wv * x * x; }

// --- elastic_plastic (material/models/elastic_plastic.hpp has the derivations) ---

// c of sigma_eq^2 = c m ||t^d||_w^2: 1/5 in 3-D, 3/8 in 2-D.
HORIZON_HD inline double ep_equivalent_stress_factor(int dimension) { return dimension == 2 ? 3.0 / 8.0 : 1.0 / 5.0; }

// psi_0 = sigma^2 / (2 c m).
HORIZON_HD inline double ep_yield_value(double yield_stress, double weighted_volume, int dimension) {
  return yield_stress * yield_stress / (2.0 * ep_equivalent_stress_factor(dimension) * weighted_volume);
}

// sigma_eq of a force state of weighted norm^2 n2.
HORIZON_HD inline double ep_equivalent_stress(double norm2, double weighted_volume, int dimension) {
  return root(ep_equivalent_stress_factor(dimension) * weighted_volume * norm2);
}

// The return mapping of one particle: beta (t^d = beta t^d_tr), d eps_p, and the trial's
// yield function f = ||t^d_tr||_w^2/2 - psi_0(eps_p,n) (> 0: plastic flow); the classical
// radial return on sigma_eq with linear hardening H.
struct ReturnMap {
  double scale = 1;           // beta
  double plastic_strain = 0;  // d eps_p
  double trial_yield = 0;
};
HORIZON_HD inline ReturnMap ep_return_map(double trial_norm2, double weighted_volume, int dimension,
                                          double shear_modulus, double yield_stress, double hardening, double eps_p) {
  ReturnMap r;
  const double sy = yield_stress + hardening * eps_p;
  r.trial_yield = 0.5 * trial_norm2 - ep_yield_value(sy, weighted_volume, dimension);
  if (!(r.trial_yield > 0)) return r;
  const double s_trial = ep_equivalent_stress(trial_norm2, weighted_volume, dimension);
  r.plastic_strain = (s_trial - sy) / (3.0 * shear_modulus + hardening);
  r.scale = 1.0 - 3.0 * shear_modulus * r.plastic_strain / s_trial;
  return r;
}

// d lambda of a step whose return scaled the trial deviatoric state by beta
// (material/models/elastic_plastic.hpp: (1 - beta)/(alpha beta), 0 in an elastic step).
HORIZON_HD inline double plastic_multiplier_step(double beta, double alpha) {
  return beta < 1.0 ? (1.0 - beta) / (alpha * beta) : 0.0;
}

// One bond after the return: the elastic deviatoric extension e^de = beta e^de_tr and the
// trial plastic extension e^dp + (1 - beta) e^de_tr.
struct EpBond {
  double elastic, plastic;
};
HORIZON_HD inline EpBond ep_bond(double e, double theta, double length, int dimension, double plastic_old,
                                 double beta) {
  const double trial = deviatoric_extension(e, theta, length, dimension) - plastic_old;
  return {beta * trial, plastic_old + (1.0 - beta) * trial};
}

// --- viscoelastic (material/models/viscoelastic.hpp) ---

// The exact update of one standard-linear-solid branch over a step:
// e^b_n+1 = decay e^b_n + from_old e^d_n + from_new e^d_n+1.
HORIZON_HD inline double sls_back_extension(double decay, double from_old, double from_new, double back, double ed_old,
                                            double ed_new) {
  return decay * back + from_old * ed_old + from_new * ed_new;
}

// --- the energy ledger's booking of a bond (material/models/history_ledger.hpp) ---

// The general force pass books a bond in the pass that breaks it: its flag is 0 (broken
// before the forces) or 2 (broken after them: it still acts in this pass).
HORIZON_HD inline bool bond_booked_now(uint8_t intact, uint8_t booked) { return !booked && intact != 1; }

// What the scalar force pass booked for a bond it broke, per unit V_i: (1/2) t_old e V_j,
// t_old the bond's scalar force state of the previous pass (history_ledger.hpp).
HORIZON_HD inline double broken_bond_booking(double t_old, double length, double e, double volume) {
  return length > 0 ? 0.5 * t_old * e * volume : 0.0;
}

// D_i from the step's work, the change of W and the booking (all per unit V_i).
HORIZON_HD inline double inelastic_loss(double work, double stored_change, double booked) {
  return work - stored_change - booked;
}

// The ledger's per-bond arrays of one pass (HistoryLedger::Row): the trial extension (null
// where the pass keeps none), the committed and trial booked flags (the same array when
// the pass writes its history in place), the pending bookings.
struct LedgerBonds {
  double* extension_trial;
  const uint8_t* booked_committed;
  uint8_t* booked_trial;
  uint8_t* pending_set;
  double* pending_amount;
};

// The booking part of opening bond k (`was`: its committed booked flag): a bond broken
// since the commit books what the breaking sweep booked for it, (1/2) t_old e V_j, once
// (pending_amount keeps it for later passes before the commit), and is marked booked; a
// pending booking of a bond that is not broken is dropped (a solver restored the bond).
// Returns true when the bond is booked.
HORIZON_HD inline bool ledger_book_bond(const LedgerBonds& L, uint64_t k, uint8_t intact, uint8_t was, double t_old,
                                        double length, double e, double volume, double& booked_sum) {
  if (bond_booked_now(intact, was)) {
    if (!L.pending_set[k]) {
      L.pending_amount[k] = broken_bond_booking(t_old, length, e, volume);
      L.pending_set[k] = 1;
    }
    booked_sum += L.pending_amount[k];
    L.booked_trial[k] = 1;
    return true;
  }
  if (L.pending_set[k]) L.pending_set[k] = 0;  // a solver restored the bond (a failed static increment)
  return false;
}

// Opens bond k's trial record at extension e (HistoryLedger::Row::open_bond): the trial
// extension, the flag carried over, then the booking.
HORIZON_HD inline bool ledger_open_bond(const LedgerBonds& L, uint64_t k, uint8_t intact, double t_old, double length,
                                        double e, double volume, double& booked_sum) {
  L.extension_trial[k] = e;
  const uint8_t was = L.booked_committed[k];
  L.booked_trial[k] = was;
  return ledger_book_bond(L, k, intact, was, t_old, length, e, volume, booked_sum);
}

}  // namespace horizon::kernels
