#include "horizon/solver/forces.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

// The bond loops below walk each particle's row in blocks of kLanes bonds: the
// neighbours' data are gathered into small arrays, and the arithmetic of a block is a
// loop over lanes that the compiler turns into SIMD instructions (SSE with the
// default -march=x86-64-v2, AVX with wider targets; check with -fopt-info-vec). Each
// lane keeps its own partial sums, added in a fixed order at the end of the row, so
// the result does not depend on the SIMD width or the thread count. Rare events
// (a bond breaks, two particles touch) leave the SIMD path and are handled one by one.
// docs/benchmarks.md has the measurements behind these choices.

namespace horizon {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kLanes = 4;

// Current positions packed with each particle's critical stretch for this pass:
// s0_i = critical_stretch_i - alpha_i min_stretch_i (DamageConfig::alpha), +inf where
// bonds may not break (no_fail regions, no damage law).
void pack_positions(System& s) {
  auto& P = s.particles;
  auto& M = s.model;
  const std::size_t n = P.size();
  M.packed.resize(n);
  M.min_stretch_next.resize(n);
  if (M.min_stretch.size() != n) M.min_stretch.assign(n, 0);
  if (M.alpha.size() != n) M.alpha.assign(n, 0);
  Point4* out = M.packed.data();
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 y = P.X[i] + P.u[i];
    double s0 = M.critical_stretch[i];
    if (M.alpha[i] != 0 && std::isfinite(M.min_stretch[i])) s0 -= M.alpha[i] * M.min_stretch[i];
    if (P.no_fail[i]) s0 = kInf;
    out[i] = {y.x, y.y, y.z, s0};
  }
}

// One block of a row: the bonds k0 .. k0 + count - 1, padded to kLanes with lanes
// that carry nothing (live = 0, Y = 0).
struct Block {
  alignas(32) double Yx[kLanes], Yy[kLanes], Yz[kLanes];
  alignas(32) double L[kLanes], iL[kLanes], wv[kLanes], pair[kLanes], dmg[kLanes], d2[kLanes];
  alignas(32) double wj[kLanes];    // the neighbour's packed value: s0_j, or P_j in the force pass
  alignas(32) double qj[kLanes];    // Q_j (force pass of state-based models)
  alignas(32) double live[kLanes];  // 1: intact (carries force), 0: broken or padding
  alignas(32) double once[kLanes];  // 1: intact and not breaking in this step (intact == 1)
};

struct RowData {
  const Point4* pt;
  const KindCoefficients* kc;
  const uint32_t* nbr;
  const uint32_t* kind;
  const uint8_t* intact;
  const double* Q;  // may be null
};

template <bool kWithQ>
inline void load_block(Block& b, const RowData& d, const Point4& pi, uint64_t k0, int count) {
  for (int l = 0; l < kLanes; ++l) {
    if (l < count) {
      const uint64_t k = k0 + static_cast<uint64_t>(l);
      const uint32_t j = d.nbr[k];
      const KindCoefficients& c = d.kc[d.kind[k]];
      const Point4 pj = d.pt[j];
      b.Yx[l] = pj.x - pi.x;
      b.Yy[l] = pj.y - pi.y;
      b.Yz[l] = pj.z - pi.z;
      b.L[l] = c.length;
      b.iL[l] = c.inv_length;
      b.wv[l] = c.wv;
      b.pair[l] = c.pair;
      b.dmg[l] = c.damage;
      b.d2[l] = c.contact_d2;
      b.wj[l] = pj.w;
      if constexpr (kWithQ) b.qj[l] = d.Q[j];
      const uint8_t s = d.intact[k];
      b.live[l] = s != 0 ? 1.0 : 0.0;
      b.once[l] = s == 1 ? 1.0 : 0.0;
    } else {
      b.Yx[l] = b.Yy[l] = b.Yz[l] = 0;
      b.L[l] = b.iL[l] = 1;
      b.wv[l] = b.pair[l] = b.dmg[l] = b.d2[l] = 0;
      b.wj[l] = kInf;
      if constexpr (kWithQ) b.qj[l] = 0;
      b.live[l] = b.once[l] = 0;
    }
  }
}

// Per-lane partial sums of one row.
struct Sums {
  alignas(32) double fx[kLanes] = {}, fy[kLanes] = {}, fz[kLanes] = {};
  alignas(32) double damage[kLanes] = {}, energy[kLanes] = {}, theta[kLanes] = {};
  alignas(32) double smin[kLanes] = {kInf, kInf, kInf, kInf};

