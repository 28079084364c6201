#pragma once
// The per-bond and per-particle work of the correspondence model (its affine pass,
// solver/forces_affine.cpp and solver/affine_sweeps.cpp) as device-portable functions
// (core/portable.hpp, issue 30): 3 x 3 matrices are row-major double[9], no Eigen, no
// containers, no exceptions. The host calls these same functions (NonlocalGradient::finish,
// Correspondence::affine_row, the sweeps' portable rows), so a device build of the pass
// computes what the host computes.
//
// Bits. The host computed these with Eigen before; every function below keeps Eigen's
// operations in Eigen's order as this build compiles them (-march=x86-64-v2: SSE2 packets
// of two doubles), so the host's answers kept their bits when it moved onto them
// (tests/unit/test_affine_kernels.cpp compares each with its Eigen form, bit for bit):
//   - a 3 x 3 product C = A B: rows 0 and 1 of a column are one packet, summed
//     (a0 b0 + a1 b1) + a2 b2; row 2 is a scalar reduction, a0 b0 + (a1 b1 + a2 b2);
//     the same for a matrix times a vector;
//   - a trace a00 + (a11 + a22); a squared norm (v0^2 + v1^2) + v2^2;
//   - the sum of the nine entries of a product of two matrices taken element by element
//     (sigma : eps), in column-major order in two lanes: ((e0 + e2) + (e4 + e6)) +
//     ((e1 + e3) + (e5 + e7)), then + e8 (e_k the k-th entry in column-major order);
//   - the inverse by cofactors: det = (c00 a00 + c10 a10) + c20 a20 over the first
//     column's cofactors, K^-1_ij = c_ji (1/det).
// One exception: the shape tensor's reciprocal condition number (smallest eigenvalue
// over largest) was Eigen's SelfAdjointEigenSolver::computeDirect; here it is the
// closed-form trigonometric solution of the characteristic cubic (Smith 1961, "Eigenvalues
// of a symmetric 3 x 3 matrix", CACM 4(4), 168). The two differ by round-off; the ratio
// only meets `shape_tolerance` (1e-4 by default) in a comparison, so the answer changes
// only for a shape tensor whose ratio lies within round-off of the tolerance.
//
// The pair form (docs/design.md, "Its affine form"): the force state of correspondence.hpp
// (*), T_ij = omega (A_i xi + G (Y - F_i xi)) with A_i = P_i K_i^-1 (seed 003 eq. 142;
// Silling 2017 for the G term), is affine in the bond:
//   T_ij = omega (M_i xi + g_i Y),   M_i = A_i - G F_i,  g_i = G,
// with M_i = 0, g_i = 0 for a particle that carries no stress (refused shape tensor) and
// A_i = 0 when its law refuses F (det F <= 0: the stabilisation stays). One record of
// kAffineRecord numbers per particle holds {M_i row by row, g_i}.
//
// The reverse bond has xi_ji = -xi, Y_ji = -Y and the same omega (the influence function
// of |xi|), so T_ji = -omega (M_j xi + g_j Y) and the force density of seed 003 eq. 33,
//   f_i = sum_j V_j (T_ij - T_ji) = sum_j omega V_j ((M_i + M_j) xi + (g_i + g_j) Y),
// needs the neighbour's 80-byte record (read by particle index: the family's records stay
// in cache from row to row) instead of the reverse bond's force state (a random 24-byte
// read through the reverse-bond index). Summed as
//   f_i = M_i sum_j w xi + g_i sum_j w Y + sum_j w (M_j xi + g_j Y),   w = omega V_j,
// the bond costs 3 + 3 + 12 multiply-adds. The same forces as the vector form of the
// general pass up to the rounding of the sums (tests/verification/test_general_pass.cpp).
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "horizon/core/point4.hpp"
#include "horizon/core/portable.hpp"
#include "horizon/core/vec3.hpp"
#include "horizon/kernels/lanes.hpp"
#include "horizon/kernels/unified.hpp"

