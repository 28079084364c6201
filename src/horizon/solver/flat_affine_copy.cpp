#include "horizon/solver/flat_affine_copy.hpp"

#include "horizon/kernels/hypoelastic.hpp"
#include "horizon/kernels/laws.hpp"
#include "horizon/material/models/correspondence.hpp"
#include "horizon/solver/forces_general.hpp"
#include "horizon/state/model_set.hpp"

namespace horizon {

namespace {

// Every model's state, one per material, or none when a model is not correspondence
// (correspondence_state wants a Model&: the copy only reads it).
std::vector<CorrespondenceState> states_of(const System& s) {
  std::vector<CorrespondenceState> out;
  for (std::size_t m = 0; m < s.models.size(); ++m) {
    out.push_back(correspondence_state(const_cast<Model&>(s.models[m])));
    if (!out.back().model) return {};
  }
  return out;
}

// Row-major copies of an Eigen 3 x 3 (Eigen stores by column), as the host's row copies them.
void to_rows(const correspondence::Mat3& m, double* out) {
  for (int k = 0; k < 9; ++k) out[k] = m(k / 3, k % 3);
}
void from_rows(const double* in, correspondence::Mat3& m) {
  for (int k = 0; k < 9; ++k) m(k / 3, k % 3) = in[k];
}

kernels::J2History j2_of(const classical::J2State& p) {
  kernels::J2History h{};
  to_rows(p.plastic_strain, h.plastic_strain);
  h.alpha = p.alpha;
  return h;
}
void j2_into(const kernels::J2History& h, classical::J2State& p) {
  from_rows(h.plastic_strain, p.plastic_strain);
  p.alpha = h.alpha;
}
kernels::HypoHistory hypo_of(const classical::HypoState& p) {
  kernels::HypoHistory h{};
  to_rows(p.F, h.F), to_rows(p.V, h.V), to_rows(p.R, h.R), to_rows(p.sigma_u, h.sigma_u);
  h.alpha = p.alpha, h.thermal = p.thermal;
  return h;
}
// Correspondence::hypo_row's write of the trial history (plastic.alpha follows the rate form's).
void hypo_into(const kernels::HypoHistory& h, correspondence::History& out) {
  from_rows(h.F, out.hypo.F), from_rows(h.V, out.hypo.V), from_rows(h.R, out.hypo.R);
  from_rows(h.sigma_u, out.hypo.sigma_u);
  out.hypo.alpha = h.alpha, out.hypo.thermal = h.thermal;
  out.plastic.alpha = h.alpha;
}

}  // namespace

bool flat_affine_model(const System& s) { return !states_of(s).empty(); }

std::string flat_affine_unsupported(const System& s) {
  const std::vector<CorrespondenceState> models = states_of(s);
  if (models.empty()) return "a model without flat rows";
  std::size_t rows = 0;
  for (const CorrespondenceState& c : models) {
    if (c.Cc != 0)
      return "correspondence with stabilization_form: peridigm (its hourglass force takes the general pass)";
    rows += c.particles->size();
  }
  if (rows != s.particles.size()) return "correspondence over some of the particles";
  if (!affine_general_pass(s)) return "correspondence outside its affine pass (forces_affine.cpp)";
  return "";
}

FlatAffineStorage flat_affine_copy(const System& s) {
  FlatAffineStorage c;
  const std::vector<CorrespondenceState> models = states_of(s);
  if (models.empty()) return c;
  const auto& P = s.particles;
  const auto& B = s.bonds;
  const auto& M = s.model;
  const std::size_t n = P.size();
  c.on = true;
  c.constants.contact = s.contact.acts_on_family();
  bool any_j2 = false, any_hypo = false, any_plane_stress = false;
  for (const CorrespondenceState& m : models) {
    kernels::FlatAffineLaw k;
    k.dim = m.law->dimension;
    k.tolerance = m.tolerance;
    k.G = m.G;
    k.rate = m.hypo;
    k.plane_stress = !m.portable_law && !m.hypo;  // the total-form laws in 2-D plane stress
    k.law = *m.constants;
    k.hypo = *m.hypo_constants;
    // The rate form's yield stress (Correspondence::hypo_row): sigma_y times the flaw's
    // factor, 0 for the elastic one.
    if (m.hypo)
      k.law.yield_stress = m.law->law != correspondence::StressLaw::hypoelastic ? m.law->j2.yield_stress : 0.0;
    c.laws.push_back(k);
    any_j2 = any_j2 || (!m.hypo && m.constants->law == kernels::kJ2Law);
    any_hypo = any_hypo || m.hypo;
    any_plane_stress = any_plane_stress || k.plane_stress;
  }
  c.material.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i) c.material[i] = static_cast<uint32_t>(P.material[i]);
  c.ref.resize(n);
  for (std::size_t i = 0; i < n; ++i) c.ref[i] = {P.X[i].x, P.X[i].y, P.X[i].z, 0.0};
  c.kind_record.resize(M.kind_dilatation.size());
  for (std::size_t q = 0; q < c.kind_record.size(); ++q) {
    const Point4& r = M.kind_dilatation[q];
    c.kind_record[q] = {r.x, r.y, r.z, r.w};
  }
  c.bond_kinds.resize(B.kinds.size());
  c.omega_volume.resize(B.kinds.size());
  for (std::size_t q = 0; q < B.kinds.size(); ++q) {
    const BondKind& b = B.kinds[q];
    c.bond_kinds[q] = {b.volume, b.fraction, b.weight};
    c.omega_volume[q] = bond_fields::weight(b) * bond_fields::volume(b);  // B.weight[k] * B.volume[k]
  }
  c.record = M.affine_record;
  c.record.resize(kernels::kAffineRecord * n, 0.0);
  c.y_old = M.affine_position;
  c.y_old.resize(n);
  c.work.assign(n, 0.0), c.von_mises.assign(n, 0.0), c.singular.assign(n, 0), c.F_pass.assign(9 * n, 0.0);
  if (any_j2) c.j2_committed.assign(n, kernels::J2History{}), c.j2_trial.assign(n, kernels::J2History{});
  if (any_plane_stress) c.lambda3_committed.assign(n, 1.0), c.lambda3_trial.assign(n, 1.0);
  if (any_hypo) {
    c.hypo_committed.assign(n, kernels::HypoHistory{}), c.hypo_trial.assign(n, kernels::HypoHistory{});
    c.yield_factor.assign(n, 1.0);
    c.kinv.assign(9 * n, 0.0), c.F.assign(9 * n, 0.0), c.sigma.assign(9 * n, 0.0), c.d.assign(9 * n, 0.0);
    c.u_committed.assign(3 * n, 0.0);
  }
  for (const CorrespondenceState& m : models) {
    const bool j2 = !m.hypo && m.constants->law == kernels::kJ2Law;
    if (m.hypo)  // every rate-form model's u at the commit is the same (Correspondence::commit)
      for (std::size_t i = 0; i < n && i < m.u_committed->size(); ++i) {
        const Vec3& u = (*m.u_committed)[i];
        c.u_committed[3 * i] = u.x, c.u_committed[3 * i + 1] = u.y, c.u_committed[3 * i + 2] = u.z;
      }
    for (std::size_t l = 0; l < m.particles->size(); ++l) {
      const uint32_t i = (*m.particles)[l];
      c.work[i] = (*m.work)[l], c.von_mises[i] = (*m.von_mises)[l], c.singular[i] = (*m.singular)[l];
      if (j2) c.j2_committed[i] = j2_of((*m.committed)[l].plastic), c.j2_trial[i] = j2_of((*m.trial)[l].plastic);
      if (!m.portable_law && !m.hypo)
        c.lambda3_committed[i] = (*m.committed)[l].lambda3, c.lambda3_trial[i] = (*m.trial)[l].lambda3;
      if (m.hypo) {
        c.hypo_committed[i] = hypo_of((*m.committed)[l].hypo), c.hypo_trial[i] = hypo_of((*m.trial)[l].hypo);
        c.yield_factor[i] = (*m.yield_factor)[l];
        to_rows((*m.kinv)[l], &c.kinv[9 * i]), to_rows((*m.F)[l], &c.F[9 * i]);
        to_rows((*m.sigma)[l], &c.sigma[9 * i]), to_rows((*m.rate)[l], &c.d[9 * i]);
      }
    }
  }
  return c;
}

