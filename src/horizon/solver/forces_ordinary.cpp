// The scalar form of the general force pass (solver/forces_general.hpp, issue 31): when
// every model of the run writes its force states along the bonds (ModelTraits::ordinary,
// or the unified form), T_ij = t_ij Y/|Y|, the pass keeps one scalar per bond instead of
// a vector, and visits the bonds twice instead of four times:
//
//   1. per row i (one thread): break i's bonds by the critical-stretch law, store |Y| of
//      each, sum the dilatation of the acting bonds, then ask i's model for the scalar
//      force states of the row (Model::force_row) while the row is in cache;
//   2. per row i, once every row has its force states: f_i = sum_j (q_ij + q_ji) Y_ij V_j
//      with q = t/|Y| (seed 003 eq. 33 with T = t M, digest sec. 9), q_ji read through the
//      reverse-bond index (8 bytes, where the vector form gathers 24), and the contact.
//
// On AVX-512 machines both sweeps and the models' rows run in the fast loops' eight lanes
// (material/models/ordinary_lanes.hpp): the dilatation, the force and the models' row sums
// add in the lanes' order, so the forces differ from the vector form's bond-order sums by
// round-off (tests/verification/test_ordinary_pass.cpp: 1e-12 after 40 steps of a breaking
// impact) and are the same bits on every thread and rank count. Elsewhere the sweeps and
// rows run in bond order, the vector form's bits (break_row and the scalar sum below). Per bond,
// T_ij - T_ji = q_ij Y - q_ji (-Y) is q_ij Y + q_ji Y in every component, and |Y|, e are
// the same expressions. The energy booked for a bond broken in the pass differs from the
// vector form's by the bond's rotation in one step (history_ledger.hpp broken_bond_booking).
// A bond's row and the reverse bond's row decide its breaking alike (the same stretch
// bits), so a model's row reads only its own bonds' flags: the rows need no order.
#include <cmath>
#include <limits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "horizon/family/bond_helpers.hpp"
#include "horizon/kernels/unified.hpp"
#include "horizon/material/models/ordinary_lanes.hpp"
#include "horizon/parallel/decomposition.hpp"
#include "horizon/solver/forces.hpp"
#include "horizon/solver/forces_general.hpp"

