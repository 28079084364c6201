// The options that pose LAMMPS PERI's problems (docs/models.md sec. 9-11): the lattice
// origin, the LAMMPS partial-volume rule, the critical stretch raised by compression
// (s00, alpha) and the breaking order, short-range contact, the rigid indenter, and
// the two implementations of the bond loops giving the same bits.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <cstring>
#include <string>

#include "horizon/core/error.hpp"
#include "horizon/deck/deck.hpp"
#include "horizon/family/neighbors.hpp"
#include "horizon/loading/loads.hpp"
#include "horizon/solver/explicit.hpp"
#include "horizon/solver/forces.hpp"
#include "test_helpers.hpp"

namespace horizon {
namespace {

// ---------------------------------------------------------------------------------
// Lattice origin and the LAMMPS cylinder.

// LAMMPS's examples/peri: `lattice sc 0.0005` (points at integer multiples of the
// spacing) filling `region target cylinder y 0 0 0.005 -0.005 0` gives 3,487 atoms.
const char* const kCylinder = R"deck(dimension: 3
spacing: 0.0005
horizon: 0.0015001
lattice_origin: [0, 0, 0]
partial_volume: lammps
materials:
  target: {model: pmb, density: 2200, micromodulus: 1.6863e22, damage: {critical_stretch: 0.0005, alpha: 0.25, breaks: after_force}}
bodies:
  - {name: target, material: target, shape: {cylinder: {from: [0, -0.005, 0], to: [0, 0, 0], radius: 0.005}}}
contact:
  short_range: {stiffness_factor: 15, reference_fraction: 0.9, max_distance: 1.35}
  indenters:
    - {name: ball, center: [0, "0.00155 - 100*t", 0], radius: 0.0015, stiffness: 1.0e17}
solver: {end_time: 1.0e-6, time_step: 1.0e-7}
output: {damage_measure: volume}
)deck";

TEST(LammpsRules, LatticeOriginGivesTheLammpsCylinder) {
  const Config c = parse_deck(kCylinder, "cylinder.yaml");
  ASSERT_TRUE(c.lattice_origin.has_value());
  System s = build_system(c);
  EXPECT_EQ(s.particles.size(), 3487u);
  // Every point at an integer multiple of the spacing.
  for (const Vec3& x : s.particles.X)
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(x[k] / 0.0005, std::round(x[k] / 0.0005), 1e-9);
  // Without the origin the lattice starts half a spacing inside the cylinder's box.
  Config shifted = c;
  shifted.lattice_origin.reset();
  EXPECT_NE(build_system(shifted).particles.size(), 3487u);
}

TEST(LammpsRules, DeckReadsTheNewOptions) {
  const Config c = parse_deck(kCylinder, "cylinder.yaml");
  EXPECT_EQ(c.partial_volume.rule, PartialVolumeRule::lammps);
  const MaterialConfig& m = c.materials[0];
  ASSERT_TRUE(m.micromodulus.has_value());
  EXPECT_EQ(*m.micromodulus, 1.6863e22);
  EXPECT_EQ(m.poissons_ratio, 0.25);
  EXPECT_EQ(m.damage.alpha, 0.25);
  EXPECT_TRUE(m.damage.break_after_force);
  EXPECT_TRUE(c.contact.short_range.enabled);
  ASSERT_EQ(c.contact.indenters.size(), 1u);
  EXPECT_EQ(c.contact.indenters[0].name, "ball");
  EXPECT_EQ(c.output.damage_measure, DamageMeasure::volume);
  // The micromodulus sets the PMB's c exactly (and the moduli derived from it).
  const System s = build_system(c);
  EXPECT_EQ(s.model.pair_coef[0], 0.5 * 1.6863e22);

  auto rule = [](const std::string& value) {
    std::string deck = kCylinder;
    deck.replace(deck.find("partial_volume: lammps"), 22, "partial_volume: " + value);
    return parse_deck(deck, "pv.yaml").partial_volume.rule;
  };
  EXPECT_EQ(rule("true"), PartialVolumeRule::linear);
  EXPECT_EQ(rule("false"), PartialVolumeRule::none);
  EXPECT_EQ(rule("linear"), PartialVolumeRule::linear);
  EXPECT_EQ(rule("none"), PartialVolumeRule::none);
  EXPECT_THROW(rule("lamps"), Error);

  std::string lps = kCylinder;
  lps.replace(lps.find("model: pmb"), 10, "model: lps");
  try {
    parse_deck(lps, "lps.yaml");
    ADD_FAILURE() << "micromodulus accepted for model lps";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("micromodulus applies to bond-based models only"), std::string::npos) << e.what();
  }
}