  static double total(const double* v) { return (v[0] + v[1]) + (v[2] + v[3]); }
  double min_stretch() const { return std::min(std::min(smin[0], smin[1]), std::min(smin[2], smin[3])); }
};

// Short-range contact of one lane (rare): the push away from the neighbour when the
// two are closer than the kind's contact distance.
template <bool kEnergy>
inline void lane_contact(const KindCoefficients& c, const Block& b, int l, Sums& sums) {
  const double r2 = b.Yx[l] * b.Yx[l] + b.Yy[l] * b.Yy[l] + b.Yz[l] * b.Yz[l];
  if (!(r2 < c.contact_d2) || r2 == 0) return;
  const double r = std::sqrt(r2), overlap = c.contact_d - r;
  const double a = -c.contact_k * overlap / r;
  sums.fx[l] += a * b.Yx[l];
  sums.fy[l] += a * b.Yy[l];
  sums.fz[l] += a * b.Yz[l];
  if constexpr (kEnergy) sums.energy[l] += 0.25 * c.contact_k * overlap * overlap;
}

// Bond-based models need no dilatation, so breaking, damage, the smallest stretch,
// contact and force fuse into one pass over the bonds. kAfter: a breaking bond still
// carries its force in this step (DamageConfig::break_after_force).
template <bool kEnergy, bool kAfter>
uint64_t bond_based_pass(System& s) {
  auto& P = s.particles;
  auto& B = s.bonds;
  auto& M = s.model;
  const std::size_t n = P.size();
  const RowData d{M.packed.data(), M.kind.data(), B.nbr.data(), B.kind.data(), B.intact.data(), nullptr};
  uint8_t* intact = B.intact.data();
  uint64_t broken = 0;
#pragma omp parallel for schedule(static) reduction(+ : broken)
  for (std::size_t i = 0; i < n; ++i) {
    const Point4 pi = d.pt[i];
    const double s0i = pi.w, Ri = M.pair_coef[i];
    Sums sums;
    double lost = 0;
    for (uint64_t k0 = B.begin(i), end = B.end(i); k0 < end; k0 += kLanes) {
      const int count = static_cast<int>(std::min<uint64_t>(kLanes, end - k0));
      Block b;
      load_block<false>(b, d, pi, k0, count);
      int events = 0;
      for (int l = 0; l < kLanes; ++l) {
        const double r2 = b.Yx[l] * b.Yx[l] + b.Yy[l] * b.Yy[l] + b.Yz[l] * b.Yz[l];
        const double r = std::sqrt(r2), e = r - b.L[l], stretch = e * b.iL[l];
        const bool live = b.live[l] != 0;
        const bool breaks = live && stretch > std::min(s0i, b.wj[l]);
        const bool carries = kAfter ? live : live && !breaks;
        const bool stays = live && !breaks;
        const double a = carries ? b.pair[l] * e / r : 0.0;
        sums.fx[l] += a * b.Yx[l];
        sums.fy[l] += a * b.Yy[l];
        sums.fz[l] += a * b.Yz[l];
        sums.smin[l] = live && stretch < sums.smin[l] ? stretch : sums.smin[l];
        sums.damage[l] += stays ? b.dmg[l] : 0.0;
        if constexpr (kEnergy) sums.energy[l] += stays ? 0.5 * b.wv[l] * Ri * b.iL[l] * e * e : 0.0;
        events |= (breaks || r2 < b.d2[l]) ? 1 : 0;
      }
      if (events == 0) continue;
      for (int l = 0; l < count; ++l) {
        const uint64_t k = k0 + static_cast<uint64_t>(l);
        const KindCoefficients& c = d.kc[d.kind[k]];
        if (intact[k]) {
          const double r2 = b.Yx[l] * b.Yx[l] + b.Yy[l] * b.Yy[l] + b.Yz[l] * b.Yz[l];
          const double e = std::sqrt(r2) - b.L[l];
          if (e * b.iL[l] > std::min(s0i, b.wj[l])) {
            intact[k] = 0;
            ++broken;
            lost += 0.5 * c.wv * Ri * c.inv_length * e * e;  // (1/2) t_ij e V_j, as in break_and_dilate
          }
        }
        lane_contact<kEnergy>(c, b, l, sums);
      }
    }
    if (lost != 0) s.dissipated_at[i] += lost * P.volume[i];
    P.damage[i] = M.damage_total[i] > 0 ? 1.0 - Sums::total(sums.damage) / M.damage_total[i] : 0.0;
    M.min_stretch_next[i] = sums.min_stretch();
    P.f[i] = {Sums::total(sums.fx), Sums::total(sums.fy), Sums::total(sums.fz)};
    if constexpr (kEnergy) P.energy[i] = Sums::total(sums.energy);
  }
  return broken;
}

