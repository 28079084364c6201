#pragma once
// Bonds in compressed rows: particle i's bonds are [offset[i], offset[i+1]). Every
// bond is stored at both ends (directed), so that each particle's force is a sum
// over its own row, done by one thread in a fixed order (results independent of the
// thread count, no atomics). Reference data are computed once.
#include <cstdint>
#include <vector>

namespace horizon {

struct Bonds {
  std::vector<uint64_t> offset;   // size n + 1
  std::vector<uint32_t> nbr;      // neighbour index j
  std::vector<double> length;     // |xi| [m]
  std::vector<double> volume;     // V_j, scaled by the partial-volume factor when enabled
  std::vector<double> weight;     // influence function omega(|xi|)
  std::vector<uint8_t> intact;    // 1 intact, 0 broken (irreversible)

  std::size_t size() const { return nbr.size(); }
  std::size_t particles() const { return offset.empty() ? 0 : offset.size() - 1; }
  uint64_t begin(std::size_t i) const { return offset[i]; }
  uint64_t end(std::size_t i) const { return offset[i + 1]; }
};

}  // namespace horizon
