#include "horizon/material/models/pmb.hpp"

#include "horizon/solver/system.hpp"

namespace horizon {

namespace {

const ModelTraits& traits() {
  static const ModelTraits t = [] {
    ModelTraits m;
    m.name = "pmb";
    m.summary = "prototype microelastic brittle, bond-based (Silling and Askari 2005)";
    m.elastic = ElasticInput::one_modulus;
    m.thermal_strain = true;  // in the general force pass (solver/forces_general.cpp)
    return m;
  }();
  return t;
}

// A unified model: R_i = c/2, P = Q = 0 in the form of solver/system.hpp.
class Pmb final : public Model {
 public:
  std::unique_ptr<Model> clone() const override { return std::make_unique<Pmb>(*this); }
  const ModelTraits& traits() const override { return horizon::traits(); }
  bool unified() const override { return true; }

  void setup(const ModelSetup& in) override {
    const MaterialConfig& mat = in.material;
    auto& M = in.system.model;
    const double c = mat.micromodulus ? *mat.micromodulus : pmb_micromodulus(mat.youngs_modulus, mat.influence, in.dims);
    double s0 = std::numeric_limits<double>::infinity();
    if (mat.damage.enabled)
      s0 = mat.damage.critical_stretch ? *mat.damage.critical_stretch
                                       : pmb_critical_stretch(*mat.damage.fracture_energy, c, mat.influence, in.dims);
    for (uint32_t i : in.particles) {
      M.pair_coef[i] = 0.5 * c;
      M.spring[i] = 0.5 * c;
      M.contact_micromodulus[i] = c;
      M.critical_stretch[i] = s0;
      M.alpha[i] = mat.damage.enabled ? mat.damage.alpha : 0.0;
    }
  }
};

}  // namespace

ModelEntry pmb_model() {
  return {traits(), [] { return std::unique_ptr<Model>(std::make_unique<Pmb>()); }};
}

}  // namespace horizon
