// Classical finite-element regions and their coupling to peridynamic bodies
// (fe/fe_region.hpp; seed 002 digest sec. 7). Checked here:
// - patch test: a uniform strain (any constant symmetric gradient) in a cube of
//   elements around a peridynamic core gives zero force on every degree of freedom
//   that is not on the cube's outer faces: the PD particles (whose families reach the
//   FE nodes), the FE nodes next to the core, everywhere, to round-off (hex8, tet4);
// - a pure-FE bar carries a longitudinal pulse at the bar speed sqrt(E/rho);
// - a pulse crossing from the FE part of a bar into its PD part: the reflected energy
//   is small (measured), the transmitted pulse arrives, and the energy ledger (the
//   FE-owned share of element energy and the particles' bond energy, kinetic energy of
//   both) closes to a stated tolerance;
// - deck errors for the fe keys.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <string>

#include <fmt/format.h>

#include "../single_thread.hpp"
#include "horizon/fe/fe_region.hpp"
#include "horizon/solver/forces.hpp"
#include "verification_support.hpp"
#include "../test_paths.hpp"

namespace horizon::verification {
namespace {

std::string cube_deck(const char* element) {
  return fmt::format(R"deck(
dimension: 3
spacing: 1.0e-3
horizon: 3.0e-3
materials:
  al: {{model: pmb, density: 2700, youngs_modulus: 68.9e9}}
bodies:
  - {{name: core, material: al, shape: {{box: {{min: [4.0e-3, 4.0e-3, 4.0e-3], max: [10.0e-3, 10.0e-3, 10.0e-3]}}}}}}
  - {{name: outer, material: al, discretization: fe, element: {}, shape: {{box: {{min: [0, 0, 0], max: [14.0e-3, 14.0e-3, 14.0e-3]}}}}}}
solver: {{end_time: 1.0e-6}}
)deck",
                     element);
}

void patch_test(const char* element) {
  test::SingleThread one;
  Config config = parse_deck(cube_deck(element), "patch.yaml");
  System s = build_system(config);
  ASSERT_TRUE(s.fe);
  const FeRegion& fe = *s.fe;
  auto& P = s.particles;
  // A constant symmetric displacement gradient (stretch, contraction and shear).
  const double G[3][3] = {{1.0e-4, 2.0e-5, -1.0e-5}, {2.0e-5, -3.0e-5, 1.5e-5}, {-1.0e-5, 1.5e-5, 5.0e-5}};
  auto field = [&](const Vec3& x) {
    Vec3 u;
    for (int i = 0; i < 3; ++i) u[i] = G[i][0] * x.x + G[i][1] * x.y + G[i][2] * x.z;
    return u;
  };
  for (std::size_t i = 0; i < P.size(); ++i) P.u[i] = field(P.X[i]);
  // The outer two node layers carry the load of the cube's faces (the outermost cells'
  // volume is scaled to reach the faces, fe_region.hpp): left out of the check.
  std::vector<uint8_t> on_face(P.size(), 0);
  for (std::size_t i = 0; i < P.size(); ++i)
    for (int k = 0; k < 3; ++k)
      if (P.X[i][k] < 2.0e-3 || P.X[i][k] > 12.0e-3) on_face[i] = 1;
  compute_forces(s, true);
  // Scale: the nodal force of the uniform stress on one cell face, E |G| h^2.
  const double scale = 68.9e9 * 1.0e-4 * 1.0e-6;
  double worst_pd = 0, worst_fe = 0, worst_face_free = 0;
  std::size_t pd = 0, fe_owned = 0;
  for (std::size_t i = 0; i < P.size(); ++i) {
    if (on_face[i]) continue;
    const double f = norm(P.f[i]) * P.volume[i] / scale;
    if (fe.owned_particle[i]) {
      worst_fe = std::max(worst_fe, f);
      ++fe_owned;
    } else {
      worst_pd = std::max(worst_pd, f);
      ++pd;
    }
  }
  // For contrast: the same core alone (no FE around it) has surface forces.
  Config alone = config;
  alone.bodies.pop_back();
  System a = build_system(alone);
  for (std::size_t i = 0; i < a.particles.size(); ++i) a.particles.u[i] = field(a.particles.X[i]);
  compute_forces(a, true);
  for (std::size_t i = 0; i < a.particles.size(); ++i)
    worst_face_free = std::max(worst_face_free, norm(a.particles.f[i]) * a.particles.volume[i] / scale);
  report(fmt::format("fe_patch_{}", element), std::max(worst_pd, worst_fe),
         fmt::format("patch test, {} cube around a PD core ({} particles, {} FE-owned inner nodes, {} elements): "
                     "largest force / (E |grad u| h^2): particles {:.1e}, FE nodes {:.1e} (the core alone: {:.2f})",
                     element, pd, fe_owned, fe.elements(), worst_pd, worst_fe, worst_face_free));
  EXPECT_EQ(pd, 216u);
  EXPECT_LT(worst_pd, 1e-9);
  EXPECT_LT(worst_fe, 1e-9);
  EXPECT_GT(worst_face_free, 0.1);  // the check can fail: without the FE the core's surface is loaded
}

TEST(FiniteElements, PatchTestAcrossTheCouplingHex8) { patch_test("hex8"); }
TEST(FiniteElements, PatchTestAcrossTheCouplingTet4) { patch_test("tet4"); }

// A bar 160 x 4 x 4 spacings along x; `pd_from`: where its PD part starts (>= 160: none).
std::string bar_deck(double pd_from_mm, bool corrected = false) {
  std::string bodies;
  if (pd_from_mm < 160)
    bodies += fmt::format(
        "  - {{name: pd, material: al, shape: {{box: {{min: [{}e-3, 0, 0], max: [160.0e-3, 4.0e-3, 4.0e-3]}}}}}}\n",
        pd_from_mm);
  if (pd_from_mm > 0)
    bodies += "  - {name: fe, material: al, discretization: fe, shape: {box: {min: [0, 0, 0], max: [160.0e-3, 4.0e-3, "
            "4.0e-3]}}}\n";
  return R"deck(
dimension: 3
spacing: 1.0e-3
horizon: 3.0e-3
materials:
  al: {model: pmb, density: 2700, youngs_modulus: 68.9e9)deck" +
         std::string(corrected ? ", surface_correction: true" : "") + R"deck(}
bodies:
)deck" + bodies +
         R"deck(
initial_conditions:
  - {displacement: ["1.0e-6*exp(-((x-0.04)/0.005)^2)", 0, 0],
     velocity: ["5052*1.0e-6*2*(x-0.04)/0.005^2*exp(-((x-0.04)/0.005)^2)", 0, 0]}
solver: {end_time: 2.0e-5, safety_factor: 0.8}
)deck";
}

