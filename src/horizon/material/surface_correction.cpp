#include "horizon/material/surface_correction.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "horizon/family/neighbors.hpp"
#include "horizon/kernels/unified.hpp"
#include "horizon/material/influence.hpp"
#include "horizon/parallel/decomposition.hpp"
#include "horizon/state/system.hpp"

namespace horizon {

FamilyView interior_family(const Config& cfg, const MaterialConfig& mat) {
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
  FamilyView f;
  for (uint64_t k = ref.begin(centre); k < ref.end(centre); ++k) {
    const BondKind& b = ref.kind_of(k);
    f.xi.push_back(points[ref.nbr[k]] - points[centre]);
    f.wv.push_back(influence(mat.influence, b.length, cfg.horizon) * b.volume * b.fraction);
  }
  return f;
}

FamilyView family_of(const System& s, uint32_t i) {
  const auto& B = s.bonds;
  const auto& X = s.particles.X;
  FamilyView f;
  for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
    const BondKind& b = B.kind_of(k);
    f.xi.push_back(X[B.nbr[k]] - X[i]);
    f.wv.push_back(b.weight * b.volume * b.fraction);
  }
  return f;
}

namespace {

constexpr double kFactorStep = 0.004;

// Per particle of `in`: itself, or for a finite-element node its nearest bonded particle
// (not a node) of `in`, the lower index on a tie. Before the proxies, a bond to a node took
// the other end's factors for both ends; in a thin plate whose factors vary through the
// thickness (surface 1.36, middle 0.91 in-plane) that made the bonds from a surface particle
// to the nodes of the middle layer stiffer than the same bonds in the pure-PD plate and
// the reverse ones softer (docs/verification.md, "Finite elements and PD-FE coupling").
std::vector<uint32_t> node_proxies(const ModelSetup& in, const std::vector<uint8_t>& member) {
  const System& s = in.system;
  const auto& B = s.bonds;
  const auto& X = s.particles.X;
  std::vector<uint32_t> proxy(X.size());
  for (uint32_t i = 0; i < proxy.size(); ++i) proxy[i] = i;
  if (!s.fe_coupling) return proxy;
  const auto& fe = s.fe_coupling->owned_particle;
  for (uint32_t i : in.particles) {
    if (!fe[i]) continue;
    double best = std::numeric_limits<double>::infinity();
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
      const uint32_t j = B.nbr[k];
      if (!member[j] || fe[j]) continue;
      const double d = norm2(X[j] - X[i]);
      if (d < best || (d == best && j < proxy[i])) best = d, proxy[i] = j;
    }
  }
  return proxy;
}

// g_ij of every bond whose ends are both particles of `in` (1 for the others). The same
// operations from either end (sums commute, n_d^2 is even in n): g_ij == g_ji bit for bit.
std::vector<double> bond_factors(const ModelSetup& in, const std::vector<Vec3>& factor) {
  const System& s = in.system;
  const auto& B = s.bonds;
  const auto& X = s.particles.X;
  const int dim = in.config.dimension;
  std::vector<uint8_t> member(X.size(), 0);
  for (uint32_t i : in.particles) member[i] = 1;
  const std::vector<uint32_t> proxy = node_proxies(in, member);
  std::vector<double> g(B.size(), 1.0);
  for (uint32_t i : in.particles)
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
      const uint32_t j = B.nbr[k];
      if (!member[j]) continue;
      // A finite-element node (fe/fe_region.hpp) enters with the factors of its proxy, the
      // nearest particle: its own family is cut where the elements take over, not by a
      // surface, and it lies where a particle of the body would have the proxy's surfaces
      // (the same distances to the faces the interface crosses).
      const Vec3& Gi = factor[proxy[i]];
      const Vec3& Gj = factor[proxy[j]];
      const Vec3 xi = X[j] - X[i];
      const double L2 = dot(xi, xi);
      double sum = 0;
      for (int a = 0; a < dim; ++a) {
        const double G = 0.5 * (Gi[a] + Gj[a]);
        sum += xi[a] * xi[a] / (L2 * G * G);
      }
      // On a logarithmic grid of step kFactorStep (g within 0.2 % of the rule's value),
      // so that the bonds share a few thousand kinds (family/bonds.hpp; docs/benchmarks.md).
      g[k] = std::exp(kFactorStep * std::round(-0.5 * std::log(sum) / kFactorStep));
    }
  return g;
}

