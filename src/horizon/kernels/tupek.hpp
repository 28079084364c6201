#pragma once
// The per-bond and per-row work of Tupek's nonlinear solid (material/models/
// nonlinear_solid.hpp, seed 000_7a6865da82fe3c94, M. R. Tupek, PhD thesis MIT 2014) as
// device-portable functions (core/portable.hpp, issue 30). The model's force pass
// (NonlinearSolid::force_pass) calls these row by row; each keeps the operations of the
// pass in their order, so its answers kept their bits.
//
// One force pass is two sweeps over the rows, each row summed by one thread in bond order:
//   1. tupek_strain_row: the bond strains eps_ij (kept per bond) and
//      theta_i = sum_j phi omega eps V_j (thesis eq. 6.8);
//   2. tupek_force_row: for each acting bond the force (t_ij + t_ji) Y/|Y| V_j with
//      t_ij = (lambda_bar_i theta_i + 2 mu_bar_i eps) phi omega d eps/d|Y| (eq. 6.8), the
//      symmetric pair criterion s_ij + s_ji >= 2 beta/|xi|^p of an intact bond in tension
//      (eqs. 6.3, 6.5), and the family contact of a broken bond that no longer acts.
// The rows read the per-kind constants through a template parameter (the host passes its
// KindCoefficients, state/system.hpp; a device build its own plain struct with the same
// members: inv_length, wv, contact_d2, contact_d, contact_k).
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "horizon/core/point4.hpp"
#include "horizon/core/portable.hpp"
#include "horizon/kernels/unified.hpp"

