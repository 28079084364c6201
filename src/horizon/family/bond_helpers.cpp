#include "horizon/family/bond_helpers.hpp"

#include <algorithm>
#include <cstddef>
#include <string>

#include "horizon/core/error.hpp"

namespace horizon {

std::vector<uint64_t> reverse_bonds(const Bonds& B, bool partial) {
  std::vector<uint64_t> rev(B.size());
  const std::size_t n = B.particles();
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i)
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
      const uint32_t j = B.nbr[k];
      const auto first = B.nbr.begin() + static_cast<std::ptrdiff_t>(B.begin(j));
      const auto last = B.nbr.begin() + static_cast<std::ptrdiff_t>(B.end(j));
      if (partial && first == last) {
        rev[k] = k;
        continue;
      }
      const auto it = std::lower_bound(first, last, static_cast<uint32_t>(i));
      if (it == last || *it != i) throw Error("bond list is not symmetric: particle " + std::to_string(i));
      rev[k] = static_cast<uint64_t>(it - B.nbr.begin());
    }
  return rev;
}

}  // namespace horizon
