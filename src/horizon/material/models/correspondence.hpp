#pragma once
// The correspondence material model (Silling et al. 2007, sec. 18; seed 003 digest sec.
// 7.6 and 9) with classical stress laws and zero-energy-mode control. docs/models/
// correspondence.md has the equations, the deck keys and the verification.
//
// Per particle i, over its acting bonds j (seed 003 eq. 17, 134, 142):
//   K_i = sum_j omega V_j xi (x) xi,   F_i = (sum_j omega V_j Y (x) xi) K_i^-1,
//   P_i = the first Piola-Kirchhoff stress of the classical law at F_i (classical/
//         stress_laws.hpp: linear_elastic, neo_hookean, j2),
//   T_ij = omega P_i K_i^-1 xi  +  G omega (Y_ij - F_i xi)                          (*)
// and the force density f_i = sum_j (T_ij - T_ji) V_j (seed 003 eq. 33, digest sec. 9),
// summed by the general force pass (solver/forces_general.hpp).
//
// The second term of (*) is the stabilisation of Silling 2017 ("Stability of peridynamic
// correspondence material models and their particle discretizations", CMAME 322, 42-57):
// a penalty on the nonuniform part z = Y - F xi of the deformation state, which F cannot
// see (sum_j omega V_j z (x) xi = 0 by the definition of F), acting like a bond-based
// spring on z. It is the Frechet derivative of W_s = (G/2) sum_j omega V_j |z|^2 (exactly:
// the term from the dependence of F on Y vanishes because sum omega V z (x) xi = 0), so an
// elastic law stays elastic, and it keeps angular momentum (sum_j Y x z omega V_j is the
// axial vector of F K F^T - F K F^T = 0). The modulus is G = G_s c / delta, with c the
// micromodulus of the bond-based material of the same bulk modulus (18 k/(pi delta^4) in
// 3-D; material/constants.hpp equivalent_micromodulus with omega = 1) and G_s the deck's
// `stabilization` (0: off). Dividing by delta makes T [N/m^6] with a dimensionless
// omega; with omega = 1 a bond of length delta then carries G_s times the bond-based force
// c s of the same non-affine stretch s = |z|/delta. The paper's abstract states the idea
// ("a term is added to the correspondence strain energy density that resists deviations
// from a uniform deformation ... leaving the stress tensor unchanged"); its normalisation
// of G could not be checked against its text here, so this one is stated and tested on
// its own (docs/models/correspondence.md).
//
// A particle whose shape tensor is singular or ill-conditioned (reciprocal condition
// number under `shape_tolerance`, material/nonlocal_gradient.hpp) writes T = 0 on all its
// bonds: it carries no stress and meets its neighbours by contact only (seed 000 digest
// sec. 6.1). A particle whose F has det F <= 0 (inverted) carries no stress either, but
// keeps the stabilisation, which pushes it back.
#include <Eigen/Dense>
#include <cmath>

#include "horizon/core/vec3.hpp"
#include "horizon/deck/config.hpp"
#include "horizon/kernels/hypoelastic.hpp"
#include "horizon/kernels/plane_stress.hpp"
#include "horizon/material/classical/hypoelastic.hpp"
#include "horizon/material/classical/stress_laws.hpp"
#include "horizon/material/model.hpp"

