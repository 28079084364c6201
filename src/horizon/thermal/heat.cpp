#include "horizon/thermal/heat.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "horizon/core/error.hpp"
#include "horizon/loading/loads.hpp"
#include "horizon/material/model.hpp"
#include "horizon/parallel/decomposition.hpp"
#include "horizon/state/owned_rows.hpp"

namespace horizon {

namespace {

constexpr double kPi = std::numbers::pi;

// g(|xi|) of the kernel (config.hpp, HeatKernel).
double kernel_value(HeatKernel k, double length) { return k == HeatKernel::inverse ? 1.0 / length : 1.0; }

double bond_kappa(const HeatState& h, std::size_t i, std::size_t j) { return 0.5 * (h.kappa[i] + h.kappa[j]); }

// g(|xi|) times bond k's quadrature weight (heat_state.hpp): per bond where the kinds
// cannot hold it, else its kind's.
double bond_factor(const HeatState& h, const Bonds& B, uint64_t k) {
  return h.bond_factor.empty() ? h.kind_factor[B.kind[k]] : h.bond_factor[k];
}

// The improved quadrature's weights of particle i's bonds (config.hpp HeatQuadrature;
// docs/models/heat.md "Improved quadrature"). With m the monomials of degree 1 and 2 in
// xi/delta (d + d(d+1)/2 of them) and A_rk = g(|xi_k|) m_r(xi_k/delta), the weights w
// are the closest to the one-point ones v (V_j times the partial-volume fraction) in the
// norm sum_k (w_k - v_k)^2 / v_k for which the bond sum integrates every monomial exactly
// over the whole ball: A w = b, b_r = int_B g m_r dV (0 for degree 1, M2/delta^2 for
// xi_a^2, 0 for xi_a xi_b, a != b; heat_moment_continuum). Lagrange's conditions give
// w = v + diag(v) A^T lambda with (A diag(v) A^T) lambda = b - A v [derived], a small
// symmetric positive definite system (Cholesky). This is the optimisation-based rule of
// Trask, You, Yu and Parks 2019 (Comput. Methods Appl. Mech. Engrg. 343:151: quadrature
// weights of least norm exact on a polynomial space), in Horizon's weighted form. Writes
// g(|xi_k|) w_k into out[k] for i's intact bonds; false where A diag(v) A^T is singular
// (a family too small or flat to fit the quadratics).
bool improved_weights(const System& s, std::size_t i, double m2, std::vector<double>& out) {
  const Bonds& B = s.bonds;
  const auto& X = s.particles.X;
  const HeatState& h = s.heat;
  const int d = s.dimension;
  const int m = d + d * (d + 1) / 2;
  const double delta = s.horizon;
  std::vector<std::array<double, 9>> rows;  // A's column of each intact bond, times g
  std::vector<double> v;
  std::vector<uint64_t> bonds;
  for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
    if (!B.intact[k]) continue;
    const Vec3 xi = (X[B.nbr[k]] - X[i]) / delta;
    const double g = kernel_value(h.kernel, B.length_of(k));
    std::array<double, 9> a{};
    int r = 0;
    for (int p = 0; p < d; ++p) a[static_cast<std::size_t>(r++)] = g * xi[p];
    for (int p = 0; p < d; ++p)
      for (int q = p; q < d; ++q) a[static_cast<std::size_t>(r++)] = g * xi[p] * xi[q];
    rows.push_back(a);
    v.push_back(B.volume[k]);
    bonds.push_back(k);
  }
  std::array<double, 9> rhs{};
  {
    int r = d;
    for (int p = 0; p < d; ++p)
      for (int q = p; q < d; ++q) rhs[static_cast<std::size_t>(r++)] = p == q ? m2 / (delta * delta) : 0.0;
  }
  // G = A diag(v) A^T and b - A v.
  std::array<double, 81> G{};
  for (std::size_t k = 0; k < rows.size(); ++k)
    for (int r = 0; r < m; ++r) {
      const auto ur = static_cast<std::size_t>(r);
      rhs[ur] -= rows[k][ur] * v[k];
      for (int c = 0; c < m; ++c) G[ur * 9 + static_cast<std::size_t>(c)] += rows[k][ur] * v[k] * rows[k][static_cast<std::size_t>(c)];
    }
  // Cholesky G = L L^T in place (lower triangle); a pivot below 1e-12 of the diagonal's
  // scale is a singular family.
  double scale = 0;
  for (int r = 0; r < m; ++r) scale = std::max(scale, G[static_cast<std::size_t>(r * 9 + r)]);
  for (int c = 0; c < m; ++c) {
    const auto uc = static_cast<std::size_t>(c);
    double piv = G[uc * 9 + uc];
    for (int k = 0; k < c; ++k) piv -= G[uc * 9 + static_cast<std::size_t>(k)] * G[uc * 9 + static_cast<std::size_t>(k)];
    if (!(piv > 1e-12 * scale)) return false;
    piv = std::sqrt(piv);
    G[uc * 9 + uc] = piv;
    for (int r = c + 1; r < m; ++r) {
      const auto ur = static_cast<std::size_t>(r);
      double sum = G[ur * 9 + uc];
      for (int k = 0; k < c; ++k) sum -= G[ur * 9 + static_cast<std::size_t>(k)] * G[uc * 9 + static_cast<std::size_t>(k)];
      G[ur * 9 + uc] = sum / piv;
    }
  }
  std::array<double, 9> lambda = rhs;
  for (int r = 0; r < m; ++r) {  // L y = b - A v
    const auto ur = static_cast<std::size_t>(r);
    for (int k = 0; k < r; ++k) lambda[ur] -= G[ur * 9 + static_cast<std::size_t>(k)] * lambda[static_cast<std::size_t>(k)];
    lambda[ur] /= G[ur * 9 + ur];
  }
  for (int r = m - 1; r >= 0; --r) {  // L^T lambda = y
    const auto ur = static_cast<std::size_t>(r);
    for (int k = r + 1; k < m; ++k) lambda[ur] -= G[static_cast<std::size_t>(k) * 9 + ur] * lambda[static_cast<std::size_t>(k)];
    lambda[ur] /= G[ur * 9 + ur];
  }
  for (std::size_t k = 0; k < rows.size(); ++k) {
    double w = v[k];
    for (int r = 0; r < m; ++r) w += v[k] * rows[k][static_cast<std::size_t>(r)] * lambda[static_cast<std::size_t>(r)];
    out[bonds[k]] = kernel_value(h.kernel, B.length_of(bonds[k])) * w;
  }
  return true;
}

// The rows this process computes: in a run split over MPI ranks (parallel/decomposition.hpp)
// its owned particles, whose conduction reads the ghosts' temperatures (exchanged after
// every change: exchange_ghosts below); every particle serially. Indices are this rank's
// (local ones with local particles: Particles::id is the global id).
using Rows = OwnedRows;  // state/owned_rows.hpp

// The owners' temperatures at this rank's ghosts. Collective when decomposed.
void exchange_ghosts(System& s) {
  if (s.decomposition) exchange_ghost_scalars(*s.decomposition, s.heat.T);
}

// The axis along which a set of particles is thinnest (as tractions, loading/loads.cpp);
// with local particles the whole set's over the ranks (collective).
int thinnest_axis(const System& s, const std::vector<uint32_t>& ids, int dimension) {
  const bool local = s.decomposition && s.decomposition->local_particles;
  int axis = 0;
  double best = 1e300;
  for (int k = 0; k < dimension; ++k) {
    double lo = 1e300, hi = -1e300;
    for (uint32_t i : ids) {
      lo = std::min(lo, s.particles.X[i][k]);
      hi = std::max(hi, s.particles.X[i][k]);
    }
    if (local) lo = min_over_ranks(lo), hi = -min_over_ranks(-hi);
    if (hi - lo < best) {
      best = hi - lo;
      axis = k;
    }
  }
  return axis;
}

}  // namespace

