#include "horizon/solver/forces.hpp"
#include "horizon/family/neighbors.hpp"

#include "horizon/parallel/decomposition.hpp"

#include "horizon/solver/forces_general.hpp"
#include "horizon/kernels/unified.hpp"

#include "horizon/core/error.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <type_traits>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define HORIZON_AVX2_KERNELS 1
#define HORIZON_AVX2 __attribute__((target("avx2")))
#define HORIZON_AVX512 __attribute__((target("avx2,avx512f,avx512vl,avx512bw,avx512dq")))
#endif

// The bond loops. Each particle's row is walked in blocks of eight bonds; bond k of a
// row goes to lane (k - row start) mod 8, each lane keeps its own partial sums, and the
// lanes are added as ((l0 + l1) + (l2 + l3)) + ((l4 + l5) + (l6 + l7)) at the end of
// the row. Three implementations of every loop follow this rule, chosen at run time:
// AVX-512 (eight lanes in one 512-bit register), AVX2 (two 256-bit registers of four)
// and a portable scalar one (eight scalar accumulators; it skips broken bonds, which
// adds nothing since a lane's sum starts at +0 and never becomes -0). They perform the
// same IEEE operations in the same order, so they give the same bits
// (tests/unit/test_lammps_rules.cpp), on any thread count, and the compiler may not
// contract a*b+c into an FMA in this file (CMakeLists.txt).
// Rare events (a bond breaks, two particles touch) leave the vector path and are
// handled lane by lane in bond order. docs/benchmarks.md has the measurements behind
// these choices.

namespace horizon {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

KernelPath g_path = KernelPath::automatic;
bool g_path_known = false;  // g_path set by set_kernel_path or read from the environment

// HORIZON_KERNEL_PATH (automatic, avx2, scalar or general) chooses the path of a whole
// run as set_kernel_path does, so that a benchmark can run the AVX2 rows on a machine
// with AVX-512 (bench/lammps/run.sh with HORIZON_KERNEL_PATH=avx2: an AVX2-only CPU's
// loops). Read once, at the first pass; set_kernel_path overrides it.
KernelPath path() {
  if (g_path_known) return g_path;
  const char* env = std::getenv("HORIZON_KERNEL_PATH");
  const std::string v = env ? env : "";
  if (v.empty() || v == "automatic") g_path = KernelPath::automatic;
  else if (v == "avx2") g_path = KernelPath::avx2;
  else if (v == "scalar") g_path = KernelPath::scalar;
  else if (v == "general") g_path = KernelPath::general;
  else
    throw Error("HORIZON_KERNEL_PATH=" + v + ": expected automatic, avx2, scalar or general");
  g_path_known = true;
  return g_path;
}

bool use_avx2() {
#if defined(HORIZON_AVX2_KERNELS)
  static const bool available = __builtin_cpu_supports("avx2");
  return path() != KernelPath::scalar && available;
#else
  return false;
#endif
}

bool use_avx512() {
#if defined(HORIZON_AVX2_KERNELS)
  static const bool available = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
                                __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq");
  return path() == KernelPath::automatic && available;
#else
  return false;
#endif
}

}  // namespace

void pack_positions(System& s) {
  auto& P = s.particles;
  auto& M = s.model;
  const std::size_t n = P.size();
  M.packed.resize(n);
  M.min_stretch_next.resize(n);
  if (M.min_stretch.size() != n) M.min_stretch.assign(n, 0);
  if (M.alpha.size() != n) M.alpha.assign(n, 0);
  Point4* out = M.packed.data();
  // Positions the solver keeps apart from X + u (System::positions, solver.verlet: peridigm).
  if (s.positions.size() == n) {
    const Vec3* y = s.positions.data();
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      const double s0 = kernels::critical_stretch_now(M.critical_stretch[i], M.alpha[i], M.min_stretch[i], P.no_fail[i]);
      out[i] = {y[i].x, y[i].y, y[i].z, s0};
    }
    return;
  }
  // Peridigm's quasi-static positions (System::step_start_u, solver.positions: peridigm).
  if (s.step_start_u.size() == n) {
    const Vec3* un = s.step_start_u.data();
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 base = P.X[i] + un[i], du = P.u[i] - un[i];
      const double s0 = kernels::critical_stretch_now(M.critical_stretch[i], M.alpha[i], M.min_stretch[i], P.no_fail[i]);
      out[i] = {base.x + du.x, base.y + du.y, base.z + du.z, s0};
    }
    return;
  }
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 y = P.X[i] + P.u[i];
    const double s0 = kernels::critical_stretch_now(M.critical_stretch[i], M.alpha[i], M.min_stretch[i], P.no_fail[i]);
    out[i] = {y.x, y.y, y.z, s0};
  }
}