namespace horizon {

namespace {

bool g_reference = false;

// The free thermal extension eps_ij |xi| of bond i-j (solver/forces_general.cpp).
inline double thermal_extension(const double* eps, std::size_t i, std::size_t j, double length) {
  return eps ? 0.5 * (eps[i] + eps[j]) * length : 0.0;
}

constexpr double kInf = std::numeric_limits<double>::infinity();

// How far ahead the scalar sum asks for the reverse bond's force state (bonds).
constexpr uint64_t kPrefetch = 64;

// --- The sweeps in bond order, without the lanes (material/models/ordinary_lanes.hpp
// wide(): machines without AVX-512). ---

// a < b ? a : b, kept in a vector register: written so, the compiler moved the row's
// smallest stretch through an integer register and a conditional move every bond, a
// chain of dependent instructions that set the breaking sweep's pace (perf, issue 31).
inline double smaller(double a, double b) {
#if defined(__SSE2__)
  return _mm_cvtsd_f64(_mm_min_sd(_mm_set_sd(a), _mm_set_sd(b)));  // minsd: a < b ? a : b
#else
  return a < b ? a : b;
#endif
}

struct RowOut {
  double smin = kInf, lost = 0, dilatation = 0;
  uint64_t broken = 0;
};

// Pass 1 of row i before its model: breaking (as forces_general.cpp break_row), |Y| of
// every bond, and sum_j omega V_j |xi| e over the bonds that act in this pass.
RowOut break_row(System& s, std::size_t i, bool after, const double* eps, const double* soft) {
  auto& B = s.bonds;
  auto& M = s.model;
  const Point4* pt = M.packed.data();
  const KindCoefficients* kind = M.kind.data();
  const uint32_t* kind_of = B.kind.data();
  const uint32_t* nbr = B.nbr.data();
  uint8_t* intact = B.intact.data();
  double* deformed = M.deformed_length.data();
  double* q = M.force_scalar.data();
  const Point4 pi = pt[i];
  auto scaled = [](double w, double f) { return std::isinf(w) ? w : w * f; };
  const double wi = soft ? scaled(pi.w, soft[i]) : pi.w;
  // The row's sums in locals, not in `out` (the returned object lives in memory: its
  // sums would carry a store and a load in every bond's chain of additions).
  double smin = kInf, dilatation = 0, lost = 0;
  uint64_t broken = 0;
  for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
    const KindCoefficients& kc = kind[kind_of[k]];
    const Point4 pj = pt[nbr[k]];
    const Vec3 Y{pj.x - pi.x, pj.y - pi.y, pj.z - pi.z};
    const double r = kernels::bond_length(Y.x, Y.y, Y.z), r_old = deformed[k];
    deformed[k] = r;
    if (!intact[k]) continue;
    const double e = kernels::extension(r, kc.length, thermal_extension(eps, i, nbr[k], kc.length)),
                 stretch = e * kc.inv_length;
    smin = smaller(stretch, smin);
    const double wj = soft ? scaled(pj.w, soft[nbr[k]]) : pj.w;
    if (kernels::breaks(stretch, wi, wj)) {
      intact[k] = after ? 2 : 0;
      ++broken;
      // (1/2) t_old e V_j, t_old = q_old |Y_old| the bond's force state of the previous
      // pass; the row's model books the same from q[k] (RowPass::t, history_ledger.hpp
      // broken_bond_booking).
      const double t_old = q[k] * r_old;
      q[k] = t_old;
      if (r > 0) lost += 0.5 * t_old * e * B.volume[k];
      M.intact_weight[i] -= kc.damage;
      if (!after) continue;
    }
    dilatation += kernels::dilatation_term(kc.wv, kc.length, e);
  }
  RowOut out;
  out.smin = smin;
  out.dilatation = dilatation;
  out.lost = lost;
  out.broken = broken;
  return out;
}

// The force states of a unified model's row (forces_general.cpp unified_force_states).
void unified_row(System& s, std::size_t i, double dilatation, const double* eps, double* energy) {
  auto& B = s.bonds;
  auto& M = s.model;
  const KindCoefficients* kind = M.kind.data();
  const double* deformed = M.deformed_length.data();
  double* q = M.force_scalar.data();
  double Pi = 0;
  if (M.dilatation_coef[i] != 0) {
    const double theta = kernels::dilatation(M.dim, dilatation, M.weighted_volume[i]);
    M.theta[i] = theta;
    Pi = kernels::dilatation_pressure(theta, M.dilatation_coef[i], M.deviatoric_coef[i], M.dim);
    M.P[i] = Pi;
  }
  double W = 0;
  for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
    if (!B.intact[k]) {
      q[k] = 0;
      continue;
    }
    const KindCoefficients& kc = kind[B.kind[k]];
    const double r = deformed[k], e = kernels::extension(r, kc.length, thermal_extension(eps, i, B.nbr[k], kc.length));
    const double omega = B.kinds[B.kind[k]].weight;
    const double t = kernels::unified_force_scalar(omega, Pi, M.deviatoric_coef[i], M.pair_coef[i], kc.length,
                                                   kc.inv_length, e);
    q[k] = t / r;
    W += kernels::bond_work(t, e, B.volume[k]);  // W_i = (1/2) sum_j t_ij e_ij V_j (exact for the unified form)
  }
  if (energy) energy[i] = W;
}

}  // namespace

void set_general_reference(bool reference) { g_reference = reference; }
bool general_reference() { return g_reference; }

bool scalar_general_pass(const System& s) {
  if (g_reference) return false;
  for (const auto& m : s.models)
    if (!m->unified() && !m->traits().ordinary) return false;
  return true;
}