struct PulseRun {
  std::vector<Vec3> X, u, v;
  std::vector<double> mass, energy;  // per particle: rho V, W V
  double speed = 0;                  // of the pulse's peak from 40 to 110.5 mm
  double max_balance_error = 0;
  double initial_energy = 0;
  // With FE: the ledger's balance as it was before it booked the coupling work
  // (fe/fe_region.hpp): the energy the force-based coupling does not conserve, largest
  // |.|; and the coupling work's largest |.| over the initial energy. max_balance_error
  // is the ledger's balance, the coupling work booked (Ledger::balance_error).
  double max_balance_without_coupling = 0, max_coupling_work = 0;
};

PulseRun run_pulse(double pd_from_mm, bool corrected = false) {
  test::SingleThread one;
  Simulation sim(parse_deck(bar_deck(pd_from_mm, corrected), "bar.yaml"));
  const auto& P = sim.system.particles;
  PulseRun r;
  r.initial_energy = sim.solver->ledger().initial;
  double vpeak = 0, tpeak = 0;
  const std::size_t probe = sim.nearest({110.5e-3, 1.5e-3, 1.5e-3});
  while (sim.solver->time() < 2.0e-5) {
    sim.solver->step(true);
    const Ledger& g = sim.solver->ledger();
    r.max_balance_error = std::max(r.max_balance_error, std::abs(g.balance_error()));
    if (sim.system.fe) {
      // Ledger::balance_error (solver/explicit.cpp) without the coupling work.
      const double scale = std::max({std::abs(g.initial), std::abs(g.external_work), std::abs(g.thermal_work),
                                     g.kinetic + g.strain + g.dissipated + g.damped, 1e-300});
      const double without =
          (g.kinetic + g.strain + g.dissipated + g.damped - g.initial - g.external_work - g.thermal_work) / scale;
      r.max_balance_without_coupling = std::max(r.max_balance_without_coupling, std::abs(without));
      r.max_coupling_work = std::max(r.max_coupling_work, std::abs(sim.system.fe->coupling_work) / g.initial);
    }
    if (P.v[probe].x > vpeak) vpeak = P.v[probe].x, tpeak = sim.solver->time();
  }
  r.speed = (110.5e-3 - 40.0e-3) / tpeak;
  r.X = P.X, r.u = P.u, r.v = P.v;
  for (std::size_t i = 0; i < P.size(); ++i) {
    r.mass.push_back(P.density[i] * P.volume[i]);
    r.energy.push_back(P.energy[i] * P.volume[i]);
  }
  return r;
}

