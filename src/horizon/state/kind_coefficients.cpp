// The per-kind coefficients of the bond loops and the damage field's bookkeeping
// (state/system.hpp), from the bonds and the per-particle coefficients. Compiled with the
// force pass's options (CMakeLists.txt), as it was when it lived in solver/forces.cpp.
#include <cstdint>
#include <vector>

#include "horizon/state/system.hpp"

namespace horizon {

namespace {

inline double total8(const double* v) { return ((v[0] + v[1]) + (v[2] + v[3])) + ((v[4] + v[5]) + (v[6] + v[7])); }

// Sum of the damage weights of i's bonds (all, or the intact ones alone), in the lanes
// of the bond loops: an undamaged particle then has damage 0 exactly, and one with no
// intact bond 1 exactly. A bond marked to break after this pass's force (intact 2) is
// already out of the intact sum.
double lane_sum_damage(const System& s, std::size_t i, bool intact_only) {
  const auto& B = s.bonds;
  double lanes[8] = {};
  for (uint64_t k = B.begin(i); k < B.end(i); ++k)
    if (!intact_only || B.intact[k] == 1) lanes[(k - B.begin(i)) & 7] += s.model.kind[B.kind[k]].damage;
  return total8(lanes);
}

}  // namespace

double intact_damage_weight(const System& s, std::size_t i) { return lane_sum_damage(s, i, true); }

void build_kind_tables(System& s, DamageMeasure measure) {
  const auto& B = s.bonds;
  auto& M = s.model;
  M.damage_measure = measure;
  const std::size_t n = s.particles.size(), nk = B.kinds.size();
  // The per-particle coefficients of a kind's two ends, from any bond of that kind
  // (coefficients are per material, and a kind joins one pair of materials).
  std::vector<int64_t> end_i(nk, -1), end_j(nk, -1);
  for (std::size_t i = 0; i < n; ++i)
    for (uint64_t k = B.begin(i); k < B.end(i); ++k)
      if (end_i[B.kind[k]] < 0) end_i[B.kind[k]] = static_cast<int64_t>(i), end_j[B.kind[k]] = B.nbr[k];
  const bool contact = s.contact.enabled();
  const double factor = contact ? s.contact.config().stiffness_factor / s.horizon : 0.0;
  M.kind.assign(nk, KindCoefficients{});
  for (std::size_t q = 0; q < nk; ++q) {
    const BondKind& b = B.kinds[q];
    KindCoefficients& c = M.kind[q];
    c.length = b.length;
    c.inv_length = 1.0 / b.length;  // (bonds with their own lengths: set below)
    c.wv = b.weight * b.volume * b.fraction;
    c.damage = measure == DamageMeasure::weighted ? c.wv : b.volume;
    if (b.one_way) c.damage = 0;  // outside i's family (restrict_to_horizons): not in i's damage
    if (end_i[q] < 0) continue;  // no bond of this kind left (all cut by precracks)
    const auto i = static_cast<std::size_t>(end_i[q]), j = static_cast<std::size_t>(end_j[q]);
    if (B.length_per_bond) {
      // Bonds with their own lengths: the loops divide by L and take the contact distance
      // from it (solver/forces.cpp, Ctx::lengths); the kind keeps what does not depend on L.
      c.length = c.inv_length = 0;
      c.pair = c.wv * (M.pair_coef[i] + M.pair_coef[j]);
      if (contact) c.contact_k = factor * 0.5 * (M.contact_micromodulus[i] + M.contact_micromodulus[j]) * b.volume;
      continue;
    }
    c.pair = c.wv * (M.pair_coef[i] + M.pair_coef[j]) / b.length;
    if (contact) {
      c.contact_d = s.contact.family_distance(b.length);
      c.contact_d2 = c.contact_d * c.contact_d;
      // LAMMPS PERI uses the neighbour's whole volume here, not the partial one.
      c.contact_k = factor * 0.5 * (M.contact_micromodulus[i] + M.contact_micromodulus[j]) * b.volume;
    }
  }
  // The kind records of the state-based passes, as their SIMD loops read them whole.
  M.kind_dilatation.resize(nk);
  M.kind_force.resize(nk);
  M.kind_rows.clear();  // rebuilt from these by the scalar general pass (state/system.hpp)
  for (std::size_t q = 0; q < nk; ++q) {
    const KindCoefficients& c = M.kind[q];
    M.kind_dilatation[q] = {c.length, c.inv_length, c.wv, 0.0};
    M.kind_force[q] = {c.length, c.wv, c.pair, c.contact_d2};
  }
}

void build_kind_coefficients(System& s, DamageMeasure measure) {
  build_kind_tables(s, measure);
  refresh_damage(s);
}

void refresh_damage(System& s) {
  auto& M = s.model;
  const std::size_t n = s.particles.size();
  M.damage_total.assign(n, 0);
  M.intact_weight.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    M.damage_total[i] = lane_sum_damage(s, i, false);
    M.intact_weight[i] = lane_sum_damage(s, i, true);
    s.particles.damage[i] = damage_of(M.intact_weight[i], M.damage_total[i]);
  }
}

}  // namespace horizon
