#include "horizon/material/models/linear_lps.hpp"

#include <cmath>

#include "horizon/core/error.hpp"
#include "horizon/kernels/linear_lps.hpp"
#include "horizon/state/system.hpp"

namespace horizon {

namespace {

const ModelTraits& traits() {
  static const ModelTraits t = [] {
    ModelTraits m;
    m.name = "linear_lps";
    m.summary = "the linear peridynamic solid linearised about the reference configuration (Silling et al. 2007, "
                "sec. 15; Silling 2010), Peridigm's Linear LPS";
    m.min_dimension = 2;
    m.rows_local = true;  // row i reads the displacements of i's family alone
    return m;
  }();
  return t;
}

class LinearLps final : public Model {
 public:
  std::unique_ptr<Model> clone() const override { return std::make_unique<LinearLps>(*this); }
  const ModelTraits& traits() const override { return horizon::traits(); }

  void setup(const ModelSetup& in) override {
    const MaterialConfig& mat = in.material;
    dim_ = in.config.dimension;
    if (dim_ == 1) throw Error("material '" + mat.name + "': model linear_lps needs dimension 2 or 3");
    particles_ = in.particles;
    bulk_ = lps_bulk_modulus(mat.bulk_modulus, mat.shear_modulus, in.dims);
    alpha_m_ = lps_deviatoric_factor(dim_) * mat.shear_modulus;
    theta_.assign(in.system.particles.size(), 0);
    // The LPS's spring, contact and critical stretch; a particle without bonds has no force.
    fill_state_based_coefficients(in, 1.0, true);
  }

  void force_state(ForcePass& pass) override {
    const System& s = pass.system;
    const auto& B = s.bonds;
    kernels::LinearLpsRow<BondKind, Point4, Vec3> a;
    a.kinds = B.kinds.data(), a.kind = B.kind.data(), a.nbr = B.nbr.data(), a.intact = B.intact.data();
    a.y = pass.y, a.X = s.particles.X.data(), a.T = pass.T;
    a.bulk = bulk_, a.alpha_m = alpha_m_, a.dim = dim_;
    const std::size_t count = particles_.size();
#pragma omp parallel for schedule(static)
    for (std::size_t q = 0; q < count; ++q) {
      const uint32_t i = particles_[q];
      if (!s.computes_row(i)) continue;  // another rank's row (ModelTraits::rows_local)
      // theta, T and W of the row (kernels/linear_lps.hpp).
      const kernels::LinearLpsSums sums = kernels::linear_lps_row(a, i, B.begin(i), B.end(i), s.model.weighted_volume[i]);
      theta_[i] = sums.theta;
      if (pass.energy) pass.energy[i] = sums.W;
    }
  }

  void fields(const System& s, std::vector<ModelField>& out) const override {
    (void)s;
    out.push_back({"dilatation", theta_});  // the Exodus file's Dilatation (rows compute it here)
  }

 private:
  std::vector<uint32_t> particles_;
  int dim_ = 3;
  double bulk_ = 0, alpha_m_ = 0;
  std::vector<double> theta_;
};

}  // namespace

ModelEntry linear_lps_model() {
  return {traits(), [] { return std::unique_ptr<Model>(std::make_unique<LinearLps>()); }};
}

}  // namespace horizon