// ---------------------------------------------------------------------------------
// Partial volumes, LAMMPS rule: family |xi| <= horizon, fraction
// (horizon + h/2 - |xi|)/h for |xi| > horizon - h/2 (LAMMPS fix peri/neigh).

TEST(LammpsRules, LammpsVolumeFractions) {
  const double h = 0.0005, delta = 0.0015001;
  test::BlockSpec b;
  b.n = {9, 9, 9};
  b.spacing = h;
  b.horizon_factor = delta / h;
  MaterialConfig mat = test::make_material("pmb", 1e9, 0.25);
  Config c = test::block_config(b, mat);
  c.partial_volume = PartialVolumeRule::lammps;
  const System s = build_system(c);
  c.partial_volume = PartialVolumeRule::linear;
  const System linear = build_system(c);
  const std::size_t centre = (4 * 9 + 4) * 9 + 4;  // (4, 4, 4)
  // The family is the sphere of the horizon: 122 neighbours (|n|^2 <= 9); the linear
  // rule reaches horizon + h/2 and adds |n|^2 = 10, 11, 12 (24 + 24 + 8 of them).
  EXPECT_EQ(s.bonds.end(centre) - s.bonds.begin(centre), 122);
  EXPECT_EQ(linear.bonds.end(centre) - linear.bonds.begin(centre), 122 + 56);
  const double V = h * h * h;
  int scaled = 0;
  for (uint64_t k = s.bonds.begin(centre); k < s.bonds.end(centre); ++k) {
    const double r = s.bonds.length[k];
    EXPECT_LE(r, delta);
    const double n2 = std::round(r * r / (h * h));
    double expected = 1.0;
    if (n2 == 8) expected = (delta + 0.5 * h - std::sqrt(8.0) * h) / h;  // 0.6718
    if (n2 == 9) expected = (delta + 0.5 * h - 3.0 * h) / h;             // 0.5002
    EXPECT_NEAR(s.bonds.volume[k], expected * V, 1e-12 * V) << "|n|^2 = " << n2;
    if (expected < 1) ++scaled;
  }
  EXPECT_EQ(scaled, 12 + 30);
}

// ---------------------------------------------------------------------------------
// Critical stretch raised by compression: s0_i = s00 - alpha * min_j s_ij (previous
// pass), a bond breaks when its stretch exceeds min(s0_i, s0_j).

struct Chain {
  System s;
  double h;
};

// Four particles on a line, nearest-neighbour bonds only: 0-1-2-3.
Chain chain(double alpha, bool after_force = false) {
  test::BlockSpec b;
  b.dimension = 1;
  b.n = {4, 1, 1};
  b.horizon_factor = 1.1;
  MaterialConfig mat = test::make_material("pmb", 1e9, 0.25);
  mat.damage.enabled = true;
  mat.damage.critical_stretch = 1e-3;
  mat.damage.alpha = alpha;
  mat.damage.break_after_force = after_force;
  return {test::make_block(b, mat), b.spacing};
}

// Sets the stretches of bonds 0-1, 1-2, 2-3 (particle 0 fixed).
void stretch_chain(Chain& c, double s01, double s12, double s23) {
  auto& u = c.s.particles.u;
  u[0] = {};
  u[1] = {u[0].x + s01 * c.h, 0, 0};
  u[2] = {u[1].x + s12 * c.h, 0, 0};
  u[3] = {u[2].x + s23 * c.h, 0, 0};
}

