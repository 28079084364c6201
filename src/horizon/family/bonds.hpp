#pragma once
// Bonds in compressed rows: particle i's bonds are [offset[i], offset[i+1]). Every
// bond is stored at both ends (directed), so that each particle's force is a sum
// over its own row, done by one thread in a fixed order (results independent of the
// thread count, no atomics). docs/benchmarks.md has the measurement that settled it.
//
// Reference data are stored once per bond *kind*, not per bond: all bonds with the
// same reference length (bit for bit), the same neighbour volume and the same pair of
// materials share one BondKind. On a lattice a few dozen kinds cover every bond (36
// for the LAMMPS cylinder), so a bond costs 4 (neighbour) + 4 (kind) + 1 (intact)
// bytes instead of 29, and the reference data stay exact: nothing is rounded, the
// length of a kind is the length every one of its bonds computed.
//
// An irregular cloud (jittered points, mesh centroids) would give nearly every bond its
// own kind: 40 bytes here and 128 in the force loops' tables per kind, several times the
// bond itself. When the lengths are that varied (find_neighbors counts them), the kinds
// leave the length out and each bond keeps its own exact |xi| in `lengths` (8 bytes):
// the kinds then hold what the bonds do share (V_j, the fraction and the weight when
// they do not vary with |xi|, the materials). kind_of(k) and the per-bond views give the
// same values either way; expand_kinds() returns to kinds with lengths where a reader
// needs a per-kind length (family/neighbors.hpp).
#include <cstddef>
#include <cstdint>
#include <vector>

namespace horizon {

// How the volume of a neighbour near the horizon is counted (docs/models.md, sec. 4):
//   none:   whole volumes, family |xi| <= horizon;
//   linear: family |xi| <= horizon + spacing/2, fraction clamp((horizon + spacing/2 - |xi|)/spacing, 0, 1)
//           (Seleson 2014, "Improved one-point quadrature algorithms for two-dimensional
//           peridynamic models"): cells the sphere cuts count by the part inside it;
//   lammps: the same fraction on the family |xi| <= horizon (LAMMPS PERI, Parks et al.
//           2008): the cells whose centre lies just outside the sphere are left out.
enum class PartialVolumeRule { none, linear, lammps };

struct BondKind {
  double length = 0;    // |xi| [m], exactly as computed from the reference positions
  double volume = 0;    // V_j, the neighbour's full volume [m^3]
  double fraction = 1;  // partial-volume factor: the bond uses fraction * volume
  double weight = 1;    // influence function omega_ij
  int32_t material_i = 0, material_j = 0;  // materials of the two ends (for weight and coefficients)
  // Bodies of different horizons (restrict_to_horizons, family/neighbors.hpp): |xi| lies
  // beyond the horizon of end i but within that of end j, so the bond is in j's family
  // alone; setup_model gives it omega_ij = 0, and it acts through t_ji.
  bool one_way = false;
};

struct Bonds;

// Read-only per-bond view of one BondKind field: bonds.length[k] is the length of bond k.
template <double (*Get)(const BondKind&)>
class BondField {
 public:
  class iterator {
   public:
    using value_type = double;
    using difference_type = std::ptrdiff_t;
    iterator(const BondField* f, std::size_t k) : f_(f), k_(k) {}
    double operator*() const { return (*f_)[k_]; }
    iterator& operator++() { ++k_; return *this; }
    bool operator==(const iterator& o) const { return k_ == o.k_; }
   private:
    const BondField* f_;
    std::size_t k_;
  };
  explicit BondField(const Bonds* b) : b_(b) {}
  double operator[](std::size_t k) const;
  std::size_t size() const;
  iterator begin() const { return {this, 0}; }
  iterator end() const { return {this, size()}; }
  // Element by element (what the bonds compare as, kinds aside).
  bool operator==(const BondField& o) const {
    if (size() != o.size()) return false;
    for (std::size_t k = 0; k < size(); ++k)
      if ((*this)[k] != o[k]) return false;
    return true;
  }

