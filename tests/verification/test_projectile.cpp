// Rigid projectiles (contact/projectile.hpp, docs/verification.md "Rigid projectiles"):
// the 2nd-order Butterworth filter against its analytic response; momentum of body plus
// particles conserved to round-off; the energy ledger closing in an elastic impact; a
// sphere on an elastic block against Hertz's impact theory; checkpoint and restart; deck
// errors.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

#include <fmt/format.h>

#include "horizon/contact/projectile.hpp"
#include "horizon/core/error.hpp"
#include "horizon/deck/deck.hpp"
#include "horizon/driver/run.hpp"
#include "horizon/solver/explicit.hpp"
#include "verification_support.hpp"

namespace horizon::verification {
namespace {

namespace fs = std::filesystem;

RunOptions quiet_in(const std::string& name) {
  RunOptions o;
  o.quiet = true;
  o.handle_signals = false;
  o.output_dir = output_dir(name).string();
  return o;
}

// ---------------------------------------------------------------------------------
// The filter. A sinusoid of frequency f through the filter at step T: after the
// transient, the output's amplitude over the input's is the gain. The digital filter's
// response is 1/sqrt(1 + (tan(pi f T)/tan(pi fc T))^4) (projectile.hpp); the analogue
// Butterworth's 1/sqrt(1 + (f/fc)^4), which it approaches for fc T << 1.

double measured_gain(double fc, double f, double T) {
  Butterworth2 b;
  b.cutoff = fc;
  const int n = static_cast<int>(std::ceil(40.0 / (f * T))) + 2000;  // 40 periods
  double peak = 0;
  for (int k = 0; k < n; ++k) {
    const double y = b.filter(std::sin(2 * M_PI * f * k * T), T);
    if (k > n / 2) peak = std::max(peak, std::abs(y));  // the second half: steady state
  }
  return peak;
}

TEST(Projectile, ButterworthGainIsOneAtDcAndOneOverRootTwoAtTheCutoff) {
  const double fc = 20e3, T = 1e-7;  // 20 kHz at a 10 MHz step: the example's ratio
  Butterworth2 dc;
  dc.cutoff = fc;
  double y = 0;
  dc.filter(0.0, T);
  for (int k = 0; k < 20000; ++k) y = dc.filter(3.5, T);  // a step from 0 to 3.5
  EXPECT_NEAR(y / 3.5, 1.0, 1e-9);
  // At the cutoff the pre-warped bilinear filter has exactly 1/sqrt(2).
  EXPECT_NEAR(Butterworth2::gain(fc, fc, T), 1 / std::sqrt(2.0), 1e-14);
  const double at_cutoff = measured_gain(fc, fc, T);
  EXPECT_NEAR(at_cutoff, 1 / std::sqrt(2.0), 2e-3) << "sampled peak of the steady-state output";
  for (double ratio : {0.1, 0.5, 2.0, 5.0}) {
    const double f = ratio * fc;
    const double measured = measured_gain(fc, f, T);
    const double digital = Butterworth2::gain(fc, f, T), analogue = 1 / std::sqrt(1 + std::pow(ratio, 4));
    EXPECT_NEAR(measured, digital, 2e-3 * std::max(digital, 0.05)) << "f/fc = " << ratio;
    EXPECT_NEAR(digital / analogue, 1.0, 1e-2) << "f/fc = " << ratio;
  }
  // Pass-through without a cutoff.
  Butterworth2 none;
  EXPECT_EQ(none.filter(2.5, T), 2.5);
}

// ---------------------------------------------------------------------------------
// The ogive's geometry. With crh = 1/2 the tangent ogive is a hemisphere (arc radius a,
// nose length a): the volume is 2/3 pi a^3 + pi a^2 L, and a point of the nose has the
// depth and normal of the sphere about the nose's centre. For crh = 3 the nose length is
// a sqrt(11) and the nose's volume the integral of pi r(z)^2 (a fine midpoint sum here).
TEST(Projectile, OgiveShapeDepthNormalAndVolume) {
  const double a = 0.01, L = 0.02;
  RigidShapeConfig c;
  c.kind = RigidShapeKind::ogive;
  c.radius = a;
  c.length = L;
  c.crh = 0.5;
  c.axis = {0, 0, -1};
  const RigidShape hemi(c);
  EXPECT_NEAR(hemi.nose_length(), a, 1e-15);
  EXPECT_NEAR(hemi.volume(), 2.0 / 3.0 * M_PI * a * a * a + M_PI * a * a * L, 1e-9 * hemi.volume());
  // The nose's centre is a above the tip (the body lies at z > 0 from the tip along -axis).
  const Vec3 centre{0, 0, a};
  for (const Vec3& q : {Vec3{0.003, 0.002, 0.004}, Vec3{-0.001, 0.005, 0.003}, Vec3{0.0, 0.0, 0.0005}}) {
    Penetration p;
    ASSERT_TRUE(hemi.penetration(q, p));
    const Vec3 d = q - centre;
    EXPECT_NEAR(p.depth, a - norm(d), 1e-14);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(p.normal[k], d[k] / norm(d), 1e-12);
  }
  Penetration p;
  EXPECT_FALSE(hemi.penetration(Vec3{0.0, 0.0, -0.0001}, p));      // ahead of the tip
  EXPECT_FALSE(hemi.penetration(Vec3{0.0099, 0.0, 0.002}, p));     // beside the nose
  EXPECT_FALSE(hemi.penetration(Vec3{0.0, 0.0, a + L + 1e-6}, p));  // behind the rear face
  // The shank: depth to the side or to the rear face, whichever is nearer.
  ASSERT_TRUE(hemi.penetration(Vec3{0.008, 0.0, 0.02}, p));
  EXPECT_NEAR(p.depth, 0.002, 1e-15);
  EXPECT_NEAR(p.normal.x, 1.0, 1e-15);
  ASSERT_TRUE(hemi.penetration(Vec3{0.0, 0.001, a + L - 0.0005}, p));
  EXPECT_NEAR(p.depth, 0.0005, 1e-15);
  EXPECT_NEAR(p.normal.z, 1.0, 1e-15);  // -axis: out of the rear face
  // crh = 3: nose length a sqrt(11); the volume against a fine disc sum of pi r(z)^2.
  c.crh = 3;
  const RigidShape ogive(c);
  EXPECT_NEAR(ogive.nose_length(), a * std::sqrt(11.0), 1e-15);
  const double s = 6 * a, l = ogive.nose_length();
  double v = 0;
  const int n = 200000;
  for (int k = 0; k < n; ++k) {
    const double z = (k + 0.5) * l / n, r = std::sqrt(s * s - (l - z) * (l - z)) - (s - a);
    v += M_PI * r * r * l / n;
  }
  EXPECT_NEAR(ogive.volume(), v + M_PI * a * a * L, 1e-8 * ogive.volume());
  // A point just inside the nose's surface at z = l/2.
  const double z = l / 2, r = std::sqrt(s * s - (l - z) * (l - z)) - (s - a);
  ASSERT_TRUE(ogive.penetration(Vec3{r - 1e-5, 0, z}, p));
  EXPECT_NEAR(p.depth, 1e-5 * (s - a + r) / s, 1e-8);  // 1e-5 along x times the normal's x part
  EXPECT_FALSE(ogive.penetration(Vec3{r + 1e-5, 0, z}, p));
}

// A deck with a projectile splits over MPI ranks (tests/mpi/projectile_heat.cmake runs
// one on 1 to 4 ranks): the driver accepts it.
TEST(Projectile, SplitsOverRanks) {
  const std::string deck = R"(dimension: 3
spacing: 0.001
horizon_factor: 3
materials:
  soft: {model: pmb, density: 1000, youngs_modulus: 1.0e9, poissons_ratio: 0.25}
bodies:
  - {name: block, material: soft, shape: {box: {min: [0, 0, 0], max: [0.004, 0.004, 0.004]}}}
contact:
  projectiles:
    - {shape: {sphere: {radius: 0.001}}, mass: 0.01, position: [0, 0, 0.006], velocity: [0, 0, -10], contact: {stiffness: 1.0e15}}
solver: {end_time: 1.0e-6}
)";
  const Config c = parse_deck(deck, "ranks.yaml");
  const System s = build_system(c);
  EXPECT_EQ(distributed_limits(c, s, RunOptions{}), "");
  // The stable step takes the penalty: K = 1e15 N/m^4 beside the bond sum.
  Config no = c;
  no.contact.projectiles.clear();
  const double with = stable_time_step(s), without = stable_time_step(build_system(no));
  EXPECT_LT(with, without);
  EXPECT_GT(with, 0.5 * without);
}

// An indenter's quadratic penalty (force density K d^2, stiffness 2 K d) joins the
// Silling-Askari sum of the stable step as a projectile's does: 1/dt^2 grows by exactly
// 2 K d / (2 rho), d = one spacing.
TEST(Projectile, IndenterPenaltyEntersTheStableStep) {
  const std::string deck = R"(dimension: 3
spacing: 0.001
horizon_factor: 3
materials:
  soft: {model: pmb, density: 1000, youngs_modulus: 1.0e9, poissons_ratio: 0.25}
bodies:
  - {name: block, material: soft, shape: {box: {min: [0, 0, 0], max: [0.004, 0.004, 0.004]}}}
contact:
  indenters:
    - {name: wall, center: [0, -10, 0], radius: 10, stiffness: 1.0e18}
solver: {end_time: 1.0e-6}
)";
  const Config c = parse_deck(deck, "indenter.yaml");
  Config no = c;
  no.contact.indenters.clear();
  const double with = stable_time_step(build_system(c)), without = stable_time_step(build_system(no));
  const double added = 1 / (with * with) - 1 / (without * without), expected = 2 * 1e18 * 0.001 / (2 * 1000.0);
  EXPECT_NEAR(added, expected, 1e-9 * expected);
}