double heat_moment_continuum(HeatKernel kernel, int dimension, double horizon, double measure) {
  // M2 = int_H g xi_1^2 dV (heat.hpp); int xi_1^2 f(r) dV = (1/d) int r^2 f(r) dV by symmetry.
  const double d = horizon;
  if (kernel == HeatKernel::inverse) {
    if (dimension == 1) return measure * d * d;                // A int_{-d}^{d} |x| dx
    if (dimension == 2) return measure * kPi * d * d * d / 3;  // h (1/2) int_0^d r 2 pi r dr
    return kPi * d * d * d * d / 3;                            // (1/3) int_0^d r 4 pi r^2 dr
  }
  if (dimension == 1) return measure * 2 * d * d * d / 3;      // A int_{-d}^{d} x^2 dx
  if (dimension == 2) return measure * kPi * d * d * d * d / 4;  // h (1/2) int_0^d r^2 2 pi r dr
  return 4 * kPi * std::pow(d, 5) / 15;                        // (1/3) int_0^d r^2 4 pi r^2 dr
}

void setup_heat(System& s, const std::vector<MaterialConfig>& materials, const Config& config, bool split) {
  auto& P = s.particles;
  auto& B = s.bonds;
  HeatState& h = s.heat;
  const std::size_t n = P.size();
  const ThermalConfig& tc = config.thermal;
  h = HeatState{};
  h.kernel = tc.kernel;
  h.calibration = tc.calibration;
  h.conduction = tc.conduction;
  h.T.resize(n);
  h.capacity.resize(n);
  h.kappa.resize(n);
  h.expansion.resize(n);
  h.reference.resize(n);
  h.plastic_fraction.resize(n);
  h.stretch_slope.resize(n);
  h.fixed.assign(n, 0);
  h.flux.assign(n, Vec3{});
  h.quadrature = tc.quadrature;
  h.kind_factor.resize(B.kinds.size());
  for (std::size_t k = 0; k < B.kinds.size(); ++k) {
    const BondKind& c = B.kinds[k];
    h.kind_factor[k] = kernel_value(h.kernel, c.length) * c.volume * c.fraction;
  }
  // Bonds with their own lengths (a mesh's centroids): the kinds hold no length, so each
  // bond keeps its g(|xi|) V_j (the improved quadrature's weights replace it below).
  if (B.length_per_bond || h.quadrature == HeatQuadrature::improved) {
    h.bond_factor.resize(B.size());
    for (uint64_t k = 0; k < B.size(); ++k) h.bond_factor[k] = kernel_value(h.kernel, B.length_of(k)) * B.volume[k];
  }
  // The discrete moment sum_j g |xi|^2 V_j / d of each particle's family; its largest
  // value per material is the bulk value of the lattice (surface particles miss part).
  std::vector<double> bulk(materials.size(), 0.0);
  if (h.calibration == HeatCalibration::discrete) {
    for (std::size_t i = 0; i < n; ++i) {
      double m2 = 0;
      for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
        const double L = B.length_of(k);
        m2 += bond_factor(h, B, k) * L * L;
      }
      m2 /= s.dimension;
      double& b = bulk[static_cast<std::size_t>(P.material[i])];
      b = std::max(b, m2);
    }
    if (split)  // the rows of other ranks: the largest over ranks (exact, a maximum)
      for (double& b : bulk) b = -min_over_ranks(-b);
  }
  const double measure = s.dimension == 1 ? config.area : config.thickness;
  const double m2_continuum = heat_moment_continuum(h.kernel, s.dimension, s.horizon, measure);
  if (h.quadrature == HeatQuadrature::improved && h.conduction) {
    // Each row's own weights (owned rows and any other row this rank holds bonds of).
    std::string failed;
    uint64_t failures = 0;
    for (std::size_t i = 0; i < n; ++i)
      if (B.end(i) > B.begin(i) && !improved_weights(s, i, m2_continuum, h.bond_factor) && failures++ == 0)
        failed = fmt::format("thermal.quadrature: improved: the family of the particle at ({:.6g}, {:.6g}, {:.6g}) "
                             "({} bonds) is too small or too flat to integrate the quadratics exactly; use a larger "
                             "horizon or quadrature: one_point",
                             P.X[i].x, P.X[i].y, P.X[i].z, B.end(i) - B.begin(i));
    if (split) failures = sum_over_ranks(failures);  // every rank stops (collective)
    if (failures > 0)
      throw Error(failed.empty() ? std::string("thermal.quadrature: improved: a family on another rank is too small "
                                               "or too flat to integrate the quadratics exactly")
                                 : failed);
  }
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t m = static_cast<std::size_t>(P.material[i]);
    const MaterialConfig& mat = materials[m];
    const ThermalMaterialConfig& th = mat.thermal;
    if (!th.enabled)
      throw Error("material '" + mat.name + "' has no thermal properties; a run with a thermal section needs "
                  "materials.NAME.thermal for every material");
    // A steady solve stores no heat: no capacity (the heat content stays 0, and the
    // balance is the boundaries' flows alone).
    h.capacity[i] = tc.integration == HeatIntegration::steady ? 0.0 : mat.density * th.specific_heat;
    if (h.conduction) {
      const double m2 = h.calibration == HeatCalibration::discrete ? bulk[m] : m2_continuum;
      if (!(m2 > 0)) throw Error("material '" + mat.name + "': its particles have no bonds to conduct heat");
      h.kappa[i] = 2 * th.conductivity / m2;
    }
    // Plane strain: the blocked out-of-plane expansion pushes the plane apart, and a free
    // body's in-plane strain is (1 + nu) alpha dT (sigma = 0 with eps_zz = 0 in
    // sigma = lambda tr(eps) I + 2 mu eps - (3 lambda + 2 mu) alpha dT I): the 2-D bonds
    // take that effective coefficient. Plane stress and 3-D: alpha itself.
    const bool plane_strain = s.dimension == 2 && config.plane == PlaneMode::strain;
    h.expansion[i] = th.expansion * (plane_strain ? 1 + mat.poissons_ratio : 1.0);
    h.reference[i] = th.reference_temperature;
    h.plastic_fraction[i] = th.plastic_heat_fraction;
    h.stretch_slope[i] = th.critical_stretch_slope;
    h.softens = h.softens || th.critical_stretch_slope != 0;
    h.expands = h.expands || th.expansion != 0;
    h.T[i] = tc.initial_temperature(0.0, P.X[i].x, P.X[i].y, P.X[i].z);
  }
  for (const auto& bc : tc.boundary) {
    HeatBoundary hb;
    hb.kind = bc.kind;
    hb.value = bc.value;
    hb.coefficient = bc.coefficient;
    hb.ambient = bc.ambient;
    hb.particles = region_particles(config, s, bc.region);
    const char* kind = bc.kind == ThermalBoundaryKind::temperature ? "temperature"
                       : bc.kind == ThermalBoundaryKind::flux      ? "flux"
                                                                   : "convection";
    hb.name = (bc.region.empty() ? std::string("all") : bc.region) + ":" + kind;
    // With local particles a rank may hold none of the region: every rank takes part.
    const bool local = s.decomposition && s.decomposition->local_particles;
    if (bc.kind != ThermalBoundaryKind::temperature && (local || !hb.particles.empty())) {
      // A flux through the boundary becomes a source density over a layer of depth d, so
      // that the total is the flux times the area (as tractions, docs/input.md).
      const int axis = bc.normal_axis >= 0 ? bc.normal_axis : thinnest_axis(s, hb.particles, s.dimension);
      hb.scale = 1.0 / layer_depth(s, hb.particles, axis);
    }
    if (bc.kind == ThermalBoundaryKind::temperature)
      for (uint32_t i : hb.particles) h.fixed[i] = 1;
    h.boundary.push_back(std::move(hb));
  }
  apply_temperature_conditions(s, 0.0);
  // reference_temperature: initial -- no thermal strain in the state at t = 0, whatever
  // its temperature (Peridigm's Temperature_Change = T - T(0); docs/peridigm.md).
  for (std::size_t i = 0; i < n; ++i)
    if (materials[static_cast<std::size_t>(P.material[i])].thermal.reference_initial) h.reference[i] = h.T[i];
  update_thermal_strain(s);
  update_heat_flux(s);
}

