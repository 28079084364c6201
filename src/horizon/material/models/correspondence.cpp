#include "horizon/material/models/correspondence.hpp"

#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "horizon/core/error.hpp"
#include "horizon/kernels/affine.hpp"
#include "horizon/kernels/force_state.hpp"
#include "horizon/kernels/hypoelastic.hpp"
#include "horizon/kernels/laws.hpp"
#include "horizon/material/nonlocal_gradient.hpp"
#include "horizon/state/system.hpp"

namespace horizon {

namespace {

using correspondence::History;
using correspondence::LawSettings;
using correspondence::Mat3;
using correspondence::StressLaw;

// The law with thermal expansion (System::thermal_strain eps of the particle; docs/models/
// heat.md): the multiplicative split F = F_e F_th with F_th = (1 + eps) on the body's axes
// (Lu and Pister 1975, Int. J. Solids Struct. 11:927), the law's energy per intermediate
// volume: W = J_th W_e(F_e), P = dW/dF = J_th P_e(F_e) F_th^-T, J_th = det F_th; sigma is
// the law's. A free expansion F = F_th is stress-free for every law. The total-form laws
// run it (and plane stress's iteration) in the device-portable kernels/plane_stress.hpp
// law_point (correspondence::total_form_law).
// The rate-form laws' arguments (dt, yield_factor, rate, Fdot) pass through unchanged.
classical::LawResult evaluate_with_expansion(const LawSettings& law, const Mat3& F, double eps,
                                             const History& committed, History& trial, double& work, double dt = 0,
                                             double yield_factor = 1, Mat3* rate = nullptr,
                                             const Mat3* Fdot = nullptr) {
  // The rate form takes the thermal strain's increment out of its strain increment.
  if (correspondence::rate_form(law.law))
    return correspondence::evaluate_law(law, F, committed, trial, work, dt, yield_factor, rate, Fdot, eps);
  work = 0;
  return correspondence::total_form_law(law, correspondence::law_constants(law), F, eps, committed, trial, work);
}

const ModelTraits& traits() {
  static const ModelTraits t = [] {
    ModelTraits m;
    m.name = "correspondence";
    m.aliases = {"nosb"};
    m.summary =
        "non-ordinary state-based correspondence with classical stress laws and Silling 2017 zero-energy-mode "
        "stabilisation (Silling et al. 2007, sec. 18)";
    m.min_dimension = 2;
    m.parameters = {
        {"stabilization",
         "zero-energy-mode stabilisation G_s: T += G omega (Y - F xi), G = G_s c/delta with c = 18k/(pi delta^4) "
         "in 3-D (Silling 2017); 0: off",
         ParameterSpec::Range::non_negative, 1.0},
        {"yield_stress", "stress_law j2: initial yield stress sigma_y [Pa] (required for j2)",
         ParameterSpec::Range::non_negative, 0.0},
        {"hardening_modulus", "stress_law j2: linear isotropic hardening modulus H [Pa]",
         ParameterSpec::Range::non_negative, 0.0},
        {"flaw_magnitude",
         "stress_law hypoelastic_j2, viscoplastic_needleman: Peridigm's yield-stress flaw, sigma_y (1 - m exp(-|x - x_f|^2/s^2)): m "
         "(0: no flaw)",
         ParameterSpec::Range::fraction, 0.0},
        {"flaw_size", "the flaw's length s [m]", ParameterSpec::Range::positive, 1.0},
        {"strain_hardening_exponent",
         "stress_law viscoplastic_needleman: N of the flow stress sigma_y (1 + alpha/eps_0)^N / (1 + "
         "(alpha/eps_1)^2) (rate/eps_dot_0)^m (Needleman 1988)",
         ParameterSpec::Range::non_negative, 0.0},
        {"rate_hardening_exponent", "stress_law viscoplastic_needleman: m", ParameterSpec::Range::non_negative, 0.0},
        {"reference_strain_rate", "stress_law viscoplastic_needleman: eps_dot_0 [1/s]", ParameterSpec::Range::positive,
         1.0},
        {"reference_strain", "stress_law viscoplastic_needleman: eps_0", ParameterSpec::Range::positive, 1.0},
        {"softening_strain", "stress_law viscoplastic_needleman: eps_1", ParameterSpec::Range::positive, 1.0},
        {"flaw_x", "the flaw's centre x_f: x [m]", ParameterSpec::Range::any, 0.0},
        {"flaw_y", "the flaw's centre x_f: y [m]", ParameterSpec::Range::any, 0.0},
        {"flaw_z", "the flaw's centre x_f: z [m]", ParameterSpec::Range::any, 0.0},
        {"shape_tolerance",
         "smallest reciprocal condition number of the shape tensor; below it the particle carries no stress "
         "(contact only)",
         ParameterSpec::Range::fraction, 1e-4},
    };
    m.choices = {
        {"stress_law",
         "classical stress law: linear_elastic (small strain), neo_hookean, j2 (plasticity), hypoelastic and "
         "hypoelastic_j2 (Peridigm's rate form in the unrotated frame, Flanagan and Taylor 1987), "
         "viscoplastic_needleman (the rate form with Needleman 1988's viscoplastic flow stress, Peridigm's update)",
         {"linear_elastic", "neo_hookean", "j2", "hypoelastic", "hypoelastic_j2", "viscoplastic_needleman"}},
        {"plastic_return",
         "stress_law hypoelastic_j2: work (the radial return with the trapezoid plastic-work increment of the "
         "equivalent plastic strain) or peridigm (Peridigm's Isotropic Hardening Correspondence update: the "
         "hardened yield stress from its estimate of the plastic multiplier, classical/hypoelastic.hpp)",
         {"work", "peridigm"}},
        {"rotation_update",
         "the rate-form laws (hypoelastic, hypoelastic_j2, viscoplastic_needleman): cayley (Flanagan and Taylor's "
         "midpoint rotation, orthogonal) or peridigm (Peridigm's exponential of dt Omega with the sign of its Omega^2 "
         "term as Peridigm evaluates it, not orthogonal: classical/hypoelastic.hpp)",
         {"cayley", "peridigm"}},
        {"stabilization_form",
         "silling: Silling 2017's G omega (Y - F xi); peridigm: Peridigm's hourglass force -C c omega ((F xi - Y).Y) "
         "Y/(|xi| |Y|) (Littlewood 2011, scale fitted from Peridigm's gold) with C = stabilization",
         {"silling", "peridigm"}},
    };
    m.affine = true;      // T = omega (M_i xi + g_i Y): kernels/affine.hpp
    m.rows_local = true;  // row i reads i's family (K_i, F_i) and i's own law history alone
    m.any_horizon = true;  // only the stabilisation modulus reads the horizon
    m.adaptive_time_step = true;  // spring_factors: the stable step from the current F_i
    m.thermal_strain = true;      // evaluate_with_expansion
    return m;
  }();
  return t;
}

class Correspondence final : public Model {
 public:
  std::unique_ptr<Model> clone() const override { return std::make_unique<Correspondence>(*this); }
  // Peridigm's hourglass force is not affine in the bond: with it the run leaves the
  // affine pass (ModelTraits::affine) for the general one.
  const ModelTraits& traits() const override {
    if (Cc_ == 0) return horizon::traits();
    static const ModelTraits general = [] {
      ModelTraits m = horizon::traits();
      m.affine = false;
      return m;
    }();
    return general;
  }