bool bond_12_intact(const System& s) {
  for (uint64_t k = s.bonds.begin(1); k < s.bonds.end(1); ++k)
    if (s.bonds.nbr[k] == 2) return s.bonds.intact[k] != 0;
  return false;
}

TEST(LammpsRules, CompressionRaisesTheCriticalStretch) {
  // Pass 1: bonds 0-1 and 2-3 compressed by 2e-3, 1-2 at rest. Particles 1 and 2 then
  // have s0 = 1e-3 + 0.25 * 2e-3 = 1.5e-3 for the next pass.
  Chain c = chain(0.25);
  stretch_chain(c, -2e-3, 0, -2e-3);
  compute_forces(c.s, false);
  EXPECT_NEAR(c.s.model.min_stretch[1], -2e-3, 1e-12);
  EXPECT_NEAR(c.s.model.min_stretch[2], -2e-3, 1e-12);
  // Pass 2: bond 1-2 at 1.4e-3 > s00 survives; the stretches of pass 2 set s0 for pass 3.
  stretch_chain(c, -2e-3, 1.4e-3, -2e-3);
  compute_forces(c.s, false);
  EXPECT_TRUE(bond_12_intact(c.s)) << "s0 = 1.5e-3 at both ends";
  EXPECT_EQ(c.s.broken, 0u);
  // Pass 3: 1.6e-3 exceeds the raised s0: both directions break in the same pass.
  stretch_chain(c, -2e-3, 1.6e-3, -2e-3);
  compute_forces(c.s, false);
  EXPECT_FALSE(bond_12_intact(c.s));
  EXPECT_EQ(c.s.broken, 2u);
}

TEST(LammpsRules, TheSmallerCriticalStretchOfTheTwoEndsDecides) {
  // Only particle 1 is compressed in pass 1: s0_1 = 1.5e-3, s0_2 = 1e-3 - 0.25 * 0 = 1e-3.
  Chain c = chain(0.25);
  stretch_chain(c, -2e-3, 0, 0);
  compute_forces(c.s, false);
  stretch_chain(c, -2e-3, 1.2e-3, 0);
  compute_forces(c.s, false);
  EXPECT_FALSE(bond_12_intact(c.s)) << "min(1.5e-3, 1e-3) = 1e-3 < 1.2e-3";

  // A bond stretched everywhere lowers s0: all bonds at 0.8e-3 give s0 = 1e-3 - 0.2e-3.
  Chain d = chain(0.25);
  stretch_chain(d, 0.8e-3, 0.8e-3, 0.8e-3);
  compute_forces(d.s, false);
  EXPECT_TRUE(bond_12_intact(d.s));
  stretch_chain(d, 0.8e-3, 0.85e-3, 0.8e-3);
  compute_forces(d.s, false);
  EXPECT_FALSE(bond_12_intact(d.s)) << "0.85e-3 > s0 = 0.8e-3";

  // alpha = 0 is the plain critical-stretch law.
  Chain e = chain(0.0);
  stretch_chain(e, -2e-3, 0, -2e-3);
  compute_forces(e.s, false);
  stretch_chain(e, -2e-3, 1.2e-3, -2e-3);
  compute_forces(e.s, false);
  EXPECT_FALSE(bond_12_intact(e.s));
}

TEST(LammpsRules, BreakingOrder) {
  // Bond 1-2 at 2e-3 > s0 = 1e-3 from the start. before_force: it breaks before the
  // forces and pulls nothing; after_force: it pulls once, in the step it breaks.
  for (bool after : {false, true}) {
    Chain c = chain(0.0, after);
    stretch_chain(c, 0, 2e-3, 0);
    compute_forces(c.s, false);
    EXPECT_FALSE(bond_12_intact(c.s));
    const double pull = c.s.particles.f[1].x;  // bond 1-2 pulls particle 1 towards 2 (+x)
    if (after) {
      const double cc = 2 * c.s.model.pair_coef[1];
      EXPECT_NEAR(pull, cc * 2e-3 * c.s.bonds.volume[c.s.bonds.begin(1)], 1e-6 * std::abs(pull));
    } else {
      EXPECT_EQ(pull, 0.0);
    }
    compute_forces(c.s, false);
    EXPECT_EQ(c.s.particles.f[1].x, 0.0) << "gone from the next pass on";
  }
}