namespace {

// What a row loop reads and writes, taken from the System once per pass.
struct Ctx {
  const Point4* pt;            // y and the packed value (s0, or P in the force pass)
  const KindCoefficients* kc;  // per bond kind
  const uint32_t* nbr;
  const uint32_t* kind;
  const uint64_t* offset;
  uint8_t* intact;
  const double* R;  // pair_coef
  const double* Q;  // deviatoric_coef
  double* intact_weight;
  double* r_of;     // |Y| per bond (state-based: dilatation pass writes, force pass reads)
  const Point4* kind_dilatation;  // per kind {L, 1/L, omega V_j, 0}
  const Point4* kind_force;       // per kind {L, omega V_j, pair, d^2}
  // Bonds with their own lengths (Bonds::length_per_bond), else null: the kinds then
  // hold no length, `pair` holds omega V_j (R_i + R_j) before the division by L, and the
  // loops compute L's fields per bond as build_kind_coefficients computes them for a
  // kind (the same IEEE operations, so the same bits).
  const double* lengths;
  bool contact;                         // short-range contact on (contact_d from L)
  double contact_fraction, contact_cutoff;  // ShortRangeContact::distance
};

// Bond k's coefficients when the bonds carry their own lengths (Ctx::lengths).
inline KindCoefficients per_bond(const Ctx& c, uint64_t k) {
  KindCoefficients kc = c.kc[c.kind[k]];
  const double L = c.lengths[k];
  kc.length = L;
  kc.inv_length = 1.0 / L;
  kc.pair = kc.pair / L;
  if (c.contact) {
    kc.contact_d = std::min(c.contact_fraction * L, c.contact_cutoff);
    kc.contact_d2 = kc.contact_d * kc.contact_d;
  }
  return kc;
}

Ctx context(System& s) {
  auto& B = s.bonds;
  auto& M = s.model;
  const bool contact = s.contact.acts_on_family();  // law peridigm: never between family pairs
  return {M.packed.data(),
          M.kind.data(),
          B.nbr.data(),
          B.kind.data(),
          B.offset.data(),
          B.intact.data(),
          M.pair_coef.data(),
          M.deviatoric_coef.data(),
          M.intact_weight.data(),
          M.deformed_length.data(),
          M.kind_dilatation.data(),
          M.kind_force.data(),
          B.length_per_bond ? B.lengths.data() : nullptr,
          contact,
          contact ? s.contact.config().reference_fraction : 0.0,
          s.contact.cutoff()};
}

// What one row gives back besides the force.
struct RowOut {
  double fx = 0, fy = 0, fz = 0, energy = 0, theta = 0, smin = kInf, lost = 0;
  uint64_t broken = 0;
};

inline double total8(const double* v) { return ((v[0] + v[1]) + (v[2] + v[3])) + ((v[4] + v[5]) + (v[6] + v[7])); }
inline double min8(const double* v) {
  double m = v[0];
  for (int l = 1; l < 8; ++l) m = std::min(m, v[l]);
  return m;
}

// Short-range contact of one bond's ends (intact or broken): the force density on i
// when they are closer than the kind's contact distance. Returns false when apart.
inline bool bond_contact(const KindCoefficients& c, double Yx, double Yy, double Yz, double r2, double& fx,
                         double& fy, double& fz, double& w) {
  double a;
  if (!kernels::contact_coefficient(c.contact_d2, c.contact_d, c.contact_k, r2, a, w)) return false;
  fx = a * Yx;
  fy = a * Yy;
  fz = a * Yz;
  return true;
}

// ------------------------------------------------------------------------------------
// Portable scalar rows: eight lanes of scalar accumulators.

// Calls f(k, lane) for the bonds [begin, end) of a row, bond k in lane (k - begin) mod 8
// with the lane a compile-time constant, so that the lanes' sums stay in registers.
template <int L>
using LaneTag = std::integral_constant<int, L>;
template <class F, int... L>
inline void full_block(uint64_t k, F& f, std::integer_sequence<int, L...>) {
  (f(k + L, LaneTag<L>{}), ...);
}
template <class F, int... L>
inline void partial_block(uint64_t k, uint64_t end, F& f, std::integer_sequence<int, L...>) {
  ((k + L < end ? f(k + L, LaneTag<L>{}) : void()), ...);
}
template <class F>
inline void for_each_lane(uint64_t begin, uint64_t end, F&& f) {
  uint64_t k = begin;
  for (; k + 8 <= end; k += 8) full_block(k, f, std::make_integer_sequence<int, 8>{});
  if (k < end) partial_block(k, end, f, std::make_integer_sequence<int, 7>{});
}

// Bond-based models: breaking, the smallest stretch, contact and force in one pass.
// kAfter: a breaking bond still carries its force in this step.
template <bool kEnergy, bool kAfter>
RowOut pair_row_scalar(const Ctx& c, std::size_t i, uint64_t /*total*/) {
  const Point4 pi = c.pt[i];
  const double Ri = c.R[i];
  double fx[8] = {}, fy[8] = {}, fz[8] = {}, en[8] = {}, sm[8];
  std::fill(sm, sm + 8, kInf);
  RowOut out;
  const uint64_t begin = c.offset[i], end = c.offset[i + 1];
  for_each_lane(begin, end, [&](uint64_t k, auto lane) {
    constexpr int l = decltype(lane)::value;
    KindCoefficients own;
    const KindCoefficients& kc = c.lengths ? (own = per_bond(c, k)) : c.kc[c.kind[k]];
    const Point4 pj = c.pt[c.nbr[k]];
    const double Yx = pj.x - pi.x, Yy = pj.y - pi.y, Yz = pj.z - pi.z;
    const double r2 = Yx * Yx + Yy * Yy + Yz * Yz;
    if (c.intact[k]) {
      const double r = std::sqrt(r2), e = kernels::extension(r, kc.length, 0), stretch = e * kc.inv_length;
      const bool breaks = kernels::breaks(stretch, pi.w, pj.w);
      if (kAfter || !breaks) {
        const double a = kernels::pair_bond_coefficient(kc.pair, e, r);
        fx[l] += a * Yx;
        fy[l] += a * Yy;
        fz[l] += a * Yz;
      }
      sm[l] = stretch < sm[l] ? stretch : sm[l];
      if constexpr (kEnergy)
        if (!breaks) en[l] += kernels::pmb_bond_energy(kc.wv, Ri, kc.inv_length, e);
      if (breaks) {
        c.intact[k] = 0;
        ++out.broken;
        out.lost += kernels::pmb_broken_energy(kc.wv, Ri, kc.inv_length, e);  // (1/2) t_ij e V_j, as in break_and_dilate
        c.intact_weight[i] -= kc.damage;
      }
    }
    double cx, cy, cz, cw;
    if (bond_contact(kc, Yx, Yy, Yz, r2, cx, cy, cz, cw)) {
      fx[l] += cx;
      fy[l] += cy;
      fz[l] += cz;
      if constexpr (kEnergy) en[l] += cw;
    }
  });
  out.fx = total8(fx), out.fy = total8(fy), out.fz = total8(fz), out.energy = total8(en), out.smin = min8(sm);
  return out;
}

// State-based pass 1: breaking, the smallest stretch and the dilatation sum. Without
// kAfter a breaking bond is gone at once (intact = 0) and leaves the dilatation; with
// kAfter it is marked (intact = 2), still counts in the dilatation and carries force
// in pass 2, which then clears it. Pi: last pass's P_i, for the energy of a breaking bond.
template <bool kAfter>
RowOut dilate_row_scalar(const Ctx& c, std::size_t i, double Pi, uint64_t /*total*/) {
  const Point4 pi = c.pt[i];
  const double Ri = c.R[i], Qi = c.Q[i];
  double th[8] = {}, sm[8];
  std::fill(sm, sm + 8, kInf);
  RowOut out;
  const uint64_t begin = c.offset[i], end = c.offset[i + 1];
  for_each_lane(begin, end, [&](uint64_t k, auto lane) {
    constexpr int l = decltype(lane)::value;
    if (!c.intact[k]) return;
    KindCoefficients own;
    const KindCoefficients& kc = c.lengths ? (own = per_bond(c, k)) : c.kc[c.kind[k]];
    const Point4 pj = c.pt[c.nbr[k]];
    const double Yx = pj.x - pi.x, Yy = pj.y - pi.y, Yz = pj.z - pi.z;
    const double r2 = Yx * Yx + Yy * Yy + Yz * Yz;
    const double r = std::sqrt(r2), e = kernels::extension(r, kc.length, 0), stretch = e * kc.inv_length;
    c.r_of[k] = r;
    const bool breaks = kernels::breaks(stretch, pi.w, pj.w);
    if (kAfter || !breaks) th[l] += kernels::dilatation_term(kc.wv, kc.length, e);
    sm[l] = stretch < sm[l] ? stretch : sm[l];
    if (breaks) {
      c.intact[k] = kAfter ? 2 : 0;
      ++out.broken;
      // Energy held by this directed bond: (1/2) t_ij e V_j (seed 003 digest sec. 9,
      // W_i = (1/2) sum_j t_ij e_ij V_j for both models), with last pass's P_i.
      out.lost += kernels::unified_bond_energy(kc.wv, Pi, Qi, Ri, kc.length, kc.inv_length, e);
      c.intact_weight[i] -= kc.damage;
    }
  });
  out.theta = total8(th), out.smin = min8(sm);
  return out;
}

// State-based pass 2: f_i = sum_j (t_ij + t_ji) Y/|Y| V_j over the bonds that carry
// force (intact != 0), the contact of every family pair; clears intact = 2. pt[j].w = P_j.
template <bool kEnergy>
RowOut force_row_scalar(const Ctx& c, std::size_t i, uint64_t /*total*/) {
  const Point4 pi = c.pt[i];
  const double Ri = c.R[i], Pi = pi.w, Qi = c.Q[i];
  double fx[8] = {}, fy[8] = {}, fz[8] = {}, en[8] = {};
  RowOut out;
  const uint64_t begin = c.offset[i], end = c.offset[i + 1];
  for_each_lane(begin, end, [&](uint64_t k, auto lane) {
    constexpr int l = decltype(lane)::value;
    const uint32_t j = c.nbr[k];
    KindCoefficients own;
    const KindCoefficients& kc = c.lengths ? (own = per_bond(c, k)) : c.kc[c.kind[k]];
    const Point4 pj = c.pt[j];
    const double Yx = pj.x - pi.x, Yy = pj.y - pi.y, Yz = pj.z - pi.z;
    const double r2 = Yx * Yx + Yy * Yy + Yz * Yz;
    if (c.intact[k]) {
      const double r = c.r_of[k], L = kc.length, e = kernels::extension(r, L, 0);  // |Y| from the dilatation pass
      const double a = kernels::pair_force_coefficient(kc.wv, kc.pair, Pi, pj.w, Qi, c.Q[j], L, e, r);
      fx[l] += a * Yx;
      fy[l] += a * Yy;
      fz[l] += a * Yz;
      if constexpr (kEnergy)
        if (c.intact[k] == 1) en[l] += kernels::unified_bond_energy(kc.wv, Pi, Qi, Ri, L, kc.inv_length, e);
      if (c.intact[k] == 2) c.intact[k] = 0;
    }
    double cx, cy, cz, cw;
    if (bond_contact(kc, Yx, Yy, Yz, r2, cx, cy, cz, cw)) {
      fx[l] += cx;
      fy[l] += cy;
      fz[l] += cz;
      if constexpr (kEnergy) en[l] += cw;
    }
  });
  out.fx = total8(fx), out.fy = total8(fy), out.fz = total8(fz), out.energy = total8(en);
  return out;
}

// ------------------------------------------------------------------------------------
// AVX2 rows: the same arithmetic, four lanes in one register.
#if defined(HORIZON_AVX2_KERNELS)

using d4 = double __attribute__((vector_size(32)));
using m4 = int64_t __attribute__((vector_size(32)));

HORIZON_AVX2 inline d4 splat(double x) { return d4{x, x, x, x}; }
HORIZON_AVX2 inline d4 sqrt4(d4 v) { return reinterpret_cast<d4>(_mm256_sqrt_pd(reinterpret_cast<__m256d>(v))); }
HORIZON_AVX2 inline d4 select(m4 mask, d4 v) { return reinterpret_cast<d4>(mask & reinterpret_cast<m4>(v)); }
HORIZON_AVX2 inline bool any(m4 mask) { return _mm256_movemask_pd(reinterpret_cast<__m256d>(mask)) != 0; }
HORIZON_AVX2 inline double sum4(d4 v) { return (v[0] + v[1]) + (v[2] + v[3]); }
HORIZON_AVX2 inline double min4(d4 v) { return std::min(std::min(v[0], v[1]), std::min(v[2], v[3])); }
// Two 16-byte halves in one register: {a0, a1, b0, b1}.
HORIZON_AVX2 inline __m256d halves(const double* a, const double* b) {
  return _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(a)), _mm_loadu_pd(b), 1);
}

