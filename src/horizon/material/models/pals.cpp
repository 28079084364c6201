#include "horizon/material/models/pals.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "horizon/core/error.hpp"
#include "horizon/kernels/pals.hpp"
#include "horizon/material/models/ordinary_flat.hpp"
#include "horizon/material/influence.hpp"
#include "horizon/state/system.hpp"

namespace horizon {

namespace pals {

// The set-up's algebra is kernels/pals.hpp's (the 6 x 6 solves written out there).
double dilatation_factor(const double lambda[6], const Vec3& x) {
  return kernels::pals_dilatation_factor(lambda, x.x, x.y, x.z);
}

double deviatoric_factor(const double mu[6], const Vec3& x) { return kernels::pals_deviatoric_factor(mu, x.x, x.y, x.z); }

bool dilatation_multipliers(const std::vector<Vec3>& xi, const std::vector<double>& wv, double out[6]) {
  return kernels::pals_dilatation_multipliers(xi.data(), wv.data(), xi.size(), out);
}

bool deviatoric_multipliers(const std::vector<Vec3>& xi, const std::vector<double>& wv, double out[6]) {
  return kernels::pals_deviatoric_multipliers(xi.data(), wv.data(), xi.size(), out);
}

}  // namespace pals

namespace {

const std::vector<std::string> kInfluenceChoices = {"influence", "constant", "inverse", "inverse_length", "linear",
                                                    "gaussian"};

const ModelTraits& traits() {
  static const ModelTraits t = [] {
    ModelTraits m;
    m.name = "pals";
    m.summary = "position-aware linear solid: the LPS with per-particle dilatation and deviatoric influence "
                "functions exact for homogeneous strains at surfaces (Mitchell, Silling, Littlewood 2015)";
    m.min_dimension = 3;
    m.choices = {
        {"dilatation_influence",
         "omega of the dilatation influence function sigma = omega (1 + Lambda : xi xi): influence (the "
         "material's influence), constant, inverse, inverse_length, linear or gaussian (material/influence.hpp)",
         kInfluenceChoices},
        {"deviatoric_influence",
         "omega of the deviatoric influence function tau = omega (1 + sum_k mu_k g_k): as dilatation_influence",
         kInfluenceChoices},
    };
    m.rows_local = true;  // row i reads i's family and the sigma, tau of i's bonds alone
    m.ordinary = true;    // T = t Y/|Y|: the scalar general pass (force_row)
    return m;
  }();
  return t;
}

// omega of a bond under a choice of kInfluenceChoices ("influence": the bond's own weight).
// A bond of weight 0 does not act in this direction (a one-way bond between bodies of
// different horizons, docs/input.md): 0 whatever the choice.
double choice_weight(const std::string& choice, const BondKind& b, double horizon) {
  if (choice == "influence" || b.weight == 0) return b.weight;
  InfluenceKind k = InfluenceKind::constant;
  if (choice == "inverse") k = InfluenceKind::inverse;
  else if (choice == "inverse_length") k = InfluenceKind::inverse_length;
  else if (choice == "linear") k = InfluenceKind::linear;
  else if (choice == "gaussian") k = InfluenceKind::gaussian;
  return influence(k, b.length, horizon);
}

class Pals final : public Model {
 public:
  std::unique_ptr<Model> clone() const override { return std::make_unique<Pals>(*this); }
  const ModelTraits& traits() const override { return horizon::traits(); }

