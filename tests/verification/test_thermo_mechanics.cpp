// Thermal expansion in the bond stretch and the dilatation (solver/forces_general.cpp,
// docs/models/heat.md "Thermal expansion"): a free block heated uniformly comes to rest at
// the strain alpha dT (plane stress, 3-D) or (1 + nu) alpha dT (plane strain) with no
// mechanical stretch in its interior bonds; runs without thermal strain keep the fast loops.
#include <string>

#include "horizon/driver/run.hpp"
#include "horizon/solver/forces.hpp"
#include "horizon/thermal/heat.hpp"
#include "verification_support.hpp"

namespace horizon::verification {
namespace {

std::string block_deck(const std::string& model, const std::string& plane, double alpha) {
  return R"DECK(
dimension: 2
plane: )DECK" + plane + R"DECK(
thickness: 0.001
spacing: 0.0005
horizon_factor: 3
partial_volume: linear
materials:
  ceramic:
    model: )DECK" + model + R"DECK(
    density: 3900
    youngs_modulus: 370e9
)DECK" + (model == "pmb" ? "" : "    poissons_ratio: 0.22\n") +
         (model == "elastic_plastic" ? "    yield_stress: 1.0e9\n" : "") +
         (model == "viscoelastic" ? "    lambda_1: 0.5\n    tau_1: 1.0e-6\n" : "") +
         R"DECK(    thermal: {conductivity: 30, specific_heat: 880, expansion: )DECK" + std::to_string(alpha) +
         R"DECK(, reference_temperature: 293}
bodies:
  - {name: block, material: ceramic, shape: {box: {min: [0, 0], max: [0.01, 0.01]}}}
thermal:
  initial_temperature: 393
solver: {end_time: 2.0e-5, damping: 1.5e6}
)DECK";
}

struct Expansion {
  double strain_xx = 0, strain_yy = 0, shear = 0;
  double max_interior_stretch = 0;  // largest |mechanical stretch| of a bond between interior particles
  double nu = 0;
};

// Runs the heated block to rest (damped explicit dynamics, the temperature uniform and
// steady) and measures the interior's displacement gradient and mechanical stretches.
Expansion expand(const std::string& model, const std::string& plane, double alpha) {
  Config c = parse_deck(block_deck(model, plane, alpha), "block.yaml");
  System s = build_system(c);
  Loads loads(c, s);
  const double dt = 0.8 * stable_time_step(s);
  ExplicitSolver solver(s, loads, dt, c.solver.damping);
  solver.initialize();
  while (solver.time() < c.solver.end_time) solver.step(false);
  const auto& P = s.particles;
  std::vector<std::size_t> interior;
  std::vector<uint8_t> inside(P.size(), 0);
  for (std::size_t i = 0; i < P.size(); ++i) {
    const double x = P.X[i].x, y = P.X[i].y, d = c.horizon;
    if (x > d && x < 0.01 - d && y > d && y < 0.01 - d) interior.push_back(i), inside[i] = 1;
  }
  Expansion r;
  const Eigen::Matrix3d G = displacement_gradient(P, interior);
  r.strain_xx = G(0, 0);
  r.strain_yy = G(1, 1);
  r.shear = 0.5 * (G(0, 1) + G(1, 0));
  for (std::size_t i : interior)
    for (uint64_t k = s.bonds.begin(i); k < s.bonds.end(i); ++k) {
      const uint32_t j = s.bonds.nbr[k];
      if (!inside[j]) continue;
      const double L = s.bonds.length[k];
      const double stretch = (norm(P.X[j] + P.u[j] - P.X[i] - P.u[i]) - L) / L;
      const double mech = stretch - 0.5 * (s.thermal_strain[i] + s.thermal_strain[j]);
      r.max_interior_stretch = std::max(r.max_interior_stretch, std::abs(mech));
    }
  r.nu = c.materials[0].poissons_ratio;
  return r;
}