 private:
  const Bonds* b_;
};

namespace bond_fields {
inline double length(const BondKind& c) { return c.length; }
inline double volume(const BondKind& c) { return c.volume * c.fraction; }
inline double weight(const BondKind& c) { return c.weight; }
}  // namespace bond_fields

struct Bonds {
  std::vector<uint64_t> offset;   // size n + 1
  std::vector<uint32_t> nbr;      // neighbour index j
  std::vector<uint32_t> kind;     // index into kinds
  std::vector<BondKind> kinds;    // reference data, shared by the bonds of one kind
  std::vector<uint8_t> intact;    // 1 intact, 0 broken (irreversible)
  // Per-bond |xi| when the kinds leave the length out (length_per_bond; their `length`
  // field is then 0); empty otherwise.
  std::vector<double> lengths;
  bool length_per_bond = false;

  // Per-bond views: |xi|, V_j scaled by the partial-volume factor, omega_ij.
  BondField<bond_fields::length> length{this};
  BondField<bond_fields::volume> volume{this};
  BondField<bond_fields::weight> weight{this};

  Bonds() = default;
  Bonds(const Bonds& o)
      : offset(o.offset), nbr(o.nbr), kind(o.kind), kinds(o.kinds), intact(o.intact), lengths(o.lengths),
        length_per_bond(o.length_per_bond) {}
  Bonds(Bonds&& o) noexcept
      : offset(std::move(o.offset)), nbr(std::move(o.nbr)), kind(std::move(o.kind)), kinds(std::move(o.kinds)),
        intact(std::move(o.intact)), lengths(std::move(o.lengths)), length_per_bond(o.length_per_bond) {}
  Bonds& operator=(const Bonds& o) {
    offset = o.offset, nbr = o.nbr, kind = o.kind, kinds = o.kinds, intact = o.intact, lengths = o.lengths;
    length_per_bond = o.length_per_bond;
    return *this;
  }
  Bonds& operator=(Bonds&& o) noexcept {
    offset = std::move(o.offset), nbr = std::move(o.nbr), kind = std::move(o.kind), kinds = std::move(o.kinds);
    intact = std::move(o.intact), lengths = std::move(o.lengths), length_per_bond = o.length_per_bond;
    return *this;
  }

  std::size_t size() const { return nbr.size(); }
  std::size_t particles() const { return offset.empty() ? 0 : offset.size() - 1; }
  uint64_t begin(std::size_t i) const { return offset[i]; }
  uint64_t end(std::size_t i) const { return offset[i + 1]; }
  // The reference data of bond k (its kind, with its own length when length_per_bond).
  BondKind kind_of(std::size_t k) const {
    BondKind c = kinds[kind[k]];
    if (length_per_bond) c.length = lengths[k];
    return c;
  }
  double length_of(std::size_t k) const { return length_per_bond ? lengths[k] : kinds[kind[k]].length; }
};

// What rewrite_bonds does with one bond.
enum class BondAction { keep, drop, keep_broken };

// Rewrites every row in place, in order, applying action(i, k) to bond k of particle i:
// keep it, drop it, or keep it with intact = 0. Returns the bonds dropped or broken.
template <class F>
std::size_t rewrite_bonds(Bonds& b, F&& action) {
  const std::size_t n = b.particles();
  uint64_t write = 0, row_begin = 0;
  std::size_t touched = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const uint64_t row_end = b.offset[i + 1];
    for (uint64_t k = row_begin; k < row_end; ++k) {
      const BondAction a = action(i, k);
      if (a != BondAction::keep) ++touched;
      if (a == BondAction::drop) continue;
      b.nbr[write] = b.nbr[k];
      b.kind[write] = b.kind[k];
      if (b.length_per_bond) b.lengths[write] = b.lengths[k];
      b.intact[write] = a == BondAction::keep_broken ? 0 : b.intact[k];
      ++write;
    }
    row_begin = row_end;
    b.offset[i + 1] = write;
  }
  b.nbr.resize(write);
  b.kind.resize(write);
  b.intact.resize(write);
  if (b.length_per_bond) b.lengths.resize(write);
  return touched;
}

template <double (*Get)(const BondKind&)>
inline double BondField<Get>::operator[](std::size_t k) const {
  return Get(b_->kind_of(k));
}
template <double (*Get)(const BondKind&)>
inline std::size_t BondField<Get>::size() const {
  return b_->nbr.size();
}

}  // namespace horizon
