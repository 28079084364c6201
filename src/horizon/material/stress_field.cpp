#include "horizon/material/stress_field.hpp"

#include <Eigen/Dense>
#include <cmath>

#include "horizon/material/nonlocal_gradient.hpp"

namespace horizon {

std::vector<SymTensor> strain_field(const System& s) {
  const auto& P = s.particles;
  const auto& B = s.bonds;
  const int d = s.dimension;
  std::vector<SymTensor> eps(P.size(), SymTensor{});
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < P.size(); ++i) {
    NonlocalGradient g;  // K and F as the correspondence model computes them
    const Vec3 yi = P.X[i] + P.u[i];
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
      if (!B.intact[k]) continue;
      const uint32_t j = B.nbr[k];
      g.add(P.X[j] - P.X[i], P.X[j] + P.u[j] - yi, B.weight[k] * B.volume[k]);
    }
    // Only the first d axes: K is singular out of plane in 2-D and 1-D. Any K of full
    // rank is accepted here (a post-processing measure): only round-off singularity is refused.
    Eigen::Matrix3d Kinv, F;
    if (!g.finish(d, 1e-12, Kinv, F)) continue;
    Eigen::Matrix3d e = Eigen::Matrix3d::Zero();
    e.topLeftCorner(d, d) = 0.5 * (F + F.transpose()).topLeftCorner(d, d) - Eigen::MatrixXd::Identity(d, d);
    eps[i] = {e(0, 0), e(1, 1), e(2, 2), e(0, 1), e(1, 2), e(0, 2)};
  }
  return eps;
}

std::vector<SymTensor> stress_field(const System& s, const std::vector<MaterialConfig>& materials, PlaneMode plane) {
  std::vector<SymTensor> sig = strain_field(s);
  for (std::size_t i = 0; i < sig.size(); ++i) {
    const MaterialConfig& m = materials[s.particles.material[i]];
    const double E = m.youngs_modulus, nu = m.poissons_ratio;
    const double mu = E / (2 * (1 + nu)), lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
    const SymTensor e = sig[i];
    SymTensor& t = sig[i];
    if (s.dimension == 1) {
      t = {E * e[0], 0, 0, 0, 0, 0};
    } else if (s.dimension == 2 && plane == PlaneMode::stress) {
      const double c = E / (1 - nu * nu);
      t = {c * (e[0] + nu * e[1]), c * (e[1] + nu * e[0]), 0, 2 * mu * e[3], 0, 0};
    } else {  // 3-D, or plane strain (eps_zz = 0)
      const double tr = e[0] + e[1] + e[2];
      t = {lambda * tr + 2 * mu * e[0], lambda * tr + 2 * mu * e[1], lambda * tr + 2 * mu * e[2],
           2 * mu * e[3],               2 * mu * e[4],               2 * mu * e[5]};
    }
  }
  return sig;
}

double von_mises(const SymTensor& t) {
  const double a = t[0] - t[1], b = t[1] - t[2], c = t[2] - t[0];
  return std::sqrt(0.5 * (a * a + b * b + c * c) + 3 * (t[3] * t[3] + t[4] * t[4] + t[5] * t[5]));
}

}  // namespace horizon