// Which 32-byte record of a bond's kind a loop reads whole (the other fields it needs
// come apart): the bond-based row reads {L, 1/L, pair, d^2} (+ omega V_j for the
// energy), the dilatation pass {L, 1/L, omega V_j, -}, the force pass {L, omega V_j, pair,
// d^2} (+ 1/L for the energy). The AVX2 and AVX-512 rows read the same records.
enum class KindView { bond_based, dilatation, force };

// Four bonds k .. k + count - 1 of row i in lanes 0..3; lanes past the row's end are
// padding (the particle itself, the first bond's kind, not live). Each 32-byte record
// (a neighbour's Point4, a kind's record of kView) is loaded as two halves, so that one
// unpack per column puts the lanes in order.
struct Quad {
  d4 Yx, Yy, Yz, wj;    // Y = y_j - y_i; the neighbour's packed value
  d4 L, iL, pair, d2c;  // kind: length, 1/length, bond-based coefficient, contact distance^2
  d4 wv;                // kind: omega V_j
  m4 live, once;        // intact != 0, intact == 1
  uint32_t j[4];        // the neighbours (padding: i)
};

// kExtra: the field the view's record lacks (bond_based: omega V_j; force: 1/L).
template <KindView kView, bool kExtra, bool kFull>
HORIZON_AVX2 __attribute__((always_inline)) inline void load_quad(Quad& q, const Ctx& c, const Point4& pi,
                                                                  std::size_t i, uint64_t k, int count,
                                                                  uint64_t total) {
  uint32_t kd[4];
  for (int l = 0; l < 4; ++l) {
    const bool in = kFull || l < count;
    q.j[l] = in ? c.nbr[k + static_cast<uint64_t>(l)] : static_cast<uint32_t>(i);
    kd[l] = c.kind[in ? k + static_cast<uint64_t>(l) : k];
  }
  const Point4* pt = c.pt;
  const __m256d A = halves(&pt[q.j[0]].x, &pt[q.j[2]].x), B = halves(&pt[q.j[1]].x, &pt[q.j[3]].x);
  const __m256d C = halves(&pt[q.j[0]].z, &pt[q.j[2]].z), D = halves(&pt[q.j[1]].z, &pt[q.j[3]].z);
  q.Yx = reinterpret_cast<d4>(_mm256_unpacklo_pd(A, B)) - splat(pi.x);
  q.Yy = reinterpret_cast<d4>(_mm256_unpackhi_pd(A, B)) - splat(pi.y);
  q.Yz = reinterpret_cast<d4>(_mm256_unpacklo_pd(C, D)) - splat(pi.z);
  q.wj = reinterpret_cast<d4>(_mm256_unpackhi_pd(C, D));
  const double* r[4];
  for (int l = 0; l < 4; ++l) {
    if constexpr (kView == KindView::bond_based) r[l] = &c.kc[kd[l]].length;
    if constexpr (kView == KindView::dilatation) r[l] = &c.kind_dilatation[kd[l]].x;
    if constexpr (kView == KindView::force) r[l] = &c.kind_force[kd[l]].x;
  }
  const __m256d E = halves(r[0], r[2]), F = halves(r[1], r[3]);
  const d4 first = reinterpret_cast<d4>(_mm256_unpacklo_pd(E, F)), second = reinterpret_cast<d4>(_mm256_unpackhi_pd(E, F));
  q.L = first;
  if constexpr (kView == KindView::force) q.wv = second;
  else q.iL = second;
  const __m256d G = halves(r[0] + 2, r[2] + 2), H = halves(r[1] + 2, r[3] + 2);
  if constexpr (kView != KindView::dilatation) {
    q.pair = reinterpret_cast<d4>(_mm256_unpacklo_pd(G, H));
    q.d2c = reinterpret_cast<d4>(_mm256_unpackhi_pd(G, H));
  } else {
    q.wv = reinterpret_cast<d4>(_mm256_unpacklo_pd(G, H));
  }
  if constexpr (kExtra && kView == KindView::bond_based) {
    const KindCoefficients* kc = c.kc;
    const __m256d U = halves(&kc[kd[0]].damage, &kc[kd[2]].damage), V = halves(&kc[kd[1]].damage, &kc[kd[3]].damage);
    q.wv = reinterpret_cast<d4>(_mm256_unpackhi_pd(U, V));
  }
  if constexpr (kExtra && kView == KindView::force) {
    const KindCoefficients* kc = c.kc;
    q.iL = d4{kc[kd[0]].inv_length, kc[kd[1]].inv_length, kc[kd[2]].inv_length, kc[kd[3]].inv_length};
  }
  if (c.lengths) {  // the bonds' own lengths (Ctx::lengths); padding lanes take bond k's
    d4 L;
    for (int l = 0; l < 4; ++l) L[l] = c.lengths[kFull || l < count ? k + static_cast<uint64_t>(l) : k];
    q.L = L;
    if constexpr (kView != KindView::force || kExtra) q.iL = splat(1.0) / L;
    if constexpr (kView != KindView::dilatation) {
      if (any(q.pair != splat(0.0))) q.pair = q.pair / L;  // 0/L is the +0 the kind gives
      if (c.contact) {
        const d4 d = reinterpret_cast<d4>(_mm256_min_pd(reinterpret_cast<__m256d>(splat(c.contact_fraction) * L),
                                                        _mm256_set1_pd(c.contact_cutoff)));
        q.d2c = d * d;
      }
    }
  }
  // The four intact flags as masks: one 4-byte load where the array allows it.
  uint32_t flags = 0;
  if (kFull || k + 4 <= total) {
    std::memcpy(&flags, c.intact + k, 4);
  } else {
    for (int l = 0; l < 4 && k + static_cast<uint64_t>(l) < total; ++l)
      flags |= static_cast<uint32_t>(c.intact[k + static_cast<uint64_t>(l)]) << (8 * l);
  }
  if (!kFull && count < 4) flags &= (1u << (8 * count)) - 1;
  const __m256i s = _mm256_cvtepu8_epi64(_mm_cvtsi32_si128(static_cast<int>(flags)));
  q.live = reinterpret_cast<m4>(_mm256_cmpgt_epi64(s, _mm256_setzero_si256()));
  q.once = reinterpret_cast<m4>(_mm256_cmpeq_epi64(s, _mm256_set1_epi64x(1)));
}

// The lane's bond recomputed from the arrays, exactly as the vector does it (rare paths).
struct Lane {
  KindCoefficients kc;
  double Yx, Yy, Yz, r2, e;
};
inline Lane lane(const Ctx& c, const Point4& pi, uint64_t k) {
  const Point4 pj = c.pt[c.nbr[k]];
  Lane b{c.lengths ? per_bond(c, k) : c.kc[c.kind[k]], pj.x - pi.x, pj.y - pi.y, pj.z - pi.z, 0, 0};
  b.r2 = b.Yx * b.Yx + b.Yy * b.Yy + b.Yz * b.Yz;
  b.e = std::sqrt(b.r2) - b.kc.length;
  return b;
}

