#pragma once
// Solid shapes: primitives combined by union and subtraction. A shape answers one
// question, "is this point inside?", and gives a bounding box for the lattice.
#include <memory>
#include <utility>
#include <string>
#include <vector>

#include "horizon/core/vec3.hpp"

namespace horizon {

class ClosedSurface;

struct Box3 {
  Vec3 min, max;
};

class Shape {
 public:
  enum class Kind { box, cylinder, sphere, half_space, union_of, difference, points, surface };

  static Shape box(Vec3 min, Vec3 max);
  // Cylinder of the given radius around the segment from a to b. In 2-D a cylinder
  // along z is a disk.
  static Shape cylinder(Vec3 a, Vec3 b, double radius);
  static Shape sphere(Vec3 center, double radius);
  // All points p with dot(p - point, normal) <= 0 (normal points out of the solid).
  static Shape half_space(Vec3 point, Vec3 normal);
  static Shape union_of(std::vector<Shape> parts);
  // parts[0] minus every later part.
  static Shape difference(std::vector<Shape> parts);
  // A set of listed points (particles given one by one, as from a text file): contains
  // exactly those points (to 1e-9 of the set's size). As a body's shape each point is one
  // particle of the given volume; as a region it selects the particles at those points.
  static Shape points(std::vector<Vec3> at, std::vector<double> volumes);
  const std::vector<Vec3>& point_list() const { return points_; }
  // The solid inside a closed triangulated surface (geometry/surface.hpp).
  static Shape surface(std::shared_ptr<const ClosedSurface> solid);
  const std::vector<double>& point_volumes() const { return volumes_; }

  bool contains(const Vec3& p) const;
  // Bounding box; unbounded shapes (half spaces) report +-1e300.
  Box3 bounds() const;
  Kind kind() const { return kind_; }

 private:
  Kind kind_ = Kind::box;
  Vec3 a_, b_;          // box min/max, cylinder ends, sphere centre, half-space point/normal
  double radius_ = 0;
  std::vector<Shape> parts_;
  std::vector<Vec3> points_;    // points: as given
  std::vector<double> volumes_;  // points: one volume per point (empty for a region)
  std::shared_ptr<const ClosedSurface> surface_;
  std::vector<std::pair<double, std::size_t>> by_x_;  // points: x and index, sorted
  double tolerance_ = 0;
};

}  // namespace horizon