void set_temperature_field(System& s, double t) {
  apply_temperature_conditions(s, t);
  s.heat.time = t;
  if (s.decomposition) exchange_ghost_scalars(*s.decomposition, s.heat.T);
  update_thermal_strain(s);
}

void apply_temperature_conditions(System& s, double t) {
  auto& P = s.particles;
  for (const auto& bc : s.heat.boundary)
    if (bc.kind == ThermalBoundaryKind::temperature)
      for (uint32_t i : bc.particles) s.heat.T[i] = bc.value(t, P.X[i].x, P.X[i].y, P.X[i].z);
}

void heat_conduction(const System& s, const std::vector<double>& T, std::vector<double>& out) {
  const auto& B = s.bonds;
  const HeatState& h = s.heat;
  const Rows rows(s);
  out.resize(s.particles.size());
#pragma omp parallel for schedule(static)
  for (std::size_t r = 0; r < rows.count; ++r) {
    const std::size_t i = rows[r];
    double sum = 0;
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
      if (!B.intact[k]) continue;
      const uint32_t j = B.nbr[k];
      sum += bond_kappa(h, i, j) * bond_factor(h, B, k) * (T[j] - T[i]);
    }
    out[i] = sum;
  }
}

double heat_stable_step(const System& s) {
  const auto& B = s.bonds;
  const HeatState& h = s.heat;
  std::vector<double> film(s.particles.size(), 0.0);
  for (const auto& bc : h.boundary)
    if (bc.kind == ThermalBoundaryKind::convection)
      for (uint32_t i : bc.particles) film[i] += bc.coefficient * bc.scale;
  double dt = std::numeric_limits<double>::infinity();
  const Rows rows(s);
  for (std::size_t r = 0; r < rows.count; ++r) {
    const std::size_t i = rows[r];
    double diag = film[i];
    for (uint64_t k = B.begin(i); k < B.end(i); ++k)
      if (B.intact[k]) diag += bond_kappa(h, i, B.nbr[k]) * bond_factor(h, B, k);
    if (diag > 0) dt = std::min(dt, h.capacity[i] / diag);
  }
  return s.decomposition ? min_over_ranks(dt) : dt;
}

