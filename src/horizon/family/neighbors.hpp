#pragma once
// Families by cell-list search: O(N) time and memory. The family of i is every other
// particle j with |X_j - X_i| <= radius (a relative tolerance of 1e-10 keeps lattice
// points that sit exactly on the horizon sphere). See docs/models.md.
#include "horizon/family/bonds.hpp"
#include "horizon/geometry/particles.hpp"

namespace horizon {

// Neighbour pairs within `radius`, in compressed rows, each row sorted by j.
// Reference data: one BondKind per distinct (length, V_j, material_i, material_j), with
// weight = 1 and fraction = 1; intact = 1. When those kinds would cost more memory than
// a length per bond (an irregular cloud: nearly every bond its own length), the kinds
// leave the length out and each bond keeps its own (Bonds::length_per_bond; the choice
// is the data's, the same on any thread count, and the values are the same bits). `material` (optional, one per point) splits
// the kinds by the materials of the two ends; without it every point is material 0.
// The kinds are numbered in sorted order, so the result does not depend on the
// number of threads.
// `rows` (optional, one flag per point): only the rows of the flagged points are built,
// the others left empty (a run split over MPI ranks, parallel/decomposition.hpp); every
// built row is the one a full search gives (the kinds' numbering may differ).
Bonds find_neighbors(const std::vector<Vec3>& points, const std::vector<double>& volume, double radius,
                     const std::vector<int32_t>* material = nullptr, const std::vector<uint8_t>* rows = nullptr);

// Kinds with their lengths again (a no-op unless length_per_bond): for the readers that
// need a per-kind length or give kinds per-bond values (partial volumes near the
// horizon, influence functions of |xi|, the models of the general force pass; see
// setup_model in solver/system.cpp). The same kinds find_neighbors would have made.
void expand_kinds(Bonds& bonds);

// The same by brute force, O(N^2): the reference the cell list is tested against.
Bonds find_neighbors_brute_force(const std::vector<Vec3>& points, const std::vector<double>& volume,
                                 double radius);


// The rules (PartialVolumeRule, family/bonds.hpp) differ in the family radius only.
// Sets each kind's partial-volume fraction: clamp((horizon + spacing/2 - |xi|)/spacing, 0, 1)
// for |xi| > horizon - spacing/2, else 1. The family radius decides which bonds exist.
void apply_partial_volume(Bonds& bonds, double horizon, double spacing);

// Search radius of the families under a rule: horizon + spacing/2 for `linear`, else
// the horizon.
inline double family_radius(double horizon, double spacing, PartialVolumeRule rule) {
  return rule == PartialVolumeRule::linear ? horizon + 0.5 * spacing : horizon;
}
inline double family_radius(double horizon, double spacing, bool partial_volume) {
  return family_radius(horizon, spacing, partial_volume ? PartialVolumeRule::linear : PartialVolumeRule::none);
}

// Makes every kind's material_i and material_j those of its bond's ends (particles i
// and nbr[k]), splitting kinds where bonds of one kind join different materials. A
// no-op when find_neighbors was given the materials.
void split_kinds_by_material(Bonds& bonds, const std::vector<int32_t>& material);
// Multiplies the influence weight of bond k by factor[k] (one per directed bond; bonds
// i->j and j->i must carry the same factor, so that omega_ij = omega_ji), regrouping the
// kinds so that each kind's bonds share one weight (the surface correction,
// material/surface_correction.hpp).
void scale_bond_weights(Bonds& bonds, const std::vector<double>& factor);

// Families of particles with their own horizons (bodies' `horizon`, docs/input.md):
// `horizon` has one value per particle, none above the search radius the bonds were found
// with. j is in i's family when |xi| <= delta_i (1 + kOwnHorizonTolerance): Peridigm's
// directed neighbour lists (its MultipleHorizons gold: each particle lists the points
// within its own block's horizon, whatever the neighbour's). A pair in neither family is
// dropped; a pair in one family alone stays a bond at both ends (the rows hold both
// directions), the direction outside i's family marked BondKind::one_way (omega_ij = 0
// once the models are set up, so it adds to neither m_i nor theta_i nor t_ij, and the
// pair acts through t_ji alone). Returns the number of one-way bonds (directed).
uint64_t restrict_to_horizons(Bonds& bonds, const std::vector<double>& horizon);
// Tighter than the search's 1e-10: MultipleHorizons tells apart horizons 1e-12 apart
// (0.999999999999 leaves out the points at 1, 1.000000000001 those at 1.000000000002).
constexpr double kOwnHorizonTolerance = 1e-13;
inline bool within_horizon(double length, double horizon) {
  return length <= horizon * (1 + kOwnHorizonTolerance);
}

}  // namespace horizon