namespace horizon::kernels {

inline constexpr int kAffineRecord = 10;

// The device's and the host's acos, hypot and cos (both within an ulp or two; used only in the
// condition number, see above).
HORIZON_HD inline double arc_cosine(double x) {
#if defined(__CUDA_ARCH__)
  return ::acos(x);
#else
  return std::acos(x);
#endif
}
HORIZON_HD inline double hypotenuse(double x, double y) {
#if defined(__CUDA_ARCH__)
  return ::hypot(x, y);
#else
  return std::hypot(x, y);
#endif
}
HORIZON_HD inline double cosine(double x) {
#if defined(__CUDA_ARCH__)
  return ::cos(x);
#else
  return std::cos(x);
#endif
}

// ---- 3 x 3 algebra (row-major double[9]) in the order given above ----

// c = a b (c may not alias a or b).
HORIZON_HD inline void mat3_mul(const double* a, const double* b, double* c) {
  for (int j = 0; j < 3; ++j) {
    for (int r = 0; r < 2; ++r) c[3 * r + j] = (a[3 * r] * b[j] + a[3 * r + 1] * b[3 + j]) + a[3 * r + 2] * b[6 + j];
    c[6 + j] = a[6] * b[j] + (a[7] * b[3 + j] + a[8] * b[6 + j]);
  }
}

// w = a v.
HORIZON_HD inline void mat3_vec(const double* a, const double* v, double* w) {
  for (int r = 0; r < 2; ++r) w[r] = (a[3 * r] * v[0] + a[3 * r + 1] * v[1]) + a[3 * r + 2] * v[2];
  w[2] = a[6] * v[0] + (a[7] * v[1] + a[8] * v[2]);
}

HORIZON_HD inline double mat3_trace(const double* a) { return a[0] + (a[4] + a[8]); }

HORIZON_HD inline double squared_norm3(const double* v) { return (v[0] * v[0] + v[1] * v[1]) + v[2] * v[2]; }

// sum_ij a_ij b_ij.
HORIZON_HD inline double mat3_contract(const double* a, const double* b) {
  double e[9];
  for (int k = 0; k < 9; ++k) e[k] = a[3 * (k % 3) + k / 3] * b[3 * (k % 3) + k / 3];  // column-major order
  return (((e[0] + e[2]) + (e[4] + e[6])) + ((e[1] + e[3]) + (e[5] + e[7]))) + e[8];
}

// The cofactor of entry (i, j).
HORIZON_HD inline double cofactor3(const double* m, int i, int j) {
  const int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
  return m[3 * i1 + j1] * m[3 * i2 + j2] - m[3 * i1 + j2] * m[3 * i2 + j1];
}

// inv = m^-1 by cofactors (no test of det: the caller has checked the conditioning).
HORIZON_HD inline void mat3_inverse(const double* m, double* inv) {
  const double c0[3] = {cofactor3(m, 0, 0), cofactor3(m, 1, 0), cofactor3(m, 2, 0)};
  const double det = (c0[0] * m[0] + c0[1] * m[3]) + c0[2] * m[6];
  const double id = 1.0 / det;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) inv[3 * r + c] = (r == 0 ? c0[c] : cofactor3(m, c, r)) * id;
}

// ---- the shape tensor and the deformation gradient (material/nonlocal_gradient.hpp) ----

