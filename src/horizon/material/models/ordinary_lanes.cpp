// The ordinary rows in eight lanes (ordinary_lanes.hpp): the body (ordinary_lanes_body.inc)
// built, on x86-64 with GCC, for AVX-512, taken when the machine has it (wide()). A copy
// for the build's own target is kept for the entry points' sake and never chosen: there
// (and for AVX2) GCC keeps the eight-wide vectors in memory, 3-4 times slower than the
// models' scalar rows (docs/benchmarks.md). Compiled with the fast loops' options (CMakeLists.txt): no FMA
// contraction, so that every target computes a lane as the others do; no FP traps, so that
// a lane that does not act may divide by anything and is never selected.
#include "horizon/material/models/ordinary_lanes.hpp"

#include <cmath>
#include <cstring>
#include <limits>
#include <string_view>
#include <type_traits>

#include "horizon/material/models/history_ledger.hpp"

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#include <immintrin.h>  // the AVX-512 copy's mask test (ordinary_lanes_body.inc any)
#endif

// The vector types never cross a call between targets (every function of a target's copy
// has internal linkage and takes its vectors from memory), so the ABI notes do not apply.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace horizon::lanes {

namespace {

// The booking part of HistoryLedger::Row::open_bond for bond k (the trial extension and
// flag already written): kernels::ledger_book_bond (kernels/ordinary.hpp), t_old in q[k].
// Returns true when the bond is booked.
__attribute__((noinline)) bool open_bond_rare(const RowBonds& b, uint64_t k, double e, double vj, double& booked) {
  const kernels::LedgerBonds L{nullptr, b.booked_committed, b.booked_trial, b.pending_set, b.pending_amount};
  return kernels::ledger_book_bond(L, k, b.intact[k], b.booked_committed[k], b.q[k], b.r[k], e, vj, booked);
}

// How far ahead the sum asks for the reverse bond's force scalar (bonds).
constexpr uint64_t kPrefetch = 64;

// Bond k of row i breaks (the sweep's rare path, in bond order): its flag, the damage
// weight, and the energy it held, (1/2) t_old e V_j with t_old = q_old |Y_old| its force
// state of the previous pass; the row's model books the same from q[k] (RowPass::t,
// history_ledger.hpp broken_bond_booking).
__attribute__((noinline)) void break_bond(const Sweep& s, std::size_t i, uint64_t k, double r, double r_old, double e,
                                          BreakOut& out) {
  s.intact[k] = s.after ? 2 : 0;
  ++out.broken;
  const double t_old = s.q[k] * r_old;
  s.q[k] = t_old;
  if (r > 0) out.lost += 0.5 * t_old * e * s.kinds[s.kind[k]].w;
  s.intact_weight[i] -= s.kc[s.kind[k]].damage;
}

namespace base {
#include "horizon/material/models/ordinary_lanes_body.inc"
}  // namespace base

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define HORIZON_LANES_X86 1
#pragma GCC push_options
#pragma GCC target("avx2,avx512f,avx512vl,avx512bw,avx512dq")
namespace avx512 {
// (the target pragma defines no __AVX512F__: the body's intrinsics ask for this)
#define HORIZON_LANES_AVX512 1
#include "horizon/material/models/ordinary_lanes_body.inc"
#undef HORIZON_LANES_AVX512
}  // namespace avx512
#pragma GCC pop_options
#endif

enum class Target { scalar, avx512 };

Target detect() {
#if defined(HORIZON_LANES_X86)
  if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512bw") &&
      __builtin_cpu_supports("avx512dq"))
    return Target::avx512;
#endif
  return Target::scalar;
}

Target g_target = detect();

}  // namespace

const char* lanes_target() { return g_target == Target::avx512 ? "avx512" : "scalar"; }
bool wide() { return g_target == Target::avx512; }

bool set_lanes_target(const char* name) {
  const std::string_view n = name;
  const Target best = detect();
  if (n == "scalar") return g_target = Target::scalar, true;
  if (n == "avx512" && best == Target::avx512) return g_target = Target::avx512, true;
  if (n == "best") return g_target = best, true;
  return false;
}

#if defined(HORIZON_LANES_X86)
#define HORIZON_LANES_CALL(f, ...)                                      \
  switch (g_target) {                                                   \
    case Target::avx512: return avx512::f(__VA_ARGS__);                 \
    default: return base::f(__VA_ARGS__);                               \
  }
#else
#define HORIZON_LANES_CALL(f, ...) return base::f(__VA_ARGS__);
#endif

RowSums ep_row(const RowBonds& b, const EpRow& m, double beta, bool norm, bool force) {
  HORIZON_LANES_CALL(ep_row, b, m, beta, norm, force)
}
RowSums ves_row(const RowBonds& b, const VesRow& m) { HORIZON_LANES_CALL(ves_row, b, m) }
RowSums micro_row(const RowBonds& b, const MicroRow& m) { HORIZON_LANES_CALL(micro_row, b, m) }
BreakOut break_row(const Sweep& s, std::size_t i, double* r_old) { HORIZON_LANES_CALL(break_row, s, i, r_old) }
SumOut sum_row(const Sweep& s, std::size_t i) { HORIZON_LANES_CALL(sum_row, s, i) }

}  // namespace horizon::lanes
