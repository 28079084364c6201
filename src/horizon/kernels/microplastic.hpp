#pragma once
// The per-bond and per-row work of the proportional microplastic bonds (material/models/
// microplastic.hpp; seed 002, Macek and Silling, sec. 2.2, eq. 19-21) as device-portable
// functions (core/portable.hpp, issue 30). The model's scalar row (Microplastic::
// force_row_scalar) is microplastic_row; its vector pass (force_state, the reference) calls
// microplastic_bond per bond. Each keeps the model's operations in their order, so its
// answers keep their bits. What is not here: the energy ledger's opening of a bond
// (HistoryLedger::Row::open_bond, material/models/history_ledger.hpp), which the row takes
// as a callable (the host passes the ledger's), and q = t/|Y| of the row's bonds, which
// the host's row divides in one vectorised loop after the sums (ordinary_rows.hpp); the
// eight-lane row (ordinary_lanes_body.inc micro_body) writes the same expressions lane by
// lane.
//
//   f = c (s - sbar),  sbar moves only at yield, |s - sbar| <= s_Y   (eq. 19-21, digest sec. 2.2)
//   t_ij = omega (c/2) (s - sbar)     (half the pair force, as PMB's t = c s/2)
//   W_i  = sum_j (t/2)(s - sbar) |xi| V_j
#include <cstdint>

#include "horizon/core/portable.hpp"
#include "horizon/kernels/ordinary.hpp"

namespace horizon::kernels {

// The return map of one bond (digest 002 sec. 2.2): r = s - sbar_old; if |r| > s_Y,
// sbar = s - sign(r) s_Y. Returns the new plastic stretch.
HORIZON_HD inline double microplastic_return(double s, double sbar_old, double yield_stretch) {
  const double r = s - sbar_old;
  if (r > yield_stretch) return s - yield_stretch;
  if (r < -yield_stretch) return s + yield_stretch;
  return sbar_old;
}

// The critical stretch s0 of a microplastic bond taking the same work to break as a PMB
// bond breaking at s_e (seed eq. 26; material/models/microplastic.hpp has the derivation):
// s0 = (s_e^2 + s_Y^2)/(2 s_Y) when s_e > s_Y, else s_e.
HORIZON_HD inline double microplastic_critical_stretch(double elastic_equivalent, double yield_stretch) {
  if (elastic_equivalent <= yield_stretch) return elastic_equivalent;
  return (elastic_equivalent * elastic_equivalent + yield_stretch * yield_stretch) / (2 * yield_stretch);
}

// t = omega (c/2) (s - sbar) (eq. 19, halved between the two directed bonds).
HORIZON_HD inline double microplastic_force_scalar(double omega, double c, double stretch, double sbar) {
  return omega * 0.5 * c * (stretch - sbar);
}

// The directed bond's share of W_i: (t/2)(s - sbar)|xi| V_j, the elastic part of the
// micropotential c (s - sbar)^2 |xi|/2 halved between the ends.
HORIZON_HD inline double microplastic_bond_energy(double t, double stretch, double sbar, double length,
                                                  double volume) {
  return 0.5 * t * (stretch - sbar) * length * volume;
}

// One acting bond of extension e: its plastic stretch, force scalar, energy share and the
// step's trapezoidal work (t_n, e_n: the ledger's committed force state and extension).
struct MicroplasticBond {
  double sbar, t, energy, work;
  bool yielded;  // sbar changed (an inelastic step)
};
HORIZON_HD_INLINE MicroplasticBond microplastic_bond(double e, double length, double omega, double volume, double c,
                                                     double yield_stretch, double sbar_old, double t_old,
                                                     double e_old) {
  MicroplasticBond b;
  const double stretch = e / length;
  b.sbar = microplastic_return(stretch, sbar_old, yield_stretch);
  b.yielded = b.sbar != sbar_old;
  b.t = microplastic_force_scalar(omega, c, stretch, b.sbar);
  b.energy = microplastic_bond_energy(b.t, stretch, b.sbar, length, volume);
  b.work = trapezoid_work(t_old, b.t, e, e_old, volume);
  return b;
}

// The flat arrays of one pass of the scalar rows (per bond unless said). Kind: a per-kind
// struct with members length, weight (omega), volume and fraction (the host's BondKind).
template <class Kind>
struct MicroplasticRow {
  const Kind* kinds = nullptr;  // per kind
  const uint32_t* kind = nullptr;
  const uint8_t* intact = nullptr;
  const double* r = nullptr;    // |Y| of the pass
  const double* sbar_old = nullptr;
  double* sbar_trial = nullptr;
  const double* old_force = nullptr;      // the ledger's committed t_n
  const double* old_extension = nullptr;  // and e_n
  double* force_trial = nullptr;          // t of the pass
  double c = 0, yield = 0;
};

// The sums of a row: W_i, the step's trapezoidal work, the ledger's bookings, and whether
// a bond yielded or released energy.
struct MicroplasticSums {
  double W = 0, work = 0, booked = 0;
  bool inelastic = false;
};

// Row [first, last) in bond order. `open(k, e, volume, booked)`: the ledger's opening of
// bond k (HistoryLedger::Row::open_bond: it reads t_old of a bond broken in this pass from
// the pass's q, so before q is written), true when it booked the bond.
template <class Kind, class Open>
HORIZON_HD_INLINE MicroplasticSums microplastic_row(const MicroplasticRow<Kind>& a, uint64_t first, uint64_t last,
                                                   Open&& open) {
  MicroplasticSums s;
  for (uint64_t k = first; k < last; ++k) {
    const Kind& bk = a.kinds[a.kind[k]];
    const double vj = bk.volume * bk.fraction;
    const double e = a.r[k] - bk.length;
    s.inelastic = open(k, e, vj, s.booked) || s.inelastic;
    if (!a.intact[k]) {
      a.sbar_trial[k] = a.sbar_old[k];
      a.force_trial[k] = 0;
      if (a.old_force[k] != 0) {
        s.work += released_work(a.old_force[k], e, a.old_extension[k], vj);
        s.inelastic = true;
      }
      continue;
    }
    const MicroplasticBond b =
        microplastic_bond(e, bk.length, bk.weight, vj, a.c, a.yield, a.sbar_old[k], a.old_force[k], a.old_extension[k]);
    a.sbar_trial[k] = b.sbar;
    if (b.yielded) s.inelastic = true;
    s.W += b.energy;
    a.force_trial[k] = b.t;
    s.work += b.work;
  }
  return s;
}

}  // namespace horizon::kernels
