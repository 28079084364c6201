#include "horizon/family/neighbors.hpp"

#include <omp.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <tuple>

#include "horizon/core/error.hpp"
#include "horizon/family/cell_grid.hpp"

namespace horizon {

namespace {

constexpr double kRadiusTolerance = 1e-10;

// Calls visit(j) for every j != i within sqrt(r2) of points[i].
template <class Visit>
void for_each_neighbor(const CellGrid& g, const std::vector<Vec3>& points, std::size_t i, double r2, Visit visit) {
  const Vec3& p = points[i];
  g.for_each_candidate(p, [&](uint32_t j) {
    if (j != i && norm2(points[j] - p) <= r2) visit(j);
  });
}

// A grid a little wider than the accepted radius (radius * (1 + kRadiusTolerance)): a
// neighbour accepted through the tolerance must never land two cells away through
// round-off in the cell coordinates (a lattice with horizon = m spacings and a
// non-zero origin lost its on-sphere neighbours that way).
CellGrid make_grid(const std::vector<Vec3>& points, double radius) {
  return CellGrid::build(points.size(), [&](std::size_t i) { return points[i]; }, radius * (1 + 100 * kRadiusTolerance));
}

// The data that make a kind, compared bit for bit.
struct KindKey {
  uint64_t length, volume, fraction, weight;
  int32_t mi, mj;
  bool one_way;
  bool operator==(const KindKey&) const = default;
  auto tie() const { return std::tie(length, volume, fraction, weight, mi, mj, one_way); }
  bool operator<(const KindKey& o) const { return tie() < o.tie(); }
};

KindKey key_of(const BondKind& c) {
  return {std::bit_cast<uint64_t>(c.length), std::bit_cast<uint64_t>(c.volume), std::bit_cast<uint64_t>(c.fraction),
          std::bit_cast<uint64_t>(c.weight), c.material_i, c.material_j, c.one_way};
}

uint64_t hash_of(const KindKey& k) {
  uint64_t h = 0x9e3779b97f4a7c15ull;
  for (uint64_t v : {k.length, k.volume, k.fraction, k.weight,
                     (static_cast<uint64_t>(static_cast<uint32_t>(k.mi)) << 32) | static_cast<uint32_t>(k.mj),
                     static_cast<uint64_t>(k.one_way)}) {
    h ^= v + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
    h *= 0xff51afd7ed558ccdull;
  }
  return h ^ (h >> 33);
}

// Open-addressing set/map of kind keys (linear probing): a lattice has a few dozen
// kinds, so lookups hit the first probe and stay in L1.
class KindTable {
 public:
  explicit KindTable(std::size_t expected = 16) {
    std::size_t cap = 32;
    while (cap < 2 * expected) cap *= 2;
    slots_.assign(cap, Slot{});
  }
  // Returns (index, inserted).
  std::pair<uint32_t, bool> insert(const KindKey& k, uint32_t value) {
    if (2 * (count_ + 1) > slots_.size()) grow();
    std::size_t s = hash_of(k) & (slots_.size() - 1);
    for (;; s = (s + 1) & (slots_.size() - 1)) {
      Slot& slot = slots_[s];
      if (!slot.used) {
        slot = {k, value, true};
        ++count_;
        return {value, true};
      }
      if (slot.key == k) return {slot.value, false};
    }
  }
  uint32_t find(const KindKey& k) const {
    for (std::size_t s = hash_of(k) & (slots_.size() - 1);; s = (s + 1) & (slots_.size() - 1)) {
      const Slot& slot = slots_[s];
      if (slot.used && slot.key == k) return slot.value;
      if (!slot.used) throw Error("internal error: a bond kind is missing from its table");
    }
  }