  void setup(const ModelSetup& in) override;
  void force_state(ForcePass& pass) override;
  void affine_row(const AffineRowPass& pass, std::size_t i, const double* sums) override;
  void commit(System& s) override;
  double pending_dissipation(const System& s) const override {
    double sum = 0;
    for (std::size_t l = 0; l < particles_.size(); ++l) sum += work_[l] * s.particles.volume[particles_[l]];
    return sum;
  }
  void fields(const System& s, std::vector<ModelField>& out) const override;
  void tensor_fields(const System& s, std::vector<ModelField>& out) const;
  bool spring_factors(const System& s, std::vector<double>& g) const override;
  bool stiffness(const System& s, StiffnessSink& out) const override;

  friend CorrespondenceState horizon::correspondence_state(Model& m);  // the flat backend's copy
  void checkpoint(StateArchive& a) override {
    a.io_listed("committed", committed_, particles_);
    a.io_listed("trial", trial_, particles_);
    a.io_listed("work", work_, particles_);
    a.io_listed("von_mises", von_mises_, particles_);
    a.io_listed("singular", singular_, particles_);
    // The rate form's displacement at the last commit (every particle; empty otherwise).
    a.io("u_committed", u_committed_, Extent::particles);
  }
 private:
  LawSettings law_;
  double G_ = 0;          // stabilisation modulus G_s c / delta [N/m^7] (silling form)
  double Cc_ = 0;         // C_hg c of Peridigm's hourglass force [N/m^6] (peridigm form)
  correspondence::Stabilization form_ = correspondence::Stabilization::silling;
  correspondence::Flaw flaw_;
  bool hypo_ = false;     // a hypoelastic law: the Peridigm tensors are fields
  double tolerance_ = 0;  // shape_tolerance
  // The affine row runs the law in the device-portable kernel (kernels/laws.hpp law_row):
  // linear_elastic, neo_hookean and j2, not in plane stress (whose iteration, law_point of
  // kernels/plane_stress.hpp, runs through law_at with the History's lambda3).
  bool portable_law_ = false;
  kernels::LawConstants constants_;  // the law of law_row
  kernels::HypoConstants hypo_constants_;  // the rate-form laws' (hypo_row)
  bool adaptive_ = false;  // solver.adaptive_time_step: spring_factors from the current state
  std::vector<uint32_t> particles_;
  std::vector<int32_t> local_;  // particle index -> index in particles_ (-1: not ours)
  std::vector<History> committed_, trial_;
  std::vector<double> work_;       // plastic work of the trial step [J/m^3]
  std::vector<double> von_mises_;  // Cauchy von Mises stress of the last pass [Pa]
  // The von Mises stress of the law's result at local particle l: the rate-form laws' of
  // their unrotated Cauchy stress (the one their return acts on), as Peridigm reports it;
  // with an orthogonal R (rotation_update cayley) the same to round-off as that of
  // sigma = R sigma_u R^T, while Peridigm's R is not orthogonal (AdaptiveQuasiStaticSolver's
  // gold: 1.5e8, the yield stress, where R sigma_u R^T gives up to 1.57e8).
  double von_mises_of(std::size_t l, const Mat3& sigma) const {
    return correspondence::von_mises(hypo_ ? trial_[l].hypo.sigma_u : sigma);
  }
  std::vector<uint8_t> singular_;  // 1: the shape tensor was refused at the last pass
  std::vector<double> yield_factor_;  // the flaw's factor on sigma_y (1 without a flaw)
  // Of the last pass, for the output (hypoelastic laws): K^-1, F, sigma, unrotated d.
  std::vector<Mat3> kinv_, F_, sigma_, rate_;
  std::vector<Vec3> u_committed_;  // hypoelastic laws: every particle's u at the last commit
  // Row l's law at F from the committed history (the flaw's factor, the rate kept).
  // Hypoelastic laws take F_dot = (sum_j omega V_j (du_j - du_i) (x) xi) K^-1 / dt, du =
  // u - u_committed: the nonlocal gradient of the step's displacement increment (Peridigm
  // takes it from the velocities, which its Verlet and quasi-static steps make du/dt),
  // free of the rounding of F - F_n (1e-11 of D on ElasticCorrespondenceFullyPrescribedTension).
  // Row l of a rate-form law in the affine pass, through kernels/hypoelastic.hpp: F_dot
  // from the bonds as law_at forms it, the step, the output tensors, the record (K^-1, F
  // row-major); returns the law's energy density (0 where it refuses F). The same bits as
  // law_at (tests/unit/test_law_kernels.cpp).
  double hypo_row(const System& s, std::size_t l, const double* Kinv, const double* F, double dt, double* rec) {
    const uint32_t i = particles_[l];
    double Fdot[9];
    const bool rate = dt > 0 && u_committed_.size() == s.particles.size();
    if (rate) {  // F_dot's bond sum (kernels/hypoelastic.hpp rate_gradient_row)
      const Bonds& B = s.bonds;
      static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 arrays read as xyz doubles");
      double N[9];
      kernels::rate_gradient_row(&s.particles.X[0].x, &s.particles.u[0].x, &u_committed_[0].x, B.offset.data(),
                                 B.nbr.data(), B.intact.data(),
                                 [&B](uint64_t k) { return B.weight[k] * B.volume[k]; }, i, N);
      kernels::rate_gradient_finish(N, Kinv, dt, Fdot);
    }
    kernels::HypoHistory n, t;
    const classical::HypoState& h = committed_[l].hypo;
    for (int k = 0; k < 9; ++k) {
      const int r = k / 3, c = k % 3;
      n.F[k] = h.F(r, c), n.V[k] = h.V(r, c), n.R[k] = h.R(r, c), n.sigma_u[k] = h.sigma_u(r, c);
    }
    n.alpha = h.alpha, n.thermal = h.thermal;
    const double yield = law_.law != StressLaw::hypoelastic ? law_.j2.yield_stress * yield_factor_[l] : 0.0;
    kernels::LawStress r;
    double d[9];
    trial_[l] = committed_[l];
    kernels::hypo_step(hypo_constants_, yield, n, F, dt, rate ? Fdot : nullptr, 0.0, t, work_[l], r, d);
    classical::HypoState& th = trial_[l].hypo;
    for (int k = 0; k < 9; ++k) {
      const int a = k / 3, c = k % 3;
      th.F(a, c) = t.F[k], th.V(a, c) = t.V[k], th.R(a, c) = t.R[k], th.sigma_u(a, c) = t.sigma_u[k];
      kinv_[l](a, c) = Kinv[k], F_[l](a, c) = F[k], sigma_[l](a, c) = r.sigma[k], rate_[l](a, c) = d[k];
    }
    th.alpha = t.alpha, th.thermal = t.thermal;
    trial_[l].plastic.alpha = t.alpha;
    von_mises_[l] = kernels::von_mises(t.sigma_u);
    if (!r.ok) {
      kernels::affine_record(nullptr, F, G_, rec);
      return 0.0;
    }
    kernels::affine_record_of_stress(r.P, Kinv, F, G_, rec);  // T = omega P K^-1 xi (seed 003 eq. 142)
    return r.W;
  }
  classical::LawResult law_at(const System& s, std::size_t l, const Mat3& F, const Mat3& Kinv, double dt) {
    Mat3 d = Mat3::Zero(), Fdot = Mat3::Zero();
    const bool rate = hypo_ && dt > 0 && u_committed_.size() == s.particles.size();
    if (rate) {
      const uint32_t i = particles_[l];
      const Bonds& B = s.bonds;
      const Vec3 dui = s.particles.u[i] - u_committed_[i];
      // F_dot in the portable kernels (kernels/hypoelastic.hpp rate_gradient_add and
      // _finish: the bits of the Eigen sum N += w du (x) xi and N K^-1 / dt).
      double N[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0}, ki[9], fd[9];
      for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
        if (!B.intact[k]) continue;
        const uint32_t j = B.nbr[k];
        const Vec3 du = (s.particles.u[j] - u_committed_[j]) - dui, xv = s.particles.X[j] - s.particles.X[i];
        const double dv[3] = {du.x, du.y, du.z}, x[3] = {xv.x, xv.y, xv.z};
        kernels::rate_gradient_add(N, dv, x, B.weight[k] * B.volume[k]);
      }
      for (int c = 0; c < 9; ++c) ki[c] = Kinv(c / 3, c % 3);
      kernels::rate_gradient_finish(N, ki, dt, fd);
      for (int c = 0; c < 9; ++c) Fdot(c / 3, c % 3) = fd[c];
    }
    const uint32_t i = particles_[l];
    const double eps = i < s.thermal_strain.size() ? s.thermal_strain[i] : 0.0;
    const classical::LawResult r = evaluate_with_expansion(law_, F, eps, committed_[l], trial_[l], work_[l], dt,
                                                           yield_factor_[l], &d, rate ? &Fdot : nullptr);
    if (hypo_) {
      kinv_[l] = Kinv;
      F_[l] = F;
      sigma_[l] = r.sigma;
      rate_[l] = d;
    }
    return r;
  }
};

void Correspondence::setup(const ModelSetup& in) {
  const MaterialConfig& mat = in.material;
  const int dim = in.config.dimension;
  if (dim < 2) throw Error("material '" + mat.name + "': the correspondence model needs dimension 2 or 3");

  const std::string& law = choice(mat, "stress_law");
  law_ = correspondence::law_settings(mat, dim, in.dims.plane);
  hypo_ = correspondence::rate_form(law_.law);
  law_.plastic_return = choice(mat, "plastic_return") == "peridigm" ? classical::PlasticReturn::peridigm
                                                                    : classical::PlasticReturn::work;
  if (law_.law == StressLaw::viscoplastic_needleman) {
    law_.plastic_return = classical::PlasticReturn::needleman;
    law_.needleman = {parameter(mat, "strain_hardening_exponent"), parameter(mat, "rate_hardening_exponent"),
                      parameter(mat, "reference_strain_rate"), parameter(mat, "reference_strain"),
                      parameter(mat, "softening_strain")};
  }
  if ((law_.law == StressLaw::j2 || law_.law == StressLaw::hypoelastic_j2 ||
       law_.law == StressLaw::viscoplastic_needleman) &&
      !(law_.j2.yield_stress > 0))
    throw Error("material '" + mat.name + "': stress_law " + law + " needs a positive yield_stress [Pa]");
  if (hypo_ && dim == 2 && law_.plane == PlaneMode::stress)
    throw Error("material '" + mat.name + "': stress_law " + law + " is not available in plane stress");
  flaw_.magnitude = parameter(mat, "flaw_magnitude");
  flaw_.on = flaw_.magnitude > 0;
  if (flaw_.on && law_.law != StressLaw::hypoelastic_j2 && law_.law != StressLaw::viscoplastic_needleman)
    throw Error("material '" + mat.name +
                "': flaw_magnitude applies to stress_law hypoelastic_j2 and viscoplastic_needleman only");
  flaw_.size = parameter(mat, "flaw_size");
  flaw_.centre = {parameter(mat, "flaw_x"), parameter(mat, "flaw_y"), parameter(mat, "flaw_z")};
  form_ = choice(mat, "stabilization_form") == "peridigm" ? correspondence::Stabilization::peridigm
                                                          : correspondence::Stabilization::silling;
  tolerance_ = parameter(mat, "shape_tolerance");
  portable_law_ = (law_.law == StressLaw::linear_elastic || law_.law == StressLaw::neo_hookean ||
                   law_.law == StressLaw::j2) &&
                  !(dim == 2 && law_.plane == PlaneMode::stress);
  constants_.law = law_.law == StressLaw::j2            ? kernels::kJ2Law
                   : law_.law == StressLaw::neo_hookean ? kernels::kNeoHookeanLaw
                                                        : kernels::kLinearElasticLaw;
  constants_.lambda = law_.elastic.lambda, constants_.mu = law_.elastic.mu, constants_.kappa = law_.elastic.kappa;
  constants_.yield_stress = law_.j2.yield_stress, constants_.hardening = law_.j2.hardening_modulus;
  hypo_constants_.lambda = law_.elastic.lambda, hypo_constants_.mu = law_.elastic.mu;
  hypo_constants_.kappa = law_.elastic.kappa, hypo_constants_.hardening = law_.j2.hardening_modulus;
  hypo_constants_.plastic_return = law_.plastic_return == classical::PlasticReturn::peridigm    ? kernels::kReturnPeridigm
                                   : law_.plastic_return == classical::PlasticReturn::needleman ? kernels::kReturnNeedleman
                                                                                                : kernels::kReturnWork;
  hypo_constants_.rotation =
      law_.rotation == classical::RotationUpdate::peridigm ? kernels::kRotationPeridigm : kernels::kRotationCayley;
  hypo_constants_.N = law_.needleman.N, hypo_constants_.m = law_.needleman.m;
  hypo_constants_.rate0 = law_.needleman.rate0, hypo_constants_.eps0 = law_.needleman.eps0;
  hypo_constants_.eps1 = law_.needleman.eps1;
  adaptive_ = in.config.solver.adaptive_time_step;

  // The bond-based micromodulus of the same bulk modulus with omega = 1 (18k/(pi delta^4)
  // in 3-D): the scale of the stabilisation and of the short-range contact, as the LPS.
  const double c = equivalent_micromodulus(mat.bulk_modulus, mat.shear_modulus, InfluenceKind::constant, in.dims);
  const double Gs = parameter(mat, "stabilization");
  if (form_ == correspondence::Stabilization::silling)
    G_ = correspondence::stabilization_modulus(Gs, c, in.dims.horizon);
  else
    Cc_ = Gs * c;
  // Stable time step (Silling-Askari bound on the shared spring): the bond-based spring of
  // the same bulk modulus, stiffened by the stabilisation, which adds at most G_s times it
  // on a bond (omega |xi|/delta <= 1 for the influence functions offered).
  particles_ = in.particles;
  // Forces reach two horizons (f_i needs F_j of every neighbour j): state-based for the
  // tangent probing.
  fill_state_based_coefficients(in, 1.0 + Gs);

  const std::size_t n = particles_.size();
  local_.assign(in.system.particles.size(), -1);
  for (std::size_t l = 0; l < n; ++l) local_[particles_[l]] = static_cast<int32_t>(l);
  committed_.assign(n, History{});
  trial_.assign(n, History{});
  work_.assign(n, 0.0);
  von_mises_.assign(n, 0.0);
  singular_.assign(n, 0);
  yield_factor_.assign(n, 1.0);
  for (std::size_t l = 0; l < n; ++l) yield_factor_[l] = flaw_.factor(in.system.particles.X[particles_[l]]);
  if (hypo_) u_committed_ = in.system.particles.u;
  if (hypo_ || Cc_ != 0) {
    kinv_.assign(n, Mat3::Zero());
    F_.assign(n, Mat3::Identity());
    sigma_.assign(n, Mat3::Zero());
    rate_.assign(n, Mat3::Zero());
  }
}

void Correspondence::force_state(ForcePass& pass) {
  const System& s = pass.system;
  const Bonds& B = s.bonds;
  const std::vector<Vec3>& X = s.particles.X;
  const Point4* y = pass.y;
  Vec3* T = pass.T;
  const int dim = law_.dimension;
  const std::size_t n = particles_.size();
  // Small bodies on one thread: the finite-difference tangent calls this thousands of
  // times, and a parallel region's barrier costs more than a few hundred particles.
#pragma omp parallel for schedule(static) if (n > 512)
  for (std::size_t l = 0; l < n; ++l) {
    const uint32_t i = particles_[l];
    if (!s.computes_row(i)) continue;  // another rank's row (ModelTraits::rows_local)
    const Point4 yi = y[i];
    // K_i and F_i over the acting bonds (seed 003 eq. 17, 134) in the portable kernels
    // (kernels/affine.hpp gradient_add and gradient_finish: NonlocalGradient's bits).
    kernels::GradientSums sums;
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
      if (!B.intact[k]) continue;
      const uint32_t j = B.nbr[k];
      const Vec3 xv = X[j] - X[i];
      const double xi[3] = {xv.x, xv.y, xv.z}, Y[3] = {y[j].x - yi.x, y[j].y - yi.y, y[j].z - yi.z};
      kernels::gradient_add(sums, xi, Y, B.weight[k] * B.volume[k]);
    }
    double kinv[9], f[9], a[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    const bool ok = kernels::gradient_finish(sums.v, sums.v + 9, dim, tolerance_, kinv, f);
    singular_[l] = ok ? 0 : 1;
    double W = 0;
    if (ok) {
      Mat3 Kinv, F;
      for (int c = 0; c < 9; ++c) Kinv(c / 3, c % 3) = kinv[c], F(c / 3, c % 3) = f[c];
      // The law in the portable kernels (law_at: kernels/plane_stress.hpp law_point or
      // kernels/hypoelastic.hpp hypo_step).
      const classical::LawResult r = law_at(s, l, F, Kinv, pass.dt);
      if (Cc_ != 0) F_[l] = F;
      if (r.ok) {
        double p[9];
        for (int c = 0; c < 9; ++c) p[c] = r.P(c / 3, c % 3);
        kernels::mat3_mul(p, kinv, a);  // A = P K^-1: T = omega P K^-1 xi (seed 003 eq. 142)
        W = r.W;
      }
      von_mises_[l] = von_mises_of(l, r.sigma);
    } else {
      trial_[l] = committed_[l];
      work_[l] = 0;
      von_mises_[l] = 0;
    }
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
      if (!B.intact[k] || !ok) {
        T[k] = {};  // a broken bond, or a particle that carries no stress (contact only)
        continue;
      }
      const uint32_t j = B.nbr[k];
      const Vec3 xv = X[j] - X[i];
      const double xi[3] = {xv.x, xv.y, xv.z}, Y[3] = {y[j].x - yi.x, y[j].y - yi.y, y[j].z - yi.z};
      const double omega = B.weight[k];
      // The bond's force state in the portable kernels (kernels/force_state.hpp).
      double t[3];
      kernels::correspondence_bond_state(a, f, G_, omega, xi, Y, t);
      if (Cc_ != 0) kernels::peridigm_hourglass_add(f, Cc_, omega, xi, Y, t);
      T[k] = {t[0], t[1], t[2]};
      if (pass.energy && G_ != 0) W += kernels::stabilization_energy(f, G_, omega * B.volume[k], xi, Y);
    }
    if (pass.energy) pass.energy[i] = W;
  }
}