// Contact of lanes where r2 < d2c (rare), returned as vectors in lane order (zero in the
// other lanes). Out of line and by value, so that the row's sums stay in registers.
struct Contact4 {
  d4 fx, fy, fz, w;
};
HORIZON_AVX2 __attribute__((noinline)) Contact4 quad_contact(const Ctx& c, const Point4& pi, uint64_t k, int mask) {
  Contact4 out{};
  for (int l = 0; l < 4; ++l) {
    if (!((mask >> l) & 1)) continue;
    const Lane b = lane(c, pi, k + static_cast<uint64_t>(l));
    double x, y, z, w;
    if (bond_contact(b.kc, b.Yx, b.Yy, b.Yz, b.r2, x, y, z, w)) out.fx[l] = x, out.fy[l] = y, out.fz[l] = z, out.w[l] = w;
  }
  return out;
}

// The rare path of a block: its breaking lanes (mask), in bond order. Out of line.
HORIZON_AVX2 __attribute__((noinline)) void quad_breaks(const Ctx& c, const Point4& pi, std::size_t i, uint64_t k,
                                                        int mask, uint8_t state, bool bond_based, double Ri,
                                                        double Pi, double Qi, RowOut& out) {
  for (int l = 0; l < 4; ++l) {
    if (!((mask >> l) & 1)) continue;
    const uint64_t kk = k + static_cast<uint64_t>(l);
    const Lane b = lane(c, pi, kk);
    const KindCoefficients& kc = b.kc;
    c.intact[kk] = state;
    ++out.broken;
    // (1/2) t_ij e V_j with t_ij = P_i L + (Q_i + R_i/L) e: the bond's energy, written
    // as in the scalar rows of each pass so that the bits agree.
    if (bond_based)
      out.lost += 0.5 * kc.wv * Ri * kc.inv_length * b.e * b.e;
    else
      out.lost += 0.5 * kc.wv * (Pi * kc.length + (Qi + Ri * kc.inv_length) * b.e) * b.e;
    c.intact_weight[i] -= kc.damage;
  }
}

// The rows walk the blocks of four bonds of one half at a time: lanes 0-3 of every block
// of eight (half 0), then lanes 4-7 (half 1). Each lane still adds its bonds in bond
// order, and the halves' sums are added as total8 adds them (sum4(half 0) + sum4(half 1)),
// so the bits are those of the interleaved walk, with half the sums live at once: AVX2
// has sixteen registers, and the interleaved walk kept its eight-lane sums on the stack.
// full (a compile-time constant) tells the block has four bonds, so that its loads need
// no padding. A breaking bond's booking (its energy and damage weight: sums in bond
// order) waits for the end of the row: its block marks it kPending, and book_pending
// books the marked bonds in bond order, as the interleaved walk booked them.
template <int h, class F>
HORIZON_AVX2 __attribute__((always_inline)) inline void for_each_quad_of_half(uint64_t begin, uint64_t end, F&& f) {
  uint64_t k = begin + 4 * h;
  for (; k + 4 <= end; k += 8) f(k, 4, std::true_type{});
  if (k < end) f(k, static_cast<int>(end - k), std::false_type{});
}

constexpr uint8_t kPending = 0x80;  // intact flag of a bond that breaks in this row's pass

HORIZON_AVX2 inline void mark_pending(const Ctx& c, uint64_t k, int mask) {
  for (int l = 0; l < 4; ++l)
    if ((mask >> l) & 1) c.intact[k + static_cast<uint64_t>(l)] = kPending;
}

// The marked bonds of a row, booked in bond order; they take the flag `state`.
HORIZON_AVX2 __attribute__((noinline)) void book_pending(const Ctx& c, const Point4& pi, std::size_t i, uint8_t state,
                                                         bool bond_based, double Ri, double Pi, double Qi, RowOut& out) {
  for (uint64_t k = c.offset[i]; k < c.offset[i + 1]; ++k)
    if (c.intact[k] == kPending) quad_breaks(c, pi, i, k, 1, state, bond_based, Ri, Pi, Qi, out);
}

// One half's lane sums.
struct Half {
  d4 fx, fy, fz, en, sm;
};
HORIZON_AVX2 inline Half half_start() { return {splat(0), splat(0), splat(0), splat(0), splat(kInf)}; }

// The contact of a block's touching lanes added to the half's sums.
template <bool kEnergy>
HORIZON_AVX2 __attribute__((always_inline)) inline void add_contact4(const Ctx& c, const Point4& pi, uint64_t k, m4 contact, Half& s) {
  const Contact4 cc = quad_contact(c, pi, k, _mm256_movemask_pd(reinterpret_cast<__m256d>(contact)));
  s.fx += cc.fx, s.fy += cc.fy, s.fz += cc.fz;
  if constexpr (kEnergy) s.en += cc.w;
}

// The row's totals: half 0's lane sums (a), then half 1's added, in total8's order.
HORIZON_AVX2 __attribute__((always_inline)) inline void add_half(RowOut& out, const Half& s, bool first) {
  const double fx = sum4(s.fx), fy = sum4(s.fy), fz = sum4(s.fz), en = sum4(s.en), sm = min4(s.sm);
  if (first) {
    out.fx = fx, out.fy = fy, out.fz = fz, out.energy = en, out.smin = sm;
  } else {
    out.fx += fx, out.fy += fy, out.fz += fz, out.energy += en, out.smin = std::min(out.smin, sm);
  }
}

template <bool kEnergy, bool kAfter, int h>
HORIZON_AVX2 __attribute__((always_inline)) inline bool pair_half_avx2(const Ctx& c, const Point4& pi, std::size_t i,
                                                                       uint64_t total, double Ri, Half& sums) {
  Half s = sums;  // a local copy, so that the sums stay in registers
  const d4 s0i = splat(pi.w);
  bool pending = false;
  for_each_quad_of_half<h>(c.offset[i], c.offset[i + 1],
                           [&](uint64_t k, int count, auto full) HORIZON_AVX2 __attribute__((always_inline)) {
    Quad q;
    load_quad<KindView::bond_based, kEnergy, decltype(full)::value>(q, c, pi, i, k, count, total);
    const d4 r2 = q.Yx * q.Yx + q.Yy * q.Yy + q.Yz * q.Yz;
    const m4 contact = (r2 < q.d2c) & (r2 > splat(0));  // padding lanes have r2 = 0
    if (!any(q.live)) {  // four broken bonds: only their contact can act
      if (any(contact)) add_contact4<kEnergy>(c, pi, k, contact, s);
      return;
    }
    const d4 r = sqrt4(r2), e = r - q.L, stretch = e * q.iL;
    const d4 s0 = s0i < q.wj ? s0i : q.wj;
    const m4 breaks = q.live & (stretch > s0);
    const m4 carries = kAfter ? q.live : q.live & ~breaks;
    // Padding and broken lanes may hold inf or NaN; the masks never select them.
    const d4 a = select(carries, q.pair * e / r);
    s.fx += a * q.Yx;
    s.fy += a * q.Yy;
    s.fz += a * q.Yz;
    s.sm = (q.live & (stretch < s.sm)) ? stretch : s.sm;
    if constexpr (kEnergy) s.en += select(q.live & ~breaks, splat(0.5 * Ri) * q.wv * q.iL * e * e);
    if (!any(breaks | contact)) return;
    const int broken_lanes = _mm256_movemask_pd(reinterpret_cast<__m256d>(breaks));
    if (broken_lanes) mark_pending(c, k, broken_lanes), pending = true;
    if (any(contact)) add_contact4<kEnergy>(c, pi, k, contact, s);
  });
  sums = s;
  return pending;
}

template <bool kEnergy, bool kAfter>
HORIZON_AVX2 RowOut pair_row_avx2(const Ctx& c, std::size_t i, uint64_t total) {
  const Point4 pi = c.pt[i];
  const double Ri = c.R[i];
  RowOut out;
  Half s = half_start();
  bool pending = pair_half_avx2<kEnergy, kAfter, 0>(c, pi, i, total, Ri, s);
  add_half(out, s, true);
  s = half_start();
  pending |= pair_half_avx2<kEnergy, kAfter, 1>(c, pi, i, total, Ri, s);
  add_half(out, s, false);
  if (pending) book_pending(c, pi, i, 0, true, Ri, 0.0, 0.0, out);
  return out;
}

