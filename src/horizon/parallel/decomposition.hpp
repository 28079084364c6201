#pragma once
// Domain decomposition of an explicit run over MPI ranks (docs/design.md, "Running on
// several ranks"; built with -DHORIZON_MPI=ON).
//
// What is distributed is the work and the bonds, and where the deck allows it (local_particles_allowed: local
// rows on more than one rank, short-range contact, checkpoints and restarts included) the particles: a rank
// then holds only its owned particles and the particles its rows read, in a local numbering in ascending global
// id (Particles::id), and every index below (owner, owned, ghost lists, loads, reactions) is local; short-range
// contact reads the particles within its reach that no bond brings as contact ghosts outside the System
// (ContactGhosts: chosen by exchanging the owned particles' boxes; the contact lists sort by global id), and a
// checkpoint goes to rank 0's file by global id window by window, and a restart reads each rank's entries
// (parallel/checkpoint_stream.hpp). The build generates the whole lattice transiently to
// decide owners and families. Rank 0 holds no gathered copy of the system (parallel/lead_view.hpp): the history
// rows and the summary's sums are exact grid sums and maxima over the ranks' owned particles, crack tracking reads
// the cracked particles alone, and state_crc32 streams the state through rank 0 a slice of global ids at a time.
// Otherwise the particles are replicated: every rank builds every particle from the deck
// (positions, velocities, per-particle model constants in the serial order: the serial
// indices are the global ids), then
//   - owns the particles of its box of a recursive coordinate bisection of the reference
//     positions (rcb_owners: the same split at any thread count, ties by global id);
//   - holds the bond rows it computes alone (local rows, build_system_split): the owners
//     are decided before the families are built, and only the owned particles' rows and
//     their bond neighbours' are searched, each the same bonds in the same order as
//     serially; the other rows are empty, so every per-bond array (the models' history
//     included) covers the rows held. decompose() drops the neighbours' rows when only the
//     owned ones are computed. Decks outside local_rows_allowed() (static and implicit
//     solves with an assembled tangent or outside the unified models, structures, FE
//     regions, decks the split refuses) build the whole system on every rank, and only
//     the work is split;
//   - integrates only its own particles, and computes the bond rows of its own and, for
//     state-based models, the critical stretch with a compression factor and the general
//     force pass (thermal strain too), also of their bond neighbours (the dilatation of a
//     neighbour is computed again here instead of being sent); with a compression factor
//     the owners also send each pass's smallest stretch to the ghosts (solver/forces.cpp
//     share_min_stretch: a recomputed neighbour row reads s0 two horizons out);
//   - receives each step the displacements of its ghosts: the bond neighbours of its
//     active particles, and every particle within the short-range contact distance plus a
//     skin of one of its own (halo_exchange). When any particle has moved more than half
//     the skin since the ghosts were chosen, all displacements are gathered and the
//     ghosts chosen again (the Verlet-list rule, as state/short_range.hpp);
//   - each particle's force is summed over its whole bond row in the serial order, so its
//     bits do not depend on the rank count;
//   - global sums (energies, work, reactions, indenter forces) go through GridSum: every
//     term is rounded to a grid of 2^-100 of the largest term of that sum over all ranks
//     and the integers are added exactly, so the total does not depend on how the terms
//     are split between ranks or on their order;
//   - before a history row, a frame or the summary, the state of every particle is
//     gathered on every rank (gather_state), so crack tracking and summary figures are
//     computed as in a serial run (damage statistics and body velocities are exact grid
//     sums over the owned particles on every path: driver/summary.hpp); a bond count
//     (broken bonds, precrack cuts, the whole system's bonds) is summed over the owned
//     rows of each rank;
//   - a checkpoint holds the whole system in serial order: gather_checkpoint takes every
//     per-particle entry from its owner and every per-bond entry from the owner of its
//     row; a restart with local rows keeps the rows it holds (keep_local_bonds).
#include <cstdint>
#include <string>
#include <vector>

#include "horizon/core/vec3.hpp"

