#pragma once
// What every implicit solver (Newton, ADR, Newmark) shares: the unknowns (free displacement
// components), the residual built from compute_forces, and a switch that holds the bond
// set fixed while a solver iterates.
//
// Nodal forces: F_i = f_i V_i [N] (f = force density of compute_forces). The residual on
// the free components is R = (f + b) V (internal plus external); equilibrium is R = 0.
// On a constrained component the same expression is minus the reaction: the constraint
// supplies -R there (docs/input.md, loads).
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "horizon/loading/loads.hpp"
#include "horizon/solver/build.hpp"

namespace horizon {

// The unknowns of an implicit solve: every displacement component within the deck's
// dimension that no constraint prescribes, numbered particle by particle.
struct DofMap {
  int dimension = 3;
  std::vector<int32_t> index;      // 3 per particle: the dof, or -1 (prescribed or out of plane)
  std::vector<uint32_t> particle;  // per dof
  std::vector<uint8_t> component;  // per dof

  std::size_t size() const { return particle.size(); }
  int32_t dof(std::size_t i, int c) const { return index[3 * i + c]; }
};

DofMap make_dof_map(const System& s, const Loads& loads);
// Every component within the dimension is free (tests, and bodies without constraints).
DofMap make_free_dof_map(const System& s);

// Holds the bond set fixed: while it lives, compute_forces breaks no bond (the critical
// stretches are swapped for +inf, and every model holds its own failure law
// (Model::hold_bonds), until destruction). Solvers iterate on a fixed bond set; bonds break between
// solves (static_driver.hpp).
class FixedBonds {
 public:
  explicit FixedBonds(System& s);
  ~FixedBonds();
  FixedBonds(const FixedBonds&) = delete;
  FixedBonds& operator=(const FixedBonds&) = delete;

 private:
  System& s_;
  std::vector<double> saved_;
};

// True when every particle's forces follow the unified bond form of state/system.hpp
// (Model::unified), for which the analytic tangent exists; false with any other
// model, whose tangent is taken by finite differences.
bool unified_form(const System& s);

// Displacements of the free dofs, and back.
Eigen::VectorXd gather_displacement(const System& s, const DofMap& d);
void scatter_displacement(System& s, const DofMap& d, const Eigen::VectorXd& u);
// u += alpha * du on the free dofs.
void add_displacement(System& s, const DofMap& d, const Eigen::VectorXd& du, double alpha = 1.0);

// Residual (f + b) V on the free dofs, from the forces of the last compute_forces.
Eigen::VectorXd gather_residual(const System& s, const DofMap& d);

// Norms of the applied load: the external forces |b V| over every dof of the dimension,
// and the reactions |(f + b) V| over the prescribed components. The convergence test of
// every solver is |R| <= tolerance * max(external, reactions) (docs/input.md).
struct LoadNorms {
  double external = 0;
  double reactions = 0;
  double reference() const { return external > reactions ? external : reactions; }
};
LoadNorms load_norms(const System& s, const DofMap& d);

// Distributed vectors (a run split over MPI ranks, parallel/decomposition.hpp): every rank
// holds vectors over all dofs but computes and updates only the dofs of the particles it
// owns; the other entries stay 0 (their ghosts' values travel by exchange_ghost_values).
// Dot products and norms over the owned dofs are GridSum totals, the same bits however
// the dofs are split between ranks. Not split: the plain Eigen products (serial bits).
// The dofs this rank owns, in dof order; empty when the run is not split.
std::vector<Eigen::Index> owned_dofs(const System& s, const DofMap& d);
// a . b over the free dofs (GridSum over the owned dofs when split). Collective when split.
double dof_dot(const System& s, const DofMap& d, const Eigen::VectorXd& a, const Eigen::VectorXd& b);
// |a| over the free dofs (sqrt of dof_dot when split, Eigen's norm otherwise).
double dof_norm(const System& s, const DofMap& d, const Eigen::VectorXd& a);
// Sets the entries of dofs this rank does not own to 0 (nothing when not split).
void keep_owned(const System& s, const DofMap& d, Eigen::VectorXd& a);
// The forces of the current displacements as the solvers need them: when split, the
// ghosts' displacements are received first (halo_exchange); then compute_forces.
// True when a bond broke in the pass (on any rank when split). Collective when split.
bool equilibrium_forces(System& s, bool energy);

// Nodal mass rho V per dof.
Eigen::VectorXd nodal_mass(const System& s, const DofMap& d);

// True when every component of u is finite.
bool finite_state(const System& s);

}  // namespace horizon