double heat_content(const System& s) {
  const HeatState& h = s.heat;
  // Serially the plain sum in index order; on ranks the owned particles' on the grid.
  GridSum sum(s, 1);
  const Rows rows(s);
  for (std::size_t r = 0; r < rows.count; ++r) {
    const std::size_t i = rows[r];
    sum.add(0, h.capacity[i] * (h.T[i] - h.reference[i]) * s.particles.volume[i]);
  }
  return sum.totals()[0];
}

void update_heat_flux(System& s) {
  const auto& B = s.bonds;
  const auto& X = s.particles.X;
  HeatState& h = s.heat;
  const Rows rows(s);
#pragma omp parallel for schedule(static)
  for (std::size_t r = 0; r < rows.count; ++r) {
    const std::size_t i = rows[r];
    Vec3 q;
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
      if (!B.intact[k]) continue;
      const uint32_t j = B.nbr[k];
      q += (bond_kappa(h, i, j) * bond_factor(h, B, k) * (h.T[j] - h.T[i])) * (X[j] - X[i]);
    }
    h.flux[i] = q * -0.5;
  }
}

void update_thermal_strain(System& s) {
  const HeatState& h = s.heat;
  if (h.active() && h.softens) {
    s.critical_stretch_factor.resize(h.T.size());
    for (std::size_t i = 0; i < h.T.size(); ++i)
      s.critical_stretch_factor[i] = std::max(0.0, 1.0 + h.stretch_slope[i] * (h.T[i] - h.reference[i]));
  } else {
    s.critical_stretch_factor.clear();
  }
  if (!h.active() || !h.expands) {
    s.thermal_strain.clear();
    return;
  }
  s.thermal_strain.resize(h.T.size());
  for (std::size_t i = 0; i < h.T.size(); ++i) s.thermal_strain[i] = h.expansion[i] * (h.T[i] - h.reference[i]);
}

