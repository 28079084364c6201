#include "horizon/material/models/linear_lps.hpp"

#include <cmath>

#include "horizon/core/error.hpp"
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
    const auto& X = s.particles.X;
    const Point4* y = pass.y;
    Vec3* T = pass.T;
    const std::size_t count = particles_.size();
    const double d = dim_;
#pragma omp parallel for schedule(static)
    for (std::size_t q = 0; q < count; ++q) {
      const uint32_t i = particles_[q];
      if (!s.computes_row(i)) continue;  // another rank's row (ModelTraits::rows_local)
      const uint64_t first = B.begin(i), last = B.end(i);
      const double m = s.model.weighted_volume[i];
      // eta . xi/|xi| = (Y - xi) . xi/|xi| with Y the current bond.
      auto extension = [&](uint64_t k, const Vec3& xi, double length) {
        const Point4 pi = y[i], pj = y[B.nbr[k]];
        const Vec3 Y{pj.x - pi.x, pj.y - pi.y, pj.z - pi.z};
        return dot(Y - xi, xi) / length;
      };
      double sum = 0;
      for (uint64_t k = first; k < last; ++k) {
        if (!B.intact[k]) continue;
        const BondKind& b = B.kind_of(k);
        sum += b.weight * b.volume * b.fraction * b.length * extension(k, X[B.nbr[k]] - X[i], b.length);
      }
      const double theta = m > 0 ? d * sum / m : 0.0;
      const double alpha = m > 0 ? alpha_m_ / m : 0.0;
      const double p = m > 0 ? d * bulk_ * theta / m : 0.0;
      double dev = 0;
      for (uint64_t k = first; k < last; ++k) {
        if (!B.intact[k]) {
          T[k] = {};
          continue;
        }
        const BondKind& b = B.kind_of(k);
        const Vec3 xi = X[B.nbr[k]] - X[i];
        const double ed = extension(k, xi, b.length) - theta * b.length / d;
        dev += b.weight * b.volume * b.fraction * ed * ed;
        const double t = p * b.weight * b.length + alpha * b.weight * ed;
        T[k] = (t / b.length) * xi;
      }
      theta_[i] = theta;
      if (pass.energy) pass.energy[i] = 0.5 * bulk_ * theta * theta + 0.5 * alpha * dev;
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
