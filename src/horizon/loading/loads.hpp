#pragma once
// Initial and boundary conditions on particle sets, built once from the deck.
#include <string>
#include <vector>

#include "horizon/contact/indenter.hpp"
#include "horizon/contact/projectile.hpp"
#include "horizon/deck/config.hpp"
#include "horizon/state/system.hpp"

namespace horizon {

struct AppliedLoad {
  std::string name;                 // "region:kind", the history column prefix
  LoadKind kind = LoadKind::traction;
  std::vector<uint32_t> particles;
  Vec3Expr value;
  double scale = 1;                 // traction: 1/d, d = depth of the loaded layer
  std::vector<Vec3> reaction_old;   // constraint force of the last step, per particle
  Vec3 reaction;                    // total force the load applies to the body [N]
  std::optional<Indenter> indenter;  // a rigid indenter (kind body_force, no particles, no value)
  mutable Vec3 applied;             // indenter: the force it applied at the last apply_forces
  // A support of a thin structure (deck structure.supports): its index, and per node the
  // share of the node's reaction it takes (1 / the number of supports through the node).
  int support = -1;
  std::vector<double> share;
};

class Loads {
 public:
  Loads() = default;
  Loads(const Config& config, const System& s);

  // Sets initial velocities and displacements.
  void apply_initial_conditions(const Config& config, System& s) const;
  // End of a step at time t: prescribed displacements (u = g(t), v = (g(t) - g(t-dt))/dt)
  // and prescribed velocities (v = h(t)) on the constrained components.
  // displacements = false: the displacement constraints are left alone (solver.verlet:
  // peridigm moves them through the drift, prescribe_increments).
  void apply_constraints(System& s, double t, double dt, bool displacements = true) const;
  // solver.verlet: peridigm, mid-step: the velocity of each displacement-constrained
  // component over the step from t_prev to t, (g(t) - g(t_prev)) (1/(t - t_prev)), as
  // Peridigm's users' guide has a prescribed displacement drive the Verlet update; where
  // g does not change over the step, (g(t) - u) (1/(t - t_prev)) (a constant g then holds
  // its value whatever u the initial conditions gave).
  void prescribe_increments(System& s, double t, double t_prev) const;
  // Mid-step: v = h(t) on velocity-constrained components, before u is advanced.
  void prescribe_velocity(System& s, double t) const;
  // Zeroes and refills particles.b (body force and traction) at time t.
  void apply_forces(System& s, double t) const;
  // After the force pass at time t: reactions of constrained regions (the force the
  // constraint exerts, rho V a - (f + b) V) and applied force totals. Returns the work
  // done by the constraints over the step (trapezoidal). Dynamic solvers pass the
  // velocities at the start of the step and the step, so that a = (v - v_before)/dt of
  // the prescribed motion counts: the constraint's work then includes the kinetic energy
  // it gives its particles. Static solvers leave them out (a = 0).
  double update_reactions(System& s, const std::vector<Vec3>& u_before, const std::vector<Vec3>* v_before = nullptr,
                          double dt = 0);

  // Checkpoint and restart: each load's reactions and applied force (the rest comes from
  // the deck).
  void checkpoint(StateArchive& a) {
    a.check("loads", loads_.size(), "loads");
    for (auto& L : loads_) {
      a.push(L.name);
      // Per particle of the load, kept by the particle's owner in a decomposed run (an
      // indenter's load lists none).
      if (L.particles.empty()) a.io("reaction_old", L.reaction_old);
      else a.io_listed("reaction_old", L.reaction_old, L.particles);
      a.io("reaction", L.reaction);
      a.io("applied", L.applied);
      a.pop();
    }
    if (!projectiles_.empty()) {
      a.check("projectiles", projectiles_.size(), "projectiles");
      for (auto& p : projectiles_) p.checkpoint(a);
    }
  }

  // Rigid projectiles (contact/projectile.hpp): apply_forces runs their contact pass; the
  // explicit solver moves them (solver/explicit.cpp).
  std::vector<Projectile>& projectiles() { return projectiles_; }
  const std::vector<Projectile>& projectiles() const { return projectiles_; }
  std::vector<AppliedLoad>& loads() { return loads_; }
  const std::vector<AppliedLoad>& loads() const { return loads_; }
  bool is_constrained(std::size_t i, int component) const;
  // |v|^2 over the components of particle i that no constraint prescribes: what mass-
  // proportional damping dissipates on (a prescribed component's velocity is set by its
  // constraint whatever the damped update gives it).
  double free_speed2(std::size_t i, const Vec3& v) const {
    const unsigned fixed = constrained_.empty() ? 0u : constrained_[i];
    double vv = 0;
    for (int c = 0; c < 3; ++c)
      if (!((fixed >> c) & 1u)) vv += v[c] * v[c];
    return vv;
  }

 private:
  std::vector<AppliedLoad> loads_;
  mutable std::vector<Projectile> projectiles_;  // their contact force is set by apply_forces
  std::vector<uint8_t> constrained_;  // bit c set: component c prescribed
};

// Particles inside a named region ("" or "all": every particle).
std::vector<uint32_t> region_particles(const Config& config, const System& s, const std::string& region);

// Depth of a loaded layer along `axis`: number of distinct lattice layers x spacing.
double layer_depth(const System& s, const std::vector<uint32_t>& ids, int axis);

}  // namespace horizon
