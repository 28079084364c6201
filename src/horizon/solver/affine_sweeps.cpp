// The affine pass's breaking sweep in eight lanes (solver/affine_sweeps.hpp). Compiled
// with the fast loops' options (CMakeLists.txt: no FMA contraction, so that every target
// computes a lane as the portable row computes it; no errno or FP traps, so that sqrt
// vectorises and masked lanes may hold anything).
#include "horizon/solver/affine_sweeps.hpp"

#include <cmath>
#include <cstring>
#include <limits>
#include <string_view>
#include <type_traits>
#include <utility>

#include "horizon/kernels/affine.hpp"
#include "horizon/solver/forces.hpp"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define HORIZON_SWEEPS_X86 1
#define HORIZON_AVX512 __attribute__((target("avx2,avx512f,avx512vl,avx512bw,avx512dq")))
#endif

namespace horizon::affine_sweeps {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kSums = 18;  // K, then N (kernels/affine.hpp GradientSums)

inline double total8(const double* v) { return kernels::lane_total(v); }
inline double min8(const double* v) { return kernels::lane_min(v); }

// The portable rows: the device-portable kernels (kernels/affine.hpp), eight lanes of
// scalar accumulators.
BreakOut break_row_portable(const Sweep& s, std::size_t i, double* sums) { return kernels::affine_break_row(s, i, sums); }
void sum_row_portable(const Sweep& s, std::size_t i, double* f, double& energy) {
  kernels::affine_sum_row(s, i, f, energy);
}

#if defined(HORIZON_SWEEPS_X86)

// The eight-lane vectors below never cross a call (every function that takes or returns
// one is inlined into its target's row), so GCC's note that their ABI depends on AVX-512
// says nothing here.
#pragma GCC diagnostic ignored "-Wpsabi"

// ------------------------------------------------------------------------------------
// The vector rows: the arithmetic written once on eight-lane vectors (GCC's vector
// extensions), the loads per target. Only AVX-512 takes them: an AVX2 build of the same
// rows (each eight-lane vector in two 256-bit registers: the 18 sums of the breaking
// sweep alone fill 36 of its 16 registers) ran 15.5 ns a bond-step against 13.6 for the
// portable rows and 12.8 for the bond-order loop before them (docs/benchmarks.md), so
// AVX2 machines take the portable rows.

using v8d = double __attribute__((vector_size(64)));
using v8l = int64_t __attribute__((vector_size(64)));

// Eight bonds k .. k + count - 1 of row i in lanes 0..7; lanes past the row's end are
// padding (the particle itself, bond k's kind) and never live.
struct Block {
  v8d Yx, Yy, Yz, wj;  // Y = y_j - y_i; the neighbour's s0
  v8d xx, xy, xz;      // xi = X_j - X_i
  v8d L, iL, w;        // the kind's |xi|, 1/|xi|, omega V_j
  v8l live;            // intact != 0
};

// The intact flags of bonds k .. k + count - 1 as 8 bytes (one load where the array allows).
inline uint64_t flags_of(const Sweep& s, uint64_t k, int count) {
  uint64_t flags = 0;
  if (k + 8 <= s.total) {
    std::memcpy(&flags, s.intact + k, 8);
  } else {
    for (int l = 0; l < 8 && k + static_cast<uint64_t>(l) < s.total; ++l)
      flags |= static_cast<uint64_t>(s.intact[k + static_cast<uint64_t>(l)]) << (8 * l);
  }
  if (count < 8) flags &= (uint64_t{1} << (8 * count)) - 1;
  return flags;
}

// The breaking lanes of a block (bit l: lane l), in bond order, each bond's r and e
// recomputed from the arrays exactly as the lanes compute them.
__attribute__((noinline)) void block_breaks(const Sweep& s, std::size_t i, uint64_t k, unsigned mask, BreakOut& out) {
  const Point4 pi = s.pt[i];
  for (int l = 0; l < 8; ++l) {
    if (!((mask >> l) & 1u)) continue;
    const uint64_t kk = k + static_cast<uint64_t>(l);
    const Point4 pj = s.pt[s.nbr[kk]], kr = s.kind_record[s.kind[kk]];
    const double Yx = pj.x - pi.x, Yy = pj.y - pi.y, Yz = pj.z - pi.z;
    const double r = std::sqrt(Yx * Yx + Yy * Yy + Yz * Yz);
    kernels::affine_break_bond(s, i, kk, r, r - kr.x, out);
  }
}

// The record pointers of a block (padding lanes: the particle itself, bond k's kind).
struct Pointers {
  const double* pt[8];
  const double* ref[8];
  const double* kind[8];
  const double* record[8];  // the neighbour's record of this pass (the sum)
};
inline void pointers(const Sweep& s, std::size_t i, uint64_t k, int count, Pointers& p) {
  for (int l = 0; l < 8; ++l) {
    const bool in = l < count;
    const uint64_t kk = in ? k + static_cast<uint64_t>(l) : k;
    const std::size_t j = in ? s.nbr[kk] : i;
    p.pt[l] = &s.pt[j].x;
    p.ref[l] = &s.ref[j].x;
    p.kind[l] = &s.kind_record[s.kind[kk]].x;
    p.record[l] = s.record + kernels::kAffineRecord * j;
  }
}

// The neighbours' records {M row by row, g} of a block, in lanes.
struct Records {
  v8d m[9], g;
};

// The row's arithmetic, written once for the per-target rows below (a macro: a template
// could not call the targets' loaders, whose intrinsics need the caller's target), on a
// loader (Target) that fills a Block and tells the lanes of a mask as bits. Lanes that
// do not act add +0, which changes no sum (a lane's sum starts at +0 and never becomes
// -0): as if skipped, as the portable row skips them.
#define HORIZON_AFFINE_BREAK_ROW(Target) \
  const Point4 pi = s.pt[i], xi_i = s.ref[i];                                                     \
  const v8d s0i = v8d{} + pi.w;                                                                   \
  const v8d zero = {};                                                                            \
  v8d acc[kSums];                                                                                 \
  for (int q = 0; q < kSums; ++q) acc[q] = zero;                                                  \
  v8d sm = zero + kInf;                                                                           \
  BreakOut out{kInf, 0, 0};                                                                       \
  const uint64_t begin = s.offset[i], end = s.offset[i + 1];                                      \
  for (uint64_t k = begin; k < end; k += 8) {                                                     \
    const int count = end - k < 8 ? static_cast<int>(end - k) : 8;                                \
    const uint64_t flags = flags_of(s, k, count);                                                 \
    if (!flags) continue;                                                                         \
    Pointers p;                                                                                   \
    pointers(s, i, k, count, p);                                                                  \
    Block b;                                                                                      \
    Target::load(p, flags, b);                                                                    \
    const v8d Yx = b.Yx - pi.x, Yy = b.Yy - pi.y, Yz = b.Yz - pi.z;                               \
    const v8d xi[3] = {b.xx - xi_i.x, b.xy - xi_i.y, b.xz - xi_i.z};                              \
    const v8d r = Target::sqrt(Yx * Yx + Yy * Yy + Yz * Yz), e = r - b.L, stretch = e * b.iL;     \
    sm = (b.live & (stretch < sm)) ? stretch : sm;                                                \
    const v8d s0 = s0i < b.wj ? s0i : b.wj;                                                       \
    const v8l breaks = b.live & (stretch > s0);                                                   \
    const v8l counts = s.after ? b.live : b.live & ~breaks;                                       \
    const v8d Y[3] = {Yx, Yy, Yz};                                                                \
    for (int a = 0; a < 3; ++a) {                                                                 \
      const v8d wa = b.w * xi[a], wy = b.w * Y[a];                                                \
      for (int c = 0; c < 3; ++c) {                                                               \
        acc[3 * a + c] += reinterpret_cast<v8d>(counts & reinterpret_cast<v8l>(wa * xi[c]));      \
        acc[9 + 3 * a + c] += reinterpret_cast<v8d>(counts & reinterpret_cast<v8l>(wy * xi[c]));  \
      }                                                                                           \
    }                                                                                             \
    if (const unsigned mask = Target::bits(breaks)) block_breaks(s, i, k, mask, out);             \
  }                                                                                               \
  alignas(64) double lanes[8];                                                                    \
  for (int q = 0; q < kSums; ++q) {                                                               \
    std::memcpy(lanes, &acc[q], sizeof lanes);                                                    \
    sums[q] = total8(lanes);                                                                      \
  }                                                                                               \
  std::memcpy(lanes, &sm, sizeof lanes);                                                          \
  out.smin = min8(lanes);                                                                         \
  return out;                                                                                     \
  static_assert(true)

// The sum's arithmetic, written once for the per-target rows below (as the breaking
// row's; kernels/affine.hpp affine_pair_add lane by lane, then affine_pair_finish).
#define HORIZON_AFFINE_SUM_ROW(Target) \
  const Point4 pi = s.pt[i], xi_i = s.ref[i];                                                       \
  const v8d zero = {};                                                                              \
  v8d sxi[3] = {zero, zero, zero}, sy[3] = {zero, zero, zero}, acc[3] = {zero, zero, zero};         \
  const uint64_t begin = s.offset[i], end = s.offset[i + 1];                                        \
  for (uint64_t k = begin; k < end; k += 8) {                                                       \
    const int count = end - k < 8 ? static_cast<int>(end - k) : 8;                                  \
    const uint64_t flags = flags_of(s, k, count);                                                   \
    if (!flags) continue;                                                                           \
    Pointers p;                                                                                     \
    pointers(s, i, k, count, p);                                                                    \
    Block b;                                                                                        \
    Target::load(p, flags, b);                                                                      \
    Records m;                                                                                      \
    Target::records(p, m);                                                                          \
    const v8d Y[3] = {b.Yx - pi.x, b.Yy - pi.y, b.Yz - pi.z};                                       \
    const v8d xi[3] = {b.xx - xi_i.x, b.xy - xi_i.y, b.xz - xi_i.z};                                \
    const v8d a[3] = {b.w * xi[0], b.w * xi[1], b.w * xi[2]};                                       \
    const v8d gy = b.w * m.g;                                                                       \
    for (int r = 0; r < 3; ++r) {                                                                   \
      sxi[r] += reinterpret_cast<v8d>(b.live & reinterpret_cast<v8l>(a[r]));                        \
      sy[r] += reinterpret_cast<v8d>(b.live & reinterpret_cast<v8l>(b.w * Y[r]));                   \
      const v8d t = m.m[3 * r] * a[0] + m.m[3 * r + 1] * a[1] + m.m[3 * r + 2] * a[2] + gy * Y[r];  \
      acc[r] += reinterpret_cast<v8d>(b.live & reinterpret_cast<v8l>(t));                           \
    }                                                                                               \
  }                                                                                                 \
  kernels::AffineRowSum sum;                                                                 \
  alignas(64) double lanes[8];                                                                      \
  for (int r = 0; r < 3; ++r) {                                                                     \
    std::memcpy(lanes, &sxi[r], sizeof lanes);                                                      \
    sum.sxi[r] = total8(lanes);                                                                     \
    std::memcpy(lanes, &sy[r], sizeof lanes);                                                       \
    sum.sy[r] = total8(lanes);                                                                      \
    std::memcpy(lanes, &acc[r], sizeof lanes);                                                      \
    sum.acc[r] = total8(lanes);                                                                     \
  }                                                                                                 \
  kernels::affine_pair_finish(sum, s.record + kernels::kAffineRecord * i, f);         \
  energy = 0;                                                                                       \
  static_assert(true)

// AVX-512: eight 32-byte records transposed into four registers (solver/forces.cpp transpose8).
struct Avx512 {
  HORIZON_AVX512 __attribute__((always_inline)) static __m512d join8(__m256d a, __m256d b) {
    return _mm512_mask_broadcast_f64x4(_mm512_mask_broadcast_f64x4(_mm512_setzero_pd(), 0x0F, a), 0xF0, b);
  }
  HORIZON_AVX512 __attribute__((always_inline)) static void transpose8(const double* const* rec, v8d& a, v8d& b, v8d& c, v8d& d) {
    const __m512d z0 = join8(_mm256_loadu_pd(rec[0]), _mm256_loadu_pd(rec[1]));
    const __m512d z1 = join8(_mm256_loadu_pd(rec[2]), _mm256_loadu_pd(rec[3]));
    const __m512d z2 = join8(_mm256_loadu_pd(rec[4]), _mm256_loadu_pd(rec[5]));
    const __m512d z3 = join8(_mm256_loadu_pd(rec[6]), _mm256_loadu_pd(rec[7]));
    const __m512d t0 = _mm512_unpacklo_pd(z0, z1), t1 = _mm512_unpackhi_pd(z0, z1);
    const __m512d t2 = _mm512_unpacklo_pd(z2, z3), t3 = _mm512_unpackhi_pd(z2, z3);
    const __m512i first = _mm512_setr_epi64(0, 4, 1, 5, 8, 12, 9, 13);
    const __m512i second = _mm512_setr_epi64(2, 6, 3, 7, 10, 14, 11, 15);
    a = reinterpret_cast<v8d>(_mm512_permutex2var_pd(t0, first, t2));
    b = reinterpret_cast<v8d>(_mm512_permutex2var_pd(t1, first, t3));
    c = reinterpret_cast<v8d>(_mm512_permutex2var_pd(t0, second, t2));
    d = reinterpret_cast<v8d>(_mm512_permutex2var_pd(t1, second, t3));
  }
  HORIZON_AVX512 __attribute__((always_inline)) static void load(const Pointers& p, uint64_t flags, Block& b) {
    v8d unused;
    transpose8(p.pt, b.Yx, b.Yy, b.Yz, b.wj);
    transpose8(p.ref, b.xx, b.xy, b.xz, unused);
    transpose8(p.kind, b.L, b.iL, b.w, unused);
    const __m512i f = _mm512_cvtepu8_epi64(_mm_cvtsi64_si128(static_cast<long long>(flags)));
    b.live = reinterpret_cast<v8l>(_mm512_movm_epi64(_mm512_test_epi64_mask(f, f)));
  }
  // The records' last two numbers (loaded two by two: a record may end the array).
  HORIZON_AVX512 __attribute__((always_inline)) static void pairs8(const double* const* rec, v8d& a, v8d& b) {
    const __m512d z0 = join8(_mm256_maskz_loadu_pd(3, rec[0]), _mm256_maskz_loadu_pd(3, rec[1]));
    const __m512d z1 = join8(_mm256_maskz_loadu_pd(3, rec[2]), _mm256_maskz_loadu_pd(3, rec[3]));
    const __m512d z2 = join8(_mm256_maskz_loadu_pd(3, rec[4]), _mm256_maskz_loadu_pd(3, rec[5]));
    const __m512d z3 = join8(_mm256_maskz_loadu_pd(3, rec[6]), _mm256_maskz_loadu_pd(3, rec[7]));
    const __m512d t0 = _mm512_unpacklo_pd(z0, z1), t1 = _mm512_unpackhi_pd(z0, z1);
    const __m512d t2 = _mm512_unpacklo_pd(z2, z3), t3 = _mm512_unpackhi_pd(z2, z3);
    const __m512i first = _mm512_setr_epi64(0, 4, 1, 5, 8, 12, 9, 13);
    a = reinterpret_cast<v8d>(_mm512_permutex2var_pd(t0, first, t2));
    b = reinterpret_cast<v8d>(_mm512_permutex2var_pd(t1, first, t3));
  }
  HORIZON_AVX512 __attribute__((always_inline)) static void records(const Pointers& p, Records& r) {
    const double* q[8];
    transpose8(p.record, r.m[0], r.m[1], r.m[2], r.m[3]);
    for (int l = 0; l < 8; ++l) q[l] = p.record[l] + 4;
    transpose8(q, r.m[4], r.m[5], r.m[6], r.m[7]);
    for (int l = 0; l < 8; ++l) q[l] = p.record[l] + 8;
    pairs8(q, r.m[8], r.g);
  }
  HORIZON_AVX512 __attribute__((always_inline)) static v8d sqrt(v8d x) { return reinterpret_cast<v8d>(_mm512_sqrt_pd(reinterpret_cast<__m512d>(x))); }
  HORIZON_AVX512 __attribute__((always_inline)) static unsigned bits(v8l m) { return _mm512_movepi64_mask(reinterpret_cast<__m512i>(m)); }
};

HORIZON_AVX512 BreakOut break_row_avx512(const Sweep& s, std::size_t i, double* sums) {
  HORIZON_AFFINE_BREAK_ROW(Avx512);
}
HORIZON_AVX512 void sum_row_avx512(const Sweep& s, std::size_t i, double* f, double& energy) {
  HORIZON_AFFINE_SUM_ROW(Avx512);
}
#undef HORIZON_AFFINE_BREAK_ROW
#undef HORIZON_AFFINE_SUM_ROW

// The AVX-512 rows where the machine has them and set_kernel_path leaves the fast loops'
// widest path ("scalar" and "avx2" take the portable rows).
bool use_avx512() {
  static const bool available = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
                                __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq");
  const std::string_view path = kernel_path_name();
  return available && path != "scalar" && path != "avx2";
}
#endif  // HORIZON_SWEEPS_X86

}  // namespace

BreakRow break_row_for(const Sweep& s) {
#if defined(HORIZON_SWEEPS_X86)
  if (!s.soft && s.kinds_have_lengths && use_avx512()) return break_row_avx512;
#endif
  return break_row_portable;
}

SumRow sum_row_for(const Sweep& s) {
#if defined(HORIZON_SWEEPS_X86)
  if (!s.contact && s.kinds_have_lengths && use_avx512()) return sum_row_avx512;
#endif
  return sum_row_portable;
}

}  // namespace horizon::affine_sweeps
