#include "horizon/solver/forces_general.hpp"

#include <cmath>
#include <limits>

#include "horizon/kernels/unified.hpp"
#include "horizon/parallel/decomposition.hpp"
#include "horizon/solver/forces.hpp"
#include "horizon/family/bond_helpers.hpp"
#include "horizon/solver/tangent.hpp"

namespace horizon {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

inline Vec3 delta(const Point4& a, const Point4& b) { return {b.x - a.x, b.y - a.y, b.z - a.z}; }

// The free thermal extension of bond i-j: eps_ij |xi| with eps_ij = (eps_i + eps_j)/2,
// eps = alpha (T - T_ref) (System::thermal_strain). A bond-based force then follows the
// stretch s - alpha dT (Oterkus, Madenci and Agwai 2014, J. Mech. Phys. Solids 64:1;
// Kilic and Madenci 2010), and a state-based dilatation becomes theta - d alpha dT on a full
// family (Madenci and Oterkus 2014, "Peridynamic Theory and Its Applications", sec. 7),
// so a free body heated uniformly expands without force.
inline double thermal_extension(const double* eps, std::size_t i, std::size_t j, double length) {
  return eps ? 0.5 * (eps[i] + eps[j]) * length : 0.0;
}

// Pass 1 of one row: breaking, the smallest stretch, the damage bookkeeping.
struct BreakOut {
  double smin = kInf, lost = 0;
  uint64_t broken = 0;
};

BreakOut break_row(System& s, std::size_t i, bool after) {
  auto& B = s.bonds;
  auto& M = s.model;
  const Point4* pt = M.packed.data();
  const Point4 pi = pt[i];
  const double* eps = s.thermal_strain.empty() ? nullptr : s.thermal_strain.data();
  // A temperature-dependent critical stretch scales each end's s0 (an end that never
  // breaks, s0 = +inf, stays so).
  const double* soft = s.critical_stretch_factor.empty() ? nullptr : s.critical_stretch_factor.data();
  auto scaled = [](double w, double f) { return std::isinf(w) ? w : w * f; };
  const double wi = soft ? scaled(pi.w, soft[i]) : pi.w;
  BreakOut out;
  for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
    if (!B.intact[k]) continue;
    const KindCoefficients& kc = M.kind[B.kind[k]];
    const Point4 pj = pt[B.nbr[k]];
    const Vec3 Y = delta(pi, pj);
    // The mechanical stretch: less the thermal strain of the bond (thermal_extension).
    const double r = kernels::bond_length(Y.x, Y.y, Y.z),
                 e = kernels::extension(r, kc.length, thermal_extension(eps, i, B.nbr[k], kc.length)),
                 stretch = e * kc.inv_length;
    out.smin = stretch < out.smin ? stretch : out.smin;
    const double wj = soft ? scaled(pj.w, soft[B.nbr[k]]) : pj.w;
    if (!kernels::breaks(stretch, wi, wj)) continue;
    B.intact[k] = after ? 2 : 0;
    ++out.broken;
    if (r > 0) out.lost += 0.5 * dot(M.force_state[k], Y) / r * e * B.volume[k];
    M.intact_weight[i] -= kc.damage;
  }
  return out;
}

// The force states of the particles whose model is unified (state/system.hpp).
// With a thermal strain, e is the mechanical extension e - eps_ij |xi| in the dilatation,
// the force and the energy alike (thermal_extension).
void unified_force_states(System& s, bool energy) {
  auto& P = s.particles;
  auto& B = s.bonds;
  auto& M = s.model;
  const Point4* pt = M.packed.data();
  const double* eps = s.thermal_strain.empty() ? nullptr : s.thermal_strain.data();
  // A decomposed run computes the rows of its active particles alone (state/system.hpp).
  const std::vector<uint32_t>* act = s.active_rows.empty() ? nullptr : &s.active_rows;
  const std::size_t n = act ? act->size() : P.size();
  std::vector<uint8_t> mine(s.models.size());
  for (std::size_t m = 0; m < s.models.size(); ++m) mine[m] = s.models[m].unified() ? 1 : 0;
#pragma omp parallel for schedule(static)
  for (std::size_t a = 0; a < n; ++a) {
    const std::size_t i = act ? (*act)[a] : a;
    if (!mine[P.material[i]]) continue;
    const Point4 pi = pt[i];
    double Pi = 0;
    if (M.dilatation_coef[i] != 0) {
      // theta_i = (d/m_i) sum_j omega |xi| e V_j over the acting bonds (seed 003 eq. 113).
      double sum = 0;
      for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
        if (!B.intact[k]) continue;
        const KindCoefficients& kc = M.kind[B.kind[k]];
        const Vec3 Y = delta(pi, pt[B.nbr[k]]);
        sum += kernels::dilatation_term(
            kc.wv, kc.length,
            kernels::extension(kernels::bond_length(Y.x, Y.y, Y.z), kc.length,
                               thermal_extension(eps, i, B.nbr[k], kc.length)));
      }
      const double theta = kernels::dilatation(M.dim, sum, M.weighted_volume[i]);
      M.theta[i] = theta;
      Pi = kernels::dilatation_pressure(theta, M.dilatation_coef[i], M.deviatoric_coef[i], M.dim);
      M.P[i] = Pi;
    }
    double W = 0;
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
      if (!B.intact[k]) {
        M.force_state[k] = {};
        continue;
      }
      const KindCoefficients& kc = M.kind[B.kind[k]];
      const Vec3 Y = delta(pi, pt[B.nbr[k]]);
      const double r = kernels::bond_length(Y.x, Y.y, Y.z),
                   e = kernels::extension(r, kc.length, thermal_extension(eps, i, B.nbr[k], kc.length));
      const double omega = B.kinds[B.kind[k]].weight;
      const double t = kernels::unified_force_scalar(omega, Pi, M.deviatoric_coef[i], M.pair_coef[i], kc.length,
                                                     kc.inv_length, e);
      M.force_state[k] = (t / r) * Y;
      W += kernels::bond_work(t, e, B.volume[k]);  // W_i = (1/2) sum_j t_ij e_ij V_j (exact for the unified form)
    }
    if (energy) P.energy[i] = W;
  }
}

}  // namespace

