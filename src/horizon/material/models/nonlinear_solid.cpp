#include "horizon/material/models/nonlinear_solid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "horizon/core/error.hpp"
#include "horizon/family/neighbors.hpp"
#include "horizon/material/constants.hpp"
#include "horizon/material/influence.hpp"
#include "horizon/material/model.hpp"
#include "horizon/parallel/decomposition.hpp"
#include "horizon/state/owned_rows.hpp"
#include "horizon/material/surface_correction.hpp"
#include "horizon/state/system.hpp"

namespace horizon {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Removes the bonds whose ends lie in different bodies: separate bodies (a projectile
// and its target) meet through contact, never through bonds.
std::size_t drop_bonds_between_bodies(Bonds& b, const std::vector<int32_t>& block) {
  return rewrite_bonds(b, [&](std::size_t i, uint64_t k) {
    return block[b.nbr[k]] != block[i] ? BondAction::drop : BondAction::keep;
  });
}

// The rows a pass computes: every particle's serially, the owned ones on a rank of a
// decomposed run (parallel/decomposition.hpp). The model owns its force pass, so it
// does not compute the bond neighbours' rows that System::active_rows adds for the
// general pass: the one thing row i reads of a neighbour j beyond positions, theta_j
// (and S_j of the stable step), is computed by j's owner from j's own row and sent to
// the ranks that hold j as a ghost. Each bond's flag is decided by the row that holds it
// from both ends' theta, the same bits on every rank, so no per-bond state crosses ranks.
using Rows = OwnedRows;  // state/owned_rows.hpp

// The owners' values of the per-particle scalar `a` at this rank's ghosts (the halo of
// the displacements, parallel/decomposition.hpp exchange_ghost_values, one component
// used). Collective in a decomposed run; nothing serially.
void exchange_ghost_scalars(const System& s, std::vector<double>& a, std::vector<Vec3>& scratch) {
  if (!s.decomposition || s.decomposition->size == 1) return;
  scratch.resize(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) scratch[i] = {a[i], 0.0, 0.0};
  exchange_ghost_values(*s.decomposition, scratch);
  for (std::size_t i = 0; i < a.size(); ++i) a[i] = scratch[i].x;
}

const ModelTraits& traits() {
  static const ModelTraits t = [] {
    ModelTraits m;
    m.name = "nonlinear_solid";
    m.aliases = {"tupek"};
    m.summary = "Tupek's nonlinear ordinary solid with brittle energy failure (seed 000, thesis ch. 5-6)";
    m.min_dimension = 2;
    m.critical_stretch_law = false;
    m.energy_law = true;
    m.exclusive = true;
    m.adaptive_time_step = true;
    // Split over MPI ranks by its own pass (force_pass below): each rank computes the rows
    // of the particles it owns and receives its ghosts' theta from their owners.
    m.rows_local = true;
    m.influences = {InfluenceKind::tupek};
    m.default_influence = InfluenceKind::tupek;
    m.parameters = {
        {"seth_hill_m", "Seth-Hill parameter m of the bond strain (thesis eq. 4.2); 0: the log strain",
         ParameterSpec::Range::any, 0.0},
        {"fracture", "false: bonds of this material never break (a projectile)", ParameterSpec::Range::boolean, 1.0},
        {"surface_correction",
         "true: correction near free surfaces: bond influence weights from per-axis factors that make the "
         "mu_bar energy of uniaxial stresses that of the continuum (the energy method's ellipse rule, Madenci "
         "and Oterkus 2014 sec. 4.2), and a per-particle factor on lambda_bar for the dilatation energy",
         ParameterSpec::Range::boolean, 0.0},
    };
    return m;
  }();
  return t;
}

// The surface correction of the nonlinear solid (docs/models.md "Surface correction"). Its
// small-strain energy (thesis eq. 5.1 with eq. 6.8) is
//   W_i = lambda_bar_i theta_i^2 / 2 + mu_bar_i sum_j omega eps^2 V_j,  theta_i = sum_j omega eps V_j,
// with the influence function normalised in the bulk (int omega = 3, or 2 in 2-D) and NOT
// renormalised near surfaces (thesis sec. 6.1.3): a truncated family stores less energy,
// like a PMB particle (it is not the LPS, whose theta is normalised by each particle's own
// weighted volume and whose surface layers are stiffer). The two terms scale differently
// with the weights (mu_bar: linearly; lambda_bar: as their square), so the correction has
// two steps, as the LPS's (Madenci and Oterkus 2014 sec. 4.2, the energy method; Le and
// Bobaru 2018 compare such corrections):
//   1. bond factors g_ij (material/surface_correction.hpp) from the mu_bar term's energy
//      of a uniaxial stress along each axis, sum_j omega g s^2 V_j, s = n_d^2 - nu' (1 -
//      n_d^2) the small-strain bond strain (eps = e/|xi| for every Seth-Hill m), against
//      the continuum's (the integrals that calibrate mu_bar, thesis sec. 5.1): the PMB's
//      measure with this model's weights;
//   2. a per-particle factor on lambda_bar, the continuum's dilatation energy over the
//      particle's, sum_d theta_d^2 over the uniaxial stresses along the axes, with the
//      corrected weights (theta enters the energy squared, so a factor on lambda_bar is
//      the energy-consistent way to scale it per particle).
// At nu = 1/4 in 3-D, lambda_bar = lambda - mu = 0 and step 2 does nothing.

// The small-strain bond strain of a uniaxial stress along `axis` (strain 1 along it, -nu'
// across), n the bond direction.
inline double uniaxial_bond_strain(const Vec3& xi, int axis, double nu) {
  const double n2 = xi[axis] * xi[axis] / dot(xi, xi);
  return n2 - nu * (1 - n2);
}

// mu_bar's term of W over mu_bar: sum omega V eps^2.
double mu_term(const FamilyView& f, int axis, double nu) {
  double w = 0;
  for (std::size_t k = 0; k < f.xi.size(); ++k) {
    const double e = uniaxial_bond_strain(f.xi[k], axis, nu);
    w += f.wv[k] * e * e;
  }
  return w;
}

// theta of the same deformation: sum omega V eps.
double dilatation(const FamilyView& f, int axis, double nu) {
  double t = 0;
  for (std::size_t k = 0; k < f.xi.size(); ++k) t += f.wv[k] * uniaxial_bond_strain(f.xi[k], axis, nu);
  return t;
}

double dilatation_energy(const FamilyView& f, int dim, double nu) {
  double w = 0;
  for (int a = 0; a < dim; ++a) w += dilatation(f, a, nu) * dilatation(f, a, nu);
  return w;
}

class NonlinearSolid final : public Model {
 public:
  std::unique_ptr<Model> clone() const override { return std::make_unique<NonlinearSolid>(*this); }
  const ModelTraits& traits() const override { return horizon::traits(); }
  bool owns_force_pass() const override { return true; }
  void setup(const ModelSetup& in) override;
  uint64_t force_pass(System& s, bool energy) override;
  double stable_time_step(const System& s) const override;
  void hold_bonds(bool hold) override {
    if (hold) {
      saved_beta_.assign(N.beta.size(), kInf);
      std::swap(N.beta, saved_beta_);
    } else {
      std::swap(N.beta, saved_beta_);
    }
  }
  void fields(const System& s, std::vector<ModelField>& out) const override {
    // Tupek's nonlocal damage D (thesis eq. 6.12), > 0 at free surfaces.
    (void)s;
    out.push_back({"nonlocal_damage", N.nonlocal_damage});
  }
  NonlinearState N;

  // theta, the nonlocal damage and the contact springs are per particle, computed by the
  // particle's owner in a decomposed run; the bond strains belong to the rows (a
  // checkpoint gathers both from their owners, output/checkpoint.hpp).
  void checkpoint(StateArchive& a) override {
    a.io("compression_only", N.compression_only);
    a.io_particles("theta", N.theta);
    a.io_particles("nonlocal_damage", N.nonlocal_damage);
    a.io_bonds("bond_strain", N.bond_strain);
    a.io_particles("contact_stiffness", N.contact_stiffness);
    a.io("last_stable_dt", N.last_stable_dt);
    a.io("saved_beta", saved_beta_);
    a.io("beta", N.beta);
  }
 private:
  std::vector<double> saved_beta_;
  mutable std::vector<Vec3> scratch_;  // exchange_ghost_scalars
};

}  // namespace

ModelEntry nonlinear_solid_model() {
  return {traits(), [] { return std::unique_ptr<Model>(std::make_unique<NonlinearSolid>()); }};
}

const NonlinearState* nonlinear_state(const System& s) {
  const auto* m = dynamic_cast<const NonlinearSolid*>(s.models.owner());
  return m ? &m->N : nullptr;
}
NonlinearState* nonlinear_state(System& s) {
  auto* m = dynamic_cast<NonlinearSolid*>(s.models.owner());
  return m ? &m->N : nullptr;
}

// Removes the bonds between bodies, sets the normalised influence weights, the Lame
// constants, beta and the contact data for every particle of the run (the model is
// exclusive: every material is a nonlinear solid).
void NonlinearSolid::setup(const ModelSetup& in) {
  System& s = in.system;
  const Config& config = in.config;
  const std::vector<MaterialConfig>& materials = config.materials;
  for (const auto& m : materials)
    if (!find_model(m.model) || find_model(m.model)->traits.name != "nonlinear_solid")
      throw Error("material '" + m.name + "' (model " + m.model +
                  ") cannot share a run with model nonlinear_solid: bodies of the nonlinear solid interact only "
                  "with nonlinear_solid bodies");
  if (config.dimension == 1) throw Error("model nonlinear_solid needs dimension 2 or 3");
  auto& P = s.particles;
  auto& B = s.bonds;
  auto& M = s.model;
  const std::size_t n = P.size();
  const int dim = config.dimension;

  drop_bonds_between_bodies(B, P.block);
  s.initial_bonds = B.size();
  split_kinds_by_material(B, P.material);
  // omega V_j must integrate over the area in 2-D: V_j = A_j t, so the weight is omega/t.
  const double per = dim == 2 ? 1.0 / config.thickness : 1.0;
  // The normalisation of (6.6)/(6.7) over the shape that influence() gives (the one the
  // surface correction's reference families use), a constant.
  const double half = 0.5 * config.horizon;
  const double normalisation =
      tupek_influence(half, config.horizon, dim) / influence(InfluenceKind::tupek, half, config.horizon) * per;
  for (auto& c : B.kinds) c.weight = influence(InfluenceKind::tupek, c.length, config.horizon);

  // The generic model arrays, neutral (other code reads their sizes).
  M.dim = dim;
  M.weighted_volume.assign(n, 0);
  reset_model_arrays(M, n);

  // Surface correction, per material that asks for it (the measures are ratios to the
  // continuum's, so the shape's constant cancels; the weights are normalised after).
  const Dimensioning dims{config.dimension, config.plane, config.thickness, config.area, config.horizon};
  std::vector<double> lambda_factor(n, 1.0);
  for (std::size_t q = 0; q < materials.size(); ++q) {
    const MaterialConfig& mat = materials[q];
    if (Model::parameter(mat, "surface_correction") == 0) continue;
    // The lateral strain of a uniaxial stress: -nu, or -nu/(1 - nu) in plane strain.
    const double nu = dim == 2 && config.plane == PlaneMode::strain ? mat.poissons_ratio / (1 - mat.poissons_ratio)
                                                                     : mat.poissons_ratio;
    std::vector<uint32_t> members;
    for (uint32_t i = 0; i < n; ++i)
      if (P.material[i] == static_cast<int>(q)) members.push_back(i);
    const ModelSetup sub{s, config, mat, static_cast<int>(q), members, dims};
    const AxisEnergy energy = [nu](const FamilyView& f, int axis) { return mu_term(f, axis, nu); };
    apply_axis_factors(sub, axis_factors(sub, energy, kSurfacePasses, Reference::continuum));
    const double w_inf = dilatation_energy(continuum_family(config, mat), dim, nu);
    for (uint32_t i : members) {
      const double w = dilatation_energy(family_of(s, i), dim, nu);
      if (w > 0) lambda_factor[i] = w_inf / w;
    }
  }
  for (auto& c : B.kinds) c.weight *= normalisation;
  M.weighted_volume.assign(n, 0);  // apply_axis_factors filled it; the model does not use it
  M.state_based = true;  // forces reach two horizons (through theta_j): the tangent probes that far
  s.dissipated_at.assign(n, 0);

  N = NonlinearState{};
  N.enabled = true;
  N.dimension = dim;
  N.lambda_bar.assign(n, 0);
  N.mu_bar.assign(n, 0);
  N.m.assign(n, 0);
  N.beta.assign(n, kInf);
  N.compression_only.assign(n, 1);
  N.theta.assign(n, 0);
  N.nonlocal_damage.assign(n, 0);
  N.bond_strain.assign(B.size(), 0);
  N.contact_stiffness.assign(n, 0);
  N.adaptive_every = config.solver.adaptive_time_step ? std::max(1, config.solver.adaptive_every) : 0;

  // One bond-failure-energy exponent p for the run (s_c = beta omega |xi|^-p): bonds join
  // materials, and the pair criterion compares both ends against one s_c.
  auto fracture = [](const MaterialConfig& m) { return Model::parameter(m, "fracture") != 0; };
  const MaterialConfig* first = nullptr;
  for (const auto& m : materials) {
    if (!(fracture(m) && m.damage.enabled)) continue;
    if (!first) first = &m;
    if (m.damage.failure_length_exponent != first->damage.failure_length_exponent)
      throw Error("materials '" + first->name + "' and '" + m.name +
                  "' give different damage.failure_length_exponent: one run uses one bond-failure-energy function");
  }
  const double exponent = first ? first->damage.failure_length_exponent : 2.0;
  N.failure_exponent_two = exponent == 2;
  N.failure_scale.assign(B.kinds.size(), 0);
  for (std::size_t q = 0; q < B.kinds.size(); ++q) N.failure_scale[q] = std::pow(B.kinds[q].length, -exponent);

  for (std::size_t i = 0; i < n; ++i) {
    const MaterialConfig& mat = materials[P.material[i]];
    const TupekLame l = tupek_lame(mat.youngs_modulus, mat.poissons_ratio, dim, config.plane == PlaneMode::stress);
    N.lambda_bar[i] = l.lambda_bar * lambda_factor[i];
    N.mu_bar[i] = l.mu_bar;
    N.m[i] = Model::parameter(mat, "seth_hill_m");
    if (fracture(mat) && mat.damage.enabled && mat.damage.fracture_energy && !P.no_fail[i])
      N.beta[i] = tupek_beta(*mat.damage.fracture_energy, config.horizon, dim, exponent);
    N.compression_only[i] = mat.damage.broken_bonds_compression ? 1 : 0;
    // Contact stiffness of the LAMMPS rule from the bond-based micromodulus of the same
    // bulk modulus (as the LPS does, solver/build.cpp).
    M.contact_micromodulus[i] = equivalent_micromodulus(mat.bulk_modulus, mat.shear_modulus, InfluenceKind::constant, dims);
  }
  s.contact.setup(config.contact.short_range, config.spacing, config.horizon);
  build_kind_coefficients(s, config.output.damage_measure);
  // The contact springs a particle may feel, for the time step: those of its family
  // pairs within the contact reach (a body it touches has a similar neighbourhood).
  if (s.contact.enabled()) {
    const double reach = s.contact.config().max_distance * config.spacing;
    for (std::size_t i = 0; i < n; ++i)
      for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
        const KindCoefficients& kc = M.kind[B.kind[k]];
        if (kc.length <= reach * (1 + 1e-9)) N.contact_stiffness[i] += kc.contact_k;
      }
  }
  // theta at rest is 0; the first force pass fills the strains.
}

