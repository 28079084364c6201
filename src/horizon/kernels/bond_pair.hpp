#pragma once
// O'Grady's bond-pair beams, plates and flat shells (material/models/bond_pair.hpp; seed
// 001, O'Grady's dissertation ch. 3-5) as device-portable functions (core/portable.hpp,
// issue 30): the per-pair and per-bond work of its force pass (BondPair::force_pass) and
// the ghost nodes' positions. The pass calls these and scatters their forces onto the
// three nodes of a pair (or the two of a bond) in its serial order, as before; each
// function keeps the pass's operations in their order (core/vec3.hpp's component-wise
// products and sums, dot = (x x + y y) + z z), so its answers keep their bits.
//
//   bending pair:  e = coef f(c), c = cos theta = Yhat . Yhat', f = 1 + c (straight),
//                  1 - cos(theta - theta0) (curved shell)                  (eq. 3.1, 4.1 x 2)
//   signed pair:   e = coef (1 - cos(s - theta_p)), s the kink (eq. 4.2-4.3, 4.8)
//   shell pair:    e = coef (1 - cos |d - p|), d the kink vector (n, t)
//   isotropic-curvature correction: kbar_k = (1/m0) sum 2 omega V_j (Y + Y')/|xi|^2  (sec. 4.4)
//   extension spring: e = coef (|Y| - |xi|)^2, + the 2-D dilatation term (eq. 4.13, sec. 3.9)
#include <cmath>
#include <cstdint>

#include "horizon/core/portable.hpp"
#include "horizon/kernels/unified.hpp"