TEST(ThermoMechanics, FreeBlockExpandsWithoutStress) {
  const double alpha = 8e-6, dT = 100;
  for (const std::string model : {"pmb", "lps"}) {
    const Expansion e = expand(model, "stress", alpha);
    const double target = alpha * dT;
    std::printf("[ figure ] %s plane stress: strain_xx / (alpha dT) = %.5f, strain_yy / (alpha dT) = %.5f, "
                "interior mechanical stretch <= %.2e (alpha dT = %.1e)\n",
                model.c_str(), e.strain_xx / target, e.strain_yy / target, e.max_interior_stretch, target);
    EXPECT_NEAR(e.strain_xx / target, 1, 0.01) << model;
    EXPECT_NEAR(e.strain_yy / target, 1, 0.01) << model;
    EXPECT_LT(std::abs(e.shear), 0.01 * target) << model;
    EXPECT_LT(e.max_interior_stretch, 0.01 * target) << model;  // no stress in the interior
  }
  // The state-based models with their own force states take the thermal strain too
  // (elastic: the yield stress is far above; the viscous branch relaxes to rest). Plane
  // strain (elastic_plastic refuses plane stress): (1 + nu) alpha dT in the plane.
  for (const std::string model : {"elastic_plastic", "viscoelastic"}) {
    const Expansion e = expand(model, "strain", alpha);
    const double target = (1 + e.nu) * alpha * dT;
    std::printf("[ figure ] %s plane strain: strain_xx / ((1 + nu) alpha dT) = %.5f, interior mechanical stretch <= "
                "%.2e\n",
                model.c_str(), e.strain_xx / target, e.max_interior_stretch);
    EXPECT_NEAR(e.strain_xx / target, 1, 0.01) << model;
    EXPECT_NEAR(e.strain_yy / target, 1, 0.01) << model;
    EXPECT_LT(e.max_interior_stretch, 0.01 * target) << model;
  }
  // Plane strain: (1 + nu) alpha dT in the plane.
  const Expansion e = expand("lps", "strain", alpha);
  const double target = (1 + e.nu) * alpha * dT;
  std::printf("[ figure ] lps plane strain: strain_xx / ((1 + nu) alpha dT) = %.5f\n", e.strain_xx / target);
  EXPECT_NEAR(e.strain_xx / target, 1, 0.01);
  EXPECT_NEAR(e.strain_yy / target, 1, 0.01);
}

TEST(ThermoMechanics, FastLoopsUnlessATemperatureStrains) {
  // Without expansion the thermal run keeps the fast loops (no thermal strain); with it,
  // at the reference temperature, the general pass gives the fast loops' forces.
  Config c = parse_deck(block_deck("lps", "stress", 0.0), "block.yaml");
  System s = build_system(c);
  EXPECT_TRUE(s.heat.active());
  EXPECT_TRUE(s.thermal_strain.empty());

  Config c2 = parse_deck(block_deck("lps", "stress", 8e-6), "block.yaml");
  System fast = build_system(c2);
  ASSERT_FALSE(fast.thermal_strain.empty());
  for (std::size_t i = 0; i < fast.particles.size(); ++i) {
    const Vec3& X = fast.particles.X[i];
    fast.particles.u[i] = {1e-4 * X.x * X.x + 2e-6 * X.y, 3e-6 * X.x - 5e-5 * X.y * X.y, 0};
  }
  System thermal = fast;
  thermal.heat.T.assign(thermal.heat.T.size(), 293.0);  // the reference temperature: no thermal strain
  update_thermal_strain(thermal);
  fast.thermal_strain.clear();
  compute_forces(fast, true);
  compute_forces(thermal, true);
  double fmax = 0, diff = 0;
  for (std::size_t i = 0; i < fast.particles.size(); ++i) {
    fmax = std::max(fmax, norm(fast.particles.f[i]));
    diff = std::max(diff, norm(fast.particles.f[i] - thermal.particles.f[i]));
  }
  EXPECT_GT(fmax, 0);
  EXPECT_LT(diff, 1e-9 * fmax);
}

}  // namespace
}  // namespace horizon::verification