template <bool kAfter, int h>
HORIZON_AVX2 __attribute__((always_inline)) inline bool dilate_half_avx2(const Ctx& c, const Point4& pi, std::size_t i,
                                                                         uint64_t total, Half& sums) {
  Half s = sums;  // a local copy, so that the sums stay in registers
  const d4 s0i = splat(pi.w);
  bool pending = false;
  for_each_quad_of_half<h>(c.offset[i], c.offset[i + 1],
                           [&](uint64_t k, int count, auto full) HORIZON_AVX2 __attribute__((always_inline)) {
    Quad q;
    load_quad<KindView::dilatation, false, decltype(full)::value>(q, c, pi, i, k, count, total);
    if (!any(q.live)) return;
    const d4 r2 = q.Yx * q.Yx + q.Yy * q.Yy + q.Yz * q.Yz;
    const d4 r = sqrt4(r2), e = r - q.L, stretch = e * q.iL;
    if constexpr (decltype(full)::value)
      _mm256_storeu_pd(c.r_of + k, reinterpret_cast<__m256d>(r));
    else
      for (int l = 0; l < count; ++l) c.r_of[k + static_cast<uint64_t>(l)] = r[l];
    const d4 s0 = s0i < q.wj ? s0i : q.wj;
    const m4 breaks = q.live & (stretch > s0);
    s.en += select(kAfter ? q.live : q.live & ~breaks, q.wv * q.L * e);  // the dilatation sum
    s.sm = (q.live & (stretch < s.sm)) ? stretch : s.sm;
    if (!any(breaks)) return;
    mark_pending(c, k, _mm256_movemask_pd(reinterpret_cast<__m256d>(breaks)));
    pending = true;
  });
  sums = s;
  return pending;
}

template <bool kAfter>
HORIZON_AVX2 RowOut dilate_row_avx2(const Ctx& c, std::size_t i, double Pi, uint64_t total) {
  const Point4 pi = c.pt[i];
  RowOut out;
  Half s = half_start();
  bool pending = dilate_half_avx2<kAfter, 0>(c, pi, i, total, s);
  add_half(out, s, true);
  s = half_start();
  pending |= dilate_half_avx2<kAfter, 1>(c, pi, i, total, s);
  add_half(out, s, false);
  out.theta = out.energy, out.energy = 0;
  if (pending) book_pending(c, pi, i, kAfter ? 2 : 0, false, c.R[i], Pi, c.Q[i], out);
  return out;
}

template <bool kEnergy, int h>
HORIZON_AVX2 __attribute__((always_inline)) inline void force_half_avx2(const Ctx& c, const Point4& pi, std::size_t i,
                                                                        uint64_t total, Half& sums) {
  Half s = sums;  // a local copy, so that the sums stay in registers
  const double Ri = c.R[i];
  const d4 Pi = splat(pi.w), Qi = splat(c.Q[i]);
  for_each_quad_of_half<h>(c.offset[i], c.offset[i + 1],
                           [&](uint64_t k, int count, auto full) HORIZON_AVX2 __attribute__((always_inline)) {
    Quad q;
    load_quad<KindView::force, kEnergy, decltype(full)::value>(q, c, pi, i, k, count, total);
    const d4 r2 = q.Yx * q.Yx + q.Yy * q.Yy + q.Yz * q.Yz;
    const m4 contact = (r2 < q.d2c) & (r2 > splat(0));  // padding lanes have r2 = 0
    if (!any(q.live)) {  // four broken bonds: only their contact can act
      if (any(contact)) add_contact4<kEnergy>(c, pi, k, contact, s);
      return;
    }
    d4 r = splat(1.0);  // |Y| from the dilatation pass; padding lanes 1
    if constexpr (decltype(full)::value)
      r = reinterpret_cast<d4>(_mm256_loadu_pd(c.r_of + k));
    else
      for (int l = 0; l < count; ++l) r[l] = c.r_of[k + static_cast<uint64_t>(l)];
    const d4 Qj = {c.Q[q.j[0]], c.Q[q.j[1]], c.Q[q.j[2]], c.Q[q.j[3]]};  // padding lanes Q_i
    const d4 wv = q.wv;
    const d4 e = r - q.L;
    const d4 t = (Pi + q.wj) * q.L + (Qi + Qj) * e;
    const d4 a = select(q.live, (wv * t + q.pair * e) / r);
    s.fx += a * q.Yx;
    s.fy += a * q.Yy;
    s.fz += a * q.Yz;
    if constexpr (kEnergy) s.en += select(q.once, splat(0.5) * wv * (Pi * q.L + (Qi + splat(Ri) * q.iL) * e) * e);
    const m4 clear = q.live ^ q.once;
    if (!any(clear | contact)) return;
    const int cleared = _mm256_movemask_pd(reinterpret_cast<__m256d>(clear));
    for (int l = 0; l < count; ++l)
      if ((cleared >> l) & 1) c.intact[k + static_cast<uint64_t>(l)] = 0;
    if (any(contact)) add_contact4<kEnergy>(c, pi, k, contact, s);
  });
  sums = s;
}

template <bool kEnergy>
HORIZON_AVX2 RowOut force_row_avx2(const Ctx& c, std::size_t i, uint64_t total) {
  const Point4 pi = c.pt[i];
  RowOut out;
  Half s = half_start();
  force_half_avx2<kEnergy, 0>(c, pi, i, total, s);
  add_half(out, s, true);
  s = half_start();
  force_half_avx2<kEnergy, 1>(c, pi, i, total, s);
  add_half(out, s, false);
  out.smin = kInf;
  return out;
}

// ------------------------------------------------------------------------------------
// AVX-512 rows: the same arithmetic, eight lanes in one 512-bit register.

using d8 = __m512d;

// {a, b} in one register: a broadcast, then b into the upper four lanes (no undefined
// upper half, which GCC 12 warns about).
HORIZON_AVX512 inline d8 join8(__m256d a, __m256d b) {
  return _mm512_mask_broadcast_f64x4(_mm512_mask_broadcast_f64x4(_mm512_setzero_pd(), 0x0F, a), 0xF0, b);
}

// Eight 32-byte records (four doubles each) into four registers of eight lanes: lane l
// of a, b, c, d holds doubles 0, 1, 2, 3 of record l.
HORIZON_AVX512 __attribute__((always_inline)) inline void transpose8(const double* const* rec, d8& a, d8& b, d8& c,
                                                                  d8& d) {
  const d8 z0 = join8(_mm256_load_pd(rec[0]), _mm256_load_pd(rec[1]));
  const d8 z1 = join8(_mm256_load_pd(rec[2]), _mm256_load_pd(rec[3]));
  const d8 z2 = join8(_mm256_load_pd(rec[4]), _mm256_load_pd(rec[5]));
  const d8 z3 = join8(_mm256_load_pd(rec[6]), _mm256_load_pd(rec[7]));
  // t0 = {a0 a2 c0 c2 a1 a3 c1 c3}, t1 = {b0 b2 d0 d2 b1 b3 d1 d3}; t2, t3 for 4..7.
  const d8 t0 = _mm512_unpacklo_pd(z0, z1), t1 = _mm512_unpackhi_pd(z0, z1);
  const d8 t2 = _mm512_unpacklo_pd(z2, z3), t3 = _mm512_unpackhi_pd(z2, z3);
  const __m512i first = _mm512_setr_epi64(0, 4, 1, 5, 8, 12, 9, 13);
  const __m512i second = _mm512_setr_epi64(2, 6, 3, 7, 10, 14, 11, 15);
  a = _mm512_permutex2var_pd(t0, first, t2);
  b = _mm512_permutex2var_pd(t1, first, t3);
  c = _mm512_permutex2var_pd(t0, second, t2);
  d = _mm512_permutex2var_pd(t1, second, t3);
}

// Eight bonds k .. k + count - 1 of row i in lanes 0..7, padded as load_quad pads
// (the members of Quad, eight lanes wide).
struct Oct {
  d8 Yx, Yy, Yz, wj;
  d8 L, iL, pair, d2c;
  d8 wv;
  __mmask8 live, once;
};