  void setup(const ModelSetup& in) override;
  void force_state(ForcePass& pass) override;
  // The scalar pass's row: force_state's sums in its order on the pass's |Y| (the same
  // bits), q = t/|Y| per bond.
  void force_row(const RowPass& pass, std::size_t i, double dilatation_sum) override;
  // The flat backend's view of the state (material/models/ordinary_flat.hpp).
  void flat_state(OrdinaryModelState& o) {
    o.kind = OrdinaryModelState::pals;
    o.dim = 3, o.kappa = kappa_, o.mu = mu_, o.sigma = &sigma_, o.pals_tau = &tau_, o.theta = &theta_;
  }
  void fields(const System& s, std::vector<ModelField>& out) const override {
    (void)s;
    // Horizon's sigma and tau carry no normalisation of omega: 1, Peridigm's value for One.
    out.push_back({"dilatation", theta_});
    out.push_back({"dilatation_normalization", normalization_});
    out.push_back({"deviatoric_normalization", normalization_});
    for (int k = 0; k < 12; ++k) {
      std::vector<double> v(multipliers_.size() / 12);
      for (std::size_t i = 0; i < v.size(); ++i) v[i] = multipliers_[12 * i + static_cast<std::size_t>(k)];
      out.push_back({std::string("lagrange_multiplier_") + (k < 6 ? "dilatation_" : "deviatoric_") +
                         std::to_string(k % 6 + 1),
                     std::move(v)});
    }
  }

 private:
  std::vector<uint32_t> particles_;
  double kappa_ = 0, mu_ = 0;
  std::vector<double> sigma_, tau_;       // per bond (of this material's rows): sigma_ij, tau_ij
  std::vector<double> multipliers_;       // per particle: Lambda (6) then mu (6)
  std::vector<double> normalization_;     // per particle: 1 at this model's particles
  std::vector<double> theta_;             // per particle: the dilatation of the last pass
};

void Pals::setup(const ModelSetup& in) {
  const MaterialConfig& mat = in.material;
  System& s = in.system;
  if (in.config.dimension != 3)
    throw Error("material '" + mat.name + "': model pals is defined in 3-D only (its modes are the six of a 3-D strain)");
  particles_ = in.particles;
  kappa_ = mat.bulk_modulus;
  mu_ = mat.shear_modulus;
  const std::string& sigma_choice = Model::choice(mat, "dilatation_influence");
  const std::string& tau_choice = Model::choice(mat, "deviatoric_influence");
  const auto& B = s.bonds;
  const auto& X = s.particles.X;
  const std::size_t n = s.particles.size();
  sigma_.assign(B.nbr.size(), 0);
  tau_.assign(B.nbr.size(), 0);
  multipliers_.assign(12 * n, 0);
  normalization_.assign(n, 0);
  theta_.assign(n, 0);
  fill_state_based_coefficients(in);
  for (uint32_t i : particles_) {
    normalization_[i] = 1;
    if (!s.computes_row(i)) continue;
    std::vector<Vec3> xi;
    std::vector<double> os, od, ws, wd;  // omega of sigma and tau; omega V
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
      const BondKind& b = B.kind_of(k);
      xi.push_back(X[B.nbr[k]] - X[i]);
      const double v = b.volume * b.fraction;
      os.push_back(choice_weight(sigma_choice, b, in.config.horizon));
      od.push_back(choice_weight(tau_choice, b, in.config.horizon));
      ws.push_back(os.back() * v);
      wd.push_back(od.back() * v);
    }
    double* lm = &multipliers_[12 * static_cast<std::size_t>(i)];
    if (!pals::dilatation_multipliers(xi, ws, lm) || !pals::deviatoric_multipliers(xi, wd, lm + 6)) {
      const Vec3& x = X[i];
      throw Error("material '" + mat.name + "': model pals: particle " + std::to_string(i) + " at (" +
                  std::to_string(x.x) + ", " + std::to_string(x.y) + ", " + std::to_string(x.z) + ") has " +
                  std::to_string(xi.size()) +
                  " bonds, too few or too flat for the six constraints of its influence functions (a 6 x 6 system "
                  "that is singular); give a larger horizon");
    }
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
      const std::size_t j = k - B.begin(i);
      sigma_[k] = os[j] * pals::dilatation_factor(lm, xi[j]);
      tau_[k] = od[j] * pals::deviatoric_factor(lm + 6, xi[j]);
    }
  }
}

