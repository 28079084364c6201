#pragma once
// The discretised body a solver advances (the run's state): particles, bonds, and
// per-particle model coefficients. Built from a Config by build_system()
// (solver/build.hpp); tests build small ones in code. This room (state/) stands below
// the models: they read and write these arrays; solvers and drivers sit above.
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "horizon/core/point4.hpp"
#include "horizon/core/state_archive.hpp"
#include "horizon/deck/config.hpp"
#include "horizon/family/bonds.hpp"
#include "horizon/geometry/particles.hpp"
#include "horizon/state/heat_state.hpp"
#include "horizon/state/model_set.hpp"
#include "horizon/state/short_range.hpp"

namespace horizon {

struct FeRegion;  // fe/fe_region.hpp
struct System;

// What the rooms below fe/ (the force pass, the models, commit_history) need of the
// classical finite-element regions coupled to the particles: fe/fe_region.hpp's FeRegion
// implements it. The force pass calls these hooks without knowing of elements, so the
// FE room plugs into the state instead of the force pass reaching into the FE room.
struct FeCoupling {
  FeCoupling() = default;
  FeCoupling(const FeCoupling&) = default;
  FeCoupling(FeCoupling&&) = default;
  FeCoupling& operator=(const FeCoupling&) = default;
  FeCoupling& operator=(FeCoupling&&) = default;
  virtual ~FeCoupling() = default;
  // 1 for each particle whose force the elements own (an FE node), else 0.
  std::vector<uint8_t> owned_particle;
  // Before the bond loops: the interpolated particles follow the elements.
  virtual void interpolate(System& s) = 0;
  // After the bond loops: overwrites the force (and, with `energy`, the energy) density
  // of the FE-owned nodes with the element assembly.
  virtual void apply(System& s, bool energy) = 0;
  // The elements' trial history becomes their history (commit_history).
  virtual void commit(System& s) = 0;
};

// The unified models (Model::unified()) write their scalar force state on bond i->j as
//   t_ij = omega_ij * ( P_i |xi| + Q_i e_ij + R_i e_ij / |xi| ),   e = |Y| - |xi|,
// and the force density on i is  sum_j (t_ij + t_ji) Y_ij/|Y_ij| V_j  (seed 003 eq. 33
// with T = t M; digest sec. 9). The bond loop is therefore the same for all of them:
//   a bond-based part R_i (material/models/pmb.cpp: R = c/2, P = Q = 0), and a dilatation
//   part P_i = theta_i (a_i - b_i/d), Q_i = b_i with a_i = dilatation_coef, b_i =
//   deviatoric_coef, theta = (d/m) sum_j omega |xi| e V_j (material/models/lps.cpp).
// Materials differ only in these per-particle coefficients, so bonds between bodies
// of different materials (or models) need no special case. Runs with other models take
// the general force pass (solver/forces_general.hpp); the shared arrays below that are
// not P/Q/R (spring, critical stretch, alpha, contact micromodulus, weighted volume)
// serve every model.
// Per bond kind (Bonds::kinds): what the force loops need, computed once by setup_model
// (build_kind_coefficients) so that a bond costs one table look-up.
struct alignas(64) KindCoefficients {
  // In pairs, as the SIMD bond loops load them (solver/forces.cpp).
  double length = 0;      // L = |xi|
  double inv_length = 0;  // 1/L: stretch = e * (1/L), the same bits from either end
  double pair = 0;        // omega V_j (R_i + R_j) / L: the bond-based part of (t_ij + t_ji) V_j per unit e
  double contact_d2 = 0;  // d_ij^2 of the short-range contact (0: no contact)
  double damage = 0;      // weight of the bond in the damage field (output.damage_measure)
  double wv = 0;          // omega V_j (V_j partial-volume scaled)
  double contact_d = 0;   // d_ij
  double contact_k = 0;   // k_ij V_j / delta: contact force density per unit overlap
};

// Short-range contact of a family pair (intact or broken), Y = y_j - y_i: the force
// density on i when the two are closer than the kind's contact distance d_ij, and its
// energy share (state/short_range.hpp). Returns false when they are apart.
inline bool family_contact(const KindCoefficients& c, const Vec3& Y, Vec3& f, double& w) {
  const double r2 = dot(Y, Y);
  if (!(r2 < c.contact_d2) || r2 == 0) return false;
  const double r = std::sqrt(r2), overlap = c.contact_d - r;
  f = (-c.contact_k * overlap / r) * Y;  // pushes i away from j
  w = 0.25 * c.contact_k * overlap * overlap;
  return true;
}

struct ModelCoefficients {
  std::vector<double> weighted_volume;  // m_i = sum omega |xi|^2 V_j, from the actual family
  std::vector<double> dilatation_coef;  // a_i: P_i = theta_i (a_i - b_i/d); 0 for bond-based
  std::vector<double> deviatoric_coef;  // b_i -> Q
  std::vector<double> pair_coef;        // -> R (bond-based part)
  std::vector<double> theta;            // dilatation
  std::vector<double> P;                // per-step P_i (depends on theta)
  std::vector<double> critical_stretch; // +inf: never breaks
  std::vector<double> spring;           // c_eq/2, bond-based equivalent, for the stable time step
  // The critical stretch law with compression (DamageConfig::alpha): bond i-j breaks
  // when its stretch exceeds min(s0_i, s0_j), s0_i = critical_stretch_i - alpha_i *
  // min_stretch_i, min_stretch_i the smallest stretch of i's bonds at the previous pass.
  std::vector<double> alpha;
  std::vector<double> min_stretch;      // 0 before the first pass
  bool break_after_force = false;       // DamageConfig::break_after_force
  std::vector<double> damage_total;     // sum of the damage weights over i's family (after precracks)
  std::vector<double> intact_weight;    // the same over i's intact bonds (updated as bonds break)
  std::vector<double> contact_micromodulus;  // c_i of the short-range contact
  DamageMeasure damage_measure = DamageMeasure::weighted;  // of the kinds' damage weights
  // Per bond kind. With bonds that keep their own lengths (Bonds::length_per_bond) the
  // fields that depend on |xi| (length, inv_length, contact_d, contact_d2) are 0 and
  // `pair` is omega V_j (R_i + R_j): the force loops finish them per bond (forces.cpp).
  std::vector<KindCoefficients> kind;
  std::vector<Point4> kind_dilatation;  // per kind {L, 1/L, omega V_j, 0} (state-based pass 1)
  std::vector<Point4> kind_force;       // per kind {L, omega V_j, pair, d^2} (state-based pass 2)
  // Per kind {L, omega, omega V_j, V_j}, as the ordinary models' rows read them
  // (material/models/ordinary_lanes.hpp): filled by the scalar general pass when empty
  // (solver/forces_ordinary.cpp), emptied whenever the kinds are built.
  std::vector<Point4> kind_rows;
  // Scratch of the force pass: current positions packed with a per-particle value
  // (the critical stretch, then P), and the next min_stretch.
  std::vector<Point4> packed;
  std::vector<double> min_stretch_next;
  // State-based models: |Y| of each bond, written by the dilatation pass and read by the
  // force pass of the same step (one square root per bond and step instead of two).
  std::vector<double> deformed_length;
  // The general force pass (solver/forces_general.hpp): the force state T of every bond
  // (written by the models) and the index of bond j->i for bond i->j.
  std::vector<Vec3> force_state;
  std::vector<uint64_t> reverse;
  // The same in 4 bytes, for the scalar form's sum (solver/forces_ordinary.cpp) when the
  // bonds number fewer than 2^32: half the index's bytes in the pass's last sweep.
  std::vector<uint32_t> reverse32;
  // Its scalar form (solver/forces_ordinary.cpp): q = t/|Y| of every bond, T = q Y.
  std::vector<double> force_scalar;
  // The force passes so far (compute_forces counts them), and the last scalar pass that
  // ran the ordinary lanes without a thermal strain (0: none): after such a pass,
  // deformed_length and force_scalar hold its |Y| and q for every computed row, from which
  // the ordinary models rebuild their ledger's committed t and e instead of storing them
  // (material/models/history_ledger.hpp LedgerMode). commit_follows: the caller commits the
  // pass's history before the next pass (the explicit step), so a model need not keep
  // the pass's trial t and e either.
  uint64_t passes = 0;
  uint64_t plain_scalar_pass = 0;
  bool commit_follows = false;
  // Its affine form (solver/forces_affine.cpp): a record of ten numbers per particle
  // (kernels/affine.hpp) instead of a force state per bond, and the
  // positions of the pass that wrote them (a bond broken in the next pass books its energy
  // from the force state they give).
  std::vector<double> affine_record;
  std::vector<Vec3> affine_position;
  bool state_based = false;             // any particle whose forces reach two horizons (tangent probing)
  int reach_hops = 0;                   // more bonds than that (bond_associated: 3), for the tangent probing
  double dim = 3;                       // d in theta = (d/m) sum ...
};

// Sizes every per-particle model array to n, neutral: no bond-based or state-based
// coefficients, bonds that never break, no contact (setup_model and setup_nonlinear
// then fill in their models).
void reset_model_arrays(ModelCoefficients& M, std::size_t n);

struct Decomposition;

struct System {
  int dimension = 3;
  // The displacement components the solvers advance, bit c for component c: the first
  // `dimension` for solids; z alone for beams and plates (the transverse deflection),
  // all three for shells (deck structure, docs/input.md). 0: by the dimension.
  uint8_t active_components = 0;
  bool active(int c) const { return active_components ? ((active_components >> c) & 1u) != 0 : c < dimension; }
  double horizon = 0;  // the deck's: with bodies of their own horizons, the largest
  double spacing = 0;
  // Some bond lies in one end's family alone (bodies of different horizons: BondKind::one_way,
  // omega_ij = 0 on it). The force passes that evaluate both directions of a bond from one
  // row's weight (the unified fast loops, the affine pass, the analytic tangent) assume
  // omega_ij = omega_ji; such a run takes the general pass, which reads t_ji from j's row.
  bool one_way_bonds = false;
  // The largest particle-side penalty stiffness of the rigid projectiles' contact, d b / d d
  // [N/m^4] (contact/rigid_contact.hpp penalty_stiffness): stable_time_step adds it to every
  // particle's bond stiffness. 0 without projectiles.
  double contact_stiffness = 0;
  Particles particles;
  Bonds bonds;
  ModelCoefficients model;
  ShortRangeContact contact;          // pairs that start outside each other's family
  ModelSet models;                    // one model object per material (material/model.hpp)
  // The time of the deformation the next force pass evaluates, and the time since the
  // committed model history (set by the solvers; history models read them).
  double time = 0;
  double dt = 0;
  // The current positions the force pass reads, when the explicit solver keeps them apart
  // from X + u (solver.verlet: peridigm: y = (X + u_n) + dt v_{n+1/2}, rounded as Peridigm's
  // Verlet forms it, while u_{n+1} = u_n + dt v_{n+1/2} is rounded on its own); empty: X + u.
  std::vector<Vec3> positions;
  // The displacement u_n at the start of a static load step, when the static solver forms
  // the current positions as Peridigm's quasi-static solvers do (solver.positions:
  // peridigm): y = (X + u_n) + (u - u_n), each sum rounded on its own; empty: X + u. Read
  // by the force pass's packing after `positions`.
  std::vector<Vec3> step_start_u;
  std::vector<std::string> block_names;
  std::size_t initial_bonds = 0;
  std::size_t precrack_bonds = 0;
  std::vector<double> dissipated_at;  // energy of the bonds broken at each particle [J]
  uint64_t broken = 0;                // directed bonds broken so far
  // Heat conduction (thermal/heat.hpp); empty without a thermal section.
  HeatState heat;
  // alpha_i (T_i - T_ref,i) when a temperature field expands the body, else empty. A bond
  // feels the mean of its ends' values: its mechanical extension is e - eps_ij |xi|
  // (solver/forces_general.cpp), and the force pass takes the general path while it is set.
  std::vector<double> thermal_strain;
  // The factor max(0, 1 + slope_i (T_i - T_ref,i)) on particle i's critical stretch
  // (temperature-dependent critical stretch), else empty; the general force pass applies it.
  std::vector<double> critical_stretch_factor;
  // Critical stretches that vary in time (a material's damage.critical_stretch written as
  // an expression in t; Peridigm's Time Dependent Critical Stretch): each such material's
  // s0(t) and its particles. The explicit solver sets model.critical_stretch of those
  // particles to s0(t) at the step's new time, before its force pass (set_critical_stretch).
  struct CriticalStretchSchedule {
    Expression s0;
    std::vector<uint32_t> particles;
  };
  std::vector<CriticalStretchSchedule> critical_stretch_schedules;
  // Classical finite-element regions coupled to the particles (fe/fe_region.hpp); null
  // without finite-element bodies. Its nodes are particles; compute_forces overwrites
  // the force of the nodes it owns with the element assembly. `fe_coupling` is the same
  // object seen through its interface (above), for the rooms below fe/; `fe` the whole
  // FeRegion for the rooms above it. build_fe_regions sets both.
  std::shared_ptr<FeRegion> fe;
  std::shared_ptr<FeCoupling> fe_coupling;

