// The part of a trilinear hexahedron inside a sphere (geometry/hex_sphere.hpp: Peridigm's
// element-horizon intersections, fitted to its NeighborhoodVolume gold): the volume of a
// parallelepiped, the rule's own closed forms (whole elements, one midpoint), its
// convergence to the octant of a ball, and whether a sphere meets an element whose
// curved face lies inside its nodes' convex hull.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "horizon/geometry/hex_sphere.hpp"

namespace horizon {
namespace {

// The box [0, a] x [0, b] x [0, c] in Exodus order.
Hex8 box(double a, double b, double c) {
  return {Vec3{0, 0, 0}, Vec3{a, 0, 0}, Vec3{a, b, 0}, Vec3{0, b, 0},
          Vec3{0, 0, c}, Vec3{a, 0, c}, Vec3{a, b, c}, Vec3{0, b, c}};
}

TEST(HexSphere, VolumeOfAParallelepiped) {
  // A sheared box: det [a, s, 0; 0, b, 0; t, 0, c] applied to the unit cube.
  Hex8 p = box(1, 1, 1);
  for (Vec3& x : p) x = Vec3{2.0 * x.x + 0.3 * x.y, 1.5 * x.y, 0.4 * x.x + 0.5 * x.z};
  EXPECT_NEAR(hex8_volume(p), 2.0 * 1.5 * 0.5, 1e-15);
}

TEST(HexSphere, WholeElementsAndTheMidpointRule) {
  const Hex8 cube = box(1, 1, 1);
  // Every corner inside: the element's volume, at any level.
  EXPECT_DOUBLE_EQ(hex_sphere_volume(cube, Vec3{0.5, 0.5, 0.5}, 0.9, 2, 2), 1.0);
  // Level 0, one sample: the centre (0.5, 0.5, 0.5), at sqrt(3)/2 = 0.866 from a corner,
  // counts the whole element or none of it.
  EXPECT_DOUBLE_EQ(hex_sphere_volume(cube, Vec3{0, 0, 0}, 0.87, 0, 1), 1.0);
  EXPECT_DOUBLE_EQ(hex_sphere_volume(cube, Vec3{0, 0, 0}, 0.86, 0, 1), 0.0);
  // Level 0, two samples per axis: the cell centres at 0.25 and 0.75; a sphere of radius
  // 0.5 about the origin holds (0.25, 0.25, 0.25) alone (0.433; the next is 0.829): 1/8.
  EXPECT_DOUBLE_EQ(hex_sphere_volume(cube, Vec3{0, 0, 0}, 0.5, 0, 2), 0.125);
  // Level 1, two samples: the child at the origin has its far corner at 0.866 > 0.5, so
  // it is sampled at 0.125, 0.375: (0.125, 0.125, 0.125), (0.375, 0.125, 0.125) x 3
  // (0.415), (0.375, 0.375, 0.125) x 3 (0.545) out: 4 of 8 of its 1/8.
  EXPECT_DOUBLE_EQ(hex_sphere_volume(cube, Vec3{0, 0, 0}, 0.5, 1, 2), 4.0 / 64.0);
}

TEST(HexSphere, ConvergesToTheOctantOfABall) {
  // The unit ball about a corner of the unit cube holds an eighth of it, pi/6.
  const Hex8 cube = box(1, 1, 1);
  const double exact = std::numbers::pi / 6;
  double last = 1;
  for (int levels : {2, 4, 6}) {
    const double err = std::abs(hex_sphere_volume(cube, Vec3{0, 0, 0}, 1.0, levels, 2) - exact);
    EXPECT_LT(err, last) << levels;
    last = err;
  }
  EXPECT_LT(last, 2e-4);
}

TEST(HexSphere, MeetsTheElementNotItsHull) {
  const Hex8 cube = box(1, 1, 1);
  // A sphere beside the face x = 1, one unit from it.
  EXPECT_TRUE(hex_meets_sphere(cube, Vec3{2, 0.5, 0.5}, 1.0001));
  EXPECT_FALSE(hex_meets_sphere(cube, Vec3{2, 0.5, 0.5}, 0.9999));
  // A small sphere inside a large element, no corner within it.
  EXPECT_TRUE(hex_meets_sphere(box(10, 10, 10), Vec3{5, 5, 5}, 0.1));
  // A saddle for a top face: corners 4 and 6 raised to z = 1.5, so the nodes' convex hull
  // has a ridge at z = 1.5 over the diagonal, but the face z = 1 + ((1 - u)(1 - v) + u v)/2
  // is at 1.25 under its middle. From (0.5, 0.5, 1.7) the face's nearest points along the
  // diagonal, (t, t, 1 + ((1 - t)^2 + t^2)/2) with t = 1/2 + s, lie at
  // sqrt(0.2025 + 1.1 s^2 + s^4) >= 0.45; the hull's ridge at 0.2.
  Hex8 saddle = cube;
  saddle[4].z = 1.5;
  saddle[6].z = 1.5;
  EXPECT_FALSE(hex_meets_sphere(saddle, Vec3{0.5, 0.5, 1.7}, 0.3));
  EXPECT_FALSE(hex_meets_sphere(saddle, Vec3{0.5, 0.5, 1.7}, 0.449));
  EXPECT_TRUE(hex_meets_sphere(saddle, Vec3{0.5, 0.5, 1.7}, 0.451));
}

}  // namespace
}  // namespace horizon
