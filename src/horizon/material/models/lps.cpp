#include "horizon/material/models/lps.hpp"

#include "horizon/core/error.hpp"
#include "horizon/solver/system.hpp"

namespace horizon {

namespace {

const ModelTraits& traits() {
  static const ModelTraits t = [] {
    ModelTraits m;
    m.name = "lps";
    m.summary = "linear peridynamic solid, ordinary state-based (Silling et al. 2007, sec. 15)";
    m.min_dimension = 2;
    return m;
  }();
  return t;
}

// A unified model: P_i = theta_i (d k'/m_i - alpha mu/(d m_i)), Q_i = alpha mu/m_i, R = 0
// in the form of solver/system.hpp (the loops compute theta and P each pass).
class Lps final : public Model {
 public:
  std::unique_ptr<Model> clone() const override { return std::make_unique<Lps>(*this); }
  const ModelTraits& traits() const override { return horizon::traits(); }
  bool unified() const override { return true; }

  void setup(const ModelSetup& in) override {
    const MaterialConfig& mat = in.material;
    auto& M = in.system.model;
    const int dim = in.config.dimension;
    if (dim == 1) throw Error("material '" + mat.name + "': the LPS model needs dimension 2 or 3");
    const double kk = lps_bulk_modulus(mat.bulk_modulus, mat.shear_modulus, in.dims);
    const double alpha_mu = lps_deviatoric_factor(dim) * mat.shear_modulus;
    const double spring = 0.5 * equivalent_micromodulus(mat.bulk_modulus, mat.shear_modulus, mat.influence, in.dims);
    // Contact stiffness from the bond-based micromodulus of the same bulk modulus with
    // omega = 1 (18k/(pi delta^4) in 3-D), as LAMMPS peri/lps.
    const double contact_c =
        equivalent_micromodulus(mat.bulk_modulus, mat.shear_modulus, InfluenceKind::constant, in.dims);
    double s0 = std::numeric_limits<double>::infinity();
    if (mat.damage.enabled)
      s0 = mat.damage.critical_stretch
               ? *mat.damage.critical_stretch
               : lps_critical_stretch(*mat.damage.fracture_energy, mat.bulk_modulus, mat.shear_modulus, in.dims);
    for (uint32_t i : in.particles) {
      const double m = M.weighted_volume[i];
      if (m <= 0)
        throw Error("particle " + std::to_string(i) + " has no neighbours: the horizon is smaller than the spacing");
      M.dilatation_coef[i] = dim * kk / m;
      M.deviatoric_coef[i] = alpha_mu / m;
      M.spring[i] = spring;
      M.contact_micromodulus[i] = contact_c;
      M.critical_stretch[i] = s0;
      M.alpha[i] = mat.damage.enabled ? mat.damage.alpha : 0.0;
    }
    M.state_based = true;
  }
};

}  // namespace

ModelEntry lps_model() {
  return {traits(), [] { return std::unique_ptr<Model>(std::make_unique<Lps>()); }};
}

}  // namespace horizon
