// The affine form of the general force pass (solver/forces_general.hpp, issue 31 scope 2):
// when every model of the run writes T_ij = omega (M_i xi + g_i Y) (ModelTraits::affine,
// material/models/correspondence_kernels.hpp), the pass keeps one record {M_i, g_i} per
// particle and visits each bond twice:
//
//   1. per row i (one thread): break i's bonds by the critical-stretch law and sum K_i and
//      sum w Y (x) xi over the bonds that act in the same visit, then ask i's model for
//      i's record (Model::affine_row: F_i and the law);
//   2. per row i, once every row has its record: f_i = sum_j omega V_j ((M_i + M_j) xi +
//      (g_i + g_j) Y) (seed 003 eq. 33 with T_ji = -omega (M_j xi + g_j Y)), and the contact.
//
// No force state per bond (24 bytes) and no reverse-bond index (8 bytes): the sum reads the
// neighbours' records by particle index. The breaking and the damage are those of the
// vector form (forces_general.cpp break_row) bit for bit; the energy booked for a bond
// broken in the pass is (1/2) (T_old . Y/|Y|) e V_j as there, with T_old the force state of
// the last pass rebuilt from the record and the positions that pass kept.
#include <cmath>
#include <limits>

#include "horizon/material/models/correspondence_kernels.hpp"
#include "horizon/solver/forces.hpp"
#include "horizon/solver/forces_general.hpp"

namespace horizon {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kRec = correspondence::kAffineRecord;

struct RowOut {
  double smin = kInf, lost = 0;
  uint64_t broken = 0;
};

// Pass 1 of row i before its model: the breaking of forces_general.cpp break_row (the
// affine models take no thermal strain: ModelTraits::thermal_strain is false for them),
// and over the bonds that act in this pass the sums of K_i and of the deformation
// gradient (correspondence_kernels.hpp gradient_add) while the bond is in registers.
RowOut break_row(System& s, std::size_t i, bool after, const double* soft, correspondence::GradientSums& g) {
  auto& B = s.bonds;
  auto& M = s.model;
  const Point4* pt = M.packed.data();
  const Vec3* X = s.particles.X.data();
  const Vec3* y_old = M.affine_position.data();
  const double* rec = M.affine_record.data() + kRec * i;
  const KindCoefficients* kcs = M.kind.data();
  const BondKind* kinds = B.kinds.data();
  const uint32_t* nbr = B.nbr.data();
  const uint32_t* kind = B.kind.data();
  uint8_t* intact = B.intact.data();
  const Point4 pi = pt[i];
  const Vec3 xi_i = X[i];
  auto scaled = [](double w, double f) { return std::isinf(w) ? w : w * f; };
  const double wi = soft ? scaled(pi.w, soft[i]) : pi.w;
  RowOut out;
  for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
    if (!intact[k]) continue;
    const uint32_t j = nbr[k];
    const KindCoefficients& kc = kcs[kind[k]];
    const Point4 pj = pt[j];
    const Vec3 Y{pj.x - pi.x, pj.y - pi.y, pj.z - pi.z};
    const Vec3 xj = X[j];
    const double xi[3] = {xj.x - xi_i.x, xj.y - xi_i.y, xj.z - xi_i.z};
    const BondKind& bk = kinds[kind[k]];
    const double w = bk.weight * (bk.volume * bk.fraction);  // omega V_j (B.weight[k] * B.volume[k])
    const double r = std::sqrt(dot(Y, Y)), e = r - kc.length, stretch = e * kc.inv_length;
    out.smin = stretch < out.smin ? stretch : out.smin;
    const double wj = soft ? scaled(pj.w, soft[j]) : pj.w;
    const double s0 = wi < wj ? wi : wj;
    if (stretch > s0) {
      intact[k] = after ? 2 : 0;
      ++out.broken;
      if (r > 0) {
        // The bond's force state at the last pass (zero before the first: the records start at 0).
        const Vec3 Yo = y_old[j] - y_old[i];
        const double yv[3] = {Yo.x, Yo.y, Yo.z};
        double T[3];
        correspondence::affine_force_state(rec, bk.weight, xi, yv, T);
        out.lost += 0.5 * (T[0] * Y.x + T[1] * Y.y + T[2] * Y.z) / r * e * (bk.volume * bk.fraction);
      }
      M.intact_weight[i] -= kc.damage;
      if (!after) continue;
    }
    const double yv[3] = {Y.x, Y.y, Y.z};
    correspondence::gradient_add(g, xi, yv, w);
  }
  return out;
}

}  // namespace

