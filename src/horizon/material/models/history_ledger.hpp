#pragma once
// The energy a history model (elastic_plastic, viscoelastic) dissipates in a step, so
// that kinetic + stored + dissipated - external work closes to the time integrator's
// error whatever happens in the step: plastic flow, viscous flow, bonds broken.
//
// Per particle i, over the step n -> n+1 of the solver:
//   D_i = sum_j (t_n + t_n+1)/2 (e_n+1 - e_n) V_j  -  (W_n+1 - W_n)  -  B_i,
// the trapezoidal work of i's bond forces (the work velocity Verlet does to second order,
// seed 003 eq. 66 discrete: sum_i f_i . du_i = sum_ij t_ij de_ij V_i V_j), less the
// change of the stored energy density W_i, less B_i, what the general force pass already
// booked as dissipated for the bonds of i it broke in this pass: (1/2) t e V_j with t the
// force state of the previous pass along the current bond (solver/forces_general.cpp).
// Without a broken bond, D_i is exactly the trapezoidal plastic work
// sum_j (t^d_n + t^d_n+1)/2 (e^dp_n+1 - e^dp_n) V_j of the elastic-plastic model, and
// exactly the dashpot work (alpha/2) sum_b lambda_b sum_j omega (q_n + q_n+1)
// (e^b_n+1 - e^b_n) V_j (q = e^d - e^b) of the viscoelastic one (both models' headers):
// their W is quadratic in e and their history, and t is its gradient. A broken bond that
// held plastic or back extension released less than (1/2) t e; the difference comes back
// through W here.
// Summed over i (with the bookings) this is the step's work less the change of W, whatever
// the booking: the energy W really loses when a bond leaves the dilatation sum, which in
// the elastic-plastic model can be negative (a tensile bond broken at a compressed
// particle raises k' theta^2/2; docs/models/elastic_plastic.md "Energy, damage").
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "horizon/core/error.hpp"
#include "horizon/core/vec3.hpp"
#include "horizon/core/state_archive.hpp"
#include "horizon/family/bonds.hpp"
#include "horizon/kernels/ordinary.hpp"
#include "horizon/state/system.hpp"

namespace horizon {

// A per-bond history array of a model, committed and trial: the force pass reads the
// committed copy and writes the trial one; a commit makes the trial copy the committed one
// by trading the two (no copy: the bond arrays are the largest a step streams). A commit
// that follows no pass (`fresh` false) changes nothing, as a copy of an unchanged trial
// state would not. Rows that a pass does not compute (another rank's) are never read.
template <class T>
class BondHistory {
 public:
  const T* committed() const { return buf_[cur_].data(); }
  T* committed() { return buf_[cur_].data(); }
  const T* trial() const { return buf_[1 - cur_].data(); }
  T* trial() { return buf_[1 - cur_].data(); }
  std::size_t size() const { return buf_[0].size(); }
  void assign(std::size_t n, const T& v) {
    buf_[0].assign(n, v);
    buf_[1].assign(n, v);
    cur_ = 0;
  }
  void flip() { cur_ = 1 - cur_; }
  // Frees both copies (HistoryLedger: while the committed values live elsewhere).
  void release() {
    std::vector<T>().swap(buf_[0]);
    std::vector<T>().swap(buf_[1]);
    cur_ = 0;
  }
  // The committed copy (and a reference to the array of a model's output fields).
  const std::vector<T>& committed_vector() const { return buf_[cur_]; }
  // Checkpoint and restart: the two copies under their names. After a commit (not
  // fresh) the trial copy is the committed one, as the model's state defines it.
  void checkpoint(StateArchive& a, const std::string& name, const std::string& trial_name, bool fresh) {
    if (!fresh) buf_[1 - cur_] = buf_[cur_];
    a.io_bonds(name, buf_[cur_]);
    a.io_bonds(trial_name, buf_[1 - cur_]);
  }

