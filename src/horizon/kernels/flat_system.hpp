#pragma once
// An explicit run of the unified models (PMB, LPS) and of Tupek's nonlinear solid over
// flat arrays: the state a backend
// keeps (raw pointers and counts, plain data), the work of one particle's row in each
// stage of a step, and the host's loop over them (advance_flat). The CUDA backend
// (cuda/cuda_backend.cu) launches the same row functions, one thread a particle, over
// device copies of the same arrays, so both compute the same operations in the same
// order: a row is summed by one thread in bond order (docs/design.md, "Backends and
// portable kernels").
//
// What it covers: velocity Verlet with mass-proportional damping, critical-stretch
// breaking (with the compression factor alpha and no_fail particles), damage, the
// family's short-range contact and the strain energy, for bond-based runs (one fused
// pass, as the fast loops' bond-based pass) and state-based ones (the dilatation pass,
// then the force pass), Tupek's nonlinear solid (the strain sweep, then the force sweep
// with its energy failure law: kernels/tupek.hpp, the rows NonlinearSolid::force_pass
// calls), force densities, prescribed velocities and displacements and
// their work (values that vary are set by the stepper before each step), with hooks for
// the host's work between the passes (the contact pairs beyond the families), bonds
// broken before or after the force pass (break_after). Thermal strains and decomposed
// runs are not here
// (solver/flat_copy.hpp says which runs a flat copy takes).
#include <cstdint>

#include "horizon/core/portable.hpp"
#include "horizon/kernels/flat_affine.hpp"
#include "horizon/kernels/lanes.hpp"
#include "horizon/kernels/tupek.hpp"
#include "horizon/kernels/unified.hpp"
#include "horizon/kernels/verlet.hpp"