 private:
  struct Slot {
    KindKey key{};
    uint32_t value = 0;
    bool used = false;
  };
  void grow() {
    std::vector<Slot> old(slots_.size() * 2);
    old.swap(slots_);
    count_ = 0;
    for (const Slot& s : old)
      if (s.used) insert(s.key, s.value);
  }
  std::vector<Slot> slots_;
  std::size_t count_ = 0;
};

// Gives every bond the kind of the data key(i, k) returns. Kinds are numbered in
// sorted order of their keys, so the numbering does not depend on the thread count.
template <class KeyFn>
void regroup(Bonds& b, KeyFn key) {
  const std::size_t n = b.particles();
  const int threads = omp_get_max_threads();
  std::vector<std::vector<BondKind>> found(static_cast<std::size_t>(threads));
#pragma omp parallel num_threads(threads)
  {
    KindTable seen;
    auto& mine = found[static_cast<std::size_t>(omp_get_thread_num())];
#pragma omp for schedule(static)
    for (std::size_t i = 0; i < n; ++i)
      for (uint64_t k = b.begin(i); k < b.end(i); ++k) {
        const BondKind c = key(i, k);
        if (seen.insert(key_of(c), 0).second) mine.push_back(c);
      }
  }
  std::vector<BondKind> all;
  for (auto& f : found) all.insert(all.end(), f.begin(), f.end());
  std::sort(all.begin(), all.end(), [](const BondKind& a, const BondKind& c) { return key_of(a) < key_of(c); });
  all.erase(std::unique(all.begin(), all.end(),
                        [](const BondKind& a, const BondKind& c) { return key_of(a) == key_of(c); }),
            all.end());
  if (all.size() >= (1ull << 32)) throw Error("more than 2^32 bond kinds");
  KindTable index(all.size());
  for (std::size_t q = 0; q < all.size(); ++q) index.insert(key_of(all[q]), static_cast<uint32_t>(q));
  b.kind.resize(b.size());
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i)
    for (uint64_t k = b.begin(i); k < b.end(i); ++k) b.kind[k] = index.find(key_of(key(i, k)));
  b.kinds = std::move(all);
}

void fill_reference_data(Bonds& b, const std::vector<Vec3>& points, const std::vector<double>& volume,
                         const std::vector<int32_t>* material) {
  b.intact.assign(b.size(), 1);
  regroup(b, [&](std::size_t i, uint64_t k) {
    const uint32_t j = b.nbr[k];
    BondKind c;
    c.length = norm(points[j] - points[i]);
    c.volume = volume[j];
    if (material) c.material_i = (*material)[i], c.material_j = (*material)[j];
    return c;
  });
}

// What bond i->j shares with other bonds besides its length: V_j and the materials.
BondKind shared_part(std::size_t i, uint32_t j, const std::vector<double>& volume,
                     const std::vector<int32_t>* material) {
  BondKind c;
  c.length = 0;
  c.volume = volume[j];
  if (material) c.material_i = (*material)[i], c.material_j = (*material)[j];
  return c;
}

// Whether kinds with lengths would cost more memory than a length per bond: a kind costs
// sizeof(BondKind) here and kKindBytes in the force loops' tables (state/system.hpp
// KindCoefficients and the two 32-byte records of the state-based passes), a per-bond
// length 8 bytes; and at least kMinKinds kinds (small tables stay kinds: they fit in
// cache). Counts the distinct (length, shared kind) pairs in bond order until the limit
// is passed, so the answer does not depend on the thread count.
constexpr std::size_t kKindBytes = 128;
constexpr std::size_t kMinKinds = 8192;
template <class LengthFn>
bool lengths_vary(const Bonds& b, LengthFn length) {
  const std::size_t limit = std::max<std::size_t>(kMinKinds, b.size() * sizeof(double) / (sizeof(BondKind) + kKindBytes));
  if (b.size() <= limit) return false;
  std::size_t cap = 64;
  while (cap < 2 * (limit + 1)) cap *= 2;
  struct Slot {
    uint64_t length;
    uint32_t kind;
    bool used;
  };
  std::vector<Slot> slots(cap, Slot{0, 0, false});
  std::size_t count = 0;
  const std::size_t n = b.particles();
  for (std::size_t i = 0; i < n; ++i)
    for (uint64_t k = b.offset[i]; k < b.offset[i + 1]; ++k) {
      const uint64_t L = std::bit_cast<uint64_t>(length(i, k));
      uint64_t h = (L ^ (static_cast<uint64_t>(b.kind[k]) << 40)) * 0x9e3779b97f4a7c15ull;
      for (std::size_t s = (h ^ (h >> 29)) & (cap - 1);; s = (s + 1) & (cap - 1)) {
        Slot& slot = slots[s];
        if (!slot.used) {
          slot = {L, b.kind[k], true};
          if (++count > limit) return true;
          break;
        }
        if (slot.length == L && slot.kind == b.kind[k]) break;
      }
    }
  return false;
}

}  // namespace

