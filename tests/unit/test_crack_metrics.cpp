// Crack measurement from a damage field (damage/crack_metrics): synthetic damage on a
// 2-D lattice with a crack of known length, plus damage that is not part of the crack.
#include <gtest/gtest.h>

#include "horizon/damage/crack_metrics.hpp"

namespace horizon {
namespace {

constexpr double h = 1e-3;  // lattice spacing

// A 200 x 100 lattice on [0, 0.2) x [-0.05, 0.05) at rest, no damage.
Particles lattice() {
  Particles p;
  for (int i = 0; i < 200; ++i)
    for (int j = -50; j < 50; ++j) p.add({i * h, j * h, 0}, h * h, 1000, 0, 0);
  return p;
}

// Damage d on the particles within half a spacing of the segment a-b.
void damage_segment(Particles& p, Vec3 a, Vec3 b, double d) {
  const Vec3 t = (b - a) / norm(b - a);
  const double len = norm(b - a);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec3 r = p.X[i] - a;
    const double s = dot(r, t);
    if (s < -1e-12 || s > len + 1e-12) continue;
    if (norm(r - t * s) <= 0.5 * h + 1e-12) p.damage[i] = std::max(p.damage[i], d);
  }
}

TEST(CrackMetrics, ConnectedLengthIgnoresDamageAwayFromThePath) {
  Particles p = lattice();
  const Vec3 tip{0.025, 0, 0}, dir{1, 0, 0};
  damage_segment(p, {0, 0, 0}, tip, 0.5);                  // the notch flanks
  damage_segment(p, tip, {0.037, 0, 0}, 0.45);             // 12 mm of crack from the tip
  damage_segment(p, {0.037, 0, 0}, {0.039, 0, 0}, 0.2);    // the process zone, under threshold
  damage_segment(p, {0.19, -0.01, 0}, {0.19, 0.01, 0}, 0.6);  // crushed under an impactor
  damage_segment(p, {0.08, 0.03, 0}, {0.09, 0.03, 0}, 0.4);   // a stray damaged patch

  // Unconnected: the furthest damaged particle anywhere ahead of the tip (the impactor).
  const CrackFront any = crack_front(p, tip, dir, 0.35, 1e300);
  ASSERT_TRUE(any.found);
  EXPECT_NEAR(any.length, 0.165, 1e-9);

  const std::vector<uint8_t> on = connected_crack(p, tip, 0.35, 5.5e-3, 1.5 * h);
  const CrackFront f = crack_front(p, tip, dir, 0.35, 1e300, &on);
  ASSERT_TRUE(f.found);
  EXPECT_NEAR(f.length, 0.012, 1e-9);
  EXPECT_NEAR(f.tip.x, 0.037, 1e-9);
  // The stray patch and the impactor damage are not on the path.
  std::size_t n = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!on[i]) continue;
    ++n;
    EXPECT_LT(p.X[i].x, 0.0375);
  }
  EXPECT_EQ(n, 38u);  // x = 0 .. 37 mm on y = 0
}

TEST(CrackMetrics, GapOfOneIntactParticleBreaksThePath) {
  Particles p = lattice();
  const Vec3 tip{0.025, 0, 0}, dir{1, 0, 0};
  damage_segment(p, tip, {0.030, 0, 0}, 0.5);
  damage_segment(p, {0.032, 0, 0}, {0.045, 0, 0}, 0.5);  // the particle at 31 mm intact
  const std::vector<uint8_t> on = connected_crack(p, tip, 0.35, 5.5e-3, 1.5 * h);
  EXPECT_NEAR(crack_front(p, tip, dir, 0.35, 1e300, &on).length, 0.005, 1e-9);
  // A diagonal step (sqrt(2) h) still joins.
  damage_segment(p, {0.030, 0, 0}, {0.031, 0.001, 0}, 0.5);
  damage_segment(p, {0.031, 0.001, 0}, {0.032, 0, 0}, 0.5);
  const std::vector<uint8_t> joined = connected_crack(p, tip, 0.35, 5.5e-3, 1.5 * h);
  EXPECT_NEAR(crack_front(p, tip, dir, 0.35, 1e300, &joined).length, 0.020, 1e-9);
}

TEST(CrackMetrics, BranchSeenOnTheConnectedPathOnly) {
  Particles p = lattice();
  const Vec3 tip{0.025, 0, 0}, dir{1, 0, 0};
  damage_segment(p, tip, {0.1, 0, 0}, 0.5);  // a straight crack to 100 mm
  // A damaged line parallel to it, 35 mm aside, not joined: no branch on the path...
  damage_segment(p, {0.05, 0.035, 0}, {0.1, 0.035, 0}, 0.5);
  const std::vector<uint8_t> on = connected_crack(p, tip, 0.35, 5.5e-3, 1.5 * h);
  EXPECT_FALSE(branch_distance(p, tip, dir, 0.35, h, 0.011, &on).has_value());
  // ...though the unmasked count sees two clusters from 25 mm past the tip.
  const auto unmasked = branch_distance(p, tip, dir, 0.35, h, 0.011);
  ASSERT_TRUE(unmasked.has_value());
  EXPECT_NEAR(*unmasked, 0.025, 1e-9);
  // A real branch: two arms at +-30 degrees from 40 mm past the tip.
  const Vec3 fork{0.065, 0, 0};
  damage_segment(p, fork, fork + Vec3{0.035, 0.0202, 0}, 0.5);
  damage_segment(p, fork, fork + Vec3{0.035, -0.0202, 0}, 0.5);
  const std::vector<uint8_t> forked = connected_crack(p, tip, 0.35, 5.5e-3, 1.5 * h);
  const auto b = branch_distance(p, tip, dir, 0.35, h, 0.011, &forked);
  ASSERT_TRUE(b.has_value());
  // Each arm is more than the gap (11 mm) from the stem beyond 40 + 19 = 59 mm.
  EXPECT_GT(*b, 0.040);
  EXPECT_LT(*b, 0.065);
}

}  // namespace
}  // namespace horizon