kernels::FlatAffine FlatAffineStorage::view() {
  kernels::FlatAffine a = constants;
  a.nlaws = laws.size(), a.laws = laws.data(), a.material = material.data();
  auto or_null = [](auto& v) { return v.empty() ? nullptr : v.data(); };
  a.ref = ref.data(), a.kind_record = kind_record.data(), a.bond_kinds = bond_kinds.data();
  a.omega_volume = omega_volume.data(), a.record = record.data(), a.y_old = y_old.data();
  a.work = work.data(), a.von_mises = von_mises.data(), a.singular = singular.data(), a.F_pass = F_pass.data();
  a.j2_committed = or_null(j2_committed), a.j2_trial = or_null(j2_trial);
  a.lambda3_committed = or_null(lambda3_committed), a.lambda3_trial = or_null(lambda3_trial);
  a.hypo_committed = or_null(hypo_committed), a.hypo_trial = or_null(hypo_trial);
  a.u_committed = or_null(u_committed), a.yield_factor = or_null(yield_factor);
  a.kinv = or_null(kinv), a.F = or_null(F), a.sigma = or_null(sigma), a.d = or_null(d);
  return a;
}

void flat_affine_write_back(const FlatAffineStorage& c, System& s) {
  if (!c.on) return;
  s.model.affine_record = c.record;
  s.model.affine_position = c.y_old;
  for (std::size_t q = 0; q < s.models.size(); ++q) {
    const CorrespondenceState m = correspondence_state(s.models[q]);
    if (!m.model) continue;
    const bool j2 = !m.hypo && m.constants->law == kernels::kJ2Law;
    for (std::size_t l = 0; l < m.particles->size(); ++l) {
      const uint32_t i = (*m.particles)[l];
      (*m.work)[l] = c.work[i], (*m.von_mises)[l] = c.von_mises[i], (*m.singular)[l] = c.singular[i];
      if (j2) j2_into(c.j2_committed[i], (*m.committed)[l].plastic), j2_into(c.j2_trial[i], (*m.trial)[l].plastic);
      if (!m.portable_law && !m.hypo)
        (*m.committed)[l].lambda3 = c.lambda3_committed[i], (*m.trial)[l].lambda3 = c.lambda3_trial[i];
      if (m.hypo) {
        hypo_into(c.hypo_committed[i], (*m.committed)[l]);
        hypo_into(c.hypo_trial[i], (*m.trial)[l]);
        from_rows(&c.kinv[9 * i], (*m.kinv)[l]), from_rows(&c.F[9 * i], (*m.F)[l]);
        from_rows(&c.sigma[9 * i], (*m.sigma)[l]), from_rows(&c.d[9 * i], (*m.rate)[l]);
      }
    }
    if (m.hypo)
      for (std::size_t i = 0; i < m.u_committed->size(); ++i)
        (*m.u_committed)[i] = {c.u_committed[3 * i], c.u_committed[3 * i + 1], c.u_committed[3 * i + 2]};
  }
}

}  // namespace horizon