// Energy of the wave the interface sent back: the coupled run minus the pure-FE run
// (identical left of the interface until the pulse reaches it; the problem is linear),
// twice the kinetic energy of the velocity difference left of x = 70 mm (a travelling
// wave carries as much strain as kinetic energy), over the initial energy.
double reflected_fraction(const PulseRun& coupled, const PulseRun& fe) {
  std::map<std::array<long, 3>, std::size_t> at;
  auto key = [](const Vec3& x) {
    return std::array<long, 3>{std::lround(x.x * 1e7), std::lround(x.y * 1e7), std::lround(x.z * 1e7)};
  };
  for (std::size_t i = 0; i < fe.X.size(); ++i) at[key(fe.X[i])] = i;
  double k = 0;
  for (std::size_t i = 0; i < coupled.X.size(); ++i) {
    if (coupled.X[i].x >= 70e-3) continue;
    const std::size_t j = at.at(key(coupled.X[i]));
    k += 0.5 * fe.mass[j] * norm2(coupled.v[i] - fe.v[j]);
  }
  return 2 * k / fe.initial_energy;
}

TEST(FiniteElements, PulseInAnFeBarTravelsAtTheBarSpeed) {
  const PulseRun fe = run_pulse(1e9);
  const double c0 = std::sqrt(68.9e9 / 2700);
  report("fe_bar_speed", fe.speed / c0 - 1,
         fmt::format("pure hex8 bar 160 x 4 x 4 elements: pulse speed {:.0f} m/s against sqrt(E/rho) = {:.0f} m/s "
                     "({:+.2f} %); max |energy balance error| {:.1e} (velocity Verlet's, conservative elements)",
                     fe.speed, c0, 100 * (fe.speed / c0 - 1), fe.max_balance_error));
  EXPECT_NEAR(fe.speed / c0, 1.0, 0.05);
  EXPECT_LT(fe.max_balance_error, 0.02);
}

TEST(FiniteElements, PulseCrossesFromFeIntoPdWithSmallReflection) {
  // The reference for the reflection: the same bar with a 5 mm PD end from 155 mm (the
  // pulse reaches it only at the end), so that it has the coupling's interface damping and
  // hence the coupled run's time step (the trailing dispersion of the FE pulse depends on
  // the step: against the pure FE bar at its own step the measure reads 6.6e-2).
  const PulseRun fe = run_pulse(1e9), pd = run_pulse(0), coupled = run_pulse(80), ref = run_pulse(155);
  const double reflected = reflected_fraction(coupled, ref);
  // The 1-D impedance estimate from the two bars' measured speeds (same density):
  // R = ((c_fe - c_pd)/(c_fe + c_pd))^2 (e.g. Graff, Wave Motion in Elastic Solids, sec. 1.6).
  const double r_imp = std::pow((fe.speed - pd.speed) / (fe.speed + pd.speed), 2);
  report("fe_pd_reflection", reflected,
         fmt::format("pulse from the hex8 half of a 160 x 4 x 4 bar into its PMB half (interface at 80 mm): reflected "
                     "energy {:.2e} of the incident; the 1-D impedance estimate from the bars' speeds (FE {:.0f}, PD "
                     "{:.0f} m/s) {:.2e}; transmitted peak speed {:.0f} m/s; max |energy balance error| {:.2f} (pure "
                     "FE {:.1e}, pure PD {:.1e})",
                     reflected, fe.speed, pd.speed, r_imp, coupled.speed, coupled.max_balance_without_coupling,
                     fe.max_balance_error, pd.max_balance_error));
  EXPECT_LT(reflected, 0.03);
  EXPECT_GT(coupled.speed, pd.speed * 0.97);
  // Force-based coupling is not conservative where the two models' stiffnesses differ
  // (this thin PD bar is 1.5 times softer than the elements): the measured figure, bounded.
  EXPECT_LT(coupled.max_balance_without_coupling, 0.5);
}

