#pragma once
// Velocity Verlet, one particle and one component at a time, as device-portable functions
// (core/portable.hpp): the explicit solver (solver/explicit.cpp) and the CUDA backend
// (cuda/cuda_backend.cu) call these. Silling and Askari 2005; Peridigm's "Verlet":
//   v(n+1/2) = v(n) + dt/2 a(n);  u(n+1) = u(n) + dt v(n+1/2);  forces;
//   v(n+1) = (v(n+1/2) + dt/2 (f + b)/rho) / (1 + gamma dt/2)
// with a(n) = (f + b)/rho - gamma v (mass-proportional damping gamma; the second half kick
// takes it implicitly so that it stays stable). Written in the solver's order of
// operations (Vec3's division is a multiplication by the reciprocal), so its bits hold.
#include "horizon/core/portable.hpp"

namespace horizon::kernels {

// The first half kick of one component: inv_rho = 1/rho, half = dt/2.
HORIZON_HD inline double half_kick(double v, double f, double b, double inv_rho, double damping, double half) {
  const double a = (f + b) * inv_rho - v * damping;
  return v + a * half;
}

// The drift of one component.
HORIZON_HD inline double drift(double u, double v, double dt) { return u + v * dt; }

// The second half kick of one component: half_over_rho = (dt/2)/rho, damp = 1/(1 + gamma dt/2).
HORIZON_HD inline double second_half_kick(double v_half, double f, double b, double half_over_rho, double damp) {
  return (v_half + (f + b) * half_over_rho) * damp;
}

// A half kick rounded as Peridigm's Verlet rounds it (solver.verlet: peridigm): the
// acceleration (f + b)/rho divided, then v + (dt/2) a; no damping.
HORIZON_HD inline double peridigm_kick(double v, double f, double b, double rho, double half) {
  return v + half * ((f + b) / rho);
}

// 1/2 rho V |v|^2.
HORIZON_HD inline double kinetic(double density, double volume, double vx, double vy, double vz) {
  return 0.5 * density * volume * (vx * vx + vy * vy + vz * vz);
}

}  // namespace horizon::kernels
