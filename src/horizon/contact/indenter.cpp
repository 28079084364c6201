#include "horizon/contact/indenter.hpp"

#include "horizon/contact/rigid_contact.hpp"

#include <cmath>

#include "horizon/state/system.hpp"

namespace horizon {

Indenter::Indenter(const IndenterConfig& config) : config_(config) {
  RigidShapeConfig sphere;
  sphere.radius = config.radius;
  shape_ = RigidShape(sphere);
}

Vec3 Indenter::center(double t) const {
  Vec3 c;
  for (int k = 0; k < 3; ++k)
    if (config_.center[k]) c[k] = (*config_.center[k])(t, 0, 0, 0);
  return c;
}

Vec3 Indenter::apply(System& s, double t) const {
  return push_particles(s, shape_, center(t), ContactLaw::quadratic, config_.stiffness);
}

}  // namespace horizon
