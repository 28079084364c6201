#pragma once
// The rows a pass of a model or solver that owns its loop computes: every particle's
// serially, the owned ones (System::owned) on a rank of a decomposed run
// (parallel/decomposition.hpp). Such a pass does not compute the bond neighbours' rows
// that System::active_rows adds for the general force pass: what its rows read of a
// neighbour beyond positions is computed by the neighbour's owner and sent to the ranks
// that hold it as a ghost.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "horizon/state/system.hpp"

namespace horizon {

struct OwnedRows {
  const std::vector<uint32_t>* own = nullptr;
  std::size_t count = 0;
  explicit OwnedRows(const System& s)
      : own(s.decomposition ? &s.owned : nullptr), count(own ? own->size() : s.particles.size()) {}
  std::size_t operator[](std::size_t k) const { return own ? (*own)[k] : k; }
};

}  // namespace horizon
