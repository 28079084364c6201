#include "horizon/solver/system.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "horizon/core/error.hpp"
#include "horizon/family/neighbors.hpp"
#include "horizon/family/precrack.hpp"
#include "horizon/geometry/lattice.hpp"
#include "horizon/material/constants.hpp"
#include "horizon/material/influence.hpp"
#include "horizon/solver/forces.hpp"
#include "horizon/solver/forces_nonlinear.hpp"

namespace horizon {

void reset_model_arrays(ModelCoefficients& M, std::size_t n) {
  M.dilatation_coef.assign(n, 0);
  M.deviatoric_coef.assign(n, 0);
  M.pair_coef.assign(n, 0);
  M.theta.assign(n, 0);
  M.P.assign(n, 0);
  M.spring.assign(n, 0);
  M.critical_stretch.assign(n, std::numeric_limits<double>::infinity());
  M.alpha.assign(n, 0);
  M.min_stretch.assign(n, 0);
  M.contact_micromodulus.assign(n, 0);
  M.state_based = false;
  M.break_after_force = false;
}

namespace {

Dimensioning dimensioning(const Config& c) {
  return {c.dimension, c.plane, c.thickness, c.area, c.horizon};
}

double cell_volume(const Config& c) {
  double v = std::pow(c.spacing, c.dimension);
  if (c.dimension == 2) v *= c.thickness;
  if (c.dimension == 1) v *= c.area;
  return v;
}

}  // namespace

System build_system(const Config& config) {
  System s;
  s.dimension = config.dimension;
  s.horizon = config.horizon;
  s.spacing = config.spacing;

  LatticeSpec spec{config.dimension, config.spacing, cell_volume(config), config.lattice_origin};
  for (std::size_t b = 0; b < config.bodies.size(); ++b) {
    const auto& body = config.bodies[b];
    int mat = -1;
    for (std::size_t m = 0; m < config.materials.size(); ++m)
      if (config.materials[m].name == body.material) mat = static_cast<int>(m);
    if (mat < 0) throw Error("body '" + body.name + "' names unknown material '" + body.material + "'");
    const std::size_t added = fill_shape(s.particles, body.shape, spec, config.materials[mat].density,
                                         static_cast<int32_t>(b), mat);
    if (added == 0)
      throw Error("body '" + body.name + "' contains no lattice point: its shape is smaller than the spacing " +
                  std::to_string(config.spacing) + " m or lies outside the lattice");
    s.block_names.push_back(body.name);
  }

  for (const auto& name : config.no_fail_regions) {
    const Shape& region = config.regions.at(name);
    for (std::size_t i = 0; i < s.particles.size(); ++i)
      if (region.contains(s.particles.X[i])) s.particles.no_fail[i] = 1;
  }

  s.bonds = find_neighbors(s.particles.X, s.particles.volume,
                           family_radius(config.horizon, config.spacing, config.partial_volume.rule),
                           &s.particles.material);
  if (config.partial_volume) apply_partial_volume(s.bonds, config.horizon, config.spacing);
  s.precrack_bonds = cut_bonds(s.bonds, s.particles.X, config.precracks, config.dimension);
  s.initial_bonds = s.bonds.size();
  setup_model(s, config.materials, config);
  return s;
}

void setup_model(System& s, const std::vector<MaterialConfig>& materials, const Config& config) {
  for (const auto& mat : materials)
    if (mat.model == ModelKind::nonlinear_solid) return setup_nonlinear(s, materials, config);
  s.nonlinear = NonlinearState{};
  const Dimensioning dims = dimensioning(config);
  const std::size_t n = s.particles.size();
  auto& P = s.particles;
  auto& B = s.bonds;
  auto& M = s.model;
  M.dim = config.dimension;

  // Influence weights, per bond kind (kinds carry the materials of both ends): the
  // average of the two ends' functions keeps omega_ij = omega_ji.
  split_kinds_by_material(B, P.material);
  for (auto& c : B.kinds) {
    c.weight = 0.5 * (influence(materials[c.material_i].influence, c.length, config.horizon) +
                      influence(materials[c.material_j].influence, c.length, config.horizon));
  }

  M.weighted_volume.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i)
    for (uint64_t k = B.begin(i); k < B.end(i); ++k)
      M.weighted_volume[i] += B.weight[k] * B.length[k] * B.length[k] * B.volume[k];

  reset_model_arrays(M, n);
  s.dissipated_at.assign(n, 0);

