#include "horizon/solver/equilibrium.hpp"

#include <cmath>

#include "horizon/parallel/decomposition.hpp"
#include "horizon/solver/forces.hpp"
#include <limits>
#include <utility>

namespace horizon {

namespace {
DofMap build_map(const System& s, const Loads* loads) {
  DofMap d;
  d.dimension = s.dimension;
  const std::size_t n = s.particles.size();
  d.index.assign(3 * n, -1);
  for (std::size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      if (!s.active(c) || (loads && loads->is_constrained(i, c))) continue;
      d.index[3 * i + c] = static_cast<int32_t>(d.particle.size());
      d.particle.push_back(static_cast<uint32_t>(i));
      d.component.push_back(static_cast<uint8_t>(c));
    }
  return d;
}
}  // namespace

DofMap make_dof_map(const System& s, const Loads& loads) { return build_map(s, &loads); }
DofMap make_free_dof_map(const System& s) { return build_map(s, nullptr); }

FixedBonds::FixedBonds(System& s) : s_(s), saved_(s.particles.size(), std::numeric_limits<double>::infinity()) {
  std::swap(s_.model.critical_stretch, saved_);
  // Models with a failure law of their own (the nonlinear solid's energy law) hold it too.
  for (std::size_t m = 0; m < s_.models.size(); ++m) s_.models[m].hold_bonds(true);
}
FixedBonds::~FixedBonds() {
  std::swap(s_.model.critical_stretch, saved_);
  for (std::size_t m = 0; m < s_.models.size(); ++m) s_.models[m].hold_bonds(false);
}

// One-way bonds (bodies of different horizons): the analytic tangent takes one omega for
// both directions of a bond; the finite-difference tangent is exact for them.
bool unified_form(const System& s) { return s.models.all_unified() && !s.one_way_bonds; }

Eigen::VectorXd gather_displacement(const System& s, const DofMap& d) {
  Eigen::VectorXd u(static_cast<Eigen::Index>(d.size()));
  for (std::size_t k = 0; k < d.size(); ++k) u[static_cast<Eigen::Index>(k)] = s.particles.u[d.particle[k]][d.component[k]];
  return u;
}

void scatter_displacement(System& s, const DofMap& d, const Eigen::VectorXd& u) {
  for (std::size_t k = 0; k < d.size(); ++k) s.particles.u[d.particle[k]][d.component[k]] = u[static_cast<Eigen::Index>(k)];
}

void add_displacement(System& s, const DofMap& d, const Eigen::VectorXd& du, double alpha) {
  for (std::size_t k = 0; k < d.size(); ++k)
    s.particles.u[d.particle[k]][d.component[k]] += alpha * du[static_cast<Eigen::Index>(k)];
}

Eigen::VectorXd gather_residual(const System& s, const DofMap& d) {
  const auto& P = s.particles;
  Eigen::VectorXd r(static_cast<Eigen::Index>(d.size()));
  for (std::size_t k = 0; k < d.size(); ++k) {
    const uint32_t i = d.particle[k];
    const int c = d.component[k];
    r[static_cast<Eigen::Index>(k)] = (P.f[i][c] + P.b[i][c]) * P.volume[i];
  }
  return r;
}

LoadNorms load_norms(const System& s, const DofMap& d) {
  const auto& P = s.particles;
  if (s.decomposition) {  // the owned particles' terms, GridSum totals (see owned_dofs)
    GridSum g(s, 2);
    for (uint32_t i : s.owned)
      for (int c = 0; c < 3; ++c) {
        if (!s.active(c)) continue;
        const double b = P.b[i][c] * P.volume[i];
        g.add(0, b * b);
        if (d.dof(i, c) < 0) {
          const double r = (P.f[i][c] + P.b[i][c]) * P.volume[i];
          g.add(1, r * r);
        }
      }
    const std::vector<double> t = g.totals();
    return {std::sqrt(t[0]), std::sqrt(t[1])};
  }
  double ext = 0, react = 0;
  for (std::size_t i = 0; i < P.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      if (!s.active(c)) continue;
      const double b = P.b[i][c] * P.volume[i];
      ext += b * b;
      if (d.dof(i, c) < 0) {
        const double r = (P.f[i][c] + P.b[i][c]) * P.volume[i];
        react += r * r;
      }
    }
  return {std::sqrt(ext), std::sqrt(react)};
}

Eigen::VectorXd nodal_mass(const System& s, const DofMap& d) {
  Eigen::VectorXd m(static_cast<Eigen::Index>(d.size()));
  for (std::size_t k = 0; k < d.size(); ++k) {
    const uint32_t i = d.particle[k];
    m[static_cast<Eigen::Index>(k)] = s.particles.density[i] * s.particles.volume[i];
  }
  return m;
}

bool finite_state(const System& s) {
  if (s.decomposition) {
    bool bad = false;
    for (uint32_t i : s.owned) bad = bad || !std::isfinite(s.particles.u[i].x + s.particles.u[i].y + s.particles.u[i].z);
    return !any_rank(*s.decomposition, bad);
  }
  for (const auto& u : s.particles.u)
    if (!std::isfinite(u.x + u.y + u.z)) return false;
  return true;
}

std::vector<Eigen::Index> owned_dofs(const System& s, const DofMap& d) {
  std::vector<Eigen::Index> rows;
  if (!s.decomposition) return rows;
  for (std::size_t k = 0; k < d.size(); ++k)
    if (s.decomposition->owns(d.particle[k])) rows.push_back(static_cast<Eigen::Index>(k));
  return rows;
}

double dof_dot(const System& s, const DofMap& d, const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  if (!s.decomposition) return a.dot(b);
  GridSum g(s, 1);
  for (std::size_t k = 0; k < d.size(); ++k)
    if (s.decomposition->owns(d.particle[k])) g.add(0, a[static_cast<Eigen::Index>(k)] * b[static_cast<Eigen::Index>(k)]);
  return g.totals()[0];
}

double dof_norm(const System& s, const DofMap& d, const Eigen::VectorXd& a) {
  return s.decomposition ? std::sqrt(dof_dot(s, d, a, a)) : a.norm();
}

void keep_owned(const System& s, const DofMap& d, Eigen::VectorXd& a) {
  if (!s.decomposition) return;
  for (std::size_t k = 0; k < d.size(); ++k)
    if (!s.decomposition->owns(d.particle[k])) a[static_cast<Eigen::Index>(k)] = 0;
}

bool equilibrium_forces(System& s, bool energy) {
  if (!s.decomposition) return compute_forces(s, energy).broken > 0;
  halo_exchange(s, *s.decomposition);
  // A bond breaks in every rank that computes its row (the owner and, for a neighbour's
  // row, the ranks that compute it again): "any rank" is the global answer.
  return any_rank(*s.decomposition, compute_forces(s, energy).broken > 0);
}

}  // namespace horizon
