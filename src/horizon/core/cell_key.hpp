#pragma once
// Keys of a hash grid over space: the cell of a point for a cell edge, packed into one
// 64-bit key (21 bits per axis), for the cell lists that live in hash maps (the
// short-range contact, crack-path searches).
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "horizon/core/vec3.hpp"

namespace horizon {

inline constexpr int64_t kCellBias = int64_t{1} << 20;  // cell coordinates within +-2^20 of the origin

inline int64_t cell_coord(double x, double edge) {
  return std::clamp<int64_t>(static_cast<int64_t>(std::floor(x / edge)), -kCellBias + 2, kCellBias - 2);
}
inline uint64_t pack_cell(int64_t a, int64_t b, int64_t c) {
  return (static_cast<uint64_t>(a + kCellBias) << 42) | (static_cast<uint64_t>(b + kCellBias) << 21) |
         static_cast<uint64_t>(c + kCellBias);
}

}  // namespace horizon
