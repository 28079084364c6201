#pragma once
// The linear peridynamic solid linearised about the reference configuration (material/
// models/linear_lps.hpp; Silling et al. 2007 sec. 15, seed 003; Silling 2010; Peridigm's
// Linear LPS) as device-portable functions (core/portable.hpp, issue 30): one row of its
// force state (LinearLps::force_state calls linear_lps_row for each of its particles),
// with the model's operations in their order, so its answers keep their bits.
//
//   e_lin = eta . xi/|xi| = (Y - xi) . xi/|xi|       (the extension to first order in eta)
//   theta = (d/m) sum_j omega V_j |xi| e_lin,  p = d k theta / m,  alpha = alpha_m/m
//   e^d = e_lin - theta |xi|/d,  t = p omega |xi| + alpha omega e^d,  T = (t/|xi|) xi
//   W_i = k theta^2/2 + (alpha/2) sum_j omega V_j (e^d)^2
#include <cstdint>

#include "horizon/core/portable.hpp"
#include "horizon/kernels/ordinary.hpp"

namespace horizon::kernels {

// (Y - xi) . xi / |xi|, the dot product summed x, y, z (core/vec3.hpp dot).
HORIZON_HD inline double linear_extension(double Yx, double Yy, double Yz, double xx, double xy, double xz,
                                          double length) {
  return ((Yx - xx) * xx + (Yy - xy) * xy + (Yz - xz) * xz) / length;
}

// The directed bond's omega V_j (the kind's weight, volume and fraction, in that order).
HORIZON_HD inline double linear_lps_weighted_volume(double weight, double volume, double fraction) {
  return weight * volume * fraction;
}

// t = p omega |xi| + alpha omega e^d.
HORIZON_HD inline double linear_lps_force_scalar(double p, double omega, double length, double alpha, double ed) {
  return p * omega * length + alpha * omega * ed;
}

// W_i = k theta^2/2 + (alpha/2) ||e^d||_w^2.
HORIZON_HD inline double linear_lps_energy(double bulk, double theta, double alpha, double dev) {
  return 0.5 * bulk * theta * theta + 0.5 * alpha * dev;
}

// The arrays of one pass. Kind: a per-kind struct with members length, weight, volume and
// fraction (the host's BondKind); Point: the current positions (members x, y, z: the
// host's Point4); Vec: the reference positions and the force states (x, y, z: Vec3).
template <class Kind, class Point, class Vec>
struct LinearLpsRow {
  const Kind* kinds = nullptr;  // per kind
  const uint32_t* kind = nullptr;
  const uint32_t* nbr = nullptr;
  const uint8_t* intact = nullptr;
  const Point* y = nullptr;  // per particle
  const Vec* X = nullptr;    // per particle
  Vec* T = nullptr;          // per bond: out
  double bulk = 0, alpha_m = 0;
  int dim = 3;
};
struct LinearLpsSums {
  double theta, W;
};

// Row i (bonds [first, last), weighted volume m): theta, the force states T and W_i.
template <class Kind, class Point, class Vec>
HORIZON_HD inline LinearLpsSums linear_lps_row(const LinearLpsRow<Kind, Point, Vec>& a, uint32_t i, uint64_t first,
                                              uint64_t last, double m) {
  const double d = a.dim;
  const Point pi = a.y[i];
  const Vec Xi = a.X[i];
  auto extension = [&](uint64_t k, double length) {
    const Point pj = a.y[a.nbr[k]];
    const Vec Xj = a.X[a.nbr[k]];
    return linear_extension(pj.x - pi.x, pj.y - pi.y, pj.z - pi.z, Xj.x - Xi.x, Xj.y - Xi.y, Xj.z - Xi.z, length);
  };
  double sum = 0;
  for (uint64_t k = first; k < last; ++k) {
    if (!a.intact[k]) continue;
    const Kind& b = a.kinds[a.kind[k]];
    sum += linear_lps_weighted_volume(b.weight, b.volume, b.fraction) * b.length * extension(k, b.length);
  }
  const double theta = m > 0 ? d * sum / m : 0.0;
  const double alpha = m > 0 ? a.alpha_m / m : 0.0;
  const double p = m > 0 ? d * a.bulk * theta / m : 0.0;
  double dev = 0;
  for (uint64_t k = first; k < last; ++k) {
    Vec& T = a.T[k];
    if (!a.intact[k]) {
      T.x = 0, T.y = 0, T.z = 0;
      continue;
    }
    const Kind& b = a.kinds[a.kind[k]];
    const Vec Xj = a.X[a.nbr[k]];
    const double xx = Xj.x - Xi.x, xy = Xj.y - Xi.y, xz = Xj.z - Xi.z;
    const double ed = deviatoric_extension(extension(k, b.length), theta, b.length, a.dim);
    const double wv = linear_lps_weighted_volume(b.weight, b.volume, b.fraction);
    dev += wv * ed * ed;
    const double s = linear_lps_force_scalar(p, b.weight, b.length, alpha, ed) / b.length;
    T.x = xx * s, T.y = xy * s, T.z = xz * s;
  }
  return {theta, linear_lps_energy(a.bulk, theta, alpha, dev)};
}

}  // namespace horizon::kernels