// The reciprocal condition number of the symmetric d x d shape tensor K (top-left block):
// smallest over largest eigenvalue, 0 when the largest is not positive.
HORIZON_HD inline double shape_condition(const double* K, int d) {
  if (d == 3) {
    // Smith 1961: scaled by the largest entry, A = q I + p B with q = tr A/3, p^2 =
    // |A - q I|_F^2 / 6, the eigenvalues are q + 2 p cos(phi + 2 pi k/3), phi = acos(det B / 2)/3.
    double s = 0;
    for (int c = 0; c < 9; ++c) {
      const double v = K[c] < 0 ? -K[c] : K[c];
      s = v > s ? v : s;
    }
    if (!(s > 0) || !finite(s)) return 0.0;
    double a[9];
    for (int c = 0; c < 9; ++c) a[c] = K[c] / s;
    const double q = (a[0] + a[4] + a[8]) / 3.0;
    const double off = a[1] * a[1] + a[2] * a[2] + a[5] * a[5];
    const double d0 = a[0] - q, d1 = a[4] - q, d2 = a[8] - q;
    const double p2 = (d0 * d0 + d1 * d1 + d2 * d2 + 2.0 * off) / 6.0;
    if (!(p2 > 0)) return q > 0 ? 1.0 : 0.0;  // a multiple of the identity
    const double p = root(p2);
    const double b[9] = {d0 / p, a[1] / p, a[2] / p, a[3] / p, d1 / p, a[5] / p, a[6] / p, a[7] / p, d2 / p};
    double h = 0.5 * ((b[0] * cofactor3(b, 0, 0) + b[3] * cofactor3(b, 1, 0)) + b[6] * cofactor3(b, 2, 0));
    h = h < -1.0 ? -1.0 : (h > 1.0 ? 1.0 : h);
    const double phi = arc_cosine(h) / 3.0;
    constexpr double kThird = 2.0943951023931954923;  // 2 pi / 3
    const double hi = q + 2.0 * p * cosine(phi), lo = q + 2.0 * p * cosine(phi + kThird);
    return hi > 0 ? lo / hi : 0.0;
  }
  if (d == 2) {
    const double a = K[0], b = K[4], c = K[1];
    const double mean = 0.5 * (a + b), r = hypotenuse(0.5 * (a - b), c);
    const double hi = mean + r, lo = mean - r;
    return hi > 0 ? lo / hi : 0.0;
  }
  return K[0] > 0 ? 1.0 : 0.0;
}

// K^-1 and F = N K^-1 of the d x d blocks (d < 3: zeros beside the block in K^-1, ones
// on F's unused diagonal); false (K^-1 = 0, F = I) when the shape tensor is refused
// (reciprocal condition not above `tolerance`; seed 000 digest sec. 6.1).
HORIZON_HD inline bool gradient_finish(const double* K, const double* N, int d, double tolerance, double* Kinv,
                                       double* F) {
  for (int c = 0; c < 9; ++c) Kinv[c] = 0.0, F[c] = (c % 4 == 0) ? 1.0 : 0.0;
  if (!(shape_condition(K, d) > tolerance)) return false;
  if (d == 3) {
    mat3_inverse(K, Kinv);
    mat3_mul(N, Kinv, F);
  } else if (d == 2) {
    const double id = 1.0 / (K[0] * K[4] - K[3] * K[1]);
    Kinv[0] = K[4] * id, Kinv[3] = -K[3] * id, Kinv[1] = -K[1] * id, Kinv[4] = K[0] * id;
    for (int r = 0; r < 2; ++r)
      for (int c = 0; c < 2; ++c) F[3 * r + c] = N[3 * r] * Kinv[c] + N[3 * r + 1] * Kinv[3 + c];
  } else {
    Kinv[0] = 1.0 / K[0];
    F[0] = N[0] * Kinv[0];
  }
  return true;
}

// ---- stress laws and stress measures (material/classical/stress_laws.hpp) ----

// The small-strain linear elastic law: eps = sym(F) - I, sigma = lambda tr(eps) I +
// 2 mu eps (= P), W = sigma : eps / 2 (classical/stress_laws.hpp linear_elastic).
HORIZON_HD inline void linear_elastic_stress(double lambda, double mu, const double* F, double* sigma, double& W) {
  double eps[9];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) eps[3 * r + c] = 0.5 * (F[3 * r + c] + F[3 * c + r]) - (r == c ? 1.0 : 0.0);
  const double lt = lambda * mat3_trace(eps), two_mu = 2.0 * mu;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) sigma[3 * r + c] = lt * (r == c ? 1.0 : 0.0) + two_mu * eps[3 * r + c];
  W = 0.5 * mat3_contract(sigma, eps);
}

// The von Mises equivalent of a Cauchy stress, sqrt(3/2 dev(s) : dev(s)).
HORIZON_HD inline double von_mises(const double* s) {
  const double m = mat3_trace(s) / 3.0;
  double dev[9];
  for (int c = 0; c < 9; ++c) dev[c] = s[c] - m * (c % 4 == 0 ? 1.0 : 0.0);
  return root(1.5 * mat3_contract(dev, dev));
}