// Row i of the affine pass: F_i and the law from the sums of the breaking sweep (those of
// force_state, the same bits), then the record {A_i - G F_i, G} (kernels/affine.hpp)
// instead of the force state of every bond.
void Correspondence::affine_row(const AffineRowPass& pass, std::size_t i, const double* sums) {
  const System& s = pass.system;
  const Bonds& B = s.bonds;
  const Vec3* X = s.particles.X.data();
  const Point4* y = pass.y;
  const std::size_t l = static_cast<std::size_t>(local_[i]);
  const Point4 yi = y[i];
  double* rec = pass.record + kernels::kAffineRecord * i;
  double f[9];  // F_i, row-major
  double W = 0;
  // A particle whose shape tensor the gradient refuses carries no stress: its history
  // stays, its record is zero.
  const auto refuse_singular = [&] {
    trial_[l] = committed_[l];
    work_[l] = 0;
    von_mises_[l] = 0;
    kernels::affine_record(nullptr, nullptr, 0.0, rec);
    if (pass.energy) pass.energy[i] = 0;
  };
  if (portable_law_) {
    // The linear elastic, neo-Hookean and J2 laws: the whole row in the device-portable
    // kernel (kernels/laws.hpp law_row), J2's history copied in and out as plain numbers.
    const bool j2 = constants_.law == kernels::kJ2Law;
    kernels::J2History committed{}, trial;
    if (j2) {
      const classical::J2State& c = committed_[l].plastic;
      for (int k = 0; k < 9; ++k) committed.plastic_strain[k] = c.plastic_strain(k / 3, k % 3);
      committed.alpha = c.alpha;
    }
    const kernels::AffineRow row =
        kernels::law_row(sums, law_.dimension, tolerance_, constants_, G_, committed, trial, work_[l], rec);
    singular_[l] = row.carries ? 0 : 1;
    trial_[l] = committed_[l];
    if (j2) {
      classical::J2State& t = trial_[l].plastic;
      for (int k = 0; k < 9; ++k) t.plastic_strain(k / 3, k % 3) = trial.plastic_strain[k];
      t.alpha = trial.alpha;
    }
    von_mises_[l] = row.von_mises;
    if (!row.carries) {
      if (pass.energy) pass.energy[i] = 0;
      return;
    }
    W = row.W;
    for (int c = 0; c < 9; ++c) f[c] = row.F[c];
  } else if (hypo_) {
    // The rate-form laws: the row in the device-portable kernel (kernels/hypoelastic.hpp
    // hypo_step) after the host's bond sum of F_dot.
    double Kinv[9];
    const bool ok = kernels::gradient_finish(sums, sums + 9, law_.dimension, tolerance_, Kinv, f);
    singular_[l] = ok ? 0 : 1;
    if (!ok) return refuse_singular();
    W = hypo_row(s, l, Kinv, f, pass.dt, rec);
  } else {
    // 2-D plane stress (the total-form laws): the whole row in the device-portable kernel
    // (kernels/plane_stress.hpp law_point_row: the law and its secant iteration), J2's
    // history and the stretch lambda3 copied in and out as plain numbers.
    const bool j2 = constants_.law == kernels::kJ2Law;
    const kernels::J2History committed = j2 ? correspondence::j2_history(committed_[l].plastic) : kernels::J2History{};
    kernels::J2History trial;
    double l3 = 1;
    const kernels::AffineRow row = kernels::law_point_row(sums, law_.dimension, tolerance_, constants_, true, G_,
                                                          committed, committed_[l].lambda3, trial, l3, work_[l], rec);
    singular_[l] = row.carries ? 0 : 1;
    if (!row.carries) return refuse_singular();
    trial_[l] = committed_[l];
    trial_[l].lambda3 = l3;
    if (j2) correspondence::set_j2_state(trial_[l].plastic, trial);
    von_mises_[l] = row.von_mises;
    W = row.W;
    for (int c = 0; c < 9; ++c) f[c] = row.F[c];
  }
  if (!pass.energy) return;
  if (G_ != 0)
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
      if (!B.intact[k]) continue;
      const uint32_t j = B.nbr[k];
      const double Y[3] = {y[j].x - yi.x, y[j].y - yi.y, y[j].z - yi.z};
      const Vec3 xv = X[j] - X[i];
      const double xi[3] = {xv.x, xv.y, xv.z};
      W += kernels::stabilization_energy(f, G_, B.weight[k] * B.volume[k], xi, Y);
    }
  pass.energy[i] = W;
}

