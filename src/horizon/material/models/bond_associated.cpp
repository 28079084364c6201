#include "horizon/material/models/bond_associated.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "horizon/core/error.hpp"
#include "horizon/kernels/bond_associated.hpp"
#include "horizon/material/models/correspondence.hpp"
#include "horizon/material/nonlocal_gradient.hpp"
#include "horizon/state/system.hpp"

namespace horizon {

namespace {

using correspondence::History;
using correspondence::LawSettings;
using correspondence::Mat3;
using correspondence::StressLaw;
using correspondence::to_eigen;
using correspondence::to_vec3;
using Vec = Eigen::Vector3d;

const ModelTraits& traits() {
  static const ModelTraits t = [] {
    ModelTraits m;
    m.name = "bond_associated_correspondence";
    m.aliases = {"bond_associated"};
    m.summary =
        "bond-associated correspondence: classical stress laws on the bond-level deformation gradient (F_i + F_j)/2 "
        "corrected along the bond, energy averaged over the family (Breitzman and Dayal 2018; Chen and Spencer 2019)";
    m.min_dimension = 2;
    m.parameters = {
        {"yield_stress", "stress_law j2, hypoelastic_j2: initial yield stress sigma_y [Pa]",
         ParameterSpec::Range::non_negative, 0.0},
        {"hardening_modulus", "stress_law j2, hypoelastic_j2: linear isotropic hardening modulus H [Pa]",
         ParameterSpec::Range::non_negative, 0.0},
        {"shape_tolerance",
         "smallest reciprocal condition number of a particle's shape tensor; below it the particle's bonds carry no "
         "force",
         ParameterSpec::Range::fraction, 1e-4},
    };
    m.choices = {
        {"stress_law",
         "classical stress law of each bond: linear_elastic, neo_hookean, j2, hypoelastic or hypoelastic_j2 "
         "(Peridigm's rate form, docs/models/correspondence.md)",
         {"linear_elastic", "neo_hookean", "j2", "hypoelastic", "hypoelastic_j2"}},
        {"rotation_update",
         "the rate-form laws' rotation increment: cayley (Flanagan and Taylor) or peridigm (Peridigm's, "
         "docs/models/correspondence.md)",
         {"cayley", "peridigm"}},
        {"kinematics",
         "lagrangian: the bond-level F on the reference bonds; semi_lagrangian (rate-form laws): the bond-level "
         "velocity gradient and the forces on the current bonds (Behzadinasab and Foster 2020)",
         {"lagrangian", "semi_lagrangian"}},
    };
    // f_i needs F_j (and m_j) of every neighbour j: two horizons of positions, which the
    // split over MPI ranks does not bring (rows_local stays false: one process).
    m.any_horizon = true;  // no constant reads the horizon
    return m;
  }();
  return t;
}

// What row i's bonds read of each end: the nonlocal gradient, its rate, K^-1 and m, row-major
// (the portable kernels' form: kernels/affine.hpp, kernels/bond_associated.hpp).
struct End {
  double F[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};  // F_i (reference gradient)
  double rate[9] = {};                         // lagrangian: F_dot_i; semi_lagrangian: L_i
  double kinv[9] = {};                         // K_i^-1 (semi_lagrangian: of the current bonds)
  double m = 0;                                // sum_j omega V_j over the acting bonds
  bool ok = false;                             // the shape tensor was accepted
};

Mat3 matrix_of(const double* a) {
  Mat3 m;
  for (int c = 0; c < 9; ++c) m(c / 3, c % 3) = a[c];
  return m;
}

class BondAssociated final : public Model {
 public:
  std::unique_ptr<Model> clone() const override { return std::make_unique<BondAssociated>(*this); }
  const ModelTraits& traits() const override { return horizon::traits(); }
  void setup(const ModelSetup& in) override;
  void force_state(ForcePass& pass) override;
  void commit(System& s) override;
  double pending_dissipation(const System& s) const override {
    double sum = 0;
    for (std::size_t l = 0; l < particles_.size(); ++l) sum += work_[l] * s.particles.volume[particles_[l]];
    return sum;
  }
  void fields(const System& s, std::vector<ModelField>& out) const override;
  void checkpoint(StateArchive& a) override {
    a.io_listed("committed", committed_, particles_);
    a.io_listed("trial", trial_, particles_);
    a.io_listed("work", work_, particles_);
    a.io("bond_committed", bond_committed_, Extent::bonds);
    a.io("bond_trial", bond_trial_, Extent::bonds);
    a.io("bond_work", bond_work_, Extent::bonds);
    a.io("u_committed", u_committed_, Extent::particles);
  }