double thermal_strain_work(const System& s, const std::vector<double>& delta) {
  const auto& B = s.bonds;
  const auto& P = s.particles;
  // The scalar force state along bond k from the last pass: T.Y/|Y| of the vector general
  // pass, or q |Y| of its scalar form (solver/forces_ordinary.cpp, T = q Y).
  const auto& T = s.model.force_state;
  const auto& Q = s.model.force_scalar;
  const bool vector = T.size() == B.size();
  if (delta.size() != P.size() || (!vector && Q.size() != B.size())) return 0;
  auto along = [&](uint64_t k, const Vec3& Y, double len) { return vector ? dot(T[k], Y) / len : Q[k] * len; };
  if (s.decomposition) {
    // On ranks: each owned row's term, summed on the grid (the same total at any rank
    // count; the serial program keeps its reduction below).
    const Rows rows(s);
    std::vector<double> terms(rows.count, 0.0);
#pragma omp parallel for schedule(static)
    for (std::size_t r = 0; r < rows.count; ++r) {
      const std::size_t i = rows[r];
      double row = 0;
      for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
        if (!B.intact[k]) continue;
        const uint32_t j = B.nbr[k];
        const Vec3 Y = P.X[j] + P.u[j] - P.X[i] - P.u[i];
        const double len = norm(Y);
        if (len == 0) continue;
        row += along(k, Y, len) * (0.5 * (delta[i] + delta[j]) * B.length[k]) * B.volume[k];
      }
      terms[r] = -row * P.volume[i];
    }
    GridSum g(s, 1);
    for (double t : terms) g.add(0, t);
    return g.totals()[0];
  }
  double sum = 0;
#pragma omp parallel for schedule(static) reduction(+ : sum)
  for (std::size_t i = 0; i < P.size(); ++i) {
    double row = 0;
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
      if (!B.intact[k]) continue;
      const uint32_t j = B.nbr[k];
      const Vec3 Y = P.X[j] + P.u[j] - P.X[i] - P.u[i];
      const double r = norm(Y);
      if (r == 0) continue;
      const double t = along(k, Y, r);
      const double de = 0.5 * (delta[i] + delta[j]) * B.length[k];
      row += t * de * B.volume[k];
    }
    sum -= row * P.volume[i];
  }
  return sum;
}

void deposit_heat(System& s, std::size_t i, double energy) {
  HeatState& h = s.heat;
  if (h.fixed[i]) return;  // a prescribed temperature takes the heat away at once
  h.T[i] += energy / (h.capacity[i] * s.particles.volume[i]);
  h.plastic_heat += energy;
}

void commit_history_with_heat(System& s) {
  HeatState& h = s.heat;
  bool plastic = false;
  for (double b : h.plastic_fraction) plastic = plastic || b > 0;
  if (!h.active() || !plastic || s.models.all_unified()) {  // the unified models dissipate nothing in commit
    commit_history(s);
    return;
  }
  std::vector<double> before = s.dissipated_at;
  commit_history(s);
  if (s.decomposition) {
    // On ranks: the owners deposit (a neighbour row computed here again is not this
    // rank's), the heat released summed on the grid, the ghosts' temperatures refreshed.
    GridSum released(s, 1);
    for (uint32_t i : s.owned) {
      const double d = s.dissipated_at[i] - before[i];
      if (d > 0 && !h.fixed[i]) {
        const double e = h.plastic_fraction[i] * d;
        h.T[i] += e / (h.capacity[i] * s.particles.volume[i]);
        released.add(0, e);
      }
    }
    h.plastic_heat += released.totals()[0];
    exchange_ghosts(s);
    return;
  }
  for (std::size_t i = 0; i < before.size(); ++i) {
    const double d = s.dissipated_at[i] - before[i];
    if (d > 0) deposit_heat(s, i, h.plastic_fraction[i] * d);
  }
}

// The backward-Euler system on the free particles, scaled by V_i so that it is symmetric:
//   (rho c V_i/dt + V_i sum_j K_ij + V_i h_i/d) T_i - sum_{j free} V_i K_ij T_j
//     = rho c V_i/dt T_i^n + V_i (q_i + h_i/d T_amb) + sum_{j fixed} V_i K_ij T_j^{n+1},
// K_ij = kbar g V_j, so a_ij = V_i K_ij = kbar_ij g(|xi|) V_i V_j (the bond kind's volume
// and partial-volume fraction depend on |xi| alone on the lattice): a_ij = a_ji. The
// matrix is the diagonal rho c V_i/dt + V_i h_i/d > 0 plus the conduction part, a weighted
// graph Laplacian sum_bonds a_ij (T_i - T_j)^2 / 2 >= 0 (its rows to fixed neighbours keep
// only the diagonal a_ij): symmetric positive definite for dt > 0.
// thermal.integration: steady drops the rho c V_i/dt terms: the steady state at the new
// time, L T + q + h/d (T_amb - T) = 0 on the free particles (Peridigm's ImplicitDiffusion
// load step). Its matrix is positive definite where every free particle reaches a fixed
// temperature or a film through its bonds (check_thermal refuses a boundary without one).
// The improved quadrature's rows are not symmetric: BiCGSTAB then (below).
//
// Solved matrix-free by the conjugate gradient (Hestenes and Stiefel 1952) with the Jacobi
// preconditioner, started from T^n, in both programs: over the owned rows of a run split
// over MPI ranks (the search direction's ghost entries sent by their owners before each
// product, exchange_ghost_scalars) and over every particle serially; every inner product
// is an exact grid sum (GridSum::exact, parallel/decomposition.hpp), and each row of the
// product sums its bond row in the serial order, so the iterates, hence the temperatures,
// are the same bits serially and on any number of ranks and threads.
// Stopped when |r| <= 1e-12 |r_0| (r_0 = b - A T^n, the step's heat flows) or
// |r| <= 1e-15 |b|, the round-off of the product: the heat the residual leaves unbooked is
// dt sum_i r_i, some 1e-11 of what the step moves.
struct HeatSolver::Implicit {
  std::vector<double> diag, b, x, r, z, p, q;
  std::vector<uint8_t> row;  // an owned free particle: an unknown of this rank
  int iterations = 0;        // CG iterations of the last step
};