// One double of each lane's kind, from the 64-byte KindCoefficients records.
HORIZON_AVX512 inline d8 gather_kind_field(const uint32_t* kd, const double* field) {
  const __m256i idx = _mm256_slli_epi32(_mm256_load_si256(reinterpret_cast<const __m256i*>(kd)), 3);
  return _mm512_mask_i32gather_pd(_mm512_setzero_pd(), 0xFF, idx, field, 8);
}

HORIZON_AVX512 inline __mmask8 lanes_of(int count) { return static_cast<__mmask8>((1u << count) - 1u); }

template <KindView kView, bool kExtra, bool kFull>
HORIZON_AVX512 __attribute__((always_inline)) inline void load_oct(Oct& q, const Ctx& c, const Point4& pi, std::size_t i, uint64_t k, int count,
                                    uint64_t total) {
  const double* rp[8];
  const double* rk[8];
  alignas(32) uint32_t kd[8];
  for (int l = 0; l < 8; ++l) {
    const bool in = kFull || l < count;
    const uint64_t kk = in ? k + static_cast<uint64_t>(l) : k;
    rp[l] = &c.pt[in ? c.nbr[kk] : static_cast<uint32_t>(i)].x;
    kd[l] = c.kind[kk];
    if constexpr (kView == KindView::bond_based) rk[l] = &c.kc[kd[l]].length;
    if constexpr (kView == KindView::dilatation) rk[l] = &c.kind_dilatation[kd[l]].x;
    if constexpr (kView == KindView::force) rk[l] = &c.kind_force[kd[l]].x;
  }
  transpose8(rp, q.Yx, q.Yy, q.Yz, q.wj);
  q.Yx = _mm512_sub_pd(q.Yx, _mm512_set1_pd(pi.x));
  q.Yy = _mm512_sub_pd(q.Yy, _mm512_set1_pd(pi.y));
  q.Yz = _mm512_sub_pd(q.Yz, _mm512_set1_pd(pi.z));
  if constexpr (kView == KindView::bond_based) {
    transpose8(rk, q.L, q.iL, q.pair, q.d2c);
    if constexpr (kExtra) q.wv = gather_kind_field(kd, &c.kc->wv);
  } else if constexpr (kView == KindView::dilatation) {
    d8 unused;
    transpose8(rk, q.L, q.iL, q.wv, unused);
  } else {
    transpose8(rk, q.L, q.wv, q.pair, q.d2c);
    if constexpr (kExtra) q.iL = gather_kind_field(kd, &c.kc->inv_length);
  }
  if (c.lengths) {  // the bonds' own lengths (Ctx::lengths); padding lanes take bond k's
    q.L = kFull ? _mm512_loadu_pd(c.lengths + k)
                : _mm512_mask_loadu_pd(_mm512_set1_pd(c.lengths[k]), lanes_of(count), c.lengths + k);
    if constexpr (kView != KindView::force || kExtra) q.iL = _mm512_div_pd(_mm512_set1_pd(1.0), q.L);
    if constexpr (kView != KindView::dilatation) {
      // 0/L is the +0 the kind gives: no division where no lane has a bond-based part.
      if (_mm512_cmp_pd_mask(q.pair, _mm512_setzero_pd(), _CMP_NEQ_UQ)) q.pair = _mm512_div_pd(q.pair, q.L);
      if (c.contact) {
        const d8 d = _mm512_min_pd(_mm512_mul_pd(_mm512_set1_pd(c.contact_fraction), q.L),
                                   _mm512_set1_pd(c.contact_cutoff));
        q.d2c = _mm512_mul_pd(d, d);
      }
    }
  }
  uint64_t flags = 0;
  if (kFull || k + 8 <= total) {
    std::memcpy(&flags, c.intact + k, 8);
  } else {
    for (int l = 0; l < 8 && k + static_cast<uint64_t>(l) < total; ++l)
      flags |= static_cast<uint64_t>(c.intact[k + static_cast<uint64_t>(l)]) << (8 * l);
  }
  if (!kFull && count < 8) flags &= (uint64_t{1} << (8 * count)) - 1;
  const __m128i f = _mm_cvtsi64_si128(static_cast<long long>(flags));
  q.live = static_cast<__mmask8>(_mm_test_epi8_mask(f, f));
  q.once = static_cast<__mmask8>(_mm_cmpeq_epi8_mask(f, _mm_set1_epi8(1)));
}

// The lanes' contact (rare) as eight-lane vectors, from the four-lane helper.
struct Contact8 {
  d8 fx, fy, fz, w;
};
HORIZON_AVX512 inline Contact8 oct_contact(const Ctx& c, const Point4& pi, uint64_t k, unsigned mask) {
  Contact4 lo{}, hi{};
  if (mask & 15u) lo = quad_contact(c, pi, k, static_cast<int>(mask & 15u));
  if (mask >> 4) hi = quad_contact(c, pi, k + 4, static_cast<int>(mask >> 4));
  Contact8 out;
  out.fx = join8(lo.fx, hi.fx), out.fy = join8(lo.fy, hi.fy), out.fz = join8(lo.fz, hi.fz), out.w = join8(lo.w, hi.w);
  return out;
}

// Breaking lanes of a block of eight, in bond order (two calls of the four-lane helper).
HORIZON_AVX512 inline void oct_breaks(const Ctx& c, const Point4& pi, std::size_t i, uint64_t k, unsigned mask,
                                      uint8_t state, bool bond_based, double Ri, double Pi, double Qi, RowOut& out) {
  if (mask & 15u) quad_breaks(c, pi, i, k, static_cast<int>(mask & 15u), state, bond_based, Ri, Pi, Qi, out);
  if (mask >> 4) quad_breaks(c, pi, i, k + 4, static_cast<int>(mask >> 4), state, bond_based, Ri, Pi, Qi, out);
}

// The sum of eight lanes in the order of total8; the smallest lane.
// The contact of a block's touching lanes added to the lane sums.
template <bool kEnergy>
HORIZON_AVX512 inline void add_contact(const Ctx& c, const Point4& pi, uint64_t k, __mmask8 contact, d8& fx, d8& fy,
                                       d8& fz, d8& en) {
  const Contact8 cc = oct_contact(c, pi, k, contact);
  fx = _mm512_add_pd(fx, cc.fx), fy = _mm512_add_pd(fy, cc.fy), fz = _mm512_add_pd(fz, cc.fz);
  if constexpr (kEnergy) en = _mm512_add_pd(en, cc.w);
}

HORIZON_AVX512 inline double sum8(d8 v) {
  alignas(64) double lane[8];
  _mm512_store_pd(lane, v);
  return total8(lane);
}
HORIZON_AVX512 inline double min8(d8 v) {
  alignas(64) double lane[8];
  _mm512_store_pd(lane, v);
  return min8(static_cast<const double*>(lane));
}

// |Y|^2 per lane, and the lanes closer than their contact distance (padding lanes have
// |Y| = 0 and never touch).
HORIZON_AVX512 inline d8 norm2(const Oct& q) {
  return _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(q.Yx, q.Yx), _mm512_mul_pd(q.Yy, q.Yy)), _mm512_mul_pd(q.Yz, q.Yz));
}
HORIZON_AVX512 inline __mmask8 touching(const Oct& q, d8 r2) {
  return _mm512_cmp_pd_mask(r2, q.d2c, _CMP_LT_OQ) & _mm512_cmp_pd_mask(r2, _mm512_setzero_pd(), _CMP_GT_OQ);
}


template <class F>
HORIZON_AVX512 inline void for_each_oct(uint64_t begin, uint64_t end, F&& f) {
  uint64_t k = begin;
  for (; k + 8 <= end; k += 8) f(k, 8, std::true_type{});
  if (k < end) f(k, static_cast<int>(end - k), std::false_type{});
}

