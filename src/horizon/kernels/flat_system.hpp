#pragma once
// An explicit run of the unified models (PMB, LPS) over flat arrays: the state a backend
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
// then the force pass). Loads other than initial velocities, thermal strains, bonds
// broken after the force pass and decomposed runs are not here: the host keeps those
// (solver/flat_copy.hpp says which runs a flat copy takes).
#include <cstdint>

#include "horizon/core/portable.hpp"
#include "horizon/kernels/unified.hpp"
#include "horizon/kernels/verlet.hpp"

namespace horizon::kernels {

// Per bond kind: the fast loops' per-kind constants (state/system.hpp KindCoefficients,
// the same layout without its alignment).
struct Kind {
  double length, inv_length, pair, contact_d2, damage, wv, contact_d, contact_k;
};

struct FlatSystem {
  uint64_t n = 0, nb = 0, nkinds = 0;
  bool state_based = false;  // LPS rows present: the dilatation pass, then the force pass
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
  const double* b = nullptr;  // body force densities (held fixed)
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
};

// Stage 1 of a pass: y = X + u and this pass's s0 (solver/forces.cpp pack_positions).
HORIZON_HD inline void pack_row(const FlatSystem& s, uint64_t i) {
  double* y = s.y4 + 4 * i;
  y[0] = s.X[3 * i] + s.u[3 * i];
  y[1] = s.X[3 * i + 1] + s.u[3 * i + 1];
  y[2] = s.X[3 * i + 2] + s.u[3 * i + 2];
  y[3] = critical_stretch_now(s.critical_stretch[i], s.alpha[i], s.min_stretch[i], s.no_fail[i] != 0);
}

// The damage weight of i's intact bonds, summed afresh in bond order.
HORIZON_HD inline double intact_weight_row(const FlatSystem& s, uint64_t i) {
  double w = 0;
  for (uint64_t k = s.offset[i]; k < s.offset[i + 1]; ++k)
    if (s.intact[k] == 1) w += s.kinds[s.kind[k]].damage;
  return w;
}

// After a row broke bonds: its energy, intact weight and damage.
HORIZON_HD inline void finish_breaks(const FlatSystem& s, uint64_t i, uint64_t broken, double lost) {
  s.broken[i] = broken;
  if (lost != 0) s.dissipated[i] += lost * s.volume[i];
  if (broken) s.intact_weight[i] = intact_weight_row(s, i);
  s.damage[i] = damage_fraction(s.intact_weight[i], s.damage_total[i]);
}

// Bond-based runs, one fused row: breaking, the smallest stretch, force, contact, energy
// (solver/forces.cpp pair_row_scalar, summed in bond order).
HORIZON_HD inline void bond_based_row(const FlatSystem& s, uint64_t i) {
  const double* pi = s.y4 + 4 * i;
  const double Ri = s.R[i];
  double fx = 0, fy = 0, fz = 0, en = 0, smin = INFINITY, lost = 0;
  uint64_t broken = 0;
  for (uint64_t k = s.offset[i]; k < s.offset[i + 1]; ++k) {
    const Kind kc = s.kinds[s.kind[k]];
    const double* pj = s.y4 + 4 * static_cast<uint64_t>(s.nbr[k]);
    const double Yx = pj[0] - pi[0], Yy = pj[1] - pi[1], Yz = pj[2] - pi[2];
    const double r2 = Yx * Yx + Yy * Yy + Yz * Yz;
    if (s.intact[k]) {
      const double r = root(r2), e = extension(r, kc.length, 0), stretch = e * kc.inv_length;
      const bool brk = breaks(stretch, pi[3], pj[3]);
      if (!brk) {
        const double a = pair_bond_coefficient(kc.pair, e, r);
        fx += a * Yx;
        fy += a * Yy;
        fz += a * Yz;
        en += pmb_bond_energy(kc.wv, Ri, kc.inv_length, e);
      }
      smin = stretch < smin ? stretch : smin;
      if (brk) {
        s.intact[k] = 0;
        ++broken;
        lost += pmb_broken_energy(kc.wv, Ri, kc.inv_length, e);
        s.intact_weight[i] -= kc.damage;
      }
    }
    double a, w;
    if (contact_coefficient(kc.contact_d2, kc.contact_d, kc.contact_k, r2, a, w)) {
      fx += a * Yx;
      fy += a * Yy;
      fz += a * Yz;
      en += w;
    }
  }
  finish_breaks(s, i, broken, lost);
  s.min_stretch_next[i] = smin;
  s.f[3 * i] = fx, s.f[3 * i + 1] = fy, s.f[3 * i + 2] = fz;
  s.energy[i] = en;
}

// State-based runs, pass 1 of a row: breaking, the smallest stretch, |Y| of each bond, the
// dilatation and P_i (solver/forces.cpp dilate_row_scalar; the broken bond's energy with
// the last pass's P_i).
HORIZON_HD inline void dilatation_row(const FlatSystem& s, uint64_t i) {
  const double* pi = s.y4 + 4 * i;
  const double Ri = s.R[i], Qi = s.Q[i], Pi = s.P[i];
  double sum = 0, smin = INFINITY, lost = 0;
  uint64_t broken = 0;
  for (uint64_t k = s.offset[i]; k < s.offset[i + 1]; ++k) {
    if (!s.intact[k]) continue;
    const Kind kc = s.kinds[s.kind[k]];
    const double* pj = s.y4 + 4 * static_cast<uint64_t>(s.nbr[k]);
    const double r = bond_length(pj[0] - pi[0], pj[1] - pi[1], pj[2] - pi[2]);
    const double e = extension(r, kc.length, 0), stretch = e * kc.inv_length;
    s.r_of[k] = r;
    const bool brk = breaks(stretch, pi[3], pj[3]);
    if (!brk) sum += dilatation_term(kc.wv, kc.length, e);
    smin = stretch < smin ? stretch : smin;
    if (brk) {
      s.intact[k] = 0;
      ++broken;
      lost += unified_bond_energy(kc.wv, Pi, Qi, Ri, kc.length, kc.inv_length, e);
      s.intact_weight[i] -= kc.damage;
    }
  }
  finish_breaks(s, i, broken, lost);
  s.min_stretch_next[i] = smin;
  if (s.dilatation_coef[i] != 0) {
    const double theta = dilatation(s.dim, sum, s.weighted_volume[i]);
    s.theta[i] = theta;
    s.P[i] = dilatation_pressure(theta, s.dilatation_coef[i], s.Q[i], s.dim);
  }
}

// Between the two passes: the packed fourth slot carries P_j to the force rows.
HORIZON_HD inline void pressure_row(const FlatSystem& s, uint64_t i) { s.y4[4 * i + 3] = s.P[i]; }

// State-based runs, pass 2 of a row: the pair form of the force, contact, energy
// (solver/forces.cpp force_row_scalar).
HORIZON_HD inline void force_row(const FlatSystem& s, uint64_t i) {
  const double* pi = s.y4 + 4 * i;
  const double Ri = s.R[i], Pi = pi[3], Qi = s.Q[i];
  double fx = 0, fy = 0, fz = 0, en = 0;
  for (uint64_t k = s.offset[i]; k < s.offset[i + 1]; ++k) {
    const uint32_t j = s.nbr[k];
    const Kind kc = s.kinds[s.kind[k]];
    const double* pj = s.y4 + 4 * static_cast<uint64_t>(j);
    const double Yx = pj[0] - pi[0], Yy = pj[1] - pi[1], Yz = pj[2] - pi[2];
    const double r2 = Yx * Yx + Yy * Yy + Yz * Yz;
    if (s.intact[k]) {
      const double r = s.r_of[k], e = extension(r, kc.length, 0);
      const double a = pair_force_coefficient(kc.wv, kc.pair, Pi, pj[3], Qi, s.Q[j], kc.length, e, r);
      fx += a * Yx;
      fy += a * Yy;
      fz += a * Yz;
      en += unified_bond_energy(kc.wv, Pi, Qi, Ri, kc.length, kc.inv_length, e);
    }
    double a, w;
    if (contact_coefficient(kc.contact_d2, kc.contact_d, kc.contact_k, r2, a, w)) {
      fx += a * Yx;
      fy += a * Yy;
      fz += a * Yz;
      en += w;
    }
  }
  s.f[3 * i] = fx, s.f[3 * i + 1] = fy, s.f[3 * i + 2] = fz;
  s.energy[i] = en;
}

// Verlet's first half kick and drift of particle i (solver/explicit.cpp).
HORIZON_HD inline void kick_drift_row(const FlatSystem& s, uint64_t i) {
  const double inv_rho = 1.0 / s.density[i], half = 0.5 * s.dt;
  for (int c = 0; c < 3; ++c) {
    const uint64_t q = 3 * i + c;
    s.v[q] = half_kick(s.v[q], s.f[q], s.b[q], inv_rho, s.damping, half);
  }
  for (int c = 0; c < 3; ++c) s.u[3 * i + c] = drift(s.u[3 * i + c], s.v[3 * i + c], s.dt);
}

// Verlet's second half kick of particle i; the smallest stretch becomes the last pass's.
HORIZON_HD inline void kick_row(const FlatSystem& s, uint64_t i) {
  const double half = 0.5 * s.dt, damp = 1.0 / (1.0 + s.damping * half), h = half / s.density[i];
  for (int c = 0; c < 3; ++c) {
    const uint64_t q = 3 * i + c;
    s.v[q] = second_half_kick(s.v[q], s.f[q], s.b[q], h, damp);
  }
  s.min_stretch[i] = s.min_stretch_next[i];
}

// The force pass on the host, row by row (the CUDA backend launches each loop as a kernel).
inline void flat_forces(const FlatSystem& s) {
  for (uint64_t i = 0; i < s.n; ++i) pack_row(s, i);
  if (!s.state_based) {
    for (uint64_t i = 0; i < s.n; ++i) bond_based_row(s, i);
    return;
  }
  for (uint64_t i = 0; i < s.n; ++i) dilatation_row(s, i);
  for (uint64_t i = 0; i < s.n; ++i) pressure_row(s, i);
  for (uint64_t i = 0; i < s.n; ++i) force_row(s, i);
}

// `steps` explicit steps on the host; returns the bonds broken.
inline uint64_t advance_flat(const FlatSystem& s, int64_t steps) {
  uint64_t broken = 0;
  for (int64_t k = 0; k < steps; ++k) {
    for (uint64_t i = 0; i < s.n; ++i) kick_drift_row(s, i);
    flat_forces(s);
    for (uint64_t i = 0; i < s.n; ++i) {
      kick_row(s, i);
      broken += s.broken[i];
    }
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