 private:
  LawSettings law_;
  bool hypo_ = false;      // a rate-form law
  bool history_ = false;   // the law keeps a history per bond
  bool semi_ = false;      // kinematics: semi_lagrangian
  double tolerance_ = 0;   // shape_tolerance
  bool plane_stress_ = false;            // 2-D plane stress: the law's secant iteration
  kernels::LawConstants constants_;      // the total-form laws (kernels/plane_stress.hpp)
  kernels::HypoConstants hypo_constants_;  // the rate-form laws (kernels/hypoelastic.hpp)
  std::vector<uint32_t> particles_;  // this material's particles
  std::vector<uint32_t> ends_;       // those and their neighbours: the rows whose End is computed
  std::vector<End> end_;             // per particle of the system (those of ends_ filled)
  std::vector<History> committed_, trial_;            // per particle of ours: the particle-level law
  std::vector<History> bond_committed_, bond_trial_;  // per bond (history laws)
  std::vector<double> bond_work_;                     // per bond: plastic work of the trial step [J/m^3]
  std::vector<double> work_;                          // per particle of ours: c V weighted [J/m^3]
  std::vector<Vec3> u_committed_;                     // rate laws: u at the last commit
  // Of the last pass, per particle of ours, for the output: von Mises of the particle-level
  // law, its sigma, unrotated rate, velocity gradient.
  std::vector<double> von_mises_;
  std::vector<uint8_t> singular_;
  std::vector<Mat3> sigma_, rate_, L_;