void Pals::force_state(ForcePass& pass) {
  const System& s = pass.system;
  const auto& B = s.bonds;
  const Point4* y = pass.y;
  Vec3* T = pass.T;
  const std::size_t count = particles_.size();
#pragma omp parallel for schedule(static)
  for (std::size_t q = 0; q < count; ++q) {
    const uint32_t i = particles_[q];
    if (!s.computes_row(i)) continue;  // another rank's row (ModelTraits::rows_local)
    const Point4 pi = y[i];
    const uint64_t first = B.begin(i), last = B.end(i);
    thread_local std::vector<double> ext;
    ext.resize(last - first);
    // theta = sum sigma |xi| e V over the acting bonds (header).
    double theta = 0;
    for (uint64_t k = first; k < last; ++k) {
      const Point4 pj = y[B.nbr[k]];
      const double dx = pj.x - pi.x, dy = pj.y - pi.y, dz = pj.z - pi.z;
      const BondKind& b = B.kind_of(k);
      const double e = std::sqrt(dx * dx + dy * dy + dz * dz) - b.length;
      ext[k - first] = e;
      if (B.intact[k]) theta += kernels::pals_dilatation_term(sigma_[k], b.length, e, b.volume, b.fraction);
    }
    // S = sum tau e^d |xi| V and the deviatoric energy sum tau (e^d)^2 V (kernels/pals.hpp).
    double S = 0, dev = 0;
    for (uint64_t k = first; k < last; ++k) {
      if (!B.intact[k]) continue;
      const BondKind& b = B.kind_of(k);
      const double ed = kernels::deviatoric_extension(ext[k - first], theta, b.length, 3);
      const double v = b.volume * b.fraction;
      S += kernels::pals_shear_term(tau_[k], ed, b.length, v);
      dev += kernels::pals_deviatoric_term(tau_[k], ed, v);
    }
    for (uint64_t k = first; k < last; ++k) {
      if (!B.intact[k]) {
        T[k] = {};
        continue;
      }
      const BondKind& b = B.kind_of(k);
      const double ed = kernels::deviatoric_extension(ext[k - first], theta, b.length, 3);
      const double t = kernels::pals_force_scalar(kappa_, mu_, theta, sigma_[k], tau_[k], b.length, ed, S);
      const Point4 pj = y[B.nbr[k]];
      const Vec3 Y{pj.x - pi.x, pj.y - pi.y, pj.z - pi.z};
      const double r = ext[k - first] + b.length;
      T[k] = r > 0 ? (t / r) * Y : Vec3{};
    }
    theta_[i] = theta;
    if (pass.energy) pass.energy[i] = kernels::pals_energy(kappa_, mu_, theta, dev);
  }
}

void Pals::force_row(const RowPass& pass, std::size_t i, double dilatation_sum) {
  (void)dilatation_sum;  // omega-weighted: PALS weighs theta with sigma instead
  const auto& B = pass.system.bonds;
  kernels::PalsRow<BondKind> a;
  a.kinds = B.kinds.data(), a.kind = B.kind.data(), a.intact = B.intact.data(), a.r = pass.deformed;
  a.sigma = sigma_.data(), a.tau = tau_.data(), a.q = pass.t;
  a.kappa = kappa_, a.mu = mu_;
  const kernels::PalsSums sums = kernels::pals_row(a, B.begin(i), B.end(i));
  theta_[i] = sums.theta;
  if (pass.energy) pass.energy[i] = sums.W;
}

}  // namespace

bool pals_state(Model& m, OrdinaryModelState& out) {
  auto* p = dynamic_cast<Pals*>(&m);
  if (p) p->flat_state(out);
  return p != nullptr;
}

ModelEntry pals_model() {
  return {traits(), [] { return std::unique_ptr<Model>(std::make_unique<Pals>()); }};
}

}  // namespace horizon