uint64_t ordinary_forces(System& s, bool energy) {
  auto& P = s.particles;
  auto& B = s.bonds;
  auto& M = s.model;
  const std::size_t n = P.size(), nb = B.size();
  if (M.deformed_length.size() != nb) M.deformed_length.assign(nb, 0);
  if (M.force_scalar.size() != nb) M.force_scalar.assign(nb, 0);
  const bool after = M.break_after_force;
  const double* eps = s.thermal_strain.empty() ? nullptr : s.thermal_strain.data();
  // A temperature-dependent critical stretch scales each end's s0 (forces_general.cpp).
  const double* soft = s.critical_stretch_factor.empty() ? nullptr : s.critical_stretch_factor.data();
  const std::vector<uint32_t>* act = s.active_rows.empty() ? nullptr : &s.active_rows;
  const std::size_t rows = act ? act->size() : n;
  if (energy)
    for (std::size_t i = 0; i < n; ++i) P.energy[i] = 0;

  // The kinds' records of the models' rows (System::model.kind_rows), built once after the
  // kinds are: {|xi|, omega, omega V_j, V_j}.
  if (M.kind_rows.size() != B.kinds.size()) {
    M.kind_rows.resize(B.kinds.size());
    for (std::size_t q = 0; q < B.kinds.size(); ++q) {
      const BondKind& bk = B.kinds[q];
      M.kind_rows[q] = {M.kind[q].length, bk.weight, M.kind[q].wv, bk.volume * bk.fraction};
    }
  }
  const RowPass pass{s,      M.packed.data(), M.deformed_length.data(), M.force_scalar.data(),
                     energy ? P.energy.data() : nullptr, s.time, s.dt, M.kind_rows.data()};
  // Per material: its model when it takes rows, null for a unified one (kept between
  // passes: no allocation in a step).
  static thread_local std::vector<Model*> row_model;
  row_model.assign(s.models.size(), nullptr);
  for (std::size_t m = 0; m < s.models.size(); ++m)
    if (!s.models[m].unified()) {
      row_model[m] = &s.models[m];
      row_model[m]->begin_rows(pass);
    }
  Model* const* model_of = row_model.data();  // (the threads of the loop below see this thread's vector)

  // The two bond sweeps in the models' lanes (material/models/ordinary_lanes.hpp).
  lanes::Sweep sw;
  sw.pt = M.packed.data();
  sw.kind_dilatation = M.kind_dilatation.data();
  sw.kinds = M.kind_rows.data();
  sw.kc = M.kind.data();
  sw.nbr = B.nbr.data();
  sw.kind = B.kind.data();
  sw.offset = B.offset.data();
  sw.intact = B.intact.data();
  sw.deformed = M.deformed_length.data();
  sw.q = M.force_scalar.data();
  sw.intact_weight = M.intact_weight.data();
  sw.eps = eps;
  sw.soft = soft;
  sw.total = nb;
  sw.after = after;
  // Without the short-range contact between family pairs every kind's contact distance is
  // 0 (state/kind_coefficients.cpp), and family_contact would only say so, bond by bond.
  sw.contact = s.contact.acts_on_family();

  const bool wide = lanes::wide();
  // The reverse index, in 4 bytes where the lanes' sum reads it and the bonds allow
  // (System::model.reverse32; the 8-byte one is then not kept).
  const bool narrow = wide && nb < (uint64_t{1} << 32);
  if (narrow ? M.reverse32.size() != nb : M.reverse.size() != nb) {
    M.reverse = reverse_bonds(B, s.decomposition && s.decomposition->local_rows);
    if (narrow) {
      M.reverse32.resize(nb);
      for (std::size_t k = 0; k < nb; ++k) M.reverse32[k] = static_cast<uint32_t>(M.reverse[k]);
      std::vector<uint64_t>().swap(M.reverse);
    }
  }
  sw.rev = M.reverse.data();
  if (narrow) sw.rev32 = M.reverse32.data();
  // A pass of the lanes without a thermal strain leaves |Y| and q behind for the models'
  // ledgers to rebuild the committed t and e from (history_ledger.hpp LedgerRows).
  if (wide && !eps) M.plain_scalar_pass = M.passes;
  uint64_t broken = 0;
#pragma omp parallel for schedule(static) reduction(+ : broken)
  for (std::size_t a = 0; a < rows; ++a) {
    const std::size_t i = act ? (*act)[a] : a;
    lanes::BreakOut o;
    // |Y| of the previous pass for the row's model (RowPass::r_old), kept by the sweep.
    thread_local std::vector<double> r_old_row;
    const double* r_old = nullptr;
    if (wide) {
      const uint64_t first = B.begin(i);
      if (r_old_row.size() < B.end(i) - first) r_old_row.resize(B.end(i) - first);
      double* kept = r_old_row.data() - first;
      o = lanes::break_row(sw, i, kept);
      r_old = kept;
    } else {
      const RowOut r = break_row(s, i, after, eps, soft);
      o = {r.smin, r.lost, r.dilatation, r.broken};
    }
    broken += o.broken;
    if (o.lost != 0) s.dissipated_at[i] += o.lost * P.volume[i];
    if (o.broken) M.intact_weight[i] = intact_damage_weight(s, i);  // afresh (state/system.hpp)
    P.damage[i] = damage_of(M.intact_weight[i], M.damage_total[i]);
    M.min_stretch_next[i] = o.smin;
    if (Model* m = model_of[P.material[i]]) {
      RowPass row = pass;
      row.r_old = r_old;
      m->force_row(row, i, o.dilatation);
    } else
      unified_row(s, i, o.dilatation, eps, pass.energy);
  }

  if (wide) {
#pragma omp parallel for schedule(static)
  for (std::size_t a = 0; a < rows; ++a) {
    const std::size_t i = act ? (*act)[a] : a;
    const lanes::SumOut o = lanes::sum_row(sw, i);
    P.f[i] = {o.fx, o.fy, o.fz};
    if (energy) P.energy[i] += o.w;
  }
  } else {
  const Point4* pt = M.packed.data();
  const double* q = M.force_scalar.data();
  const uint64_t* rev = M.reverse.data();
  const uint32_t* nbr = B.nbr.data();
  const uint32_t* kind = B.kind.data();
  const uint8_t* intact = B.intact.data();
  const BondKind* kinds = B.kinds.data();
  const KindCoefficients* kc = M.kind.data();
  const bool contact = sw.contact;
#pragma omp parallel for schedule(static)
  for (std::size_t a = 0; a < rows; ++a) {
    const std::size_t i = act ? (*act)[a] : a;
    const Point4 pi = pt[i];
    Vec3 f;
    double w = 0;
    const uint64_t first = B.begin(i), last = B.end(i);
    for (uint64_t k = first; k < last; ++k) {
      // q_ji lies in j's row, up to a horizon of rows away: out of cache on a large body.
      // The reverse index is read in order, so the line is asked for kPrefetch bonds ahead.
      if (k + kPrefetch < nb) __builtin_prefetch(q + rev[k + kPrefetch]);
      const Point4 pj = pt[nbr[k]];
      const Vec3 Y{pj.x - pi.x, pj.y - pi.y, pj.z - pi.z};
      const BondKind& bk = kinds[kind[k]];
      if (intact[k]) f += (bk.volume * bk.fraction) * (q[k] * Y + q[rev[k]] * Y);  // V_j (q_ij + q_ji) Y
      Vec3 fc;
      double wc = 0;
      if (contact && family_contact(kc[kind[k]], Y, fc, wc)) {
        f += fc;
        w += wc;
      }
    }
    P.f[i] = f;
    if (energy) P.energy[i] += w;
  }
  }
  if (after)
    for (std::size_t k = 0; k < nb; ++k)
      if (B.intact[k] == 2) B.intact[k] = 0;
  return broken;
}

}  // namespace horizon