Bonds find_neighbors(const std::vector<Vec3>& points, const std::vector<double>& volume, double radius,
                     const std::vector<int32_t>* material, const std::vector<uint8_t>* rows) {
  if (points.size() >= (1ull << 32)) throw Error("more than 2^32 particles on one process");
  const double r2 = radius * radius * (1 + 2 * kRadiusTolerance);
  const CellGrid g = make_grid(points, radius);
  const std::size_t n = points.size();
  Bonds b;
  b.offset.assign(n + 1, 0);
  // Pass 1 counts, pass 2 fills: no per-particle allocation, memory exactly O(bonds).
#pragma omp parallel for schedule(dynamic, 1024)
  for (std::size_t i = 0; i < n; ++i) {
    uint64_t count = 0;
    if (rows && !(*rows)[i]) {
      b.offset[i + 1] = 0;
      continue;
    }
    for_each_neighbor(g, points, i, r2, [&](uint32_t) { ++count; });
    b.offset[i + 1] = count;
  }
  for (std::size_t i = 0; i < n; ++i) b.offset[i + 1] += b.offset[i];
  b.nbr.resize(b.offset[n]);
  b.kind.resize(b.offset[n]);
  b.intact.assign(b.offset[n], 1);
  // Fill, sort each row, and give each bond the kind of what it shares besides its length
  // (V_j, the materials), numbered per thread (thread t owns the particles
  // [n t / T, n (t + 1) / T)); then renumber the kinds in sorted order, so that the
  // result does not depend on the thread count.
  const int threads = omp_get_max_threads();
  std::vector<std::vector<BondKind>> found(static_cast<std::size_t>(threads));
  auto range = [&](int t) { return std::pair<std::size_t, std::size_t>{n * t / threads, n * (t + 1) / threads}; };
#pragma omp parallel num_threads(threads)
  {
    const int t = omp_get_thread_num();
    auto& mine = found[static_cast<std::size_t>(t)];
    KindTable table;
    const auto [first, last] = range(t);
    for (std::size_t i = first; i < last; ++i) {
      if (rows && !(*rows)[i]) continue;
      uint64_t k = b.offset[i];
      for_each_neighbor(g, points, i, r2, [&](uint32_t j) { b.nbr[k++] = j; });
      std::sort(b.nbr.begin() + static_cast<int64_t>(b.offset[i]), b.nbr.begin() + static_cast<int64_t>(k));
      for (k = b.offset[i]; k < b.offset[i + 1]; ++k) {
        const BondKind c = shared_part(i, b.nbr[k], volume, material);
        const auto [id, inserted] = table.insert(key_of(c), static_cast<uint32_t>(mine.size()));
        if (inserted) mine.push_back(c);
        b.kind[k] = id;
      }
    }
  }
  std::vector<BondKind> all;
  for (auto& f : found) all.insert(all.end(), f.begin(), f.end());
  std::sort(all.begin(), all.end(), [](const BondKind& x, const BondKind& y) { return key_of(x) < key_of(y); });
  all.erase(std::unique(all.begin(), all.end(),
                        [](const BondKind& x, const BondKind& y) { return key_of(x) == key_of(y); }),
            all.end());
  if (all.size() >= (1ull << 32)) throw Error("more than 2^32 bond kinds");
  KindTable index(all.size());
  for (std::size_t q = 0; q < all.size(); ++q) index.insert(key_of(all[q]), static_cast<uint32_t>(q));
#pragma omp parallel num_threads(threads)
  {
    const int t = omp_get_thread_num();
    const auto& mine = found[static_cast<std::size_t>(t)];
    std::vector<uint32_t> remap(mine.size());
    for (std::size_t q = 0; q < mine.size(); ++q) remap[q] = index.find(key_of(mine[q]));
    const auto [first, last] = range(t);
    for (uint64_t k = b.offset[first]; k < b.offset[last]; ++k) b.kind[k] = remap[b.kind[k]];
  }
  b.kinds = std::move(all);
  found.clear();
  // Each bond's exact |xi|, as the kinds with lengths computed it.
  auto length = [&](std::size_t i, uint64_t k) { return norm(points[b.nbr[k]] - points[i]); };
  if (lengths_vary(b, length)) {
    b.length_per_bond = true;
    b.lengths.resize(b.size());
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i)
      for (uint64_t k = b.offset[i]; k < b.offset[i + 1]; ++k) b.lengths[k] = length(i, k);
    return b;
  }
  const std::vector<BondKind> shared = b.kinds;
  regroup(b, [&](std::size_t i, uint64_t k) {
    BondKind c = shared[b.kind[k]];
    c.length = length(i, k);
    return c;
  });
  return b;
}