namespace horizon {

struct System;
struct Config;
class CheckpointReader;

// Owner rank of each particle: recursive coordinate bisection of `x` into `ranks` boxes
// (a box of p ranks is cut across its longest side, at the particle that gives its two
// halves floor(p/2) and ceil(p/2) ranks' shares of particles; ties broken by index).
std::vector<int32_t> rcb_owners(const std::vector<Vec3>& x, int ranks);

struct HaloStats {
  uint64_t steps = 0;             // exchanges so far
  uint64_t messages = 0;          // messages this rank sent, summed over the exchanges
  uint64_t bytes = 0;             // bytes this rank sent, summed over the exchanges
  uint64_t rebuilds = 0;          // ghost re-selections (each gathers every displacement)
};

// Local particles with short-range contact: the particles of other ranks within the
// contact reach plus the skin of one of this rank's owned particles that this rank does
// not hold (not in its System), with what the contact pass reads of them
// (state/short_range.hpp). Chosen again with the other ghosts (halo_exchange).
struct ContactGhosts {
  uint64_t generation = 0;              // +1 each time the set is chosen
  std::vector<int64_t> id;              // global id
  std::vector<Vec3> X, u;               // reference position; displacement (sent each step)
  std::vector<double> volume, micromodulus;  // V and the contact micromodulus c
  std::size_t most = 0;                 // the largest set so far
};

struct Decomposition {
  int rank = 0, size = 1;
  double skin = 0;                   // ghost margin for moving particles [m]
  double contact_reach = 0;          // short-range contact distance [m] (0: no contact)
  bool state_based = false;          // neighbours' rows are computed here too (decompose)
  // Some particle on some rank has the compression factor alpha: after each force pass the
  // owners send their smallest stretch (ModelState::min_stretch) to the ghosts
  // (solver/forces.cpp share_min_stretch; set by decompose).
  bool alpha = false;
  std::vector<int32_t> owner;        // per particle
  std::vector<uint32_t> owned;       // this rank's, in index order
  std::vector<uint8_t> is_owned;     // per particle
  std::vector<std::vector<uint32_t>> send, recv;  // per rank: owned particles it needs / ghosts it sends us
  std::vector<uint8_t> bond_ghosts;  // per particle: a bond neighbour of a computed row (or such a row) not owned
  std::vector<Vec3> y_built;         // positions when the ghosts were chosen (owned entries)
  HaloStats stats;
  // The bonds of the whole system that were not intact when the run was decomposed but
  // that System::broken (the passes' breaks: the serial count) did not count: a
  // precrack's bonds kept broken (bonds: broken). gather_state counts the broken bonds
  // from the owned rows and leaves these out (set by decompose).
  uint64_t broken_at_start = 0;
  // Local rows (build_system_split): this rank holds the bond rows it computes alone, the
  // others are empty. Set before decompose(), which fills in the rest.
  bool local_rows = false;
  uint64_t global_bonds = 0;             // bonds of the whole system (the serial count)
  std::vector<uint64_t> global_offset;   // per particle + 1: where its row starts in the serial CSR

  // Local particles (build_system_split with a Decomposition): this rank holds only the
  // particles it reads, in a local numbering in ascending global id (Particles::id), so
  // every per-particle array is local-sized; `owner`, `owned`, `is_owned`, the send and
  // receive lists and every System index are local then. Set by the build.
  bool local_particles = false;
  uint64_t global_particles = 0;         // particles of the whole system
  // Local particles with short-range contact: the contact ghosts, and per rank the owned
  // particles whose displacement it needs for its contact ghosts / the ghosts it sends.
  ContactGhosts contact;
  std::vector<std::vector<uint32_t>> contact_send, contact_recv;