void Correspondence::commit(System& s) {
  if (hypo_) u_committed_ = s.particles.u;
  for (std::size_t l = 0; l < particles_.size(); ++l) {
    if (!s.computes_row(particles_[l])) continue;
    committed_[l] = trial_[l];
    if (work_[l] != 0) s.dissipated_at[particles_[l]] += work_[l] * s.particles.volume[particles_[l]];
    work_[l] = 0;  // a second commit without a force pass dissipates nothing more
  }
}

// The stable step from the current state (solver.adaptive_time_step). The force state
// omega P K^-1 xi is written on the reference bonds, and the law's Kirchhoff stress
// tau = c : (ln V - E_p) (classical/stress_laws.hpp) gives P = tau F^-T, so the reference
// tangent dP/dF is, up to the small geometric term tau, c acting on (dF F^-1) F^-T: a
// reference bond of direction n sees the acoustic stiffness of c along F^-T n, |F^-T n|^2
// times the undeformed one. A compression to the stretch lambda along n stiffens the bonds
// along n by 1/lambda^2 (digest 000 sec. 10, pitfall 14), while the Silling-Askari bound of
// the shared spring (Silling and Askari 2005, eq. 17) is taken once from the reference
// state. The factor of particle i is the mean of |F_i^-T n|^2 over its bonds with the
// bound's weights omega V / |xi|: 1 in the reference state, the stiffening of the
// compressed direction weighted by how many bonds lie along it (tr(F^-1 F^-T)/3 for a full
// isotropic family). A particle that carries no stress (refused shape tensor, det F <= 0)
// keeps 1.
bool Correspondence::spring_factors(const System& s, std::vector<double>& g) const {
  if (!adaptive_) return false;
  const Bonds& B = s.bonds;
  const Particles& P = s.particles;
  const int dim = law_.dimension;
  const std::size_t n = particles_.size();
#pragma omp parallel for schedule(static) if (n > 512)
  for (std::size_t l = 0; l < n; ++l) {
    const uint32_t i = particles_[l];
    if (B.begin(i) == B.end(i)) continue;  // another rank's row
    const Vec3 yi = P.position(i);
    NonlocalGradient grad;
    for (uint64_t k = B.begin(i); k < B.end(i); ++k)
      if (B.intact[k]) grad.add(P.X[B.nbr[k]] - P.X[i], P.position(B.nbr[k]) - yi, B.weight[k] * B.volume[k]);
    Mat3 Kinv, F;
    if (!grad.finish(dim, tolerance_, Kinv, F) || !(F.determinant() > 0)) continue;
    const Mat3 FinvT = F.inverse().transpose();
    double num = 0, den = 0;
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
      const Vec3 xi = P.X[B.nbr[k]] - P.X[i];
      const double L = B.length[k];
      const Eigen::Vector3d m = FinvT * Eigen::Vector3d(xi.x / L, xi.y / L, xi.z / L);
      const double w = B.weight[k] * B.volume[k] / L;
      num += w * m.squaredNorm();
      den += w;
    }
    if (den > 0 && std::isfinite(num)) g[i] = num / den;
  }
  return true;
}