 private:
  std::vector<T> buf_[2];
  int cur_ = 0;
};

// The general force pass books a bond in the pass that breaks it: its flag is 0 (broken
// before the forces) or 2 (broken after them: it still acts in this pass).
using kernels::bond_booked_now;

// What the force pass booked for it, per unit V_i: (1/2) (T_old . Y/|Y|) e V_j, T_old the
// bond's force state of the previous pass (still in ForcePass::T when the model runs).
inline double broken_bond_booking(const Vec3& T_old, const Vec3& Y, double length, double e, double volume) {
  return length > 0 ? 0.5 * dot(T_old, Y) / length * e * volume : 0.0;
}
// The same in the scalar pass (solver/forces_ordinary.cpp), whose force states lie along
// the bond: T_old . Y/|Y| is taken as the previous pass's scalar t_old (their difference,
// t_old (1 - cos) of the bond's turn in one step, is far below the ledger's error; RowPass::t
// holds t_old for a bond broken in the pass), exactly as that pass books the bond's energy
// when it breaks it, so that the two cancel.
using kernels::broken_bond_booking;  // (kernels/ordinary.hpp)

// D_i from the step's work, the change of W and the booking (all per unit V_i).
using kernels::inelastic_loss;  // (kernels/ordinary.hpp)

// How a pass of the scalar form's lanes reads the committed t_n and e_n of the ledger
// (HistoryLedger::begin_rows). They are the last commit's force state and extension, and
// when that commit followed a single pass of the lanes without a thermal strain (the
// explicit step), that pass left them behind in System::model: e_n = |Y_n| - |xi| (the
// expression that computed it) and t_n = q_n |Y_n| (q = t/|Y|: t to round-off), |Y_n| as
// the breaking sweep reads it before writing this pass's (RowPass::r_old), q_n the row's q
// before the row writes it, or for a bond this pass broke, t_n itself (RowPass::t). Then
// the ledger's committed arrays are not read, and when a commit follows the pass
// (System::model.commit_follows) its trial arrays are not written either: 48 bytes a bond
// and step less to stream (docs/benchmarks.md). Every pass that can rebuild them does, so
// a run's ledger does not depend on its thread or rank count; only a run whose passes
// cannot (static solvers, a thermal strain, the scalar rows) reads the stored arrays.
//
// When the commit follows as well (the explicit step), the pass also writes its history
// (the booked flags, and the models' own per-bond arrays: e^dp, the back extensions, the
// plastic stretches) over the committed copy, bond by bond after reading it, and the commit
// trades nothing (`in_place`): a trial array written without being read costs the line's
// read as well as its write, 8 bytes a bond and step more for each such array
// (docs/benchmarks.md). No pass reads the committed copy between the pass and its commit.
struct LedgerRows {
  bool rebuild = false;      // t_n, e_n from RowPass::r_old and RowPass::t
  bool zero = false;         // t_n = e_n = 0 (no commit yet), not read from arrays
  bool write_trial = true;   // write the trial t and e (a later pass or commit reads them)
  bool materialize = false;  // write the rebuilt t_n, e_n into the committed arrays
  bool in_place = false;     // the history written over the committed copy (above)
};

// The ledger state of a history model, committed and trial: per directed bond what the
// step's work needs (the scalar force state t and the extension e of the last commit, and
// whether the bond's breaking was booked), per particle the stored energy density W and
// the trial loss D_i [J/m^3]. The model calls begin_pass once per force pass, open_bond for
// each bond of a pass and sets force_trial(), and commit_particle for each particle and
// commit_bonds once at its commit. Per-bond arrays are flat (8 or 1 bytes a bond), as the
// force pass streams them.
struct HistoryLedger {
  BondHistory<double> force, extension;  // t and e (t = 0 when the bond did not act)
  BondHistory<uint8_t> booked;           // the force pass has booked the bond as broken (or it was precracked)
  // Bonds broken since the commit: the booking, computed in the pass that broke the bond
  // (whose force states still hold the previous pass's) and reused by the later passes
  // before the commit (a static solver's iterations after a breaking round). Never read
  // once the bond's breaking is committed (booked), so a commit need not clear it.
  std::vector<double> pending_amount;
  std::vector<uint8_t> pending_set;
  std::vector<double> stored, stored_trial, loss_trial;
  bool fresh = false;  // a force pass ran since the last commit
  // The committed force and extension are not in the arrays (LedgerRows): the last commit
  // followed a pass that rebuilt them and kept no trial copy; the pass (System::model.passes)
  // and whether it was a plain scalar pass, its |Y| and q left in System::model.
  bool virtual_committed = false;
  // No commit since the bonds were sized: the committed force and extension are 0. In both
  // states the arrays of t and e are not allocated (32 bytes a bond: a quarter of the
  // elastic-plastic bench deck's memory, docs/benchmarks.md); a pass or a checkpoint that
  // needs them allocates them (ensure_arrays, materialize).
  bool zero_committed = false;
  bool kept_trial = true;  // the passes since the commit wrote the trial t and e
  // The pass since the commit wrote its history over the committed copy (LedgerRows::in_place):
  // the commit then trades no copies, and no other pass may come before it.
  bool in_place = false;
  uint64_t committed_pass = 0;
  bool committed_plain = false;
  const System* system = nullptr;  // of the last pass (materialize at a checkpoint)