  // A run split over MPI ranks (parallel/decomposition.hpp), else null and both lists
  // empty: `owned` are the particles this rank integrates, `active_rows` those whose forces
  // it computes (the force passes and the contact loop run over them alone).
  Decomposition* decomposition = nullptr;
  std::vector<uint32_t> owned, active_rows;
  // The same as a flag per particle (empty when not decomposed): a model whose traits say
  // rows_local computes and commits the rows of the particles with computes_row(i) alone.
  std::vector<uint8_t> row_active;
  bool computes_row(std::size_t i) const { return row_active.empty() || row_active[i] != 0; }

  // Sum of dissipated_at in a fixed order: the same figure on any thread count (over
  // the owned particles, by parallel/decomposition.hpp GridSum, when decomposed).
  double dissipated() const;
};

// Per-kind coefficients (ModelCoefficients::kind) and the damage totals from the
// bonds' reference data and the per-particle coefficients. setup_model calls it; call
// it again after changing either by hand.
void build_kind_coefficients(System& s, DamageMeasure measure);
// The same tables alone, the damage totals left as they are (the kinds regrouped with the
// same damage weights: forces.cpp when the general pass needs kinds with lengths).
void build_kind_tables(System& s, DamageMeasure measure);

// Recomputes the damage field's bookkeeping (per-particle totals and intact sums) from
// the bonds' intact flags. The force pass keeps it up to date as bonds break; call this
// after changing intact flags by hand.
void refresh_damage(System& s);

// The damage weight of i's intact bonds (intact == 1), summed afresh in the lanes of the
// bond loops. A row whose bonds broke in a pass takes it in place of its running sum, so
// that a particle whose every bond is broken has damage exactly 1 (the running sum's
// subtractions leave a rounding residue: 1.0000000000000007 on the glass demo).
double intact_damage_weight(const System& s, std::size_t i);

// phi_i = 1 - (intact weight) / (total weight), exactly 0 with every bond intact and
// exactly 1 with none.
inline double damage_of(double intact_weight, double total_weight) {
  return total_weight > 0 ? 1.0 - intact_weight / total_weight : 0.0;
}

// Total strain energy sum_i W_i V_i [J] (after compute_forces(s, true)).
double strain_energy(const System& s);

}  // namespace horizon