// The analytic tangent K = -dF/du (F_i = f_i V_i) of the pair form of the force density
// (kernels/affine.hpp):
//   f_i = sum_j w_ij ((M_i + M_j) xi_ij + (g_i + g_j) Y_ij),   w_ij = omega V_j,
//   M_m = A_m - G F_m,  A_m = P(F_m) K_m^-1,  g_m = G  (M_m = 0, g_m = 0: m carries no stress).
// With q_mk = w_mk K_m^-1 xi_mk and Q_m = sum_k q_mk, dF_m = sum_k du_k (x) q_mk - du_m (x) Q_m
// (seed 003 eq. 134 differentiated; K_m symmetric), and for a vector v
//   dM_m v = D_m[dF_m] K_m^-1 v - G dF_m v,   D_m = dP/dF at F_m,
// so du_k = e_a moves dM_m v by R_m(v, q)_ra = sum_sc D_m[(r,s),(a,c)] (K_m^-1 v)_s q_c - G delta_ra (q . v)
// with q = q_mk (and -Q_m for k = m). Row i then gathers
//   R_i(s_i, .) over i's family, s_i = sum_j w_ij xi_ij (zero in the bulk: the surface's share),
//   R_j(w_ij xi_ij, .) over the family of each neighbour j (the tangent reaches two horizons),
//   (g_i + g_j) w_ij I for the Y of each bond.
// D_m comes from central differences of the stress law at F_m (step 1e-6, from the
// committed history: the consistent tangent of the step for j2), so every law of the model
// has its tangent; the linear elastic law is linear in F and its difference quotient is
// exact to round-off. Taken when this material holds every particle of a serial run (the
// pair form's M_j of a neighbour of another model would need that model's tangent), every
// bond acts both ways, the law is not a rate form and the stabilisation is Silling's;
// otherwise the static solvers take finite differences of the forces.
bool Correspondence::stiffness(const System& s, StiffnessSink& out) const {
  const Particles& P = s.particles;
  const Bonds& B = s.bonds;
  const std::size_t n = P.size();
  // One-way bonds (bodies of different horizons) have omega_ij != omega_ji: no pair form.
  // The rate-form laws (their stress follows the step's increments, not F alone) and
  // Peridigm's hourglass force (not affine in the bond) are left to finite differences.
  if (s.decomposition || s.one_way_bonds || particles_.size() != n || hypo_ ||
      (form_ == correspondence::Stabilization::peridigm && Cc_ != 0))
    return false;
  const int dim = law_.dimension;
  using Mat9 = Eigen::Matrix<double, 9, 9>;
  std::vector<Mat3> Kinv(n, Mat3::Zero());
  std::vector<Mat9> D(n, Mat9::Zero());
  std::vector<uint8_t> carries(n, 0);
#pragma omp parallel for schedule(static) if (n > 512)
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 yi = P.position(i);
    NonlocalGradient grad;
    for (uint64_t k = B.begin(i); k < B.end(i); ++k)
      if (B.intact[k]) grad.add(P.X[B.nbr[k]] - P.X[i], P.position(B.nbr[k]) - yi, B.weight[k] * B.volume[k]);
    Mat3 F;
    if (!grad.finish(dim, tolerance_, Kinv[i], F)) continue;
    carries[i] = 1;
    const std::size_t l = static_cast<std::size_t>(local_[i]);
    History trial;
    double work = 0;
    // The law as the force pass takes it: with the particle's thermal strain.
    const double eps = i < s.thermal_strain.size() ? s.thermal_strain[i] : 0.0;
    if (!evaluate_with_expansion(law_, F, eps, committed_[l], trial, work).ok) continue;  // A = 0: G alone
    constexpr double h = 1e-6;
    for (int a = 0; a < dim; ++a)
      for (int c = 0; c < dim; ++c) {
        Mat3 Fp = F, Fm = F;
        Fp(a, c) += h;
        Fm(a, c) -= h;
        const classical::LawResult rp = evaluate_with_expansion(law_, Fp, eps, committed_[l], trial, work);
        const classical::LawResult rm = evaluate_with_expansion(law_, Fm, eps, committed_[l], trial, work);
        if (!rp.ok || !rm.ok) continue;
        const Mat3 dP = (rp.P - rm.P) / (2 * h);
        for (int r = 0; r < 3; ++r)
          for (int q = 0; q < 3; ++q) D[i](3 * r + q, 3 * a + c) = dP(r, q);
      }
  }
  // q_mk of every acting bond and Q_m.
  std::vector<Eigen::Vector3d> q(B.size(), Eigen::Vector3d::Zero());
  std::vector<Eigen::Vector3d> Q(n, Eigen::Vector3d::Zero());
  for (std::size_t m = 0; m < n; ++m) {
    if (!carries[m]) continue;
    for (uint64_t k = B.begin(m); k < B.end(m); ++k) {
      if (!B.intact[k]) continue;
      const Vec3 xi = P.X[B.nbr[k]] - P.X[m];
      q[k] = B.weight[k] * B.volume[k] * (Kinv[m] * correspondence::to_eigen(xi));
      Q[m] += q[k];
    }
  }
  // Row i's blocks by column particle (scratch: slot of each particle, -1 when untouched).
  std::vector<int32_t> slot(n, -1);
  std::vector<uint32_t> cols;
  std::vector<Mat3> blocks;
  auto block = [&](uint32_t k) -> Mat3& {
    if (slot[k] < 0) {
      slot[k] = static_cast<int32_t>(cols.size());
      cols.push_back(k);
      blocks.push_back(Mat3::Zero());
    }
    return blocks[static_cast<std::size_t>(slot[k])];
  };
  // Adds R_m(v, .) of every column particle of m's dF to row i's blocks.
  auto add_response = [&](uint32_t m, const Eigen::Vector3d& v) {
    const Eigen::Vector3d p = Kinv[m] * v;
    std::array<double, 27> E{};  // E[(r, a, c)] = sum_s D[(r,s),(a,c)] p_s
    for (int r = 0; r < 3; ++r)
      for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 3; ++c) {
          double e = 0;
          for (int t = 0; t < 3; ++t) e += D[m](3 * r + t, 3 * a + c) * p[t];
          E[static_cast<std::size_t>(9 * r + 3 * a + c)] = e;
        }
    auto response = [&](const Eigen::Vector3d& qq) {
      Mat3 R;
      for (int r = 0; r < 3; ++r)
        for (int a = 0; a < 3; ++a) {
          const std::size_t e = static_cast<std::size_t>(9 * r + 3 * a);
          R(r, a) = E[e] * qq[0] + E[e + 1] * qq[1] + E[e + 2] * qq[2];
        }
      R.diagonal().array() -= G_ * qq.dot(v);
      return R;
    };
    for (uint64_t k = B.begin(m); k < B.end(m); ++k)
      if (B.intact[k]) block(B.nbr[k]) += response(q[k]);
    block(m) -= response(Q[m]);
  };
  for (uint32_t i = 0; i < n; ++i) {
    const double gi = carries[i] ? G_ : 0.0;
    Eigen::Vector3d si = Eigen::Vector3d::Zero();
    block(i);  // the diagonal block first
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
      if (!B.intact[k]) continue;
      const uint32_t j = B.nbr[k];
      const double w = B.weight[k] * B.volume[k];
      const Eigen::Vector3d b = w * correspondence::to_eigen(P.X[j] - P.X[i]);
      si += b;
      if (carries[j]) add_response(j, b);
      const double spring = (gi + (carries[j] ? G_ : 0.0)) * w;
      block(j).diagonal().array() += spring;
      block(i).diagonal().array() -= spring;
    }
    if (carries[i]) add_response(i, si);
    const double V = P.volume[i];
    for (std::size_t c = 0; c < cols.size(); ++c) {
      for (int r = 0; r < dim; ++r)
        for (int a = 0; a < dim; ++a) out.add(i, r, cols[c], a, -V * blocks[c](r, a));
      slot[cols[c]] = -1;
    }
    cols.clear();
    blocks.clear();
  }
  return true;
}

