#include "horizon/solver/flat_copy.hpp"


#include "horizon/loading/loads.hpp"
#include "horizon/state/model_set.hpp"

namespace horizon {

std::string flat_unsupported(const System& s, const Loads& loads) {
  if (s.models.owner() || !s.models.all_unified()) return "a model without the unified per-bond form (ModelTraits::unified)";
  if (!loads.loads().empty() || !loads.projectiles().empty()) return "loads or projectiles";
  if (!s.thermal_strain.empty() || !s.critical_stretch_factor.empty()) return "temperature";
  if (s.contact.enabled()) return "short-range contact";
  if (s.model.break_after_force) return "damage.break_after_force";
  if (s.decomposition) return "a run over several ranks";
  if (s.fe_coupling) return "finite-element regions";
  if (s.bonds.length_per_bond) return "bonds without kinds (an irregular cloud)";
  if (s.model.kind.size() != s.bonds.kinds.size()) return "no force pass yet";
  return "";
}

namespace {
std::vector<double> flat3(const std::vector<Vec3>& a) {
  std::vector<double> out(3 * a.size());
  for (std::size_t i = 0; i < a.size(); ++i) out[3 * i] = a[i].x, out[3 * i + 1] = a[i].y, out[3 * i + 2] = a[i].z;
  return out;
}
void unflat3(const std::vector<double>& a, std::vector<Vec3>& out) {
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = {a[3 * i], a[3 * i + 1], a[3 * i + 2]};
}
}  // namespace

FlatStorage flat_copy(const System& s, double dt, double damping) {
  const auto& P = s.particles;
  const auto& B = s.bonds;
  const auto& M = s.model;
  FlatStorage c;
  c.n = P.size();
  c.state_based = M.state_based;
  c.dim = M.dim, c.dt = dt, c.damping = damping;
  c.offset = B.offset, c.nbr = B.nbr, c.kind = B.kind, c.intact = B.intact;
  c.kinds.resize(M.kind.size());
  for (std::size_t k = 0; k < M.kind.size(); ++k) {
    const KindCoefficients& kc = M.kind[k];
    c.kinds[k] = {kc.length, kc.inv_length, kc.pair, kc.contact_d2, kc.damage, kc.wv, kc.contact_d, kc.contact_k};
  }
  c.r_of = M.deformed_length;
  c.r_of.resize(B.size(), 1.0);
  c.X = flat3(P.X), c.u = flat3(P.u), c.v = flat3(P.v), c.f = flat3(P.f), c.b = flat3(P.b);
  c.density = P.density, c.volume = P.volume, c.no_fail = P.no_fail;
  c.no_fail.resize(c.n, 0);
  c.critical_stretch = M.critical_stretch, c.alpha = M.alpha, c.min_stretch = M.min_stretch;
  c.alpha.resize(c.n, 0);
  c.min_stretch.resize(c.n, 0);
  c.min_stretch_next.assign(c.n, 0);
  c.dilatation_coef = M.dilatation_coef, c.Q = M.deviatoric_coef, c.R = M.pair_coef;
  c.weighted_volume = M.weighted_volume, c.theta = M.theta, c.P = M.P;
  c.theta.resize(c.n, 0);
  c.P.resize(c.n, 0);
  c.intact_weight = M.intact_weight, c.damage_total = M.damage_total;
  c.damage = P.damage, c.energy = P.energy, c.dissipated = s.dissipated_at;
  c.energy.resize(c.n, 0);
  c.dissipated.resize(c.n, 0);
  c.y4.assign(4 * c.n, 0);
  c.broken.assign(c.n, 0);
  return c;
}

kernels::FlatSystem FlatStorage::view() {
  kernels::FlatSystem s;
  s.n = n, s.nb = nbr.size(), s.nkinds = kinds.size(), s.state_based = state_based, s.dim = dim, s.dt = dt, s.damping = damping;
  s.offset = offset.data(), s.nbr = nbr.data(), s.kind = kind.data(), s.intact = intact.data();
  s.kinds = kinds.data(), s.r_of = r_of.data();
  s.X = X.data(), s.u = u.data(), s.v = v.data(), s.f = f.data(), s.b = b.data();
  s.density = density.data(), s.volume = volume.data(), s.critical_stretch = critical_stretch.data();
  s.alpha = alpha.data(), s.no_fail = no_fail.data(), s.min_stretch = min_stretch.data();
  s.min_stretch_next = min_stretch_next.data(), s.dilatation_coef = dilatation_coef.data(), s.Q = Q.data();
  s.R = R.data(), s.weighted_volume = weighted_volume.data(), s.theta = theta.data(), s.P = P.data();
  s.intact_weight = intact_weight.data(), s.damage_total = damage_total.data(), s.damage = damage.data();
  s.energy = energy.data(), s.dissipated = dissipated.data(), s.y4 = y4.data(), s.broken = broken.data();
  return s;
}

void flat_write_back(const FlatStorage& c, System& s) {
  auto& P = s.particles;
  unflat3(c.u, P.u);
  unflat3(c.v, P.v);
  unflat3(c.f, P.f);
  P.damage = c.damage;
  P.energy = c.energy;
  s.bonds.intact = c.intact;
  s.dissipated_at = c.dissipated;
  s.model.min_stretch = c.min_stretch;
  s.model.intact_weight = c.intact_weight;
  s.model.theta = c.theta;
  s.model.P = c.P;
}

}  // namespace horizon
