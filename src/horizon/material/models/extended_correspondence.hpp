#pragma once
// Tupek's extended constitutive correspondence (thesis ch. 4, eq. 4.2-4.7; seed 000
// digest sec. 3.2-3.4) with the modified Johnson-Cook viscoplasticity and damage of
// thesis ch. 7 (digest sec. 6) and the damage-dependent influence function (eq. 7.1-7.2).
// docs/models/extended_correspondence.md has the equations, keys and verification.
//
// Per particle i, over its acting bonds j (xi = x_j - x_i, Y = y_j - y_i):
//   c_j = |Y|^2/|xi|^2,  eps_j = (c^m - 1)/(2m)  (eps = ln(c)/2 for m = 0)     (4.2)
//   H_j = 5/2 n (x) n - 1/2 I  (3-D),  2 n (x) n - 1/2 I_2 (2-D plane strain),  n = xi/|xi|  (4.4)
//   E_i = M_i^-1 sum_j w_j eps_j H_j,  w_j = omega_j V_j                        (4.3) (*)
//   sigma_i = the law at E_i (classical/strain_laws.hpp), conjugate to E_(m)
//   T_ij = omega_j [sigma_i : Ht_j + 2 k_s (r_j - R_i : Ht_j)] c_j^(m-1) Y/|xi|^2  (4.7) (**)
// with Ht_j = M_i^-1 H_j. The force is parallel to Y: the model is ordinary and keeps
// angular momentum (thesis sec. 4.3).
//
// (*) The moment map M_i (a linear map of symmetric tensors, 6 x 6 in 3-D) is
//   M_i(e) = sum_j w_j (n_j . e n_j) H_j.
// For the continuum bulk with int omega = 3 it is the identity (thesis: the moments
// J_11 = 1/2, I_1111 = 3/2, I_1122 = 1/2 make E = eps exact for uniform small strain),
// and (*) is then Tupek's (4.3). On a particle family (a lattice at delta = 3 h, a free
// surface, a damaged family) the discrete moments are not isotropic; dividing by M_i makes
// E_i = eps exactly for every uniform small strain at every particle, the way K^-1 makes
// the classical F exact for every affine map. It keeps the finite-strain dilatation
// property (m = 0, F = J^(1/3) R: eps_j = ln(J)/3 for every bond, so E = M^-1 (ln J/3)
// sum w H = ln(J)/3 I since M(I) = sum w H). Departure from the thesis, which does not
// renormalise near surfaces (sec. 6.1.3): documented in the model page.
//
// (**) The second term is a bond-level stabilisation (not in the thesis): the energy
//   W_s = k_s sum_j w_j r_j^2,   r_j = eps_j - n_j . E_i n_j,
// penalises the part of the bond strains that E_i cannot see (a zero-energy mode of E,
// e.g. the 3-D checkerboard, leaves E at O(a^2) while bonds strain at O(a)). r_j = 0 for
// every uniform small strain (E_i = eps exactly by (*)), so the stabilisation leaves the
// small-strain moduli alone. Its exact Frechet derivative is (**) with R_i =
// sum_j w_j r_j n_j (x) n_j, so W + W_s stays an energy and T stays parallel to Y.
// k_s = G_s mu_bar d / sum_j omega_j V_j (reference family), mu_bar = 5/2 mu (3-D), 2 mu
// (2-D) (digest sec. 13.2: the bond-based modulus of the nonlinear solid); G_s is the
// deck's `stabilization`. At finite strain r_j is not zero for a homogeneous shear (the
// log of a mean is not the mean of the logs): r ~ 0.4 at a compressive log strain of 1,
// so G_s must stay small (<= 1e-3) under large plastic flow.
//
// Damage-dependent influence (thesis eq. 7.1-7.2): omega_j = omega_xi(|xi|) omega_D(D_i,
// D_j), omega_D = 0 if D_i > D_c or D_j > D_c, else 1 (D the Johnson-Cook damage). A
// particle with D > D_c, or whose shape tensor K_i = sum w xi (x) xi is ill-conditioned
// (material/nonlocal_gradient.hpp; the digest's guard "treat as fully failed"), carries no
// stress and meets its neighbours through contact only.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "horizon/core/vec3.hpp"
#include "horizon/kernels/extended.hpp"
#include "horizon/kernels/extended_law.hpp"
#include "horizon/kernels/strain_laws.hpp"
#include "horizon/material/classical/strain_laws.hpp"
#include "horizon/material/model.hpp"
#include "horizon/material/models/nonlinear_solid.hpp"

