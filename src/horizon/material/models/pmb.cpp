#include "horizon/material/models/pmb.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <map>

#include "horizon/family/neighbors.hpp"
#include "horizon/material/influence.hpp"
#include "horizon/solver/system.hpp"

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
         "true: force normalisation near surfaces, c_i = c p_inf/p_i with p the largest eigenvalue of the "
         "particle's stiffness tensor (seed 002 eq. 35-36), the mean of the two ends per bond",
         ParameterSpec::Range::boolean, 0.0},
    };
    m.thermal_strain = true;  // in the general force pass (solver/forces_general.cpp)
    return m;
  }();
  return t;
}

// The largest eigenvalue of the nodal stiffness tensor of a PMB particle (seed 002 eq. 35;
// discrete form, digest sec. 4): P = sum_j omega c xi xi^T/|xi|^3 v_j, here with c = 1
// (only the ratio p_inf/p matters).
double largest_stiffness(const std::vector<Vec3>& xi, const std::vector<double>& weight_volume) {
  Eigen::Matrix3d P = Eigen::Matrix3d::Zero();
  for (std::size_t k = 0; k < xi.size(); ++k) {
    const Eigen::Vector3d x(xi[k].x, xi[k].y, xi[k].z);
    const double L = x.norm();
    P += (weight_volume[k] / (L * L * L)) * x * x.transpose();
  }
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(P, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff();
}

// p_inf from an interior particle of the same lattice (digest sec. 4: so that the
// lattice's own discretisation error cancels): the centre of a block of lattice points
// with the deck's spacing, family radius, partial-volume rule and influence function.
double interior_stiffness(const Config& cfg, const MaterialConfig& mat) {
  const int d = cfg.dimension;
  const double h = cfg.spacing;
  const double radius = family_radius(cfg.horizon, h, cfg.partial_volume.rule);
  const int n = static_cast<int>(std::ceil(radius / h)) + 1;
  double cell = std::pow(h, d);
  if (d == 2) cell *= cfg.thickness;
  if (d == 1) cell *= cfg.area;
  std::vector<Vec3> points;
  std::size_t centre = 0;
  for (int k = (d > 2 ? -n : 0); k <= (d > 2 ? n : 0); ++k)
    for (int j = (d > 1 ? -n : 0); j <= (d > 1 ? n : 0); ++j)
      for (int i = -n; i <= n; ++i) {
        if (i == 0 && j == 0 && k == 0) centre = points.size();
        points.push_back(Vec3{i * h, j * h, k * h});
      }
  Bonds ref = find_neighbors(points, std::vector<double>(points.size(), cell), radius);
  if (cfg.partial_volume) apply_partial_volume(ref, cfg.horizon, h);
  std::vector<Vec3> xi;
  std::vector<double> wv;
  for (uint64_t k = ref.begin(centre); k < ref.end(centre); ++k) {
    const BondKind& b = ref.kind_of(k);
    xi.push_back(points[ref.nbr[k]] - points[centre]);
    wv.push_back(influence(mat.influence, b.length, cfg.horizon) * b.volume * b.fraction);
  }
  return largest_stiffness(xi, wv);
}

// Per-particle factors p_inf/p_i of the surface correction, grouped into classes of equal
// factor (to 1e-9) so that the bonds of one kind share their ends' coefficients
// (family/bonds.hpp; the force loops read a kind's pair coefficient once). Splits the
// bond kinds by class; returns the factor of each particle (1 for the others).
std::vector<double> surface_factors(const ModelSetup& in) {
  System& s = in.system;
  auto& B = s.bonds;
  const auto& X = s.particles.X;
  const double p_inf = interior_stiffness(in.config, in.material);
  std::vector<double> factor(X.size(), 1.0);
  std::vector<Vec3> xi;
  std::vector<double> wv;
  for (uint32_t i : in.particles) {
    xi.clear();
    wv.clear();
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
      const BondKind& b = B.kind_of(k);
      xi.push_back(X[B.nbr[k]] - X[i]);
      wv.push_back(b.weight * b.volume * b.fraction);
    }
    const double p = xi.empty() ? 0.0 : largest_stiffness(xi, wv);
    factor[i] = p > 0 ? p_inf / p : 1.0;
  }
  // Classes: the particles' current classes (another material's), this material's anew.
  std::vector<int32_t> cls(X.size(), 0);
  for (std::size_t i = 0; i < X.size(); ++i)
    if (B.begin(i) < B.end(i)) cls[i] = B.kind_of(B.begin(i)).class_i;
  std::map<long long, int32_t> index;
  std::vector<double> representative;
  for (uint32_t i : in.particles) {
    const long long key = std::llround(factor[i] * 1e9);
    auto it = index.find(key);
    if (it == index.end()) {
      it = index.emplace(key, static_cast<int32_t>(representative.size())).first;
      representative.push_back(factor[i]);
    }
    factor[i] = representative[static_cast<std::size_t>(it->second)];
    cls[i] = ((in.material_index + 1) << 20) + it->second;
  }
  split_kinds_by_class(B, cls);
  return factor;
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
    // Surface correction (seed 002 eq. 36): c_i = c p_inf/p_i; a bond's pair coefficient
    // R_i + R_j is then the mean (c_i + c_j)/2, symmetric as eq. 5 needs.
    const std::vector<double> factor = Model::parameter(mat, "surface_correction") != 0
                                           ? surface_factors(in)
                                           : std::vector<double>(in.system.particles.size(), 1.0);
    for (uint32_t i : in.particles) {
      M.pair_coef[i] = 0.5 * c * factor[i];
      M.spring[i] = 0.5 * c * factor[i];
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