namespace horizon {

ModelEntry correspondence_model();

namespace correspondence {

using Mat3 = Eigen::Matrix3d;

// hypoelastic, hypoelastic_j2, viscoplastic_needleman: Peridigm's rate form
// (classical/hypoelastic.hpp).
enum class StressLaw { linear_elastic, neo_hookean, j2, hypoelastic, hypoelastic_j2, viscoplastic_needleman };

inline bool rate_form(StressLaw l) {
  return l == StressLaw::hypoelastic || l == StressLaw::hypoelastic_j2 || l == StressLaw::viscoplastic_needleman;
}

// The zero-energy-mode control: Silling 2017's (*) above, or Peridigm's hourglass force
// (peridigm_hourglass below).
enum class Stabilization { silling, peridigm };

// Peridigm's yield-stress flaw (Isotropic Hardening Correspondence's Enable Flaw):
// sigma_y(x) = sigma_y (1 - m exp(-|x - x_f|^2 / s^2)), the form fitted from the gold of
// IsotropicHardeningPlasticFullyPrescribedTension_WithFlaw (m = 0.2, s = 0.751: the yield
// stresses inverted from its Von_Mises_Stress and Equivalent_Plastic_Strain agree with it
// to 5e-4 of sigma_y at every particle, against 3e-2 for exp(-r/s) or exp(-r^2/(2 s^2))).
struct Flaw {
  bool on = false;
  Vec3 centre{};
  double size = 1, magnitude = 0;
  double factor(const Vec3& x) const {
    if (!on) return 1.0;
    const Vec3 r = x - centre;
    return 1.0 - magnitude * std::exp(-(r.x * r.x + r.y * r.y + r.z * r.z) / (size * size));
  }
};

struct LawSettings {
  StressLaw law = StressLaw::linear_elastic;
  classical::Elastic elastic;
  classical::J2Params j2;
  int dimension = 3;
  PlaneMode plane = PlaneMode::none;  // 2-D: stress or strain
  // hypoelastic_j2: the plastic_return (work or peridigm); viscoplastic_needleman: needleman.
  classical::PlasticReturn plastic_return = classical::PlasticReturn::work;
  classical::Needleman needleman;  // viscoplastic_needleman
  classical::RotationUpdate rotation = classical::RotationUpdate::cayley;  // the rate form's R increment
};

// The settings every model of the correspondence family reads from its deck the same way
// (correspondence, bond_associated_correspondence): the stress law by name, its elastic
// and J2 constants, the dimension and plane mode, the rate form's rotation update. The
// plastic return and Needleman's constants are correspondence's alone.
inline LawSettings law_settings(const MaterialConfig& mat, int dimension, PlaneMode plane) {
  LawSettings s;
  const std::string& law = Model::choice(mat, "stress_law");
  s.law = law == "neo_hookean"              ? StressLaw::neo_hookean
          : law == "j2"                     ? StressLaw::j2
          : law == "hypoelastic"            ? StressLaw::hypoelastic
          : law == "hypoelastic_j2"         ? StressLaw::hypoelastic_j2
          : law == "viscoplastic_needleman" ? StressLaw::viscoplastic_needleman
                                            : StressLaw::linear_elastic;
  s.elastic = classical::elastic_from_bulk_shear(mat.bulk_modulus, mat.shear_modulus);
  s.j2 = {Model::parameter(mat, "yield_stress"), Model::parameter(mat, "hardening_modulus")};
  s.dimension = dimension;
  s.plane = plane;
  s.rotation = Model::choice(mat, "rotation_update") == "peridigm" ? classical::RotationUpdate::peridigm
                                                                   : classical::RotationUpdate::cayley;
  return s;
}

// Per-particle history (the trial copy is written by the force pass, the committed one
// read; Model::commit swaps them).
struct History {
  classical::J2State plastic;
  classical::HypoState hypo;  // hypoelastic laws
  double lambda3 = 1;  // plane stress: the out-of-plane stretch of the last evaluation
};

// The total-form laws' constants and J2 history as the portable kernels take them
// (kernels/laws.hpp; row-major copies of the Eigen history).
inline kernels::LawConstants law_constants(const LawSettings& s) {
  kernels::LawConstants c;
  c.law = s.law == StressLaw::j2            ? kernels::kJ2Law
          : s.law == StressLaw::neo_hookean ? kernels::kNeoHookeanLaw
                                            : kernels::kLinearElasticLaw;
  c.lambda = s.elastic.lambda, c.mu = s.elastic.mu, c.kappa = s.elastic.kappa;
  c.yield_stress = s.j2.yield_stress, c.hardening = s.j2.hardening_modulus;
  return c;
}
inline kernels::J2History j2_history(const classical::J2State& h) {
  kernels::J2History k;
  for (int c = 0; c < 9; ++c) k.plastic_strain[c] = h.plastic_strain(c / 3, c % 3);
  k.alpha = h.alpha;
  return k;
}
inline void set_j2_state(classical::J2State& h, const kernels::J2History& k) {
  for (int c = 0; c < 9; ++c) h.plastic_strain(c / 3, c % 3) = k.plastic_strain[c];
  h.alpha = k.alpha;
}

// A total-form law (linear_elastic, neo_hookean, j2) at F from the committed history with
// the thermal strain eps (0: none): the device-portable kernels/plane_stress.hpp law_point
// (the law, plane stress's secant iteration in 2-D, the thermal split), over row-major
// copies. trial = committed but for J2's E_p, alpha and plane stress's lambda3.
inline classical::LawResult total_form_law(const LawSettings& s, const kernels::LawConstants& c, const Mat3& F,
                                           double eps, const History& committed, History& trial,
                                           double& plastic_work) {
  trial = committed;
  double f[9];
  for (int k = 0; k < 9; ++k) f[k] = F(k / 3, k % 3);
  const bool j2 = c.law == kernels::kJ2Law;
  const kernels::J2History kc = j2 ? j2_history(committed.plastic) : kernels::J2History{};
  kernels::J2History kt;
  kernels::LawStress r;
  double l3 = committed.lambda3;
  kernels::law_point(c, s.dimension, s.dimension == 2 && s.plane == PlaneMode::stress, eps, kc, f, l3, kt,
                     plastic_work, r);
  trial.lambda3 = l3;
  if (j2) set_j2_state(trial.plastic, kt);
  classical::LawResult out;
  for (int k = 0; k < 9; ++k) out.P(k / 3, k % 3) = r.P[k], out.sigma(k / 3, k % 3) = r.sigma[k];
  out.W = r.W;
  out.ok = r.ok;
  return out;
}

// The rate-form laws' constants and history as kernels/hypoelastic.hpp takes them.
inline kernels::HypoConstants hypo_constants(const LawSettings& s) {
  kernels::HypoConstants c;
  c.lambda = s.elastic.lambda, c.mu = s.elastic.mu, c.kappa = s.elastic.kappa;
  c.hardening = s.j2.hardening_modulus;
  c.plastic_return = s.plastic_return == classical::PlasticReturn::peridigm    ? kernels::kReturnPeridigm
                     : s.plastic_return == classical::PlasticReturn::needleman ? kernels::kReturnNeedleman
                                                                               : kernels::kReturnWork;
  c.rotation = s.rotation == classical::RotationUpdate::peridigm ? kernels::kRotationPeridigm : kernels::kRotationCayley;
  c.N = s.needleman.N, c.m = s.needleman.m, c.rate0 = s.needleman.rate0, c.eps0 = s.needleman.eps0;
  c.eps1 = s.needleman.eps1;
  return c;
}
inline kernels::HypoHistory hypo_history(const classical::HypoState& h) {
  kernels::HypoHistory k;
  for (int c = 0; c < 9; ++c) {
    const int a = c / 3, b = c % 3;
    k.F[c] = h.F(a, b), k.V[c] = h.V(a, b), k.R[c] = h.R(a, b), k.sigma_u[c] = h.sigma_u(a, b);
  }
  k.alpha = h.alpha, k.thermal = h.thermal;
  return k;
}
inline void set_hypo_state(classical::HypoState& h, const kernels::HypoHistory& k) {
  for (int c = 0; c < 9; ++c) {
    const int a = c / 3, b = c % 3;
    h.F(a, b) = k.F[c], h.V(a, b) = k.V[c], h.R(a, b) = k.R[c], h.sigma_u(a, b) = k.sigma_u[c];
  }
  h.alpha = k.alpha, h.thermal = k.thermal;
}

// A rate-form law (hypoelastic, hypoelastic_j2, viscoplastic_needleman) over dt from the
// committed history: the device-portable kernels/hypoelastic.hpp hypo_step (the same bits
// as classical::hypoelastic_step, tests/unit/test_law_kernels.cpp) over row-major copies.
inline classical::LawResult rate_form_law(const LawSettings& s, const Mat3& F, const History& committed,
                                          History& trial, double& plastic_work, double dt, double yield_factor,
                                          Mat3* rate, const Mat3* Fdot, double thermal) {
  trial = committed;
  const double yield = s.law != StressLaw::hypoelastic ? s.j2.yield_stress * yield_factor : 0.0;
  double f[9], fd[9], d[9];
  for (int k = 0; k < 9; ++k) f[k] = F(k / 3, k % 3), fd[k] = Fdot ? (*Fdot)(k / 3, k % 3) : 0.0;
  kernels::HypoHistory t;
  kernels::LawStress r;
  kernels::hypo_step(hypo_constants(s), yield, hypo_history(committed.hypo), f, dt, Fdot ? fd : nullptr, thermal, t,
                     plastic_work, r, d);
  set_hypo_state(trial.hypo, t);
  trial.plastic.alpha = t.alpha;
  classical::LawResult out;
  for (int k = 0; k < 9; ++k) {
    const int a = k / 3, b = k % 3;
    out.P(a, b) = r.P[k], out.sigma(a, b) = r.sigma[k];
    if (rate) (*rate)(a, b) = d[k];
  }
  out.W = r.W;
  out.ok = r.ok;
  return out;
}

// The classical law at F (from NonlocalGradient::finish: F(2,2) = 1 in 2-D) from the
// committed history; the trial history and the plastic work of the step come back.
// The hypoelastic laws integrate over dt (the time since the committed state) with the
// yield stress scaled by yield_factor (the flaw); `rate` receives their unrotated rate of
// deformation.
// `thermal`: the rate-form laws' thermal strain now (the total-form laws take it by
// splitting F: evaluate_with_expansion in correspondence.cpp).
inline classical::LawResult evaluate_law(const LawSettings& s, const Mat3& F, const History& committed,
                                         History& trial, double& plastic_work, double dt = 0,
                                         double yield_factor = 1, Mat3* rate = nullptr,
                                         const Mat3* Fdot = nullptr, double thermal = 0) {
  trial = committed;
  plastic_work = 0;
  if (rate_form(s.law)) return rate_form_law(s, F, committed, trial, plastic_work, dt, yield_factor, rate, Fdot, thermal);
  return total_form_law(s, law_constants(s), F, 0.0, committed, trial, plastic_work);
}

inline Eigen::Vector3d to_eigen(const Vec3& a) { return {a.x, a.y, a.z}; }
inline Vec3 to_vec3(const Eigen::Vector3d& a) { return {a[0], a[1], a[2]}; }

// The stabilisation modulus G = G_s c / delta of (*).
inline double stabilization_modulus(double coefficient, double micromodulus, double horizon) {
  return coefficient * micromodulus / horizon;
}

// T_ij of (*): A = P K^-1 (zero for a particle that carries no stress), F the nonlocal
// deformation gradient, G the stabilisation modulus.
inline Vec3 bond_force_state(const Mat3& A, const Mat3& F, double G, double omega, const Vec3& xi, const Vec3& Y) {
  const Eigen::Vector3d x = to_eigen(xi);
  const Eigen::Vector3d t = omega * (A * x + G * (to_eigen(Y) - F * x));
  return to_vec3(t);
}

// The stabilisation energy of one bond, (G/2) omega V_j |Y - F xi|^2 [J/m^3].
inline double bond_stabilization_energy(const Mat3& F, double G, double omega_volume, const Vec3& xi, const Vec3& Y) {
  const Eigen::Vector3d z = to_eigen(Y) - F * to_eigen(xi);
  return 0.5 * G * omega_volume * z.squaredNorm();
}

// Peridigm's hourglass force: a bond-based spring on the part of the bond's deformation
// that F does not reproduce, projected on the deformed bond,
//   T_hg = -C_hg c omega ((F xi - Y) . Y) Y / (|xi| |Y|)
//        = -C_hg c omega ((F xi - Y) . n) (|Y|/|xi|) n,   n = Y/|Y|,   c = 18 k/(pi delta^4),
// with C_hg the deck's Hourglass Coefficient and c the bond-based micromodulus of the
// same bulk modulus (`micromodulus` below). The form follows Littlewood 2011 ("A nonlocal
// approach to modeling crack nucleation in AA 7075-T651", ASME IMECE2011-64236: the
// hourglass vector F xi - Y projected on the deformed bond, scaled by the bond-based
// micromodulus); its exact scale is FITTED from Peridigm's gold
// PredictorFromPreviousSolverQSTrue_gold.e at t = 1 (docs/peridigm.md, "Peridigm's
// hourglass force"): with the gold's own displacements, F, K^-1 and Cauchy stress, the
// force density the gold writes minus the stress part sum (T_ij - T_ji) V_j, T = omega
// P K^-1 xi, P = J sigma F^-T, is this force with C_hg = 0.02000000 (the deck's) to a
// relative misfit of 4e-12, while the "stretch" form (z . n)/|xi| n misses by 9e-2 (best
// factor 0.19) and (z . n) n without |Y|/|xi| by 4e-5. Note the magnitude is c times a
// length (z . n |Y|/|xi|), not a stretch: the force depends on the length unit, as in
// Peridigm. omega is the bond's influence (1 in every suite deck: only omega = 1 is
// checked against a gold). Zero for a homogeneous deformation (Y = F xi on every bond).
inline Vec3 peridigm_hourglass(const Mat3& F, double Cc, double omega, const Vec3& xi, const Vec3& Y) {
  const double y = std::sqrt(Y.x * Y.x + Y.y * Y.y + Y.z * Y.z);
  const double x = std::sqrt(xi.x * xi.x + xi.y * xi.y + xi.z * xi.z);
  if (!(y > 0) || !(x > 0) || Cc == 0) return {};
  const Eigen::Vector3d Ye = to_eigen(Y);
  const Eigen::Vector3d z = F * to_eigen(xi) - Ye;
  return to_vec3((-Cc * omega * z.dot(Ye) / (x * y)) * Ye);
}

// Von Mises equivalent of a Cauchy stress.
inline double von_mises(const Mat3& s) {
  const Mat3 dev = s - (s.trace() / 3.0) * Mat3::Identity();
  return std::sqrt(1.5 * (dev.array() * dev.array()).sum());
}

}  // namespace correspondence

namespace kernels {
struct LawConstants;
struct HypoConstants;
}  // namespace kernels

// A correspondence model's constants and state as the flat backend copies them and writes
// them back (solver/flat_affine_copy.cpp): pointers into the model, `model` null when the
// model is not correspondence.
struct CorrespondenceState {
  const Model* model = nullptr;
  const correspondence::LawSettings* law = nullptr;
  const kernels::LawConstants* constants = nullptr;    // law_row's (portable_law)
  const kernels::HypoConstants* hypo_constants = nullptr;  // hypo_step's (hypo)
  double G = 0, Cc = 0, tolerance = 0;
  bool portable_law = false, hypo = false;
  const std::vector<uint32_t>* particles = nullptr;
  std::vector<correspondence::History>*committed = nullptr, *trial = nullptr;
  std::vector<double>*work = nullptr, *von_mises = nullptr;
  const std::vector<double>* yield_factor = nullptr;
  std::vector<uint8_t>* singular = nullptr;
  std::vector<correspondence::Mat3>*kinv = nullptr, *F = nullptr, *sigma = nullptr, *rate = nullptr;
  std::vector<Vec3>* u_committed = nullptr;
};
CorrespondenceState correspondence_state(Model& m);

// A History is numbers and fixed-size Eigen matrices: it checkpoints as its bytes (the
// correspondence and bond-associated models both keep one).
template <>
struct plain_data<correspondence::History> : std::true_type {};

}  // namespace horizon