HeatSolver::HeatSolver(System& s, HeatIntegration integration) : s_(s), integration_(integration) {
  if (integration_ != HeatIntegration::explicit_euler) implicit_ = std::make_unique<Implicit>();
}
HeatSolver::~HeatSolver() = default;

int HeatSolver::iterations() const { return implicit_ ? implicit_->iterations : 0; }

void HeatSolver::implicit_step(double dt, const std::vector<double>& source, const std::vector<double>& film,
                               const std::vector<double>& film_t) {
  auto& P = s_.particles;
  auto& B = s_.bonds;
  HeatState& h = s_.heat;
  Implicit& I = *implicit_;
  const std::size_t n = P.size();
  const bool steady = integration_ == HeatIntegration::steady;
  const Rows rows(s_);
  I.row.assign(n, 0);
  for (std::size_t k = 0; k < rows.count; ++k)
    if (!h.fixed[rows[k]]) I.row[rows[k]] = 1;
  // Diagonal and right-hand side of the owned free rows (heat.cpp, above).
  I.diag.assign(n, 0.0);
  I.b.assign(n, 0.0);
#pragma omp parallel for schedule(static)
  for (std::size_t k = 0; k < rows.count; ++k) {
    const std::size_t i = rows[k];
    if (!I.row[i]) continue;
    const double Vi = P.volume[i];
    const double stored = steady ? 0.0 : h.capacity[i] * Vi / dt;  // a steady solve stores no heat
    double diag = stored + Vi * film[i];
    double rhs = stored * old_[i] + Vi * (source[i] + film_t[i]);
    for (uint64_t e = B.begin(i); e < B.end(i); ++e) {
      if (!B.intact[e]) continue;
      const uint32_t j = B.nbr[e];
      const double a = Vi * bond_kappa(h, i, j) * bond_factor(h, B, e);
      diag += a;
      if (h.fixed[j]) rhs += a * h.T[j];
    }
    I.diag[i] = diag;
    I.b[i] = rhs;
  }
  // A steady row without conductance (a particle without bonds or film) has no steady
  // temperature; the Jacobi preconditioner divides by the diagonal. (The improved
  // quadrature's weights may be negative, and on a thin body its diagonal too: BiCGSTAB
  // takes that; only a zero one is refused.)
  // Every rank learns of it (the solve's collectives stay matched); the owner names it.
  std::string isolated;
  for (std::size_t k = 0; k < rows.count && isolated.empty(); ++k) {
    const std::size_t i = rows[k];
    if (I.row[i] && (I.diag[i] == 0 || !std::isfinite(I.diag[i])))
      isolated = fmt::format("the heat solve: the particle at ({:.6g}, {:.6g}, {:.6g}) has no bond to conduct through "
                             "and no heat capacity or film, so its {} temperature is not defined",
                             P.X[i].x, P.X[i].y, P.X[i].z, steady ? "steady" : "new");
  }
  const bool any = s_.decomposition ? any_rank(*s_.decomposition, !isolated.empty()) : !isolated.empty();
  if (any)
    throw Error(isolated.empty() ? std::string("the heat solve: a particle of another rank has no bond to conduct "
                                               "through and no heat capacity or film")
                                 : isolated);
  // q = A v on the owned free rows (v's ghost entries current; fixed particles' ignored).
  auto apply = [&](const std::vector<double>& v, std::vector<double>& q) {
#pragma omp parallel for schedule(static)
    for (std::size_t k = 0; k < rows.count; ++k) {
      const std::size_t i = rows[k];
      if (!I.row[i]) continue;
      const double Vi = P.volume[i];
      double off = 0;
      for (uint64_t e = B.begin(i); e < B.end(i); ++e) {
        if (!B.intact[e]) continue;
        const uint32_t j = B.nbr[e];
        if (h.fixed[j]) continue;
        off += Vi * bond_kappa(h, i, j) * bond_factor(h, B, e) * v[j];
      }
      q[i] = I.diag[i] * v[i] - off;
    }
  };
  // Inner products of the owned free rows on the grid (the same bits at any rank count).
  auto dots = [&](std::initializer_list<std::pair<const std::vector<double>*, const std::vector<double>*>> pairs) {
    GridSum g = GridSum::exact(s_, static_cast<int>(pairs.size()));
    for (std::size_t k = 0; k < rows.count; ++k) {
      const std::size_t i = rows[k];
      if (!I.row[i]) continue;
      int q = 0;
      for (const auto& [u, v] : pairs) g.add(q++, (*u)[i] * (*v)[i]);
    }
    return g.totals();
  };
  if (h.quadrature == HeatQuadrature::improved) {
    // BiCGSTAB (van der Vorst 1992, SIAM J. Sci. Stat. Comput. 13:631, with the Jacobi
    // preconditioner applied on the right): the improved weights are per row (omega_ij !=
    // omega_ji), so A is not symmetric. From T^n, with the same products, grid sums and
    // stopping rule as the conjugate gradient below (the same bits serially and on ranks).
    auto each = [&](auto&& f) {
      for (std::size_t k = 0; k < rows.count; ++k)
        if (I.row[rows[k]]) f(rows[k]);
    };
    auto product = [&](std::vector<double>& v, std::vector<double>& out) {
      if (s_.decomposition) exchange_ghost_scalars(*s_.decomposition, v);
      apply(v, out);
    };
    I.x = old_;
    I.r.assign(n, 0.0);
    I.q.assign(n, 0.0);
    apply(I.x, I.q);
    each([&](std::size_t i) { I.r[i] = I.b[i] - I.q[i]; });
    std::vector<double> shadow = I.r, p(n, 0.0), v(n, 0.0), y(n, 0.0), z(n, 0.0), sv(n, 0.0), t(n, 0.0);
    std::vector<double> d0 = dots({{&I.r, &I.r}, {&I.b, &I.b}});
    const double stop = std::max(1e-12 * std::sqrt(d0[0]), 1e-15 * std::sqrt(d0[1]));
    double rho = 1, alpha = 1, omega = 1, rr = d0[0];
    const int most = 10000;
    int it = 0;
    while (std::sqrt(rr) > stop) {
      if (++it > most)
        throw Error(fmt::format("the heat solve did not converge in {} BiCGSTAB iterations (residual {:.3e}, wanted "
                                "{:.3e}); with quadrature: improved every particle's weights integrate over its whole "
                                "ball, which no free surface bounds: hold the temperature on a layer one horizon "
                                "deep at each surface (the nonlocal volume constraint, as Peridigm's decks do) or "
                                "use quadrature: one_point",
                                most, std::sqrt(rr), stop));
      const double rho_new = dots({{&shadow, &I.r}})[0];
      if (rho_new == 0 || omega == 0) throw Error("the heat solve failed: BiCGSTAB broke down (the system is singular)");
      const double beta = (rho_new / rho) * (alpha / omega);
      rho = rho_new;
      each([&](std::size_t i) { p[i] = I.r[i] + beta * (p[i] - omega * v[i]), y[i] = p[i] / I.diag[i]; });
      product(y, v);
      const double sv_dot = dots({{&shadow, &v}})[0];
      if (sv_dot == 0) throw Error("the heat solve failed: BiCGSTAB broke down (the system is singular)");
      alpha = rho / sv_dot;
      each([&](std::size_t i) { sv[i] = I.r[i] - alpha * v[i], z[i] = sv[i] / I.diag[i]; });
      product(z, t);
      const std::vector<double> ts = dots({{&t, &sv}, {&t, &t}});
      omega = ts[1] > 0 ? ts[0] / ts[1] : 0.0;
      each([&](std::size_t i) { I.x[i] += alpha * y[i] + omega * z[i], I.r[i] = sv[i] - omega * t[i]; });
      rr = dots({{&I.r, &I.r}})[0];
      if (omega == 0 && std::sqrt(rr) > stop)
        throw Error("the heat solve failed: BiCGSTAB broke down (the system is singular)");
    }
    I.iterations = it;
    each([&](std::size_t i) { h.T[i] = I.x[i]; });
    return;
  }
  // x_0 = T^n (old_ = h.T before the step: its ghost entries current), r_0 = b - A x_0.
  I.x = old_;
  I.r.assign(n, 0.0);
  I.z.assign(n, 0.0);
  I.q.assign(n, 0.0);
  apply(I.x, I.q);
  for (std::size_t k = 0; k < rows.count; ++k) {
    const std::size_t i = rows[k];
    if (I.row[i]) I.r[i] = I.b[i] - I.q[i], I.z[i] = I.r[i] / I.diag[i];
  }
  I.p = I.z;
  std::vector<double> d0 = dots({{&I.r, &I.r}, {&I.b, &I.b}, {&I.r, &I.z}});
  const double stop = std::max(1e-12 * std::sqrt(d0[0]), 1e-15 * std::sqrt(d0[1]));
  double rr = d0[0], rz = d0[2];
  const int most = 10000;
  int it = 0;
  while (std::sqrt(rr) > stop) {
    if (++it > most)
      throw Error(fmt::format("the implicit heat step did not converge in {} conjugate-gradient iterations "
                              "(residual {:.3e}, wanted {:.3e}); use a smaller solver.time_step",
                              most, std::sqrt(rr), stop));
    if (s_.decomposition) exchange_ghost_scalars(*s_.decomposition, I.p);
    apply(I.p, I.q);
    const double pq = dots({{&I.p, &I.q}})[0];
    if (!(pq > 0)) throw Error("the implicit heat step failed: the conduction matrix is not positive definite");
    const double alpha = rz / pq;
#pragma omp parallel for schedule(static)
    for (std::size_t k = 0; k < rows.count; ++k) {
      const std::size_t i = rows[k];
      if (!I.row[i]) continue;
      I.x[i] += alpha * I.p[i];
      I.r[i] -= alpha * I.q[i];
      I.z[i] = I.r[i] / I.diag[i];
    }
    const std::vector<double> d = dots({{&I.r, &I.r}, {&I.r, &I.z}});
    rr = d[0];
    const double beta = d[1] / rz;
    rz = d[1];
#pragma omp parallel for schedule(static)
    for (std::size_t k = 0; k < rows.count; ++k) {
      const std::size_t i = rows[k];
      if (I.row[i]) I.p[i] = I.z[i] + beta * I.p[i];
    }
  }
  I.iterations = it;
  for (std::size_t k = 0; k < rows.count; ++k) {
    const std::size_t i = rows[k];
    if (I.row[i]) h.T[i] = I.x[i];
  }
}