// ---- the record, the stabilisation and the pair form ----

// The record of one particle: A (row-major 3 x 3, or null: carries no stress through its
// law), F (row-major), G; null F: the particle carries no stress at all (record 0).
HORIZON_HD inline void affine_record(const double* A, const double* F, double G, double* rec) {
  for (int c = 0; c < kAffineRecord; ++c) rec[c] = 0;
  if (!F) return;
  for (int c = 0; c < 9; ++c) rec[c] = (A ? A[c] : 0.0) - G * F[c];
  rec[9] = G;
}

// The record from the law's first Piola-Kirchhoff stress P (null: the law refused F):
// A = P K^-1 (T = omega P K^-1 xi, seed 003 eq. 142), then affine_record.
HORIZON_HD inline void affine_record_of_stress(const double* P, const double* Kinv, const double* F, double G,
                                               double* rec) {
  double A[9];
  if (P) mat3_mul(P, Kinv, A);
  affine_record(P ? A : nullptr, F, G, rec);
}

// The stabilisation energy of one bond, (G/2) omega V_j |Y - F xi|^2 [J/m^3]
// (correspondence.hpp bond_stabilization_energy).
HORIZON_HD inline double stabilization_energy(const double* F, double G, double omega_volume, const double* xi,
                                              const double* Y) {
  double Fx[3];
  mat3_vec(F, xi, Fx);
  const double z[3] = {Y[0] - Fx[0], Y[1] - Fx[1], Y[2] - Fx[2]};
  return 0.5 * G * omega_volume * squared_norm3(z);
}

// T_ij = omega (M_i xi + g_i Y) of one bond.
HORIZON_HD inline void affine_force_state(const double* rec, double omega, const double* xi, const double* Y,
                                          double* T) {
  for (int r = 0; r < 3; ++r)
    T[r] = omega * (rec[3 * r] * xi[0] + rec[3 * r + 1] * xi[1] + rec[3 * r + 2] * xi[2] + rec[9] * Y[r]);
}

// The sums of the shape tensor and of the deformation gradient over a row's acting bonds
// (seed 003 eq. 17, 134; material/nonlocal_gradient.hpp): K = sum_j w xi (x) xi,
// N = sum_j w Y (x) xi, w = omega V_j, both row-major, added bond by bond as
// NonlocalGradient::add does (the same products in the same order: the same bits).
struct GradientSums {
  double v[18] = {};  // K, then N
};

HORIZON_HD inline void gradient_add(GradientSums& g, const double* xi, const double* Y, double w) {
  for (int r = 0; r < 3; ++r) {
    const double wa = w * xi[r], wy = w * Y[r];
    for (int c = 0; c < 3; ++c) {
      g.v[3 * r + c] += wa * xi[c];
      g.v[9 + 3 * r + c] += wy * xi[c];
    }
  }
}

// The running sums of one row (see above).
struct AffineRowSum {
  double sxi[3] = {0, 0, 0};  // sum_j w xi
  double sy[3] = {0, 0, 0};   // sum_j w Y
  double acc[3] = {0, 0, 0};  // sum_j w (M_j xi + g_j Y)
};

// One acting bond of the row: w = omega V_j, recj the neighbour's record.
HORIZON_HD inline void affine_pair_add(AffineRowSum& s, const double* recj, double w, const double* xi,
                                       const double* Y) {
  const double a[3] = {w * xi[0], w * xi[1], w * xi[2]};
  const double gy = w * recj[9];
  for (int r = 0; r < 3; ++r) {
    s.sxi[r] += a[r];
    s.sy[r] += w * Y[r];
    s.acc[r] += recj[3 * r] * a[0] + recj[3 * r + 1] * a[1] + recj[3 * r + 2] * a[2] + gy * Y[r];
  }
}