// A build split over MPI ranks (local rows, parallel/decomposition.hpp; s.row_active set
// by the build) holds the rows of its owned particles and of their bond neighbours alone,
// while each pass reads the factors of the previous one at both ends of a held row's bonds
// (the passes carry them one horizon deeper each). After each pass every rank sends the
// factors of the held rows of `in` (id, G) to all ranks, and every particle it holds takes
// its value from a rank holding its row: every holder computed the same bits (the same
// row, in the serial order, from the same factors of the previous pass), so each factor
// is the serial program's. O(N) doubles a pass on each rank, at set-up only. Collective:
// every rank sets up every material.
void share_held_factors(const ModelSetup& in, std::vector<Vec3>& factor) {
  const System& s = in.system;
  if (world_size() < 2 || s.row_active.empty()) return;
  const auto& B = s.bonds;
  const auto& id = s.particles.id;
  std::vector<double> mine;
  for (uint32_t i : in.particles)
    if (B.end(i) > B.begin(i))
      mine.insert(mine.end(), {static_cast<double>(id[i]), factor[i].x, factor[i].y, factor[i].z});
  const std::vector<double> all = allgather_values(mine);
  for (std::size_t q = 0; q + 3 < all.size(); q += 4) {
    const auto g = static_cast<int64_t>(all[q]);
    const auto it = std::lower_bound(id.begin(), id.end(), g);  // ids ascend (local particles too)
    if (it == id.end() || *it != g) continue;
    factor[static_cast<std::size_t>(it - id.begin())] = Vec3{all[q + 1], all[q + 2], all[q + 3]};
  }
}

}  // namespace

FamilyView continuum_family(const Config& cfg, const MaterialConfig& mat) {
  const int d = cfg.dimension;
  const double delta = cfg.horizon, h = delta / kContinuumCells;
  double cell = std::pow(h, d);
  if (d == 2) cell *= cfg.thickness;
  if (d == 1) cell *= cfg.area;
  const int n = kContinuumCells + 1;
  FamilyView f;
  for (int k = (d > 2 ? -n : 0); k <= (d > 2 ? n : 0); ++k)
    for (int j = (d > 1 ? -n : 0); j <= (d > 1 ? n : 0); ++j)
      for (int i = -n; i <= n; ++i) {
        const Vec3 xi{i * h, j * h, k * h};
        const double r = norm(xi);
        // The cells the sphere cuts count by the part inside it (the linear partial-volume
        // rule, family/bonds.hpp): the sum converges as h^2 instead of h.
        const double fraction = std::clamp((delta + 0.5 * h - r) / h, 0.0, 1.0);
        if (r == 0 || fraction <= 0) continue;
        f.xi.push_back(xi);
        f.wv.push_back(influence(mat.influence, r, delta) * cell * fraction);
      }
  return f;
}

std::vector<Vec3> axis_factors(const ModelSetup& in, const AxisEnergy& energy, int iterations, Reference reference) {
  const System& s = in.system;
  const auto& B = s.bonds;
  const auto& X = s.particles.X;
  const int dim = in.config.dimension;
  const FamilyView ref = reference == Reference::lattice ? interior_family(in.config, in.material)
                                                         : continuum_family(in.config, in.material);
  double w_inf[3] = {1, 1, 1};
  for (int a = 0; a < dim; ++a) w_inf[a] = energy(ref, a);
  std::vector<Vec3> factor(X.size(), Vec3{1, 1, 1});
  FamilyView f;
  for (int it = 0; it < iterations; ++it) {
    // Each pass measures the particles with the bond factors of the previous one
    // (Jacobi), so the result does not depend on the particles' order.
    const std::vector<double> g = it == 0 ? std::vector<double>(B.size(), 1.0) : bond_factors(in, factor);
    std::vector<Vec3> next = factor;
    for (uint32_t i : in.particles) {
      // The particles' families include the finite-element nodes within a horizon, so
      // they are whole where the elements take over; the nodes' own are not measured.
      if (s.fe_coupling && s.fe_coupling->owned_particle[i]) continue;
      f.xi.clear();
      f.wv.clear();
      for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
        const BondKind& b = B.kind_of(k);
        f.xi.push_back(X[B.nbr[k]] - X[i]);
        f.wv.push_back(g[k] * b.weight * b.volume * b.fraction);
      }
      if (f.xi.empty()) continue;
      for (int a = 0; a < dim; ++a) {
        const double w = energy(f, a);
        // Rounded to 1e-4: particles in the same place relative to the surfaces get the
        // same factors whatever the order of their sums, and the passes, which carry the
        // surface's factors one horizon deeper each, leave the deep particles at the
        // interior's value; otherwise every particle near a surface would get bond kinds
        // of its own (docs/benchmarks.md, "Surface correction").
        if (w > 0) next[i][a] = std::round(1e4 * factor[i][a] * w_inf[a] / w) * 1e-4;
      }
    }
    factor = std::move(next);
    share_held_factors(in, factor);
  }
  return factor;
}

std::pair<double, double> apply_axis_factors(const ModelSetup& in, const std::vector<Vec3>& factor) {
  System& s = in.system;
  auto& B = s.bonds;
  const std::vector<double> g = bond_factors(in, factor);
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (double x : g) lo = std::min(lo, x), hi = std::max(hi, x);
  scale_bond_weights(B, g);
  for (uint32_t i : in.particles) {
    double m = 0;
    for (uint64_t k = B.begin(i); k < B.end(i); ++k)
      m += kernels::weighted_volume_term(B.weight[k], B.length[k], B.volume[k]);  // kernels/unified.hpp
    s.model.weighted_volume[i] = m;
  }
  if (lo > hi) lo = hi = 1;
  return {lo, hi};
}

}  // namespace horizon