uint64_t general_forces(System& s, bool energy) {
  auto& P = s.particles;
  auto& B = s.bonds;
  auto& M = s.model;
  const std::size_t n = P.size(), nb = B.size();
  if (affine_general_pass(s)) {
    pack_positions(s);
    return affine_forces(s, energy);  // solver/forces_affine.cpp
  }
  if (!general_reference() && s.models.size() == 1 && s.models[0].takes_pair_pass(s)) {
    pack_positions(s);
    return s.models[0].pair_forces(s, energy);  // the model's pair form (Model::takes_pair_pass)
  }
  pack_positions(s);
  if (scalar_general_pass(s)) return ordinary_forces(s, energy);  // solver/forces_ordinary.cpp (its own reverse index)
  if (M.reverse.size() != nb) M.reverse = reverse_bonds(B, s.decomposition && s.decomposition->local_rows);
  if (M.force_state.size() != nb) M.force_state.assign(nb, Vec3{});
  const bool after = M.break_after_force;
  // A decomposed run computes the rows of its active particles alone: its own and their
  // bond neighbours', whose T_ji enter f_i (parallel/decomposition.hpp).
  const std::vector<uint32_t>* act = s.active_rows.empty() ? nullptr : &s.active_rows;
  const std::size_t rows = act ? act->size() : n;

  uint64_t broken = 0;
#pragma omp parallel for schedule(static) reduction(+ : broken)
  for (std::size_t a = 0; a < rows; ++a) {
    const std::size_t i = act ? (*act)[a] : a;
    const BreakOut o = break_row(s, i, after);
    broken += o.broken;
    if (o.lost != 0) s.dissipated_at[i] += o.lost * P.volume[i];
    if (o.broken) M.intact_weight[i] = intact_damage_weight(s, i);  // afresh (state/system.hpp)
    P.damage[i] = damage_of(M.intact_weight[i], M.damage_total[i]);
    M.min_stretch_next[i] = o.smin;
  }

  if (energy)
    for (std::size_t i = 0; i < n; ++i) P.energy[i] = 0;
  unified_force_states(s, energy);
  ForcePass pass{s, M.packed.data(), M.force_state.data(), energy ? P.energy.data() : nullptr, s.time, s.dt};
  for (std::size_t m = 0; m < s.models.size(); ++m)
    if (!s.models[m].unified()) s.models[m].force_state(pass);

  const Point4* pt = M.packed.data();
  const Vec3* T = M.force_state.data();
#pragma omp parallel for schedule(static)
  for (std::size_t a = 0; a < rows; ++a) {
    const std::size_t i = act ? (*act)[a] : a;
    const Point4 pi = pt[i];
    Vec3 f;
    double w = 0;
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
      // T_ji lies in j's row, up to a horizon of rows away: asked for 64 bonds ahead, as
      // the scalar form does (forces_ordinary.cpp).
      if (k + 64 < nb) __builtin_prefetch(T + M.reverse[k + 64]);
      if (B.intact[k]) f += B.volume[k] * (T[k] - T[M.reverse[k]]);
      const KindCoefficients& kc = M.kind[B.kind[k]];
      const Vec3 Y = delta(pi, pt[B.nbr[k]]);
      Vec3 fc;
      double wc = 0;
      if (family_contact(kc, Y, fc, wc)) {
        f += fc;
        w += wc;
      }
    }
    P.f[i] = f;
    if (energy) P.energy[i] += w;
  }
  if (after)
    for (std::size_t k = 0; k < nb; ++k)
      if (B.intact[k] == 2) B.intact[k] = 0;
  return broken;
}

}  // namespace horizon