// The coupling's energy account (fe/fe_region.hpp, history.csv column fe_coupling_work):
// the work the force-based coupling puts in or takes out. Booked, it closes the coupled
// bar's ledger to velocity Verlet's error (the pure-FE bar's balance error), and it is
// nothing where no coupling acts (the pure-FE bar).
TEST(FiniteElements, CouplingWorkClosesTheLedger) {
  const PulseRun fe = run_pulse(1e9), coupled = run_pulse(80);
  report("fe_coupling_work", coupled.max_balance_error,
         fmt::format("FE-to-PD pulse: largest |coupling work| {:.3f} of the initial energy; largest |balance error| "
                     "{:.3f} without it, {:.1e} with it booked (pure FE bar: coupling work {:.1e}, balance {:.1e})",
                     coupled.max_coupling_work, coupled.max_balance_without_coupling, coupled.max_balance_error,
                     fe.max_coupling_work, fe.max_balance_error));
  EXPECT_GT(coupled.max_coupling_work, 0.1);  // the 0.29 the ledger would miss without it
  EXPECT_GT(coupled.max_balance_without_coupling, 0.1);
  EXPECT_LT(coupled.max_balance_error, 0.03);  // the ledger books it (Ledger::coupling_work)
  EXPECT_LT(fe.max_coupling_work, 1e-6);  // elements alone derive from their energy
}

// The same bar with the PMB surface correction: the thin PD bar's modulus comes to within
// a few per cent of E, and with the mismatch go the reflection and most of the energy the
// force-based coupling does not conserve (fe/fe_region.hpp).
TEST(FiniteElements, PulseIntoACorrectedPdBarReflectsLessAndLosesLessEnergy) {
  const PulseRun fe = run_pulse(1e9), pd = run_pulse(0, true), coupled = run_pulse(80, true),
                 ref = run_pulse(155, true);  // the reference at the coupled run's step (above)
  const double reflected = reflected_fraction(coupled, ref);
  report("fe_pd_reflection_corrected", reflected,
         fmt::format("the bar of the previous test with surface_correction: PD speed {:.0f} m/s (FE {:.0f}); reflected "
                     "energy {:.2e} of the incident; max |energy balance error| {:.3f} (pure PD {:.1e})",
                     pd.speed, fe.speed, reflected, coupled.max_balance_without_coupling, pd.max_balance_error));
  EXPECT_NEAR(pd.speed / fe.speed, 1.0, 0.03);   // measured -1.6 %
  EXPECT_LT(reflected, 1e-3);                    // measured 2.2e-4 (plain PD bar: 3.9e-3)
  EXPECT_LT(coupled.max_balance_without_coupling, 0.1);  // measured 0.075 (plain PD bar: 0.29)
}

TEST(FiniteElements, DeckErrorsNameTheKey) {
  auto fails_with = [](const std::string& text, const std::string& expected) {
    try {
      parse_deck(text, "bad.yaml");
      ADD_FAILURE() << "no error; expected " << expected;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  };
  const std::string head = R"deck(
dimension: 3
spacing: 1.0e-3
horizon: 3.0e-3
materials:
  al: {model: pmb, density: 2700, youngs_modulus: 68.9e9}
bodies:
)deck";
  fails_with(head + "  - {name: a, material: al, element: hex8, shape: {box: {min: [0,0,0], max: [4e-3,4e-3,4e-3]}}}\n"
                    "solver: {end_time: 1e-6}\n",
             "bad.yaml:8:29: error: bodies[0].element: applies to finite-element bodies only");
  fails_with(head + "  - {name: a, material: al, discretization: fem, shape: {box: {min: [0,0,0], max: [4e-3,4e-3,4e-3]}}}\n"
                    "solver: {end_time: 1e-6}\n",
             "peridynamic");
  fails_with(head + "  - {name: a, material: al, discretization: fe, shape: {sphere: {center: [0,0,0], radius: 4e-3}}}\n"
                    "solver: {end_time: 1e-6}\n",
             "a finite-element body's shape is a box");
  fails_with(head + "  - {name: a, material: al, discretization: fe, shape: {box: {min: [0,0,0], max: [4e-3,4e-3,4e-3]}}}\n"
                    "solver: {type: static, end_time: 1, load_steps: 1}\n",
             "finite-element bodies run with solver type explicit");
  fails_with(head + "  - {name: a, material: al, discretization: fe, element: tet4, hourglass: 0.1, shape: {box: {min: "
                    "[0,0,0], max: [4e-3,4e-3,4e-3]}}}\nsolver: {end_time: 1e-6}\n",
             "hourglass control applies to hex8 elements only");
}

}  // namespace
}  // namespace horizon::verification

