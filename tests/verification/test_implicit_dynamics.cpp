// Implicit dynamics (solver/newmark.hpp; docs/verification.md, "Static and implicit
// solvers"): the fundamental mode of a 1-D PMB bar, clamped at one end and free at the
// other, integrated by Newmark's average acceleration with a time step ten times the
// explicit stable step. Its period must match the analytic T = 4 L / c, c = sqrt(E/rho),
// to 1 %; the energy must be conserved.
//
// The bar: nodes x = i h, i = -3 .. 200, h = L/200, horizon 3 h with partial volumes
// (exact 1-D energy in the bulk, docs/models.md sec. 8); nodes x <= 0 held (the clamp and
// its collar), the material ends at L + h/2 (the free face of the last cell), so the
// mode is u = A sin(pi x / (2 L')), L' = L + h/2. The nonlocal dispersion lowers the
// frequency by O((k delta)^2) = 6e-4 here, and average acceleration lengthens the period
// by (omega dt)^2 / 12 = 2.6e-4 (Hughes 2000, sec. 9.1.4).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <omp.h>

#include "horizon/solver/newmark.hpp"
#include "../single_thread.hpp"
#include "verification_support.hpp"

namespace horizon::verification {
namespace {

// One OpenMP thread for these small problems (tests/single_thread.hpp).
using OneThread = test::SingleThread;

TEST(ImplicitDynamics, NewmarkBarPeriodWithTenTimesTheStableStep) {
  OneThread one;
  const double L = 0.1, h = L / 200, E = 200e9, rho = 8000;
  const std::string deck = fmt::format(R"(dimension: 1
area: 1.0e-4
spacing: {h}
horizon_factor: 3
partial_volume: true
lattice_origin: [0]
materials:
  steel: {{model: pmb, density: {rho}, youngs_modulus: {E}}}
bodies:
  - {{name: bar, material: steel, shape: {{box: {{min: [{x0}], max: [{x1}]}}}}}}
regions:
  clamp: {{box: {{min: [{x0}], max: [{q}]}}}}
loads:
  - {{region: clamp, displacement: [0]}}
solver: {{type: implicit_dynamic, end_time: 1.0, time_step: 1.0}}
)",
                                       fmt::arg("h", h), fmt::arg("rho", rho), fmt::arg("E", E),
                                       fmt::arg("x0", -3.5 * h), fmt::arg("x1", L + 0.5 * h), fmt::arg("q", 0.25 * h));
  Config c = parse_deck(deck, "bar.yaml");
  System s = build_system(c);
  Loads loads(c, s);
  const double L_eff = L + 0.5 * h, A = 1e-5;
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    const double x = s.particles.X[i].x;
    s.particles.u[i].x = x > 0 ? A * std::sin(std::numbers::pi * x / (2 * L_eff)) : 0.0;
  }
  const double dt_stable = stable_time_step(s), dt = 10 * dt_stable;
  const double T = 4 * L_eff / std::sqrt(E / rho);

  NewtonOptions o;
  o.linear_solver = LinearSolverKind::cg;
  o.tolerance = 1e-8;
  NewmarkSolver solver(s, loads, dt, 0.0, o, 1);
  solver.initialize();
  const double energy0 = solver.ledger().kinetic + solver.ledger().strain;

  // Tip displacement; periods from its downward zero crossings (linear interpolation).
  std::size_t tip = 0;
  for (std::size_t i = 0; i < s.particles.size(); ++i)
    if (s.particles.X[i].x > s.particles.X[tip].x) tip = i;
  std::vector<double> crossings;
  double t_prev = 0, u_prev = s.particles.u[tip].x, max_drift = 0;
  while (solver.time() < 3.3 * T) {
    const SolveReport r = solver.step();
    ASSERT_TRUE(r.converged) << r.failure;
    const double u = s.particles.u[tip].x, t = solver.time();
    if (u_prev > 0 && u <= 0) crossings.push_back(t_prev + (t - t_prev) * u_prev / (u_prev - u));
    t_prev = t;
    u_prev = u;
    const double energy = solver.ledger().kinetic + solver.ledger().strain;
    max_drift = std::max(max_drift, std::abs(energy / energy0 - 1));
  }
  ASSERT_GE(crossings.size(), 3u);
  const double period = (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
  report("newmark_period", period / T,
         fmt::format("1-D bar, Newmark, dt = 10 x the stable step ({:.3e} s, {:.0f} steps per period): period "
                     "{:.6e} s, analytic 4L/c = {:.6e} s ({:+.3f} %); {} Newton iterations in {} steps",
                     dt, T / dt, period, T, 100 * (period / T - 1), solver.newton_iterations(), solver.steps()));
  report("newmark_energy_drift", max_drift,
         fmt::format("1-D bar, Newmark: largest |E(t)/E(0) - 1| = {:.2e}", max_drift));
  EXPECT_NEAR(period / T, 1.0, 0.01);
  EXPECT_LT(max_drift, 1e-4);
}

}  // namespace
}  // namespace horizon::verification