// ---------------------------------------------------------------------------------
// A free PMB block (E = 1 GPa, nu = 1/4, rho = 1000) and a rigid body striking it.
std::string block_deck(const std::string& size, const std::string& projectile, const std::string& solver,
                       const std::string& output = "{frames: 1, history_every: 1}") {
  return fmt::format(R"(dimension: 3
spacing: 0.001
horizon_factor: 3
materials:
  soft: {{model: pmb, density: 1000, youngs_modulus: 1.0e9, poissons_ratio: 0.25}}
bodies:
  - {{name: block, material: soft, shape: {{box: {{min: [0, 0, 0], max: {}}}}}}}
contact:
  projectiles:
    - {}
solver: {}
output: {}
)",
                     size, projectile, solver, output);
}

// An ogive nose striking a small block obliquely: the total momentum, sum rho V v + M v_b,
// stays M v_0 to round-off (F on the body is minus sum b V, bond forces cancel in pairs).
TEST(Projectile, MomentumOfBodyAndParticlesIsConserved) {
  const std::string deck = block_deck(
      "[0.008, 0.008, 0.005]",
      "{name: nose, shape: {ogive: {radius: 0.002, length: 0.004, crh: 2, axis: [0.3, 0, -1]}}, mass: 0.002, "
      "position: [0.0035, 0.004, 0.0048], velocity: [40, -30, -200], contact: {law: quadratic, stiffness: 5.0e19}}",
      "{end_time: 1.0e-5}");
  const Config c = parse_deck(deck, "momentum.yaml");
  ExplicitRun run(c, quiet_in("projectile_momentum"));
  const Projectile& body = run.loads().projectiles().at(0);
  const Vec3 p0 = c.contact.projectiles[0].velocity * body.mass();
  run.advance(std::numeric_limits<int64_t>::max());
  ASSERT_EQ(run.finish(), 0);
  const auto& P = run.system().particles;
  Vec3 p = body.v * body.mass();
  for (std::size_t i = 0; i < P.size(); ++i) p += P.v[i] * (P.density[i] * P.volume[i]);
  // The contact did act: the sharp nose, 1.5 mm deep at the end, has passed 0.4 % of its
  // momentum (1.7e-3 N s) to the block, 1e12 times the round-off asserted below.
  EXPECT_GT(norm(body.impulse), 2e-3 * norm(p0));
  EXPECT_GT(body.peak_force, 0);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(p[k], p0[k], 1e-12 * norm(p0)) << "component " << k;
  report("projectile_momentum_error", norm(p - p0) / norm(p0),
         fmt::format("ogive into a free block, {} steps: |p - p0|/|p0| = {:.2e}, impulse {:.3e} of {:.3e} N s",
                     run.steps(), norm(p - p0) / norm(p0), norm(body.impulse), norm(p0)));
}