namespace horizon {

ModelEntry extended_correspondence_model();

namespace extended {

// The pair form's bond sweeps in the fast loops' eight lanes where the machine has AVX-512
// (on by default); off: bond by bond, as machines without AVX-512 run them. Tests compare
// the two (tests/verification/test_general_pass.cpp). Not thread-safe: set between runs.
void set_pair_lanes(bool on);
bool pair_lanes();

using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Mat3 = Eigen::Matrix3d;

// Symmetric tensors as 6-vectors (11, 22, 33, 23, 13, 12); A : B = sum_k w_k a_k b_k with
// w = (1, 1, 1, 2, 2, 2).
inline Vec6 to_vec6(const Mat3& A) { return (Vec6() << A(0, 0), A(1, 1), A(2, 2), A(1, 2), A(0, 2), A(0, 1)).finished(); }
inline Mat3 to_mat3(const Vec6& a) {
  Mat3 A;
  A << a[0], a[5], a[4], a[5], a[1], a[3], a[4], a[3], a[2];
  return A;
}
inline Vec6 contraction_weights() { return (Vec6() << 1, 1, 1, 2, 2, 2).finished(); }

// H<xi> of (4.4) as a 6-vector: 3-D 5/2 n n - 1/2 I; 2-D (digest sec. 3.3, derived)
// 2 n n - 1/2 I_2 (no out-of-plane part).
inline Vec6 shape_state(const Vec3& xi, int dimension) {
  const double L2 = dot(xi, xi);
  const double a = dimension == 3 ? 2.5 : 2.0;
  Vec6 h;
  h << a * xi.x * xi.x / L2 - 0.5, a * xi.y * xi.y / L2 - 0.5, dimension == 3 ? a * xi.z * xi.z / L2 - 0.5 : 0.0,
      a * xi.y * xi.z / L2, a * xi.x * xi.z / L2, a * xi.x * xi.y / L2;
  return h;
}

// p with p . e = n . e n (the bond's normal strain of a tensor e).
inline Vec6 normal_projector(const Vec3& xi) {
  const double L2 = dot(xi, xi);
  Vec6 p;
  p << xi.x * xi.x / L2, xi.y * xi.y / L2, xi.z * xi.z / L2, 2 * xi.y * xi.z / L2, 2 * xi.x * xi.z / L2,
      2 * xi.x * xi.y / L2;
  return p;
}

// n n as a 6-vector (tensor components).
inline Vec6 normal_dyad(const Vec3& xi) {
  const double L2 = dot(xi, xi);
  Vec6 p;
  p << xi.x * xi.x / L2, xi.y * xi.y / L2, xi.z * xi.z / L2, xi.y * xi.z / L2, xi.x * xi.z / L2, xi.x * xi.y / L2;
  return p;
}

// The pair pass's bond geometry (issue 31 scope 2), from the unit vector n = xi/|xi| taken
// with the kind's 1/|xi| (a multiplication where shape_state and normal_projector divide
// by |xi|^2 six times): H<xi> of (4.4) and the normal projector p (p . e = n . e n), equal
// to those to round-off. Both are even in n: a bond and its reverse get the same bits.
// (Device-portable kernels: kernels/extended.hpp.)
inline Vec6 unit_shape_state(const Vec3& n, int dimension) {
  const double v[3] = {n.x, n.y, n.z};
  Vec6 h;
  kernels::unit_shape_state(v, dimension, h.data());
  return h;
}
inline Vec6 unit_normal_projector(const Vec3& n) {
  const double v[3] = {n.x, n.y, n.z};
  Vec6 p;
  kernels::unit_normal_projector(v, p.data());
  return p;
}
// The Seth-Hill strain of (4.2) in the pair pass: for m = 1 (the hencky measure's Green
// bond strain) (c - 1)/2, exact in c (Sterbenz: c - 1 is exact for c in [1/2, 2]), where
// seth_hill_strain's expm1(ln c)/2 rounds twice and costs a logarithm and an exponential
// per bond; the last bits differ from it.
using kernels::pair_strain;  // kernels/extended.hpp

// d eps_(m) / d Y = c^(m-1) Y / |xi|^2 (digest sec. 3.2), as the scalar factor of Y.
inline double strain_gradient_factor(double c, double m, double xi2) {
  return (m == 0.0 ? 1.0 / c : m == 1.0 ? 1.0 : std::pow(c, m - 1.0)) / xi2;
}

// The moment map M_i of (*) and its factorisation: it depends on the reference bonds and
// the acting set only, so a particle keeps it until its acting set changes. The algebra is
// the device-portable kernels of kernels/extended_law.hpp (Eigen's outer products, its
// FullPivLU and the products with M^-1 written out in Eigen's order: the same bits,
// tests/unit/test_extended_law_kernels.cpp) over the Eigen matrices' column-major storage.
class MomentMap {
 public:
  void reset(int dimension) { kernels::moment_map_reset(M_.data(), dimension); }
  void add(const Vec3& xi, double w, int dimension) {
    const double x[3] = {xi.x, xi.y, xi.z};
    kernels::moment_map_add(M_.data(), x, w, dimension);
  }
  // False when M is singular (Eigen's FullPivLU rank test) or M^-1 is not finite.
  bool finish() { return kernels::moment_map_inverse(M_.data(), inverse_.data()); }
  Vec6 solve(const Vec6& b) const {
    Vec6 e;
    kernels::moment_solve(inverse_.data(), b.data(), e.data());
    return e;
  }
  // The vector a with t : Ht_j = a . h_j for a tensor t (a = M^-T W t).
  Vec6 dual(const Mat3& t) const {
    double r[9];
    for (int k = 0; k < 9; ++k) r[k] = t(k / 3, k % 3);
    Vec6 a;
    kernels::moment_dual(inverse_.data(), r, a.data());
    return a;
  }
  // dual of a tensor given as its weighted 6-vector w .* to_vec6(t) (a sum of normal
  // projectors p: the pair pass's stabilisation, R = sum c n (x) n, is sum c p so).
  Vec6 dual_weighted(const Vec6& wt) const {
    Vec6 a;
    kernels::moment_dual_weighted(inverse_.data(), wt.data(), a.data());
    return a;
  }
  const double* inverse() const { return inverse_.data(); }
  // The column-major storage of M and M^-1 (kernels/extended_law.hpp moment_map_row).
  double* matrix_data() { return M_.data(); }
  double* inverse_data() { return inverse_.data(); }

