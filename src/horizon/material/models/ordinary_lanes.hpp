#pragma once
// The ordinary history models' rows (Model::force_row of the scalar general pass,
// solver/forces_ordinary.cpp) and the pass's two bond sweeps in the fast loops' eight
// lanes (solver/forces.cpp): bond k of a row goes to lane (k - row start) mod 8, each lane
// keeps its own partial sums, and the lanes are added as ((l0 + l1) + (l2 + l3)) +
// ((l4 + l5) + (l6 + l7)) at the end of the row. The body is written once on GCC's
// eight-wide vector types and built for AVX-512 (one register a vector), taken on
// machines that have it (wide()); elsewhere the models and the pass run their scalar rows
// in bond order (GCC keeps eight-wide vectors in memory on AVX2 and SSE: 3-4 times
// slower, docs/benchmarks.md). No FMA contraction in the file (CMakeLists.txt), so the
// lanes are the scalar expressions, operand by operand (but for theta |xi| / d, taken as
// (theta / d) |xi| in the elastic-plastic and viscoelastic rows: one division a row). A bond's kind constants {|xi|,
// omega, omega V_j, V_j} come in one 32-byte record per kind (System::model.kind_rows),
// eight records turned into four vectors at once. Rare events (a bond breaking, the
// ledger's booking of a bond broken in this pass, a pending booking, the family contact)
// leave the vectors and are handled bond by bond in bond order.
//
// The sums' order is the lanes', not the bond order of the scalar rows and of
// Model::force_state (the vector pass kept as the reference): the forces agree with them to
// round-off (tests/verification/test_ordinary_pass.cpp: 1e-12 after 40 steps of a breaking
// impact), the same bits on any thread and rank count on one machine.
#include <cstddef>
#include <cstdint>

#include "horizon/core/error.hpp"
#include "horizon/core/point4.hpp"
#include "horizon/material/model.hpp"
#include "horizon/material/models/history_ledger.hpp"
#include "horizon/state/system.hpp"