// f_i of the row from its sums and its own record.
HORIZON_HD inline void affine_pair_finish(const AffineRowSum& s, const double* reci, double* f) {
  for (int r = 0; r < 3; ++r)
    f[r] = reci[3 * r] * s.sxi[0] + reci[3 * r + 1] * s.sxi[1] + reci[3 * r + 2] * s.sxi[2] + reci[9] * s.sy[r] +
           s.acc[r];
}

// ---- one whole particle of the linear elastic law ----

// What the row of a linear elastic particle leaves (Correspondence::affine_row).
struct AffineRow {
  bool carries = false;  // the shape tensor was accepted
  double W = 0;          // the law's energy density (without the stabilisation's)
  double von_mises = 0;  // of sigma
  double F[9];           // the deformation gradient (I when refused)
};

// The start of a law row: K^-1 and F from the sums (gradient_finish) into out; a refused
// shape tensor leaves out.carries false and the record zero.
HORIZON_HD inline bool law_row_gradient(const double* sums, int d, double tolerance, double* Kinv, AffineRow& out,
                                        double* rec) {
  out.carries = gradient_finish(sums, sums + 9, d, tolerance, Kinv, out.F);
  if (!out.carries) affine_record(nullptr, nullptr, 0.0, rec);
  return out.carries;
}

// Row i of the linear elastic law from its sums (K then N, GradientSums) to its record:
// gradient_finish, the law, the von Mises stress, the record {P K^-1 - G F, G}.
HORIZON_HD inline AffineRow linear_elastic_row(const double* sums, int d, double tolerance, double lambda, double mu,
                                               double G, double* rec) {
  AffineRow out;
  double Kinv[9];
  if (!law_row_gradient(sums, d, tolerance, Kinv, out, rec)) return out;
  double sigma[9];
  linear_elastic_stress(lambda, mu, out.F, sigma, out.W);
  out.von_mises = von_mises(sigma);
  affine_record_of_stress(sigma, Kinv, out.F, G, rec);
  return out;
}

// ---- the pass's two sweeps (solver/forces_affine.cpp), in the fast loops' lanes ----
//
// Bond k of a row goes to lane (k - row start) mod 8, each lane keeps its own partial sums
// (of K and N in the breaking sweep, of the pair form's three sums in the force sum), and
// the lanes are added as ((l0 + l1) + (l2 + l3)) + ((l4 + l5) + (l6 + l7)) at the end of
// the row (kernels/lanes.hpp). The host's AVX-512 rows (solver/affine_sweeps.cpp) add
// the same lanes in one register each, so they give these rows' bits. The per-kind
// constants are read through template parameters: Kind (state/system.hpp
// KindCoefficients: damage, contact_d2, contact_d, contact_k) and BondK (family/bonds.hpp
// BondKind: weight, volume, fraction); a device build passes plain structs with the same
// members.

// What the sweeps read and write, taken from the System once per pass.
// Point: the packed points' type, the host's aligned Point4 or the flat arrays' FlatPoint
// (kernels/flat_system.hpp, the same four doubles without the alignment).
template <class Kind, class BondK, class Point = Point4>
struct AffineSweep {
  const Point* pt = nullptr;            // y, w = s0 of the pass (packed positions)
  const Point* ref = nullptr;           // the reference positions X, packed {x, y, z, 0}
  const Vec3* y_old = nullptr;          // the positions of the last pass (System::model.affine_position)
  const double* record = nullptr;       // the records (System::model.affine_record): the last pass's
                                        // in the breaking sweep, this pass's in the sum
  const Kind* kc = nullptr;             // per kind
  const Point* kind_record = nullptr;   // per kind {L, 1/L, omega V_j, -} (System::model.kind_dilatation)
  const BondK* kinds = nullptr;
  const uint32_t* nbr = nullptr;
  const uint32_t* kind = nullptr;
  const uint64_t* offset = nullptr;
  uint8_t* intact = nullptr;
  double* intact_weight = nullptr;  // per particle
  const double* soft = nullptr;     // critical-stretch factor per particle, or null
  uint64_t total = 0;               // bonds
  bool after = false;               // break_after_force: a breaking bond still acts in this pass
  bool contact = false;             // short-range contact between family pairs
  bool kinds_have_lengths = true;   // not Bonds::length_per_bond
};