Bonds find_neighbors_brute_force(const std::vector<Vec3>& points, const std::vector<double>& volume,
                                 double radius) {
  const double r2 = radius * radius * (1 + 2 * kRadiusTolerance);
  Bonds b;
  b.offset.push_back(0);
  for (std::size_t i = 0; i < points.size(); ++i) {
    for (std::size_t j = 0; j < points.size(); ++j)
      if (j != i && norm2(points[j] - points[i]) <= r2) b.nbr.push_back(static_cast<uint32_t>(j));
    b.offset.push_back(b.nbr.size());
  }
  fill_reference_data(b, points, volume, nullptr);
  return b;
}

void expand_kinds(Bonds& bonds) {
  if (!bonds.length_per_bond) return;
  const std::vector<BondKind> shared = bonds.kinds;
  regroup(bonds, [&](std::size_t, uint64_t k) {
    BondKind c = shared[bonds.kind[k]];
    c.length = bonds.lengths[k];
    return c;
  });
  bonds.lengths = {};
  bonds.length_per_bond = false;
}

void apply_partial_volume(Bonds& bonds, double horizon, double spacing) {
  if (bonds.length_per_bond) {
    // The fraction varies with |xi| only beyond horizon - spacing/2: kinds with lengths
    // where some bond reaches there.
    bool inner = true;
    for (double r : bonds.lengths) inner = inner && !(r > horizon - 0.5 * spacing);
    if (inner) return;  // every fraction stays 1
    expand_kinds(bonds);
  }
  for (auto& c : bonds.kinds) {
    const double r = c.length;
    c.fraction = r > horizon - 0.5 * spacing ? std::clamp((horizon + 0.5 * spacing - r) / spacing, 0.0, 1.0) : 1.0;
  }
}

namespace {

// Gives every bond kind the per-particle labels `label` of its two ends in the fields
// `end_i`, `end_j`, splitting a kind whose bonds join differently labelled particles;
// a no-op when every kind already agrees.
void split_kinds_by(Bonds& bonds, const std::vector<int32_t>& label, int32_t BondKind::*end_i,
                    int32_t BondKind::*end_j) {
  const std::size_t n = bonds.particles();
  bool consistent = true;
#pragma omp parallel for schedule(static) reduction(&& : consistent)
  for (std::size_t i = 0; i < n; ++i)
    for (uint64_t k = bonds.begin(i); k < bonds.end(i); ++k) {
      const BondKind& c = bonds.kinds[bonds.kind[k]];
      consistent = consistent && c.*end_i == label[i] && c.*end_j == label[bonds.nbr[k]];
    }
  if (consistent) return;
  const std::vector<BondKind> old = bonds.kinds;
  regroup(bonds, [&](std::size_t i, uint64_t k) {
    BondKind c = old[bonds.kind[k]];
    c.*end_i = label[i];
    c.*end_j = label[bonds.nbr[k]];
    return c;
  });
}

}  // namespace

void split_kinds_by_material(Bonds& bonds, const std::vector<int32_t>& material) {
  split_kinds_by(bonds, material, &BondKind::material_i, &BondKind::material_j);
}

void scale_bond_weights(Bonds& bonds, const std::vector<double>& factor) {
  expand_kinds(bonds);  // per-bond weights: the kinds carry them with their lengths
  const std::vector<BondKind> old = bonds.kinds;
  regroup(bonds, [&](std::size_t, uint64_t k) {
    BondKind c = old[bonds.kind[k]];
    c.weight *= factor[k];
    return c;
  });
}

uint64_t restrict_to_horizons(Bonds& bonds, const std::vector<double>& horizon) {
  rewrite_bonds(bonds, [&](std::size_t i, uint64_t k) {
    const double L = bonds.length_of(k);
    return within_horizon(L, horizon[i]) || within_horizon(L, horizon[bonds.nbr[k]]) ? BondAction::keep
                                                                                      : BondAction::drop;
  });
  uint64_t one_way = 0;
  for (std::size_t i = 0; i < bonds.particles(); ++i)
    for (uint64_t k = bonds.begin(i); k < bonds.end(i); ++k) one_way += within_horizon(bonds.length_of(k), horizon[i]) ? 0 : 1;
  if (one_way == 0) return 0;  // every pair in both families: the kinds stay as they are
  const std::vector<BondKind> old = bonds.kinds;
  regroup(bonds, [&](std::size_t i, uint64_t k) {
    BondKind c = old[bonds.kind[k]];
    c.one_way = !within_horizon(bonds.length_of(k), horizon[i]);
    return c;
  });
  return one_way;
}

}  // namespace horizon