bool affine_general_pass(const System& s) {
  // One-way bonds: the record sum takes one omega for both directions of a bond.
  if (general_reference() || s.models.size() == 0 || s.one_way_bonds) return false;
  for (const auto& m : s.models)
    if (!m->traits().affine) return false;
  return true;
}

uint64_t affine_forces(System& s, bool energy) {
  auto& P = s.particles;
  auto& B = s.bonds;
  auto& M = s.model;
  const std::size_t n = P.size(), nb = B.size();
  if (M.affine_record.size() != kRec * n) M.affine_record.assign(kRec * n, 0.0);
  if (M.affine_position.size() != n) M.affine_position.assign(n, Vec3{});
  const bool after = M.break_after_force;
  const double* soft = s.critical_stretch_factor.empty() ? nullptr : s.critical_stretch_factor.data();
  // A decomposed run computes the rows of its active particles alone: its own and their
  // bond neighbours' (ModelTraits::rows_local), whose records enter the owned rows' sums
  // (parallel/decomposition.hpp); the sums of the other active rows are not used.
  const std::vector<uint32_t>* act = s.active_rows.empty() ? nullptr : &s.active_rows;
  const std::size_t rows = act ? act->size() : n;
  if (energy)
    for (std::size_t i = 0; i < n; ++i) P.energy[i] = 0;

  const AffineRowPass pass{s, M.packed.data(), M.affine_record.data(), energy ? P.energy.data() : nullptr, s.time,
                           s.dt};
  // Per material, its model (kept between passes: no allocation in a step).
  static thread_local std::vector<Model*> row_model;
  row_model.assign(s.models.size(), nullptr);
  for (std::size_t m = 0; m < s.models.size(); ++m) row_model[m] = &s.models[m];
  Model* const* model_of = row_model.data();

  uint64_t broken = 0;
#pragma omp parallel for schedule(static) reduction(+ : broken) if (rows > 512)
  for (std::size_t a = 0; a < rows; ++a) {
    const std::size_t i = act ? (*act)[a] : a;
    correspondence::GradientSums g;
    const RowOut o = break_row(s, i, after, soft, g);
    broken += o.broken;
    if (o.lost != 0) s.dissipated_at[i] += o.lost * P.volume[i];
    if (o.broken) M.intact_weight[i] = intact_damage_weight(s, i);  // afresh (state/system.hpp)
    P.damage[i] = damage_of(M.intact_weight[i], M.damage_total[i]);
    M.min_stretch_next[i] = o.smin;
    model_of[P.material[i]]->affine_row(pass, i, g.v);
  }

  const Point4* pt = M.packed.data();
  const Vec3* X = P.X.data();
  const double* rec = M.affine_record.data();
  const uint32_t* nbr = B.nbr.data();
  const uint32_t* kind = B.kind.data();
  const uint8_t* intact = B.intact.data();
  const BondKind* kinds = B.kinds.data();
  const KindCoefficients* kc = M.kind.data();
#pragma omp parallel for schedule(static) if (rows > 512)
  for (std::size_t a = 0; a < rows; ++a) {
    const std::size_t i = act ? (*act)[a] : a;
    const Point4 pi = pt[i];
    const Vec3 xi_i = X[i];
    correspondence::AffineRowSum sum;
    double w = 0;
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
      const uint32_t j = nbr[k];
      const Point4 pj = pt[j];
      const double Y[3] = {pj.x - pi.x, pj.y - pi.y, pj.z - pi.z};
      if (intact[k]) {
        const BondKind& bk = kinds[kind[k]];
        const Vec3 xj = X[j];
        const double xi[3] = {xj.x - xi_i.x, xj.y - xi_i.y, xj.z - xi_i.z};
        correspondence::affine_pair_add(sum, rec + kRec * static_cast<std::size_t>(j),
                                        bk.weight * (bk.volume * bk.fraction), xi, Y);
      }
      Vec3 fc;
      double wc = 0;
      if (family_contact(kc[kind[k]], Vec3{Y[0], Y[1], Y[2]}, fc, wc)) {
        sum.acc[0] += fc.x, sum.acc[1] += fc.y, sum.acc[2] += fc.z;
        w += wc;
      }
    }
    double f[3];
    correspondence::affine_pair_finish(sum, rec + kRec * i, f);
    P.f[i] = {f[0], f[1], f[2]};
    if (energy) P.energy[i] += w;
  }
  // The positions of this pass, for the booking of the next one's breaks.
  for (std::size_t i = 0; i < n; ++i) M.affine_position[i] = {pt[i].x, pt[i].y, pt[i].z};
  if (after)
    for (std::size_t k = 0; k < nb; ++k)
      if (B.intact[k] == 2) B.intact[k] = 0;
  return broken;
}

}  // namespace horizon