  // A pass of the scalar form begins (`lanes`: its rows run in the lanes, which rebuild,
  // and it gives them RowPass::r_old): how its rows treat t_n and e_n (LedgerRows).
  LedgerRows begin_rows(const System& s, bool lanes) {
    not_in_place();
    const bool rebuild = lanes && committed_plain && s.model.passes == committed_pass + 1;
    if (virtual_committed && !rebuild) begin_pass();  // fails: nothing left to rebuild from
    fresh = true;
    system = &s;
    LedgerRows m;
    m.rebuild = rebuild;
    // Before the first commit the lanes read t_n = e_n = 0 as they rebuild them later. The
    // trial t and e are left out only when the next pass can rebuild them from this one: a
    // plain pass of the lanes (no thermal strain: commit_bonds' committed_plain).
    m.zero = lanes && zero_committed;
    const bool plain = lanes && s.thermal_strain.empty();
    m.write_trial = !((rebuild || m.zero) && plain && s.model.commit_follows);
    m.materialize = rebuild && m.write_trial && virtual_committed;
    m.in_place = lanes && s.model.commit_follows;
    if (m.write_trial) {  // (the arrays hold the committed values, or 0 before the first commit)
      ensure_arrays();
      m.zero = false;
    }
    if (m.materialize) virtual_committed = false;
    kept_trial = m.write_trial;
    in_place = m.in_place;
    return m;
  }
  // Any other pass (the vector form, the scalar rows): the stored arrays.
  void begin_pass() {
    not_in_place();
    if (virtual_committed)
      throw Error("internal error: the energy ledger's committed force states were rebuilt from the last pass and "
                  "are gone (history_ledger.hpp LedgerRows)");
    ensure_arrays();
    fresh = true;
    kept_trial = true;
  }
  // The arrays of t and e allocated; 0 in both copies when they were not (zero_committed).
  void ensure_arrays() {
    if (force.size() != booked.size()) {
      force.assign(booked.size(), 0);
      extension.assign(booked.size(), 0);
    }
    zero_committed = false;
  }
  // The committed copies hold the last commit's state (not a pass's written in place).
  void not_in_place() const {
    if (in_place)
      throw Error("internal error: a pass that wrote its history in place was not committed before another pass or "
                  "a checkpoint (history_ledger.hpp LedgerRows::in_place)");
  }
  // The committed t_n, e_n rebuilt into the arrays from the committed pass's |Y| and q
  // (System::model), as the lanes rebuild them; before a checkpoint.
  void materialize() {
    if (zero_committed) ensure_arrays();
    if (!virtual_committed) return;
    if (fresh || !system || system->model.passes != committed_pass)
      throw Error("internal error: the energy ledger cannot rebuild its committed force states here");
    ensure_arrays();
    const auto& B = system->bonds;
    const auto& M = system->model;
    double* t = force.committed();
    double* e = extension.committed();
    for (std::size_t k = 0; k < force.size(); ++k) {
      const double r = M.deformed_length[k];
      t[k] = M.force_scalar[k] * r;
      e[k] = r - M.kind[B.kind[k]].length;
    }
    virtual_committed = false;
  }

  // Checkpoint and restart (core/state_archive.hpp).
  void checkpoint(StateArchive& a) {
    if (!a.loading()) not_in_place(), materialize();
    force.checkpoint(a, "ledger_force", "ledger_force_trial", fresh);
    extension.checkpoint(a, "ledger_extension", "ledger_extension_trial", fresh);
    booked.checkpoint(a, "ledger_booked", "ledger_booked_trial", fresh);
    a.io_bonds("ledger_pending_amount", pending_amount);
    a.io_bonds("ledger_pending_set", pending_set);
    a.io_particles("ledger_stored", stored);
    a.io_particles("ledger_stored_trial", stored_trial);
    a.io_particles("ledger_loss_trial", loss_trial);
    uint8_t f = fresh ? 1 : 0;
    a.io("ledger_fresh", f);
    fresh = f != 0;
    if (a.loading())
      virtual_committed = false, zero_committed = false, kept_trial = true, committed_pass = 0, committed_plain = false;
  }