 private:
  Mat6 M_ = Mat6::Zero();
  Mat6 inverse_ = Mat6::Zero();
};

// One particle's evaluation on its acting bonds: sweep 1 adds every bond (add), finish()
// gives E; the force needs E, and the stabilisation needs R of all bonds, before any force.
class NonlocalStrain {
 public:
  NonlocalStrain(int dimension, double m) : dim_(dimension), m_(m) { map_.reset(dimension); }
  // Sweep 1 with the moment map built here (tests, and a particle whose map is rebuilt).
  double add(const Vec3& xi, const Vec3& Y, double w) {
    map_.add(xi, w, dim_);
    return add_strain(xi, Y, w);
  }
  // Sweep 1 with a kept moment map (use()).
  double add_strain(const Vec3& xi, const Vec3& Y, double w) {
    const double x[3] = {xi.x, xi.y, xi.z}, y[3] = {Y.x, Y.y, Y.z};
    return kernels::vector_strain_add(S_.data(), x, y, w, m_, dim_);  // (kernels/extended_law.hpp)
  }
  void use(const MomentMap& map) { map_ = map; }
  const MomentMap& map() const { return map_; }
  // E = M^-1 S; false when M is singular.
  bool finish(bool factorise = true) {
    if (factorise && !map_.finish()) return false;
    E_ = map_.solve(S_);
    return E_.allFinite();
  }
  // E of an earlier finish() over the same bonds and map (the force pass's sweep 1).
  void set_strain(const Vec6& e) { E_ = e; }
  Mat3 strain() const { return to_mat3(E_); }
  const Vec6& strain_vector() const { return E_; }
  Vec6 dual(const Mat3& sigma) const { return map_.dual(sigma); }
  // r_j = eps_j - n . E n.
  double residual(const Vec3& xi, double eps) const {
    const double x[3] = {xi.x, xi.y, xi.z};
    double p[6];
    kernels::normal_projector_of(x, p);
    return eps - kernels::dot6(p, E_.data());
  }