// Pass 1 of state-based models: breaking, damage, the smallest stretch and the
// dilatation. Without kAfter a breaking bond is gone at once (intact = 0) and leaves
// the dilatation; with kAfter it is marked (intact = 2), still counts in the dilatation
// and carries force in pass 2, which then clears it. Only row i is written.
template <bool kAfter>
uint64_t break_and_dilate(System& s) {
  auto& P = s.particles;
  auto& B = s.bonds;
  auto& M = s.model;
  const std::size_t n = P.size();
  const RowData d{M.packed.data(), M.kind.data(), B.nbr.data(), B.kind.data(), B.intact.data(), nullptr};
  uint8_t* intact = B.intact.data();
  uint64_t broken = 0;
#pragma omp parallel for schedule(static) reduction(+ : broken)
  for (std::size_t i = 0; i < n; ++i) {
    const Point4 pi = d.pt[i];
    const double s0i = pi.w, Ri = M.pair_coef[i], Pi = M.P[i], Qi = M.deviatoric_coef[i];
    Sums sums;
    double lost = 0;
    for (uint64_t k0 = B.begin(i), end = B.end(i); k0 < end; k0 += kLanes) {
      const int count = static_cast<int>(std::min<uint64_t>(kLanes, end - k0));
      Block b;
      load_block<false>(b, d, pi, k0, count);
      int events = 0;
      for (int l = 0; l < kLanes; ++l) {
        const double r2 = b.Yx[l] * b.Yx[l] + b.Yy[l] * b.Yy[l] + b.Yz[l] * b.Yz[l];
        const double e = std::sqrt(r2) - b.L[l], stretch = e * b.iL[l];
        const bool live = b.live[l] != 0;
        const bool breaks = live && stretch > std::min(s0i, b.wj[l]);
        const bool stays = live && !breaks;
        const bool counts = kAfter ? live : stays;
        sums.theta[l] += counts ? b.wv[l] * b.L[l] * e : 0.0;
        sums.smin[l] = live && stretch < sums.smin[l] ? stretch : sums.smin[l];
        sums.damage[l] += stays ? b.dmg[l] : 0.0;
        events |= breaks ? 1 : 0;
      }
      if (events == 0) continue;
      for (int l = 0; l < count; ++l) {
        const uint64_t k = k0 + static_cast<uint64_t>(l);
        if (!intact[k]) continue;
        const double r2 = b.Yx[l] * b.Yx[l] + b.Yy[l] * b.Yy[l] + b.Yz[l] * b.Yz[l];
        const double e = std::sqrt(r2) - b.L[l];
        if (!(e * b.iL[l] > std::min(s0i, b.wj[l]))) continue;
        intact[k] = kAfter ? 2 : 0;
        ++broken;
        // Energy held by this directed bond: (1/2) t_ij e V_j (seed 003 digest sec. 9,
        // W_i = (1/2) sum_j t_ij e_ij V_j for both models), with last pass's P_i.
        lost += 0.5 * b.wv[l] * (Pi * b.L[l] + (Qi + Ri * b.iL[l]) * e) * e;
      }
    }
    if (lost != 0) s.dissipated_at[i] += lost * P.volume[i];
    P.damage[i] = M.damage_total[i] > 0 ? 1.0 - Sums::total(sums.damage) / M.damage_total[i] : 0.0;
    M.min_stretch_next[i] = sums.min_stretch();
    if (M.dilatation_coef[i] != 0) {
      const double theta = M.dim * Sums::total(sums.theta) / M.weighted_volume[i];
      M.theta[i] = theta;
      M.P[i] = theta * (M.dilatation_coef[i] - M.deviatoric_coef[i] / M.dim);
    }
  }
  return broken;
}

