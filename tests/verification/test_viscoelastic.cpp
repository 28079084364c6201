// The viscoelastic solid (material/models/viscoelastic.hpp; docs/models/viscoelastic.md;
// docs/verification.md, "the elastic-plastic and viscoelastic models"):
// - stress relaxation at a material point (the centre of a lattice block with a full family,
//   homogeneous pure shear eps_xx = -eps_yy = g ramped in t_r and held) against the analytic
//   standard linear solid with two Maxwell branches, at three times; 3-D and plane strain;
// - creep under a constant shear stress (the strain solved each step so that the collapsed
//   stress holds its value): the retardation time tau/lambda_inf, from which tau is recovered;
// - zero force under rigid motion; momentum and thread independence in an impact with bond
//   breaking; the energy ledger of an impact with the viscous dissipation counted; the static
//   solver (Newton, finite-difference tangent) against ADR and against the LPS of the
//   long-term moduli.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "model_checks.hpp"

namespace horizon::verification {
namespace {

constexpr double kE = 70e9, kNu = 0.3;
constexpr double kTau1 = 1e-3, kTau2 = 1e-2, kL1 = 0.4, kL2 = 0.3, kLinf = 0.3;

MaterialConfig material() {
  return model_material("viscoelastic", kE, kNu, 2700,
                        {{"lambda_1", kL1}, {"tau_1", kTau1}, {"lambda_2", kL2}, {"tau_2", kTau2}});
}

// Pure shear g ramped linearly over t_r (5 steps), then held (steps of tau_1/4, which the
// exact update does not need). Returns tau_xy-equivalent (sigma_xx - sigma_yy)/2 / (2 mu g)
// at the requested times after t = 0, against the analytic curve of a ramp-and-hold:
//   G(t)/mu = lambda_inf + sum_b lambda_b (tau_b/t_r)(exp(t_r/tau_b) - 1) exp(-t/tau_b).
struct Relaxation {
  std::vector<double> model, exact;
  double elastic = 0;  // the response at the end of the ramp relative to its analytic value
};

Relaxation relax(int dimension, double r_horizon, const std::vector<double>& times) {
  test::SingleThread one;
  MaterialPoint mp(material(), dimension, dimension == 2 ? PlaneMode::strain : PlaneMode::none, r_horizon);
  const double mu = kE / (2 * (1 + kNu)), g = 1e-4, tr = 0.1 * kTau1;
  auto exact = [&](double t) {
    return kLinf + kL1 * (kTau1 / tr) * std::expm1(tr / kTau1) * std::exp(-t / kTau1) +
           kL2 * (kTau2 / tr) * std::expm1(tr / kTau2) * std::exp(-t / kTau2);
  };
  auto shear = [&](double gg, double t) {
    const Strain3 eps{{{gg, 0, 0}, {0, -gg, 0}, {0, 0, 0}}};
    const Eigen::Matrix3d s = mp.stress(eps, t);
    mp.commit(t);
    return 0.5 * (s(0, 0) - s(1, 1)) / (2 * mu * g);
  };
  Relaxation r;
  double t = 0, value = 0;
  for (int n = 1; n <= 5; ++n) {
    t = tr * n / 5;
    value = shear(g * n / 5, t);
  }
  r.elastic = value / exact(tr);
  for (double target : times) {
    while (t < target - 1e-15) {
      t = std::min(target, t + 0.25 * kTau1);
      value = shear(g, t);
    }
    r.model.push_back(value);
    r.exact.push_back(exact(target));
  }
  return r;
}

TEST(Viscoelastic, StressRelaxationFollowsTheStandardLinearSolid) {
  const std::vector<double> times{0.5 * kTau1, 2 * kTau1, 2 * kTau2};
  for (int dim : {3, 2}) {
    // horizon 4 spacings: the lattice's shear modulus in this pure shear is within 0.6 %
    // (+1.7 % in 3-D and +3.6 % in plane strain at 3 spacings).
    const Relaxation r = relax(dim, 4.0, times);
    std::string text = fmt::format("viscoelastic, {} pure shear relaxation (two branches): ",
                                   dim == 3 ? "3-D" : "plane strain");
    double worst = 0;
    for (std::size_t k = 0; k < times.size(); ++k) {
      const double err = r.model[k] / r.exact[k] - 1;
      worst = std::max(worst, std::abs(err));
      text += fmt::format("G/mu({:.1e} s) = {:.4f} (SLS {:.4f}, {:+.2f} %); ", times[k], r.model[k], r.exact[k], 100 * err);
      EXPECT_NEAR(r.model[k] / r.exact[k], 1.0, 0.02) << dim << "-D at t = " << times[k];
    }
    // The shape of the curve alone (the lattice's shear modulus divides out): exact up to
    // the geometric nonlinearity of e = |Y| - |xi| at a strain of 1e-4 (about 1e-8).
    for (std::size_t k = 0; k < times.size(); ++k)
      EXPECT_NEAR(r.model[k] / r.elastic / r.exact[k], 1.0, 1e-7) << dim << "-D at t = " << times[k];
    report(dim == 3 ? "ves_relaxation_3d" : "ves_relaxation_2d", worst,
           text + fmt::format("lattice shear modulus {:+.2f} %", 100 * (r.elastic - 1)));
  }
}

// Isotropic expansion eps_xx = eps_yy (= eps_zz in 3-D) = 1e-4, ramped and held as above:
// the mean stress of the collapsed force state. 3-D: the dilatation is elastic, p = 3 k eps
// at every time. Plane strain: the 3-D model with eps_33 = 0, whose in-plane mean stress
// is [k + (mu/3) g(t)] 2 eps with g the relaxation function of the ramp (header): the
// lattice does not enter (theta is exact under isotropic expansion), so the check is tight.
TEST(Viscoelastic, DilatationIsElasticIn3dAndRelaxesItsShearPartInPlaneStrain) {
  test::SingleThread one;
  const double mu = kE / (2 * (1 + kNu)), K = kE / (3 * (1 - 2 * kNu)), e0 = 1e-4, tr = 0.1 * kTau1;
  auto g = [&](double t) {
    return kLinf + kL1 * (kTau1 / tr) * std::expm1(tr / kTau1) * std::exp(-t / kTau1) +
           kL2 * (kTau2 / tr) * std::expm1(tr / kTau2) * std::exp(-t / kTau2);
  };
  for (int dim : {3, 2}) {
    MaterialPoint mp(material(), dim, dim == 2 ? PlaneMode::strain : PlaneMode::none, 3.0);
    auto mean_stress = [&](double e, double t) {
      Strain3 eps{};
      for (int a = 0; a < dim; ++a) eps[a][a] = e;
      const Eigen::Matrix3d s = mp.stress(eps, t);
      mp.commit(t);
      return (dim == 3 ? s.trace() : s(0, 0) + s(1, 1)) / dim;
    };
    double t = 0;
    for (int n = 1; n <= 5; ++n) mean_stress(e0 * n / 5, t = tr * n / 5);
    double worst = 0;
    std::string text;
    for (double target : {0.5 * kTau1, 2 * kTau1, 2 * kTau2}) {
      double p = 0;
      while (t < target - 1e-15) p = mean_stress(e0, t = std::min(target, t + 0.25 * kTau1));
      const double exact = dim == 3 ? 3 * K * e0 : (K + mu / 3 * g(target)) * 2 * e0;
      worst = std::max(worst, std::abs(p / exact - 1));
      text += fmt::format("{:.1e} s: {:.5f} MPa ({:.5f}); ", target, p / 1e6, exact / 1e6);
      EXPECT_NEAR(p / exact, 1.0, 1e-6) << dim << "-D at t = " << target;
    }
    report(dim == 3 ? "ves_dilatation_3d" : "ves_dilatation_2d", worst,
           fmt::format("viscoelastic, {} isotropic expansion, mean stress {}worst {:.1e}",
                       dim == 3 ? "3-D (elastic)" : "plane strain (k + mu/3 g(t))", text, worst));
  }
}

// Creep under a constant shear stress S0 (one branch, lambda_1 = 0.5): the strain follows
//   g(t) = S0/(2 mu) [1/lambda_inf - (1/lambda_inf - 1) exp(-t lambda_inf/tau)].
// From three equally spaced samples, tau_c = dt / ln((g2 - g1)/(g3 - g2)), independent of the
// end values (and so of the lattice's modulus); tau = lambda_inf tau_c.
TEST(Viscoelastic, CreepRecoversTheDecayTime) {
  test::SingleThread one;
  const double tau = 1e-3, lambda = 0.5, linf = 1 - lambda;
  MaterialPoint mp(model_material("viscoelastic", kE, kNu, 2700, {{"lambda_1", lambda}, {"tau_1", tau}}), 3,
                   PlaneMode::none, 3.0);
  const double mu = kE / (2 * (1 + kNu)), s0 = 2 * mu * 1e-4, tc = tau / linf;
  const int per = 100;  // steps per retardation time
  double g = 0, t = 0;
  auto hold = [&](double time) {
    auto residual = [&](double gg) {
      const Strain3 eps{{{gg, 0, 0}, {0, -gg, 0}, {0, 0, 0}}};
      const Eigen::Matrix3d s = mp.stress(eps, time);
      return 0.5 * (s(0, 0) - s(1, 1)) - s0;
    };
    g = secant(residual, g, g + 1e-6, 1e-12 * s0);
    residual(g);
    mp.commit(time);
  };
  hold(1e-9 * tau);  // the load comes on: the instantaneous (elastic) response
  std::vector<double> samples;
  for (int n = 1; n <= 3 * per; ++n) {
    t = n * tc / per;
    hold(t);
    if (n % per == 0) samples.push_back(g);
  }
  const double tc_fit = tc / std::log((samples[1] - samples[0]) / (samples[2] - samples[1]));
  const double tau_fit = linf * tc_fit;
  report("ves_creep_tau", tau_fit / tau,
         fmt::format("viscoelastic, creep under constant shear stress: retardation time {:.4e} s (tau/lambda_inf = "
                     "{:.4e}), decay time recovered {:.4e} s against {:.1e} ({:+.3f} %)",
                     tc_fit, tc, tau_fit, tau, 100 * (tau_fit / tau - 1)));
  EXPECT_NEAR(tau_fit / tau, 1.0, 0.03);
}

TEST(Viscoelastic, RigidMotionGivesNoForce) {
  const double f3 = rigid_motion_force(material(), 3, PlaneMode::none);
  const double f2 = rigid_motion_force(material(), 2, PlaneMode::stress);
  report("ves_rigid_force", std::max(f2, f3),
         fmt::format("viscoelastic, rigid rotation (0.6 rad) and translation: max |f| = {:.1e} (3-D), {:.1e} "
                     "(plane stress) of the force of a 1e-3 strain", f3, f2));
  EXPECT_LT(f3, 1e-9);
  EXPECT_LT(f2, 1e-9);
}

// Branch decay times of the order of the impact's duration, so that the dashpots work.
const std::string kPolymer =
    "{model: viscoelastic, density: 7850, youngs_modulus: 200.0e9, poissons_ratio: 0.3, lambda_1: 0.5, tau_1: 1.0e-6, "
    "lambda_2: 0.2, tau_2: 5.0e-6";

TEST(Viscoelastic, ImpactWithBreakingConservesMomentumAndIsThreadIndependent) {
  const std::string deck = impact_deck(kPolymer + ", damage: {critical_stretch: 0.002}}", 40, 3e-6);
  const ImpactRun one = run_impact(deck, 1), two = run_impact(deck, 2);
  double lost = 0;
  for (double d : one.dissipated_at) lost += d;
  const double dp = norm(one.p1 - one.p0) / norm(one.p0), dL = norm(one.L1 - one.L0) / norm(one.L0);
  report("ves_momentum", std::max(dp, dL),
         fmt::format("viscoelastic impact (40 m/s, {} steps, {} bonds broken, {:.3e} J dissipated): "
                     "|dp|/|p| = {:.1e}, |dL|/|L| = {:.1e}", one.steps, one.broken, lost, dp, dL));
  EXPECT_GT(one.broken, 0u) << "the run is meant to break bonds";
  EXPECT_LT(dp, 1e-12);
  EXPECT_LT(dL, 1e-12);
  EXPECT_EQ(one.broken, two.broken);
  EXPECT_TRUE(same_bits(one.u, two.u)) << "displacements differ between 1 and 2 threads";
  EXPECT_TRUE(same_bits(one.v, two.v)) << "velocities differ";
  EXPECT_TRUE(same_bits(one.dissipated_at, two.dissipated_at)) << "dissipated energy differs";
}

TEST(Viscoelastic, EnergyLedgerClosesWithTheViscousDissipation) {
  const ImpactRun r = run_impact_ledger(impact_deck(kPolymer + "}", 2, 8e-6));
  report("ves_ledger", r.max_balance_error,
         fmt::format("viscoelastic impact (2 m/s, {} steps): viscous dissipation {:.1f} % of the initial energy, "
                     "max |balance error| = {:.2e}", r.steps, 100 * r.ledger.dissipated / r.ledger.initial,
                     r.max_balance_error));
  EXPECT_GT(r.ledger.dissipated, 0.05 * r.ledger.initial);
  EXPECT_LT(r.max_balance_error, 0.01);
  // With bonds breaking at 0.2 % (material/models/history_ledger.hpp).
  const ImpactRun broken = run_impact_ledger(impact_deck(kPolymer + ", damage: {critical_stretch: 0.002}}", 40, 3e-6));
  report("ves_ledger_breaking", broken.max_balance_error,
         fmt::format("viscoelastic, impact with breaking (40 m/s, {} steps): dissipated {:.1f} % of the initial "
                     "energy, max |balance error| = {:.2e}", broken.steps,
                     100 * broken.ledger.dissipated / broken.ledger.initial, broken.max_balance_error));
  EXPECT_LT(broken.max_balance_error, 0.01);
  // Plane strain, where the mu/3 of k' relaxes too (a back dilatation per particle).
  const std::string plane = R"(dimension: 2
plane: strain
thickness: 1.0e-3
spacing: 1.0e-3
horizon: 3.0e-3
materials:
  p: {model: viscoelastic, density: 7850, youngs_modulus: 200.0e9, poissons_ratio: 0.3, lambda_1: 0.5, tau_1: 1.0e-6, lambda_2: 0.2, tau_2: 5.0e-6}
bodies:
  - {name: striker, material: p, shape: {box: {min: [0, 0], max: [0.006, 0.004]}}}
  - {name: bar, material: p, shape: {box: {min: [0.006, 0], max: [0.018, 0.004]}}}
regions:
  striker: {box: {min: [0, 0], max: [0.006, 0.004]}}
initial_conditions:
  - {region: striker, velocity: [2, 0.3]}
solver: {type: explicit, end_time: 8.0e-6, safety_factor: 0.5}
)";
  const ImpactRun two_d = run_impact_ledger(plane);
  report("ves_ledger_plane_strain", two_d.max_balance_error,
         fmt::format("viscoelastic, plane-strain impact (2 m/s, {} steps): dissipated {:.1f} % of the initial energy, "
                     "max |balance error| = {:.2e}", two_d.steps, 100 * two_d.ledger.dissipated / two_d.ledger.initial,
                     two_d.max_balance_error));
  EXPECT_GT(two_d.ledger.dissipated, 0.05 * two_d.ledger.initial);
  EXPECT_LT(two_d.max_balance_error, 0.01);
}

// Static: the pseudo-time of the solve (1 s) is long against tau, so the static answer is
// the relaxed one: the LPS with the long-term shear modulus lambda_inf mu (K unchanged).
TEST(Viscoelastic, StaticNewtonMatchesAdrAndTheRelaxedLps) {
  const double K = 200e9 / (3 * (1 - 2 * 0.3)), mu = 200e9 / (2 * 1.3), linf = 0.3;
  const std::string ves =
      "{model: viscoelastic, density: 7850, youngs_modulus: 200.0e9, poissons_ratio: 0.3, lambda_1: 0.7, tau_1: 1.0e-7}";
  const std::string lps = fmt::format("{{model: lps, density: 7850, bulk_modulus: {}, shear_modulus: {}}}", K, linf * mu);
  const double traction = 50e6;
  std::string failure;
  const auto newton = solve_static(
      static_block_deck(ves, traction, "{type: static, method: newton, tangent: finite_difference, tolerance: 1.0e-10}"),
      &failure);
  ASSERT_FALSE(newton.empty()) << failure;
  const auto adr = solve_static(static_block_deck(ves, traction, "{type: static, method: adr, tolerance: 1.0e-9}"), &failure);
  ASSERT_FALSE(adr.empty()) << failure;
  const auto relaxed = solve_static(static_block_deck(lps, traction, "{type: static, method: newton, tolerance: 1.0e-10}"));
  ASSERT_FALSE(relaxed.empty());
  const double d_adr = max_difference(adr, newton), d_lps = max_difference(newton, relaxed);
  report("ves_static", d_adr,
         fmt::format("viscoelastic block, static (pseudo-time 1 s, tau 1e-7 s): max |u_Newton(FD) - u_ADR|/max|u| = "
                     "{:.1e}, against the LPS of the long-term moduli {:.1e}", d_adr, d_lps));
  EXPECT_LT(d_adr, 1e-5);
  EXPECT_LT(d_lps, 1e-5);
}

}  // namespace
}  // namespace horizon::verification
