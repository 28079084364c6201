#include "horizon/contact/indenter.hpp"

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
  const std::size_t n = P.size();
  // One pass in particle order: the force densities and their total, the same on any
  // thread count (the loop is cheap next to the bond loops).
  Vec3 total;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 d = P.X[i] + P.u[i] - c;
    const double r2 = norm2(d);
    if (!(r2 < R2) || r2 == 0) continue;
    const double r = std::sqrt(r2);
    const Vec3 b = d * (K * (R - r) * (R - r) / r);
    P.b[i] += b;
    total += b * P.volume[i];
  }
  return total;
}

}  // namespace horizon
