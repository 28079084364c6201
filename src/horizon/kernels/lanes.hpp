#pragma once
// The fast loops' eight lanes as device-portable helpers (core/portable.hpp, issue 30):
// shared by the flat rows of PMB and LPS (kernels/flat_system.hpp) and the affine pass of
// correspondence (kernels/affine.hpp).
#include <cstdint>

#include "horizon/core/portable.hpp"

namespace horizon::kernels {

// A row's sums in the host's lanes (solver/forces.cpp): bond k of a row adds into lane
// (k - begin) mod 8 and the lanes are added as ((l0 + l1) + (l2 + l3)) + ((l4 + l5) +
// (l6 + l7)) at the end of the row, the smallest stretch as std::min over the lanes. The
// fast loops (scalar, AVX2, AVX-512) all sum so, so a flat row gives their bits and a
// flat run the CPU backend's (tests/regression/test_backend.cpp). The lane is a constant
// once the loop is unrolled, so the eight partial sums stay in registers.
constexpr int kLanes = 8;
#if defined(__CUDA_ARCH__)  // nvcc's device pass
#define HORIZON_UNROLL _Pragma("unroll")
#elif defined(__CUDACC__)  // nvcc's host pass (the host compiler unrolls on its own)
#define HORIZON_UNROLL
#elif defined(__clang__)
#define HORIZON_UNROLL _Pragma("clang loop unroll(full)")
#elif defined(__GNUC__)
#define HORIZON_UNROLL _Pragma("GCC unroll 8")
#else
#define HORIZON_UNROLL
#endif
template <class F>
HORIZON_HD inline void for_each_lane(uint64_t begin, uint64_t end, F&& f) {
  uint64_t k = begin;
  for (; k + kLanes <= end; k += kLanes) {
    HORIZON_UNROLL
    for (int l = 0; l < kLanes; ++l) f(k + static_cast<uint64_t>(l), l);
  }
  HORIZON_UNROLL
  for (int l = 0; l < kLanes - 1; ++l)
    if (k + static_cast<uint64_t>(l) < end) f(k + static_cast<uint64_t>(l), l);
}
HORIZON_HD inline double lane_total(const double* v) {
  return ((v[0] + v[1]) + (v[2] + v[3])) + ((v[4] + v[5]) + (v[6] + v[7]));
}
HORIZON_HD inline double lane_min(const double* v) {
  double m = v[0];
  for (int l = 1; l < kLanes; ++l) m = v[l] < m ? v[l] : m;  // std::min(m, v[l])
  return m;
}

}  // namespace horizon::kernels