uint64_t NonlinearSolid::force_pass(System& s, bool energy) {
  auto& P = s.particles;
  auto& B = s.bonds;
  auto& M = s.model;
  const std::size_t n = P.size();
  if (N.bond_strain.size() != B.size()) N.bond_strain.assign(B.size(), 0);
  M.packed.resize(n);
  Point4* pt = M.packed.data();
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 y = P.X[i] + P.u[i];
    pt[i] = {y.x, y.y, y.z, 0.0};
  }
  const KindCoefficients* kc = M.kind.data();
  const uint32_t* nbr = B.nbr.data();
  const uint32_t* kind = B.kind.data();
  uint8_t* intact = B.intact.data();
  double* eps_of = N.bond_strain.data();
  const bool contact = s.contact.enabled();

  const Rows rows(s);
  // The two sweeps' rows are device-portable kernels (kernels/tupek.hpp).
  kernels::TupekPass<KindCoefficients> tp;
  tp.pt = pt;
  tp.kc = kc;
  tp.nbr = nbr;
  tp.kind = kind;
  tp.offset = B.offset.data();
  tp.intact = intact;
  tp.eps = eps_of;
  tp.m = N.m.data();
  tp.lambda_bar = N.lambda_bar.data();
  tp.mu_bar = N.mu_bar.data();
  tp.theta = N.theta.data();
  tp.beta = N.beta.data();
  tp.compression_only = N.compression_only.data();
  tp.failure_scale = N.failure_scale.data();
  tp.exponent_two = N.failure_exponent_two;
  tp.contact = contact;
  // Sweep 1: strains and theta_phi (eq. 6.8).
