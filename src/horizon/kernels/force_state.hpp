#pragma once
// The correspondence model's force state of one bond in the general pass (material/models/
// correspondence.hpp: bond_force_state, Silling et al. 2007's omega P K^-1 xi with Silling
// 2017's stabilisation, and peridigm_hourglass, Peridigm's hourglass force fitted from its
// gold; the formulas and their sources are there) as device-portable functions
// (core/portable.hpp, issue 30), over row-major double[9]. Correspondence::force_state
// calls these per bond, after the row's gradient (kernels/affine.hpp gradient_add,
// gradient_finish) and its law (kernels/plane_stress.hpp law_point, kernels/hypoelastic.hpp
// hypo_step); the stabilisation energy is affine.hpp's stabilization_energy.
//
// Bits: the operations of the Eigen forms in their order (tests/unit/
// test_plane_stress_kernels.cpp compares them bit for bit): products of a matrix and a
// vector in mat3_vec's order, the dot product of two 3-vectors (a0 b0 + a1 b1) + a2 b2
// (one packet and the remainder), the lengths as the scalar code wrote them.
#include "horizon/core/portable.hpp"
#include "horizon/kernels/affine.hpp"
#include "horizon/kernels/unified.hpp"

namespace horizon::kernels {

// T = omega (A xi + G (Y - F xi)), A = P K^-1 (zero: the law refused F), F the nonlocal
// gradient, G the stabilisation modulus (correspondence.hpp (*)).
HORIZON_HD inline void correspondence_bond_state(const double* A, const double* F, double G, double omega,
                                                 const double* xi, const double* Y, double* T) {
  double Ax[3], Fx[3];
  mat3_vec(A, xi, Ax);
  mat3_vec(F, xi, Fx);
  for (int r = 0; r < 3; ++r) T[r] = omega * (Ax[r] + G * (Y[r] - Fx[r]));
}

// Peridigm's hourglass force, added to T: T += -Cc omega ((F xi - Y) . Y) Y / (|xi| |Y|)
// (correspondence.hpp peridigm_hourglass); nothing for a zero-length bond or Cc = 0.
HORIZON_HD inline void peridigm_hourglass_add(const double* F, double Cc, double omega, const double* xi,
                                              const double* Y, double* T) {
  const double y = root(Y[0] * Y[0] + Y[1] * Y[1] + Y[2] * Y[2]);
  const double x = root(xi[0] * xi[0] + xi[1] * xi[1] + xi[2] * xi[2]);
  if (!(y > 0) || !(x > 0) || Cc == 0) {
    for (int r = 0; r < 3; ++r) T[r] = T[r] + 0.0;  // the host added a zero vector (-0 becomes +0)
    return;
  }
  double Fx[3];
  mat3_vec(F, xi, Fx);
  const double z[3] = {Fx[0] - Y[0], Fx[1] - Y[1], Fx[2] - Y[2]};
  const double s = -Cc * omega * ((z[0] * Y[0] + z[1] * Y[1]) + z[2] * Y[2]) / (x * y);
  for (int r = 0; r < 3; ++r) T[r] = T[r] + s * Y[r];
}

}  // namespace horizon::kernels