  void gradient(const System& s, const Point4* y, double dt, uint32_t i, End& e) const;
};

void BondAssociated::setup(const ModelSetup& in) {
  const MaterialConfig& mat = in.material;
  const int dim = in.config.dimension;
  System& s = in.system;
  if (dim < 2) throw Error("material '" + mat.name + "': the bond-associated correspondence model needs dimension 2 or 3");
  const std::string& law = choice(mat, "stress_law");
  law_ = correspondence::law_settings(mat, dim, in.dims.plane);
  hypo_ = correspondence::rate_form(law_.law);
  if ((law_.law == StressLaw::j2 || law_.law == StressLaw::hypoelastic_j2) && !(law_.j2.yield_stress > 0))
    throw Error("material '" + mat.name + "': stress_law " + law + " needs a positive yield_stress [Pa]");
  if (hypo_ && dim == 2 && law_.plane == PlaneMode::stress)
    throw Error("material '" + mat.name + "': stress_law " + law + " is not available in plane stress");
  semi_ = choice(mat, "kinematics") == "semi_lagrangian";
  if (semi_ && !hypo_)
    throw Error("material '" + mat.name +
                "': kinematics semi_lagrangian needs a rate-form stress_law (hypoelastic or hypoelastic_j2)");
  if (s.one_way_bonds)
    throw Error("material '" + mat.name +
                "': the bond-associated correspondence model needs the bonds both ways (one horizon for its bodies)");
  history_ = hypo_ || law_.law == StressLaw::j2 || (dim == 2 && law_.plane == PlaneMode::stress);
  tolerance_ = parameter(mat, "shape_tolerance");
  plane_stress_ = dim == 2 && law_.plane == PlaneMode::stress;
  constants_ = correspondence::law_constants(law_);
  hypo_constants_ = correspondence::hypo_constants(law_);
  particles_ = in.particles;
  // The stable step of the bond-based spring of the same bulk modulus. Forces reach three
  // bonds (f_i takes T_ji, whose S_j reads F_k of j's neighbours k): the finite-difference
  // tangent probes that far.
  fill_state_based_coefficients(in);
  s.model.reach_hops = std::max(s.model.reach_hops, 3);

  const Bonds& B = s.bonds;
  std::vector<uint8_t> mark(s.particles.size(), 0);
  for (uint32_t i : particles_) {
    mark[i] = 1;
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) mark[B.nbr[k]] = 1;
  }
  ends_.clear();
  for (uint32_t i = 0; i < mark.size(); ++i)
    if (mark[i]) ends_.push_back(i);
  end_.assign(s.particles.size(), End{});
  const std::size_t n = particles_.size();
  committed_.assign(n, History{});
  trial_.assign(n, History{});
  work_.assign(n, 0.0);
  von_mises_.assign(n, 0.0);
  singular_.assign(n, 0);
  if (history_) {
    bond_committed_.assign(B.nbr.size(), History{});
    bond_trial_.assign(B.nbr.size(), History{});
    bond_work_.assign(B.nbr.size(), 0.0);
  }
  if (hypo_) {
    u_committed_ = s.particles.u;
    sigma_.assign(n, Mat3::Zero());
    rate_.assign(n, Mat3::Zero());
    L_.assign(n, Mat3::Zero());
  }
}

// End e of particle i: F_i (and K_i^-1, m_i) over the acting bonds (Silling et al. 2007,
// eq. 17, 134), and the rate: lagrangian F_dot_i = (sum omega V (du_j - du_i) (x) xi)
// K_i^-1 / dt from the displacement increments since the commit (as the correspondence
// model takes it, free of the cancellation of F - F_n); semi_lagrangian L_i = (sum omega V
// (du_j - du_i)/dt (x) Y) K_c^-1 with K_c of the current bonds.
void BondAssociated::gradient(const System& s, const Point4* y, double dt, uint32_t i, End& e) const {
  const Bonds& B = s.bonds;
  const std::vector<Vec3>& X = s.particles.X;
  const int dim = law_.dimension;
  const bool rate = hypo_ && dt > 0 && u_committed_.size() == s.particles.size();
  const Vec3 yi{y[i].x, y[i].y, y[i].z};
  const Vec3 dui = rate ? s.particles.u[i] - u_committed_[i] : Vec3{};
  // The sums of NonlocalGradient::add in the portable kernel (kernels/affine.hpp
  // gradient_add, the same bits): g of F_i, gc of K_c and sum omega V du (x) Y, gr of
  // sum omega V du (x) xi.
  kernels::GradientSums g, gc, gr;
  e.m = 0;
  for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
    if (!B.intact[k]) continue;
    const uint32_t j = B.nbr[k];
    const double wv = B.weight[k] * B.volume[k];
    const Vec3 xv = X[j] - X[i], Yv = Vec3{y[j].x, y[j].y, y[j].z} - yi;
    const double xi[3] = {xv.x, xv.y, xv.z}, Y[3] = {Yv.x, Yv.y, Yv.z};
    e.m += wv;
    kernels::gradient_add(g, xi, Y, wv);
    if (rate) {
      const Vec3 dv = (s.particles.u[j] - u_committed_[j]) - dui;
      const double du[3] = {dv.x, dv.y, dv.z};
      if (semi_) kernels::gradient_add(gc, Y, du, wv);  // K_c and sum omega V du (x) Y
      else kernels::gradient_add(gr, xi, du, wv);       // sum omega V du (x) xi
    } else if (semi_) {
      const double zero[3] = {0, 0, 0};
      kernels::gradient_add(gc, Y, zero, wv);
    }
  }
  e.ok = kernels::gradient_finish(g.v, g.v + 9, dim, tolerance_, e.kinv, e.F);
  for (double& r : e.rate) r = 0.0;
  if (!e.ok) return;
  double M[9];
  if (semi_) {
    e.ok = kernels::gradient_finish(gc.v, gc.v + 9, dim, tolerance_, e.kinv, M);
    if (rate) {
      for (int a = dim; a < 3; ++a) M[4 * a] = 0;  // finish puts 1 on the unused axes
      for (int c = 0; c < 9; ++c) e.rate[c] = M[c] / dt;
    }
  } else if (rate) {
    double Kr[9];
    kernels::gradient_finish(gr.v, gr.v + 9, dim, 0.0, Kr, M);
    for (int a = dim; a < 3; ++a) M[4 * a] = 0;
    for (int c = 0; c < 9; ++c) e.rate[c] = M[c] / dt;
  }
}

