#pragma once
// The viscoelastic ordinary state-based solid: the LPS (seed 003 eq. 113; 2-D digest
// sec. 8) with an elastic dilatation and a standard linear solid on the deviatoric
// extension (J. A. Mitchell, "A non-local, ordinary-state-based viscoelasticity model for
// peridynamics", SAND2011-8064; Peridigm's "Viscoelastic", LAMMPS peri/ves).
// docs/models/viscoelastic.md has the derivations.
//
// Per particle i (theta, e^d, alpha = (15 or 8) mu/m as in the LPS and the elastic-plastic
// model), with an equilibrium weight lambda_inf and Maxwell branches b = 1..B of weight
// lambda_b and decay time tau_b, lambda_inf + sum_b lambda_b = 1 (Peridigm's convention:
// mu is the instantaneous shear modulus, lambda_inf mu the long-term one):
//   t   = (d k' theta/m) omega |xi| + t^d,
//   t^d = alpha omega [ lambda_inf e^d + sum_b lambda_b (e^d - e^b_b) ],
//   d e^b_b / dt = (e^d - e^b_b) / tau_b        (each branch a spring 2 lambda_b mu in series
//                                                 with a dashpot of time tau_b; Mitchell 2011)
// e^b_b the back extension of branch b on each directed bond (history). The classical
// analogue is S = 2 mu [lambda_inf eps^d + sum_b lambda_b (eps^d - eps^b_b)], whose
// relaxation modulus is G(t) = mu [lambda_inf + sum_b lambda_b exp(-t/tau_b)].
//
// Time integration: exact for e^d linear in time over the step (dt, h = dt/tau):
//   e^b_n+1 = e^b_n exp(-h) + e^d_n [(1 - exp(-h))/h - exp(-h)] + e^d_n+1 [1 - (1 - exp(-h))/h]
// [DERIVED: the convolution e^b(t) = e^b_n exp(-h) + int_0^dt exp(-(dt - s)/tau) e^d(s) ds/tau
// with e^d(s) = e^d_n + (e^d_n+1 - e^d_n) s/dt]. The coefficients sum to 1 (a held e^d is a
// fixed point), and the update is exact, not an approximation, for a piecewise-linear
// strain history: the relaxation test holds to round-off whatever dt.
//
// Energy: W = k' theta^2/2 + (alpha/2) sum_j omega [lambda_inf (e^d)^2 + sum_b lambda_b
// (e^d - e^b_b)^2] V_j (the springs). The dissipated energy of a step
// (material/models/history_ledger.hpp) is the trapezoidal work of the step less the change
// of W; without broken bonds that is exactly the dashpots' work
// (alpha/2) sum_b lambda_b sum_j omega (q_n + q_n+1) (e^b_n+1 - e^b_n) V_j, q = e^d - e^b.
//
// 2-D [DERIVED]. Plane strain is the 3-D model with eps_33 = 0, exactly: the 3-D deviator
// has the in-plane part eps_ab - theta/3 delta_ab = e2_ab + (theta/6) delta_ab (e2 the
// in-plane deviator, theta the in-plane dilatation), so the in-plane stress is
// sigma_ab = [k theta + (1/3)(2 mu * theta/2)] delta_ab + 2 mu * e2_ab, where 2 mu * is the
// standard-linear-solid operator: the mu/3 of k' = k + mu/3 relaxes like the deviatoric
// part. The model writes the dilatation term as (d/m) omega |xi| p with
//   p = k theta + (mu/3) [lambda_inf theta + sum_b lambda_b (theta - theta^b_b)],
// theta^b_b a back dilatation per particle and branch, updated like e^b, and adds
// (mu/6) [lambda_inf theta^2 + sum_b lambda_b (theta - theta^b_b)^2] to W. Plane stress keeps
// the elastic k' = 9 k mu/(3k + 4 mu) of the instantaneous moduli: its sigma_33 = 0 couples
// eps_33 to the relaxation in a way that is not of this form, so only isochoric in-plane
// deformation is exact there.
#include <cmath>

#include "horizon/kernels/ordinary.hpp"
#include "horizon/material/model.hpp"

namespace horizon {

// The most Maxwell branches a material may have (deck keys lambda_1..3, tau_1..3).
inline constexpr int kMaxViscousBranches = 3;

// Coefficients of the exact update of one branch over dt (formula above):
// e^b_n+1 = decay e^b_n + from_old e^d_n + from_new e^d_n+1.
struct SlsStep {
  double decay = 1, from_old = 0, from_new = 0;
};
inline SlsStep sls_step(double dt, double tau) {
  SlsStep c;
  if (!(dt > 0)) return c;  // no time has passed: the back extension holds
  const double h = dt / tau;
  c.decay = std::exp(-h);
  if (h < 0.05) {
    // Both other coefficients are differences of nearly equal numbers for small h; their
    // series (from those of exp(-h) and (1 - exp(-h))/h) keep every digit:
    //   from_new = sum_k>=1 (-1)^(k+1) h^k/(k+1)!,  from_old = sum_k>=1 (-1)^(k+1) k h^k/(k+1)!
    // (the terms beyond k = 8 are below 1e-16 relative for h < 0.05).
    double term = 1, fact = 1, sign = 1;
    c.from_new = c.from_old = 0;
    for (int k = 1; k <= 8; ++k) {
      term *= h;
      fact *= (k + 1);
      c.from_new += sign * term / fact;
      c.from_old += sign * k * term / fact;
      sign = -sign;
    }
    return c;
  }
  const double ratio = -std::expm1(-h) / h;  // (1 - exp(-h))/h
  c.from_old = ratio - c.decay;
  c.from_new = 1.0 - ratio;
  return c;
}

// The branch update of one bond.
// (kernels/ordinary.hpp: the device-portable form, which the rows reach through this one.)
inline double sls_back_extension(const SlsStep& c, double back, double ed_old, double ed_new) {
  return kernels::sls_back_extension(c.decay, c.from_old, c.from_new, back, ed_old, ed_new);
}

// The relaxation function of the model, G(t)/mu = lambda_inf + sum_b lambda_b exp(-t/tau_b)
// (Mitchell 2011; the classical standard linear solid).
inline double sls_relaxation(double t, double lambda_inf, const double* lambda, const double* tau, int branches) {
  double g = lambda_inf;
  for (int b = 0; b < branches; ++b) g += lambda[b] * std::exp(-t / tau[b]);
  return g;
}

ModelEntry viscoelastic_model();

}  // namespace horizon