// ---------------------------------------------------------------------------------
// Hertz (Johnson, Contact Mechanics, 1985, sec. 11.4, eq. 11.23-11.24): a rigid sphere of
// radius R striking an elastic half-space (E* = E/(1 - nu^2)) at v0 with mass m:
//   delta_max = (15 m v0^2 / (16 E* R^1/2))^(2/5),  F_max = 4/3 E* R^1/2 delta_max^(3/2),
//   t_c = 2.868 (m^2 / (R E*^2 v0))^(1/5).
// The block is free, so m is the reduced mass m M/(m + M) of sphere and block.
// One run of the sphere at 50 m/s (starting 0.6 mm above the top particles) on a
// 24 x 24 x 12 mm block serves the Hertz and the
// ledger tests.
struct HertzRun {
  nlohmann::json summary;
  double mass = 0, block_mass = 0, v0 = 50, R = 0.01, E = 1.0e9, nu = 0.25;
  double max_balance = 0, min_kinetic_fraction = 1, final_body_energy = 0, initial = 0;
  double separated_speed = 0;
};

const HertzRun& hertz_run() {
  static const HertzRun r = [] {
    HertzRun h;
    h.mass = 2.0e-3;
    const std::string deck = block_deck(
        "[0.024, 0.024, 0.012]",
        fmt::format("{{name: ball, shape: {{sphere: {{radius: {}}}}}, mass: {}, position: [0.012, 0.012, 0.0221], "
                    "velocity: [0, 0, -{}], contact: {{law: linear, stiffness: 3.0e15}}, filter: {{cutoff: 1.0e6}}}}",
                    h.R, h.mass, h.v0),
        "{end_time: 8.0e-5, safety_factor: 0.8}");
    const Config c = parse_deck(deck, "hertz.yaml");
    ExplicitRun run(c, quiet_in("projectile_hertz"));
    const auto& P = run.system().particles;
    for (std::size_t i = 0; i < P.size(); ++i) h.block_mass += P.density[i] * P.volume[i];
    const Projectile& body = run.loads().projectiles().at(0);
    h.initial = body.kinetic();
    while (!run.done()) {
      run.advance(1);
      h.min_kinetic_fraction = std::min(h.min_kinetic_fraction, body.kinetic() / h.initial);
    }
    EXPECT_EQ(run.finish(), 0);
    h.summary = run.summary();
    h.max_balance = h.summary["energy"]["max_abs_balance_error"];
    h.final_body_energy = body.kinetic();
    h.separated_speed = -body.v.z;
    return h;
  }();
  return r;
}

