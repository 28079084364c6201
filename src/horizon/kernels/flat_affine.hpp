#pragma once
// The correspondence model's affine pass over the flat arrays (kernels/flat_system.hpp
// FlatSystem::affine): the rows that solver/forces_affine.cpp and Correspondence::affine_row
// run on the host, as row functions of one particle each, so that the flat backend and the
// CUDA backend step a correspondence run with the CPU backend's bits (docs/design.md,
// "Backends and portable kernels").
//
// A pass is three sweeps, each one row a thread:
//   1. flat_affine_break_row: the breaking sweep of kernels/affine.hpp (affine_break_row,
//      the fast loops' lanes: the same sums of K and N), the damage bookkeeping of
//      forces_affine.cpp, then the law of the row (kernels/laws.hpp law_row: linear
//      elastic, neo-Hookean, J2; or kernels/hypoelastic.hpp hypo_step for the rate-form
//      laws, F_dot from rate_gradient_row), the record, the von Mises stress, the trial
//      history and the law's energy (Correspondence::affine_row, operation for operation);
//   2. flat_affine_sum_row, once every row has its record: affine_sum_row (the pair form
//      and the family contact) and in its bond loop the stabilisation's energy (the host
//      row adds it in a loop of its own, in the same order: no second sweep of the bonds
//      here), the positions of the pass kept for the next pass's booking of broken
//      bonds, bonds broken in this pass (break_after) switched off;
//   3. flat_affine_commit_row: the trial history becomes the committed one and the plastic
//      work goes to the particle's dissipation (Correspondence::commit, which the explicit
//      solver calls after every force pass).
// The law's history lives here in plain structs (J2History, HypoHistory); the flat copy
// (solver/flat_affine_copy.cpp) converts from and to the model's History.
#include <cstdint>
#include <type_traits>

#include "horizon/core/portable.hpp"
#include "horizon/core/vec3.hpp"
#include "horizon/kernels/affine.hpp"
#include "horizon/kernels/hypoelastic.hpp"
#include "horizon/kernels/laws.hpp"