namespace horizon::kernels {

// Three doubles (a position, a bond, a force), with core/vec3.hpp's operations written out
// component by component: the kernels' own type, plain data on the host and the device.
struct BpVec {
  double x = 0, y = 0, z = 0;
};
HORIZON_HD inline BpVec bp_add(const BpVec& a, const BpVec& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
HORIZON_HD inline BpVec bp_sub(const BpVec& a, const BpVec& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
HORIZON_HD inline BpVec bp_scale(const BpVec& a, double s) { return {a.x * s, a.y * s, a.z * s}; }
HORIZON_HD inline double bp_dot(const BpVec& a, const BpVec& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

HORIZON_HD inline double bp_sin(double x) {
#if defined(__CUDA_ARCH__)
  return ::sin(x);
#else
  return std::sin(x);
#endif
}
HORIZON_HD inline double bp_cos(double x) {
#if defined(__CUDA_ARCH__)
  return ::cos(x);
#else
  return std::cos(x);
#endif
}
// sqrt(x^2 + y^2) without overflow: the C library's hypot on the host (std::hypot), the
// device library's on the device (both accurate to an ulp or so, not bit-identical).
HORIZON_HD inline double bp_hypot(double x, double y) {
#if defined(__CUDA_ARCH__)
  return ::hypot(x, y);
#else
  return std::hypot(x, y);
#endif
}
HORIZON_HD inline double bp_abs(double x) {
#if defined(__CUDA_ARCH__)
  return ::fabs(x);
#else
  return std::fabs(x);
#endif
}
// std::max(a, b): a < b ? b : a.
HORIZON_HD inline double bp_max(double a, double b) { return a < b ? b : a; }

// d(1 + cos theta)/dY and d(1 + cos theta)/dY' of a pair with deformed bonds Y, Y'
// (material/models/bond_pair.hpp bond_pair_gradient: one square root, two divisions):
// with r = 1/(|Y||Y'|), cos theta = (Y.Y') r, (Y' - (Y.Y'/|Y|^2) Y) r and symmetrically.
struct BpGradient {
  BpVec dY, dYp;
  double one_plus_cos = 0;
};
HORIZON_HD inline BpGradient bp_gradient(const BpVec& Y, const BpVec& Yp) {
  const double ia2 = 1 / bp_dot(Y, Y), ib2 = 1 / bp_dot(Yp, Yp), d = bp_dot(Y, Yp);
  const double r = root(ia2 * ib2);
  return {bp_scale(bp_sub(Yp, bp_scale(Y, d * ia2)), r), bp_scale(bp_sub(Y, bp_scale(Yp, d * ib2)), r), 1 + d * r};
}

// f(c) = 1 - cos(theta - theta0) = 1 - c c0 - s s0 of a pair with a reference angle, its
// f'(c) and f''(c) (bond_pair.hpp referenced_pair; s kept above 1e-9).
struct BpReferenced {
  double energy, dc, dcc;
};
HORIZON_HD inline BpReferenced bp_referenced(double c, double c0, double s0) {
  if (s0 == 0) return {1 + c, -c0, 0};
  const double s = bp_max(root(bp_max(0.0, 1 - c * c)), 1e-9);
  return {1 - c * c0 - s * s0, -c0 + s0 * c / s, s0 / (s * s * s)};
}

// The signed kink (w_j + w_j' - 2 w_k)/|xi| of the transverse mode (bond_pair.hpp signed_kink).
HORIZON_HD inline double bp_signed_kink(double wj, double wjp, double wk, double length) {
  return (wj + wjp - 2 * wk) / length;
}

// The elastic-perfectly-plastic return of a signed kink (bond_pair.hpp plastic_offset).
HORIZON_HD inline double bp_plastic_offset(double s, double theta_p, double theta_c) {
  const double trial = s - theta_p;
  if (bp_abs(trial) <= theta_c) return theta_p;
  return theta_p + (trial > 0 ? trial - theta_c : trial + theta_c);
}

// The kink vector (n, t) of a flat shell's pair and its radial return on the circle
// |d - p| <= theta_c (bond_pair.hpp Kink, plastic_offset).
struct BpKink {
  double n = 0, t = 0;
};
HORIZON_HD inline BpKink bp_kink_offset(const BpKink& d, const BpKink& p, double theta_c) {
  const double en = d.n - p.n, et = d.t - p.t, r = bp_hypot(en, et);
  if (r <= theta_c) return p;
  const double f = (r - theta_c) / r;
  return {p.n + f * en, p.t + f * et};
}

// d = (u_j + u_j' - 2 u_k)/|xi| in the pair's frame: n along z, t along z x xi/|xi|
// (BondPair::shell_kink), from the current (y) and reference (X) positions of j, j', k.
HORIZON_HD inline BpKink bp_shell_kink(const BpVec& yj, const BpVec& yjp, const BpVec& yk, const BpVec& Xj,
                                       const BpVec& Xjp, const BpVec& Xk, double inv_length) {
  const BpVec d = bp_scale(bp_sub(bp_add(bp_sub(yj, Xj), bp_sub(yjp, Xjp)), bp_scale(bp_sub(yk, Xk), 2.0)), inv_length);
  const BpVec e0 = bp_scale(bp_sub(Xj, Xk), inv_length);
  return {d.z, e0.x * d.y - e0.y * d.x};
}

// A pair fails (brittle, eq. 4.9) when its measure reaches the threshold, unless failure is
// off (theta_fail 0) or a node of the pair lies in a no_fail region.
HORIZON_HD inline bool bp_fails(double theta_fail, bool no_fail, double measure, double threshold) {
  return theta_fail > 0 && !no_fail && measure >= threshold;
}

// --- One pair of each kind: the force G on each of j and j' (-2 G on k, or the signs the
// pass gives them), the energy coef f, and the trial plastic offset. ---

// A flat shell's pair with its plastic offset p: e = coef (1 - cos r), r = |d - p|; the
// force on j and j' is -G, on k +2 G, G = coef sin(r)/r (-e0.y et, e0.x et, en)/|xi|.
struct BpShellPair {
  BpKink offset;
  BpVec G;
  double energy;
};
HORIZON_HD inline BpShellPair bp_shell_pair(const BpKink& d, const BpKink& p, double theta_yield, double coef,
                                            double inv_length, const BpVec& Xj, const BpVec& Xk) {
  BpShellPair out;
  out.offset = bp_kink_offset(d, p, theta_yield);
  const double en = d.n - out.offset.n, et = d.t - out.offset.t, r = bp_hypot(en, et);
  const double g = coef * (r > 0 ? bp_sin(r) / r : 1.0) * inv_length;
  const BpVec e0 = bp_scale(bp_sub(Xj, Xk), inv_length);
  out.G = {-e0.y * et * g, e0.x * et * g, en * g};
  out.energy = coef * (1 - bp_cos(r));
  return out;
}

// The transverse mode's signed kink of a pair, less the reference configuration's.
HORIZON_HD inline double bp_transverse_kink(double yj, double yjp, double yk, double Xj, double Xjp, double Xk,
                                            double inv_length) {
  return bp_signed_kink(yj, yjp, yk, 1 / inv_length) - (Xj + Xjp - 2 * Xk) * inv_length;
}
// Its pair with the plastic offset: e = coef (1 - cos(s - theta_p)); z-force -g on j and
// j', +2 g on k, g = coef sin(s - theta_p)/|xi|.
struct BpSignedPair {
  double offset, g, energy;
};
HORIZON_HD inline BpSignedPair bp_signed_pair(double sk, double theta_p, double theta_yield, double coef,
                                              double inv_length) {
  BpSignedPair out;
  out.offset = bp_plastic_offset(sk, theta_p, theta_yield);
  const double se = sk - out.offset;
  const double dEds = coef * bp_sin(se);
  out.g = dEds * inv_length;
  out.energy = coef * (1 - bp_cos(se));
  return out;
}

// An elastic pair (straight or with a reference angle): the forces on j and j' (k takes
// minus their sum) and f(c), the measure of the failure test (1 - cos theta_fail).
struct BpElasticPair {
  BpVec Fj, Fjp;
  double f;  // f(c): e = coef f
};
HORIZON_HD inline BpElasticPair bp_elastic_pair(const BpVec& Y, const BpVec& Yp, double coef, double c0, double s0) {
  const BpGradient gr = bp_gradient(Y, Yp);
  const BpReferenced rp = bp_referenced(gr.one_plus_cos - 1, c0, s0);
  return {bp_scale(gr.dY, -coef * rp.dc), bp_scale(gr.dYp, -coef * rp.dc), rp.energy};
}

// The isotropic-curvature sum's term of a pair at its centre: (Y + Y') 2 V_j/(|xi| m0).
HORIZON_HD inline BpVec bp_curvature_term(const BpVec& Y, const BpVec& Yp, double inv_length, double Vj,
                                          double m0_inv) {
  return bp_scale(bp_add(Y, Yp), 2 * inv_length * Vj * m0_inv);
}
// C kbar.kbar V_k, the correction's energy at a node.
HORIZON_HD inline double bp_curvature_energy(double C, const BpVec& kbar, double Vk) {
  return C * bp_dot(kbar, kbar) * Vk;
}

// --- Extension springs (one unordered bond k-j) ---

// |Y| of the bond, and |Y| - |xi|.
HORIZON_HD inline double bp_bond_length(const BpVec& Y) { return root(bp_dot(Y, Y)); }
HORIZON_HD inline double bp_bond_extension(const BpVec& Y, double length) { return bp_bond_length(Y) - length; }
// The bond's term of an end's 2-D dilatation, (2 omega |xi| / m_b) V e of the other end's V.
HORIZON_HD inline double bp_dilatation_term(double dil, double e, double V) { return dil * e * V; }
// The force on k (j takes minus it), Y dE/d|Y| / |Y| with dE/d|Y| = 2 coef e, plus the
// dilatation term dil_coef (theta_k V_k dil V_j + theta_j V_j dil V_k) when dil_coef != 0
// (L = |Y|, e = |Y| - |xi|).
HORIZON_HD inline BpVec bp_spring_force(const BpVec& Y, double L, double e, double coef, double dil_coef, double dil,
                                        double theta_k, double theta_j, double Vk, double Vj) {
  double t = 2 * coef * e;
  if (dil_coef != 0) t += dil_coef * (theta_k * Vk * dil * Vj + theta_j * Vj * dil * Vk);
  return bp_scale(Y, t / L);
}
// Each end's share of the spring's energy, coef e^2/2.
HORIZON_HD inline double bp_spring_energy(double coef, double e) { return 0.5 * coef * e * e; }
// The 2-D dilatation's energy at a node, (dil_coef/2) theta^2 V.
HORIZON_HD inline double bp_dilatation_energy(double dil_coef, double theta, double V) {
  return 0.5 * dil_coef * theta * theta * V;
}

// A ghost node's displacement, one term at a time: u += coeff o u_master (component-wise).
HORIZON_HD inline BpVec bp_ghost_term(const BpVec& u, const BpVec& coeff, const BpVec& um) {
  return bp_add(u, {coeff.x * um.x, coeff.y * um.y, coeff.z * um.z});
}

// --- Per node ---

// A real node's force density from its summed force F (core/vec3.hpp's F / V: F times
// 1/V): beams and plates move in z only (the force (0, 0, 1) f_z), and a shell's node on a
// support line takes its energy weight w on its in-plane force (BondPair::force_pass).
HORIZON_HD inline BpVec bp_node_force(const BpVec& F, double volume, bool transverse, double weight) {
  const BpVec f = bp_scale(F, 1.0 / volume);
  if (transverse) return {0.0 * f.z, 0.0 * f.z, 1.0 * f.z};
  if (weight != 1) return {f.x * weight, f.y * weight, f.z};
  return f;
}
// The node's booked energy density, its energies' sum e times w/V.
HORIZON_HD inline double bp_node_energy(double e, double weight, double volume) { return e * (weight / volume); }
// Damage: the fraction of failed pairs about the node (dissertation Fig. 5.16).
HORIZON_HD inline double bp_damage(double failed, double pairs) { return pairs > 0 ? failed / pairs : 0.0; }
// The node's stable step 2/sqrt(lambda_max), lambda_max <= bound/(rho section) (digest sec. 4.8).
HORIZON_HD inline double bp_stable_step(double bound, double density, double section) {
  const double mass = density * section;  // rho A or rho h
  return 2 / root(bound / mass);
}

}  // namespace horizon::kernels
