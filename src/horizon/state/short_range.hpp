#pragma once
// Short-range contact: any two particles closer than d_ij = min(f |X_j - X_i|, m h)
// repel with the force density (on i)
//     k_ij V_j (d_ij - |Y|) / delta  along  -Y/|Y|,   Y = y_j - y_i,
// k_ij = K (c_i + c_j)/2, c the bond-based micromodulus of each end (the PMB's own, or
// for a state-based model the PMB micromodulus with its bulk modulus and omega = 1),
// K = stiffness_factor (15), f = reference_fraction (0.9), m = max_distance (1.35).
// This is the rule of LAMMPS PERI (after Silling's EMU manual), with V_j the whole
// volume of the neighbour. docs/models.md sec. 9.
//
// law peridigm (ShortRangeContactConfig): Peridigm's Short Range Force. Only pairs that
// were not bonded at the start touch (the bond loops add nothing); d = R_c for every
// pair and k_ij = 9 k/(pi delta^4) for every pair (half the PMB micromodulus of the
// spring constant k, Peridigm's users' guide SAND2012-7800), plus Coulomb friction: the
// force density mu k_ij V_j (d - |Y|)/delta along the pair's relative tangential
// velocity (v_j - v_i less its part along Y), which opposes their sliding. Its pass is a
// separate instantiation, so the LAMMPS law's loop is unchanged.
// `pairs` (either law) keeps only the pairs of the listed bodies, at list build time.
// With search_radius (law peridigm: Peridigm's Search Radius and Search Frequency) the
// candidates are Peridigm's: found at the first pass and then every search_every steps,
// within search_radius of each other at the positions the step starts from (those of the
// previous step's pass, before the drift), kept until the next search; a pair touches
// when it is listed and closer than R_c at the pass. The Verlet lists below already hold
// every pair closer than R_c, so the pass keeps those that were within search_radius at
// the last search's positions: the same pairs, without listing every pair within the
// (often much larger) search radius.
// Contact_Ring's gold (search radius = R_c, every step: a pair that comes within R_c during
// a step touches from the next step on) and Contact_Perforation's fix it (docs/peridigm.md).
// Law peridigm's energy (0.25 k (R_c - r)^2 a pair end) is kept apart from the material's
// (own_energy; strain_energy adds it): Peridigm's Stored_Elastic_Energy leaves it out.
//
// Pairs inside one family (bonded at the start, intact or broken) are handled in the
// bond loops (solver/forces.cpp), which visit them anyway. This class finds the others
// (pairs that start more than a family apart, or across a precrack) with a Verlet list
// kept per particle: the list holds every such pair within cut-off + skin of each
// other's positions at their last update; a particle that has moved more than skin/2
// since its last update is updated alone (its pairs found again through a hash grid).
// Only the particles that move fast cost anything, so a body at rest or in slow
// motion pays almost nothing for contact.
//
// A run split over ranks with local particles (parallel/decomposition.hpp) also reads the
// contact ghosts, the particles of other ranks within reach of its own that it does not
// hold (Decomposition::contact): they take indices n, n + 1, ... after the n particles of
// the system, each row is sorted by global id (so every sum runs in the serial program's
// order), only pairs with a computed row (System::computes_row) are listed, and the lists
// are built again whenever the decomposition chooses the ghosts again. A particle's
// force sums the same nonzero terms in the same order as serially as long as its list
// holds every pair within the contact distance, so the bits do not depend on the ranks.
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "horizon/core/point4.hpp"
#include "horizon/core/vec3.hpp"
#include "horizon/deck/config.hpp"

namespace horizon {

struct System;

class ShortRangeContact {
 public:
  bool enabled() const { return enabled_; }
  const ShortRangeContactConfig& config() const { return config_; }

  // Remembers the rule; the list is built at the first call of add_forces.
  void setup(const ShortRangeContactConfig& config, double spacing, double horizon);

