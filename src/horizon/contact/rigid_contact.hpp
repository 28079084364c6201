#pragma once
// Penalty contact between a rigid shape and the particles (peridynamic particles and
// finite-element nodes alike: both are particles, fe/fe_region.hpp). Shared by the
// prescribed indenter (contact/indenter.hpp) and the free projectile
// (contact/projectile.hpp).
//
// Every particle whose current position y lies inside the shape, at depth d below its
// surface, feels the force density
//     b = K d^p n,   p = 1 (law linear) or 2 (law quadratic, LAMMPS fix indent),
// n the shape's outward normal at the nearest surface point. The shape feels minus the
// sum of b V over the particles (Newton's third law: the pair conserves momentum).
#include "horizon/deck/config.hpp"

namespace horizon {

struct System;

// Depth below the surface (> 0 inside) and outward unit normal there.
struct Penetration {
  double depth = 0;
  Vec3 normal;
};

class RigidShape {
 public:
  RigidShape() = default;
  explicit RigidShape(const RigidShapeConfig& c);

  // The penetration of a point at `d` from the reference point (sphere centre, ogive tip);
  // false outside.
  bool penetration(const Vec3& d, Penetration& p) const;
  // Volume [m^3] (ogive: the nose integrated by Simpson's rule) and the largest distance of
  // a surface point from the reference point (a bound for the contact search).
  double volume() const;
  double reach() const;
  // Ogive: length of the nose, a sqrt(4 crh - 1) for a tangent ogive.
  double nose_length() const { return nose_; }
  const RigidShapeConfig& config() const { return c_; }

 private:
  RigidShapeConfig c_;
  double arc_ = 0;   // ogive arc radius s = 2 crh a
  double nose_ = 0;  // nose length l
};

// Adds the penalty force density of `shape` at reference point `at` to particles.b and
// returns the total force the particles receive, sum b V [N] (the shape receives minus
// it). In a decomposed run each rank pushes its own particles; GridSum makes the total
// independent of the split. `energy` (if not null) receives the penalty energy
// sum V K d^(p+1)/(p+1) [J].
Vec3 push_particles(System& s, const RigidShape& shape, const Vec3& at, ContactLaw law, double stiffness,
                    double* energy = nullptr);

// The particle-side stiffness of the law, d b / d d [N/m^4]: K (linear) or 2 K d_max
// (quadratic, at the penetration d_max). The stable step adds it to the bond stiffness of
// every particle (solver/build.cpp stable_time_step).
double penalty_stiffness(ContactLaw law, double stiffness, double max_penetration);

}  // namespace horizon