template <bool kEnergy, bool kAfter>
HORIZON_AVX512 RowOut pair_row_avx512(const Ctx& c, std::size_t i, uint64_t total) {
  const Point4 pi = c.pt[i];
  const double Ri = c.R[i];
  const d8 s0i = _mm512_set1_pd(pi.w), zero = _mm512_setzero_pd();
  d8 fx = zero, fy = zero, fz = zero, en = zero, sm = _mm512_set1_pd(kInf);
  RowOut out;
  for_each_oct(c.offset[i], c.offset[i + 1], [&](uint64_t k, int count, auto full) HORIZON_AVX512 __attribute__((always_inline)) {
    Oct q;
    load_oct<KindView::bond_based, kEnergy, decltype(full)::value>(q, c, pi, i, k, count, total);
    const d8 r2 = norm2(q);
    const __mmask8 contact = touching(q, r2);
    if (q.live) {
      const d8 r = _mm512_sqrt_pd(r2), e = _mm512_sub_pd(r, q.L), stretch = _mm512_mul_pd(e, q.iL);
      const d8 s0 = _mm512_min_pd(s0i, q.wj);  // s0i < wj ? s0i : wj, as the other paths
      const __mmask8 breaks = q.live & _mm512_cmp_pd_mask(stretch, s0, _CMP_GT_OQ);
      const __mmask8 carries = kAfter ? q.live : static_cast<__mmask8>(q.live & ~breaks);
      const d8 a = _mm512_maskz_div_pd(carries, _mm512_mul_pd(q.pair, e), r);
      fx = _mm512_add_pd(fx, _mm512_mul_pd(a, q.Yx));
      fy = _mm512_add_pd(fy, _mm512_mul_pd(a, q.Yy));
      fz = _mm512_add_pd(fz, _mm512_mul_pd(a, q.Yz));
      sm = _mm512_mask_min_pd(sm, q.live, stretch, sm);  // stretch < sm ? stretch : sm
      if constexpr (kEnergy) {
        const d8 w = _mm512_mul_pd(_mm512_mul_pd(_mm512_mul_pd(_mm512_mul_pd(_mm512_set1_pd(0.5 * Ri), q.wv), q.iL), e), e);
        en = _mm512_add_pd(en, _mm512_maskz_mov_pd(static_cast<__mmask8>(q.live & ~breaks), w));
      }
      if (breaks) oct_breaks(c, pi, i, k, breaks, 0, true, Ri, 0.0, 0.0, out);
    }
    if (contact) add_contact<kEnergy>(c, pi, k, contact, fx, fy, fz, en);
  });
  out.fx = sum8(fx), out.fy = sum8(fy), out.fz = sum8(fz), out.energy = sum8(en), out.smin = min8(sm);
  return out;
}

template <bool kAfter>
HORIZON_AVX512 RowOut dilate_row_avx512(const Ctx& c, std::size_t i, double Pi, uint64_t total) {
  const Point4 pi = c.pt[i];
  const double Ri = c.R[i], Qi = c.Q[i];
  const d8 s0i = _mm512_set1_pd(pi.w);
  d8 th = _mm512_setzero_pd(), sm = _mm512_set1_pd(kInf);
  RowOut out;
  for_each_oct(c.offset[i], c.offset[i + 1], [&](uint64_t k, int count, auto full) HORIZON_AVX512 __attribute__((always_inline)) {
    Oct q;
    load_oct<KindView::dilatation, false, decltype(full)::value>(q, c, pi, i, k, count, total);
    if (!q.live) return;
    const d8 r2 = norm2(q);
    const d8 r = _mm512_sqrt_pd(r2), e = _mm512_sub_pd(r, q.L), stretch = _mm512_mul_pd(e, q.iL);
    _mm512_mask_storeu_pd(c.r_of + k, lanes_of(count), r);
    const d8 s0 = _mm512_min_pd(s0i, q.wj);
    const __mmask8 breaks = q.live & _mm512_cmp_pd_mask(stretch, s0, _CMP_GT_OQ);
    const __mmask8 counts = kAfter ? q.live : static_cast<__mmask8>(q.live & ~breaks);
    th = _mm512_add_pd(th, _mm512_maskz_mov_pd(counts, _mm512_mul_pd(_mm512_mul_pd(q.wv, q.L), e)));
    sm = _mm512_mask_min_pd(sm, q.live, stretch, sm);
    if (breaks) oct_breaks(c, pi, i, k, breaks, kAfter ? 2 : 0, false, Ri, Pi, Qi, out);
  });
  out.theta = sum8(th), out.smin = min8(sm);
  return out;
}

template <bool kEnergy>
HORIZON_AVX512 RowOut force_row_avx512(const Ctx& c, std::size_t i, uint64_t total) {
  const Point4 pi = c.pt[i];
  const double Ri = c.R[i];
  const d8 Pi = _mm512_set1_pd(pi.w), Qi = _mm512_set1_pd(c.Q[i]), zero = _mm512_setzero_pd();
  d8 fx = zero, fy = zero, fz = zero, en = zero;
  RowOut out;
  for_each_oct(c.offset[i], c.offset[i + 1], [&](uint64_t k, int count, auto full) HORIZON_AVX512 __attribute__((always_inline)) {
    Oct q;
    load_oct<KindView::force, kEnergy, decltype(full)::value>(q, c, pi, i, k, count, total);
    const d8 r2 = norm2(q);
    const __mmask8 contact = touching(q, r2);
    if (q.live) {
      // Q_j of the neighbours; padding lanes read Q_i.
      __m256i idx;
      if constexpr (decltype(full)::value) {
        idx = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(c.nbr + k));
      } else {
        alignas(32) uint32_t j[8];
        for (int l = 0; l < 8; ++l) j[l] = l < count ? c.nbr[k + static_cast<uint64_t>(l)] : static_cast<uint32_t>(i);
        idx = _mm256_load_si256(reinterpret_cast<const __m256i*>(j));
      }
      const d8 Qj = _mm512_mask_i32gather_pd(_mm512_setzero_pd(), 0xFF, idx, c.Q, 8);
      // |Y| from the dilatation pass; padding lanes 1.
      const d8 r = _mm512_mask_loadu_pd(_mm512_set1_pd(1.0), lanes_of(count), c.r_of + k), e = _mm512_sub_pd(r, q.L);
      const d8 t = _mm512_add_pd(_mm512_mul_pd(_mm512_add_pd(Pi, q.wj), q.L), _mm512_mul_pd(_mm512_add_pd(Qi, Qj), e));
      const d8 a = _mm512_maskz_div_pd(q.live, _mm512_add_pd(_mm512_mul_pd(q.wv, t), _mm512_mul_pd(q.pair, e)), r);
      fx = _mm512_add_pd(fx, _mm512_mul_pd(a, q.Yx));
      fy = _mm512_add_pd(fy, _mm512_mul_pd(a, q.Yy));
      fz = _mm512_add_pd(fz, _mm512_mul_pd(a, q.Yz));
      if constexpr (kEnergy) {
        const d8 inner = _mm512_add_pd(_mm512_mul_pd(Pi, q.L),
                                       _mm512_mul_pd(_mm512_add_pd(Qi, _mm512_mul_pd(_mm512_set1_pd(Ri), q.iL)), e));
        const d8 w = _mm512_mul_pd(_mm512_mul_pd(_mm512_mul_pd(_mm512_set1_pd(0.5), q.wv), inner), e);
        en = _mm512_add_pd(en, _mm512_maskz_mov_pd(q.once, w));
      }
      const unsigned clear = q.live ^ q.once;
      if (clear)
        for (int l = 0; l < count; ++l)
          if ((clear >> l) & 1u) c.intact[k + static_cast<uint64_t>(l)] = 0;
    }
    if (contact) add_contact<kEnergy>(c, pi, k, contact, fx, fy, fz, en);
  });
  out.fx = sum8(fx), out.fy = sum8(fy), out.fz = sum8(fz), out.energy = sum8(en);
  return out;
}
#endif  // HORIZON_AVX2_KERNELS

// ------------------------------------------------------------------------------------
// The passes: one row per particle, static schedule, each row written by one thread.

