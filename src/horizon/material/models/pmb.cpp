#include "horizon/material/models/pmb.hpp"

#include <cmath>

#include "horizon/material/surface_correction.hpp"
#include "horizon/state/system.hpp"

namespace horizon {

namespace {

const ModelTraits& traits() {
  static const ModelTraits t = [] {
    ModelTraits m;
    m.name = "pmb";
    m.summary = "prototype microelastic brittle, bond-based (Silling and Askari 2005)";
    m.elastic = ElasticInput::one_modulus;
    m.parameters = {
        {"surface_correction",
         "true: energy-based correction near free surfaces (Madenci and Oterkus 2014 sec. 4.2): per-axis "
         "factors W_inf/W_i from uniform strains, a bond's from its ends' by the ellipse rule, applied to the "
         "bond's influence weight",
         ParameterSpec::Range::boolean, 0.0},
    };
    m.thermal_strain = true;  // in the general force pass (solver/forces_general.cpp)
    m.unified = true;  // its force state has the unified form (Model::unified)
    return m;
  }();
  return t;
}

// The PMB's energy density under a uniaxial stress along `axis` (strain 1 along it, -nu
// across, nu the bond-based material's 1/4 or 1/3 in plane stress), any constant factor:
// the bond stretch is s = n_a^2 - nu (1 - n_a^2) and w_i = sum_j c s^2 |xi| omega V_j / 4
// (the PMB bond's micropotential c s^2 |xi|/2, half to each end), here with c/4 = 1.
// Uniaxial stress, not the uniaxial strain of Madenci and Oterkus: measured on the thin
// plate of docs/verification.md, the strain measure leaves +2.4 %, the stress one -0.8 %.
double axis_energy(const FamilyView& f, int axis, double lateral) {
  double w = 0;
  for (std::size_t k = 0; k < f.xi.size(); ++k) {
    const double L2 = dot(f.xi[k], f.xi[k]);
    const double na = f.xi[k][axis] * f.xi[k][axis] / L2;
    const double s = na - lateral * (1 - na);
    w += f.wv[k] * s * s * std::sqrt(L2);
  }
  return w;
}

// A unified model: R_i = c/2, P = Q = 0 in the form of state/system.hpp.
class Pmb final : public Model {
 public:
  std::unique_ptr<Model> clone() const override { return std::make_unique<Pmb>(*this); }
  const ModelTraits& traits() const override { return horizon::traits(); }

  void setup(const ModelSetup& in) override {
    const MaterialConfig& mat = in.material;
    auto& M = in.system.model;
    const double c = mat.micromodulus ? *mat.micromodulus : pmb_micromodulus(mat.youngs_modulus, mat.influence, in.dims);
    double s0 = std::numeric_limits<double>::infinity();
    if (mat.damage.enabled)
      s0 = mat.damage.critical_stretch ? *mat.damage.critical_stretch
                                       : pmb_critical_stretch(*mat.damage.fracture_energy, c, mat.influence, in.dims);
    // Surface correction (material/surface_correction.hpp): the bonds' influence weights
    // take the energy method's factors; c itself stays.
    // The reference is the continuum: the PMB lattice with delta = 3h and partial volumes
    // is itself 7.0 % stiffer than E inside (docs/verification.md), which a lattice
    // reference would keep (the plate then ends at +7.0 %).
    if (Model::parameter(mat, "surface_correction") != 0) {
      const double nu = bond_based_poisson_ratio(in.dims.dimension, in.dims.plane);
      const AxisEnergy energy = [nu](const FamilyView& f, int axis) { return axis_energy(f, axis, nu); };
      apply_axis_factors(in, axis_factors(in, energy, kSurfacePasses, Reference::continuum));
    }
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