void HeatSolver::step(double dt) {
  auto& P = s_.particles;
  auto& B = s_.bonds;
  HeatState& h = s_.heat;
  const std::size_t n = P.size();
  const double t0 = h.time, t1 = h.time + dt;
  old_ = h.T;
  // Sources and films at the new time (implicit) or the old one (explicit).
  const double ts = integration_ != HeatIntegration::explicit_euler ? t1 : t0;
  std::vector<double> source(n, 0.0), film(n, 0.0), film_t(n, 0.0);
  for (const auto& bc : h.boundary) {
    if (bc.kind == ThermalBoundaryKind::flux) {
      for (uint32_t i : bc.particles) source[i] += bc.value(ts, P.X[i].x, P.X[i].y, P.X[i].z) * bc.scale;
    } else if (bc.kind == ThermalBoundaryKind::convection) {
      for (uint32_t i : bc.particles) {
        film[i] += bc.coefficient * bc.scale;
        film_t[i] += bc.coefficient * bc.scale * bc.ambient(ts, P.X[i].x, P.X[i].y, P.X[i].z);
      }
    }
  }
  if (!h.conduction) {
    // A prescribed field (thermal.conduction: false): the conditions below alone.
  } else if (integration_ == HeatIntegration::explicit_euler) {
    heat_conduction(s_, h.T, rate_);
    const Rows rows(s_);
#pragma omp parallel for schedule(static)
    for (std::size_t r = 0; r < rows.count; ++r) {
      const std::size_t i = rows[r];
      if (!h.fixed[i]) h.T[i] += dt * (rate_[i] + source[i] + film_t[i] - film[i] * h.T[i]) / h.capacity[i];
    }
  } else {
    apply_temperature_conditions(s_, t1);  // the fixed values the free ones see
    implicit_step(dt, source, film, film_t);
  }
  apply_temperature_conditions(s_, t1);
  // The heat each boundary brought in over the step (on ranks: its owned particles', on
  // the grid; serially the plain sum in the list's order).
  // (slots nb + b: the heat through boundary b particle by particle, |q| summed: the
  // scale of the run's heat balance, HeatSolver::moved)
  const int nb = static_cast<int>(h.boundary.size());
  GridSum brought(s_, 2 * nb);
  for (std::size_t b = 0; b < h.boundary.size(); ++b) {
    const HeatBoundary& bc = h.boundary[b];
    const bool implicit = integration_ != HeatIntegration::explicit_euler;
    for (uint32_t i : bc.particles) {
      if (s_.decomposition && !s_.decomposition->owns(i)) continue;
      double q = 0;
      const double Vi = P.volume[i];
      if (bc.kind == ThermalBoundaryKind::flux) {
        q += dt * Vi * bc.value(ts, P.X[i].x, P.X[i].y, P.X[i].z) * bc.scale;
      } else if (bc.kind == ThermalBoundaryKind::convection) {
        const double Ti = implicit ? h.T[i] : old_[i];
        q += dt * Vi * bc.coefficient * bc.scale * (bc.ambient(ts, P.X[i].x, P.X[i].y, P.X[i].z) - Ti);
      } else {
        // What the prescribed particle gave its free neighbours over the step (explicit:
        // at the old temperatures; implicit: at the new ones), plus its own change.
        const std::vector<double>& Tc = implicit ? h.T : old_;
        double out = 0;
        for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
          if (!B.intact[k]) continue;
          const uint32_t j = B.nbr[k];
          if (h.fixed[j]) continue;
          out += bond_kappa(h, i, j) * bond_factor(h, B, k) * (Tc[i] - Tc[j]);
        }
        q += dt * Vi * out + h.capacity[i] * Vi * (h.T[i] - old_[i]);
      }
      brought.add(static_cast<int>(b), q);
      brought.add(nb + static_cast<int>(b), std::abs(q));
    }
  }
  const std::vector<double> heat_in = brought.totals();
  for (std::size_t b = 0; b < h.boundary.size(); ++b) {
    h.boundary[b].heat += heat_in[b];
    moved_ += heat_in[static_cast<std::size_t>(nb) + b];
  }
  h.time = t1;
  exchange_ghosts(s_);  // the new temperatures of the ghosts, before the thermal strain reads them
  update_thermal_strain(s_);
}

}  // namespace horizon
