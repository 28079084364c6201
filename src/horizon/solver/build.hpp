#pragma once
// Building the run's state (state/system.hpp) from a deck, and what a solver asks of it
// as a whole: the stable time step, checkpoints, the memory estimate. The state itself
// sits below the models; its builder calls geometry/, family/, material/ and fe/, so it
// lives here, above them (docs/design.md, "Floors").
#include <cstddef>
#include <vector>

#include "horizon/material/model.hpp"
#include "horizon/state/system.hpp"

namespace horizon {

// Builds particles (lattice), families, precracks, influence weights and model
// coefficients from a validated deck.
System build_system(const Config& config);

// Influence weights, model objects and model coefficients of every particle from its
// material (particles.material indexes `materials`, which are config.materials for
// build_system). Bonds must exist. build_system calls it; tests call it on small systems
// built in code.
void setup_model(System& s, const std::vector<MaterialConfig>& materials, const Config& config);

// The stable time step of Silling and Askari (2005): min_i sqrt(2 rho_i / sum_j V_j C_ij),
// C_ij = c_ij / |xi| (before the safety factor), or the model's own when it owns the
// force pass.
double stable_time_step(const System& s);

// Checkpoint and restart (output/checkpoint.hpp): everything of the system that a run
// changes (positions, velocities, forces, bond flags, the shared model arrays, heat,
// dissipation, every model's own state through Model::checkpoint), after a check that
// particle, bond and material counts and the models match the deck's.
void checkpoint_system(System& s, StateArchive& a);

// Whether a deck's bonds need kinds with their lengths (family/neighbors.hpp
// expand_kinds) rather than a length per bond: a model off the fast loops, an influence
// function of |xi|, the surface correction, heat conduction, structures, finite elements.
// setup_model regroups the bonds then; the memory guard counts the kinds.
bool kinds_need_lengths(const std::vector<MaterialConfig>& materials, const Config& config);

// Estimated memory of the run [bytes]: the program (kProgramBytes), particles, bonds,
// bond kinds and model arrays, as an explicit run of the unified models holds them
// (tests/unit/test_clouds.cpp checks it is not below what such a run allocates).
std::size_t memory_estimate(const System& s);
// The program itself: its code and shared libraries (`horizon --version` is resident in
// 19 MiB), and the deck, small objects and the allocator's rounding on the heap.
constexpr std::size_t kCodeBytes = std::size_t{20} << 20;
constexpr std::size_t kProgramBytes = kCodeBytes + (std::size_t{4} << 20);

}  // namespace horizon
