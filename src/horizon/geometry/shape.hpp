#pragma once
// Solid shapes: primitives combined by union and subtraction. A shape answers one
// question, "is this point inside?", and gives a bounding box for the lattice.
#include <memory>
#include <string>
#include <vector>

#include "horizon/core/vec3.hpp"

namespace horizon {

struct Box3 {
  Vec3 min, max;
};

class Shape {
 public:
  enum class Kind { box, cylinder, sphere, half_space, union_of, difference, points };

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

  // A finite set of points (the particles of a mesh: element centres), matched exactly;
  // `measures` (volume in 3-D, area in 2-D, one per point) when the set is a body, empty
  // when it only selects particles (a region).
  static Shape points(std::vector<Vec3> points, std::vector<double> measures);

  bool contains(const Vec3& p) const;
  // Kind::points only: the points and their measures.
  const std::vector<Vec3>& point_list() const;
  const std::vector<double>& point_measures() const;
  // Whether a point set appears anywhere in this shape.
  bool has_points() const;
  // Bounding box; unbounded shapes (half spaces) report +-1e300.
  Box3 bounds() const;
  Kind kind() const { return kind_; }

 private:
  Kind kind_ = Kind::box;
  Vec3 a_, b_;          // box min/max, cylinder ends, sphere centre, half-space point/normal
  double radius_ = 0;
  std::vector<Shape> parts_;
  struct PointSet;
  std::shared_ptr<const PointSet> points_;
};

}  // namespace horizon