// ---------------------------------------------------------------------------------
// Short-range contact: force density on i, K c V_j (d - r)/delta away from j when
// r < d = min(0.9 |xi|, 1.35 h); nothing beyond.

// Two single-particle bodies 5 spacings apart (no bond), particle 1 moved to `gap`
// from particle 0 along direction `dir`.
System two_bodies(const Vec3& dir, double gap, double* c_out) {
  const double h = 1e-3;
  Config c;
  c.dimension = 3;
  c.spacing = h;
  c.horizon = 3.0001 * h;
  c.lattice_origin = Vec3{};
  MaterialConfig m = test::make_material("pmb", 1e9, 0.25);
  c.materials = {m};
  c.bodies = {BodyConfig{"a", "solid", Shape::box({-0.5 * h, -0.5 * h, -0.5 * h}, {0.5 * h, 0.5 * h, 0.5 * h})},
              BodyConfig{"b", "solid", Shape::box({4.5 * h, -0.5 * h, -0.5 * h}, {5.5 * h, 0.5 * h, 0.5 * h})}};
  c.contact.short_range.enabled = true;
  System s = build_system(c);
  EXPECT_EQ(s.particles.size(), 2u);
  EXPECT_EQ(s.bonds.size(), 0u);
  s.particles.u[1] = dir * gap - s.particles.X[1];
  *c_out = 2 * s.model.pair_coef[0];
  return s;
}

TEST(LammpsRules, ContactForceMagnitudeDirectionAndRange) {
  const double h = 1e-3, delta = 3.0001 * h;
  const Vec3 dir = Vec3{1, 2, 2} / 3.0;
  double c = 0;
  System s = two_bodies(dir, 1.2 * h, &c);
  compute_forces(s, true);
  // d = min(0.9 * 5h, 1.35 h) = 1.35 h; overlap 0.15 h.
  const double f = 15 * c * s.particles.volume[1] * (1.35 * h - 1.2 * h) / delta;
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(s.particles.f[0][k], -f * dir[k], 1e-9 * f) << k;  // pushed away from particle 1
    EXPECT_NEAR(s.particles.f[1][k], f * dir[k], 1e-9 * f) << k;
  }
  // Energy: each particle holds half of (1/2) k V_i V_j overlap^2 per unit volume.
  EXPECT_NEAR(s.particles.energy[0], 0.25 * f / (0.15 * h) * (0.15 * h) * (0.15 * h), 1e-9 * f * h);
  // The same contact reached by motion after the contact list was built (the particle
  // that moved is found again through the list's update).
  System moving = two_bodies(dir, 4 * h, &c);
  compute_forces(moving, false);
  EXPECT_EQ(norm(moving.particles.f[0]), 0.0);
  for (double gap : {3.0 * h, 2.2 * h, 1.6 * h, 1.2 * h}) {
    moving.particles.u[1] = dir * gap - moving.particles.X[1];
    compute_forces(moving, false);
  }
  EXPECT_NEAR(moving.particles.f[0].x, -f * dir.x, 1e-9 * f);
  EXPECT_GE(moving.contact.rebuilds(), 4u);
  // Beyond the contact distance: nothing.
  System apart = two_bodies(dir, 1.36 * h, &c);
  compute_forces(apart, false);
  EXPECT_EQ(norm(apart.particles.f[0]), 0.0);
  EXPECT_EQ(norm(apart.particles.f[1]), 0.0);
  // Contact off: nothing either.
  System off = two_bodies(dir, 1.2 * h, &c);
  off.contact.setup(ShortRangeContactConfig{}, h, delta);
  build_kind_coefficients(off, DamageMeasure::weighted);
  compute_forces(off, false);
  EXPECT_EQ(norm(off.particles.f[0]), 0.0);
}

