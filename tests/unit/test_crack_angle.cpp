// The crack angle of the Kalthoff-Winkler report (damage/crack_angle.hpp) on synthetic
// damage fields with a known answer: a straight crack of damage 0.8 (its faces 0.5) leaves
// the tip at a set angle, beside it lies a fan of diffuse damage 0.4 (bonds broken in the
// sheared zone ahead of the crack) and away from it a strongly damaged patch under the
// notch line (the far edge of the struck strip). The ridge fit must return the crack's
// angle, with its sign, whatever the notch direction; a plain fit through every damaged
// particle of the window (the measure used before) is pulled far off by the distractors.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "horizon/damage/crack_angle.hpp"

namespace horizon {
namespace {

constexpr double kH = 1.0e-3;         // lattice spacing
constexpr double kDelta = 4.0 * kH;   // horizon
constexpr double kThreshold = 0.35;   // as in driver/run.cpp
constexpr double kDeg = std::numbers::pi / 180.0;

Vec3 rotate(const Vec3& d, double degrees) {
  const double c = std::cos(degrees * kDeg), s = std::sin(degrees * kDeg);
  return {c * d.x - s * d.y, s * d.x + c * d.y, 0};
}

// A square lattice around `tip` (+-12 horizons). In the frame of the notch (along d, side
// n = z x d) a particle at angle a (degrees, from d towards n) and distance r from the tip
// gets: 0.8 within 0.6 h of the crack ray at `crack_deg`, 0.5 within 1.6 h (the crack
// faces); 0.4 in the fan 10..40 degrees from the crack towards the notch line (shadow side
// of the crack), r in [1, 6] horizons; 0.95 in the patch -35..-5 degrees, r in [5, 8]
// horizons. Only particles ahead of the tip are damaged.
Particles synthetic(const Vec3& tip, const Vec3& d, double crack_deg, bool distractors) {
  Particles p;
  const Vec3 n{-d.y, d.x, 0};
  const Vec3 u = rotate(d, crack_deg);
  const double sign = crack_deg >= 0 ? 1.0 : -1.0;
  const int m = static_cast<int>(12 * kDelta / kH);
  for (int i = -m; i <= m; ++i)
    for (int j = -m; j <= m; ++j) {
      const Vec3 x{tip.x + (i + 0.5) * kH, tip.y + (j + 0.5) * kH, 0};
      p.add(x, kH * kH, 1.0, 0, 0);
      const Vec3 r = x - tip;
      const double along = dot(r, u), across = std::abs(r.x * u.y - r.y * u.x);
      const double dist = std::sqrt(dot(r, r));
      const double a = std::atan2(dot(r, n), dot(r, d)) / kDeg;
      double D = 0;
      if (along > 0 && across < 0.6 * kH) D = 0.8;
      else if (along > 0 && across < 1.6 * kH) D = 0.5;
      else if (distractors) {
        const double off = sign * (crack_deg - a);  // degrees from the crack towards the notch line
        if (off > 10 && off < 40 && dist > kDelta && dist < 6 * kDelta) D = 0.4;
        if (sign * a > -35 && sign * a < -5 && dist > 5 * kDelta && dist < 8 * kDelta) D = 0.95;
      }
      if (dot(r, d) < 0) D = 0;
      p.damage.back() = D;
    }
  return p;
}

CrackAngle measure(const Particles& p, const Vec3& tip, const Vec3& d) {
  return crack_angle(p, tip, d, kThreshold, 2 * kDelta, 8 * kDelta, kH, kDelta);
}

// The former measure: principal axis of every particle with damage >= threshold in the
// window, unsigned angle.
double plain_fit(const Particles& p, const Vec3& tip, const Vec3& d) {
  double sxx = 0, sxy = 0, syy = 0, mx = 0, my = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec3 r = p.X[i] - tip;
    const double dist = std::sqrt(dot(r, r));
    if (p.damage[i] < kThreshold || dist < 2 * kDelta || dist > 8 * kDelta || dot(r, d) < 0) continue;
    sxx += r.x * r.x, sxy += r.x * r.y, syy += r.y * r.y, mx += r.x, my += r.y;
  }
  const double phi = 0.5 * std::atan2(2 * sxy, sxx - syy);
  double ux = std::cos(phi), uy = std::sin(phi);
  if (ux * mx + uy * my < 0) ux = -ux, uy = -uy;
  return std::atan2(std::abs(ux * d.y - uy * d.x), ux * d.x + uy * d.y) / kDeg;
}

TEST(CrackAngle, StraightCrackGivesItsAngle) {
  const Vec3 tip{0.05, 0.025, 0}, d{1, 0, 0};
  for (double angle : {30.0, 66.0, 70.0}) {
    const CrackAngle a = measure(synthetic(tip, d, angle, false), tip, d);
    ASSERT_TRUE(a.found);
    EXPECT_NEAR(a.degrees, angle, 1.0) << angle;
    EXPECT_GE(a.points, static_cast<std::size_t>(6 * kDelta / kH) - 2);
  }
}

TEST(CrackAngle, IgnoresTheFanAndDamageAwayFromTheCrack) {
  const Vec3 tip{0.05, 0.025, 0}, d{1, 0, 0};
  const Particles p = synthetic(tip, d, 66.0, true);
  const CrackAngle a = measure(p, tip, d);
  ASSERT_TRUE(a.found);
  EXPECT_NEAR(a.degrees, 66.0, 1.0);
  // The distractors are strong: the plain fit is pulled more than 15 degrees off.
  EXPECT_GT(std::abs(plain_fit(p, tip, d) - 66.0), 15.0);
}

TEST(CrackAngle, SignFollowsTheSideTheCrackTurnsTo) {
  // Kalthoff: the lower notch's crack is the mirror image of the upper one's.
  const Vec3 tip{0.05, -0.025, 0}, d{1, 0, 0};
  const CrackAngle a = measure(synthetic(tip, d, -66.0, true), tip, d);
  ASSERT_TRUE(a.found);
  EXPECT_NEAR(a.degrees, -66.0, 1.0);
}

TEST(CrackAngle, MeasuredFromTheNotchDirection) {
  // A notch running along -y (struck edge on top); the crack turns 60 degrees
  // counter-clockwise from it, i.e. towards +x.
  const Vec3 tip{0.0, 0.0, 0}, d{0, -1, 0};
  const CrackAngle a = measure(synthetic(tip, d, 60.0, true), tip, d);
  ASSERT_TRUE(a.found);
  EXPECT_NEAR(a.degrees, 60.0, 1.0);
}

TEST(CrackAngle, NoCrackNoAngle) {
  const Vec3 tip{0.05, 0.025, 0}, d{1, 0, 0};
  Particles p = synthetic(tip, d, 66.0, false);
  for (double& D : p.damage) D = 0.2;  // below the threshold everywhere
  EXPECT_FALSE(measure(p, tip, d).found);
}

}  // namespace
}  // namespace horizon
