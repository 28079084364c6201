// ordinary_rows.hpp: the body is written once (always inline) and built three times, for
// AVX-512, AVX2 and the build's own target (no FMA contraction and no FP traps in this
// file, CMakeLists.txt: a masked lane may divide by 0 and is never selected).
#include "horizon/material/models/ordinary_rows.hpp"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define HORIZON_ROWS_X86 1
#define HORIZON_AVX2 __attribute__((target("avx2")))
#define HORIZON_AVX512 __attribute__((target("avx2,avx512f,avx512vl,avx512bw,avx512dq")))
#endif

namespace horizon::rows {

namespace {

__attribute__((always_inline)) inline void scalars_body(const double* __restrict t, const double* __restrict r,
                                                        const uint8_t* __restrict intact, bool positive,
                                                        uint64_t first, uint64_t last, double* __restrict q) {
  if (positive) {
    for (uint64_t k = first; k < last; ++k) q[k] = intact[k] && r[k] > 0 ? t[k] / r[k] : 0.0;
  } else {
    for (uint64_t k = first; k < last; ++k) q[k] = intact[k] ? t[k] / r[k] : 0.0;
  }
}

#if defined(HORIZON_ROWS_X86)
HORIZON_AVX2 void scalars_avx2(const double* t, const double* r, const uint8_t* intact, bool positive, uint64_t first,
                               uint64_t last, double* q) {
  scalars_body(t, r, intact, positive, first, last, q);
}
HORIZON_AVX512 void scalars_avx512(const double* t, const double* r, const uint8_t* intact, bool positive,
                                   uint64_t first, uint64_t last, double* q) {
  scalars_body(t, r, intact, positive, first, last, q);
}

enum class Isa { base, avx2, avx512 };
Isa isa() {
  static const Isa level = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
                                   __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq")
                               ? Isa::avx512
                           : __builtin_cpu_supports("avx2") ? Isa::avx2
                                                            : Isa::base;
  return level;
}
#endif

}  // namespace

void force_scalars(const double* t, const double* r, const uint8_t* intact, bool positive, uint64_t first,
                   uint64_t last, double* q) {
#if defined(HORIZON_ROWS_X86)
  if (isa() == Isa::avx512) return scalars_avx512(t, r, intact, positive, first, last, q);
  if (isa() == Isa::avx2) return scalars_avx2(t, r, intact, positive, first, last, q);
#endif
  scalars_body(t, r, intact, positive, first, last, q);
}

}  // namespace horizon::rows