namespace horizon::verification {
namespace {

// Heating from plastic work (one-way: thermal/heat.hpp commit_history_with_heat): a 2-D
// elastic-plastic strip pulled past yield, insulated and without conduction losses to
// the outside, holds beta times the plastic work the model dissipated as heat.
TEST(ThermoMechanics, PlasticWorkHeatsTheBody) {
  Config c = parse_deck(R"DECK(
dimension: 2
plane: strain
thickness: 0.001
spacing: 0.0005
horizon_factor: 3
materials:
  steel:
    model: elastic_plastic
    density: 7850
    youngs_modulus: 200.0e9
    poissons_ratio: 0.3
    yield_stress: 250.0e6
    thermal: {conductivity: 45, specific_heat: 460, plastic_heat_fraction: 0.9}
bodies:
  - {name: strip, material: steel, shape: {box: {min: [0, 0], max: [0.01, 0.004]}}}
regions:
  left:  {box: {min: [0, 0], max: [0.0006, 0.004]}}
  right: {box: {min: [0.0094, 0], max: [0.01, 0.004]}}
thermal:
  initial_temperature: 293
loads:
  - {region: left,  velocity: [-5, null]}
  - {region: right, velocity: [5, null]}
solver: {end_time: 2.0e-5}
)DECK",
                        "plastic_heat.yaml");
  System s = build_system(c);
  Loads loads(c, s);
  ExplicitSolver solver(s, loads, 0.8 * stable_time_step(s), 0);
  solver.initialize();
  const double q0 = heat_content(s);
  HeatSolver heat(s, HeatIntegration::explicit_euler);
  while (solver.time() < c.solver.end_time) {
    solver.step(false);
    heat.step(solver.dt());
  }
  const double dissipated = s.dissipated();  // no bond breaks: all of it plastic work
  std::printf("[ figure ] plastic work %.4e J, heat %.4e J, content change %.4e J, max temperature rise %.3f K\n",
              dissipated, s.heat.plastic_heat, heat_content(s) - q0,
              *std::max_element(s.heat.T.begin(), s.heat.T.end()) - 293);
  EXPECT_GT(dissipated, 0);
  EXPECT_NEAR(s.heat.plastic_heat / (0.9 * dissipated), 1, 1e-12);
  EXPECT_NEAR((heat_content(s) - q0) / s.heat.plastic_heat, 1, 1e-9);  // conduction conserves it
}

// Temperature-dependent critical stretch: s0(T) = s0 max(0, 1 + slope (T - T_ref)). A
// PMB block stretched uniformly to 0.7 s0 keeps every bond at T_ref and at T_ref + 250 K
// (s0 x 0.75), and loses every bond at T_ref + 500 K with slope -1e-3/K (s0 halved).
TEST(ThermoMechanics, CriticalStretchFallsWithTemperature) {
  auto broken_at = [](double T) {
    Config c = parse_deck(R"DECK(
dimension: 2
plane: stress
thickness: 0.001
spacing: 0.0005
horizon_factor: 3
materials:
  ceramic:
    model: pmb
    density: 3900
    youngs_modulus: 370e9
    damage: {critical_stretch: 1.0e-3}
    thermal: {conductivity: 30, specific_heat: 880, reference_temperature: 293, critical_stretch_slope: -1.0e-3}
bodies:
  - {name: block, material: ceramic, shape: {box: {min: [0, 0], max: [0.005, 0.005]}}}
thermal:
  initial_temperature: )DECK" + std::to_string(T) + R"DECK(
solver: {end_time: 1.0e-6}
)DECK",
                          "soft.yaml");
    System s = build_system(c);
    EXPECT_TRUE(s.thermal_strain.empty());
    EXPECT_FALSE(s.critical_stretch_factor.empty());
    for (std::size_t i = 0; i < s.particles.size(); ++i) s.particles.u[i] = s.particles.X[i] * 0.7e-3;
    compute_forces(s, false);
    return static_cast<double>(s.broken) / static_cast<double>(s.bonds.size());
  };
  const double cold = broken_at(293), hot = broken_at(793), warm = broken_at(293 + 250);
  std::printf("[ figure ] broken bond fraction at 0.7 s0: T_ref %.3f, T_ref + 250 K %.3f, T_ref + 500 K %.3f\n", cold,
              warm, hot);
  EXPECT_EQ(cold, 0);
  EXPECT_EQ(warm, 0);  // s0 x 0.75 > 0.7 s0
  EXPECT_EQ(hot, 1);   // s0 x 0.5 < 0.7 s0
}

TEST(ThermoMechanics, ExpansionRefusedForModelsThatDoNotTakeIt) {
  const std::string deck = R"DECK(
dimension: 2
plane: strain
thickness: 0.001
spacing: 0.0005
horizon_factor: 3
materials:
  steel:
    model: nonlinear_solid
    density: 7850
    youngs_modulus: 200.0e9
    poissons_ratio: 0.3
    thermal: {conductivity: 45, specific_heat: 460, expansion: 1.2e-5, reference_temperature: 293}
bodies:
  - {name: strip, material: steel, shape: {box: {min: [0, 0], max: [0.004, 0.004]}}}
thermal:
  initial_temperature: 293
solver: {end_time: 1.0e-6}
)DECK";
  const Config c = parse_deck(deck, "refused.yaml");
  try {
    build_system(c);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("thermal expansion acts on models pmb, lps"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("material 'steel' (model nonlinear_solid)"), std::string::npos) << e.what();
  }
}

// A coupled thermal deck splits over MPI ranks with either heat integration
// (tests/mpi/projectile_heat.cmake runs both on 1 to 4 ranks): the backward-Euler step is a
// distributed conjugate gradient (thermal/heat.cpp).
TEST(ThermoMechanics, HeatSplitsOverRanksWithEitherIntegration) {
  Config c = parse_deck(block_deck("pmb", "stress", 7.5e-6), "ranks.yaml");
  EXPECT_EQ(distributed_limits(c, build_system(c), RunOptions{}), "");
  c.thermal.integration = HeatIntegration::implicit_euler;
  EXPECT_EQ(distributed_limits(c, build_system(c), RunOptions{}), "");
}

}  // namespace
}  // namespace horizon::verification