// What the breaking sweep leaves of a row: its smallest stretch, the energy of the bonds
// it broke (per unit V_i) and how many.
struct AffineBreak {
  double smin, lost;
  uint64_t broken;
};

// s0 scaled by a temperature-dependent factor; an infinite s0 (no_fail) stays infinite.
HORIZON_HD inline double scaled_s0(double w, double f) { return (w == INFINITY || w == -INFINITY) ? w : w * f; }

// Bond k of row i breaks (bond order; the rare path of every implementation): its flag,
// the damage weight, and the energy it held, (1/2) (T_old . Y/|Y|) e V_j with T_old its
// force state of the last pass rebuilt from i's record and that pass's positions (zero
// before the first: the records start at 0), as forces_general.cpp break_row books it.
// r, e: this pass's |Y| and extension, computed as the lanes compute them.
template <class Kind, class BondK, class Point>
HORIZON_HD inline void affine_break_bond(const AffineSweep<Kind, BondK, Point>& s, std::size_t i, uint64_t k, double r,
                                         double e, AffineBreak& out) {
  const uint32_t j = s.nbr[k];
  const BondK& bk = s.kinds[s.kind[k]];
  s.intact[k] = s.after ? 2 : 0;
  ++out.broken;
  if (r > 0) {
    const Point pi = s.pt[i], pj = s.pt[j], xi_i = s.ref[i], xj = s.ref[j];
    const double Y[3] = {pj.x - pi.x, pj.y - pi.y, pj.z - pi.z};
    const double xi[3] = {xj.x - xi_i.x, xj.y - xi_i.y, xj.z - xi_i.z};
    const Vec3 &yo_i = s.y_old[i], &yo_j = s.y_old[j];
    const double yv[3] = {yo_j.x - yo_i.x, yo_j.y - yo_i.y, yo_j.z - yo_i.z};
    double T[3];
    affine_force_state(s.record + kAffineRecord * i, bk.weight, xi, yv, T);
    out.lost += 0.5 * (T[0] * Y[0] + T[1] * Y[1] + T[2] * Y[2]) / r * e * (bk.volume * bk.fraction);
  }
  s.intact_weight[i] -= s.kc[s.kind[k]].damage;
}

// Row i of the breaking sweep: the critical-stretch breaking of its intact bonds, their
// smallest stretch, and over the bonds that act in this pass sums[0..8] = K, sums[9..17]
// = N (row-major; w the kind's omega V_j), what the model's row reads.
template <class Kind, class BondK, class Point>
HORIZON_HD inline AffineBreak affine_break_row(const AffineSweep<Kind, BondK, Point>& s, std::size_t i, double* sums) {
  constexpr int kSums = 18;
  const Point pi = s.pt[i], xi_i = s.ref[i];
  const double wi = s.soft ? scaled_s0(pi.w, s.soft[i]) : pi.w;
  double acc[kSums][kLanes] = {};
  double sm[kLanes];
  for (int l = 0; l < kLanes; ++l) sm[l] = INFINITY;
  AffineBreak out{INFINITY, 0, 0};
  for_each_lane(s.offset[i], s.offset[i + 1], [&](uint64_t k, int l) {
    if (!s.intact[k]) return;
    const uint32_t j = s.nbr[k];
    const Point pj = s.pt[j], xj = s.ref[j], kr = s.kind_record[s.kind[k]];
    const double Y[3] = {pj.x - pi.x, pj.y - pi.y, pj.z - pi.z};
    const double xi[3] = {xj.x - xi_i.x, xj.y - xi_i.y, xj.z - xi_i.z};
    const double r = bond_length(Y[0], Y[1], Y[2]), e = r - kr.x, stretch = e * kr.y;
    sm[l] = stretch < sm[l] ? stretch : sm[l];
    const double wj = s.soft ? scaled_s0(pj.w, s.soft[j]) : pj.w;
    if (breaks(stretch, wi, wj)) {
      affine_break_bond(s, i, k, r, e, out);
      if (!s.after) return;
    }
    const double w = kr.z;  // omega V_j of the kind
    for (int a = 0; a < 3; ++a) {
      const double wa = w * xi[a], wy = w * Y[a];
      for (int c = 0; c < 3; ++c) {
        acc[3 * a + c][l] += wa * xi[c];
        acc[9 + 3 * a + c][l] += wy * xi[c];
      }
    }
  });
  for (int q = 0; q < kSums; ++q) sums[q] = lane_total(acc[q]);
  out.smin = lane_min(sm);
  return out;
}