void BondAssociated::force_state(ForcePass& pass) {
  const System& s = pass.system;
  const Bonds& B = s.bonds;
  const std::vector<Vec3>& X = s.particles.X;
  const Point4* y = pass.y;
  Vec3* T = pass.T;
  const double dt = pass.dt;
  const bool rate = hypo_ && dt > 0 && u_committed_.size() == s.particles.size();
  const std::size_t ne = ends_.size();
  // Pass 1: every end's gradient (ours and our neighbours').
#pragma omp parallel for schedule(static) if (ne > 512)
  for (std::size_t q = 0; q < ne; ++q) gradient(s, y, dt, ends_[q], end_[ends_[q]]);

  // Pass 2: row i's bonds from the two ends' gradients.
  const std::size_t n = particles_.size();
#pragma omp parallel for schedule(static) if (n > 512)
  for (std::size_t l = 0; l < n; ++l) {
    const uint32_t i = particles_[l];
    const End& ei = end_[i];
    const Vec3 yi{y[i].x, y[i].y, y[i].z};
    const Vec3 dui = rate ? s.particles.u[i] - u_committed_[i] : Vec3{};
    singular_[l] = ei.ok ? 0 : 1;
    work_[l] = 0;
    // The particle-level law (rate laws: the Peridigm tensors of the output; else von
    // Mises of P(F_i)), not a force.
    if (ei.ok) {
      double w = 0;
      Mat3 d = Mat3::Zero();
      const Mat3 Fi = matrix_of(ei.F), Ri = matrix_of(ei.rate);
      Mat3 Fdot = semi_ ? Mat3(Ri * Fi) : Ri;
      const classical::LawResult r =
          correspondence::evaluate_law(law_, Fi, committed_[l], trial_[l], w, dt, 1.0, &d, rate ? &Fdot : nullptr);
      von_mises_[l] = correspondence::von_mises(r.sigma);
      if (hypo_) {
        sigma_[l] = r.sigma;
        rate_[l] = d;
        L_[l] = semi_ ? Ri : Mat3(Ri * Fi.inverse());
      }
    } else {
      trial_[l] = committed_[l];
      von_mises_[l] = 0;
    }
    // Row i's bonds in the portable kernels (kernels/bond_associated.hpp: the bond-level
    // gradient and its rate, the bond's force term and its share of S_i; the law in
    // kernels/plane_stress.hpp law_point or kernels/hypoelastic.hpp hypo_step), the
    // history of each bond copied in and out of the host's History.
    double S[9] = {};  // S_i of the header
    double W = 0;
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
      T[k] = {};
      if (history_) bond_trial_[k] = bond_committed_[k], bond_work_[k] = 0;
      const uint32_t j = B.nbr[k];
      const End& ej = end_[j];
      // m_j > 0 whenever the reverse bond acts; a bond one way alone carries nothing.
      if (!B.intact[k] || !ei.ok || !ej.ok || !(ej.m > 0)) continue;
      const Vec3 xv = X[j] - X[i], Yv = Vec3{y[j].x, y[j].y, y[j].z} - yi;
      const double xi[3] = {xv.x, xv.y, xv.z}, Y[3] = {Yv.x, Yv.y, Yv.z};
      const double xx = kernels::squared_norm3(xi), yy = kernels::squared_norm3(Y);
      if (!(xx > 0) || (semi_ && !(yy > 0))) continue;  // two particles on one spot: no direction
      double Fb[9], Fdot[9];
      kernels::bond_level_gradient(ei.F, ej.F, xi, Y, xx, Fb);
      if (rate) {
        const Vec3 dv = (s.particles.u[j] - u_committed_[j]) - dui;
        const double dY[3] = {dv.x / dt, dv.y / dt, dv.z / dt};
        if (semi_) {
          double L[9];
          kernels::bond_level_gradient(ei.rate, ej.rate, Y, dY, yy, L);
          kernels::mat3_mul(L, Fb, Fdot);  // L_ij F_ij
        } else {
          kernels::bond_level_gradient(ei.rate, ej.rate, xi, dY, xx, Fdot);
        }
      }
      kernels::LawStress r;
      double w = 0;
      if (hypo_) {
        const kernels::HypoHistory before = correspondence::hypo_history(bond_committed_[k].hypo);
        kernels::HypoHistory after;
        double d[9];
        kernels::hypo_step(hypo_constants_, law_.law != StressLaw::hypoelastic ? law_.j2.yield_stress : 0.0, before,
                           Fb, dt, rate ? Fdot : nullptr, 0.0, after, w, r, d);
        correspondence::set_hypo_state(bond_trial_[k].hypo, after);
        bond_trial_[k].plastic.alpha = after.alpha;
        if (!r.ok) continue;
        if (semi_) {  // P = J_n sigma, J_n = det V of the bond's committed step
          const double Jn = kernels::mat3_det(before.V);
          for (int c = 0; c < 9; ++c) r.P[c] = Jn * r.sigma[c];
        }
      } else {
        const bool j2 = constants_.law == kernels::kJ2Law;
        kernels::J2History before{}, after;
        double l3 = 1;
        if (history_) {
          if (j2) before = correspondence::j2_history(bond_committed_[k].plastic);
          l3 = bond_committed_[k].lambda3;
        }
        kernels::law_point(constants_, law_.dimension, plane_stress_, 0.0, before, Fb, l3, after, w, r);
        if (history_) {
          bond_trial_[k].lambda3 = l3;
          if (j2) correspondence::set_j2_state(bond_trial_[k].plastic, after);
        }
        if (!r.ok) continue;
      }
      const double c_ij = B.weight[k] / ei.m, c_ji = B.weight[k] / ej.m;
      double t[3];
      kernels::bond_associated_terms(r.P, semi_ ? Y : xi, semi_ ? yy : xx, c_ij, c_ji, B.volume[k], t, S);
      T[k] = {t[0], t[1], t[2]};
      W += c_ij * B.volume[k] * r.W;
      if (history_) bond_work_[k] = w;
      work_[l] += c_ij * B.volume[k] * w;
    }
    if (!ei.ok) {
      if (pass.energy) pass.energy[i] = 0;
      continue;
    }
    double A[9];
    kernels::mat3_mul(S, ei.kinv, A);
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
      if (!B.intact[k]) continue;
      const uint32_t j = B.nbr[k];
      if (!end_[j].ok || !(end_[j].m > 0)) continue;
      const Vec3 bv = semi_ ? Vec3{y[j].x, y[j].y, y[j].z} - yi : X[j] - X[i];
      const double b3[3] = {bv.x, bv.y, bv.z};
      double t[3] = {T[k].x, T[k].y, T[k].z};
      kernels::bond_associated_tail(A, B.weight[k], b3, t);
      T[k] = {t[0], t[1], t[2]};
    }
    if (pass.energy) pass.energy[i] = W;
  }
}

