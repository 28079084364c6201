#pragma once
// The per-bond work of the unified models (PMB, LPS) as device-portable functions
// (core/portable.hpp, issue 30): plain doubles in, plain doubles out, no containers, no
// exceptions, no allocation. The host's force passes (solver/forces.cpp's scalar rows,
// solver/forces_general.cpp, solver/forces_ordinary.cpp) and the CUDA backend
// (cuda/cuda_backend.cu) call these same functions; each is written with the operations
// in the order the passes had them, so the host's answers keep their bits.
//
// The unified force state on bond i->j (docs/design.md, "The unified bond loop"):
//   t_ij = omega_ij (P_i |xi| + Q_i e_ij + R_i e_ij/|xi|)
// PMB (Silling and Askari 2005; seed 002 eq. 22): P = Q = 0, R = c/2.
// LPS (Silling et al. 2007; seed 003 eq. 112-113): P_i = theta_i (a_i - b_i/d),
// Q_i = b_i = alpha mu/m_i, R = 0; theta_i = (d/m_i) sum_j omega |xi| e V_j.
#include <cmath>

#include "horizon/core/portable.hpp"

namespace horizon::kernels {

// The square root of the host's <cmath> and of the device's math library: both IEEE,
// correctly rounded (nvcc's default -prec-sqrt=true).
HORIZON_HD inline double root(double x) {
#if defined(__CUDA_ARCH__)
  return ::sqrt(x);
#else
  return std::sqrt(x);
#endif
}

// The natural logarithm of the host's <cmath> and of the device's library (the nonlinear
// solid's Seth-Hill strain, the Hencky strain of kernels/eigen3.hpp).
HORIZON_HD inline double natural_log(double x) {
#if defined(__CUDA_ARCH__)
  return ::log(x);
#else
  return std::log(x);
#endif
}

// x to the power y, the host's <cmath> and the device's library (the nonlinear solid's
// stable step, extended correspondence's Seth-Hill strains, the hypoelastic laws).
HORIZON_HD inline double power(double x, double y) {
#if defined(__CUDA_ARCH__)
  return ::pow(x, y);
#else
  return std::pow(x, y);
#endif
}

// x is neither infinite nor NaN (x - x is 0 exactly then, NaN otherwise); no library call,
// the same on the host and the device.
HORIZON_HD inline bool finite(double x) { return x - x == 0.0; }

// |Y| of the deformed bond Y = y_j - y_i.
HORIZON_HD inline double bond_length(double Yx, double Yy, double Yz) { return root(Yx * Yx + Yy * Yy + Yz * Yz); }

// The bond's extension e = |Y| - |xi| - (free thermal extension; 0 without temperature).
HORIZON_HD inline double extension(double r, double length, double thermal) { return r - length - thermal; }

// s0 of particle i at this pass: its critical stretch lowered by alpha times the smallest
// stretch of its intact bonds at the last pass (Silling and Askari 2005, sec. 5); a
// particle marked no_fail never breaks (infinity).
HORIZON_HD inline double critical_stretch_now(double s0, double alpha, double min_stretch, bool no_fail) {
  if (alpha != 0 && finite(min_stretch)) s0 -= alpha * min_stretch;
  return no_fail ? INFINITY : s0;
}

// A bond breaks when its stretch passes the smaller s0 of its two ends (the same test from
// either end, so both copies of a bond break in the same pass).
HORIZON_HD inline bool breaks(double stretch, double s0_i, double s0_j) {
  const double s0 = s0_i < s0_j ? s0_i : s0_j;
  return stretch > s0;
}

// t_ij of the unified form (above), with the kind's omega.
HORIZON_HD inline double unified_force_scalar(double omega, double P_i, double Q_i, double R_i, double length,
                                              double inv_length, double e) {
  return omega * (P_i * length + Q_i * e + R_i * e * inv_length);
}

// W_i's share of the directed bond, (1/2) t_ij e_ij V_j (exact for the unified form).
HORIZON_HD inline double bond_work(double t, double e, double volume) { return 0.5 * t * e * volume; }

// The directed bond's term of LPS's dilatation sum: omega V_j |xi| e.
HORIZON_HD inline double dilatation_term(double wv, double length, double e) { return wv * length * e; }

// The directed bond's term of the weighted volume m_i = sum_j omega |xi|^2 V_j (seed 003
// eq. 112), in the set-up's order of operations.
HORIZON_HD inline double weighted_volume_term(double omega, double length, double volume) {
  return omega * length * length * volume;
}

// theta_i = d sum / m_i, and P_i = theta_i (a_i - b_i/d) (seed 003 eq. 112-113).
HORIZON_HD inline double dilatation(double dim, double sum, double weighted_volume) {
  return dim * sum / weighted_volume;
}
HORIZON_HD inline double dilatation_pressure(double theta, double a_i, double b_i, double dim) {
  return theta * (a_i - b_i / dim);
}

// The pair form of (t_ij V_j + t_ji V_i)/|Y| along Y (the fast loops' evaluation: both
// directions of the bond at once, no reverse gather): wv ((P_i + P_j) L + (Q_i + Q_j) e)
// plus the bond-based part pair e, over |Y|. `pair` = omega V_j (R_i + R_j)/L (the kind's).
HORIZON_HD inline double pair_force_coefficient(double wv, double pair, double P_i, double P_j, double Q_i, double Q_j,
                                                double length, double e, double r) {
  const double t = (P_i + P_j) * length + (Q_i + Q_j) * e;
  return (wv * t + pair * e) / r;
}
// The bond-based pair form alone (PMB rows): pair e/|Y|.
HORIZON_HD inline double pair_bond_coefficient(double pair, double e, double r) { return pair * e / r; }

// Energy held by the directed bond, (1/2) t_ij e V_j (seed 003 digest sec. 9:
// W_i = (1/2) sum_j t_ij e_ij V_j, exact for both models), from the kind's wv = omega V_j.
HORIZON_HD inline double unified_bond_energy(double wv, double P_i, double Q_i, double R_i, double length,
                                             double inv_length, double e) {
  return 0.5 * wv * (P_i * length + (Q_i + R_i * inv_length) * e) * e;
}
// The bond-based case (P = Q = 0), in the bond-based row's order of operations.
HORIZON_HD inline double pmb_bond_energy(double wv, double R_i, double inv_length, double e) {
  return 0.5 * R_i * wv * inv_length * e * e;
}
// The same share when the bond breaks, in the order of the breaking sweep.
HORIZON_HD inline double pmb_broken_energy(double wv, double R_i, double inv_length, double e) {
  return 0.5 * wv * R_i * inv_length * e * e;
}

// Short-range contact of a family pair (state/short_range.hpp): the force density on i per
// component of Y (a, times Y) and the energy share, when the pair is closer than d; false
// otherwise.
HORIZON_HD inline bool contact_coefficient(double d2, double d, double k, double r2, double& a, double& w) {
  if (!(r2 < d2) || r2 == 0) return false;
  const double r = root(r2), overlap = d - r;
  a = -k * overlap / r;  // pushes i away from j
  w = 0.25 * k * overlap * overlap;
  return true;
}

// phi_i = 1 - (intact weight)/(total weight): exactly 0 with every bond intact, exactly 1
// with none (state/system.hpp damage_of).
HORIZON_HD inline double damage_fraction(double intact_weight, double total_weight) {
  return total_weight > 0 ? 1.0 - intact_weight / total_weight : 0.0;
}

}  // namespace horizon::kernels
