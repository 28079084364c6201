// Check 1 (docs/verification.md): a long-wavelength pulse travels at the bar speed
// c0 = sqrt(E/rho), in a 1-D PMB bar and in a slender 3-D LPS bar, within 2 %.
//
// The pulse is a cosine bump of initial velocity, v(x, 0) = (1 + cos(pi (x - x0)/H))/2
// for |x - x0| < H, of full width (wavelength) 2H >= 20 horizons. By d'Alembert it splits
// into two halves of amplitude 1/2 that run at +-c. The speed is the distance between two
// stations over the difference of the times at which the leading edge of the right-running
// half reaches half its maximum there: measuring between two stations cancels the start-up
// (the initial pulse has no lateral motion yet), and the leading half-maximum is little
// affected by the short-wavelength tail that dispersion leaves behind.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "verification_support.hpp"

namespace horizon::verification {
namespace {

// Steel-like 1-D bar, 1 m long, spacing 1 mm, horizon 3 mm: c0 = sqrt(200e9/8000) = 5000 m/s.
// Partial volumes are on: with full volumes for the neighbours at exactly 3 spacings, the
// 1-D lattice sum is 4/3 of the integral that calibrates c (docs/models.md section 8), and
// the bar is 4/3 too stiff: the pulse runs at 5760 m/s, +15 % (measured).
// `initial_condition` is one entry of initial_conditions, e.g. {velocity: ["..."]}.
std::string bar_1d_deck(const std::string& initial_condition) {
  return fmt::format(R"(dimension: 1
area: 1.0e-4
spacing: 1.0e-3
horizon: 3.0e-3
partial_volume: true
materials:
  steel: {{model: pmb, density: 8000, youngs_modulus: 200.0e9}}
bodies:
  - {{name: bar, material: steel, shape: {{box: {{min: [0], max: [1.0]}}}}}}
initial_conditions:
  - {}
solver: {{end_time: 1.4e-4}}
)",
                     initial_condition);
}

// The cosine bump of initial velocity around x = 0.2 m, of full width 2H.
std::string pulse(double half_width) {
  return fmt::format(R"ic({{velocity: ["abs(x-0.2) < {0} ? 0.5*(1+cos(pi*(x-0.2)/{0})) : 0"]}})ic", half_width);
}

constexpr double kBarSpeed = 5000.0;  // sqrt(E/rho) of both bars

// Speed of the right-running half between stations at xa and xb: each station records
// the mean axial velocity of the lattice layer nearest to it (one particle in 1-D, a
// cross-section in 3-D).
double measured_speed(Simulation& sim, double xa, double xb, double end_time) {
  const auto& P = sim.system.particles;
  std::vector<double> at;
  std::vector<std::vector<std::size_t>> layer(2);
  for (double x : {xa, xb}) at.push_back(P.X[sim.nearest({x, 0, 0})].x);
  for (std::size_t i = 0; i < P.size(); ++i)
    for (int s = 0; s < 2; ++s)
      if (std::abs(P.X[i].x - at[s]) < 1e-3 * sim.system.spacing) layer[s].push_back(i);
  std::vector<StationRecord> record(2);
  auto mean_vx = [&](const std::vector<std::size_t>& ids) {
    double sum = 0;
    for (std::size_t i : ids) sum += P.v[i].x;
    return sum / static_cast<double>(ids.size());
  };
  sim.run_to(end_time, [&] {
    for (int s = 0; s < 2; ++s) record[s].add(sim.solver->time(), mean_vx(layer[s]));
  });
  for (int s = 0; s < 2; ++s) {
    // The right-running half carries half the initial amplitude (1 m/s).
    EXPECT_NEAR(record[s].peak(), 0.5, 0.03) << "station " << s << ": the pulse did not arrive whole";
  }
  const auto ta = record[0].half_max_arrival(), tb = record[1].half_max_arrival();
  if (!ta || !tb) {
    ADD_FAILURE() << "the pulse did not reach both stations by t = " << end_time;
    return 0;
  }
  return (at[1] - at[0]) / (*tb - *ta);
}

double speed_1d(double wavelength) {
  Simulation sim(parse_deck(bar_1d_deck(pulse(wavelength / 2)), "1-D bar"));
  // Stations at 0.4 and 0.8 m: the right-running half passes both before the left-running
  // one, reflected at x = 0, or its own reflection from x = 1 m come back.
  return measured_speed(sim, 0.4, 0.8, 1.4e-4);
}

TEST(WaveSpeed, PulseInA1DPmbBarRunsAtTheBarSpeed) {
  const double horizon = 3.0e-3;
  const double c = speed_1d(20 * horizon);
  report("speed_1d", c,
         fmt::format("1-D PMB bar, wavelength 20 horizons: c = {:.1f} m/s, sqrt(E/rho) = {:.0f} m/s ({:+.2f} %)", c,
                     kBarSpeed, 100 * (c / kBarSpeed - 1)));
  EXPECT_NEAR(c / kBarSpeed, 1.0, 0.02);
}

// Dispersion: the peridynamic bar is dispersive, short waves are slower. A standing wave
// u = A cos(k x) (k = n pi/L, free ends) oscillates at the frequency of the lattice's
// dispersion relation, which for the linearised 1-D PMB reads (seed 002 eq. 22 with
// s = (u_j - u_i)/|xi|, summed over the discrete family with partial volumes beta_j)
//   rho omega^2 = sum_j c beta_j V (1 - cos(k xi_j)) / |xi_j|,
// and velocity Verlet turns omega into (2/dt) asin(omega dt/2). The phase speed omega/k
// tends to sqrt(E/rho) as wavelength/horizon grows (at long wavelength the sum with
// partial volumes equals the integral that calibrates c). The frequency is measured from
// the zero crossings of the wave's amplitude, the projection of u on cos(k x).
TEST(WaveSpeed, PeridynamicDispersionMatchesTheLatticeAndVanishesAtLongWavelength) {
  const double E = 200.0e9, rho = 8000, h = 1.0e-3, delta = 3.0e-3, area = 1.0e-4, length = 1.0;
  const double c = 2 * E / (area * delta * delta);  // 1-D micromodulus, omega = 1
  double previous_speed = 0;
  for (double ratio : {5.0, 10.0, 20.0, 40.0}) {
    const int n = static_cast<int>(std::lround(2 * length / (ratio * delta)));
    const double k = n * std::numbers::pi / length;
    const std::string deck = bar_1d_deck(fmt::format(R"ic({{displacement: ["1e-6*cos({:.17g}*x)"]}})ic", k));
    Simulation sim(parse_deck(deck, "1-D standing wave"));
    const auto& P = sim.system.particles;

    double sum = 0;
    for (int j = 1; j <= 3; ++j) sum += 2 * c * (j == 3 ? 0.5 : 1.0) * h * area * (1 - std::cos(k * j * h)) / (j * h);
    const double omega = std::sqrt(sum / rho);
    const double dt = sim.solver->dt();
    const double omega_verlet = 2 / dt * std::asin(0.5 * omega * dt);

    double norm_cos = 0;
    for (std::size_t i = 0; i < P.size(); ++i) norm_cos += std::pow(std::cos(k * P.X[i].x), 2);
    std::vector<double> crossings;
    double t_prev = 0, a_prev = 1e-6;
    sim.run_to(4.25 * 2 * std::numbers::pi / omega, [&] {
      double a = 0;
      for (std::size_t i = 0; i < P.size(); ++i) a += P.u[i].x * std::cos(k * P.X[i].x);
      a /= norm_cos;
      const double t = sim.solver->time();
      if ((a_prev > 0) != (a > 0)) crossings.push_back(t_prev + (t - t_prev) * a_prev / (a_prev - a));
      t_prev = t;
      a_prev = a;
    });
    ASSERT_GE(crossings.size(), 6u);
    const double measured =
        std::numbers::pi * static_cast<double>(crossings.size() - 1) / (crossings.back() - crossings.front());
    const double speed = measured / k;
    report(fmt::format("phase_speed_lambda_{:.0f}", ratio), speed,
           fmt::format("1-D PMB standing wave, wavelength {:>4.1f} horizons: phase speed {:.1f} m/s ({:+.2f} % from "
                       "c0), lattice relation {:.1f} m/s (measured/relation {:+.3f} %)",
                       2 * std::numbers::pi / k / delta, speed, 100 * (speed / kBarSpeed - 1), omega_verlet / k,
                       100 * (measured / omega_verlet - 1)));
    EXPECT_NEAR(measured / omega_verlet, 1.0, 2e-3) << "the frequency of the lattice's dispersion relation";
    EXPECT_GT(speed, previous_speed) << "longer waves are faster";
    previous_speed = speed;
  }
  EXPECT_NEAR(previous_speed / kBarSpeed, 1.0, 5e-3);
}

// The 3-D bar of examples/wave_in_bar.yaml: LPS, nu = 0.25, 240 x 10 x 10 spacings,
// horizon 3 spacings, partial volumes, a pulse 20 horizons (6 bar widths) wide. The
// lateral-inertia correction (Rayleigh: c/c0 ~ 1 - nu^2 (k r)^2/4, r the radius of
// gyration of the section) is -0.1 %. What limits the comparison with sqrt(E/rho) is the
// surface effect: every particle of a section only 3.3 horizons wide is within a horizon
// of a free surface, and the LPS layers near a free surface are stiffer (check 2), so the
// section as a whole is about 17 % stiffer than the material and the pulse runs about 7 %
// fast. The speed is therefore checked twice:
// - against sqrt(E_section/rho), where E_section is measured statically on a piece of
//   the same bar (traction over the mean axial strain of the section, at rest): within 2 %,
//   the wave runs at the speed the bar's own stiffness gives (this is what the dynamics
//   can get right or wrong);
// - against sqrt(E/rho), within 10 %: the surface effect at this section (the real figure
//   is printed and written in docs/verification.md).
// The section modulus of a 20-spacing piece of the bar of `config`, pulled by 1 MPa at
// its end layers and damped to rest, and the pulse speed in the whole bar.
struct BarFigures {
  double speed = 0, section_modulus = 0, balance_error = 0, dt = 0;
};
BarFigures bar_figures(const Config& config, bool section = true) {
  const double c0 = std::sqrt(config.materials.at(0).youngs_modulus / config.materials.at(0).density);
  Config piece = config;
  const Box3 bar = config.bodies.at(0).shape.bounds();
  const double h = config.spacing, length = 20 * h;
  const Vec3 lo = bar.min, hi{bar.min.x + length, bar.max.y, bar.max.z};
  piece.bodies.at(0).shape = Shape::box(lo, hi);
  piece.initial_conditions.clear();
  piece.regions = {{"left", Shape::box(lo, {lo.x + 1.2 * h, hi.y, hi.z})},
                   {"right", Shape::box({hi.x - 1.2 * h, lo.y, lo.z}, hi)}};
  piece.loads.clear();
  for (const auto& [region, sign] : {std::pair{"left", -1.0}, std::pair{"right", 1.0}}) {
    LoadConfig load;
    load.kind = LoadKind::traction;
    load.region = region;
    load.value = {Expression(sign * 1.0e6), Expression(0.0), Expression(0.0)};
    piece.loads.push_back(load);
  }
  piece.solver.damping = 2 * std::numbers::pi * c0 / length;  // twice the lowest axial frequency
  piece.solver.end_time = 60 / piece.solver.damping;
  BarFigures out;
  if (section) out.section_modulus = measure_tension(piece).youngs_section;

  Simulation sim{Config(config)};
  out.dt = sim.solver->dt();
  out.speed = measured_speed(sim, 0.09, 0.19, 3.4e-5);
  // An elastic pulse without damping keeps its energy (the ledger, check 3).
  sim.solver->step(true);
  out.balance_error = sim.solver->ledger().balance_error();
  return out;
}

TEST(WaveSpeed, PulseInASlender3DLpsBarRunsAtTheBarSpeedOfItsSection) {
  const Config config = load_deck(source_path("examples/wave_in_bar.yaml"));
  const double E = config.materials.at(0).youngs_modulus, rho = config.materials.at(0).density;
  const double c0 = std::sqrt(E / rho);
  ASSERT_NEAR(c0, kBarSpeed, 1e-9);
  const BarFigures f = bar_figures(config);
  const double c = f.speed, c_section = std::sqrt(f.section_modulus / rho);
  report("speed_3d", c,
         fmt::format("3-D LPS bar (nu 0.25, 10 x 10 section): c = {:.1f} m/s; sqrt(E/rho) = {:.0f} m/s ({:+.2f} %); "
                     "sqrt(E_section/rho) = {:.1f} m/s ({:+.2f} %), E_section = {:.1f} GPa",
                     c, c0, 100 * (c / c0 - 1), c_section, 100 * (c / c_section - 1), f.section_modulus / 1e9));
  EXPECT_NEAR(c / c_section, 1.0, 0.02);
  EXPECT_NEAR(c / c0, 1.0, 0.10);
  EXPECT_LT(std::abs(f.balance_error), 5e-3);
}

// The same bar with the LPS surface correction (material/models/lps.cpp): the issue's
// target is the speed within 2 % of sqrt(E/rho) (docs/verification.md "Surface correction").
TEST(WaveSpeed, SurfaceCorrectedLpsBarRunsAtSqrtEOverRho) {
  Config config = load_deck(source_path("examples/wave_in_bar.yaml"));
  const double E = config.materials.at(0).youngs_modulus, rho = config.materials.at(0).density;
  const double c0 = std::sqrt(E / rho);
  const double dt_plain = Simulation(Config(config)).solver->dt();
  config.materials.at(0).parameters["surface_correction"] = 1;
  // The section modulus of the corrected bar (197.0 GPa, -0.98 %, since the deviatoric
  // factor's continuum reference; docs/verification.md) is left out here to keep the test
  // short: the speed is the issue's figure (measured -1.60 %).
  const BarFigures f = bar_figures(config, false);
  const double c = f.speed;
  report("speed_3d_corrected", c,
         fmt::format("3-D LPS bar, surface_correction: true: c = {:.1f} m/s; sqrt(E/rho) = {:.0f} m/s ({:+.2f} %); "
                     "stable step {:.3f} of the uncorrected bar's",
                     c, c0, 100 * (c / c0 - 1), f.dt / dt_plain));
  EXPECT_NEAR(c / c0, 1.0, 0.02);
  EXPECT_LT(std::abs(f.balance_error), 5e-3);
}

// The same bar of Tupek's nonlinear solid (log strain, no failure; nu = 0.25, so its
// lambda_bar = 0) with its surface correction (material/models/nonlinear_solid.cpp): the
// issue's target, the speed within 2 % of sqrt(E/rho) (docs/verification.md "Surface
// correction"). About 45 s CPU on the shared machine: the model's two sweeps per pass.
TEST(WaveSpeed, SurfaceCorrectedNonlinearSolidBarRunsAtSqrtEOverRho) {
  Config config = load_deck(source_path("examples/wave_in_bar.yaml"));
  MaterialConfig& mat = config.materials.at(0);
  mat.model = "nonlinear_solid";
  mat.influence = InfluenceKind::tupek;
  mat.parameters["surface_correction"] = 1;
  const double E = mat.youngs_modulus, rho = mat.density;
  const double c0 = std::sqrt(E / rho);
  const BarFigures f = bar_figures(config, false);
  const double c = f.speed;
  report("speed_3d_nonlinear_corrected", c,
         fmt::format("3-D nonlinear solid bar (nu 0.25, 10 x 10 section), surface_correction: {}: c = {:.1f} m/s; "
                     "sqrt(E/rho) = {:.0f} m/s ({:+.2f} %)",
                     mat.parameters["surface_correction"] != 0, c, c0, 100 * (c / c0 - 1)));
  EXPECT_NEAR(c / c0, 1.0, 0.02);
  EXPECT_LT(std::abs(f.balance_error), 5e-3);
}

// Without partial volumes the same bar runs at sqrt(E/rho) within 2 %, but only because
// two errors cancel: the interior of that lattice is 14 % too soft along the bar (check 2,
// BlockWithoutPartialVolumesMatchesItsAnisotropicLattice) and the surface layers are stiffer.
// Kept as a figure for docs/verification.md, not as a check of the code.

}  // namespace
}  // namespace horizon::verification