void BondAssociated::commit(System& s) {
  if (hypo_) u_committed_ = s.particles.u;
  if (history_) bond_committed_ = bond_trial_;
  for (std::size_t l = 0; l < particles_.size(); ++l) {
    committed_[l] = trial_[l];
    if (work_[l] != 0) s.dissipated_at[particles_[l]] += work_[l] * s.particles.volume[particles_[l]];
    work_[l] = 0;
  }
}

// von_mises_stress (of the particle-level law at F_i), singular_shape_tensor, and with a
// rate-form law the particle-level tensors under Peridigm's names (as the correspondence
// model's, docs/models/correspondence.md) plus velocity_gradient_* (L_i) and
// jacobian_determinant (det V_i). A run keeps the first model's field of a name: with a
// correspondence material first, its fields hold (docs/models/bond_associated.md).
void BondAssociated::fields(const System& s, std::vector<ModelField>& out) const {
  const std::size_t n = s.particles.size();
  std::vector<const BondAssociated*> all;
  bool hypo = false;
  for (const auto& model : s.models)
    if (const auto* b = dynamic_cast<const BondAssociated*>(model.get())) {
      all.push_back(b);
      hypo = hypo || b->hypo_;
    }
  ModelField vm{"von_mises_stress", std::vector<double>(n, 0.0)};
  ModelField sg{"singular_shape_tensor", std::vector<double>(n, 0.0)};
  for (const BondAssociated* b : all)
    for (std::size_t l = 0; l < b->particles_.size(); ++l) {
      vm.values[b->particles_[l]] = b->von_mises_[l];
      sg.values[b->particles_[l]] = b->singular_[l];
    }
  out.push_back(std::move(vm));
  out.push_back(std::move(sg));
  if (!hypo) return;
  static const char* rc[9] = {"xx", "xy", "xz", "yx", "yy", "yz", "zx", "zy", "zz"};
  const char* names[7] = {"left_stretch_tensor", "rotation_tensor", "shape_tensor_inverse",
                          "unrotated_rate_of_deformation", "cauchy_stress", "unrotated_cauchy_stress",
                          "velocity_gradient"};
  std::vector<ModelField> f;
  for (const char* name : names)
    for (const char* c : rc) f.push_back({std::string(name) + "_" + c, std::vector<double>(n, 0.0)});
  ModelField jac{"jacobian_determinant", std::vector<double>(n, 0.0)};
  for (const BondAssociated* b : all) {
    if (!b->hypo_) continue;
    for (std::size_t l = 0; l < b->particles_.size(); ++l) {
      const uint32_t i = b->particles_[l];
      const classical::HypoState& h = b->committed_[l].hypo;
      const Mat3 kinv = matrix_of(b->end_[i].kinv);
      const Mat3* m[7] = {&h.V, &h.R, &kinv, &b->rate_[l], &b->sigma_[l], &h.sigma_u, &b->L_[l]};
      for (int t = 0; t < 7; ++t)
        for (int k = 0; k < 9; ++k) f[static_cast<std::size_t>(9 * t + k)].values[i] = (*m[t])(k / 3, k % 3);
      jac.values[i] = h.V.determinant();
    }
  }
  for (auto& x : f) out.push_back(std::move(x));
  out.push_back(std::move(jac));
}

}  // namespace

ModelEntry bond_associated_model() {
  return {traits(), [] { return std::unique_ptr<Model>(std::make_unique<BondAssociated>()); }};
}

}  // namespace horizon