// Pass 2 of state-based models: f_i = sum_j (t_ij + t_ji) Y/|Y| V_j over the bonds that
// carry force, plus the short-range contact of every family pair; bonds marked as
// breaking in pass 1 (intact = 2) are cleared. pt[j].w holds P_j.
template <bool kEnergy>
void internal_force(System& s) {
  auto& P = s.particles;
  auto& B = s.bonds;
  const auto& M = s.model;
  const std::size_t n = P.size();
  const RowData d{M.packed.data(), M.kind.data(), B.nbr.data(), B.kind.data(), B.intact.data(),
                  M.deviatoric_coef.data()};
  uint8_t* intact = B.intact.data();
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const Point4 pi = d.pt[i];
    const double Ri = M.pair_coef[i], Pi = pi.w, Qi = d.Q[i];
    Sums sums;
    for (uint64_t k0 = B.begin(i), end = B.end(i); k0 < end; k0 += kLanes) {
      const int count = static_cast<int>(std::min<uint64_t>(kLanes, end - k0));
      Block b;
      load_block<true>(b, d, pi, k0, count);
      int events = 0;
      for (int l = 0; l < kLanes; ++l) {
        const double r2 = b.Yx[l] * b.Yx[l] + b.Yy[l] * b.Yy[l] + b.Yz[l] * b.Yz[l];
        const double r = std::sqrt(r2), L = b.L[l], e = r - L;
        const double t = (Pi + b.wj[l]) * L + (Qi + b.qj[l]) * e;
        const double a = b.live[l] != 0 ? (b.wv[l] * t + b.pair[l] * e) / r : 0.0;
        sums.fx[l] += a * b.Yx[l];
        sums.fy[l] += a * b.Yy[l];
        sums.fz[l] += a * b.Yz[l];
        if constexpr (kEnergy)
          sums.energy[l] += b.once[l] != 0 ? 0.5 * b.wv[l] * (Pi * L + (Qi + Ri * b.iL[l]) * e) * e : 0.0;
        events |= (b.live[l] != b.once[l] || r2 < b.d2[l]) ? 1 : 0;
      }
      if (events == 0) continue;
      for (int l = 0; l < count; ++l) {
        const uint64_t k = k0 + static_cast<uint64_t>(l);
        if (intact[k] == 2) intact[k] = 0;
        lane_contact<kEnergy>(d.kc[d.kind[k]], b, l, sums);
      }
    }
    P.f[i] = {Sums::total(sums.fx), Sums::total(sums.fy), Sums::total(sums.fz)};
    if constexpr (kEnergy) P.energy[i] = Sums::total(sums.energy);
  }
}

}  // namespace

void build_kind_coefficients(System& s, DamageMeasure measure) {
  const auto& B = s.bonds;
  auto& M = s.model;
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
    c.inv_length = 1.0 / b.length;
    c.wv = b.weight * b.volume * b.fraction;
    c.damage = measure == DamageMeasure::weighted ? c.wv : b.volume;
    if (end_i[q] < 0) continue;  // no bond of this kind left (all cut by precracks)
    const auto i = static_cast<std::size_t>(end_i[q]), j = static_cast<std::size_t>(end_j[q]);
    c.pair = c.wv * (M.pair_coef[i] + M.pair_coef[j]) / b.length;
    if (contact) {
      c.contact_d = s.contact.distance(b.length);
      c.contact_d2 = c.contact_d * c.contact_d;
      // LAMMPS PERI uses the neighbour's whole volume here, not the partial one.
      c.contact_k = factor * 0.5 * (M.contact_micromodulus[i] + M.contact_micromodulus[j]) * b.volume;
    }
  }
  M.damage_total.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i)
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) M.damage_total[i] += M.kind[B.kind[k]].damage;
}

ForceStats compute_forces(System& s, bool energy) {
  ForceStats stats;
  auto& M = s.model;
  if (M.kind.size() != s.bonds.kinds.size() || M.damage_total.size() != s.particles.size())
    build_kind_coefficients(s, DamageMeasure::weighted);
  pack_positions(s);
  const bool after = M.break_after_force;
  if (M.state_based) {
    stats.broken = after ? break_and_dilate<true>(s) : break_and_dilate<false>(s);
    // Pass 2 gathers P_j with the position.
    const std::size_t n = s.particles.size();
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) M.packed[i].w = M.P[i];
    energy ? internal_force<true>(s) : internal_force<false>(s);
  } else if (after) {
    stats.broken = energy ? bond_based_pass<true, true>(s) : bond_based_pass<false, true>(s);
  } else {
    stats.broken = energy ? bond_based_pass<true, false>(s) : bond_based_pass<false, false>(s);
  }
  M.min_stretch.swap(M.min_stretch_next);
  s.contact.add_forces(s, M.packed.data(), s.particles.f.data(), energy ? s.particles.energy.data() : nullptr);
  s.broken += stats.broken;
  return stats;
}

double strain_energy(const System& s) {
  double sum = 0;
  for (std::size_t i = 0; i < s.particles.size(); ++i) sum += s.particles.energy[i] * s.particles.volume[i];
  return sum;
}

}  // namespace horizon