  // Constants per material, then copied to its particles.
  struct Constants {
    double pair = 0, kk = 0, alpha_mu = 0, spring = 0, s0 = std::numeric_limits<double>::infinity();
    double alpha = 0, contact_c = 0;
  };
  std::vector<Constants> constants(materials.size());
  for (std::size_t m = 0; m < materials.size(); ++m) {
    const auto& mat = materials[m];
    Constants& c = constants[m];
    if (mat.model == ModelKind::pmb) {
      const double cc = mat.micromodulus ? *mat.micromodulus : pmb_micromodulus(mat.youngs_modulus, mat.influence, dims);
      c.contact_c = cc;
      c.pair = 0.5 * cc;
      c.spring = 0.5 * cc;
      if (mat.damage.enabled)
        c.s0 = mat.damage.critical_stretch ? *mat.damage.critical_stretch
                                           : pmb_critical_stretch(*mat.damage.fracture_energy, cc, mat.influence, dims);
    } else {
      if (config.dimension == 1) throw Error("material '" + mat.name + "': the LPS model needs dimension 2 or 3");
      c.kk = lps_bulk_modulus(mat.bulk_modulus, mat.shear_modulus, dims);
      c.alpha_mu = lps_deviatoric_factor(config.dimension) * mat.shear_modulus;
      c.spring = 0.5 * equivalent_micromodulus(mat.bulk_modulus, mat.shear_modulus, mat.influence, dims);
      // Contact stiffness from the bond-based micromodulus of the same bulk modulus with
      // omega = 1 (18k/(pi delta^4) in 3-D), as LAMMPS peri/lps.
      c.contact_c = equivalent_micromodulus(mat.bulk_modulus, mat.shear_modulus, InfluenceKind::constant, dims);
      if (mat.damage.enabled)
        c.s0 = mat.damage.critical_stretch
                   ? *mat.damage.critical_stretch
                   : lps_critical_stretch(*mat.damage.fracture_energy, mat.bulk_modulus, mat.shear_modulus, dims);
      M.state_based = true;
    }
  }
  M.break_after_force = false;
  for (std::size_t m = 0; m < materials.size(); ++m)
    if (materials[m].damage.enabled) {
      constants[m].alpha = materials[m].damage.alpha;
      M.break_after_force = M.break_after_force || materials[m].damage.break_after_force;
    }
  for (std::size_t i = 0; i < n; ++i) {
    const Constants& c = constants[P.material[i]];
    M.alpha[i] = c.alpha;
    M.contact_micromodulus[i] = c.contact_c;
    M.pair_coef[i] = c.pair;
    M.spring[i] = c.spring;
    M.critical_stretch[i] = c.s0;
    if (c.kk > 0) {
      const double m = M.weighted_volume[i];
      if (m <= 0)
        throw Error("particle " + std::to_string(i) + " has no neighbours: the horizon is smaller than the spacing");
      M.dilatation_coef[i] = config.dimension * c.kk / m;
      M.deviatoric_coef[i] = c.alpha_mu / m;
    }
  }
  s.contact.setup(config.contact.short_range, config.spacing, config.horizon);
  build_kind_coefficients(s, config.output.damage_measure);
}

double System::dissipated() const {
  double sum = 0;
  for (double d : dissipated_at) sum += d;
  return sum;
}

double stable_time_step(const System& s) {
  if (s.nonlinear.enabled) return nonlinear_stable_time_step(s);
  const auto& P = s.particles;
  const auto& B = s.bonds;
  double dt = std::numeric_limits<double>::infinity();
#pragma omp parallel for schedule(static) reduction(min : dt)
  for (std::size_t i = 0; i < P.size(); ++i) {
    double sum = 0;
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
      const uint32_t j = B.nbr[k];
      sum += B.volume[k] * B.weight[k] * (s.model.spring[i] + s.model.spring[j]) / B.length[k];
    }
    if (sum > 0) dt = std::min(dt, std::sqrt(2 * P.density[i] / sum));
  }
  return dt;
}

std::size_t memory_estimate(const System& s) {
  const std::size_t n = s.particles.size(), nb = s.bonds.size();
  // Particles, model arrays (12 doubles), the force pass's scratch (4 + 1 doubles).
  const std::size_t per_particle = 5 * sizeof(Vec3) + 4 * sizeof(double) + 2 * sizeof(int32_t) + sizeof(int64_t) + 1 +
                                   17 * sizeof(double) + sizeof(uint64_t);
  // Neighbour, kind, intact flag; reference data per kind (family/bonds.hpp).
  // State-based models keep each bond's |Y| between their two passes (8 bytes more).
  const std::size_t per_bond = 2 * sizeof(uint32_t) + sizeof(uint8_t) + (s.model.state_based ? sizeof(double) : 0);
  const std::size_t kinds = s.bonds.kinds.size() * (sizeof(BondKind) + sizeof(KindCoefficients));
  return n * per_particle + nb * per_bond + kinds;
}

}  // namespace horizon