namespace horizon::verification {
namespace {

// The centre-cracked plate of seed 002 sec. 9.1 (examples/center_cracked_plate*.yaml) at
// half resolution (spacing 4 mm, horizon 12 mm: 25 x 75 x 3 lattice points): the peak
// far-field stress (grip reaction / section) as pure PD and as PD core + hexahedra. The
// full-size figures (docs/verification.md) come from the examples.
struct PlateFigures {
  double peak_stress = 0;  // [Pa]
  double at = 0;           // [s]
  bool broken = false;     // the stress fell below half its peak before the end
  std::size_t particles = 0, bonds = 0, elements = 0;
};

PlateFigures cracked_plate(const std::string& example) {
  test::SingleThread one;
  Config config = load_deck((std::filesystem::path(HORIZON_SOURCE_DIR) / "examples" / example).string());
  RunOptions o;
  o.coarsen = 2;
  apply_run_options(config, o);
  // Without the examples' surface correction: at half resolution the plate is 3 lattice
  // layers thick, so every particle is a surface particle and the corrected bonds (s0
  // kept, docs/verification.md) break far above the handbook's stress (pure PD +116 %,
  // coupled -18 % from it, measured). The coupling is what this test checks.
  for (auto& m : config.materials) m.parameters["surface_correction"] = 0;
  Simulation sim(std::move(config));
  PlateFigures r;
  r.particles = sim.system.particles.size();
  r.bonds = sim.system.bonds.size();
  r.elements = sim.system.fe ? sim.system.fe->elements() : 0;
  const AppliedLoad* bottom = nullptr;
  for (const auto& L : sim.loads.loads())
    if (L.name.rfind("bottom", 0) == 0) bottom = &L;
  while (sim.solver->time() < sim.config.solver.end_time) {
    sim.solver->step(false);
    const double stress = -bottom->reaction.y / (0.100 * 0.010);
    if (stress > r.peak_stress) r.peak_stress = stress, r.at = sim.solver->time();
    if (stress < 0.5 * r.peak_stress) {  // broken through
      r.broken = true;
      break;
    }
  }
  return r;
}

TEST(FiniteElements, CentreCrackedPlatePureAndCoupledBreakAtTheSameStress) {
  const PlateFigures pd = cracked_plate("center_cracked_plate_pd.yaml");
  const PlateFigures fe = cracked_plate("center_cracked_plate.yaml");
  const double handbook = 72.2e6;  // K_IC / (sqrt(pi a) F(a/b)), seed 002 digest sec. 9.1
  report("ccp_half_pd", pd.peak_stress / handbook - 1,
         fmt::format("centre-cracked plate at half resolution, pure PD ({} particles, {} bonds): peak far-field stress "
                     "{:.1f} MPa at {:.2f} ms ({:+.1f} % from the handbook's 72.2 MPa)",
                     pd.particles, pd.bonds, pd.peak_stress / 1e6, pd.at * 1e3, 100 * (pd.peak_stress / handbook - 1)));
  report("ccp_half_coupled", fe.peak_stress / pd.peak_stress - 1,
         fmt::format("the same, PD core + hex8 ({} particles and nodes, {} bonds, {} elements): {:.1f} MPa at {:.2f} "
                     "ms ({:+.1f} % from pure PD)",
                     fe.particles, fe.bonds, fe.elements, fe.peak_stress / 1e6, fe.at * 1e3,
                     100 * (fe.peak_stress / pd.peak_stress - 1)));
  // At half resolution (horizon 12 mm against a 25 mm half crack, 3 lattice layers through
  // the thickness) the fracture stress is far above the handbook's (+57 %; the full-size
  // figures are in docs/verification.md): checked here are that both variants break and
  // that they break at the same stress (measured +2.6 %; tolerance 5 %).
  EXPECT_TRUE(pd.broken);
  EXPECT_TRUE(fe.broken);
  EXPECT_NEAR(fe.peak_stress / pd.peak_stress, 1.0, 0.05);
}

}  // namespace
}  // namespace horizon::verification
