// The affine form of the general force pass (solver/forces_general.hpp, issue 31 scope 2):
// when every model of the run writes T_ij = omega (M_i xi + g_i Y) (ModelTraits::affine,
// kernels/affine.hpp), the pass keeps one record {M_i, g_i} per
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
#include <vector>

#include "horizon/kernels/affine.hpp"
#include "horizon/solver/affine_sweeps.hpp"
#include "horizon/solver/forces.hpp"
#include "horizon/solver/forces_general.hpp"

namespace horizon {

namespace {

constexpr int kRec = kernels::kAffineRecord;

}  // namespace

bool affine_general_pass(const System& s) {
  // Its breaking sweep knows no thermal strain: a temperature field takes the general pass,
  // whose breaking test takes the mechanical stretch and whose rows call the model's
  // force_state (correspondence subtracts the strain there). One-way bonds: the record sum
  // takes one omega for both directions of a bond.
  if (general_reference() || s.models.size() == 0 || !s.thermal_strain.empty() || s.one_way_bonds) return false;
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

  // The reference positions packed {x, y, z, 0}, as the sweep's vector rows load them
  // (kept between passes: no allocation in a step).
  static thread_local std::vector<Point4> reference;
  reference.resize(n);
  for (std::size_t i = 0; i < n; ++i) reference[i] = {P.X[i].x, P.X[i].y, P.X[i].z, 0.0};
  affine_sweeps::Sweep sw;
  sw.pt = M.packed.data();
  sw.ref = reference.data();
  sw.y_old = M.affine_position.data();
  sw.record = M.affine_record.data();
  sw.kc = M.kind.data();
  sw.kind_record = M.kind_dilatation.data();
  sw.kinds = B.kinds.data();
  sw.nbr = B.nbr.data();
  sw.kind = B.kind.data();
  sw.offset = B.offset.data();
  sw.intact = B.intact.data();
  sw.intact_weight = M.intact_weight.data();
  sw.soft = soft;
  sw.total = nb;
  sw.after = after;
  // Without the short-range contact between family pairs every kind's contact distance is
  // 0 (state/kind_coefficients.cpp), and family_contact would only say so, bond by bond.
  sw.contact = s.contact.acts_on_family();
  sw.kinds_have_lengths = !B.length_per_bond;
  // The breaking sweep in the fast loops' lanes, per target (solver/affine_sweeps.hpp).
  const affine_sweeps::BreakRow break_row = affine_sweeps::break_row_for(sw);
  const affine_sweeps::SumRow sum_row = affine_sweeps::sum_row_for(sw);

  uint64_t broken = 0;
#pragma omp parallel for schedule(static) reduction(+ : broken) if (rows > 512)
  for (std::size_t a = 0; a < rows; ++a) {
    const std::size_t i = act ? (*act)[a] : a;
    double sums[18];  // K, then N (kernels/affine.hpp GradientSums)
    const affine_sweeps::BreakOut o = break_row(sw, i, sums);
    broken += o.broken;
    if (o.lost != 0) s.dissipated_at[i] += o.lost * P.volume[i];
    if (o.broken) M.intact_weight[i] = intact_damage_weight(s, i);  // afresh (state/system.hpp)
    P.damage[i] = damage_of(M.intact_weight[i], M.damage_total[i]);
    M.min_stretch_next[i] = o.smin;
    model_of[P.material[i]]->affine_row(pass, i, sums);
  }

  // The sum, once every row has its record (this pass's: sw.record is the same array).
#pragma omp parallel for schedule(static) if (rows > 512)
  for (std::size_t a = 0; a < rows; ++a) {
    const std::size_t i = act ? (*act)[a] : a;
    double f[3], w = 0;
    sum_row(sw, i, f, w);
    P.f[i] = {f[0], f[1], f[2]};
    if (energy) P.energy[i] += w;
  }
  const Point4* pt = M.packed.data();
  // The positions of this pass, for the booking of the next one's breaks.
  for (std::size_t i = 0; i < n; ++i) M.affine_position[i] = {pt[i].x, pt[i].y, pt[i].z};
  if (after)
    for (std::size_t k = 0; k < nb; ++k)
      if (B.intact[k] == 2) B.intact[k] = 0;
  return broken;
}

}  // namespace horizon