namespace horizon::kernels {

// Per bond kind: the fast loops' per-kind constants (state/system.hpp KindCoefficients,
// the same layout without its alignment).
struct Kind {
  double length, inv_length, pair, contact_d2, damage, wv, contact_d, contact_k;
};

// A row's sums in the host's lanes: kernels/lanes.hpp.

// y4's four values of a particle as the nonlinear solid's rows read them (core/point4.hpp's
// Point4 without its 32-byte alignment: a device array or a std::vector<double> of 4n).
struct FlatPoint {
  double x, y, z, w;
};

struct FlatOrdinary;  // the ordinary history models' state (kernels/flat_ordinary.hpp)

struct FlatSystem {
  uint64_t n = 0, nb = 0, nkinds = 0;
  bool state_based = false;  // LPS rows present: the dilatation pass, then the force pass
  // damage.breaks: after_force (System's model.break_after_force): a bond that breaks in a
  // pass still carries its force in that pass (state-based: marked 2 by the dilatation row,
  // counted in theta, cleared by the force row), as the fast loops' kAfter rows.
  bool break_after = false;
  double dim = 3;            // d of theta
  double dt = 0, damping = 0;
  // Bonds, compressed rows: row i is [offset[i], offset[i+1]).
  const uint64_t* offset = nullptr;
  const uint32_t* nbr = nullptr;
  const uint32_t* kind = nullptr;
  uint8_t* intact = nullptr;  // 1 intact, 0 broken
  const Kind* kinds = nullptr;
  double* r_of = nullptr;  // |Y| of each bond from the dilatation pass (state-based), nb
  // Particles; vectors are xyz interleaved (3n).
  const double* X = nullptr;
  double* u = nullptr;
  double* v = nullptr;
  double* f = nullptr;
  double* b = nullptr;  // body force densities (held fixed, or set from b_next each step)
  const double* density = nullptr;
  const double* volume = nullptr;
  const double* critical_stretch = nullptr;
  const double* alpha = nullptr;
  const uint8_t* no_fail = nullptr;
  double* min_stretch = nullptr;       // the last pass's smallest stretch of i's intact bonds
  double* min_stretch_next = nullptr;  // this pass's (the stepper swaps the two)
  const double* dilatation_coef = nullptr;  // a_i
  const double* Q = nullptr;                // b_i (deviatoric_coef)
  const double* R = nullptr;                // pair_coef
  const double* weighted_volume = nullptr;  // m_i
  double* theta = nullptr;
  double* P = nullptr;
  double* intact_weight = nullptr;
  const double* damage_total = nullptr;
  double* damage = nullptr;
  double* energy = nullptr;     // W_i of the last pass
  double* dissipated = nullptr;  // per particle: the energy of i's broken bonds (times V_i)
  double* y4 = nullptr;          // 4n: y = X + u and s0 (then P, in the state-based force pass)
  uint64_t* broken = nullptr;    // n: bonds broken by row i in the last pass
  // Loads, each value a constant (the kernels evaluate no expression of the deck): the
  // force densities b above, prescribed velocities and displacements (`fixed`), and their
  // work over each step booked as ExplicitSolver::step and Loads::update_reactions book it,
  // summed by one thread in their order, so that the ledger keeps the CPU backend's bits.
  const uint8_t* fixed = nullptr;        // n, or null: bit c velocity component c prescribed, bit 3 + c displacement
  double* fixed_value = nullptr;         // 3n: the prescribed velocity or displacement at the step's end
  // Values that vary (the stepper evaluates the deck's expressions before each step and
  // sets these; null when every value is a constant): the prescribed velocity at mid-step
  // (else fixed_value), a prescribed displacement's velocity (g(t) - g(t - dt))/dt (else
  // 0), the force densities at the step's end (apply_forces at t + dt; else b is held).
  double* fixed_mid = nullptr;           // 3n
  double* fixed_v = nullptr;             // 3n
  double* b_next = nullptr;              // 3n
  // solver.verlet: peridigm (ExplicitSolver::set_peridigm_verlet): the kicks round as
  // kernels::peridigm_kick (no damping), the prescribed displacements move by their
  // increments over the step (Loads::prescribe_increments: v = (g(t1) - g(t0)) r, or
  // (g(t1) - u) r where the increment is 0, r = 1/(t1 - t0); fixed_v holds the increment,
  // fixed_rate r, set by the stepper before each step), the positions the force pass reads
  // are y = (X + u) + dt v(n+1/2) apart from u (System::positions), and the prescribed
  // displacements' components keep the second half kick.
  bool peridigm = false;
  double* fixed_rate = nullptr;          // 3n, with peridigm and prescribed displacements
  double* positions = nullptr;           // 3n, with peridigm
  double* b_before = nullptr;            // 3 ntracked: b at the start of the step (its work)
  uint64_t ntracked = 0;                 // the particles loaded (b != 0) or constrained, in index order
  const uint32_t* tracked = nullptr;
  double* u_before = nullptr;            // 3 ntracked: u at the start of the step
  double* v_before = nullptr;            // 3 ntracked: v at the start of the step
  bool has_forces = false;               // the deck has force loads (step adds their work)
  uint64_t nentries = 0;                 // the constraints' (load, particle) pairs, in the loads' order
  const uint32_t* entry_slot = nullptr;  // the particle's place in tracked
  const uint8_t* entry_mask = nullptr;   // bit c: the load prescribes component c
  double* entry_reaction = nullptr;      // 3 nentries: the reaction at the last step (Loads' reaction_old)
  double* ledger = nullptr;              // [0]: the external work so far
  // Mass-proportional damping (damping > 0): the energy it removed, per particle, summed
  // over the steps (the ledger's damped energy is their sum in index order), and each
  // step's |v|^2 at its start over the free components.
  // Set to 1 by a row whose u or v turned non-finite (every writer writes 1), so that the
  // stepper need not copy the state back to look (ExplicitSolver::step's check).
  uint8_t* nonfinite = nullptr;     // 1, or null
  double* damped = nullptr;        // n, or null without damping
  double* speed2_before = nullptr;  // n
  // Tupek's nonlinear solid (material/models/nonlinear_solid.hpp NonlinearState; `tupek`
  // set, state_based unused): its rows replace the unified ones, theta holds theta_phi of
  // eq. 6.8, intact_weight the sum of omega V_j over the intact bonds, damage the broken
  // fraction of that weight; R, Q, P, critical_stretch, alpha and the smallest stretches
  // are not read.
  bool tupek = false;
  bool tupek_exponent_two = true;         // NonlinearState::failure_exponent_two
  bool tupek_contact = false;             // short-range contact: broken bonds' ends repel
  double* eps = nullptr;                  // nb: each bond's strain of the last pass (bond_strain)
  const double* seth_m = nullptr;         // n: the Seth-Hill parameter m
  const double* lambda_bar = nullptr;     // n
  const double* mu_bar = nullptr;         // n
  const double* beta = nullptr;           // n: +inf where bonds never break
  const uint8_t* compression_only = nullptr;  // n
  const double* failure_scale = nullptr;  // nkinds: |xi|^-p of s_c
  double* nonlocal_damage = nullptr;      // n: eq. 6.12
  const double* contact_stiffness = nullptr;  // n: the family contact springs (the stable step)
  // Critical stretches that vary in time (System::critical_stretch_schedules): the stepper
  // sets critical_stretch at the step's end before each step (the CUDA backend copies it).
  bool critical_stretch_varies = false;
  // Bonds with their own lengths (an irregular cloud, Bonds::length_per_bond), else null:
  // the kinds hold no length, `pair` holds omega V_j (R_i + R_j) before the division by
  // |xi|, and flat_kind finishes each bond's constants as solver/forces.cpp per_bond does
  // (the contact distance min(fraction |xi|, cutoff) when the family contact acts).
  const double* length_of = nullptr;  // nb
  bool contact_from_length = false;
  double contact_fraction = 0, contact_cutoff = 0;
  // elastic_plastic or viscoelastic (kernels/flat_ordinary.hpp), else null: their rows
  // replace the unified ones.
  const FlatOrdinary* ordinary = nullptr;
  // The correspondence model's affine pass (kernels/flat_affine.hpp; `correspondence` set,
  // state_based unused): its rows replace the unified ones and commit its history.
  bool correspondence = false;
  FlatAffine affine;
};

// Bond k's constants with its own length (FlatSystem::length_of). The rows below take the
// bonds' own lengths (kOwn) and break_after as template parameters, chosen once a pass
// (flat_unified_forces), and copy a kind's constants directly otherwise
// (`kOwn ? flat_kind(s, k) : s.kinds[s.kind[k]]`): the flags tested in the loop, or the
// kind returned through a function, cost the host's rows 10 to 20 % (a lattice, backend flat).
HORIZON_HD inline Kind flat_kind(const FlatSystem& s, uint64_t k) {
  Kind kc = s.kinds[s.kind[k]];
  const double L = s.length_of[k];
  kc.length = L;
  kc.inv_length = 1.0 / L;
  kc.pair = kc.pair / L;
  if (s.contact_from_length) {
    const double d = s.contact_fraction * L;
    kc.contact_d = s.contact_cutoff < d ? s.contact_cutoff : d;  // std::min(d, cutoff)
    kc.contact_d2 = kc.contact_d * kc.contact_d;
  }
  return kc;
}

// Stage 1 of a pass: y = X + u and this pass's s0 (solver/forces.cpp pack_positions).
HORIZON_HD inline void pack_row(const FlatSystem& s, uint64_t i) {
  double* y = s.y4 + 4 * i;
  if (s.positions) {  // solver.verlet: peridigm (solver/forces.cpp pack_positions)
    y[0] = s.positions[3 * i], y[1] = s.positions[3 * i + 1], y[2] = s.positions[3 * i + 2];
    y[3] = critical_stretch_now(s.critical_stretch[i], s.alpha[i], s.min_stretch[i], s.no_fail[i] != 0);
    return;
  }
  y[0] = s.X[3 * i] + s.u[3 * i];
  y[1] = s.X[3 * i + 1] + s.u[3 * i + 1];
  y[2] = s.X[3 * i + 2] + s.u[3 * i + 2];
  y[3] = critical_stretch_now(s.critical_stretch[i], s.alpha[i], s.min_stretch[i], s.no_fail[i] != 0);
}

// The damage weight of i's intact bonds, summed afresh in the lanes (as
// state/kind_coefficients.cpp intact_damage_weight sums it).
HORIZON_HD inline double intact_weight_row(const FlatSystem& s, uint64_t i) {
  double w[kLanes] = {};
  for_each_lane(s.offset[i], s.offset[i + 1], [&](uint64_t k, int l) {
    if (s.intact[k] == 1) w[l] += s.kinds[s.kind[k]].damage;
  });
  return lane_total(w);
}

// After a row broke bonds: its energy, intact weight and damage.
HORIZON_HD inline void finish_breaks(const FlatSystem& s, uint64_t i, uint64_t broken, double lost) {
  s.broken[i] = broken;
  if (lost != 0) s.dissipated[i] += lost * s.volume[i];
  if (broken) s.intact_weight[i] = intact_weight_row(s, i);
  s.damage[i] = damage_fraction(s.intact_weight[i], s.damage_total[i]);
}

// Bond-based runs, one fused row: breaking, the smallest stretch, force, contact, energy
// (solver/forces.cpp pair_row_scalar, summed in its lanes).
template <bool kOwn, bool kAfter>
HORIZON_HD_INLINE void bond_based_row_of(const FlatSystem& s, uint64_t i) {
  const double* pi = s.y4 + 4 * i;
  const double Ri = s.R[i];
  double fx[kLanes] = {}, fy[kLanes] = {}, fz[kLanes] = {}, en[kLanes] = {}, sm[kLanes];
  for (int l = 0; l < kLanes; ++l) sm[l] = INFINITY;
  double lost = 0;
  uint64_t broken = 0;
  for_each_lane(s.offset[i], s.offset[i + 1], [&](uint64_t k, int l) {
    const Kind kc = kOwn ? flat_kind(s, k) : s.kinds[s.kind[k]];
    const double* pj = s.y4 + 4 * static_cast<uint64_t>(s.nbr[k]);
    const double Yx = pj[0] - pi[0], Yy = pj[1] - pi[1], Yz = pj[2] - pi[2];
    const double r2 = Yx * Yx + Yy * Yy + Yz * Yz;
    if (s.intact[k]) {
      const double r = root(r2), e = extension(r, kc.length, 0), stretch = e * kc.inv_length;
      const bool brk = breaks(stretch, pi[3], pj[3]);
      if (kAfter || !brk) {
        const double a = pair_bond_coefficient(kc.pair, e, r);
        fx[l] += a * Yx;
        fy[l] += a * Yy;
        fz[l] += a * Yz;
      }
      sm[l] = stretch < sm[l] ? stretch : sm[l];
      if (!brk) en[l] += pmb_bond_energy(kc.wv, Ri, kc.inv_length, e);
      if (brk) {
        s.intact[k] = 0;
        ++broken;
        lost += pmb_broken_energy(kc.wv, Ri, kc.inv_length, e);
        s.intact_weight[i] -= kc.damage;
      }
    }
    double a, w;
    if (contact_coefficient(kc.contact_d2, kc.contact_d, kc.contact_k, r2, a, w)) {
      fx[l] += a * Yx;
      fy[l] += a * Yy;
      fz[l] += a * Yz;
      en[l] += w;
    }
  });
  finish_breaks(s, i, broken, lost);
  s.min_stretch_next[i] = lane_min(sm);
  s.f[3 * i] = lane_total(fx), s.f[3 * i + 1] = lane_total(fy), s.f[3 * i + 2] = lane_total(fz);
  s.energy[i] = lane_total(en);
}

// State-based runs, pass 1 of a row: breaking, the smallest stretch, |Y| of each bond, the
// dilatation and P_i (solver/forces.cpp dilate_row_scalar, in its lanes; the broken
// bond's energy with the last pass's P_i).
template <bool kOwn, bool kAfter>
HORIZON_HD inline void dilatation_row_of(const FlatSystem& s, uint64_t i) {
  const double* pi = s.y4 + 4 * i;
  const double Ri = s.R[i], Qi = s.Q[i], Pi = s.P[i];
  double th[kLanes] = {}, sm[kLanes];
  for (int l = 0; l < kLanes; ++l) sm[l] = INFINITY;
  double lost = 0;
  uint64_t broken = 0;
  for_each_lane(s.offset[i], s.offset[i + 1], [&](uint64_t k, int l) {
    if (!s.intact[k]) return;
    const Kind kc = kOwn ? flat_kind(s, k) : s.kinds[s.kind[k]];
    const double* pj = s.y4 + 4 * static_cast<uint64_t>(s.nbr[k]);
    const double r = bond_length(pj[0] - pi[0], pj[1] - pi[1], pj[2] - pi[2]);
    const double e = extension(r, kc.length, 0), stretch = e * kc.inv_length;
    s.r_of[k] = r;
    const bool brk = breaks(stretch, pi[3], pj[3]);
    if (kAfter || !brk) th[l] += dilatation_term(kc.wv, kc.length, e);
    sm[l] = stretch < sm[l] ? stretch : sm[l];
    if (brk) {
      s.intact[k] = kAfter ? 2 : 0;
      ++broken;
      lost += unified_bond_energy(kc.wv, Pi, Qi, Ri, kc.length, kc.inv_length, e);
      s.intact_weight[i] -= kc.damage;
    }
  });
  finish_breaks(s, i, broken, lost);
  s.min_stretch_next[i] = lane_min(sm);
  if (s.dilatation_coef[i] != 0) {
    const double theta = dilatation(s.dim, lane_total(th), s.weighted_volume[i]);
    s.theta[i] = theta;
    s.P[i] = dilatation_pressure(theta, s.dilatation_coef[i], s.Q[i], s.dim);
  }
}

// Tupek's nonlinear solid (NonlinearSolid::force_pass, row by row): the two sweeps of
// kernels/tupek.hpp over the flat arrays, y4's fourth slot 0 as the host packs it.
HORIZON_HD inline TupekPass<Kind, FlatPoint> tupek_pass(const FlatSystem& s) {
  TupekPass<Kind, FlatPoint> p;
  p.pt = reinterpret_cast<const FlatPoint*>(s.y4);
  p.kc = s.kinds;
  p.nbr = s.nbr;
  p.kind = s.kind;
  p.offset = s.offset;
  p.intact = s.intact;
  p.eps = s.eps;
  p.m = s.seth_m;
  p.lambda_bar = s.lambda_bar;
  p.mu_bar = s.mu_bar;
  p.theta = s.theta;
  p.beta = s.beta;
  p.compression_only = s.compression_only;
  p.failure_scale = s.failure_scale;
  p.exponent_two = s.tupek_exponent_two;
  p.contact = s.tupek_contact;
  return p;
}

// Stage 1 of the nonlinear solid's pass: y = X + u, w = 0.
HORIZON_HD inline void tupek_pack_row(const FlatSystem& s, uint64_t i) {
  double* y = s.y4 + 4 * i;
  y[0] = s.X[3 * i] + s.u[3 * i];
  y[1] = s.X[3 * i + 1] + s.u[3 * i + 1];
  y[2] = s.X[3 * i + 2] + s.u[3 * i + 2];
  y[3] = 0.0;
}

// Sweep 1, row i: the bond strains and theta_i (eq. 6.8).
HORIZON_HD inline void tupek_theta_row(const FlatSystem& s, uint64_t i) {
  s.theta[i] = tupek_strain_row(tupek_pass(s), i);
}

// Sweep 2, row i: the pair criterion, the force, the dissipated energy, the row's energy
// (with the bonds cut in this pass taken out, and the family contact of broken bonds),
// the damage (its broken weight fraction), the nonlocal damage 1 - (1/d) sum omega phi V
// (eq. 6.12) and the intact weight, as NonlinearSolid::force_pass leaves them.
HORIZON_HD inline void tupek_row(const FlatSystem& s, uint64_t i) {
  const TupekRow o = tupek_force_row(tupek_pass(s), i);
  s.f[3 * i] = o.f[0], s.f[3 * i + 1] = o.f[1], s.f[3 * i + 2] = o.f[2];
  s.broken[i] = o.broken;
  if (o.lost != 0) s.dissipated[i] += o.lost * s.volume[i];
  s.energy[i] = tupek_row_energy(o, s.lambda_bar[i], s.mu_bar[i], s.theta[i]);
  s.damage[i] = damage_fraction(o.intact_w, o.total_w);
  s.nonlocal_damage[i] = 1.0 - o.intact_w / s.dim;
  s.intact_weight[i] = o.intact_w;
}

// Between the two passes: the packed fourth slot carries P_j to the force rows.
HORIZON_HD inline void pressure_row(const FlatSystem& s, uint64_t i) { s.y4[4 * i + 3] = s.P[i]; }

// State-based runs, pass 2 of a row: the pair form of the force, contact, energy
// (solver/forces.cpp force_row_scalar, in its lanes).
template <bool kOwn, bool kAfter>
HORIZON_HD inline void force_row_of(const FlatSystem& s, uint64_t i) {
  const double* pi = s.y4 + 4 * i;
  const double Ri = s.R[i], Pi = pi[3], Qi = s.Q[i];
  double fx[kLanes] = {}, fy[kLanes] = {}, fz[kLanes] = {}, en[kLanes] = {};
  for_each_lane(s.offset[i], s.offset[i + 1], [&](uint64_t k, int l) {
    const uint32_t j = s.nbr[k];
    const Kind kc = kOwn ? flat_kind(s, k) : s.kinds[s.kind[k]];
    const double* pj = s.y4 + 4 * static_cast<uint64_t>(j);
    const double Yx = pj[0] - pi[0], Yy = pj[1] - pi[1], Yz = pj[2] - pi[2];
    const double r2 = Yx * Yx + Yy * Yy + Yz * Yz;
    if (s.intact[k]) {
      const double r = s.r_of[k], e = extension(r, kc.length, 0);
      const double a = pair_force_coefficient(kc.wv, kc.pair, Pi, pj[3], Qi, s.Q[j], kc.length, e, r);
      fx[l] += a * Yx;
      fy[l] += a * Yy;
      fz[l] += a * Yz;
      if constexpr (kAfter) {  // a bond broken in this pass (2): its force, not its energy; then off
        if (s.intact[k] == 1) en[l] += unified_bond_energy(kc.wv, Pi, Qi, Ri, kc.length, kc.inv_length, e);
        if (s.intact[k] == 2) s.intact[k] = 0;
      } else {
        en[l] += unified_bond_energy(kc.wv, Pi, Qi, Ri, kc.length, kc.inv_length, e);
      }
    }
    double a, w;
    if (contact_coefficient(kc.contact_d2, kc.contact_d, kc.contact_k, r2, a, w)) {
      fx[l] += a * Yx;
      fy[l] += a * Yy;
      fz[l] += a * Yz;
      en[l] += w;
    }
  });
  s.f[3 * i] = lane_total(fx), s.f[3 * i + 1] = lane_total(fy), s.f[3 * i + 2] = lane_total(fz);
  s.energy[i] = lane_total(en);
}

// The rows' entry points: the variant of the run's options.
HORIZON_HD inline void bond_based_row(const FlatSystem& s, uint64_t i) {
  if (s.length_of) {
    if (s.break_after) bond_based_row_of<true, true>(s, i);
    else bond_based_row_of<true, false>(s, i);
  } else {
    if (s.break_after) bond_based_row_of<false, true>(s, i);
    else bond_based_row_of<false, false>(s, i);
  }
}
HORIZON_HD inline void dilatation_row(const FlatSystem& s, uint64_t i) {
  if (s.length_of) {
    if (s.break_after) dilatation_row_of<true, true>(s, i);
    else dilatation_row_of<true, false>(s, i);
  } else {
    if (s.break_after) dilatation_row_of<false, true>(s, i);
    else dilatation_row_of<false, false>(s, i);
  }
}
HORIZON_HD inline void force_row(const FlatSystem& s, uint64_t i) {
  if (s.length_of) {
    if (s.break_after) force_row_of<true, true>(s, i);
    else force_row_of<true, false>(s, i);
  } else {
    if (s.break_after) force_row_of<false, true>(s, i);
    else force_row_of<false, false>(s, i);
  }
}

// Loads::apply_constraints at the step's end: u = g and v = (g(t) - g(t - dt))/dt on the
// displaced components, v = h on the velocity components.
HORIZON_HD inline void constrain_row(const FlatSystem& s, uint64_t i, unsigned fixed) {
  for (int c = 0; c < 3; ++c) {
    const uint64_t q = 3 * i + c;
    if ((fixed >> (3 + c)) & 1u) s.u[q] = s.fixed_value[q], s.v[q] = s.fixed_v ? s.fixed_v[q] : 0.0;
    if ((fixed >> c) & 1u) s.v[q] = s.fixed_value[q];
  }
}

// Verlet's first half kick and drift of particle i (solver/explicit.cpp), with the
// prescribed velocity at mid-step (Loads::prescribe_velocity) and the prescribed
// displacement after the drift (Loads::apply_constraints: u = g, v = (g - g)/dt = 0).
// |v|^2 over the components no constraint prescribes (Loads::free_speed2).
HORIZON_HD inline double free_speed2(const FlatSystem& s, uint64_t i) {
  const unsigned fixed = s.fixed ? s.fixed[i] : 0u;
  double vv = 0;
  for (int c = 0; c < 3; ++c)
    if (!(((fixed >> c) | (fixed >> (3 + c))) & 1u)) vv += s.v[3 * i + c] * s.v[3 * i + c];
  return vv;
}

HORIZON_HD inline void kick_drift_row(const FlatSystem& s, uint64_t i) {
  const double inv_rho = 1.0 / s.density[i], half = 0.5 * s.dt;
  const unsigned fixed = s.fixed ? s.fixed[i] : 0u;
  if (s.damped) s.speed2_before[i] = free_speed2(s, i);
  for (int c = 0; c < 3; ++c) {
    const uint64_t q = 3 * i + c;
    s.v[q] = s.peridigm ? peridigm_kick(s.v[q], s.f[q], s.b[q], s.density[i], half)
                        : half_kick(s.v[q], s.f[q], s.b[q], inv_rho, s.damping, half);
  }
  if (fixed) {
    const double* mid = s.fixed_mid ? s.fixed_mid : s.fixed_value;
    for (int c = 0; c < 3; ++c)
      if ((fixed >> c) & 1u) s.v[3 * i + c] = mid[3 * i + c];
  }
  if (s.peridigm) {
    if (fixed)  // Loads::prescribe_increments
      for (int c = 0; c < 3; ++c) {
        const uint64_t q = 3 * i + c;
        if ((fixed >> (3 + c)) & 1u) {
          const double step = s.fixed_v[q];
          s.v[q] = (step == 0.0 ? s.fixed_value[q] - s.u[q] : step) * s.fixed_rate[q];
        }
      }
    for (int c = 0; c < 3; ++c) {  // ExplicitSolver::step: y = (X + u_n) + dt v(n+1/2)
      const uint64_t q = 3 * i + c;
      s.positions[q] = (s.X[q] + s.u[q]) + s.dt * s.v[q];
    }
  }
  for (int c = 0; c < 3; ++c) s.u[3 * i + c] = drift(s.u[3 * i + c], s.v[3 * i + c], s.dt);
  // (peridigm: the displacements are not set to g(t1); the velocities are)
  if (fixed) constrain_row(s, i, s.peridigm ? fixed & 7u : fixed);
  if (s.b_next)  // Loads::apply_forces at the step's end
    for (int c = 0; c < 3; ++c) s.b[3 * i + c] = s.b_next[3 * i + c];
}

// Verlet's second half kick of particle i, then the constraints (Loads::apply_constraints);
// the smallest stretch becomes the last pass's.
HORIZON_HD inline void kick_row(const FlatSystem& s, uint64_t i) {
  const double half = 0.5 * s.dt, damp = 1.0 / (1.0 + s.damping * half), h = half / s.density[i];
  for (int c = 0; c < 3; ++c) {
    const uint64_t q = 3 * i + c;
    s.v[q] = s.peridigm ? peridigm_kick(s.v[q], s.f[q], s.b[q], s.density[i], half)
                        : second_half_kick(s.v[q], s.f[q], s.b[q], h, damp);
  }
  if (s.nonfinite) {
    const double* u = s.u + 3 * i;
    const double* v = s.v + 3 * i;
    if (!finite(v[0] + v[1] + v[2] + u[0] + u[1] + u[2])) s.nonfinite[0] = 1;
  }
  // Peridigm's prescribed displacements keep the second half kick (apply_constraints(..., false)).
  if (const unsigned fixed = s.fixed ? s.fixed[i] : 0u) constrain_row(s, i, s.peridigm ? fixed & 7u : fixed);
  // The energy damping removed over the step (solver/explicit.cpp: the implicit half step
  // on v(n+1) and v(n), the constrained components left out).
  if (s.damped)
    s.damped[i] += s.density[i] * s.volume[i] * s.damping * half * (free_speed2(s, i) + s.speed2_before[i]);
  s.min_stretch[i] = s.min_stretch_next[i];
}

// Before a step's first half kick: the tracked particles' u and v.
HORIZON_HD inline void save_tracked_row(const FlatSystem& s, uint64_t m) {
  const uint64_t i = s.tracked[m];
  for (int c = 0; c < 3; ++c) {
    s.u_before[3 * m + c] = s.u[3 * i + c];
    s.v_before[3 * m + c] = s.v[3 * i + c];
    if (s.b_before) s.b_before[3 * m + c] = s.b[3 * i + c];
  }
}

// After the second half kick and the constraints, one thread: the step's work into the
// ledger, with the operations and order of Loads::update_reactions (each constraint's
// reaction r = -(f + b) V on its components, 1/2 (r_old + r) . du, then the inertial
// part 1/2 m (v^2 - v_before^2) of each component) and of ExplicitSolver::step (plus, with
// force loads, 1/2 V (b + b_before) . du over the loaded particles; b is held fixed).
HORIZON_HD inline void book_load_work(const FlatSystem& s) {
  double work = 0;
  for (uint64_t e = 0; e < s.nentries; ++e) {
    const uint64_t m = s.entry_slot[e], i = s.tracked[m];
    const unsigned mask = s.entry_mask[e];
    const double V = s.volume[i];
    double r[3];
    for (int c = 0; c < 3; ++c) r[c] = ((mask >> c) & 1u) ? -(s.f[3 * i + c] + s.b[3 * i + c]) * V : 0.0;
    double* ro = s.entry_reaction + 3 * e;
    const double* u = s.u + 3 * i;
    const double* u0 = s.u_before + 3 * m;
    work += 0.5 * ((ro[0] + r[0]) * (u[0] - u0[0]) + (ro[1] + r[1]) * (u[1] - u0[1]) + (ro[2] + r[2]) * (u[2] - u0[2]));
    for (int c = 0; c < 3; ++c) ro[c] = r[c];
    const double mass = 1.0 * s.density[i] * V;
    for (int c = 0; c < 3; ++c)
      if ((mask >> c) & 1u) {
        const double v = s.v[3 * i + c], v0 = s.v_before[3 * m + c];
        work += 0.5 * mass * (v * v - v0 * v0);
      }
  }
  if (s.has_forces) {
    double w = 0;
    for (uint64_t m = 0; m < s.ntracked; ++m) {
      const uint64_t i = s.tracked[m];
      const double* b = s.b + 3 * i;
      const double* bb = s.b_before ? s.b_before + 3 * m : b;
      if (b[0] == 0 && b[1] == 0 && b[2] == 0 && bb[0] == 0 && bb[1] == 0 && bb[2] == 0) continue;
      const double* u = s.u + 3 * i;
      const double* u0 = s.u_before + 3 * m;
      w += 0.5 * s.volume[i] *
           ((b[0] + bb[0]) * (u[0] - u0[0]) + (b[1] + bb[1]) * (u[1] - u0[1]) + (b[2] + bb[2]) * (u[2] - u0[2]));
    }
    work += w;
  }
  s.ledger[0] += work + 0.0;
}

// The host's loops over the rows: each row is written by one thread (the CUDA backend
// launches each loop as a kernel), so the answer does not depend on the thread count.
#if defined(_OPENMP)
#define HORIZON_FLAT_ROWS _Pragma("omp parallel for schedule(static)")
#define HORIZON_FLAT_ROWS_BROKEN _Pragma("omp parallel for schedule(static) reduction(+ : broken)")
#else
#define HORIZON_FLAT_ROWS
#define HORIZON_FLAT_ROWS_BROKEN
#endif

// The force pass on the host.
// The unified models' passes, with the run's options chosen once (kOwn, kAfter).
template <bool kOwn, bool kAfter>
inline void flat_unified_forces(const FlatSystem& s) {
  const uint64_t n = s.n;
  HORIZON_FLAT_ROWS
  for (uint64_t i = 0; i < n; ++i) pack_row(s, i);
  if (!s.state_based) {
    HORIZON_FLAT_ROWS
    for (uint64_t i = 0; i < n; ++i) bond_based_row_of<kOwn, kAfter>(s, i);
    return;
  }
  HORIZON_FLAT_ROWS
  for (uint64_t i = 0; i < n; ++i) dilatation_row_of<kOwn, kAfter>(s, i);
  HORIZON_FLAT_ROWS
  for (uint64_t i = 0; i < n; ++i) pressure_row(s, i);
  HORIZON_FLAT_ROWS
  for (uint64_t i = 0; i < n; ++i) force_row_of<kOwn, kAfter>(s, i);
}

inline void flat_ordinary_forces(const FlatSystem& s);  // kernels/flat_ordinary.hpp

inline void flat_forces(const FlatSystem& s) {
  const uint64_t n = s.n;
  if (s.ordinary) return flat_ordinary_forces(s);
  if (s.correspondence) {  // kernels/flat_affine.hpp: the pass, then the commit that follows it
    HORIZON_FLAT_ROWS
    for (uint64_t i = 0; i < n; ++i) pack_row(s, i);
    HORIZON_FLAT_ROWS
    for (uint64_t i = 0; i < n; ++i) flat_affine_break_row(s, i);
    HORIZON_FLAT_ROWS
    for (uint64_t i = 0; i < n; ++i) flat_affine_sum_row(s, i);
    HORIZON_FLAT_ROWS
    for (uint64_t i = 0; i < n; ++i) flat_affine_commit_row(s, i);
    return;
  }
  if (s.tupek) {
    HORIZON_FLAT_ROWS
    for (uint64_t i = 0; i < n; ++i) tupek_pack_row(s, i);
    HORIZON_FLAT_ROWS
    for (uint64_t i = 0; i < n; ++i) tupek_theta_row(s, i);
    HORIZON_FLAT_ROWS
    for (uint64_t i = 0; i < n; ++i) tupek_row(s, i);
    return;
  }
  if (s.length_of) {
    if (s.break_after) flat_unified_forces<true, true>(s);
    else flat_unified_forces<true, false>(s);
  } else {
    if (s.break_after) flat_unified_forces<false, true>(s);
    else flat_unified_forces<false, false>(s);
  }
}

// The nonlinear solid's stable time step over the copy (NonlinearSolid::stable_time_step's
// rows, kernels/tupek.hpp): each row's S into S (n), then the smallest row step, a minimum
// (the same bits in any order and on any device), as the host's min reduction takes it.
inline double flat_tupek_stable_step(const FlatSystem& s, double* S) {
  const TupekPass<Kind, FlatPoint> p = tupek_pass(s);
  const uint64_t n = s.n;
  HORIZON_FLAT_ROWS
  for (uint64_t i = 0; i < n; ++i) S[i] = tupek_coupling_row(p, i);
  double dt = INFINITY;
#if defined(_OPENMP)
#pragma omp parallel for schedule(static) reduction(min : dt)
#endif
  for (uint64_t i = 0; i < n; ++i) {
    const double r = tupek_stable_row(p, S, s.contact_stiffness[i], s.density[i], i);
    dt = r < dt ? r : dt;  // std::min(dt, r)
  }
  return dt;
}

// No work between a step's force pass and its second half kick, nor before a step.
struct NoHook {
  void operator()() const {}
};
struct NoStepHook {
  void operator()(int64_t) const {}
};

// `steps` explicit steps on the host; returns the bonds broken. `before_step(k)` runs
// before step k of the call (the loads' values that vary: solver/flat_backend.cpp),
// `after_forces` after each force pass (the host's short-range contact pairs).
template <class Hook = NoHook, class StepHook = NoStepHook>
inline uint64_t advance_flat(const FlatSystem& s, int64_t steps, Hook&& after_forces = Hook{},
                             StepHook&& before_step = StepHook{}) {
  const uint64_t n = s.n;
  uint64_t broken = 0;
  for (int64_t k = 0; k < steps; ++k) {
    before_step(k);
    for (uint64_t m = 0; m < s.ntracked; ++m) save_tracked_row(s, m);
    HORIZON_FLAT_ROWS
    for (uint64_t i = 0; i < n; ++i) kick_drift_row(s, i);
    flat_forces(s);
    after_forces();
    HORIZON_FLAT_ROWS_BROKEN
    for (uint64_t i = 0; i < n; ++i) {
      kick_row(s, i);
      broken += s.broken[i];
    }
    if (s.ntracked) book_load_work(s);
  }
  return broken;
}

// Sums in particle order: the kinetic energy, the strain energy sum W_i V_i, the mean damage.
struct FlatTotals {
  double kinetic = 0, strain = 0, mean_damage = 0;
};
inline FlatTotals flat_totals(const FlatSystem& s) {
  FlatTotals t;
  for (uint64_t i = 0; i < s.n; ++i) {
    t.kinetic += kinetic(s.density[i], s.volume[i], s.v[3 * i], s.v[3 * i + 1], s.v[3 * i + 2]);
    t.strain += s.energy[i] * s.volume[i];
    t.mean_damage += s.damage[i];
  }
  if (s.n) t.mean_damage /= static_cast<double>(s.n);
  return t;
}

}  // namespace horizon::kernels

#include "horizon/kernels/flat_ordinary.hpp"  // (the ordinary models' rows, which flat_forces runs)