// No work beside the sum's (the host's rows).
struct NoBondWork {
  HORIZON_HD void operator()(uint64_t, const double*, const double*) const {}
};

// Row i of the sum, once every row has its record: f_i = sum_j omega V_j ((M_i + M_j) xi +
// (g_i + g_j) Y) over the acting bonds (affine_pair_add lane by lane, then
// affine_pair_finish), plus the family contact of every bond (energy: its share).
// `bond(k, xi, Y)` is called for each acting bond in bond order after its sums (the flat
// rows: the stabilisation's energy, kernels/flat_affine.hpp).
template <class Kind, class BondK, class Point, class BondWork = NoBondWork>
HORIZON_HD inline void affine_sum_row(const AffineSweep<Kind, BondK, Point>& s, std::size_t i, double* f, double& energy,
                                      const BondWork& bond = BondWork{}) {
  const Point pi = s.pt[i], xi_i = s.ref[i];
  double sxi[3][kLanes] = {}, sy[3][kLanes] = {}, acc[3][kLanes] = {}, w[kLanes] = {};
  for_each_lane(s.offset[i], s.offset[i + 1], [&](uint64_t k, int l) {
    const uint32_t j = s.nbr[k];
    const Point pj = s.pt[j];
    const double Y[3] = {pj.x - pi.x, pj.y - pi.y, pj.z - pi.z};
    if (s.intact[k]) {
      const Point xj = s.ref[j];
      const double* m = s.record + kAffineRecord * static_cast<std::size_t>(j);
      const double xi[3] = {xj.x - xi_i.x, xj.y - xi_i.y, xj.z - xi_i.z};
      const double wv = s.kind_record[s.kind[k]].z;  // omega V_j of the kind
      const double a[3] = {wv * xi[0], wv * xi[1], wv * xi[2]};
      const double gy = wv * m[9];
      for (int r = 0; r < 3; ++r) {
        sxi[r][l] += a[r];
        sy[r][l] += wv * Y[r];
        acc[r][l] += m[3 * r] * a[0] + m[3 * r + 1] * a[1] + m[3 * r + 2] * a[2] + gy * Y[r];
      }
      bond(k, xi, Y);
    }
    if (s.contact) {
      const Kind& kc = s.kc[s.kind[k]];
      double c = 0, wc = 0;
      if (contact_coefficient(kc.contact_d2, kc.contact_d, kc.contact_k, (Y[0] * Y[0] + Y[1] * Y[1]) + Y[2] * Y[2], c,
                              wc)) {
        acc[0][l] += c * Y[0], acc[1][l] += c * Y[1], acc[2][l] += c * Y[2];
        w[l] += wc;
      }
    }
  });
  AffineRowSum sum;
  for (int r = 0; r < 3; ++r) {
    sum.sxi[r] = lane_total(sxi[r]);
    sum.sy[r] = lane_total(sy[r]);
    sum.acc[r] = lane_total(acc[r]);
  }
  affine_pair_finish(sum, s.record + kAffineRecord * i, f);
  energy = lane_total(w);
}

// The damage weight of row i's intact bonds (intact == 1), in the lanes
// (state/kind_coefficients.cpp intact_damage_weight), after a row broke bonds.
template <class Kind>
HORIZON_HD inline double intact_weight_lanes(const uint64_t* offset, const uint8_t* intact, const uint32_t* kind,
                                             const Kind* kc, std::size_t i) {
  double w[kLanes] = {};
  for_each_lane(offset[i], offset[i + 1], [&](uint64_t k, int l) {
    if (intact[k] == 1) w[l] += kc[kind[k]].damage;
  });
  return lane_total(w);
}

}  // namespace horizon::kernels