TEST(LammpsRules, ContactActsOnBondedAndBrokenPairs) {
  // Two bonded particles pressed to 0.8 h: the bond pushes back with c s V_j and the
  // contact (d = 0.9 h) adds 15 c V_j (0.9 h - 0.8 h)/delta, also once the bond is broken.
  const double h = 1e-3;
  test::BlockSpec b;
  b.n = {2, 1, 1};
  b.horizon_factor = 1.5;
  MaterialConfig mat = test::make_material("pmb", 1e9, 0.25);
  Config cfg = test::block_config(b, mat);
  cfg.contact.short_range.enabled = true;
  System s = build_system(cfg);
  ASSERT_EQ(s.bonds.size(), 2u);
  s.particles.u[1] = {-0.2 * h, 0, 0};
  compute_forces(s, false);
  const double c = 2 * s.model.pair_coef[0], V = s.particles.volume[1], delta = 1.5 * h;
  const double bond = c * 0.2 * V, contact = 15 * c * V * 0.1 * h / delta;
  EXPECT_NEAR(s.particles.f[0].x, -(bond + contact), 1e-9 * (bond + contact));
  EXPECT_NEAR(s.particles.f[1].x, bond + contact, 1e-9 * (bond + contact));
  s.bonds.intact.assign(2, 0);
  refresh_damage(s);
  compute_forces(s, false);
  EXPECT_NEAR(s.particles.f[0].x, -contact, 1e-9 * contact);
  EXPECT_EQ(s.particles.damage[0], 1.0);
}

// Two rows of particles on either side of a precrack slide one spacing past each other
// (a rigid shift of the upper row: no bond is strained). A pair that started diagonally
// across the crack (|xi| = sqrt(2) h) is now face to face at the lattice distance h.
// With LAMMPS's max_distance 1.35 its contact distance is min(0.9 sqrt(2) h, 1.35 h) =
// 1.27 h, so the sliding faces repel (they grind); with max_distance 0.9 every pair's
// distance is 0.9 h and faces at the lattice distance slide freely (docs/input.md).
Vec3 sliding_row_force(double max_distance) {
  const double h = 1e-3;
  test::BlockSpec b;
  b.dimension = 2;
  b.plane = PlaneMode::stress;
  b.n = {9, 2, 1};
  b.horizon_factor = 2.0;
  MaterialConfig mat = test::make_material("pmb", 1e9, 1.0 / 3.0);
  Config cfg = test::block_config(b, mat);
  Precrack crack;
  crack.points = {Vec3{-h, 0.5 * h, 0}, Vec3{9 * h, 0.5 * h, 0}};
  cfg.precracks = {crack};
  cfg.contact.short_range.enabled = true;
  cfg.contact.short_range.max_distance = max_distance;
  System s = build_system(cfg);
  for (std::size_t i = 0; i < s.particles.size(); ++i)
    if (s.particles.X[i].y > 0.5 * h) s.particles.u[i] = {h, 0, 0};
  compute_forces(s, false);
  // The middle particle of the lower row: its upper neighbours are at (x, h) and (x +- h, h)
  // in the current positions, as before the shift, but now they are other particles.
  return s.particles.f[s.particles.size() / 4];
}

TEST(LammpsRules, SlidingCrackFacesGrindOnlyWithContactBeyondOneSpacing) {
  const Vec3 grind = sliding_row_force(1.35);
  EXPECT_LT(grind.y, 0.0) << "the shifted upper row pushes the lower row down";
  const Vec3 free = sliding_row_force(0.9);
  EXPECT_EQ(free.x, 0.0);
  EXPECT_EQ(free.y, 0.0);
}