namespace horizon::kernels {

HORIZON_HD inline double natural_exp(double x) {
#if defined(__CUDA_ARCH__)
  return ::exp(x);
#else
  return std::exp(x);
#endif
}
HORIZON_HD inline double magnitude(double x) {
#if defined(__CUDA_ARCH__)
  return ::fabs(x);
#else
  return std::fabs(x);
#endif
}
HORIZON_HD inline double exp_minus_one(double x) {
#if defined(__CUDA_ARCH__)
  return ::expm1(x);
#else
  return std::expm1(x);
#endif
}

// Seth-Hill bond strain (thesis eq. 4.2): eps_(m) = (c^m - 1)/(2m), eps_(0) = ln(c)/2,
// c = |Y|^2/|xi|^2. m = 1/2 is the engineering bond strain e/|xi| of the LPS. Written
// with expm1 so that small strains keep their digits.
HORIZON_HD inline double seth_hill_strain(double c, double m) {
  if (m == 0) return 0.5 * natural_log(c);
  if (m == 0.5) return root(c) - 1.0;
  return exp_minus_one(m * natural_log(c)) / (2.0 * m);
}

// d eps / d|Y| = c^m / |Y| = (1 + 2 m eps)/|Y| (digest sec. 13.1: lambda^(2m-1)/|xi|).
HORIZON_HD inline double seth_hill_slope(double eps, double m, double r) { return (1.0 + 2.0 * m * eps) / r; }

// d^2 eps / d|Y|^2 = (2m - 1) c^m / |Y|^2 (digest sec. 13.1).
HORIZON_HD inline double seth_hill_curvature(double eps, double m, double r) {
  return (2.0 * m - 1.0) * (1.0 + 2.0 * m * eps) / (r * r);
}

// The instantaneous bond energy (thesis eq. 6.5) per unit omega: s_inst / omega =
// lambda_bar eps theta_phi + mu_bar eps^2: the energy density dropped by cutting this one
// bond, per unit (omega V_j).
HORIZON_HD inline double instantaneous_bond_energy(double lambda_bar, double mu_bar, double eps, double theta) {
  return lambda_bar * eps * theta + mu_bar * eps * eps;
}

// phi of eq. 6.9: an intact bond acts; a broken one acts in compression only, or never
// (the Kalthoff variant).
HORIZON_HD inline bool tupek_acts(uint8_t intact, bool compression_only, double eps) {
  return intact || (compression_only && eps < 0);
}

// What the two sweeps read and write, as flat arrays (per particle unless said). Point:
// the host's Point4 (32-byte aligned), or any struct of x, y, z, w (the flat backend's
// FlatPoint over its y4 array, kernels/flat_system.hpp).
template <class Kind, class Point = Point4>
struct TupekPass {
  const Point* pt = nullptr;         // y = X + u
  const Kind* kc = nullptr;          // per bond kind
  const uint32_t* nbr = nullptr;     // per bond
  const uint32_t* kind = nullptr;    // per bond
  const uint64_t* offset = nullptr;  // row i's bonds: offset[i] .. offset[i + 1]
  uint8_t* intact = nullptr;         // per bond
  double* eps = nullptr;             // per bond: the strain of this pass (sweep 1 writes it)
  const double* m = nullptr;         // Seth-Hill parameter
  const double* lambda_bar = nullptr;
  const double* mu_bar = nullptr;
  const double* theta = nullptr;          // theta_phi of sweep 1 (sweep 2 reads both ends')
  const double* beta = nullptr;           // +inf: bonds never break
  const uint8_t* compression_only = nullptr;
  const double* failure_scale = nullptr;  // per kind: |xi|^-p of s_c (used when p != 2)
  bool exponent_two = true;               // p = 2: the criterion takes 1/|xi|^2 as written
  bool contact = false;                   // short-range contact: broken bonds' ends repel
};

// Sweep 1, row i: eps of each bond (stored) and theta_i over the acting ones (eq. 6.8).
template <class Kind, class Point>
HORIZON_HD inline double tupek_strain_row(const TupekPass<Kind, Point>& p, std::size_t i) {
  const Point pi = p.pt[i];
  const double m = p.m[i];
  const bool comp = p.compression_only[i];
  double theta = 0;
  for (uint64_t k = p.offset[i]; k < p.offset[i + 1]; ++k) {
    const Point pj = p.pt[p.nbr[k]];
    const Kind& c = p.kc[p.kind[k]];
    // (y_j - y_i)^2 and (y_i - y_j)^2 are the same bits: eps_ij == eps_ji exactly.
    const double dx = pj.x - pi.x, dy = pj.y - pi.y, dz = pj.z - pi.z;
    const double r2 = dx * dx + dy * dy + dz * dz;
    const double eps = seth_hill_strain(r2 * (c.inv_length * c.inv_length), m);
    p.eps[k] = eps;
    if (tupek_acts(p.intact[k], comp, eps)) theta += c.wv * eps;
  }
  return theta;
}

// What sweep 2 leaves of row i.
struct TupekRow {
  double f[3] = {0, 0, 0};  // the force density
  double mu_sum = 0;        // sum omega V_j eps^2 over the bonds that act and stay
  double theta_cut = 0;     // sum omega V_j eps over the bonds cut in this pass
  double lost = 0;          // their energy, sum omega V_j s_ij (eq. 6.5), per unit V_i
  double intact_w = 0;      // sum omega V_j over the intact bonds (after the pass)
  double total_w = 0;       // sum omega V_j over all bonds
  double contact_w = 0;     // the family contact's energy share
  uint64_t broken = 0;
};

// Sweep 2, row i: the pair criterion, then the force with the flags at the start of the
// pass (a bond that breaks here still carries its force in this pass).
template <class Kind, class Point>
HORIZON_HD inline TupekRow tupek_force_row(const TupekPass<Kind, Point>& p, std::size_t i) {
  TupekRow o;
  const Point pi = p.pt[i];
  const double m = p.m[i], li = p.lambda_bar[i], mi = p.mu_bar[i], ti = p.theta[i], bi = p.beta[i];
  const bool comp = p.compression_only[i];
  const double gi = li * ti;
  double fx = 0, fy = 0, fz = 0;
  for (uint64_t k = p.offset[i]; k < p.offset[i + 1]; ++k) {
    const uint32_t j = p.nbr[k];
    const Point pj = p.pt[j];
    const Kind& c = p.kc[p.kind[k]];
    const double eps = p.eps[k];
    const double Yx = pj.x - pi.x, Yy = pj.y - pi.y, Yz = pj.z - pi.z;
    const double r2 = Yx * Yx + Yy * Yy + Yz * Yz;
    o.total_w += c.wv;
    if (tupek_acts(p.intact[k], comp, eps)) {
      const double r = root(r2);
      const double lj = p.lambda_bar[j], mj = p.mu_bar[j], tj = p.theta[j];
      // (t_ij + t_ji) / (omega d eps/d|Y|), eq. 6.8.
      const double sum = (gi + 2 * mi * eps) + (lj * tj + 2 * mj * eps);
      const double a = c.wv * sum * seth_hill_slope(eps, m, r) / r;
      fx += a * Yx;
      fy += a * Yy;
      fz += a * Yz;
      bool cut = false;
      if (p.intact[k] && eps > 0) {
        const double sij = instantaneous_bond_energy(li, mi, eps, ti);
        const double sji = instantaneous_bond_energy(lj, mj, eps, tj);
        const double bij = 0.5 * (bi + p.beta[j]);  // +inf when either end may not break
        // 2 s_c / omega = 2 beta |xi|^-p (eq. 6.3 and its generalisation, p = 2 as printed).
        const double threshold =
            p.exponent_two ? 2 * bij * c.inv_length * c.inv_length : 2 * bij * p.failure_scale[p.kind[k]];
        if (sij + sji >= threshold) {
          cut = true;
          p.intact[k] = 0;
          ++o.broken;
          o.lost += c.wv * sij;  // eq. 6.5: omega V_j s_ij, per unit V_i
          o.theta_cut += c.wv * eps;
        }
      }
      if (!cut) o.mu_sum += c.wv * eps * eps;
    } else if (p.contact) {
      // A broken bond that no longer acts: its ends repel like non-family pairs
      // (state/short_range.hpp), so the crack faces do not interpenetrate.
      if (r2 < c.contact_d2 && r2 > 0) {
        const double r = root(r2), overlap = c.contact_d - r;
        const double a = -c.contact_k * overlap / r;
        fx += a * Yx;
        fy += a * Yy;
        fz += a * Yz;
        o.contact_w += 0.25 * c.contact_k * overlap * overlap;
      }
    }
    if (p.intact[k]) o.intact_w += c.wv;
  }
  o.f[0] = fx, o.f[1] = fy, o.f[2] = fz;
  return o;
}

// The row's strain energy density with the bonds cut in this pass taken out (eq. 5.1 with
// phi, eq. 6.4): lambda_bar/2 (theta - theta_cut)^2 + mu_bar sum omega V eps^2, plus contact.
HORIZON_HD inline double tupek_row_energy(const TupekRow& o, double lambda_bar, double mu_bar, double theta) {
  const double th = theta - o.theta_cut;
  return 0.5 * lambda_bar * th * th + mu_bar * o.mu_sum + o.contact_w;
}

// The stable time step of the current bond tangent stiffness (NonlinearSolid::
// stable_time_step, digest sec. 13.1): min_i sqrt(2 rho_i / K_i), two sweeps over the rows.
// |Y| of a bond from its strain: c^m = 1 + 2 m eps, |Y| = |xi| c^(1/2) (|xi| e^eps for m = 0).
HORIZON_HD inline double tupek_bond_length(double length, double m, double eps) {
  if (m == 0) return length * natural_exp(eps);
  const double cm = 1 + 2 * m * eps;
  return length * power(cm < 1e-300 ? 1e-300 : cm, 0.5 / m);  // std::max(cm, 1e-300)
}

// Sweep 1, row i: S_i = sum omega V_j |d eps/d|Y|| over the acting bonds (the dilatation
// coupling of the row, bounded Gershgorin-wise). `eps` null: every strain 0 (before the
// first force pass). The Kind needs `length` too.
template <class Kind, class Point>
HORIZON_HD inline double tupek_coupling_row(const TupekPass<Kind, Point>& p, std::size_t i) {
  const double m = p.m[i];
  const bool comp = p.compression_only[i];
  double sum = 0;
  for (uint64_t k = p.offset[i]; k < p.offset[i + 1]; ++k) {
    const Kind& c = p.kc[p.kind[k]];
    const double eps = p.eps ? p.eps[k] : 0.0;
    if (!tupek_acts(p.intact[k], comp, eps)) continue;
    const double Y = tupek_bond_length(c.length, m, eps);
    sum += c.wv * magnitude(seth_hill_slope(eps, m, Y));
  }
  return sum;
}

// Sweep 2, row i: K_i = k_contact,i + sum omega V_j (|(lambda_bar_i theta_i + 2 mu_bar_i eps)
// eps''| + 2 mu_bar_i eps'^2 + the same of j + |lambda_bar_i| |eps'| S_i + |lambda_bar_j|
// |eps'| S_j); the row's stable step sqrt(2 rho_i / K_i), or +inf when K_i is 0.
template <class Kind, class Point>
HORIZON_HD inline double tupek_stable_row(const TupekPass<Kind, Point>& p, const double* S, double contact_stiffness,
                                          double density, std::size_t i) {
  const double m = p.m[i], li = p.lambda_bar[i], mi = p.mu_bar[i], ti = p.theta[i];
  const bool comp = p.compression_only[i];
  double K = contact_stiffness;
  for (uint64_t k = p.offset[i]; k < p.offset[i + 1]; ++k) {
    const uint32_t j = p.nbr[k];
    const Kind& c = p.kc[p.kind[k]];
    const double eps = p.eps ? p.eps[k] : 0.0;
    if (!tupek_acts(p.intact[k], comp, eps)) continue;
    const double Y = tupek_bond_length(c.length, m, eps);
    const double d1 = seth_hill_slope(eps, m, Y), d2 = seth_hill_curvature(eps, m, Y);
    const double lj = p.lambda_bar[j], mj = p.mu_bar[j], tj = p.theta[j];
    K += c.wv * (magnitude((li * ti + 2 * mi * eps) * d2) + 2 * mi * d1 * d1 + magnitude((lj * tj + 2 * mj * eps) * d2) +
                 2 * mj * d1 * d1 + magnitude(li) * magnitude(d1) * S[i] + magnitude(lj) * magnitude(d1) * S[j]);
  }
  return K > 0 ? root(2 * density / K) : INFINITY;
}

}  // namespace horizon::kernels