  bool owns(std::size_t i) const { return is_owned[i] != 0; }
};

// True when this build has MPI (HORIZON_MPI).
bool mpi_built();
// Rank and size of MPI_COMM_WORLD (0 and 1 without MPI).
int world_rank();
int world_size();

// The system of this rank for a run split over world_size() ranks with local rows
// (solver/build.cpp): particles and every per-particle array whole, but bond rows only
// for the particles this rank owns (rcb_owners of the reference positions) and their
// bond neighbours; the other rows are empty, so the global indices and the serial order
// of every row stay. Each built row holds the same bonds in the same order as serially.
// The precrack check and count are global. Collective.
System build_system_split(const Config& config);
// The same with local particles (local_particles_allowed): every rank generates the whole
// lattice transiently (positions, volumes, materials: ~170 B a particle), computes
// rcb_owners, and keeps only the rows it computes (its owned particles', and for
// state-based models, the compression factor alpha or the general force pass also their
// bond neighbours') and the particles those rows read, renumbered in ascending global
// id; the models are set up on that local system alone. Fills d.owner (per local
// particle), d.local_particles and d.global_particles; d.local_rows is set too.
// Collective.
System build_system_split(const Config& config, Decomposition& d);
// Whether a deck may be built with local particles: an explicit run that local_rows_allowed (short-range contact
// reads contact ghosts, a checkpoint is streamed by global id and a restart reads its particles' entries; the
// driver builds a run on one rank with every particle).
bool local_particles_allowed(const Config& config);
// Whether a deck may be built with local rows: an explicit run whose every model is split
// over ranks row by row, or a static or implicit solve split over ranks (unified models,
// matrix-free Newton or ADR: driver/run_implicit.cpp), that uses nothing split on the
// whole system only (structures, FE regions); the surface correction of the unified
// models exchanges its set-up factors between passes (material/surface_correction.cpp).
// Otherwise every rank builds the whole system (the old way) and decompose() splits the
// work only.
bool local_rows_allowed(const Config& config);
// Splits the system over the ranks, chooses the ghosts and sets s.active, s.owned and
// s.decomposition. With d.local_rows: drops the rows this rank does not compute (a
// bond-based run keeps its owned rows only), counts the global bonds (s.initial_bonds
// becomes the whole system's) and where each row lies in the serial order. Collective.
void decompose(System& s, Decomposition& d, double skin);
// What the busiest of `ranks` ranks would hold with local rows, from the whole system
// `s` (horizon check --ranks; solver/build.cpp): its bonds (owned rows, and the bond
// neighbours' rows where decompose() keeps them), its particles (with local particles
// those rows and the particles they read, else every particle) and its memory estimate.
struct RankShare {
  uint64_t bonds = 0;
  uint64_t particles = 0;
  std::size_t bytes = 0;
};
RankShare largest_rank_share(const System& s, int ranks, bool local_particles);
// Sum over ranks and minimum over ranks (the value itself without MPI). Collective.
uint64_t sum_over_ranks(uint64_t x);
double min_over_ranks(double x);
// Every rank's x, on rank 0 (others get an empty vector). Collective.
std::vector<uint64_t> gather_on_lead(uint64_t x);
// Every rank's values, one after the other in rank order, on every rank. Collective.
std::vector<double> allgather_values(const std::vector<double>& mine);
// The bonds a checkpoint holds: the whole system's (d.global_bonds with local rows).
uint64_t checkpoint_bond_count(const System& s);
// Before a restart with local rows reads a checkpoint: the per-bond records of `records`
// (CheckpointWriter::bond_records of this rank's state) are cut to this rank's rows.
void keep_local_bonds(const System& s, const Decomposition& d, const std::vector<std::string>& records,
                      CheckpointReader& in);
// Before a force pass: re-chooses the ghosts when needed, then sends the displacements of
// owned particles to the ranks that hold them as ghosts. Collective.
void halo_exchange(System& s, Decomposition& d);
// The same exchange for any per-particle vector field `a` (the ghosts chosen as they are):
// each ghost entry receives its owner's value. The distributed Krylov solvers send their
// search direction this way before a tangent product (solver/linear.hpp). Collective.
void exchange_ghost_values(Decomposition& d, std::vector<Vec3>& a);
// The same for a per-particle scalar field (the heat solver's temperature, once per heat
// step: thermal/heat.cpp). Collective.
void exchange_ghost_scalars(Decomposition& d, std::vector<double>& a);
// Gathers u, v, f, b, damage, energy and dissipated_at of every particle from its owner
// onto every rank, and the count of broken bonds. Collective.
// With local particles only the count of broken bonds (s.broken, on every rank): the
// particles stay with their owners, and rank 0 gathers what it reads itself
// (parallel/lead_view.hpp).
void gather_state(System& s, Decomposition& d);
// Local particles: every owned particle's value of `local` (one per local particle) on
// rank 0 in global order (others get an empty vector). Collective.
std::vector<double> gather_on_lead(const System& s, const Decomposition& d, const std::vector<double>& local);
// After a restart has loaded the whole state on every rank: the ghosts chosen again from
// the loaded positions. Collective.
void refresh_ghosts(System& s, Decomposition& d);
// Before rank 0 writes a checkpoint (not with local particles: parallel/checkpoint_stream.hpp):
// every per-particle and per-bond record of `w`
// (CheckpointWriter::spread) is overwritten on rank 0 with each entry from the rank that
// owns the particle (the bond's row), in index order, so that the file holds the global
// state as a serial run would. Collective; other ranks' writers are left as they were.
void gather_checkpoint(const System& s, const Decomposition& d, class CheckpointWriter& w);
// Any rank's flag (logical or). Collective.
bool any_rank(const Decomposition& d, bool flag);
// The halo statistics of every rank, on rank 0 (others get an empty vector). Collective.
std::vector<HaloStats> gather_halo_stats(const Decomposition& d);

// Sums of several quantities (add(q, term)), independent of how the terms are split
// between ranks when the system is decomposed (see above), and the plain sum in the order
// of the calls when it is not (the serial result, bit for bit).
// GridSum::exact sums on the grid without a decomposition too (the grid of the terms
// given here alone): the same bits as the decomposed sum of the same terms on any rank
// count. For the sums that feed back into the state (a rigid projectile's contact force:
// contact/rigid_contact.cpp), so that the serial program and the MPI program agree.
class GridSum {
 public:
  GridSum(const System& s, int quantities);
  static GridSum exact(const System& s, int quantities) {
    GridSum g(s, quantities);
    if (!g.grid_) g.exact_ = true, g.terms_.resize(static_cast<std::size_t>(quantities));
    return g;
  }
  void add(int q, double term) {
    if (!grid_ && !exact_) plain_[q] += term;
    else if (term != 0) terms_[q].push_back(term);  // most terms are 0 (work away from loads)
  }
  void add(int q, const Vec3& v) {
    add(q, v.x);
    add(q + 1, v.y);
    add(q + 2, v.z);
  }
  // Collective when decomposed.
  std::vector<double> totals() const;

 private:
  const struct Decomposition* grid_ = nullptr;
  bool exact_ = false;  // GridSum::exact without a decomposition
  std::vector<double> plain_;
  std::vector<std::vector<double>> terms_;
};

}  // namespace horizon