// ---------------------------------------------------------------------------------
// Rigid indenter: force density K (R - r)^2 along (y - c)/r inside the sphere.

TEST(LammpsRules, IndenterForce) {
  const double h = 1e-3;
  test::BlockSpec b;
  b.n = {3, 1, 1};
  b.horizon_factor = 1.5;
  Config cfg = test::block_config(b, test::make_material("pmb", 1e9, 0.25));
  IndenterConfig ic;
  ic.name = "ball";
  ic.center = {Expression("0"), Expression("0.0025 - 100*t"), Expression("0")};
  ic.radius = 2.2e-3;
  ic.stiffness = 1e17;
  cfg.contact.indenters = {ic};
  System s = build_system(cfg);
  Loads loads(cfg, s);
  const double t = 0;  // centre at (0, 0.0025, 0): particle 0 at r = 2.5e-3 > R
  loads.apply_forces(s, t);
  EXPECT_EQ(norm(s.particles.b[0]), 0.0);
  const double t2 = 6e-6;  // centre at (0, 0.0019, 0): particle 0 (r = 1.9e-3), particle 1 (2.15e-3)
  loads.apply_forces(s, t2);
  const double K = 1e17, R = 2.2e-3;
  const double r0 = 1.9e-3, b0 = K * (R - r0) * (R - r0);
  EXPECT_NEAR(s.particles.b[0].y, -b0, 1e-9 * b0);  // pushed out of the sphere: down
  EXPECT_NEAR(s.particles.b[0].x, 0.0, 1e-9 * b0);
  const Vec3 d1 = s.particles.X[1] - Vec3{0, 0.0019, 0};
  const double r1 = norm(d1), b1 = K * (R - r1) * (R - r1);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(s.particles.b[1][k], b1 * d1[k] / r1, 1e-9 * b1);
  EXPECT_EQ(norm(s.particles.b[2]), 0.0) << "particle 2 is at r = 2.76e-3 > R";
  // The indenter's total force on the body, reported as the load's reaction.
  loads.update_reactions(s, s.particles.u);
  const AppliedLoad& L = loads.loads().back();
  EXPECT_EQ(L.name, "ball");
  EXPECT_NEAR(L.reaction.y, (s.particles.b[0].y + s.particles.b[1].y) * h * h * h, 1e-9 * b0 * h * h * h);
}

// ---------------------------------------------------------------------------------
// The AVX-512, AVX2 and scalar bond loops give the same bits, on the LAMMPS problem shrunk
// to fit a unit test (PMB and LPS, breaking after the force, contact, indenter).

struct Snapshot {
  std::vector<Vec3> u, v, f;
  std::vector<double> damage, dissipated;
  uint64_t broken = 0;
};

// model: pmb or lps, breaking after the force as LAMMPS does; with "_now", breaking before
// it (the rows' other branch: a breaking bond carries no force in its step).
Snapshot run_small(const std::string& name, KernelPath path, int threads) {
  set_kernel_path(path);
  omp_set_num_threads(threads);
  std::string deck = kCylinder;
  const bool now = name.size() > 4 && name.substr(name.size() - 4) == "_now";
  const std::string model = now ? name.substr(0, name.size() - 4) : name;
  if (now) deck.replace(deck.find(", breaks: after_force"), 21, "");
  if (model == "lps") {
    deck.replace(deck.find("micromodulus: 1.6863e22"), 23,
                 "bulk_modulus: 14.9e9, shear_modulus: 14.9e9, influence: inverse");
    deck.replace(deck.find("model: pmb"), 10, "model: lps");
  }
  Config c = parse_deck(deck, "small.yaml");
  // A quarter of the cylinder's radius and height; a faster indenter breaks bonds sooner.
  c.bodies[0].shape = Shape::cylinder({0, -0.0015, 0}, {0, 0, 0}, 0.0025);
  c.contact.indenters[0].center[1] = Expression("0.00155 - 1000*t");
  System s = build_system(c);
  Loads loads(c, s);
  ExplicitSolver solver(s, loads, 1e-7, 0.0);
  solver.initialize();
  for (int step = 0; step < 40; ++step) solver.step(step % 10 == 0);
  set_kernel_path(KernelPath::automatic);
  return {s.particles.u, s.particles.v, s.particles.f, s.particles.damage, s.dissipated_at, s.broken};
}

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

