#pragma once
// A rigid spherical indenter (LAMMPS fix indent, sphere style): every particle at a
// distance r < R from the centre c(t) feels the force density
//     K (R - r)^2 (y - c)/r,
// pushing it out of the sphere. The body pushes back on the indenter with minus the
// sum of these forces times the particle volumes. The pass is contact/rigid_contact.hpp's
// (law quadratic), shared with the free projectiles.
#include "horizon/contact/rigid_contact.hpp"
#include "horizon/deck/config.hpp"

namespace horizon {

struct System;

class Indenter {
 public:
  Indenter() = default;
  explicit Indenter(const IndenterConfig& config);

  Vec3 center(double t) const;
  // Adds the indenter's force density at time t to particles.b; returns the total
  // force it applies to the body [N].
  Vec3 apply(System& s, double t) const;

  const IndenterConfig& config() const { return config_; }

 private:
  IndenterConfig config_;
  RigidShape shape_;
};

}  // namespace horizon