#pragma omp parallel for schedule(static)
  for (std::size_t r = 0; r < rows.count; ++r) {
    const std::size_t i = rows[r];
    N.theta[i] = kernels::tupek_strain_row(tp, i);
  }
  exchange_ghost_scalars(s, N.theta, scratch_);  // theta_j of the ghosts, from their owners

  // Sweep 2: the pair criterion, then the force with the flags at the start of the pass.
  uint64_t broken = 0;
  const double dim = N.dimension;
#pragma omp parallel for schedule(static) reduction(+ : broken)
  for (std::size_t r = 0; r < rows.count; ++r) {
    const std::size_t i = rows[r];
    const kernels::TupekRow o = kernels::tupek_force_row(tp, i);
    P.f[i] = {o.f[0], o.f[1], o.f[2]};
    broken += o.broken;
    if (o.lost != 0) s.dissipated_at[i] += o.lost * P.volume[i];
    if (energy) P.energy[i] = kernels::tupek_row_energy(o, N.lambda_bar[i], N.mu_bar[i], N.theta[i]);
    P.damage[i] = o.total_w > 0 ? 1.0 - o.intact_w / o.total_w : 0.0;
    N.nonlocal_damage[i] = 1.0 - o.intact_w / dim;  // eq. 6.12
    M.intact_weight[i] = o.intact_w;
  }
  // The rows of System::active_rows this pass does not compute (a decomposed run's bond
  // neighbours): no force, so that the contact below adds to zero there (nothing reads it).
  if (rows.own)
    for (uint32_t i : s.active_rows)
      if (!s.decomposition->owns(i)) {
        P.f[i] = {};
        if (energy) P.energy[i] = 0;
      }
  s.contact.add_forces(s, pt, P.f.data(), energy ? P.energy.data() : nullptr);
  return broken;
}