TEST(Projectile, EnergyLedgerClosesInAnElasticImpact) {
  const HertzRun& h = hertz_run();
  ASSERT_EQ(h.summary["status"], "completed");
  // The body's kinetic energy is in the ledger: at t = 0 it is all of it.
  EXPECT_NEAR(h.summary["energy"]["initial"].get<double>(), h.initial, 1e-12 * h.initial);
  // The impact happened: the sphere gave most of its energy to the block at some point.
  EXPECT_LT(h.min_kinetic_fraction, 0.5);
  report("projectile_energy_balance", h.max_balance,
         fmt::format("sphere on a block, linear penalty: max |balance error| {:.2e}, body energy at its lowest "
                     "{:.1f} % of the initial",
                     h.max_balance, 100 * h.min_kinetic_fraction));
  EXPECT_LE(h.max_balance, 1e-2);
}

TEST(Projectile, SphereOnAnElasticBlockAgainstHertz) {
  const HertzRun& h = hertz_run();
  ASSERT_EQ(h.summary["status"], "completed");
  const auto& b = h.summary["projectiles"]["ball"];
  const double m = h.mass * h.block_mass / (h.mass + h.block_mass);
  const double Es = h.E / (1 - h.nu * h.nu);
  const double delta = std::pow(15 * m * h.v0 * h.v0 / (16 * Es * std::sqrt(h.R)), 0.4);
  const double F = 4.0 / 3.0 * Es * std::sqrt(h.R) * std::pow(delta, 1.5);
  const double tc = 2.868 * std::pow(m * m / (h.R * Es * Es * h.v0), 0.2);
  const double peak = b["peak_force"], duration = b["contact_end"].get<double>() - b["contact_start"].get<double>();
  report("projectile_hertz_peak_force", peak / F,
         fmt::format("Hertz: F_max {:.1f} N, t_c {:.2f} us (delta_max {:.3f} mm, a = {:.2f} mm); PD: {:.1f} N, "
                     "{:.2f} us; ratios {:.3f}, {:.3f}",
                     F, 1e6 * tc, 1e3 * delta, 1e3 * std::sqrt(h.R * delta), peak, 1e6 * duration, peak / F,
                     duration / tc));
  // Measured: peak force 1.089 F_max, contact time 1.017 t_c (5121.5 N, 61.70 us). The
  // tolerance, 15 %, covers what this reduced model leaves out of Hertz's: a contact
  // radius of only 3.2 spacings (the contact area counts whole particles), a free block
  // 24 x 24 x 12 mm rather than a half-space (its waves return within the contact time),
  // the penalty's own compliance, and the PMB's softer surface layer.
  EXPECT_NEAR(peak / F, 1.0, 0.15);
  EXPECT_NEAR(duration / tc, 1.0, 0.15);
}