TEST(LammpsRules, ScalarAndVectorLoopsGiveTheSameBits) {
  const int saved = omp_get_max_threads();
  std::printf("[ kernels ] vector path on this CPU: %s\n", kernel_path_name());
  for (const std::string model : {"pmb", "lps", "pmb_now", "lps_now"}) {
    const Snapshot a = run_small(model, KernelPath::scalar, 1);
    const Snapshot b = run_small(model, KernelPath::automatic, 1);
    const Snapshot c = run_small(model, KernelPath::automatic, 2);
    const Snapshot d = run_small(model, KernelPath::avx2, 1);  // AVX2 even where AVX-512 runs
    std::printf("[ kernels ] %s: %llu directed bonds broken\n", model.c_str(),
                static_cast<unsigned long long>(a.broken));
    EXPECT_GT(a.broken, 0u) << model;
    for (const Snapshot* o : {&b, &c, &d}) {
      EXPECT_EQ(a.broken, o->broken) << model;
      EXPECT_TRUE(same_bits(a.u, o->u)) << model;
      EXPECT_TRUE(same_bits(a.v, o->v)) << model;
      EXPECT_TRUE(same_bits(a.f, o->f)) << model;
      EXPECT_TRUE(same_bits(a.damage, o->damage)) << model;
      EXPECT_TRUE(same_bits(a.dissipated, o->dissipated)) << model;
    }
  }
  omp_set_num_threads(saved);
}

// The general force pass (solver/forces_general.hpp, which every non-unified model takes)
// run on the unified models: the same physics as the fast loops, summed in another order,
// so the same answer to round-off; and the same bits on 1 and 2 threads.
TEST(LammpsRules, GeneralPassMatchesTheFastLoops) {
  const int saved = omp_get_max_threads();
  for (const std::string model : {"pmb", "lps"}) {
    const Snapshot fast = run_small(model, KernelPath::scalar, 1);
    const Snapshot g1 = run_small(model, KernelPath::general, 1);
    const Snapshot g2 = run_small(model, KernelPath::general, 2);
    EXPECT_EQ(g1.broken, g2.broken) << model;
    EXPECT_TRUE(same_bits(g1.u, g2.u)) << model;
    EXPECT_TRUE(same_bits(g1.f, g2.f)) << model;
    EXPECT_TRUE(same_bits(g1.damage, g2.damage)) << model;
    double umax = 0, du = 0, vmax = 0, dv = 0, dmg = 0;
    for (std::size_t i = 0; i < fast.u.size(); ++i) {
      umax = std::max(umax, norm(fast.u[i]));
      du = std::max(du, norm(fast.u[i] - g1.u[i]));
      vmax = std::max(vmax, norm(fast.v[i]));
      dv = std::max(dv, norm(fast.v[i] - g1.v[i]));
      dmg = std::max(dmg, std::abs(fast.damage[i] - g1.damage[i]));
    }
    std::printf("[ general ] %s: %llu vs %llu bonds broken, |du|/|u| %.2e, |dv|/|v| %.2e\n", model.c_str(),
                static_cast<unsigned long long>(fast.broken), static_cast<unsigned long long>(g1.broken), du / umax,
                dv / vmax);
    EXPECT_GT(fast.broken, 0u);
    EXPECT_NEAR(static_cast<double>(g1.broken), static_cast<double>(fast.broken), 0.02 * static_cast<double>(fast.broken))
        << model;
    EXPECT_LT(du, 1e-10 * umax) << model;
    EXPECT_LT(dv, 1e-9 * vmax) << model;
  }
  omp_set_num_threads(saved);
}

}  // namespace
}  // namespace horizon