  void size_particles(std::size_t n) {
    stored.assign(n, 0);
    stored_trial.assign(n, 0);
    loss_trial.assign(n, 0);
  }
  // Sizes the bond arrays when the bond count changed; true when it did.
  bool size_bonds(const Bonds& B) {
    const std::size_t nb = B.size();
    if (booked.size() == nb) return false;
    force.release();  // (allocated when a pass or a checkpoint needs them: zero_committed)
    extension.release();
    zero_committed = true;
    booked.assign(nb, 0);
    pending_amount.assign(nb, 0);
    pending_set.assign(nb, 0);
    // Bonds broken before the first pass (precracks) were never booked as dissipated.
    for (std::size_t k = 0; k < nb; ++k) booked.committed()[k] = booked.trial()[k] = B.intact[k] ? 0 : 1;
    virtual_committed = false, kept_trial = true, in_place = false, committed_pass = 0, committed_plain = false;
    return true;
  }
  // Starts bond k's trial record at extension e; adds to `booked` what the force pass
  // booked for it if it broke since the commit (`booking()`: its amount, called only
  // then). Returns true when it did. The model then sets force.trial()[k].
  template <class Booking>
  bool open(uint64_t k, uint8_t intact, double e, double& booked_sum, Booking&& booking) {
    extension.trial()[k] = e;
    const uint8_t was = booked.committed()[k];
    booked.trial()[k] = was;
    if (bond_booked_now(intact, was)) {
      if (!pending_set[k]) {
        pending_amount[k] = booking();
        pending_set[k] = 1;
      }
      booked_sum += pending_amount[k];
      booked.trial()[k] = 1;
      return true;
    }
    if (pending_set[k]) pending_set[k] = 0;  // a solver restored the bond (a failed static increment)
    return false;
  }
  // The vector form of the general pass (T_old: the bond's force state of the previous pass).
  bool open_bond(uint64_t k, uint8_t intact, const Vec3& T_old, const Vec3& Y, double length, double e,
                 double volume, double& booked_sum) {
    return open(k, intact, e, booked_sum, [&] { return broken_bond_booking(T_old, Y, length, e, volume); });
  }
  // The scalar form (t_old: the bond's scalar force state of the previous pass).
  bool open_bond(uint64_t k, uint8_t intact, double t_old, double length, double e, double volume,
                 double& booked_sum) {
    return open(k, intact, e, booked_sum, [&] { return broken_bond_booking(t_old, length, e, volume); });
  }
  // The per-bond arrays of one pass as plain pointers, taken once per row by the scalar
  // pass's rows: open() through the ledger's vectors reloads their pointers after every
  // store of a flag (a byte store may alias anything), bond by bond. The same operations
  // as open() and open_bond() (scalar form) on the same arrays: the portable booking of
  // kernels/ordinary.hpp (ledger_open_bond), which the flat rows call too.
  struct Row : kernels::LedgerBonds {
    bool open_bond(uint64_t k, uint8_t intact, double t_old, double length, double e, double volume,
                   double& booked_sum) const {
      return kernels::ledger_open_bond(*this, k, intact, t_old, length, e, volume, booked_sum);
    }
  };
  Row row() {
    return {{extension.trial(), booked.committed(), booked.trial(), pending_set.data(), pending_amount.data()}};
  }
  // The trial bond records become the committed ones; true when the model must trade its
  // own bond arrays' copies the same way (a pass ran since the last commit and did not
  // write in place). A pass that kept no trial t and e leaves them to be rebuilt, one that
  // wrote in place leaves nothing to trade (LedgerRows).
  bool commit_bonds(const System& s) {
    if (!fresh) return false;
    if (kept_trial) {
      force.flip();
      extension.flip();
    }
    virtual_committed = !kept_trial;
    if (virtual_committed) force.release(), extension.release();  // (rebuilt when asked: materialize)
    zero_committed = false;
    committed_pass = s.model.passes;
    committed_plain = s.model.plain_scalar_pass == s.model.passes;
    const bool trade = !in_place;
    if (trade) booked.flip();
    fresh = false;
    in_place = false;
    return trade;
  }
  // Makes particle i's trial stored energy the committed one; returns its loss [J/m^3].
  double commit_particle(std::size_t i) {
    stored[i] = stored_trial[i];
    const double loss = loss_trial[i];
    loss_trial[i] = 0;
    return loss;
  }
  // What commit would add to the ledger [J] (Model::pending_dissipation).
  double pending_energy(const std::vector<uint32_t>& particles, const std::vector<double>& volume) const {
    double sum = 0;
    for (uint32_t i : particles) sum += loss_trial[i] * volume[i];
    return sum;
  }
};

}  // namespace horizon