namespace horizon::lanes {

// What every ordinary row reads and writes (one row i, bonds [first, last)).
struct RowBonds {
  uint64_t first = 0, last = 0;
  std::size_t i = 0;
  const double* r = nullptr;  // |Y| per bond (the breaking sweep's)
  const uint8_t* intact = nullptr;
  const uint32_t* kind = nullptr;
  const uint32_t* nbr = nullptr;
  const Point4* kinds = nullptr;  // per kind {|xi|, omega, omega V_j, V_j}
  const double* eps = nullptr;    // thermal strain per particle (null: none)
  double* q = nullptr;            // in: t_old of a bond broken in this pass (RowPass::t); out: t/|Y|
  // The energy ledger (material/models/history_ledger.hpp HistoryLedger::Row, and the
  // committed and trial force states and extensions; old_force null and r_old null: 0).
  const double* old_force = nullptr;
  const double* old_extension = nullptr;
  double* force_trial = nullptr;      // null: the pass keeps no trial t and e (LedgerRows)
  double* extension_trial = nullptr;
  const uint8_t* booked_committed = nullptr;
  uint8_t* booked_trial = nullptr;  // with booked_in_place, the committed flags themselves
  bool booked_in_place = false;     // LedgerRows::in_place: no copy of the flags, a booking sets the committed one
  uint8_t* pending_set = nullptr;
  double* pending_amount = nullptr;
  // The committed t_n and e_n rebuilt from the previous pass (history_ledger.hpp LedgerRows)
  // when r_old is set: |Y_n| per bond (RowPass::r_old), and t_n per bond of the row kept by
  // the row's first visit for a later one (scratch, indexed by k), since the first visit
  // overwrites q. With force_committed set, the rebuilt values are also written there.
  const double* r_old = nullptr;
  double* t_old = nullptr;
  bool revisit = false;
  double* force_committed = nullptr;
  double* extension_committed = nullptr;
};

// Row i's bonds [first, last) and the ledger's arrays, as every ordinary model's row hands
// them to its lanes; `thermal`: the models that take the thermal strain; `mode`: what
// the ledger's begin_rows said of this pass.
inline RowBonds row_bonds(const RowPass& pass, HistoryLedger& ledger, const LedgerRows& mode, std::size_t i,
                          bool thermal) {
  const System& s = pass.system;
  const auto& B = s.bonds;
  const HistoryLedger::Row row = ledger.row();
  RowBonds b;
  b.first = B.begin(i), b.last = B.end(i), b.i = i;
  b.r = pass.deformed, b.intact = B.intact.data(), b.kind = B.kind.data(), b.nbr = B.nbr.data();
  b.kinds = pass.kinds;
  b.eps = thermal && !s.thermal_strain.empty() ? s.thermal_strain.data() : nullptr;
  b.q = pass.t;
  if (!mode.zero) b.old_force = ledger.force.committed(), b.old_extension = ledger.extension.committed();
  if (mode.write_trial) b.force_trial = ledger.force.trial(), b.extension_trial = row.extension_trial;
  b.booked_committed = row.booked_committed, b.booked_trial = row.booked_trial;
  if (mode.in_place) b.booked_trial = ledger.booked.committed(), b.booked_in_place = true;
  b.pending_set = row.pending_set, b.pending_amount = row.pending_amount;
  if (mode.rebuild) {  // (t_old: set by a model whose row visits its bonds twice)
    if (!pass.r_old) throw Error("internal error: an ordinary row without the previous pass's |Y|");
    b.r_old = pass.r_old;
    if (mode.materialize) b.force_committed = ledger.force.committed(), b.extension_committed = ledger.extension.committed();
  }
  return b;
}

// The sums of a row: sum_k of the models' weighted squares, the step's trapezoidal work,
// the bookings of bonds broken since the commit (all per unit V_i), and whether a bond
// released energy or yielded (an inelastic step).
struct RowSums {
  double norm = 0;  // elastic_plastic: ||e^d_tr||_w^2 (the yield norm / alpha^2)
  double dev = 0;   // elastic_plastic: ||e^de||_w^2; viscoelastic: sum omega V_j (springs); microplastic: W
  double work = 0;
  double booked = 0;
  bool inelastic = false;
};

// elastic_plastic (material/models/elastic_plastic.cpp force_row): the trial deviatoric
// extension e^d - e^dp_n, its norm, and with `force` the return's scaling beta of it, the
// trial plastic extensions, the force states and the ledger.
struct EpRow {
  // e^dp_n per bond and the trial e^dp; both null for a row that never yielded, whose
  // e^dp are 0 in both copies and stay so while beta = 1 (ep + 0 * e^de = ep: the bits the
  // row would write).
  const double* ep = nullptr;
  double* ep_trial = nullptr;
  double* ede = nullptr;  // scratch per bond of the row (indexed by k): the trial extension
  double theta = 0, alpha = 0, p_coef = 0;
  int dim = 3;
};
RowSums ep_row(const RowBonds& b, const EpRow& m, double beta, bool norm, bool force);

// viscoelastic (material/models/viscoelastic.cpp force_row): e^d, the branches' back
// extensions, the force states and the ledger. The committed e^d_n of a bond is rebuilt
// as e_n - theta_n |xi| / d from the ledger's committed extension and theta_n, the row's
// committed dilatation (the operations that computed it, so its bits).
constexpr int kMaxBranches = 4;
struct VesRow {
  double theta_old = 0;  // theta_n of the row
  const double* back_old[kMaxBranches] = {};
  double* back_trial[kMaxBranches] = {};
  double decay[kMaxBranches] = {}, from_old[kMaxBranches] = {}, from_new[kMaxBranches] = {};
  double lambda[kMaxBranches] = {};
  int branches = 0;
  double lambda_inf = 1, theta = 0, alpha = 0, p_coef = 0;
  int dim = 3;
};
RowSums ves_row(const RowBonds& b, const VesRow& m);

// microplastic (material/models/microplastic.cpp force_row): the bonds' return maps, the
// force states, W and the ledger.
struct MicroRow {
  const double* sbar_old = nullptr;
  double* sbar_trial = nullptr;
  double c = 0, yield = 0;
};
RowSums micro_row(const RowBonds& b, const MicroRow& m);

// The scalar general pass's two bond sweeps (solver/forces_ordinary.cpp) in the same lanes.
struct Sweep {
  const Point4* pt = nullptr;               // y, w = s0 of the pass (System::model.packed)
  const Point4* kind_dilatation = nullptr;  // per kind {L, 1/L, omega V_j, 0}
  const Point4* kinds = nullptr;            // per kind {L, omega, omega V_j, V_j}
  const KindCoefficients* kc = nullptr;     // per kind (damage weight, family contact)
  const uint32_t* nbr = nullptr;
  const uint32_t* kind = nullptr;
  const uint64_t* offset = nullptr;
  const uint64_t* rev = nullptr;    // the reverse bond's index
  const uint32_t* rev32 = nullptr;  // the same in 4 bytes (read instead of rev when set)
  uint8_t* intact = nullptr;
  double* deformed = nullptr;       // |Y| per bond (every bond), written by the breaking sweep
  double* q = nullptr;              // the force scalars q = t/|Y|
  double* intact_weight = nullptr;  // per particle
  const double* eps = nullptr;      // thermal strain per particle, or null
  const double* soft = nullptr;     // critical-stretch factor per particle, or null
  uint64_t total = 0;               // bonds
  bool after = false;               // break_after_force: a breaking bond still acts in this pass
  bool contact = false;             // short-range contact between family pairs (family_contact)
};
// Pass 1 of row i before its model: breaking (critical stretch), |Y| of every bond, the
// smallest stretch of the intact bonds, the energy of the broken ones and sum_j omega V_j
// |xi| e over the bonds that act in this pass.
struct BreakOut {
  double smin, lost, dilatation;
  uint64_t broken;
};
// r_old (indexed by bond, the row's bonds at least): |Y| of the previous pass, as the sweep
// found it in `deformed` before writing this pass's (RowPass::r_old).
BreakOut break_row(const Sweep& s, std::size_t i, double* r_old);
// Pass 2 of row i: f_i = sum_j V_j (q_ij + q_ji) Y over the acting bonds, plus the family
// contact (w: its energy density; state/system.hpp family_contact).
struct SumOut {
  double fx, fy, fz, w;
};
SumOut sum_row(const Sweep& s, std::size_t i);

// Whether the lanes run (AVX-512 here): the models' force_row and the pass call the
// functions above only then. lanes_target() names the choice ("avx512" or "scalar");
// set_lanes_target makes one the machine has ("best": the lanes where they run), for tests
// that compare them; false if the machine lacks it.
bool wide();
const char* lanes_target();
bool set_lanes_target(const char* name);

}  // namespace horizon::lanes