// ---------------------------------------------------------------------------------
// Checkpoint and restart carry the body: a run restarted from its checkpoint ends with
// the same history.csv bytes as the straight run.
TEST(Projectile, RestartContinuesTheBodyBitForBit) {
  const std::string deck = block_deck(
      "[0.008, 0.008, 0.005]",
      "{name: ball, shape: {sphere: {radius: 0.003}}, density: 7800, position: [0.004, 0.004, 0.0075], "
      "velocity: [0, 0, -100], contact: {law: linear, stiffness: 3.0e15}, filter: {cutoff: 2.0e5}}",
      "{end_time: 6.0e-6, time_step: 1.0e-7}", "{frames: 2, history_every: 5, checkpoint: {every: 30}}");
  const Config c = parse_deck(deck, "restart.yaml");
  RunOptions a = quiet_in("projectile_restart_straight");
  ExplicitRun straight(c, a);
  straight.advance(std::numeric_limits<int64_t>::max());
  ASSERT_EQ(straight.finish(), 0);
  EXPECT_GT(straight.loads().projectiles()[0].peak_force, 0) << "the ball must reach the block";
  RunOptions b = quiet_in("projectile_restart");
  {
    ExplicitRun killed(c, b);
    killed.advance(37);
  }
  b.restart = (fs::path(*b.output_dir) / "checkpoint.hzc").string();
  ExplicitRun restarted(c, b);
  EXPECT_EQ(restarted.steps(), 30);
  restarted.advance(std::numeric_limits<int64_t>::max());
  ASSERT_EQ(restarted.finish(), 0);
  EXPECT_EQ(straight.history_csv(), restarted.history_csv());
  EXPECT_EQ(straight.summary()["projectiles"].dump(), restarted.summary()["projectiles"].dump());
}

// ---------------------------------------------------------------------------------
// Deck errors: name the deck, the line and column, and what was expected.
std::string deck_error(const std::string& projectile, const std::string& solver = "{end_time: 1.0e-6}") {
  try {
    parse_deck(block_deck("[0.004, 0.004, 0.004]", projectile, solver), "bad.yaml");
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

TEST(Projectile, DeckErrorsNameTheLineAndWhatWasExpected) {
  const std::string ok = "{shape: {sphere: {radius: 0.001}}, mass: 0.01, position: [0, 0, 0.006], velocity: [0, 0, -10], "
                         "contact: {law: linear, stiffness: 1.0e15}}";
  EXPECT_NO_THROW(parse_deck(block_deck("[0.004, 0.004, 0.004]", ok, "{end_time: 1.0e-6}"), "ok.yaml"));
  auto expect = [](const std::string& message, const std::string& part) {
    EXPECT_NE(message.find("bad.yaml:10:"), std::string::npos) << message;
    EXPECT_NE(message.find(part), std::string::npos) << message;
  };
  auto with = [&](const std::string& from, const std::string& to) {
    std::string s = ok;
    s.replace(s.find(from), from.size(), to);
    return deck_error(s);
  };
  expect(with("{sphere: {radius: 0.001}}", "{ogive: {radius: 0.001, length: 0.002, crh: 0.3, axis: [0, 0, -1]}}"),
         "caliber-radius-head >= 0.5");
  expect(with("law: linear, stiffness: 1.0e15", "law: linear"), "stiffness");
  expect(with("law: linear", "law: hertz"), "linear");
  expect(with("mass: 0.01", "mass: 0.01, density: 7800"), "density");
  expect(with("mass: 0.01, ", ""), "mass");
  expect(with("stiffness: 1.0e15", "stiffness: 1.0e15, max_penetration: 0.001"), "applies to law quadratic only");
  expect(with("{sphere: {radius: 0.001}}", "{cube: {side: 0.001}}"), "sphere");
  const std::string implicit = deck_error(ok, "{type: static, end_time: 1.0}");
  EXPECT_NE(implicit.find("bad.yaml:9:3: error: contact.projectiles: rigid projectiles run with solver type explicit "
                          "only"),
            std::string::npos)
      << implicit;
}

}  // namespace
}  // namespace horizon::verification
