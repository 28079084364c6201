// Short-range contact with law peridigm (Peridigm's Short Range Force, users' guide
// SAND2012-7800; state/short_range.hpp): force density on i
// 2 x 9k/(pi delta^4) V_j (R_c - r)/delta away from j when r < R_c (Peridigm's c = 9k/(pi
// delta^4), which each particle of a pair receives from both particles' contact lists:
// Contact_2x1x1's gold, docs/peridigm.md "Contact"), only between pairs not
// bonded at the start, Coulomb friction mu |f_n| against the sliding, and `pairs`.
#include <gtest/gtest.h>

#include <cmath>

#include "horizon/solver/forces.hpp"
#include "test_helpers.hpp"

namespace horizon {
namespace {

constexpr double kH = 1e-3, kDelta = 3.0001e-3, kSpring = 1e9, kPi = 3.14159265358979323846;

ShortRangeContactConfig peridigm_law(double radius, double friction = 0) {
  ShortRangeContactConfig c;
  c.enabled = true;
  c.law = ShortRangeLaw::peridigm;
  c.contact_radius = radius;
  c.spring_constant = kSpring;
  c.friction = friction;
  return c;
}

// Single-particle bodies at x = 0, 5h, 10h, ... (no bonds), body k named "b<k>".
System bodies(int count, const ShortRangeContactConfig& contact) {
  Config c;
  c.dimension = 3;
  c.spacing = kH;
  c.horizon = kDelta;
  c.lattice_origin = Vec3{};
  c.materials = {test::make_material("pmb", 1e9, 0.25)};
  for (int k = 0; k < count; ++k) {
    const double x = 5 * k * kH;
    c.bodies.push_back(BodyConfig{"b" + std::to_string(k), "solid",
                                  Shape::box({x - 0.5 * kH, -0.5 * kH, -0.5 * kH}, {x + 0.5 * kH, 0.5 * kH, 0.5 * kH})});
  }
  c.contact.short_range = contact;
  System s = build_system(c);
  EXPECT_EQ(s.bonds.size(), 0u);
  return s;
}

double peridigm_force(double V, double radius, double r) {
  return 18 * kSpring / (kPi * std::pow(kDelta, 4)) * V * (radius - r) / kDelta;
}

TEST(PeridigmContact, ForceIsPeridigmsShortRangeForce) {
  const Vec3 dir = Vec3{2, 1, 2} / 3.0;
  System s = bodies(2, peridigm_law(1.3 * kH));
  s.particles.u[1] = dir * (1.1 * kH) - s.particles.X[1];
  compute_forces(s, true);
  const double f = peridigm_force(s.particles.volume[1], 1.3 * kH, 1.1 * kH);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(s.particles.f[0][k], -f * dir[k], 1e-12 * f) << k;
    EXPECT_NEAR(s.particles.f[1][k], f * dir[k], 1e-12 * f) << k;
  }
  // The same distance for every pair: R_c, not a fraction of the reference distance.
  System apart = bodies(2, peridigm_law(1.3 * kH));
  apart.particles.u[1] = dir * (1.31 * kH) - apart.particles.X[1];
  compute_forces(apart, false);
  EXPECT_EQ(norm(apart.particles.f[0]), 0.0);
}

TEST(PeridigmContact, BondedPairsDoNotTouch) {
  // Two bonded particles pressed to 0.8 h: only the bond pushes back (the LAMMPS law
  // would add its contact, test_lammps_rules ContactActsOnBondedAndBrokenPairs).
  test::BlockSpec b;
  b.n = {2, 1, 1};
  b.horizon_factor = 1.5;
  Config cfg = test::block_config(b, test::make_material("pmb", 1e9, 0.25));
  cfg.contact.short_range = peridigm_law(0.9 * kH);
  System s = build_system(cfg);
  ASSERT_EQ(s.bonds.size(), 2u);
  s.particles.u[1] = {-0.2 * kH, 0, 0};
  compute_forces(s, false);
  const double bond = 2 * s.model.pair_coef[0] * 0.2 * s.particles.volume[1];
  EXPECT_NEAR(s.particles.f[0].x, -bond, 1e-12 * bond);
  s.bonds.intact.assign(2, 0);  // nor once the bond is broken
  refresh_damage(s);
  compute_forces(s, false);
  EXPECT_EQ(norm(s.particles.f[0]), 0.0);
}

TEST(PeridigmContact, FrictionOpposesSliding) {
  System s = bodies(2, peridigm_law(1.3 * kH, 0.3));
  s.particles.u[1] = Vec3{1.1 * kH, 0, 0} - s.particles.X[1];
  s.particles.v[1] = {4.0, 3.0, 0.0};  // slides along +y (and closes along x: not friction)
  compute_forces(s, false);
  const double fn = peridigm_force(s.particles.volume[1], 1.3 * kH, 1.1 * kH);
  EXPECT_NEAR(s.particles.f[0].x, -fn, 1e-12 * fn);
  EXPECT_NEAR(s.particles.f[0].y, 0.3 * fn, 1e-12 * fn);   // dragged along with particle 1
  EXPECT_NEAR(s.particles.f[1].y, -0.3 * fn, 1e-12 * fn);  // held back by particle 0
  EXPECT_EQ(s.particles.f[0].z, 0.0);
}

TEST(PeridigmContact, PairsKeepOnlyTheListedBodies) {
  // b0 at 0, b1 at 5h, b2 at 10h; b1 and b2 pressed onto b0. Only b0-b1 touch.
  ShortRangeContactConfig c = peridigm_law(1.3 * kH);
  c.pairs = {{"b1", "b0"}};
  System s = bodies(3, c);
  s.particles.u[1] = Vec3{1.1 * kH, 0, 0} - s.particles.X[1];
  s.particles.u[2] = Vec3{-1.1 * kH, 0, 0} - s.particles.X[2];
  compute_forces(s, false);
  const double f = peridigm_force(s.particles.volume[1], 1.3 * kH, 1.1 * kH);
  EXPECT_NEAR(s.particles.f[0].x, -f, 1e-12 * f);
  EXPECT_EQ(norm(s.particles.f[2]), 0.0);
  // Without pairs (General Contact) b2 also touches b0: b0's net force is zero and b2 is
  // pushed away along -x.
  System all = bodies(3, peridigm_law(1.3 * kH));
  all.particles.u[1] = s.particles.u[1];
  all.particles.u[2] = s.particles.u[2];
  compute_forces(all, false);
  EXPECT_NEAR(all.particles.f[0].x, 0.0, 1e-12 * f);
  EXPECT_NEAR(all.particles.f[2].x, -f, 1e-12 * f);
}

TEST(PeridigmContact, BodiesWithoutBondsBetweenThemTouch) {
  // Two one-particle bodies one spacing apart, within a horizon: bonded by default; with
  // bonds_between_bodies false (Omit Bonds Between Blocks: All) they meet through contact.
  Config c;
  c.dimension = 3;
  c.spacing = kH;
  c.horizon = kDelta;
  c.lattice_origin = Vec3{};
  c.materials = {test::make_material("pmb", 1e9, 0.25)};
  for (int k = 0; k < 2; ++k)
    c.bodies.push_back(BodyConfig{"b" + std::to_string(k), "solid",
                                  Shape::box({k * kH - 0.5 * kH, -0.5 * kH, -0.5 * kH},
                                             {k * kH + 0.5 * kH, 0.5 * kH, 0.5 * kH})});
  c.contact.short_range = peridigm_law(1.3 * kH);
  EXPECT_EQ(build_system(c).bonds.size(), 2u);
  c.bonds_between_bodies = false;
  System s = build_system(c);
  EXPECT_EQ(s.bonds.size(), 0u);
  s.particles.u[1] = {-0.1 * kH, 0, 0};
  compute_forces(s, false);
  const double f = peridigm_force(s.particles.volume[1], 1.3 * kH, 0.9 * kH);
  EXPECT_NEAR(s.particles.f[0].x, -f, 1e-12 * f);
  EXPECT_NEAR(s.particles.f[1].x, f, 1e-12 * f);
}

// Peridigm's search (search_radius, search_every: Contact_Ring's and Contact_Perforation's
// golds, docs/peridigm.md "Contact"): the candidates are found at the positions a step
// starts from (those of the previous step's pass), so a pair that comes within the search
// radius during a step touches from the next step on.
TEST(PeridigmContact, SearchAtTheStepsStartPositions) {
  const double rc = 1.3 * kH;
  ShortRangeContactConfig c = peridigm_law(rc);
  c.search_radius = rc;
  c.search_every = 1;
  System s = bodies(2, c);
  const Vec3 far = Vec3{2.0 * kH, 0, 0} - s.particles.X[1], near = Vec3{1.1 * kH, 0, 0} - s.particles.X[1];
  s.particles.u[1] = far;
  compute_forces(s, false);  // t = 0: searched here, nothing within R_c
  EXPECT_EQ(s.contact.candidates(), 0u);
  s.particles.u[1] = near;   // step 1 closes the gap: searched at step 0's positions
  s.time = 1e-9;
  compute_forces(s, false);
  EXPECT_EQ(norm(s.particles.f[0]), 0.0);
  s.time = 2e-9;             // step 2: searched at step 1's positions, the pair touches
  compute_forces(s, false);
  const double f = peridigm_force(s.particles.volume[1], rc, 1.1 * kH);
  EXPECT_NEAR(s.particles.f[0].x, -f, 1e-12 * f);
  EXPECT_NEAR(s.particles.f[1].x, f, 1e-12 * f);
  // A pass again at the same time is not a new step: the same list.
  compute_forces(s, false);
  EXPECT_NEAR(s.particles.f[0].x, -f, 1e-12 * f);
  // Horizon's own lists (no search_radius) hold the pair at once.
  System own = bodies(2, peridigm_law(rc));
  own.particles.u[1] = far;
  compute_forces(own, false);
  own.particles.u[1] = near;
  own.time = 1e-9;
  compute_forces(own, false);
  EXPECT_NEAR(own.particles.f[0].x, -f, 1e-12 * f);
}

TEST(PeridigmContact, SearchEveryNSteps) {
  // Search every 3 steps within 2 R_c: the list found at step 0 (the pair 3 R_c apart:
  // empty) stands until step 3, which finds the pair at step 2's positions.
  const double rc = 1.3 * kH;
  ShortRangeContactConfig c = peridigm_law(rc);
  c.search_radius = 2 * rc;
  c.search_every = 3;
  System s = bodies(2, c);
  s.particles.u[1] = Vec3{3 * rc, 0, 0} - s.particles.X[1];
  compute_forces(s, false);
  s.particles.u[1] = Vec3{1.1 * kH, 0, 0} - s.particles.X[1];
  const double f = peridigm_force(s.particles.volume[1], rc, 1.1 * kH);
  for (int step = 1; step <= 3; ++step) {
    s.time = step * 1e-9;
    compute_forces(s, false);
    EXPECT_NEAR(s.particles.f[0].x, step < 3 ? 0.0 : -f, 1e-12 * f) << step;
  }
  // Listed, the pair keeps touching between searches; apart, it stops.
  s.time = 4e-9;
  compute_forces(s, false);
  EXPECT_NEAR(s.particles.f[0].x, -f, 1e-12 * f);
  s.particles.u[1] = Vec3{1.5 * rc, 0, 0} - s.particles.X[1];
  s.time = 5e-9;
  compute_forces(s, false);
  EXPECT_EQ(norm(s.particles.f[0]), 0.0);
}

TEST(PeridigmContact, EnergyKeptApartFromTheMaterials) {
  // Peridigm's Stored_Elastic_Energy leaves the contact out (Contact_Ring's gold); the
  // ledger's strain energy keeps it: the pair's 0.5 K V_0 V_1 (R_c - r)^2, K = 18k/(pi delta^5).
  const double rc = 1.3 * kH, r = 1.1 * kH;
  System s = bodies(2, peridigm_law(rc));
  s.particles.u[1] = Vec3{r, 0, 0} - s.particles.X[1];
  compute_forces(s, true);
  EXPECT_EQ(s.particles.energy[0], 0.0);
  EXPECT_EQ(s.particles.energy[1], 0.0);
  const double K = 18 * kSpring / (kPi * std::pow(kDelta, 5));
  const double V0 = s.particles.volume[0], V1 = s.particles.volume[1];
  const double pair = 0.5 * K * V0 * V1 * (rc - r) * (rc - r);
  EXPECT_NEAR(strain_energy(s), pair, 1e-12 * pair);
  // The force is minus the energy's derivative: (E(r - e) - E(r + e))/(2e) = F V_0.
  const double F = peridigm_force(V1, rc, r) * V0;
  EXPECT_NEAR(K * V0 * V1 * (rc - r), F, 1e-12 * F);
}

}  // namespace
}  // namespace horizon