// One field per name for every correspondence material of the run (the run keeps the
// first model's fields of a name, so the first fills them all).
void Correspondence::fields(const System& s, std::vector<ModelField>& out) const {
  const std::size_t n = s.particles.size();
  ModelField vm{"von_mises_stress", std::vector<double>(n, 0.0)};
  ModelField ep{"equivalent_plastic_strain", std::vector<double>(n, 0.0)};
  ModelField sg{"singular_shape_tensor", std::vector<double>(n, 0.0)};
  for (const auto& model : s.models) {
    const auto* c = dynamic_cast<const Correspondence*>(model.get());
    if (!c) continue;
    for (std::size_t l = 0; l < c->particles_.size(); ++l) {
      const uint32_t i = c->particles_[l];
      vm.values[i] = c->von_mises_[l];
      ep.values[i] = c->committed_[l].plastic.alpha;
      sg.values[i] = c->singular_[l];
    }
  }
  out.push_back(std::move(vm));
  out.push_back(std::move(ep));
  out.push_back(std::move(sg));
  tensor_fields(s, out);
}

// The tensors of the hypoelastic laws under Peridigm's names (lower case: the Exodus
// writer's Left_Stretch_Tensor etc., driver/exodus_output.hpp), each as 9 fields
// <name>_xx, _xy, ..., _zz, and Peridigm's hourglass force density (3 fields
// hourglass_force_density_x/y/z): published only where a model has them.
void Correspondence::tensor_fields(const System& s, std::vector<ModelField>& out) const {
  const std::size_t n = s.particles.size();
  bool hypo = false, hourglass = false;
  for (const auto& model : s.models)
    if (const auto* c = dynamic_cast<const Correspondence*>(model.get())) {
      hypo = hypo || c->hypo_;
      hourglass = hourglass || c->form_ == correspondence::Stabilization::peridigm;
    }
  static const char* rc[9] = {"xx", "xy", "xz", "yx", "yy", "yz", "zx", "zy", "zz"};
  if (hypo) {
    const char* names[6] = {"left_stretch_tensor", "rotation_tensor", "shape_tensor_inverse",
                            "unrotated_rate_of_deformation", "cauchy_stress", "unrotated_cauchy_stress"};
    std::vector<ModelField> f;
    for (const char* name : names)
      for (const char* c : rc) f.push_back({std::string(name) + "_" + c, std::vector<double>(n, 0.0)});
    for (const auto& model : s.models) {
      const auto* c = dynamic_cast<const Correspondence*>(model.get());
      if (!c || !c->hypo_) continue;
      for (std::size_t l = 0; l < c->particles_.size(); ++l) {
        const uint32_t i = c->particles_[l];
        const classical::HypoState& h = c->committed_[l].hypo;
        const Mat3* m[6] = {&h.V, &h.R, &c->kinv_[l], &c->rate_[l], &c->sigma_[l], &h.sigma_u};
        for (int t = 0; t < 6; ++t)
          for (int k = 0; k < 9; ++k) f[static_cast<std::size_t>(9 * t + k)].values[i] = (*m[t])(k / 3, k % 3);
      }
    }
    for (auto& x : f) out.push_back(std::move(x));
  }
  if (hourglass) {
    // f_hg,i = sum_j (T_hg,ij - T_hg,ji) V_j over the acting bonds, T_hg,ji with F_j and
    // the reversed bond (-xi, -Y). A neighbour whose row another rank computes has no F_j
    // here: its term is left out (output only; the forces themselves are exact).
    std::vector<Vec3> f(n, Vec3{});
    std::vector<const Mat3*> Fof(n, nullptr);
    std::vector<double> Ccof(n, 0.0);
    for (const auto& model : s.models)
      if (const auto* c = dynamic_cast<const Correspondence*>(model.get()); c && c->Cc_ != 0)
        for (std::size_t l = 0; l < c->particles_.size(); ++l)
          if (!c->singular_[l] && s.computes_row(c->particles_[l]))
            Fof[c->particles_[l]] = &c->F_[l], Ccof[c->particles_[l]] = c->Cc_;
    const Bonds& B = s.bonds;
    const Particles& P = s.particles;
    for (std::size_t i = 0; i < n; ++i) {
      if (!Fof[i] || i + 1 >= B.offset.size()) continue;
      for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
        if (!B.intact[k]) continue;
        const uint32_t j = B.nbr[k];
        const Vec3 xi = P.X[j] - P.X[i], Y = P.position(j) - P.position(i);
        Vec3 t = correspondence::peridigm_hourglass(*Fof[i], Ccof[i], B.weight[k], xi, Y);
        if (Fof[j]) t -= correspondence::peridigm_hourglass(*Fof[j], Ccof[j], B.weight[k], -xi, -Y);
        f[i] += t * B.volume[k];
      }
    }
    const char* xyz[3] = {"x", "y", "z"};
    for (int c = 0; c < 3; ++c) {
      ModelField h{std::string("hourglass_force_density_") + xyz[c], std::vector<double>(n, 0.0)};
      for (std::size_t i = 0; i < n; ++i) h.values[i] = f[i][c];
      out.push_back(std::move(h));
    }
  }
}

}  // namespace

ModelEntry correspondence_model() {
  return {traits(), [] { return std::unique_ptr<Model>(std::make_unique<Correspondence>()); }};
}

CorrespondenceState correspondence_state(Model& m) {
  CorrespondenceState out;
  auto* c = dynamic_cast<Correspondence*>(&m);
  if (!c) return out;
  out.model = c;
  out.law = &c->law_;
  out.constants = &c->constants_;
  out.hypo_constants = &c->hypo_constants_;
  out.G = c->G_, out.Cc = c->Cc_, out.tolerance = c->tolerance_;
  out.portable_law = c->portable_law_, out.hypo = c->hypo_;
  out.particles = &c->particles_;
  out.committed = &c->committed_, out.trial = &c->trial_;
  out.work = &c->work_, out.von_mises = &c->von_mises_, out.yield_factor = &c->yield_factor_;
  out.singular = &c->singular_;
  out.kinv = &c->kinv_, out.F = &c->F_, out.sigma = &c->sigma_, out.rate = &c->rate_;
  out.u_committed = &c->u_committed_;
  return out;
}

}  // namespace horizon