double NonlinearSolid::stable_time_step(const System& s) const {
  const auto& P = s.particles;
  const auto& B = s.bonds;
  const auto& M = s.model;
  const std::size_t n = P.size();
  // The rows are device-portable kernels (kernels/tupek.hpp tupek_coupling_row and
  // tupek_stable_row), which the flat backend calls over its own copy.
  kernels::TupekPass<KindCoefficients> tp;
  tp.kc = M.kind.data();
  tp.nbr = B.nbr.data();
  tp.kind = B.kind.data();
  tp.offset = B.offset.data();
  tp.intact = const_cast<uint8_t*>(B.intact.data());  // (read only here)
  tp.eps = N.bond_strain.size() == B.size() ? const_cast<double*>(N.bond_strain.data()) : nullptr;
  tp.m = N.m.data();
  tp.lambda_bar = N.lambda_bar.data();
  tp.mu_bar = N.mu_bar.data();
  tp.theta = N.theta.data();
  tp.compression_only = N.compression_only.data();
  // S_i = sum_k omega V_k |d eps_ik/d|Y||: the dilatation coupling of row i (Gershgorin).
  // A decomposed run: the owned rows, S_j of the ghosts from their owners, and the
  // minimum over ranks taken by the caller (driver/check.cpp whole_stable_step).
  std::vector<double> S(n, 0);
  const Rows rows(s);
#pragma omp parallel for schedule(static)
  for (std::size_t r = 0; r < rows.count; ++r) {
    const std::size_t i = rows[r];
    S[i] = kernels::tupek_coupling_row(tp, i);
  }
  exchange_ghost_scalars(s, S, scratch_);
  double dt = kInf;
#pragma omp parallel for schedule(static) reduction(min : dt)
  for (std::size_t r = 0; r < rows.count; ++r) {
    const std::size_t i = rows[r];
    dt = std::min(dt, kernels::tupek_stable_row(tp, S.data(), N.contact_stiffness[i], P.density[i], i));
  }
  return dt;
}

}  // namespace horizon
