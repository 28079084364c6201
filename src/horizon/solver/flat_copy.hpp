#pragma once
// A System's explicit state as flat arrays (kernels/flat_system.hpp): what a backend that
// keeps its own copy of the particles and bonds (the CUDA backend, cuda/cuda_backend.hpp)
// is given, and what the tests step on the host with the portable row functions to check
// them against the host's own passes (tests/unit/test_portable_kernels.cpp).
#include <cstdint>
#include <string>
#include <vector>

#include "horizon/kernels/flat_system.hpp"
#include "horizon/solver/flat_affine_copy.hpp"
#include "horizon/solver/flat_ordinary_copy.hpp"
#include "horizon/state/system.hpp"

namespace horizon {

class Loads;

// Why this run cannot be stepped over flat arrays, or "" when it can: the unified models
// (ModelTraits::unified), Tupek's nonlinear solid (kernels/tupek.hpp) or correspondence
// in its affine pass (kernels/flat_affine.hpp; solver/flat_affine_copy.hpp); no loads but
// initial conditions, force densities (traction, body_force, force, pressure) and
// prescribed velocities and displacements (values that vary are the stepper's to evaluate
// before each step: FlatBackend); no thermal strain, no contact friction; bonds broken
// before or after the force pass; critical stretches that vary in time (the stepper sets
// them); one rank, no FE regions; kinds with their lengths or, for the unified models,
// bonds with their own (an irregular cloud). Short-range contact: the flat rows hold the
// family pairs' part; the pairs beyond the families are the stepper's (FlatBackend adds
// them between passes with the host's lists; a bare advance_flat leaves them out).
std::string flat_unsupported(const System& s, const Loads& loads);

// Owning copies of every array a FlatSystem points to; view() points into them.
struct FlatStorage {
  kernels::FlatSystem view();
  std::vector<uint64_t> offset;
  std::vector<uint32_t> nbr, kind;
  std::vector<uint8_t> intact, no_fail;
  std::vector<kernels::Kind> kinds;
  std::vector<double> r_of, X, u, v, f, b, density, volume, critical_stretch, alpha, min_stretch, min_stretch_next,
      dilatation_coef, Q, R, weighted_volume, theta, P, intact_weight, damage_total, damage, energy, dissipated, y4;
  std::vector<uint64_t> broken;
  // Loads (kernels::FlatSystem): the constraints per particle, the tracked particles, the
  // constraints' (load, particle) entries and where each comes from (entry_load, entry_index:
  // the load and the particle's place in its list; the host's, for the reactions).
  std::vector<uint8_t> fixed, entry_mask;
  std::vector<double> fixed_value, u_before, v_before, entry_reaction, ledger;
  std::vector<double> damped, speed2_before;  // with damping: per particle, since the copy
  std::vector<uint8_t> nonfinite{0};
  // Loads whose values vary in time or space (the stepper evaluates them before each step).
  std::vector<double> fixed_mid, fixed_v, b_next, b_before;
  // solver.verlet: peridigm (kernels::FlatSystem::peridigm): the positions the force pass
  // reads, and each prescribed displacement's 1/(t1 - t0) (set before each step).
  bool peridigm = false;
  std::vector<double> positions, fixed_rate;
  bool vary_constraints = false, vary_forces = false;
  bool vary_critical_stretch = false;  // System::critical_stretch_schedules (set before each step)
  std::vector<uint32_t> tracked, entry_slot, entry_load, entry_index;
  bool has_forces = false;
  // Tupek's nonlinear solid (NonlinearState; empty otherwise).
  bool tupek = false, tupek_exponent_two = true, tupek_contact = false;
  std::vector<double> eps, seth_m, lambda_bar, mu_bar, beta, failure_scale, nonlocal_damage, contact_stiffness;
  std::vector<uint8_t> compression_only;
  FlatAffineStorage affine;  // the correspondence model (solver/flat_affine_copy.hpp; off otherwise)
  uint64_t n = 0;
  bool state_based = false, break_after = false;
  // elastic_plastic or viscoelastic (solver/flat_ordinary_copy.hpp), else null.
  std::shared_ptr<FlatOrdinaryStorage> ordinary;
  std::vector<double> length_of;  // an irregular cloud: each bond's |xi| (else empty)
  bool contact_from_length = false;
  double contact_fraction = 0, contact_cutoff = 0;
  double dim = 3, dt = 0, damping = 0;
};

// Copies s (after ExplicitSolver::initialize or any step: forces, damage and the smallest
// stretches are those of the last pass) with the step dt and the damping; the ledger's
// external work starts at external_work; with `loads`, their constraints and work; with
// `peridigm`, the step of solver.verlet: peridigm (ExplicitSolver::set_peridigm_verlet).
FlatStorage flat_copy(const System& s, double dt, double damping, double external_work = 0,
                      const Loads* loads = nullptr, bool peridigm = false);

// The loads' reactions at the copy's last step, as Loads::update_reactions leaves them
// (each constraint's reaction_old and reaction; the force loads' are constants).
void flat_write_reactions(const FlatStorage& c, Loads& loads);

// Writes the copy's u, v, f, damage, energy (with `energy`: a pass the CPU backend would
// have computed it in), intact flags and dissipation back into s (and the nonlinear
// solid's theta, bond strains and nonlocal damage into its NonlinearState).
void flat_write_back(const FlatStorage& c, System& s, bool energy = true);

}  // namespace horizon
