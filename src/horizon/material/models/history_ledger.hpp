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
#include <cmath>
#include <cstdint>
#include <vector>

#include "horizon/core/vec3.hpp"
#include "horizon/core/state_archive.hpp"
#include "horizon/family/bonds.hpp"

namespace horizon {

// What the ledger keeps of each directed bond at the committed state.
struct BondLedger {
  double force = 0;      // the scalar force state t (0 when the bond did not act)
  double extension = 0;  // e = |Y| - |xi|
  uint8_t booked = 0;    // the force pass has booked the bond as broken (or it was precracked)
};

// The general force pass books a bond in the pass that breaks it: its flag is 0 (broken
// before the forces) or 2 (broken after them: it still acts in this pass).
inline bool bond_booked_now(uint8_t intact, uint8_t booked) { return !booked && intact != 1; }

// What the force pass booked for it, per unit V_i: (1/2) (T_old . Y/|Y|) e V_j, T_old the
// bond's force state of the previous pass (still in ForcePass::T when the model runs).
inline double broken_bond_booking(const Vec3& T_old, const Vec3& Y, double length, double e, double volume) {
  return length > 0 ? 0.5 * dot(T_old, Y) / length * e * volume : 0.0;
}

// The booking of a bond broken since the last commit, computed in the pass that broke it
// (whose T still holds the previous force state) and reused by the later passes before
// the commit (a static solver's iterations after a breaking round, which find T zeroed).
struct PendingBooking {
  double amount = 0;
  uint8_t set = 0;
};
inline double pending_booking(PendingBooking& p, const Vec3& T_old, const Vec3& Y, double length, double e,
                              double volume) {
  if (!p.set) {
    p.amount = broken_bond_booking(T_old, Y, length, e, volume);
    p.set = 1;
  }
  return p.amount;
}

// D_i from the step's work, the change of W and the booking (all per unit V_i).
inline double inelastic_loss(double work, double stored_change, double booked) { return work - stored_change - booked; }

// The ledger state of a history model, committed and trial: per directed bond what the
// step's work needs, per particle the stored energy density W and the trial loss D_i
// [J/m^3]. The model calls open_bond for each bond of a pass, loss for each particle,
// and commit_bond / commit_particle at its commit.
struct HistoryLedger {
  std::vector<BondLedger> bond, bond_trial;
  std::vector<PendingBooking> pending;  // bonds broken since the commit
  std::vector<double> stored, stored_trial, loss_trial;

  // Checkpoint and restart (core/state_archive.hpp).
  void checkpoint(StateArchive& a) {
    a.io_bonds("ledger_bond", bond);
    a.io_bonds("ledger_bond_trial", bond_trial);
    a.io_bonds("ledger_pending", pending);
    a.io_particles("ledger_stored", stored);
    a.io_particles("ledger_stored_trial", stored_trial);
    a.io_particles("ledger_loss_trial", loss_trial);
  }

  void size_particles(std::size_t n) {
    stored.assign(n, 0);
    stored_trial.assign(n, 0);
    loss_trial.assign(n, 0);
  }
  // Sizes the bond arrays when the bond count changed; true when it did.
  bool size_bonds(const Bonds& B) {
    const std::size_t nb = B.size();
    if (bond.size() == nb) return false;
    bond.assign(nb, BondLedger{});
    pending.assign(nb, PendingBooking{});
    // Bonds broken before the first pass (precracks) were never booked as dissipated.
    for (std::size_t k = 0; k < nb; ++k) bond[k].booked = B.intact[k] ? 0 : 1;
    bond_trial = bond;
    return true;
  }
  // Starts bond k's trial record at extension e; adds to `booked` what the force pass
  // booked for it if it broke since the commit (T_old: its force state of the previous
  // pass). Returns true when it did.
  bool open_bond(uint64_t k, uint8_t intact, const Vec3& T_old, const Vec3& Y, double length, double e,
                 double volume, double& booked) {
    const BondLedger& old = bond[k];
    BondLedger& now = bond_trial[k];
    now = old;
    now.extension = e;
    if (bond_booked_now(intact, old.booked)) {
      booked += pending_booking(pending[k], T_old, Y, length, e, volume);
      now.booked = 1;
      return true;
    }
    if (pending[k].set) pending[k] = PendingBooking{};  // a solver restored the bond (a failed static increment)
    return false;
  }
  void commit_bond(uint64_t k) {
    bond[k] = bond_trial[k];
    pending[k] = PendingBooking{};
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
