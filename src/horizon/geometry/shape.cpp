#include "horizon/geometry/shape.hpp"

#include "horizon/geometry/surface.hpp"

#include <algorithm>
#include <limits>

namespace horizon {

namespace {
constexpr double kHuge = 1e300;
// Points on a face count as inside: a lattice point that lands exactly on a box face
// is kept. The tolerance is relative to the size of the coordinates.
bool le(double a, double b) { return a <= b + 1e-12 * (std::abs(a) + std::abs(b) + 1e-300); }
}  // namespace

Shape Shape::box(Vec3 min, Vec3 max) {
  Shape s;
  s.kind_ = Kind::box;
  s.a_ = min;
  s.b_ = max;
  return s;
}

Shape Shape::cylinder(Vec3 a, Vec3 b, double radius) {
  Shape s;
  s.kind_ = Kind::cylinder;
  s.a_ = a;
  s.b_ = b;
  s.radius_ = radius;
  return s;
}

Shape Shape::sphere(Vec3 center, double radius) {
  Shape s;
  s.kind_ = Kind::sphere;
  s.a_ = center;
  s.radius_ = radius;
  return s;
}

Shape Shape::half_space(Vec3 point, Vec3 normal) {
  Shape s;
  s.kind_ = Kind::half_space;
  s.a_ = point;
  s.b_ = normal / norm(normal);
  return s;
}

Shape Shape::union_of(std::vector<Shape> parts) {
  Shape s;
  s.kind_ = Kind::union_of;
  s.parts_ = std::move(parts);
  return s;
}

Shape Shape::difference(std::vector<Shape> parts) {
  Shape s;
  s.kind_ = Kind::difference;
  s.parts_ = std::move(parts);
  return s;
}

Shape Shape::points(std::vector<Vec3> at, std::vector<double> volumes) {
  Shape s;
  s.kind_ = Kind::points;
  s.points_ = std::move(at);
  s.volumes_ = std::move(volumes);
  s.by_x_.reserve(s.points_.size());
  double scale = 0;
  for (std::size_t i = 0; i < s.points_.size(); ++i) {
    s.by_x_.emplace_back(s.points_[i].x, i);
    for (int k = 0; k < 3; ++k) scale = std::max(scale, std::abs(s.points_[i][k]));
  }
  std::sort(s.by_x_.begin(), s.by_x_.end());
  s.tolerance_ = 1e-9 * std::max(scale, 1e-300);
  return s;
}

Shape Shape::surface(std::shared_ptr<const ClosedSurface> solid) {
  Shape s;
  s.kind_ = Kind::surface;
  s.surface_ = std::move(solid);
  return s;
}

bool Shape::contains(const Vec3& p) const {
  switch (kind_) {
    case Kind::surface:
      return surface_->contains(p);
    case Kind::points: {
      auto it = std::lower_bound(by_x_.begin(), by_x_.end(), std::make_pair(p.x - tolerance_, std::size_t{0}));
      for (; it != by_x_.end() && it->first <= p.x + tolerance_; ++it)
        if (norm(points_[it->second] - p) <= tolerance_) return true;
      return false;
    }
    case Kind::box:
      return le(a_.x, p.x) && le(p.x, b_.x) && le(a_.y, p.y) && le(p.y, b_.y) && le(a_.z, p.z) &&
             le(p.z, b_.z);
    case Kind::cylinder: {
      const Vec3 axis = b_ - a_;
      const double len2 = norm2(axis);
      const double s = dot(p - a_, axis) / len2;
      if (!le(0.0, s) || !le(s, 1.0)) return false;
      const Vec3 radial = (p - a_) - axis * s;
      return le(norm2(radial), radius_ * radius_);
    }
    case Kind::sphere:
      return le(norm2(p - a_), radius_ * radius_);
    case Kind::half_space:
      return le(dot(p - a_, b_), 0.0);
    case Kind::union_of:
      return std::any_of(parts_.begin(), parts_.end(), [&](const Shape& s) { return s.contains(p); });
    case Kind::difference:
      if (parts_.empty() || !parts_[0].contains(p)) return false;
      return std::none_of(parts_.begin() + 1, parts_.end(), [&](const Shape& s) { return s.contains(p); });
  }
  return false;
}

Box3 Shape::bounds() const {
  switch (kind_) {
    case Kind::surface:
      return {surface_->min(), surface_->max()};
    case Kind::box:
      return {a_, b_};
    case Kind::cylinder: {
      // Exact box of a cylinder: along each axis e, the end discs reach radius*sqrt(1-(d.e)^2).
      const Vec3 d = (b_ - a_) / norm(b_ - a_);
      Box3 r;
      for (int k = 0; k < 3; ++k) {
        const double ext = radius_ * std::sqrt(std::max(0.0, 1.0 - d[k] * d[k]));
        r.min[k] = std::min(a_[k], b_[k]) - ext;
        r.max[k] = std::max(a_[k], b_[k]) + ext;
      }
      return r;
    }
    case Kind::sphere:
      return {a_ - Vec3{radius_, radius_, radius_}, a_ + Vec3{radius_, radius_, radius_}};
    case Kind::half_space:
      return {{-kHuge, -kHuge, -kHuge}, {kHuge, kHuge, kHuge}};
    case Kind::union_of: {
      Box3 r{{kHuge, kHuge, kHuge}, {-kHuge, -kHuge, -kHuge}};
      for (const auto& s : parts_) {
        const Box3 b = s.bounds();
        for (int k = 0; k < 3; ++k) {
          r.min[k] = std::min(r.min[k], b.min[k]);
          r.max[k] = std::max(r.max[k], b.max[k]);
        }
      }
      return r;
    }
    case Kind::difference:
      return parts_.empty() ? Box3{} : parts_[0].bounds();
    case Kind::points: {
      Box3 r{{kHuge, kHuge, kHuge}, {-kHuge, -kHuge, -kHuge}};
      for (const auto& q : points_)
        for (int k = 0; k < 3; ++k) {
          r.min[k] = std::min(r.min[k], q[k]);
          r.max[k] = std::max(r.max[k], q[k]);
        }
      return r;
    }
  }
  return {};
}

}  // namespace horizon
