// The run's state (state/system.hpp): the neutral model arrays and the sums over it.
#include "horizon/state/system.hpp"

#include "horizon/parallel/decomposition.hpp"

namespace horizon {

void reset_model_arrays(ModelCoefficients& M, std::size_t n) {
  M.dilatation_coef.assign(n, 0);
  M.deviatoric_coef.assign(n, 0);
  M.pair_coef.assign(n, 0);
  M.theta.assign(n, 0);
  M.P.assign(n, 0);
  M.spring.assign(n, 0);
  M.critical_stretch.assign(n, std::numeric_limits<double>::infinity());
  M.alpha.assign(n, 0);
  M.min_stretch.assign(n, 0);
  M.contact_micromodulus.assign(n, 0);
  M.state_based = false;
  M.break_after_force = false;
}

double System::dissipated() const {
  if (decomposition) {
    GridSum g(*this, 1);
    for (uint32_t i : owned) g.add(0, dissipated_at[i]);
    return g.totals()[0];
  }
  double sum = 0;
  for (double d : dissipated_at) sum += d;
  return sum;
}

double strain_energy(const System& s) {
  // With the energy law peridigm's contact keeps apart from the material's (its
  // own_energy, state/short_range.hpp), so that the ledger still balances.
  const std::vector<double>& c = s.contact.own_energy();
  const bool with_contact = c.size() == s.particles.size();
  auto density = [&](std::size_t i) { return with_contact ? s.particles.energy[i] + c[i] : s.particles.energy[i]; };
  if (s.decomposition) {
    GridSum g(s, 1);
    for (uint32_t i : s.owned) g.add(0, density(i) * s.particles.volume[i]);
    return g.totals()[0];
  }
  double sum = 0;
  for (std::size_t i = 0; i < s.particles.size(); ++i) sum += density(i) * s.particles.volume[i];
  return sum;
}

}  // namespace horizon
