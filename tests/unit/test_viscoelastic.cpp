// The kernels of the viscoelastic solid (material/models/viscoelastic.hpp) alone: the exact
// exponential update of a Maxwell branch against the analytic standard-linear-solid
// relaxation after a ramp (exact for any step), the small-step limit, and creep under a
// constant stress (second-order in the step, since the creep strain is not piecewise
// linear in time).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "horizon/material/models/viscoelastic.hpp"

namespace horizon {
namespace {

TEST(ViscoelasticKernels, StepCoefficientsSumToOneAndHoldWithoutTime) {
  for (double h : {1e-12, 1e-9, 1e-6, 1e-3, 0.04, 0.05, 0.1, 1.0, 10.0, 1e3}) {
    const SlsStep c = sls_step(h, 1.0);
    EXPECT_NEAR(c.decay + c.from_old + c.from_new, 1.0, 1e-15) << h;
    EXPECT_GE(c.from_old, 0);
    EXPECT_GE(c.from_new, 0);
    if (h >= 0.05) {
      // Against the formulas in long double, where they lose no digits.
      const long double H = h, e = std::exp(-H), ratio = (1 - e) / H;
      EXPECT_NEAR(c.decay, static_cast<double>(e), 1e-15);
      EXPECT_NEAR(c.from_new, static_cast<double>(1 - ratio), 1e-14);
      EXPECT_NEAR(c.from_old, static_cast<double>(ratio - e), 1e-14);
    } else {
      // The leading terms of the series: from_new = h/2 - h^2/6 + h^3/24, from_old =
      // h/2 - h^2/3 + h^3/8 (relative error of the truncation below 1e-4 here).
      EXPECT_NEAR(c.from_new / (h / 2 - h * h / 6 + h * h * h / 24), 1.0, 1e-4 + h * h * h);
      EXPECT_NEAR(c.from_old / (h / 2 - h * h / 3 + h * h * h / 8), 1.0, 1e-4 + h * h * h);
    }
  }
  // The series and the closed form meet without a jump.
  const SlsStep below = sls_step(0.05 * (1 - 1e-13), 1.0), above = sls_step(0.05, 1.0);
  EXPECT_NEAR(below.from_new, above.from_new, 1e-14);  // d/dh is about 1/2
  EXPECT_NEAR(below.from_old, above.from_old, 1e-14);
  const SlsStep none = sls_step(0.0, 1.0);
  EXPECT_EQ(none.decay, 1.0);
  EXPECT_EQ(none.from_old, 0.0);
  EXPECT_EQ(none.from_new, 0.0);
}

// A ramp of e^d from 0 to e0 over t_r, then held. The analytic standard linear solid
// (one branch): for t >= t_r,
//   S/(2 mu e0) = lambda_inf + lambda (tau/t_r)(exp(t_r/tau) - 1) exp(-t/tau).
// The update is exact for this piecewise-linear history, whatever the step.
TEST(ViscoelasticKernels, ExponentialUpdateIsExactForRampAndHold) {
  const double tau = 2e-3, lambda = 0.6, linf = 0.4, e0 = 1e-3, tr = 0.5e-3;
  for (int ramp_steps : {1, 3, 50}) {
    for (double hold_dt : {1e-5, 3e-4, 5e-3}) {
      double t = 0, ed = 0, back = 0;
      const double dt = tr / ramp_steps;
      for (int n = 0; n < ramp_steps; ++n) {
        const double next = e0 * (n + 1) / ramp_steps;
        back = sls_back_extension(sls_step(dt, tau), back, ed, next);
        ed = next;
        t += dt;
      }
      double worst = 0;
      while (t < 5 * tau) {
        back = sls_back_extension(sls_step(hold_dt, tau), back, ed, ed);
        t += hold_dt;
        const double model = (linf * ed + lambda * (ed - back)) / e0;
        const double exact = linf + lambda * (tau / tr) * std::expm1(tr / tau) * std::exp(-t / tau);
        worst = std::max(worst, std::abs(model - exact));
      }
      EXPECT_LT(worst, 1e-13) << ramp_steps << " ramp steps, hold step " << hold_dt;
    }
  }
}

// The relaxation function of three branches, sampled by the update with a sudden step
// (one very short ramp): G(t)/mu = lambda_inf + sum lambda_b exp(-t/tau_b).
TEST(ViscoelasticKernels, ThreeBranchesRelaxAsTheirSum) {
  const double lambda[3] = {0.3, 0.2, 0.1}, tau[3] = {1e-4, 1e-3, 1e-2}, linf = 0.4;
  const double tr = 1e-9;
  double back[3] = {0, 0, 0};
  for (int b = 0; b < 3; ++b) back[b] = sls_back_extension(sls_step(tr, tau[b]), 0, 0, 1.0);
  double t = tr;
  for (double target : {5e-5, 1e-3, 2e-2}) {
    const double dt = target - t;
    double g = linf;
    for (int b = 0; b < 3; ++b) {
      back[b] = sls_back_extension(sls_step(dt, tau[b]), back[b], 1.0, 1.0);
      g += lambda[b] * (1.0 - back[b]);
    }
    t = target;
    EXPECT_NEAR(g, sls_relaxation(t, linf, lambda, tau, 3), 2e-5) << t;  // O(tr/tau) from the ramp
  }
}

// Creep: a constant deviatoric stress S0 from t = 0. The classical answer (one branch):
//   e(t) = S0/(2 mu) [1/lambda_inf - (1/lambda_inf - 1) exp(-lambda_inf t/tau)],
// a retardation time tau/lambda_inf. Each step solves S(e_n+1) = S0 for e_n+1 with the
// update (linear in e_n+1); the error is second order in the step.
double creep_error(double dt) {
  const double tau = 1e-3, lambda = 0.7, linf = 0.3, s0 = 1e-3;  // s0 = S0/(2 mu)
  double ed = s0, back = 0, t = 0, worst = 0;                     // instantaneous elastic response
  while (t < 5 * tau) {
    const SlsStep c = sls_step(dt, tau);
    // s0 = linf e + lambda (e - decay back - from_old e_n - from_new e).
    const double e = (s0 + lambda * (c.decay * back + c.from_old * ed)) / (linf + lambda * (1 - c.from_new));
    back = sls_back_extension(c, back, ed, e);
    ed = e;
    t += dt;
    const double exact = s0 * (1 / linf - (1 / linf - 1) * std::exp(-linf * t / tau));
    worst = std::max(worst, std::abs(ed - exact) / exact);
  }
  return worst;
}

TEST(ViscoelasticKernels, CreepConvergesAtSecondOrderToTheClassicalCurve) {
  const double coarse = creep_error(1e-4), fine = creep_error(0.5e-4);
  EXPECT_LT(coarse, 2e-3);
  EXPECT_NEAR(coarse / fine, 4.0, 0.4);
}

}  // namespace
}  // namespace horizon