template <bool kEnergy, bool kAfter>
uint64_t bond_based_pass(System& s) {
  auto& P = s.particles;
  auto& M = s.model;
  const Ctx c = context(s);
  // A decomposed run computes the rows of its active particles alone (state/system.hpp).
  const std::vector<uint32_t>* act = s.active_rows.empty() ? nullptr : &s.active_rows;
  const std::size_t n = act ? act->size() : P.size();
  const uint64_t total = s.bonds.size();
  RowOut (*row)(const Ctx&, std::size_t, uint64_t) = pair_row_scalar<kEnergy, kAfter>;
#if defined(HORIZON_AVX2_KERNELS)
  if (use_avx2()) row = pair_row_avx2<kEnergy, kAfter>;
  if (use_avx512()) row = pair_row_avx512<kEnergy, kAfter>;
#endif
  uint64_t broken = 0;
#pragma omp parallel for schedule(static) reduction(+ : broken)
  for (std::size_t a = 0; a < n; ++a) {
    const std::size_t i = act ? (*act)[a] : a;
    const RowOut o = row(c, i, total);
    broken += o.broken;
    if (o.lost != 0) s.dissipated_at[i] += o.lost * P.volume[i];
    if (o.broken) M.intact_weight[i] = intact_damage_weight(s, i);  // afresh (state/system.hpp)
    P.damage[i] = damage_of(M.intact_weight[i], M.damage_total[i]);
    M.min_stretch_next[i] = o.smin;
    P.f[i] = {o.fx, o.fy, o.fz};
    if constexpr (kEnergy) P.energy[i] = o.energy;
  }
  return broken;
}

template <bool kAfter>
uint64_t break_and_dilate(System& s) {
  auto& P = s.particles;
  auto& M = s.model;
  if (M.deformed_length.size() != s.bonds.size()) M.deformed_length.assign(s.bonds.size(), 1.0);
  const Ctx c = context(s);
  // A decomposed run computes the rows of its active particles alone (state/system.hpp).
  const std::vector<uint32_t>* act = s.active_rows.empty() ? nullptr : &s.active_rows;
  const std::size_t n = act ? act->size() : P.size();
  const uint64_t total = s.bonds.size();
  RowOut (*row)(const Ctx&, std::size_t, double, uint64_t) = dilate_row_scalar<kAfter>;
#if defined(HORIZON_AVX2_KERNELS)
  if (use_avx2()) row = dilate_row_avx2<kAfter>;
  if (use_avx512()) row = dilate_row_avx512<kAfter>;
#endif
  uint64_t broken = 0;
#pragma omp parallel for schedule(static) reduction(+ : broken)
  for (std::size_t a = 0; a < n; ++a) {
    const std::size_t i = act ? (*act)[a] : a;
    const RowOut o = row(c, i, M.P[i], total);
    broken += o.broken;
    if (o.lost != 0) s.dissipated_at[i] += o.lost * P.volume[i];
    if (o.broken) M.intact_weight[i] = intact_damage_weight(s, i);  // afresh (state/system.hpp)
    P.damage[i] = damage_of(M.intact_weight[i], M.damage_total[i]);
    M.min_stretch_next[i] = o.smin;
    if (M.dilatation_coef[i] != 0) {
      const double theta = kernels::dilatation(M.dim, o.theta, M.weighted_volume[i]);
      M.theta[i] = theta;
      M.P[i] = kernels::dilatation_pressure(theta, M.dilatation_coef[i], M.deviatoric_coef[i], M.dim);
    }
  }
  return broken;
}

template <bool kEnergy>
void internal_force(System& s) {
  auto& P = s.particles;
  const Ctx c = context(s);
  // A decomposed run computes the rows of its active particles alone (state/system.hpp).
  const std::vector<uint32_t>* act = s.active_rows.empty() ? nullptr : &s.active_rows;
  const std::size_t n = act ? act->size() : P.size();
  const uint64_t total = s.bonds.size();
  RowOut (*row)(const Ctx&, std::size_t, uint64_t) = force_row_scalar<kEnergy>;
#if defined(HORIZON_AVX2_KERNELS)
  if (use_avx2()) row = force_row_avx2<kEnergy>;
  if (use_avx512()) row = force_row_avx512<kEnergy>;
#endif
#pragma omp parallel for schedule(static)
  for (std::size_t a = 0; a < n; ++a) {
    const std::size_t i = act ? (*act)[a] : a;
    const RowOut o = row(c, i, total);
    P.f[i] = {o.fx, o.fy, o.fz};
    if constexpr (kEnergy) P.energy[i] = o.energy;
  }
}

}  // namespace

void set_kernel_path(KernelPath p) {
  g_path = p;
  g_path_known = true;
}

const char* kernel_path_name() {
  if (path() == KernelPath::general) return "general";
  return use_avx512() ? "avx512" : use_avx2() ? "avx2" : "scalar";
}

uint64_t state_based_dilatation_pass(System& s) {
  pack_positions(s);
  return s.model.break_after_force ? break_and_dilate<true>(s) : break_and_dilate<false>(s);
}

void state_based_force_pass(System& s, bool energy) {
  auto& M = s.model;
  const std::size_t n = s.particles.size();
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) M.packed[i].w = M.P[i];
  energy ? internal_force<true>(s) : internal_force<false>(s);
}

namespace {
// The compression factor alpha lowers s0_j by the smallest stretch of j's *intact* bonds
// at the previous pass (Silling and Askari 2005, sec. 5). A rank computes its particles'
// bond neighbours' rows again (decompose), but such a row j reads s0_k of particles two
// horizons out that the rank does not compute, so once bonds break there its intact flags,
// and with them its smallest stretch and the owned rows' decisions on their bonds to j,
// could part from those of j's owner (found on tests/mpi/projectile.yaml: a bond broke on
// 2 ranks at step 193 and not on 1). The owners' values go to the ghosts after each pass
// (one scalar a ghost), so every row reads every s0 from the row that owns it, as
// serially. Collective when decomposed; nothing on one rank.
void share_min_stretch(System& s) {
  if (s.decomposition && s.decomposition->alpha) exchange_ghost_scalars(*s.decomposition, s.model.min_stretch);
}
}  // namespace

ForceStats compute_forces(System& s, bool energy) {
  ForceStats stats;
  ++s.model.passes;  // (history_ledger.hpp LedgerRows: which pass left |Y| and q behind)
  if (Model* owner = s.models.owner()) {  // a model that computes the whole pass (material/model.hpp)
    stats.broken = owner->force_pass(s, energy);
    s.broken += stats.broken;
    return stats;
  }
  if (s.fe_coupling) s.fe_coupling->interpolate(s);  // the interpolated particles follow the elements (FeCoupling)
  auto& M = s.model;
  if (M.kind.size() != s.bonds.kinds.size() || M.intact_weight.size() != s.particles.size())
    build_kind_coefficients(s, DamageMeasure::weighted);
  // The fast loops know no temperature: a thermal strain or a temperature-dependent
  // critical stretch takes the general pass.
  // One-way bonds (bodies of different horizons) need t_ji with j's own weight: the
  // general pass too (the fast loops take omega_ij for both directions).
  if (!s.models.all_unified() || path() == KernelPath::general || !s.thermal_strain.empty() ||
      !s.critical_stretch_factor.empty() || s.one_way_bonds) {
    if (s.bonds.length_per_bond) {
      // The general pass reads kinds with their lengths: regrouped, the same damage weights
      // (the running intact sums stay valid). Setup does this for the decks that need it
      // (setup_model); here only a pass chosen by set_kernel_path(general) gets here.
      expand_kinds(s.bonds);
      build_kind_tables(s, M.damage_measure);
    }
    stats.broken = general_forces(s, energy);  // solver/forces_general.cpp
    M.min_stretch.swap(M.min_stretch_next);
    share_min_stretch(s);
    s.contact.add_forces(s, M.packed.data(), s.particles.f.data(), energy ? s.particles.energy.data() : nullptr);
    if (s.fe_coupling) s.fe_coupling->apply(s, energy);  // the FE-owned nodes' forces (FeCoupling)
    s.broken += stats.broken;
    return stats;
  }
  pack_positions(s);
  const bool after = M.break_after_force;
  if (M.state_based) {
    stats.broken = after ? break_and_dilate<true>(s) : break_and_dilate<false>(s);
    state_based_force_pass(s, energy);  // gathers P_j with the position
  } else if (after) {
    stats.broken = energy ? bond_based_pass<true, true>(s) : bond_based_pass<false, true>(s);
  } else {
    stats.broken = energy ? bond_based_pass<true, false>(s) : bond_based_pass<false, false>(s);
  }
  M.min_stretch.swap(M.min_stretch_next);
  share_min_stretch(s);
  s.contact.add_forces(s, M.packed.data(), s.particles.f.data(), energy ? s.particles.energy.data() : nullptr);
  if (s.fe_coupling) s.fe_coupling->apply(s, energy);  // the FE-owned nodes' forces (FeCoupling)
  s.broken += stats.broken;
  return stats;
}


}  // namespace horizon
