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
  if (s.decomposition) {
    GridSum g(s, 1);
    for (uint32_t i : s.owned) g.add(0, s.particles.energy[i] * s.particles.volume[i]);
    return g.totals()[0];
  }
  double sum = 0;
  for (std::size_t i = 0; i < s.particles.size(); ++i) sum += s.particles.energy[i] * s.particles.volume[i];
  return sum;
}

}  // namespace horizon
