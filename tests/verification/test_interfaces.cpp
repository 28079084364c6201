// Interfaces between materials (seed 002 sec. 2.4, eq. 30-31). A bond between materials m
// and n takes the mean spring constant (c_m + c_n)/2: in the unified bond form
// (state/system.hpp) its pair coefficient is omega (R_i + R_j) with R = c/2 per end. Its
// critical stretch is min(s0_m, s0_n): the force loops break a bond when its stretch
// exceeds the smaller of its ends' values. Checked here:
// - the pair coefficients of a bimaterial family are those rules, read from the system;
// - a pulse crossing the interface of a bimaterial 1-D bar (impedance ratio 2) transmits
//   the energy fraction 4 Z_1 Z_2/(Z_1 + Z_2)^2 and the peak velocity 2 Z_1/(Z_1 + Z_2)
//   of the classical impedance formulas (e.g. Graff, Wave Motion in Elastic Solids,
//   sec. 1.6) within 3 %, and the momentum 2 Z_2/(Z_1 + Z_2) (its zero-frequency limit).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <fmt/format.h>

#include "../single_thread.hpp"
#include "verification_support.hpp"

namespace horizon::verification {
namespace {

// A: E = 50 GPa; B: E = 200 GPa; both rho = 2500: c_B = 2 c_A, Z_B = 2 Z_A.
const char* kBar = R"deck(
dimension: 1
area: 1.0e-4
spacing: 5.0e-4
horizon: 1.5e-3
partial_volume: true
materials:
  soft:  {model: pmb, density: 2500, youngs_modulus: 50.0e9, damage: {critical_stretch: 0.02}}
  stiff: {model: pmb, density: 2500, youngs_modulus: 200.0e9, damage: {critical_stretch: 0.01}}
bodies:
  - {name: a, material: soft,  shape: {box: {min: [0], max: [0.2]}}}
  - {name: b, material: stiff, shape: {box: {min: [0.2], max: [0.6]}}}
initial_conditions:
  - {velocity: ["exp(-((x-0.1)/0.01)^2)"]}
solver: {end_time: 4.5e-5}
)deck";

TEST(Interfaces, BondsBetweenMaterialsTakeTheMeanSpringAndTheSmallerCriticalStretch) {
  Config config = parse_deck(kBar, "bimaterial.yaml");
  const System s = build_system(config);
  const auto& P = s.particles;
  const auto& M = s.model;
  const double cA = 2 * M.pair_coef[0];  // R = c/2
  std::size_t cross = 0;
  for (std::size_t i = 0; i < P.size(); ++i) {
    for (uint64_t k = s.bonds.begin(i); k < s.bonds.end(i); ++k) {
      const uint32_t j = s.bonds.nbr[k];
      if (P.material[i] == P.material[j]) continue;
      ++cross;
      const double c_pair = M.pair_coef[i] + M.pair_coef[j];
      EXPECT_NEAR(c_pair / (0.5 * (cA + 4 * cA)), 1.0, 1e-14);  // (c_m + c_n)/2, c_stiff = 4 c_soft
      EXPECT_EQ(std::min(M.critical_stretch[i], M.critical_stretch[j]), 0.01);
    }
  }
  EXPECT_EQ(cross, 2u * 6u);  // 1-D, horizon 3 spacings: 1 + 2 + 3 pairs cross, each stored twice
}

TEST(Interfaces, PulseCrossesABimaterialBarWithTheImpedanceTransmission) {
  test::SingleThread one;
  Simulation sim(parse_deck(kBar, "bimaterial.yaml"));
  const auto& P = sim.system.particles;
  auto momentum = [&](int block) {
    double p = 0;
    for (std::size_t i = 0; i < P.size(); ++i)
      if (P.block[i] == block) p += P.density[i] * P.volume[i] * P.v[i].x;
    return p;
  };
  auto energy = [&](int block) {  // kinetic + strain (particles.energy is current after step(true))
    double e = 0;
    for (std::size_t i = 0; i < P.size(); ++i)
      if (P.block[i] == block) e += 0.5 * P.density[i] * P.volume[i] * norm2(P.v[i]) + P.energy[i] * P.volume[i];
    return e;
  };
  double peak_incident = 0, peak_transmitted = 0;
  auto peaks = [&] {
    for (std::size_t i = 0; i < P.size(); ++i) {
      if (P.block[i] == 0 && P.X[i].x > 0.15 && P.X[i].x < 0.16) peak_incident = std::max(peak_incident, P.v[i].x);
      if (P.block[i] == 1 && P.X[i].x > 0.3 && P.X[i].x < 0.31) peak_transmitted = std::max(peak_transmitted, P.v[i].x);
    }
  };
  const double p0 = momentum(0), e0 = energy(0);  // all in A at t = 0, kinetic; half of it runs right
  // The right-running half reaches the interface (x = 0.2 m) from about 19 to 26 us at
  // c_A = 4472 m/s; its transmitted part reaches B's far end at 60 us, the left-running
  // half (reflected at x = 0) the interface at 60 us. Measured at 45 us.
  sim.run_to(sim.config.solver.end_time, peaks);
  sim.solver->step(true);
  const double zA = std::sqrt(2500 * 50e9), zB = std::sqrt(2500 * 200e9);
  // Energy: T_E = 4 Z_A Z_B/(Z_A + Z_B)^2 (all the pulse's frequencies; the interface is
  // a horizon wide, so this is where a wrong interface stiffness would show).
  const double t_energy = energy(1) / (0.5 * e0), e_expected = 4 * zA * zB / ((zA + zB) * (zA + zB));
  // Peak velocity: T_v = 2 Z_A/(Z_A + Z_B) (the incident peak is half the initial one).
  const double t_velocity = peak_transmitted / peak_incident, v_expected = 2 * zA / (zA + zB);
  // Momentum (the zero-frequency limit): 2 Z_B/(Z_A + Z_B), exact for any interface.
  const double t_momentum = momentum(1) / (0.5 * p0), p_expected = 2 * zB / (zA + zB);
  report("interface_transmission_energy", t_energy / e_expected - 1,
         fmt::format("bimaterial 1-D PMB bar, Z_B/Z_A = 2: transmitted energy fraction {:.4f} against "
                     "4 Z_A Z_B/(Z_A + Z_B)^2 = {:.4f} ({:+.2f} %)",
                     t_energy, e_expected, 100 * (t_energy / e_expected - 1)));
  report("interface_transmission_velocity", t_velocity / v_expected - 1,
         fmt::format("peak particle velocity transmitted/incident {:.4f} against 2 Z_A/(Z_A + Z_B) = {:.4f} ({:+.2f} %)",
                     t_velocity, v_expected, 100 * (t_velocity / v_expected - 1)));
  report("interface_transmission_momentum", t_momentum / p_expected - 1,
         fmt::format("transmitted momentum fraction {:.6f} against 2 Z_B/(Z_A + Z_B) = {:.6f} ({:+.1e})", t_momentum,
                     p_expected, t_momentum / p_expected - 1));
  EXPECT_NEAR(t_energy / e_expected, 1.0, 0.03);
  EXPECT_NEAR(t_velocity / v_expected, 1.0, 0.03);
  EXPECT_NEAR(t_momentum / p_expected, 1.0, 1e-6);
  EXPECT_NEAR((momentum(0) + momentum(1)) / p0, 1.0, 1e-10);
}

}  // namespace
}  // namespace horizon::verification