  // Adds the contact force densities of non-family pairs to f (and, with `energy`,
  // each particle's half of the pair energy to W), from the current positions y.
  // Each particle's sum runs over its own list in a fixed order.
  // y: current positions (the w component unused). W may be null.
  void add_forces(const System& s, const Point4* y, Vec3* f, double* W);

  // The contact distance of a pair from its reference distance:
  // enabled() ? min(config().reference_fraction * reference_length, cutoff()) : 0.
  double distance(double reference_length) const;
  // The contact distance of a family pair (the bond loops' contact): 0 for law peridigm,
  // whose contact never acts between pairs bonded at the start.
  double family_distance(double reference_length) const {
    return acts_on_family() ? distance(reference_length) : 0.0;
  }
  // Whether the bond loops' contact acts at all (on, and a law that acts between family pairs).
  bool acts_on_family() const { return enabled_ && config_.law != ShortRangeLaw::peridigm; }
  // The largest distance at which any pair touches [m] (the contact ghosts' reach).
  double reach() const { return enabled_ ? cutoff_ : 0.0; }
  double cutoff() const { return cutoff_; }

  // Keep each particle's contact force density of the last add_forces (the pairs of its
  // own list, friction included): Exodus output's Contact_Force_Density. Off by default
  // (one store a particle per pass when on). For the LAMMPS law it leaves out the family
  // pairs' contact, which the bond loops add to the bond forces.
  void record_forces(bool on) { record_ = on; }
  bool records_forces() const { return record_; }
  const std::vector<Vec3>& recorded_forces() const { return recorded_; }

  // Particle updates so far (each particle counts once per update), and pairs listed now.
  std::size_t rebuilds() const { return rebuilds_; }
  std::size_t candidates() const { return candidates_; }
  // Law peridigm: each particle's contact energy density of the last pass with energy
  // (empty before one, and for the LAMMPS law, whose energy is the particles' own).
  const std::vector<double>& own_energy() const { return energy_; }

 private:
  void update(const System& s, const Point4* y, bool first);
  // search_radius: counts the steps and keeps the positions of the last search (those
  // the searching step started from) in y_start_ (see the header comment).
  void peridigm_search(const System& s, const Point4* y);
  uint64_t cell_key(const Vec3& p) const;

  bool enabled_ = false;
  ShortRangeContactConfig config_;
  double cutoff_ = 0, skin_ = 0, horizon_ = 0;
  double peridigm_k_ = 0;              // law peridigm: 2 x 9 k/(pi delta^4)/delta
  bool record_ = false;
  std::vector<Vec3> recorded_;         // record_forces: per particle, the last pass's sum
  std::vector<uint8_t> touch_;         // pairs: bodies a, b touch when touch_[a * bodies + b]
  std::size_t touch_bodies_ = 0;
  std::vector<Vec3> y_built_;                  // position at each particle's last update
  std::vector<std::vector<uint32_t>> rows_;    // candidates of each particle, sorted
  std::vector<uint64_t> cell_of_;              // hash-grid cell of y_built_
  std::unordered_map<uint64_t, std::vector<uint32_t>> cells_;
  std::vector<uint32_t> movers_;
  std::vector<uint8_t> is_mover_;
  // Contact ghosts (local particles on ranks): their current positions (w unused), the
  // global id of every index (local ones, then the ghosts; empty without ghosts) and the
  // generation of the ghost set the lists were built for.
  std::vector<Point4> ghost_y_;
  std::vector<int64_t> key_;
  uint64_t generation_ = 0;
  std::size_t rebuilds_ = 0, candidates_ = 0;
  std::vector<double> energy_;        // law peridigm: own_energy
  // search_radius: the positions of the last pass and of the last search, the last
  // pass's time, and the steps since the first pass (-1 before it).
  std::vector<Vec3> y_last_, y_start_;
  double last_time_ = 0;
  long step_ = -1;
};

}  // namespace horizon
