#include "horizon/contact/rigid_contact.hpp"

#include "horizon/core/parallel_select.hpp"

#include <algorithm>
#include <cmath>

#include "horizon/parallel/decomposition.hpp"
#include "horizon/state/system.hpp"

namespace horizon {

RigidShape::RigidShape(const RigidShapeConfig& c) : c_(c) {
  if (c_.kind == RigidShapeKind::ogive) {
    // Tangent ogive of caliber 2a and caliber-radius-head psi: arc radius s = 2 psi a,
    // nose length l = sqrt(s^2 - (s - a)^2) = a sqrt(4 psi - 1) (e.g. Forrestal and
    // Piekutowski 2000, Int. J. Impact Eng. 24, eq. 1; seed 002 digest sec. 9.3).
    arc_ = 2 * c_.crh * c_.radius;
    nose_ = c_.radius * std::sqrt(4 * c_.crh - 1);
    const double n = norm(c_.axis);
    c_.axis = c_.axis / n;
  }
}

bool RigidShape::penetration(const Vec3& d, Penetration& p) const {
  const double a = c_.radius;
  if (c_.kind == RigidShapeKind::sphere) {
    const double r2 = norm2(d);
    if (!(r2 < a * a) || r2 == 0) return false;
    const double r = std::sqrt(r2);
    p.depth = a - r;
    p.normal = d / r;
    return true;
  }
  // Ogive: z along the body from the tip (z = -d.axis), rho the distance from the axis.
  const Vec3& e = c_.axis;
  const double z = -dot(d, e);
  const double total = nose_ + c_.length;
  if (z <= 0 || z >= total) return false;
  const Vec3 radial_v = d + e * z;  // the part of d normal to the axis
  const double rho = norm(radial_v);
  const Vec3 radial = rho > 0 ? radial_v / rho : Vec3{};
  const double back = total - z;  // depth below the rear face, normal -e
  double side = 0;
  Vec3 side_n;
  if (z < nose_) {
    // The meridian arc: centre at (z, rho) = (l, -(s - a)), radius s; inside when the
    // point is within s of it.
    const double dz = z - nose_, dr = rho + (arc_ - a);
    const double q = std::sqrt(dz * dz + dr * dr);
    if (!(q < arc_)) return false;
    side = arc_ - q;
    side_n = (radial * dr - e * dz) / q;  // (dz along -e, dr along radial), normalised
  } else {
    if (!(rho < a)) return false;
    side = a - rho;
    side_n = radial;
    if (rho == 0) side_n = e;  // on the axis of the shank: push forward (any direction would do)
  }
  if (back < side) {
    p.depth = back;
    p.normal = -e;
  } else {
    p.depth = side;
    p.normal = side_n;
  }
  return true;
}

double RigidShape::volume() const {
  const double a = c_.radius;
  if (c_.kind == RigidShapeKind::sphere) return 4.0 / 3.0 * M_PI * a * a * a;
  // Nose: pi int_0^l r(z)^2 dz, r(z) = sqrt(s^2 - (l - z)^2) - (s - a), Simpson's rule.
  const int n = 2000;
  const double h = nose_ / n;
  double sum = 0;
  for (int k = 0; k <= n; ++k) {
    const double z = k * h, t = nose_ - z;
    const double r = std::max(0.0, std::sqrt(std::max(0.0, arc_ * arc_ - t * t)) - (arc_ - a));
    sum += (k == 0 || k == n ? 1 : (k % 2 ? 4 : 2)) * r * r;
  }
  return M_PI * sum * h / 3 + M_PI * a * a * c_.length;
}

double RigidShape::reach() const {
  if (c_.kind == RigidShapeKind::sphere) return c_.radius;
  const double total = nose_ + c_.length;
  return std::sqrt(total * total + c_.radius * c_.radius);
}

double penalty_stiffness(ContactLaw law, double stiffness, double max_penetration) {
  return law == ContactLaw::linear ? stiffness : 2 * stiffness * max_penetration;
}

Vec3 push_particles(System& s, const RigidShape& shape, const Vec3& at, ContactLaw law, double stiffness,
                    double* energy) {
  auto& P = s.particles;
  const double reach2 = shape.reach() * shape.reach();
  const std::vector<uint32_t>* own = s.owned.empty() ? nullptr : &s.owned;
  const std::size_t n = own ? own->size() : P.size();
  // The threads find the particles inside the shape; one pass over those in particle
  // order then adds the force densities and their total, the same on any thread count.
  auto inside = [&](std::size_t k, Penetration& p) {
    const std::size_t i = own ? (*own)[k] : k;
    const Vec3 d = P.X[i] + P.u[i] - at;
    return norm2(d) < reach2 && shape.penetration(d, p);
  };
  const std::vector<uint32_t> touching = parallel_select(n, [&](std::size_t k) {
    Penetration p;
    return inside(k, p);
  });
  // On the grid in the serial program too (GridSum::exact): the body's force feeds back
  // into the state, so the serial and the MPI program must add it alike.
  GridSum total = GridSum::exact(s, 4);
  Penetration p;
  for (uint32_t k : touching) {
    const std::size_t i = own ? (*own)[k] : k;
    inside(k, p);
    const double mag = law == ContactLaw::linear ? stiffness * p.depth : stiffness * p.depth * p.depth;
    const Vec3 b = p.normal * mag;
    P.b[i] += b;
    total.add(0, b * P.volume[i]);
    if (energy) total.add(3, P.volume[i] * mag * p.depth / (law == ContactLaw::linear ? 2.0 : 3.0));
  }
  const std::vector<double> f = total.totals();
  if (energy) *energy = f[3];
  return {f[0], f[1], f[2]};
}

}  // namespace horizon
