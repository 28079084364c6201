// The elastic-plastic solid (material/models/elastic_plastic.hpp; docs/models/elastic_plastic.md;
// docs/verification.md, "the elastic-plastic and viscoelastic models"):
// - uniaxial stress at a material point (the centre of a lattice block with a full family,
//   homogeneous deformation u = eps (X - X_c) on every particle, the lateral strains solved
//   so that the lateral stresses of the collapsed force state vanish): yield at sigma_y,
//   the hardening slope E H/(E + H), the elastic unloading slope E and the permanent strain
//   after unloading against classical J2 with linear isotropic hardening;
// - plane strain: yield in in-plane pure shear at sigma_y/sqrt(3) (the 2-D calibration);
//   plane stress refused;
// - zero force under rigid motion; linear and angular momentum in a plastic impact with
//   bond breaking; the energy ledger of an elastic impact (and of a plastic one, with the
//   plastic work as dissipated energy); the same bits on 1 and 2 threads; the static
//   solver (Newton, finite-difference tangent) against ADR and against the LPS below yield.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "model_checks.hpp"

namespace horizon::verification {
namespace {

constexpr double kE = 200e9, kNu = 0.3, kYield = 200e6;

// One uniaxial-stress history at the material point: along x to eps_max, then back to zero
// stress. Returns the (strain, stress) path and the permanent strain.
struct UniaxialPath {
  std::vector<double> strain, stress;  // loading branch
  double unload_slope = 0, permanent = 0, elastic_slope = 0;
};

UniaxialPath uniaxial(double hardening, double r, int increments, InfluenceKind omega = InfluenceKind::constant) {
  test::SingleThread one;
  MaterialConfig mat =
      model_material("elastic_plastic", kE, kNu, 7850, {{"yield_stress", kYield}, {"hardening_modulus", hardening}});
  mat.influence = omega;
  MaterialPoint mp(mat, 3, PlaneMode::none, r);
  const double ey = kYield / kE, emax = 4 * ey, de = emax / increments;
  double lateral = 0, t = 0;
  UniaxialPath out;
  // Stress at axial strain e with the lateral strains solved for sigma_yy = sigma_zz = 0
  // (equal by the lattice's cubic symmetry); leaves the trial state of the solution.
  auto solve = [&](double e) {
    auto g = [&](double l) {
      const Strain3 eps{{{e, 0, 0}, {0, l, 0}, {0, 0, l}}};
      return mp.stress(eps, t).coeff(1, 1);
    };
    lateral = secant(g, lateral, lateral - 0.3 * de, 1e-9 * kYield);
    const Strain3 eps{{{e, 0, 0}, {0, lateral, 0}, {0, 0, lateral}}};
    return mp.stress(eps, t).coeff(0, 0);
  };
  for (int n = 1; n <= increments; ++n) {
    t += 1;
    const double e = n * de, s = solve(e);
    mp.commit(t);
    out.strain.push_back(e);
    out.stress.push_back(s);
  }
  out.elastic_slope = out.stress[0] / out.strain[0];
  // Unloading: one small elastic step for the slope, then the strain of zero axial stress
  // (sigma_xx is linear in the axial strain while the step stays elastic).
  t += 1;
  const double s_top = out.stress.back(), e_top = out.strain.back();
  const double s_down = solve(e_top - 0.1 * ey);
  mp.commit(t);
  out.unload_slope = (s_top - s_down) / (0.1 * ey);
  t += 1;
  out.permanent = secant([&](double e) { return solve(e); }, e_top - 0.1 * ey, e_top - 0.5 * ey, 1e-9 * kYield);
  return out;
}

// Least-squares line through the points with strain in [lo, hi].
std::pair<double, double> fit_line(const UniaxialPath& p, double lo, double hi) {
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t k = 0; k < p.strain.size(); ++k) {
    if (p.strain[k] < lo - 1e-12 || p.strain[k] > hi + 1e-12) continue;
    n += 1;
    sx += p.strain[k];
    sy += p.stress[k];
    sxx += p.strain[k] * p.strain[k];
    sxy += p.strain[k] * p.stress[k];
  }
  const double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
  return {slope, (sy - slope * sx) / n};
}

TEST(ElasticPlastic, UniaxialStressPerfectPlasticityYieldUnloadingAndPermanentStrain) {
  const UniaxialPath p = uniaxial(0.0, 3.0, 16);
  const double ey = kYield / kE, emax = p.strain.back();
  const double plateau = p.stress.back();
  // Classical J2, perfect plasticity: sigma = sigma_y after yield; unloading with E;
  // permanent strain eps_max - sigma_y/E.
  const double permanent_j2 = emax - kYield / kE;
  report("ep_perfect_yield", plateau / kYield,
         fmt::format("elastic-plastic, uniaxial stress, perfect plasticity: plateau at 4 eps_y = {:.2f} MPa "
                     "(sigma_y {:.0f} MPa, {:+.2f} %)", plateau / 1e6, kYield / 1e6, 100 * (plateau / kYield - 1)));
  report("ep_elastic_slope", p.elastic_slope / kE,
         fmt::format("elastic-plastic, uniaxial stress: loading slope {:.1f} GPa ({:+.2f} %), unloading slope "
                     "{:.1f} GPa ({:+.2f} %) against E = 200 GPa",
                     p.elastic_slope / 1e9, 100 * (p.elastic_slope / kE - 1), p.unload_slope / 1e9,
                     100 * (p.unload_slope / kE - 1)));
  report("ep_perfect_permanent", p.permanent / permanent_j2,
         fmt::format("elastic-plastic, perfect plasticity: permanent strain {:.4e} after unloading from {:.1e} "
                     "(J2: {:.4e}, {:+.2f} %)", p.permanent, emax, permanent_j2, 100 * (p.permanent / permanent_j2 - 1)));
  EXPECT_NEAR(plateau / kYield, 1.0, 0.03);
  // The plateau is flat: the stress at 2 eps_y and at 4 eps_y agree.
  EXPECT_NEAR(p.stress[7] / plateau, 1.0, 0.005);
  EXPECT_LT(p.stress[2], 1.0 * kYield) << "elastic below yield";
  EXPECT_NEAR(p.stress[2] / (p.strain[2] * kE), 1.0, 0.03);
  EXPECT_NEAR(p.unload_slope / kE, 1.0, 0.03);
  EXPECT_NEAR(p.permanent / permanent_j2, 1.0, 0.05);
  (void)ey;
}

TEST(ElasticPlastic, UniaxialStressLinearHardeningSlopeAndPermanentStrain) {
  const double H = 20e9;
  const UniaxialPath p = uniaxial(H, 3.0, 16);
  const double ey = kYield / kE, emax = p.strain.back();
  const auto [slope, intercept] = fit_line(p, 2 * ey, 4 * ey);
  const double tangent = kE * H / (kE + H);
  // Yield: where the hardening line meets the elastic line sigma = E_measured eps.
  const double e_yield = intercept / (p.elastic_slope - slope);
  const double s_yield = p.elastic_slope * e_yield;
  // Classical: eps_p = (E eps - sigma_y)/(E + H) at eps; unloading is elastic.
  const double permanent_j2 = (kE * emax - kYield) / (kE + H);
  report("ep_hardening_slope", slope / tangent,
         fmt::format("elastic-plastic, H = 20 GPa: hardening slope {:.3f} GPa against E H/(E + H) = {:.3f} GPa "
                     "({:+.2f} %)", slope / 1e9, tangent / 1e9, 100 * (slope / tangent - 1)));
  report("ep_hardening_yield", s_yield / kYield,
         fmt::format("elastic-plastic, H = 20 GPa: yield (elastic and hardening lines meet) at {:.2f} MPa "
                     "({:+.2f} %)", s_yield / 1e6, 100 * (s_yield / kYield - 1)));
  report("ep_hardening_permanent", p.permanent / permanent_j2,
         fmt::format("elastic-plastic, H = 20 GPa: permanent strain {:.4e} (J2: {:.4e}, {:+.2f} %); unloading slope "
                     "{:.1f} GPa ({:+.2f} %)", p.permanent, permanent_j2, 100 * (p.permanent / permanent_j2 - 1),
                     p.unload_slope / 1e9, 100 * (p.unload_slope / kE - 1)));
  EXPECT_NEAR(slope / tangent, 1.0, 0.05);
  EXPECT_NEAR(s_yield / kYield, 1.0, 0.03);
  EXPECT_NEAR(p.unload_slope / kE, 1.0, 0.03);
  EXPECT_NEAR(p.permanent / permanent_j2, 1.0, 0.05);
}

// The yield value holds for any influence function (the 1/omega-weighted norm, header):
// the plateau with omega = 1 - r/delta and omega = delta/r.
TEST(ElasticPlastic, UniaxialYieldWithOtherInfluenceFunctions) {
  std::string text = "elastic-plastic, uniaxial stress, perfect plasticity, plateau at 4 eps_y: ";
  double worst = 0;
  for (const auto& [omega, name] : {std::pair{InfluenceKind::linear, "linear"}, std::pair{InfluenceKind::inverse, "inverse"}}) {
    const UniaxialPath p = uniaxial(0.0, 3.0, 8, omega);
    const double ratio = p.stress.back() / kYield;
    worst = std::max(worst, std::abs(ratio - 1));
    text += fmt::format("{} {:.2f} MPa ({:+.2f} %, elastic slope {:+.2f} %); ", name,
                        p.stress.back() / 1e6, 100 * (ratio - 1), 100 * (p.elastic_slope / kE - 1));
    EXPECT_NEAR(ratio, 1.0, 0.03) << name;
  }
  report("ep_yield_influence", worst, text);
}

// Plane strain: the 2-D calibration is in-plane pure shear, eps = diag(g, -g): the shear
// stress (sigma_xx - sigma_yy)/2 saturates at sigma_y/sqrt(3).
TEST(ElasticPlastic, PlaneStrainPureShearYieldsAtTheShearYieldStress) {
  test::SingleThread one;
  MaterialPoint mp(model_material("elastic_plastic", kE, kNu, 7850, {{"yield_stress", kYield}}), 2,
                   PlaneMode::strain, 3.0);
  const double mu = kE / (2 * (1 + kNu)), gy = kYield / std::sqrt(3.0) / (2 * mu);
  double tau = 0, tau_elastic = 0;
  for (int n = 1; n <= 12; ++n) {
    const double g = n * 0.25 * gy;
    const Strain3 eps{{{g, 0, 0}, {0, -g, 0}, {0, 0, 0}}};
    const Eigen::Matrix3d s = mp.stress(eps, n);
    mp.commit(n);
    tau = 0.5 * (s(0, 0) - s(1, 1));
    if (n == 2) tau_elastic = tau / (2 * mu * g);
  }
  const double expected = kYield / std::sqrt(3.0);
  report("ep_plane_strain_shear_yield", tau / expected,
         fmt::format("elastic-plastic, plane strain, pure shear: plateau {:.2f} MPa against sigma_y/sqrt(3) = "
                     "{:.2f} MPa ({:+.2f} %); elastic shear modulus {:+.2f} %",
                     tau / 1e6, expected / 1e6, 100 * (tau / expected - 1), 100 * (tau_elastic - 1)));
  EXPECT_NEAR(tau / expected, 1.0, 0.03);
}

TEST(ElasticPlastic, PlaneStressIsRefusedWithAReason) {
  const MaterialConfig mat = model_material("elastic_plastic", kE, kNu, 7850, {{"yield_stress", kYield}});
  test::BlockSpec b;
  b.dimension = 2;
  b.plane = PlaneMode::stress;
  b.n = {5, 5, 1};
  try {
    test::make_block(b, mat);
    FAIL() << "plane stress must be refused";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("plane: stress"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("strain"), std::string::npos) << e.what();
  }
}

TEST(ElasticPlastic, RigidMotionGivesNoForce) {
  const MaterialConfig mat = model_material("elastic_plastic", kE, kNu, 7850, {{"yield_stress", kYield}});
  const double f3 = rigid_motion_force(mat, 3, PlaneMode::none);
  const double f2 = rigid_motion_force(mat, 2, PlaneMode::strain);
  report("ep_rigid_force", std::max(f2, f3),
         fmt::format("elastic-plastic, rigid rotation (0.6 rad) and translation: max |f| = {:.1e} (3-D), {:.1e} "
                     "(plane strain) of the force of a 1e-3 strain", f3, f2));
  EXPECT_LT(f3, 1e-9);
  EXPECT_LT(f2, 1e-9);
}

const std::string kSteel =
    "{model: elastic_plastic, density: 7850, youngs_modulus: 200.0e9, poissons_ratio: 0.3, yield_stress: 200.0e6, "
    "hardening_modulus: 2.0e9";

TEST(ElasticPlastic, PlasticImpactWithBreakingConservesMomentumAndIsThreadIndependent) {
  // 40 m/s: about 1.5 GPa of impact stress, far beyond yield; bonds break at 0.6 %.
  const std::string deck = impact_deck(kSteel + ", damage: {critical_stretch: 0.006}}", 40, 3e-6);
  const ImpactRun one = run_impact(deck, 1), two = run_impact(deck, 2);
  double plastic = 0;
  for (double d : one.dissipated_at) plastic += d;
  const double dp = norm(one.p1 - one.p0) / norm(one.p0), dL = norm(one.L1 - one.L0) / norm(one.L0);
  report("ep_momentum", std::max(dp, dL),
         fmt::format("elastic-plastic impact (40 m/s, {} steps, {} bonds broken, {:.3e} J dissipated): "
                     "|dp|/|p| = {:.1e}, |dL|/|L| = {:.1e}", one.steps, one.broken, plastic, dp, dL));
  EXPECT_GT(one.broken, 0u) << "the run is meant to break bonds";
  EXPECT_GT(plastic, 0.0);
  EXPECT_LT(dp, 1e-12);
  EXPECT_LT(dL, 1e-12);
  EXPECT_EQ(one.broken, two.broken);
  EXPECT_TRUE(same_bits(one.u, two.u)) << "displacements differ between 1 and 2 threads";
  EXPECT_TRUE(same_bits(one.v, two.v)) << "velocities differ";
  EXPECT_TRUE(same_bits(one.dissipated_at, two.dissipated_at)) << "dissipated energy differs";
}

TEST(ElasticPlastic, EnergyLedgerClosesInElasticAndPlasticImpacts) {
  // 2 m/s: about 80 MPa, below yield: no plastic work, the stored energy is elastic.
  const ImpactRun elastic = run_impact_ledger(impact_deck(kSteel + "}", 2, 6e-6));
  report("ep_ledger_elastic", elastic.max_balance_error,
         fmt::format("elastic-plastic, elastic impact (2 m/s, {} steps): max |balance error| = {:.2e}, dissipated "
                     "{:.1e} J", elastic.steps, elastic.max_balance_error, elastic.ledger.dissipated));
  EXPECT_EQ(elastic.ledger.dissipated, 0.0);
  EXPECT_GT(elastic.ledger.strain, 0.05 * elastic.ledger.initial);
  EXPECT_LT(elastic.max_balance_error, 0.01);
  // 20 m/s: plastic; the plastic work goes to the dissipated energy and the ledger closes.
  const ImpactRun plastic = run_impact_ledger(impact_deck(kSteel + "}", 20, 6e-6));
  report("ep_ledger_plastic", plastic.max_balance_error,
         fmt::format("elastic-plastic, plastic impact (20 m/s, {} steps): plastic work {:.1f} % of the initial "
                     "energy, max |balance error| = {:.2e}", plastic.steps,
                     100 * plastic.ledger.dissipated / plastic.ledger.initial, plastic.max_balance_error));
  EXPECT_GT(plastic.ledger.dissipated, 0.02 * plastic.ledger.initial);
  EXPECT_LT(plastic.max_balance_error, 0.01);
  // 40 m/s with bonds breaking at 0.6 %: plastic bonds break, and the ledger books what
  // they held beyond (1/2) t e (material/models/history_ledger.hpp).
  const ImpactRun broken = run_impact_ledger(impact_deck(kSteel + ", damage: {critical_stretch: 0.006}}", 40, 3e-6));
  report("ep_ledger_breaking", broken.max_balance_error,
         fmt::format("elastic-plastic, impact with breaking (40 m/s, {} steps): dissipated {:.1f} % of the initial "
                     "energy, max |balance error| = {:.2e}", broken.steps,
                     100 * broken.ledger.dissipated / broken.ledger.initial, broken.max_balance_error));
  EXPECT_LT(broken.max_balance_error, 0.01);
}

// Breaking a bond in the state-based model changes the stored energy W of the bonds that
// remain: theta = (3/m) sum omega |xi| e V_j loses the bond's term (m is not updated), so
// a bond that breaks in tension at a particle in compression (theta < 0) makes theta more
// negative and k' theta^2/2 larger. Elastic bonds at the critical stretch hold more
// deviatoric energy than that (the release stays positive); bonds that reached it by
// plastic flow hold little (the deviatoric force is capped by the yield), and the model
// then gains energy: kinetic + stored ends above the initial energy with no external work,
// so the dissipated energy that closes the ledger is negative (docs/models/elastic_plastic.md
// "Energy, damage"; not a booking error: W >= 0, and the ledger's D is work - dW).
TEST(ElasticPlastic, BreakingUnderCompressionCanReleaseNegativeEnergyAndTheLedgerStillCloses) {
  auto run = [](const std::string& material, std::vector<double>& dissipated) {
    test::SingleThread one;
    Simulation sim(parse_deck(impact_deck(material, 100, 3e-6), "impact.yaml"));
    double max_error = 0;
    while (sim.solver->time() < sim.config.solver.end_time * (1 - 1e-12)) {
      sim.solver->step(true);
      max_error = std::max(max_error, std::abs(sim.solver->ledger().balance_error()));
      dissipated.push_back(sim.solver->ledger().dissipated);
    }
    return std::pair{sim.solver->ledger(), max_error};
  };
  // Plasticity off (the LPS's forces): every step's dissipation is >= 0.
  std::vector<double> d_elastic;
  const auto [elastic, elastic_error] =
      run(kSteel + ", plasticity: off, damage: {critical_stretch: 0.006}}", d_elastic);
  double worst_step = 0;
  for (std::size_t n = 1; n < d_elastic.size(); ++n) worst_step = std::min(worst_step, d_elastic[n] - d_elastic[n - 1]);
  // Plastic, bonds breaking at 1 %: the model gains energy, the ledger still closes.
  std::vector<double> d_plastic;
  const auto [plastic, plastic_error] = run(kSteel + ", damage: {critical_stretch: 0.01}}", d_plastic);
  const double gained = (plastic.kinetic + plastic.strain - plastic.initial) / plastic.initial;
  report("ep_negative_dissipation", plastic.dissipated / plastic.initial,
         fmt::format("elastic-plastic impact at 100 m/s, s0 = 1 %: kinetic + stored {:+.1f} % above the initial "
                     "energy, dissipated {:+.3f} J of {:.3f} J, max |balance error| {:.1e}; plasticity off, s0 = "
                     "0.6 %: dissipated {:+.3f} J, worst step {:+.1e} J, max |balance error| {:.1e}",
                     100 * gained, plastic.dissipated, plastic.initial, plastic_error, elastic.dissipated,
                     worst_step, elastic_error));
  EXPECT_GT(elastic.dissipated, 0.05 * elastic.initial);
  EXPECT_GE(worst_step, -1e-9 * elastic.initial);
  EXPECT_LT(elastic_error, 0.01);
  EXPECT_GT(gained, 0.03) << "if the model no longer gains energy when plastic bonds break, update "
                             "docs/models/elastic_plastic.md (Energy, damage)";
  EXPECT_LT(plastic.dissipated, 0.0);
  EXPECT_LT(plastic_error, 0.01);
}

TEST(ElasticPlastic, StaticNewtonMatchesAdrAndTheLpsBelowYield) {
  const std::string ep = kSteel + "}";
  const std::string lps = "{model: lps, density: 7850, youngs_modulus: 200.0e9, poissons_ratio: 0.3}";
  const double traction = 50e6;  // well below yield
  std::string failure;
  const auto newton = solve_static(
      static_block_deck(ep, traction, "{type: static, method: newton, tangent: finite_difference, tolerance: 1.0e-10}"),
      &failure);
  ASSERT_FALSE(newton.empty()) << failure;
  const auto adr = solve_static(static_block_deck(ep, traction, "{type: static, method: adr, tolerance: 1.0e-9}"), &failure);
  ASSERT_FALSE(adr.empty()) << failure;
  const auto reference = solve_static(static_block_deck(lps, traction, "{type: static, method: newton, tolerance: 1.0e-10}"));
  ASSERT_FALSE(reference.empty());
  const double d_adr = max_difference(adr, newton), d_lps = max_difference(newton, reference);
  report("ep_static", d_adr,
         fmt::format("elastic-plastic block below yield, static: max |u_Newton(FD) - u_ADR|/max|u| = {:.1e}, "
                     "against the LPS {:.1e}", d_adr, d_lps));
  EXPECT_LT(d_adr, 1e-5);
  EXPECT_LT(d_lps, 1e-7);
}

}  // namespace
}  // namespace horizon::verification
