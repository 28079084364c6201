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
    m.thermal_strain = true;  // in the general force pass (solver/forces_general.cpp)
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
    fill_state_based_coefficients(in);
    for (uint32_t i : in.particles) {
      M.dilatation_coef[i] = dim * kk / M.weighted_volume[i];
      M.deviatoric_coef[i] = alpha_mu / M.weighted_volume[i];
    }
  }
};

}  // namespace

ModelEntry lps_model() {
  return {traits(), [] { return std::unique_ptr<Model>(std::make_unique<Lps>()); }};
}

}  // namespace horizon
