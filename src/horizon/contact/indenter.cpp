#include "horizon/contact/indenter.hpp"

#include "horizon/parallel/decomposition.hpp"

#include <cmath>

#include "horizon/solver/system.hpp"

namespace horizon {

Indenter::Indenter(const IndenterConfig& config) : config_(config) {}

Vec3 Indenter::center(double t) const {
  Vec3 c;
  for (int k = 0; k < 3; ++k)
    if (config_.center[k]) c[k] = (*config_.center[k])(t, 0, 0, 0);
  return c;
}

Vec3 Indenter::apply(System& s, double t) const {
  auto& P = s.particles;
  const Vec3 c = center(t);
  const double R = config_.radius, R2 = R * R, K = config_.stiffness;
  // A decomposed run pushes its own particles alone; GridSum makes the total independent
  // of the split (parallel/decomposition.hpp).
  const std::vector<uint32_t>* own = s.owned.empty() ? nullptr : &s.owned;
  const std::size_t n = own ? own->size() : P.size();
  // One pass in particle order: the force densities and their total, the same on any
  // thread count (the loop is cheap next to the bond loops).
  GridSum total(s, 3);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = own ? (*own)[k] : k;
    const Vec3 d = P.X[i] + P.u[i] - c;
    const double r2 = norm2(d);
    if (!(r2 < R2) || r2 == 0) continue;
    const double r = std::sqrt(r2);
    const Vec3 b = d * (K * (R - r) * (R - r) / r);
    P.b[i] += b;
    total.add(0, b * P.volume[i]);
  }
  const std::vector<double> f = total.totals();
  return {f[0], f[1], f[2]};
}

}  // namespace horizon