 private:
  int dim_;
  double m_;
  MomentMap map_;
  Vec6 S_ = Vec6::Zero();
  Vec6 E_ = Vec6::Zero();
};

// The force state (**) of one bond: a = dual(sigma), b = dual(R), ks the stabilisation
// modulus, omega the (damage-dependent) influence weight.
// (kernels/extended_law.hpp vector_bond_force: the former Eigen form's bits.)
inline Vec3 bond_force_state(const Vec6& a, const Vec6& b, double ks, double omega, double m, int dimension,
                             const Vec3& xi, const Vec3& Y, double r) {
  const double x[3] = {xi.x, xi.y, xi.z}, y[3] = {Y.x, Y.y, Y.z};
  double T[3];
  kernels::vector_bond_force(a.data(), b.data(), ks, omega, m, dimension, x, y, r, T);
  return {T[0], T[1], T[2]};
}

// The `hencky` strain measure (not in the thesis; departure documented in the model page).
// Tupek's E_(m) of (4.3) averages the bond strains; for m != 1 the average of a nonlinear
// function of the bond stretch is not that function of the deformation (Jensen): an
// isochoric homogeneous compression to a stretch of 1/2 gives tr E_(0) = 0.37 instead of
// 0 (docs/models/extended_correspondence.md), so under large plastic flow the bulk term
// kappa tr E prescribes a spurious pressure and the body collapses in volume (the first
// Taylor bar). With m = 1 the bond strain (c - 1)/2 is linear in C, so E_(1) = M^-1 sum w
// eps H is the Green-Lagrange strain (C - I)/2 exactly for every homogeneous deformation
// at any finite strain. The measure takes the logarithm of C = I + 2 E_(1):
//   E_log = 1/2 ln C = sum_a 1/2 ln(l_a) N_a (x) N_a        (C = sum l_a N_a (x) N_a),
// the material Hencky strain (Miehe, Apel and Lambrecht 2002, CMAME 191, 5383, eq. 2.5),
// the law runs on E_log, and the stress conjugate to E_(1) (the force of (4.7) with m = 1)
// is S = (d E_log / d E_(1))^T : T, T the law's stress, by the Daleckii-Krein formula for
// the derivative of an isotropic tensor function (Miehe et al. 2002, eq. 2.8):
//   S = sum_ab theta_ab (N_a . T N_b) N_a (x) N_b,
//   theta_aa = 1/l_a,  theta_ab = (ln l_a - ln l_b)/(l_a - l_b).
// Eigenvalues below `floor` (a locally inverted average) are clamped to it.
// The strain law's constants as the portable kernel takes them (kernels/strain_laws.hpp).
inline kernels::StrainLawConstants strain_law_constants(const classical::StrainLawParams& p) {
  kernels::StrainLawConstants k;
  k.law = p.law == classical::StrainLaw::j2             ? kernels::kStrainJ2
          : p.law == classical::StrainLaw::johnson_cook ? kernels::kStrainJohnsonCook
                                                        : kernels::kStrainElastic;
  k.kappa = p.kappa, k.mu = p.mu, k.yield_stress = p.yield_stress, k.hardening = p.hardening_modulus;
  k.sigma0 = p.sigma0, k.B = p.B, k.n = p.n, k.C = p.C, k.rate0 = p.rate0;
  k.d1 = p.d1, k.d2 = p.d2, k.d3 = p.d3, k.d4 = p.d4, k.damage_rate0 = p.damage_rate0, k.damage = p.damage;
  return k;
}

struct HenckyMap {
  Mat3 N;        // eigenvectors of C (columns)
  double l[3];   // eigenvalues (clamped)
  Mat3 strain;   // E_log
};

// The model's law step computes this map with the portable kernels of kernels/hencky.hpp
// (hencky_of_green3, green_stress_of_hencky3: the same bits, tests/unit/test_hencky_kernels.cpp);
// the Eigen forms below are the reference those are held to.
inline constexpr double kHenckyFloor = 1e-6;
inline HenckyMap hencky_of_green(const Mat3& E1, double floor = kHenckyFloor) {
  const Mat3 C = Mat3::Identity() + 2.0 * E1;
  const Eigen::SelfAdjointEigenSolver<Mat3> eig(0.5 * (C + C.transpose()));
  HenckyMap h;
  h.N = eig.eigenvectors();
  Mat3 Lg = Mat3::Zero();
  for (int a = 0; a < 3; ++a) {
    h.l[a] = std::max(eig.eigenvalues()[a], floor);
    Lg(a, a) = 0.5 * std::log(h.l[a]);
  }
  h.strain = h.N * Lg * h.N.transpose();
  return h;
}

// (ln a - ln b)/(a - b), stable as b -> a (series in x = (a - b)/(a + b)).
inline double log_divided_difference(double a, double b) {
  const double x = (a - b) / (a + b);
  if (std::abs(x) < 1e-4) return 2.0 / (a + b) * (1.0 + x * x / 3.0 + x * x * x * x / 5.0);
  return (std::log(a) - std::log(b)) / (a - b);
}

inline Mat3 green_stress_of_hencky(const HenckyMap& h, const Mat3& T) {
  const Mat3 Tt = h.N.transpose() * T * h.N;
  Mat3 S;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) S(a, b) = (a == b ? 1.0 / h.l[a] : log_divided_difference(h.l[a], h.l[b])) * Tt(a, b);
  return h.N * S * h.N.transpose();
}

}  // namespace extended
}  // namespace horizon