namespace horizon::kernels {

struct FlatPoint;  // kernels/flat_system.hpp

// family/bonds.hpp BondKind's members that the breaking sweep reads (affine_break_bond).
struct FlatBondKind {
  double volume, fraction, weight;
};

// One correspondence material's constants (material/models/correspondence.cpp).
struct FlatAffineLaw {
  int dim = 3;           // the law's dimension (2: plane strain)
  double tolerance = 0;  // shape_tolerance
  double G = 0;          // the stabilisation modulus
  bool rate = false;     // a rate-form law (hypo_step), else law_row's `law`
  LawConstants law;      // (the rate form: law.yield_stress its sigma_y, 0 for hypoelastic)
  HypoConstants hypo;
};

// The correspondence models' constants and state, every particle of the run a row of one
// of them (its material's).
struct FlatAffine {
  bool contact = false;  // the family pairs' short-range contact (ShortRangeContact::acts_on_family)
  uint64_t nlaws = 0;
  const FlatAffineLaw* laws = nullptr;  // per material
  const uint32_t* material = nullptr;   // n: the particle's material (Particles::material)
  const FlatPoint* ref = nullptr;          // n: X packed {x, y, z, 0}
  const FlatPoint* kind_record = nullptr;  // per kind {L, 1/L, omega V_j, 0} (System::model.kind_dilatation)
  const FlatBondKind* bond_kinds = nullptr;  // per kind
  const double* omega_volume = nullptr;    // per kind: omega (V_j fraction), B.weight[k] * B.volume[k]
  double* record = nullptr;                // kAffineRecord n (System::model.affine_record)
  Vec3* y_old = nullptr;                   // n: the positions of the last pass (System::model.affine_position)
  double* work = nullptr;                  // n: the plastic work of the trial step [J/m^3]
  double* von_mises = nullptr;             // n
  uint8_t* singular = nullptr;             // n: 1 where the shape tensor was refused
  double* F_pass = nullptr;                // 9n: F of this pass (the sum row's stabilisation energy)
  J2History* j2_committed = nullptr;       // n (law J2), else null
  J2History* j2_trial = nullptr;
  // The rate-form laws: history, F_dot's u at the last commit, the flaw's factor on the
  // yield stress, and the output tensors of the last pass (K^-1, F, sigma, d; row-major).
  HypoHistory* hypo_committed = nullptr;  // n
  HypoHistory* hypo_trial = nullptr;
  double* u_committed = nullptr;          // 3n, or null (F_dot then (F - F_n)/dt)
  const double* yield_factor = nullptr;   // n
  double* kinv = nullptr;                 // 9n each
  double* F = nullptr;
  double* sigma = nullptr;
  double* d = nullptr;
};

// w = omega V_j of bond k as the host's B.weight[k] * B.volume[k] (rate_gradient_row).
struct FlatOmegaVolume {
  const uint32_t* kind;
  const double* per_kind;
  HORIZON_HD double operator()(uint64_t k) const { return per_kind[kind[k]]; }
};

// The sweep of kernels/affine.hpp over the flat arrays (Sys: FlatSystem).
template <class Sys, class Point = FlatPoint>
HORIZON_HD inline auto flat_affine_sweep(const Sys& s)
    -> AffineSweep<std::remove_cv_t<std::remove_pointer_t<decltype(s.kinds)>>, FlatBondKind, Point> {
  AffineSweep<std::remove_cv_t<std::remove_pointer_t<decltype(s.kinds)>>, FlatBondKind, Point> w;
  const FlatAffine& a = s.affine;
  w.pt = reinterpret_cast<const Point*>(s.y4);
  w.ref = a.ref;
  w.y_old = a.y_old;
  w.record = a.record;
  w.kc = s.kinds;
  w.kind_record = a.kind_record;
  w.kinds = a.bond_kinds;
  w.nbr = s.nbr;
  w.kind = s.kind;
  w.offset = s.offset;
  w.intact = s.intact;
  w.intact_weight = s.intact_weight;
  w.total = s.nb;
  w.after = s.break_after;
  w.contact = a.contact;
  return w;
}

// The law of row i from its sums (Correspondence::affine_row): the record, the trial
// history, the von Mises stress; the law's energy density back, with `carries` false when
// the shape tensor is refused (then the energy is 0 and no stabilisation energy is added).
template <class Sys>
HORIZON_HD inline double flat_affine_law(const Sys& s, uint64_t i, const double* sums, double* F, bool& carries) {
  const FlatAffine& a = s.affine;
  const FlatAffineLaw& m = a.laws[a.material[i]];
  double* rec = a.record + kAffineRecord * i;
  if (!m.rate) {
    J2History none{};
    const bool j2 = m.law.law == kJ2Law;  // (the J2 arrays exist when a material is J2)
    J2History trial;
    const AffineRow row = law_row(sums, m.dim, m.tolerance, m.law, m.G, j2 ? a.j2_committed[i] : none, trial,
                                  a.work[i], rec);
    if (j2) a.j2_trial[i] = trial;
    a.singular[i] = row.carries ? 0 : 1;
    a.von_mises[i] = row.von_mises;
    carries = row.carries;
    for (int c = 0; c < 9; ++c) F[c] = row.F[c];
    return row.carries ? row.W : 0.0;
  }
  // The rate-form laws (Correspondence::hypo_row).
  double Kinv[9];
  carries = gradient_finish(sums, sums + 9, m.dim, m.tolerance, Kinv, F);
  a.singular[i] = carries ? 0 : 1;
  if (!carries) {  // refuse_singular: the history stays, the record is zero
    a.hypo_trial[i] = a.hypo_committed[i];
    a.work[i] = 0;
    a.von_mises[i] = 0;
    affine_record(nullptr, nullptr, 0.0, rec);
    return 0.0;
  }
  const double dt = s.dt;
  double Fdot[9];
  const bool rate = dt > 0 && a.u_committed;
  if (rate) {
    double N[9];
    rate_gradient_row(s.X, s.u, a.u_committed, s.offset, s.nbr, s.intact, FlatOmegaVolume{s.kind, a.omega_volume}, i,
                      N);
    rate_gradient_finish(N, Kinv, dt, Fdot);
  }
  const double yield = m.law.yield_stress * a.yield_factor[i];  // 0 for hypoelastic (set so by the copy)
  LawStress r;
  double* d = a.d + 9 * i;
  HypoHistory t;
  hypo_step(m.hypo, yield, a.hypo_committed[i], F, dt, rate ? Fdot : nullptr, 0.0, t, a.work[i], r, d);
  a.hypo_trial[i] = t;
  for (int k = 0; k < 9; ++k) a.kinv[9 * i + k] = Kinv[k], a.F[9 * i + k] = F[k], a.sigma[9 * i + k] = r.sigma[k];
  a.von_mises[i] = von_mises(t.sigma_u);
  if (!r.ok) {
    affine_record(nullptr, F, m.G, rec);
    return 0.0;
  }
  affine_record_of_stress(r.P, Kinv, F, m.G, rec);  // T = omega P K^-1 xi (seed 003 eq. 142)
  return r.W;
}

// Sweep 1, row i: breaking (forces_affine.cpp's first loop), then the model's row.
template <class Sys>
HORIZON_HD inline void flat_affine_break_row(const Sys& s, uint64_t i) {
  const FlatAffine& a = s.affine;
  const auto w = flat_affine_sweep(s);
  double sums[18];  // K, then N
  const AffineBreak o = affine_break_row(w, i, sums);
  s.broken[i] = o.broken;
  if (o.lost != 0) s.dissipated[i] += o.lost * s.volume[i];
  if (o.broken) s.intact_weight[i] = intact_weight_lanes(s.offset, s.intact, s.kind, s.kinds, i);
  s.damage[i] = damage_fraction(s.intact_weight[i], s.damage_total[i]);
  s.min_stretch_next[i] = o.smin;
  double F[9];
  bool carries = false;
  // The law's energy density; the stabilisation's follows in the sum row's bond loop.
  s.energy[i] = flat_affine_law(s, i, sums, F, carries);
  for (int c = 0; c < 9; ++c) a.F_pass[9 * i + c] = F[c];
}

// Sweep 2, row i: the force density; the energy: the stabilisation's, (G/2) omega V_j
// |Y - F xi|^2 of each acting bond in bond order added to the law's (as
// Correspondence::affine_row adds it after the law, with the bonds' Y and xi as it forms
// them), where the shape tensor was taken and G != 0, then the contact's share; the pass's
// position kept, the bonds this pass broke but let act (break_after: 2) switched off.
template <class Sys>
HORIZON_HD inline void flat_affine_sum_row(const Sys& s, uint64_t i) {
  const FlatAffine& a = s.affine;
  const auto w = flat_affine_sweep(s);
  const double G = a.laws[a.material[i]].G;
  const bool stabilised = G != 0 && !a.singular[i];
  double F[9];
  for (int c = 0; c < 9; ++c) F[c] = a.F_pass[9 * i + c];
  double W = s.energy[i];
  const auto bond = [&](uint64_t k, const double* xi, const double* Y) {
    if (stabilised) W += stabilization_energy(F, G, a.omega_volume[s.kind[k]], xi, Y);
  };
  double f[3], e = 0;
  affine_sum_row(w, i, f, e, bond);
  s.f[3 * i] = f[0], s.f[3 * i + 1] = f[1], s.f[3 * i + 2] = f[2];
  s.energy[i] = W;
  s.energy[i] += e;
  s.affine.y_old[i] = {w.pt[i].x, w.pt[i].y, w.pt[i].z};
  if (s.break_after)
    for (uint64_t k = s.offset[i]; k < s.offset[i + 1]; ++k)
      if (s.intact[k] == 2) s.intact[k] = 0;
}

// Sweep 3, row i: Correspondence::commit.
template <class Sys>
HORIZON_HD inline void flat_affine_commit_row(const Sys& s, uint64_t i) {
  const FlatAffine& a = s.affine;
  if (a.j2_committed) a.j2_committed[i] = a.j2_trial[i];
  if (a.hypo_committed) a.hypo_committed[i] = a.hypo_trial[i];
  if (a.u_committed)
    for (int c = 0; c < 3; ++c) a.u_committed[3 * i + c] = s.u[3 * i + c];
  if (a.work[i] != 0) s.dissipated[i] += a.work[i] * s.volume[i];
  a.work[i] = 0;
}

}  // namespace horizon::kernels
