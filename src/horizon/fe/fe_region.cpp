#include "horizon/fe/fe_region.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <array>
#include <map>
#include <unordered_map>
#include <unordered_set>

#include "horizon/core/error.hpp"
#include "horizon/core/state_archive.hpp"
#include "horizon/deck/config.hpp"
#include "horizon/geometry/mesh.hpp"
#include "horizon/material/classical/strain_laws.hpp"
#include "horizon/parallel/decomposition.hpp"
#include "horizon/state/system.hpp"

namespace horizon {

namespace {

// Hexahedron node signs in the parent cube (the usual ordering: bottom face
// counter-clockwise, then the top face).
constexpr int kHexSign[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};

// The Kuhn split of a cube into six tetrahedra around its diagonal 0-6 (hex local
// numbering): every cube split alike, so neighbouring cubes' faces match.
constexpr int kTets[6][4] = {{0, 1, 2, 6}, {0, 2, 3, 6}, {0, 3, 7, 6}, {0, 7, 4, 6}, {0, 4, 5, 6}, {0, 5, 1, 6}};

double det3(const double J[3][3]) {
  return J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) - J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
         J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
}

// Inverse of a 3 x 3 matrix (det given).
void inv3(const double J[3][3], double d, double I[3][3]) {
  I[0][0] = (J[1][1] * J[2][2] - J[1][2] * J[2][1]) / d;
  I[0][1] = (J[0][2] * J[2][1] - J[0][1] * J[2][2]) / d;
  I[0][2] = (J[0][1] * J[1][2] - J[0][2] * J[1][1]) / d;
  I[1][0] = (J[1][2] * J[2][0] - J[1][0] * J[2][2]) / d;
  I[1][1] = (J[0][0] * J[2][2] - J[0][2] * J[2][0]) / d;
  I[1][2] = (J[0][2] * J[1][0] - J[0][0] * J[1][2]) / d;
  I[2][0] = (J[1][0] * J[2][1] - J[1][1] * J[2][0]) / d;
  I[2][1] = (J[0][1] * J[2][0] - J[0][0] * J[2][1]) / d;
  I[2][2] = (J[0][0] * J[1][1] - J[0][1] * J[1][0]) / d;
}


// Barycentric coordinates of x in the tetrahedron (a, b, c, d) (lambda_0 first); false
// for a flat one.
bool barycentric(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, const Vec3& x, double l[4]) {
  const double v = dot(b - a, cross(c - a, d - a));
  if (!(std::abs(v) > 0)) return false;
  l[1] = dot(x - a, cross(c - a, d - a)) / v;
  l[2] = dot(b - a, cross(x - a, d - a)) / v;
  l[3] = dot(b - a, cross(c - a, x - a)) / v;
  l[0] = 1 - l[1] - l[2] - l[3];
  return true;
}

// The trilinear shape functions of the hexahedron (x[8], parent cube [-1, 1]^3) at the
// point p: natural coordinates by Newton's method on x(xi) = sum_I N_I(xi) x_I (one step
// on a parallelepiped), N_I = (1 + s_I xi)(1 + t_I eta)(1 + u_I zeta) / 8. False when p is
// outside (a natural coordinate beyond 1 + 1e-9) or the iteration fails.
bool hex_weights(const Vec3 x[8], const Vec3& p, double N[8]) {
  double xi[3] = {0, 0, 0};
  const double size = norm(x[6] - x[0]);
  for (int it = 0; it < 40; ++it) {
    double dN[8][3];
    Vec3 r = -1.0 * p;
    for (int I = 0; I < 8; ++I) {
      const double f[3] = {1 + kHexSign[I][0] * xi[0], 1 + kHexSign[I][1] * xi[1], 1 + kHexSign[I][2] * xi[2]};
      N[I] = f[0] * f[1] * f[2] / 8;
      dN[I][0] = kHexSign[I][0] * f[1] * f[2] / 8;
      dN[I][1] = f[0] * kHexSign[I][1] * f[2] / 8;
      dN[I][2] = f[0] * f[1] * kHexSign[I][2] / 8;
      r += N[I] * x[I];
    }
    if (norm(r) <= 1e-13 * size)
      return std::abs(xi[0]) <= 1 + 1e-9 && std::abs(xi[1]) <= 1 + 1e-9 && std::abs(xi[2]) <= 1 + 1e-9;
    double J[3][3] = {};
    for (int I = 0; I < 8; ++I)
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) J[i][k] += x[I][i] * dN[I][k];
    const double d = det3(J);
    if (!(d > 0)) return false;
    double Ji[3][3];
    inv3(J, d, Ji);
    for (int k = 0; k < 3; ++k) {
      xi[k] -= Ji[k][0] * r.x + Ji[k][1] * r.y + Ji[k][2] * r.z;
      if (!(std::abs(xi[k]) < 4)) return false;
    }
  }
  return false;
}

// Peridynamic particles by position: a cell list of side h over the first n particles.
struct PointGrid {
  double h;
  std::unordered_map<int64_t, std::vector<uint32_t>> cells;
  static int64_t key(int64_t i, int64_t j, int64_t k) { return (i * 73856093) ^ (j * 19349663) ^ (k * 83492791); }
  int64_t index(double v) const { return static_cast<int64_t>(std::floor(v / h)); }
  PointGrid(const std::vector<Vec3>& X, std::size_t n, double side) : h(side) {
    for (std::size_t p = 0; p < n; ++p) cells[key(index(X[p].x), index(X[p].y), index(X[p].z))].push_back(static_cast<uint32_t>(p));
  }
  // Calls f(p) for the particles in the cells that meet the box [lo, hi].
  template <class F>
  void visit(const Vec3& lo, const Vec3& hi, F&& f) const {
    for (int64_t k = index(lo.z); k <= index(hi.z); ++k)
      for (int64_t j = index(lo.y); j <= index(hi.y); ++j)
        for (int64_t i = index(lo.x); i <= index(hi.x); ++i) {
          auto it = cells.find(key(i, j, k));
          if (it != cells.end())
            for (uint32_t p : it->second) f(p);
        }
  }
};

// The nodes and elements of a body made of a mesh's hex8 or tet4 cells (BodyConfig::fe_mesh,
// checked by the deck: one type, none inverted). The mesh's nodes are the FE nodes; a node
// at a peridynamic particle (to 1e-6 spacings) is that particle (shared, as the lattice
// points of a box body inside a peridynamic body are); cells whose nodes are all
// particles are left out. A particle inside a kept cell but at none of its nodes cannot
// be coupled by coincident nodes: an error. FE-owned nodes become particles (volume set
// with the lumped one later).
void add_mesh_elements(FeRegion& fe, System& s, const BodyConfig& body, std::size_t n_pd, double h, int32_t block,
                       int mat, double rho) {
  auto& P = s.particles;
  const Mesh& mesh = *body.fe_mesh;
  const double sc = body.fe_mesh_scale;
  const int npe = fe.nodes_per_element;
  const PointGrid grid(P.X, n_pd, h);
  const double tol = 1e-6 * h;
  std::vector<int64_t> pd_of(mesh.nodes.size(), -2);  // -2: not looked up, -1: no particle
  auto particle_at = [&](uint32_t n) {
    if (pd_of[n] != -2) return pd_of[n];
    const Vec3 x = mesh.nodes[n] * sc;
    int64_t found = -1;
    const Vec3 d{tol, tol, tol};
    grid.visit(x - d, x + d, [&](uint32_t p) {
      if (found < 0 && norm(P.X[p] - x) <= tol) found = p;
    });
    return pd_of[n] = found;
  };
  std::vector<uint32_t> kept;
  for (uint32_t e : body.fe_cells) {
    bool free_node = false;
    for (uint32_t n : mesh.cell_nodes[e]) free_node = free_node || particle_at(n) < 0;
    if (free_node) kept.push_back(e);
  }
  // Particles inside a kept cell (closed, to 1e-9 in barycentric coordinates; a hexahedron
  // by its six Kuhn tetrahedra, exact for plane faces) other than at its nodes.
  if (n_pd > 0)
    for (uint32_t e : kept) {
      const auto& cn = mesh.cell_nodes[e];
      std::vector<Vec3> x;
      Vec3 lo = mesh.nodes[cn[0]] * sc, hi = lo;
      for (uint32_t n : cn) {
        x.push_back(mesh.nodes[n] * sc);
        for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], x.back()[k]), hi[k] = std::max(hi[k], x.back()[k]);
      }
      grid.visit(lo, hi, [&](uint32_t p) {
        const Vec3& X = P.X[p];
        for (const Vec3& xn : x)
          if (norm(X - xn) <= tol) return;
        bool inside = false;
        double l[4];
        if (npe == 4) {
          inside = barycentric(x[0], x[1], x[2], x[3], X, l) && *std::min_element(l, l + 4) >= -1e-9;
        } else {
          for (const auto& t : kTets)
            inside = inside || (barycentric(x[static_cast<std::size_t>(t[0])], x[static_cast<std::size_t>(t[1])],
                                            x[static_cast<std::size_t>(t[2])], x[static_cast<std::size_t>(t[3])], X, l) &&
                                *std::min_element(l, l + 4) >= -1e-9);
        }
        if (inside)
          throw Error(fmt::format(
              "body '{}' (finite elements from the mesh {}): the particle at ({:g}, {:g}, {:g}) of body '{}' lies in "
              "element {} of the mesh but at none of its nodes; a peridynamic body couples to a mesh through "
              "coincident nodes: give the mesh nodes at the particles where the two overlap (the lattice of spacing "
              "{:g} m), or keep the peridynamic body out of the mesh",
              body.name, mesh.file, X.x, X.y, X.z, s.block_names[static_cast<std::size_t>(P.block[p])], e + 1, h));
      });
    }
  std::vector<int64_t> node_id(mesh.nodes.size(), -1);
  for (uint32_t e : kept) {
    for (uint32_t n : mesh.cell_nodes[e]) {
      if (node_id[n] < 0) {
        node_id[n] = static_cast<int64_t>(fe.node_particle.size());
        const Vec3 x = mesh.nodes[n] * sc;
        const int64_t p = particle_at(n);
        fe.node_X.push_back(p >= 0 ? P.X[static_cast<std::size_t>(p)] : x);
        fe.node_owned.push_back(p >= 0 ? 0 : 1);
        fe.node_particle.push_back(p >= 0 ? static_cast<uint32_t>(p) : static_cast<uint32_t>(P.size()));
        if (p < 0) P.add(x, 0.0, rho, block, mat);
      }
      fe.conn.push_back(static_cast<uint32_t>(node_id[n]));
    }
    fe.volume_scale.push_back(1.0);
  }
}
}  // namespace

std::size_t FeRegion::owned_nodes() const {
  std::size_t n = 0;
  for (auto o : node_owned) n += o;
  return n;
}

void FeRegion::setup_geometry() {
  const int n = nodes_per_element;
  const std::size_t ne = conn.size() / static_cast<std::size_t>(n);
  volume.assign(ne, 0);
  grad.assign(ne * static_cast<std::size_t>(3 * n), 0);
  if (n == 8) gamma.assign(ne * 32, 0);
  for (std::size_t e = 0; e < ne; ++e) {
    const uint32_t* c = &conn[e * static_cast<std::size_t>(n)];
    double* b = &grad[e * static_cast<std::size_t>(3 * n)];
    if (n == 8) {
      // One-point integration with the uniform gradient of Flanagan and Belytschko (1981,
      // eq. 16): b_I = (1/V) int dN_I/dx dV and V = int det J, both by 2 x 2 x 2 Gauss
      // points, which integrate them exactly for the trilinear map (det J and the cofactors
      // of J times dN_I/dxi are at most quadratic in each natural coordinate). On a
      // parallelepiped these are the centre values (J constant); on a distorted hexahedron
      // of a mesh the uniform gradient keeps sum_I x_I (x) b_I = I (linear fields exact)
      // and sum over a node's elements of V b_I = 0 (the patch test).
      const double gp = 1.0 / std::sqrt(3.0);
      double V = 0;
      for (int q = 0; q < 8; ++q) {
        const double xi[3] = {kHexSign[q][0] * gp, kHexSign[q][1] * gp, kHexSign[q][2] * gp};
        double dN[8][3];  // dN_I/dxi_k at the point
        for (int I = 0; I < 8; ++I) {
          const double f[3] = {1 + kHexSign[I][0] * xi[0], 1 + kHexSign[I][1] * xi[1], 1 + kHexSign[I][2] * xi[2]};
          dN[I][0] = kHexSign[I][0] * f[1] * f[2] / 8;
          dN[I][1] = f[0] * kHexSign[I][1] * f[2] / 8;
          dN[I][2] = f[0] * f[1] * kHexSign[I][2] / 8;
        }
        double J[3][3] = {};
        for (int I = 0; I < 8; ++I)
          for (int i = 0; i < 3; ++i)
            for (int k = 0; k < 3; ++k) J[i][k] += node_X[c[I]][i] * dN[I][k];
        const double d = det3(J);
        if (!(d > 0)) throw Error(fmt::format("finite element {} is inverted or flat (Jacobian {:.3g})", e, d));
        double Ji[3][3];
        inv3(J, d, Ji);
        // dN_I/dx det J (weight 1 per point).
        for (int I = 0; I < 8; ++I)
          for (int i = 0; i < 3; ++i) {
            double sum = 0;
            for (int k = 0; k < 3; ++k) sum += Ji[k][i] * dN[I][k];
            b[3 * I + i] += sum * d;
          }
        V += d;
      }
      for (int q = 0; q < 24; ++q) b[q] /= V;
      volume[e] = V * (e < volume_scale.size() ? volume_scale[e] : 1.0);
      // Hourglass vectors (Flanagan and Belytschko 1981, eq. 35 with their B_iI = V b_iI):
      // gamma_aI = h_aI - (sum_J h_aJ x_J) . b_I, with h_1..4 = xi eta, eta zeta, zeta xi,
      // xi eta zeta at the nodes. gamma is orthogonal to every linear field.
      for (int a = 0; a < 4; ++a) {
        double h[8];
        for (int I = 0; I < 8; ++I) {
          const int* s = kHexSign[I];
          h[I] = a == 0 ? s[0] * s[1] : a == 1 ? s[1] * s[2] : a == 2 ? s[2] * s[0] : s[0] * s[1] * s[2];
        }
        Vec3 hx;
        for (int I = 0; I < 8; ++I) hx += h[I] * node_X[c[I]];
        for (int I = 0; I < 8; ++I)
          gamma[e * 32 + static_cast<std::size_t>(a * 8 + I)] =
              h[I] - (hx.x * b[3 * I] + hx.y * b[3 * I + 1] + hx.z * b[3 * I + 2]);
      }
    } else {
      // Linear tetrahedron: N_I linear, b_I constant; J = [x1 - x0, x2 - x0, x3 - x0].
      double J[3][3];
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) J[i][k] = node_X[c[k + 1]][i] - node_X[c[0]][i];
      const double d = det3(J);
      if (!(d > 0)) throw Error(fmt::format("finite element {} is inverted or flat (Jacobian {:.3g})", e, d));
      double Ji[3][3];
      inv3(J, d, Ji);
      for (int i = 0; i < 3; ++i) {
        double s0 = 0;
        for (int k = 0; k < 3; ++k) {
          b[3 * (k + 1) + i] = Ji[k][i];
          s0 -= Ji[k][i];
        }
        b[i] = s0;
      }
      volume[e] = d / 6 * (e < volume_scale.size() ? volume_scale[e] : 1.0);
    }
  }
}

void FeRegion::apply(System& s, bool energy) {
  auto& P = s.particles;
  const int n = nodes_per_element;
  const std::size_t ne = elements();
  if (!interface_marked) mark_interface(s);
  const bool account = coupled();
  elem_force.resize(ne * static_cast<std::size_t>(n));
  elem_energy.resize(ne);
  // On ranks: the elements of this rank's FE-owned nodes alone (split).
  const std::size_t nw = split_done ? work_elements.size() : ne;
#pragma omp parallel for schedule(static)
  for (std::size_t q = 0; q < nw; ++q) {
    const std::size_t e = split_done ? work_elements[q] : q;
    const uint32_t* c = &conn[e * static_cast<std::size_t>(n)];
    const double* b = &grad[e * static_cast<std::size_t>(3 * n)];
    // Small-strain linear elasticity at the centre: H = sum_I u_I (x) b_I, eps = sym H,
    // sigma = lambda tr(eps) I + 2 mu eps; internal nodal force F_I = -V sigma b_I.
    double H[3][3] = {};
    for (int I = 0; I < n; ++I) {
      const Vec3& u = P.u[node_particle[c[I]]];
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) H[i][j] += u[i] * b[3 * I + j];
    }
    double eps[3][3], sig[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) eps[i][j] = 0.5 * (H[i][j] + H[j][i]);
    const double tr = eps[0][0] + eps[1][1] + eps[2][2];
    double w = 0;
    const double V = volume[e];
    if (plastic() && yield_stress[e] > 0) {
      // J2 plasticity at the integration point (classical/strain_laws.hpp, j2: radial
      // return of Simo and Hughes 1998, box 3.2) on the small strain eps; w is the
      // elastic energy kappa/2 tr(E_e)^2 + mu |dev E_e|^2, the step's plastic work
      // Y(eps_p,n+1) Delta eps_p goes to the ledger at commit.
      classical::StrainLawParams law;
      law.law = classical::StrainLaw::j2;
      law.kappa = lambda[e] + 2.0 * mu[e] / 3.0;
      law.mu = mu[e];
      law.yield_stress = yield_stress[e];
      law.hardening_modulus = hardening[e];
      classical::StrainLawState committed, trial;
      const double* hc = &history[e * kHistory];
      committed.plastic_strain = Eigen::Map<const Eigen::Matrix3d>(hc);
      committed.alpha = hc[9];
      Eigen::Matrix3d E;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) E(i, j) = eps[i][j];
      const classical::StrainLawOut out = classical::strain_law(law, committed, E, s.dt, trial);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) sig[i][j] = out.S(i, j);
      w = out.W;
      double* ht = &history_trial[e * kHistory];
      Eigen::Map<Eigen::Matrix3d> plastic_strain(ht);
      plastic_strain = trial.plastic_strain;
      ht[9] = trial.alpha;
      elem_work[e] = out.plastic_work * V;
    } else {
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          sig[i][j] = 2 * mu[e] * eps[i][j] + (i == j ? lambda[e] * tr : 0.0);
          w += 0.5 * sig[i][j] * eps[i][j];
        }
    }
    const double beta = damping_beta.empty() ? 0.0 : damping_beta[e];
    if (beta > 0) {
      // Interface damping (fe_region.hpp): sigma_v = beta (lambda tr(D) I + 2 mu D), D the
      // symmetric velocity gradient; its work is not stored energy (w unchanged).
      double L[3][3] = {};
      for (int I = 0; I < n; ++I) {
        const Vec3& v = P.v[node_particle[c[I]]];
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) L[i][j] += v[i] * b[3 * I + j];
      }
      const double trD = L[0][0] + L[1][1] + L[2][2];
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) sig[i][j] += beta * (mu[e] * (L[i][j] + L[j][i]) + (i == j ? lambda[e] * trD : 0.0));
    }
    Vec3* F = &elem_force[e * static_cast<std::size_t>(n)];
    for (int I = 0; I < n; ++I) {
      Vec3 f;
      for (int i = 0; i < 3; ++i) f[i] = -V * (sig[i][0] * b[3 * I] + sig[i][1] * b[3 * I + 1] + sig[i][2] * b[3 * I + 2]);
      F[I] = f;
    }
    double energy_e = V * w;
    if (n == 8) {
      // Hourglass control, stiffness form (Flanagan and Belytschko 1981, sec. 5): the
      // generalised hourglass displacements q_a = sum_I gamma_aI u_I resist with
      // F_I = -k sum_a gamma_aI q_a, energy k/2 sum_a |q_a|^2.
      const double* g = &gamma[e * 32];
      const double k = hourglass_k[e];
      for (int a = 0; a < 4; ++a) {
        Vec3 q;
        for (int I = 0; I < 8; ++I) q += g[a * 8 + I] * P.u[node_particle[c[I]]];
        for (int I = 0; I < 8; ++I) F[I] -= (k * g[a * 8 + I]) * q;
        energy_e += 0.5 * k * norm2(q);
        if (beta > 0) {
          Vec3 qv;
          for (int I = 0; I < 8; ++I) qv += g[a * 8 + I] * P.v[node_particle[c[I]]];
          for (int I = 0; I < 8; ++I) F[I] -= (beta * k * g[a * 8 + I]) * qv;
        }
      }
    }
    elem_energy[e] = energy_e;
  }
  const std::size_t nn = nodes();
  const Decomposition* d = s.decomposition;
#pragma omp parallel for schedule(static)
  for (std::size_t a = 0; a < nn; ++a) {
    if (!node_owned[a]) continue;
    const uint32_t p = node_particle[a];
    if (d && !d->owns(p)) continue;  // another rank's node: its owner sums it
    Vec3 f, fi;
    double w = 0, wi = 0;
    for (uint64_t k = node_offset[a]; k < node_offset[a + 1]; ++k) {
      const uint32_t e = node_elem[k] / static_cast<uint32_t>(n);
      f += elem_force[node_elem[k]];
      w += elem_energy[e] / n;
      // The coupling account's share: the interface elements' alone (fe_region.hpp).
      if (account && interface_element[e]) fi += elem_force[node_elem[k]], wi += elem_energy[e] / n;
    }
    P.f[p] = f / P.volume[p];
    P.damage[p] = 0;
    if (energy) P.energy[p] = w / P.volume[p];
    if (account) {
      interface_force[p] = fi;
      if (energy) interface_energy[p] = wi;
    }
  }
  // Interpolated particles: their motion is the elements' (interpolate), their own bond
  // forces are not integrated.
  for (uint32_t p : slave_particle) {
    P.f[p] = Vec3{};
    P.damage[p] = 0;
    if (energy) P.energy[p] = 0;
  }
  update_coupling_account(s, energy);
}

void FeRegion::interpolate(System& s) {
  auto& P = s.particles;
  // On ranks the ghosts' velocities too (the displacements came with halo_exchange): the
  // interpolated particles and the interface damping read the nodes' velocities.
  if (s.decomposition) exchange_ghost_values(*s.decomposition, P.v);
  const std::size_t n = static_cast<std::size_t>(nodes_per_element);
  const std::size_t ns = split_done ? work_slaves.size() : slave_particle.size();
#pragma omp parallel for schedule(static)
  for (std::size_t k = 0; k < ns; ++k) {
    const std::size_t q = split_done ? work_slaves[k] : k;
    Vec3 u, v;
    for (std::size_t I = 0; I < n; ++I) {
      const uint32_t p = node_particle[slave_node[q * n + I]];
      u += slave_weight[q * n + I] * P.u[p];
      v += slave_weight[q * n + I] * P.v[p];
    }
    P.u[slave_particle[q]] = u;
    P.v[slave_particle[q]] = v;
  }
}

void FeRegion::mark_interface(const System& s) {
  // Peridynamic particles: those the FE does not own (FeCoupling::owned_particle).
  has_peridynamics = false;
  for (uint8_t o : owned_particle) has_peridynamics = has_peridynamics || o == 0;
  // With local particles a rank may hold elements alone: the account's sums are collective.
  if (s.decomposition) has_peridynamics = any_rank(*s.decomposition, has_peridynamics);
  interface_marked = true;
  if (!has_peridynamics) return;
  const std::size_t n = static_cast<std::size_t>(nodes_per_element);
  interface_element.assign(elements(), 0);
  for (std::size_t e = 0; e < elements(); ++e) {
    bool touches = !damping_beta.empty() && damping_beta[e] > 0;  // interface damping: the coupling's work
    for (std::size_t I = 0; I < n; ++I) touches = touches || !node_owned[conn[e * n + I]];
    interface_element[e] = touches ? 1 : 0;
  }
  const std::size_t np = s.particles.size();
  interface_force.assign(np, Vec3{});
  interface_energy.assign(np, 0.0);
  if (interface_dissipated.size() != np) interface_dissipated.assign(np, 0.0);  // a checkpoint may have set it
}

void FeRegion::update_coupling_account(System& s, bool energy) {
  // This pass is the last of compute_forces (solver/forces.cpp), so P.f is every
  // particle's final internal force density (bonds, contact, elements). Only the
  // interface set (fe_region.hpp) enters: a peridynamic particle's whole force, an
  // FE-owned node's interface elements' (interface_force; 0 for interpolated particles).
  if (!coupled()) return;
  const auto& P = s.particles;
  const std::size_t np = P.size();
  const auto& owned = owned_particle;
  auto force = [&](std::size_t i) { return owned[i] ? interface_force[i] : P.f[i] * P.volume[i]; };
  if (!account_started) {
    if (!energy) return;
    account_started = 1;
    account_pending = 2;  // the start: U + D read after the commit (close_account)
  } else {
    // The particles' terms (on ranks the owned ones) added on the grid: the same total at
    // any rank and thread count, and the serial program sums the same terms the same way
    // (GridSum::exact; parallel/decomposition.hpp), so its coupling work is the MPI one.
    const std::size_t nt = s.decomposition ? s.owned.size() : np;
    std::vector<double> terms(nt);
#pragma omp parallel for schedule(static)
    for (std::size_t k = 0; k < nt; ++k) {
      const std::size_t i = s.decomposition ? s.owned[k] : k;
      terms[k] = 0.5 * dot(account_F[i] + force(i), P.u[i] - account_u[i]);
    }
    GridSum g = GridSum::exact(s, 1);
    for (double w : terms) g.add(0, w);
    internal_work += g.totals()[0];
    if (energy) account_pending = 1;
  }
  account_F.resize(np);
  account_u = P.u;
  for (std::size_t i = 0; i < np; ++i) account_F[i] = force(i);
}

void FeRegion::close_account(System& s) {
  if (!account_pending) return;
  // The interface set's stored and dissipated energy (fe_region.hpp), read after the
  // commit as the ledger reads U and D (solver/explicit.cpp): the step's plastic work is in.
  const auto& P = s.particles;
  const std::size_t nt = s.decomposition ? s.owned.size() : P.size();
  GridSum g = GridSum::exact(s, 1);
  for (std::size_t k = 0; k < nt; ++k) {
    const std::size_t i = s.decomposition ? s.owned[k] : k;
    g.add(0, owned_particle[i] ? interface_energy[i] + interface_dissipated[i]
                               : P.energy[i] * P.volume[i] + s.dissipated_at[i]);
  }
  const double stored = g.totals()[0];
  if (account_pending == 2) stored_at_start = stored;
  else coupling_work = internal_work + stored - stored_at_start;
  account_pending = 0;
}

void FeRegion::commit(System& s) {
  if (plastic()) {
    history = history_trial;
    const int n = nodes_per_element;
    const Decomposition* d = s.decomposition;
    const bool account = coupled();
    for (std::size_t a = 0; a < nodes(); ++a) {
      if (!node_owned[a] || (d && !d->owns(node_particle[a]))) continue;
      double w = 0, wi = 0;
      for (uint64_t k = node_offset[a]; k < node_offset[a + 1]; ++k) {
        const uint32_t e = node_elem[k] / static_cast<uint32_t>(n);
        w += elem_work[e];
        if (account && interface_element[e]) wi += elem_work[e];
      }
      if (w != 0) s.dissipated_at[node_particle[a]] += w / n;
      // The interface elements' share, for the coupling account (close_account): the same
      // plastic work, in D once; the account reads its change, not a second copy.
      if (wi != 0) interface_dissipated[node_particle[a]] += wi / n;
    }
    // A second commit without a force pass dissipates nothing more.
    std::fill(elem_work.begin(), elem_work.end(), 0.0);
  }
  close_account(s);
}

void FeRegion::checkpoint(StateArchive& a) {
  a.check("fe elements", elements(), "finite elements");
  // Per element, listed by its keeper particle: on ranks each element's record comes from
  // the rank that owns that particle (parallel/decomposition.cpp gather_checkpoint), one
  // that evaluates the element (split). The same bytes as a global record on one process.
  if (element_keeper.size() != elements()) {
    const std::size_t n = static_cast<std::size_t>(nodes_per_element);
    element_keeper.assign(elements(), 0);
    for (std::size_t e = 0; e < elements(); ++e) {
      const uint32_t* c = &conn[e * n];
      std::size_t I = 0;
      while (I + 1 < n && !node_owned[c[I]]) ++I;
      element_keeper[e] = node_particle[c[I]];
    }
  }
  a.io_listed("fe_history", history, element_keeper);
  a.io_listed("fe_history_trial", history_trial, element_keeper);
  a.io_listed("fe_plastic_work", elem_work, element_keeper);
}

void FeRegion::split(const std::vector<uint8_t>& is_owned, std::vector<uint8_t>& ghosts) {
  const std::size_t n = static_cast<std::size_t>(nodes_per_element);
  // The interpolated particles this rank owns or its rows read.
  work_slaves.clear();
  for (std::size_t q = 0; q < slave_particle.size(); ++q)
    if (is_owned[slave_particle[q]] || ghosts[slave_particle[q]]) work_slaves.push_back(static_cast<uint32_t>(q));
  // The elements of the FE-owned nodes this rank owns (each owned node's force is its
  // elements' sum).
  std::vector<uint8_t> take(elements(), 0);
  for (std::size_t a = 0; a < nodes(); ++a)
    if (node_owned[a] && is_owned[node_particle[a]])
      for (uint64_t k = node_offset[a]; k < node_offset[a + 1]; ++k) take[node_elem[k] / n] = 1;
  work_elements.clear();
  for (std::size_t e = 0; e < elements(); ++e)
    if (take[e]) work_elements.push_back(static_cast<uint32_t>(e));
  // Their nodes are read here: ghosts where another rank owns them.
  auto mark = [&](uint32_t p) {
    if (!is_owned[p]) ghosts[p] = 1;
  };
  for (uint32_t e : work_elements)
    for (std::size_t I = 0; I < n; ++I) mark(node_particle[conn[e * n + I]]);
  for (uint32_t q : work_slaves)
    for (std::size_t I = 0; I < n; ++I) mark(node_particle[slave_node[q * n + I]]);
  split_done = true;
}

void FeRegion::checkpoint_account(StateArchive& a) {
  a.io("fe_internal_work", internal_work);
  a.io("fe_coupling_work", coupling_work);
  a.io("fe_stored_at_start", stored_at_start);
  a.io("fe_account_started", account_started);
  // Per particle: on ranks each entry from its owner (the owners' terms are summed).
  a.io_particles("fe_account_force", account_F);
  a.io_particles("fe_account_u", account_u);
  a.io_particles("fe_account_dissipated", interface_dissipated);
}

double FeRegion::element_energy(const System&) const {
  double sum = 0;
  for (double w : elem_energy) sum += w;
  return sum;
}

double FeRegion::stable_time_step() const {
  // Element eigenvalue inequality (the assembled omega_max is at most the largest element
  // one with the element's share of the lumped mass; Hughes, "The Finite Element Method",
  // 2000, sec. 9.3). Element bound: lambda_max(K_e) <= V (3 lambda + 2 mu) lambda_max(sum_I
  // b_I b_I^T) (since tr(eps)^2 <= 3 eps:eps and |eps| <= |H|), plus the hourglass part
  // k lambda_max(sum_a gamma_a gamma_a^T) <= k sum_a |gamma_a|^2; mass per node rho V / n.
  // For a cube of side h with nu = 1/4 this gives dt = h / (1.29 c_d), the
  // one-point hexahedron's own limit (Flanagan and Belytschko 1981, sec. 7).
  double dt = std::numeric_limits<double>::infinity();
  const int n = nodes_per_element;
  for (std::size_t e = 0; e < elements(); ++e) {
    const double* b = &grad[e * static_cast<std::size_t>(3 * n)];
    double G[3][3] = {};
    for (int I = 0; I < n; ++I)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) G[i][j] += b[3 * I + i] * b[3 * I + j];
    double lmax = 0;  // Gershgorin bound on the largest eigenvalue
    for (int i = 0; i < 3; ++i) lmax = std::max(lmax, std::abs(G[i][0]) + std::abs(G[i][1]) + std::abs(G[i][2]));
    double K = volume[e] * (3 * lambda[e] + 2 * mu[e]) * lmax;
    if (n == 8) {
      // The hourglass vectors are orthogonal to the linear fields, which hold the range of
      // the one-point stiffness on a parallelepiped (b_I is linear in the nodes there), so
      // the two parts act on orthogonal subspaces: the larger of the two bounds. The
      // hourglass part: k lambda_max(Gram of gamma), Gershgorin on its rows.
      const double* g = &gamma[e * 32];
      double hg = 0;
      for (int a = 0; a < 4; ++a) {
        double row = 0;
        for (int c = 0; c < 4; ++c) {
          double d = 0;
          for (int I = 0; I < 8; ++I) d += g[a * 8 + I] * g[c * 8 + I];
          row += std::abs(d);
        }
        hg = std::max(hg, row);
      }
      K = std::max(K, hourglass_k[e] * hg);
    }
    const double omega2 = K * n / (density[e] * volume[e]);
    // With a damping ratio xi at omega the central difference needs dt <= 2 / omega
    // (sqrt(1 + xi^2) - xi) (Belytschko, Liu and Moran 2000, "Nonlinear Finite Elements
    // for Continua and Structures", eq. 6.3.27).
    const double xi = !damped.empty() && damped[e] ? interface_damping : 0.0;
    if (omega2 > 0) dt = std::min(dt, 2 / std::sqrt(omega2) * (std::sqrt(1 + xi * xi) - xi));
  }
  return dt;
}

double FeRegion::element_omega(std::size_t e) const {
  const int n = nodes_per_element;
  const double* b = &grad[e * static_cast<std::size_t>(3 * n)];
  double G[3][3] = {};
  for (int I = 0; I < n; ++I)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) G[i][j] += b[3 * I + i] * b[3 * I + j];
  double lmax = 0;
  for (int i = 0; i < 3; ++i) lmax = std::max(lmax, std::abs(G[i][0]) + std::abs(G[i][1]) + std::abs(G[i][2]));
  return std::sqrt(volume[e] * (3 * lambda[e] + 2 * mu[e]) * lmax * n / (density[e] * volume[e]));
}

void build_fe_regions(System& s, const Config& config, double radius, std::vector<uint8_t>& ghost) {
  auto& P = s.particles;
  const std::size_t n_pd = P.size();
  const double h = config.spacing;
  FeRegion fe;
  bool any = false, any_mesh = false;
  std::vector<int32_t> elem_block, elem_material;  // per element: its body and material
  for (std::size_t b = 0; b < config.bodies.size(); ++b) {
    const BodyConfig& body = config.bodies[b];
    if (body.discretization != Discretization::fe) continue;
    const int npe = body.element == FeElement::tet4 ? 4 : 8;
    if (any && npe != fe.nodes_per_element)
      throw Error("body '" + body.name + "': the finite-element bodies of one deck use one element type");
    fe.nodes_per_element = npe;
    any = true;
    int mat = -1;
    for (std::size_t m = 0; m < config.materials.size(); ++m)
      if (config.materials[m].name == body.material) mat = static_cast<int>(m);
    if (mat < 0) throw Error("body '" + body.name + "' names unknown material '" + body.material + "'");
    const MaterialConfig& mc = config.materials[static_cast<std::size_t>(mat)];
    const double E = mc.youngs_modulus, nu = mc.poissons_ratio, rho = mc.density;
    if (!(E > 0) || !(nu > -1 && nu < 0.5) || !(rho > 0))
      throw Error(fmt::format("body '{}' (finite elements): material '{}' needs a Young's modulus > 0, a Poisson's "
                              "ratio in (-1, 0.5) and a density > 0 (it has E = {}, nu = {}, density = {})",
                              body.name, mc.name, E, nu, rho));
    const double lam = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
    const std::size_t elem_before = fe.conn.size() / static_cast<std::size_t>(npe);
    // Per element of this body: its material and plasticity.
    auto add_element_data = [&] {
      const std::size_t added = fe.conn.size() / static_cast<std::size_t>(npe) - elem_before;
      if (added == 0)
        throw Error("body '" + body.name + "' (finite elements): every node of its " +
                    (body.fe_mesh ? "mesh" : "box") + " is a particle of a peridynamic body, so it has no element");
      for (std::size_t e = elem_before; e < elem_before + added; ++e) {
        fe.lambda.push_back(lam);
        fe.mu.push_back(mu);
        fe.density.push_back(rho);
        fe.hourglass_k.push_back(body.hourglass);  // scaled below, once the geometry is known
        fe.yield_stress.push_back(body.fe_yield_stress);
        fe.hardening.push_back(body.fe_hardening_modulus);
        elem_block.push_back(static_cast<int32_t>(b));
        elem_material.push_back(mat);
      }
    };
    if (body.fe_mesh) {
      any_mesh = true;
      add_mesh_elements(fe, s, body, n_pd, h, static_cast<int32_t>(b), mat, rho);
      add_element_data();
      continue;
    }
    const Box3 box = body.shape.bounds();
    const Vec3 origin = config.lattice_origin ? *config.lattice_origin : box.min + Vec3{0.5 * h, 0.5 * h, 0.5 * h};
    // Per axis: the lattice indices inside the box and their coordinates.
    int64_t first[3], count[3];
    std::vector<double> coord[3];
    double ext_lo[3], ext_hi[3];  // from the outermost lattice points to the box faces
    for (int k = 0; k < 3; ++k) {
      const double lo = (box.min[k] - origin[k]) / h, hi = (box.max[k] - origin[k]) / h;
      first[k] = static_cast<int64_t>(std::ceil(lo - 1e-9));
      const int64_t last = static_cast<int64_t>(std::floor(hi + 1e-9));
      count[k] = last - first[k] + 1;
      if (count[k] < 2)
        throw Error(fmt::format("body '{}' (finite elements): its box holds {} lattice point(s) along axis {}; an "
                                "element needs two (make the box at least two spacings long)",
                                body.name, std::max<int64_t>(0, count[k]), "xyz"[k]));
      if (count[k] > 200000) throw Error("body '" + body.name + "' (finite elements): more than 2e5 nodes along an axis");
      for (int64_t i = 0; i < count[k]; ++i) coord[k].push_back(origin[k] + static_cast<double>(first[k] + i) * h);
      ext_lo[k] = std::max(0.0, coord[k].front() - box.min[k]);
      ext_hi[k] = std::max(0.0, box.max[k] - coord[k].back());
    }
    // The peridynamic particles on this lattice inside the box (by index), which take
    // their points.
    std::unordered_map<int64_t, uint32_t> pd;
    auto key = [&](int64_t i, int64_t j, int64_t k) { return (k * count[1] + j) * count[0] + i; };
    for (std::size_t p = 0; p < n_pd; ++p) {
      int64_t idx[3];
      bool on = true;
      for (int k = 0; k < 3 && on; ++k) {
        const double v = (P.X[p][k] - origin[k]) / h;
        const double r = std::round(v);
        on = std::abs(v - r) < 1e-6 && r >= static_cast<double>(first[k]) &&
             r <= static_cast<double>(first[k] + count[k] - 1);
        idx[k] = static_cast<int64_t>(r) - first[k];
      }
      if (on) {
        pd.emplace(key(idx[0], idx[1], idx[2]), static_cast<uint32_t>(p));
      } else {
        bool inside = true;
        for (int k = 0; k < 3; ++k) inside = inside && P.X[p][k] > box.min[k] && P.X[p][k] < box.max[k];
        if (inside)
          throw Error(fmt::format(
              "body '{}' (finite elements): the particle at ({:g}, {:g}, {:g}) of body '{}' lies inside its box but "
              "off its lattice (spacing {:g} m from ({:g}, {:g}, {:g})); put the peridynamic body's box a whole number "
              "of spacings from the finite-element box, or set lattice_origin",
              body.name, P.X[p].x, P.X[p].y, P.X[p].z, s.block_names[static_cast<std::size_t>(P.block[p])], h,
              origin.x, origin.y, origin.z));
      }
    }
    // The grid lines (lattice indices of the nodes) per axis. element_size 1: every lattice
    // point. n > 1: a graded tensor-product grid. Per axis, each peridynamic body inside
    // the box has a fine zone, the lattice indices its particles take widened by the
    // band's reach m = floor(radius / h) spacings (clipped to the box): every lattice
    // point there is a line. The box's outermost points and the zones' ends are lines too,
    // and every other gap of G spacings is cut into max(1, G / n) elements of floor or ceil
    // of G / that (n to 2n - 1 spacings; a gap under n spacings is one element). So every
    // lattice point within a horizon of a peridynamic particle (the overlap band) and every
    // particle is a node of unit elements: the interface is the matching coupling of
    // element_size 1, the coarse elements lie beyond the band, and the grid stays
    // conforming (no hanging nodes). It replaces an earlier coarse grid up to the
    // peridynamic body whose band points were interpolated inside coarse elements: that
    // coupling reflected 44 % of a pulse's energy (docs/verification.md, "Interpolation
    // coupling and coarser elements").
    const int64_t es = body.fe_element_size;
    const int64_t reach = static_cast<int64_t>(std::floor(radius / h + 1e-9));
    // Per peridynamic body: the lattice indices its particles on this lattice take (also
    // outside the box: a body next to the box has its band inside it), kept where the
    // range widened by the reach meets the box along every axis.
    std::map<int32_t, std::array<std::array<int64_t, 2>, 3>> near_range;
    if (es > 1) {
      for (std::size_t p = 0; p < n_pd; ++p) {
        int64_t idx[3];
        bool on = true;
        for (int k = 0; k < 3 && on; ++k) {
          const double v = (P.X[p][k] - origin[k]) / h;
          on = std::abs(v - std::round(v)) < 1e-6;
          idx[k] = static_cast<int64_t>(std::round(v)) - first[k];
        }
        if (!on) continue;
        auto [it, fresh] = near_range.try_emplace(P.block[p]);
        for (int k = 0; k < 3; ++k) {
          auto& r = it->second[static_cast<std::size_t>(k)];
          if (fresh) r = {idx[k], idx[k]};
          r = {std::min(r[0], idx[k]), std::max(r[1], idx[k])};
        }
      }
      for (auto it = near_range.begin(); it != near_range.end();) {
        bool meets = true;
        for (int k = 0; k < 3; ++k)
          meets = meets && it->second[static_cast<std::size_t>(k)][0] - reach <= count[k] - 1 &&
                  it->second[static_cast<std::size_t>(k)][1] + reach >= 0;
        it = meets ? std::next(it) : near_range.erase(it);
      }
    }
    std::vector<int64_t> lines[3];
    for (int k = 0; k < 3; ++k) {
      if (es == 1) {
        for (int64_t i = 0; i < count[k]; ++i) lines[k].push_back(i);
        continue;
      }
      std::vector<std::array<int64_t, 2>> fine;
      std::vector<int64_t> must{0, count[k] - 1};
      for (const auto& [blk, r] : near_range) {
        const auto& rk = r[static_cast<std::size_t>(k)];
        fine.push_back({std::max<int64_t>(0, rk[0] - reach), std::min<int64_t>(count[k] - 1, rk[1] + reach)});
        must.insert(must.end(), fine.back().begin(), fine.back().end());
      }
      std::sort(must.begin(), must.end());
      must.erase(std::unique(must.begin(), must.end()), must.end());
      lines[k].push_back(must[0]);
      for (std::size_t q = 1; q < must.size(); ++q) {
        const int64_t a = must[q - 1], G = must[q] - a;
        const bool in_fine = std::any_of(fine.begin(), fine.end(), [&](const auto& f) { return a >= f[0] && must[q] <= f[1]; });
        const int64_t parts = in_fine ? G : std::max<int64_t>(1, G / es);
        int64_t at = a;
        for (int64_t e = 0; e < parts; ++e) {
          at += G / parts + (e < G % parts ? 1 : 0);
          lines[k].push_back(at);
        }
      }
    }
    const int64_t cn[3] = {static_cast<int64_t>(lines[0].size()), static_cast<int64_t>(lines[1].size()),
                           static_cast<int64_t>(lines[2].size())};
    // Node g of the grid of lines and the lattice point it sits on.
    auto fine_of = [&](int64_t g) {
      return key(lines[0][static_cast<std::size_t>(g % cn[0])], lines[1][static_cast<std::size_t>((g / cn[0]) % cn[1])],
                 lines[2][static_cast<std::size_t>(g / (cn[0] * cn[1]))]);
    };
    auto pd_at = [&](int64_t g) -> int64_t {
      auto it = pd.find(fine_of(g));
      return it == pd.end() ? -1 : static_cast<int64_t>(it->second);
    };
    const std::size_t nodes = static_cast<std::size_t>(cn[0] * cn[1] * cn[2]);
    std::vector<int64_t> node_id(nodes, -1);  // FE node id per grid node (when used)
    std::vector<uint8_t> is_pd(nodes, 0);
    for (std::size_t g = 0; g < nodes; ++g) is_pd[g] = pd_at(static_cast<int64_t>(g)) >= 0 ? 1 : 0;
    // Elements: the grid cells (or their six tetrahedra) with at least one node that no
    // peridynamic particle takes.
    std::vector<std::size_t> new_nodes;
    auto node_of = [&](int64_t g) -> uint32_t {
      auto& id = node_id[static_cast<std::size_t>(g)];
      if (id < 0) {
        id = static_cast<int64_t>(fe.node_particle.size());
        const int64_t i = g % cn[0], j = (g / cn[0]) % cn[1], k = g / (cn[0] * cn[1]);
        fe.node_X.push_back({coord[0][static_cast<std::size_t>(lines[0][static_cast<std::size_t>(i)])],
                             coord[1][static_cast<std::size_t>(lines[1][static_cast<std::size_t>(j)])],
                             coord[2][static_cast<std::size_t>(lines[2][static_cast<std::size_t>(k)])]});
        fe.node_owned.push_back(is_pd[static_cast<std::size_t>(g)] ? 0 : 1);
        fe.node_particle.push_back(is_pd[static_cast<std::size_t>(g)] ? static_cast<uint32_t>(pd_at(g)) : 0);
        if (!is_pd[static_cast<std::size_t>(g)]) new_nodes.push_back(static_cast<std::size_t>(g));
      }
      return static_cast<uint32_t>(id);
    };
    auto gkey = [&](int64_t i, int64_t j, int64_t k) { return (k * cn[1] + j) * cn[0] + i; };
    for (int64_t k = 0; k + 1 < cn[2]; ++k)
      for (int64_t j = 0; j + 1 < cn[1]; ++j)
        for (int64_t i = 0; i + 1 < cn[0]; ++i) {
          int64_t g[8];
          bool free_node = false;
          for (int I = 0; I < 8; ++I) {
            g[I] = gkey(i + (kHexSign[I][0] > 0), j + (kHexSign[I][1] > 0), k + (kHexSign[I][2] > 0));
            free_node = free_node || !is_pd[static_cast<std::size_t>(g[I])];
          }
          if (!free_node) continue;
          // The cells of the outermost layers also stand for the material between the
          // outermost lattice points and the box faces (half a spacing by default): their
          // volume (mass and stiffness) is scaled by (L + that distance) / L per axis (L
          // the cell's edge), their kinematics stay on the lattice, so every node
          // coincides with its lattice point (fe_region.hpp).
          const int64_t ijk[3] = {i, j, k};
          double scale = 1;
          for (int a = 0; a < 3; ++a) {
            const double L = static_cast<double>(lines[a][static_cast<std::size_t>(ijk[a] + 1)] -
                                                 lines[a][static_cast<std::size_t>(ijk[a])]) * h;
            scale *= (L + (ijk[a] == 0 ? ext_lo[a] : 0.0) + (ijk[a] + 2 == cn[a] ? ext_hi[a] : 0.0)) / L;
          }
          if (npe == 8) {
            for (int I = 0; I < 8; ++I) fe.conn.push_back(node_of(g[I]));
            fe.volume_scale.push_back(scale);
          } else {
            for (const auto& t : kTets) {
              bool f = false;
              for (int I : t) f = f || !is_pd[static_cast<std::size_t>(g[I])];
              if (!f) continue;
              for (int I : t) fe.conn.push_back(node_of(g[I]));
              fe.volume_scale.push_back(scale);
            }
          }
        }
    add_element_data();
    // The FE-owned nodes become particles at their lattice points (the element geometry
    // keeps node_X); the volume is set to the lumped one below.
    for (std::size_t g : new_nodes) {
      const int64_t fg = fine_of(static_cast<int64_t>(g));
      const int64_t i = fg % count[0], j = (fg / count[0]) % count[1], k = fg / (count[0] * count[1]);
      const Vec3 x{origin.x + static_cast<double>(first[0] + i) * h, origin.y + static_cast<double>(first[1] + j) * h,
                   origin.z + static_cast<double>(first[2] + k) * h};
      const uint32_t id = static_cast<uint32_t>(node_id[g]);
      fe.node_particle[id] = static_cast<uint32_t>(P.size());
      P.add(x, 0.0, rho, static_cast<int32_t>(b), mat);
    }
  }
  if (!any) return;
  if (config.dimension != 3) throw Error("finite-element bodies are three-dimensional (dimension: 3)");
  fe.setup_geometry();
  const std::size_t ne = fe.elements();
  if (std::any_of(fe.yield_stress.begin(), fe.yield_stress.end(), [](double y) { return y > 0; })) {
    fe.history.assign(ne * FeRegion::kHistory, 0.0);
    fe.history_trial = fe.history;
    fe.elem_work.assign(ne, 0.0);
  }
  const int npe = fe.nodes_per_element;
  // Hourglass stiffness k = kappa (lambda + 2 mu) V sum_I |b_I|^2 / 8: kappa times the
  // one-point element's stiffness scale for a mode of unit hourglass vector norm^2 / 8
  // (Flanagan and Belytschko 1981 take it proportional to (lambda + 2 mu) b_iI b_iI).
  for (std::size_t e = 0; e < ne; ++e) {
    double bb = 0;
    for (int q = 0; q < 3 * npe; ++q) bb += fe.grad[e * static_cast<std::size_t>(3 * npe) + q] * fe.grad[e * static_cast<std::size_t>(3 * npe) + q];
    fe.hourglass_k[e] *= (fe.lambda[e] + 2 * fe.mu[e]) * fe.volume[e] * bb / 8;
  }
  // Node -> element lists, lumped volumes (V_e / n per node) of the FE-owned nodes.
  const std::size_t nn = fe.nodes();
  fe.node_offset.assign(nn + 1, 0);
  for (uint32_t a : fe.conn) ++fe.node_offset[a + 1];
  for (std::size_t a = 0; a < nn; ++a) fe.node_offset[a + 1] += fe.node_offset[a];
  fe.node_elem.resize(fe.conn.size());
  std::vector<uint64_t> fill(fe.node_offset.begin(), fe.node_offset.end() - 1);
  for (std::size_t q = 0; q < fe.conn.size(); ++q) fe.node_elem[fill[fe.conn[q]]++] = static_cast<uint32_t>(q);
  for (std::size_t a = 0; a < nn; ++a) {
    if (!fe.node_owned[a]) continue;
    double v = 0;
    for (uint64_t k = fe.node_offset[a]; k < fe.node_offset[a + 1]; ++k) v += fe.volume[fe.node_elem[k] / static_cast<uint32_t>(npe)] / npe;
    P.volume[fe.node_particle[a]] = v;
  }
  // The overlap band: the lattice points within `radius` of a peridynamic particle (on
  // each particle's own lattice: offsets by whole spacings) that no peridynamic particle
  // takes. One at an FE-owned node is that node (a ghost: the neighbour search sees it);
  // one inside a kept element but at none of its nodes becomes an interpolated particle
  // of that element's body (u, v = sum_I N_I(X) u_I, v_I at its reference point X; no
  // mass, no force of its own; fe_region.hpp); one outside every element lies outside the
  // finite-element bodies (a free surface of the peridynamic body).
  std::vector<uint8_t> band_node(nn, 0);
  if (n_pd > 0) {
    const PointGrid pd_grid(P.X, n_pd, h);
    const PointGrid node_grid(fe.node_X, nn, h);
    const double tol = 1e-6 * h;
    const Vec3 d{tol, tol, tol};
    // Elements by their bounding boxes, cells of side 2h.
    const double side = 2 * h;
    auto cidx = [&](double v) { return static_cast<int64_t>(std::floor(v / side)); };
    std::unordered_map<int64_t, std::vector<uint32_t>> elem_cells;
    for (std::size_t e = 0; e < ne; ++e) {
      const uint32_t* c = &fe.conn[e * static_cast<std::size_t>(npe)];
      Vec3 lo = fe.node_X[c[0]], hi = lo;
      for (int I = 1; I < npe; ++I)
        for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], fe.node_X[c[I]][k]), hi[k] = std::max(hi[k], fe.node_X[c[I]][k]);
      for (int64_t k = cidx(lo.z - tol); k <= cidx(hi.z + tol); ++k)
        for (int64_t j = cidx(lo.y - tol); j <= cidx(hi.y + tol); ++j)
          for (int64_t i = cidx(lo.x - tol); i <= cidx(hi.x + tol); ++i)
            elem_cells[PointGrid::key(i, j, k)].push_back(static_cast<uint32_t>(e));
    }
    const int R = static_cast<int>(std::floor(radius / h + 1e-9));
    const double r2 = radius * radius * (1 + 2e-10);
    std::vector<std::array<int, 3>> offsets;
    for (int k = -R; k <= R; ++k)
      for (int j = -R; j <= R; ++j)
        for (int i = -R; i <= R; ++i)
          if ((i != 0 || j != 0 || k != 0) && static_cast<double>(i * i + j * j + k * k) * h * h <= r2) offsets.push_back({i, j, k});
    struct KeyHash {
      std::size_t operator()(const std::array<int64_t, 3>& a) const {
        return static_cast<std::size_t>(PointGrid::key(a[0], a[1], a[2]));
      }
    };
    std::unordered_set<std::array<int64_t, 3>, KeyHash> seen;
    const double quantum = 1e-3 * h;
    double N[8];
    for (std::size_t p = 0; p < n_pd; ++p)
      for (const auto& o : offsets) {
        const Vec3 x = P.X[p] + Vec3{o[0] * h, o[1] * h, o[2] * h};
        if (!seen.insert({std::llround(x.x / quantum), std::llround(x.y / quantum), std::llround(x.z / quantum)}).second)
          continue;
        bool taken = false;
        pd_grid.visit(x - d, x + d, [&](uint32_t q) { taken = taken || norm(P.X[q] - x) <= tol; });
        if (taken) continue;
        int64_t node = -1;
        node_grid.visit(x - d, x + d, [&](uint32_t a) {
          if (node < 0 && norm(fe.node_X[a] - x) <= tol) node = a;
        });
        if (node >= 0) {
          band_node[static_cast<std::size_t>(node)] = 1;
          continue;
        }
        auto it = elem_cells.find(PointGrid::key(cidx(x.x), cidx(x.y), cidx(x.z)));
        if (it == elem_cells.end()) continue;
        for (uint32_t e : it->second) {
          const uint32_t* c = &fe.conn[static_cast<std::size_t>(e) * static_cast<std::size_t>(npe)];
          Vec3 xn[8];
          for (int I = 0; I < npe; ++I) xn[I] = fe.node_X[c[I]];
          const bool in = npe == 8 ? hex_weights(xn, x, N)
                                   : barycentric(xn[0], xn[1], xn[2], xn[3], x, N) && *std::min_element(N, N + 4) >= -1e-9;
          if (!in) continue;
          fe.slave_particle.push_back(static_cast<uint32_t>(P.size()));
          for (int I = 0; I < npe; ++I) {
            fe.slave_node.push_back(c[I]);
            fe.slave_weight.push_back(N[I]);
          }
          P.add(x, 0.0, fe.density[e], elem_block[e], elem_material[e]);
          break;
        }
      }
  }
  // Interface damping (fe_region.hpp): the elements with a node at a peridynamic particle
  // or in the overlap band.
  fe.damped.assign(ne, 0);
  fe.damping_beta.assign(ne, 0.0);
  if (fe.interface_damping > 0)
    for (std::size_t e = 0; e < ne; ++e) {
      for (int I = 0; I < npe; ++I) {
        const uint32_t a = fe.conn[e * static_cast<std::size_t>(npe) + static_cast<std::size_t>(I)];
        if (!fe.node_owned[a] || band_node[a]) fe.damped[e] = 1;
      }
      if (fe.damped[e]) fe.damping_beta[e] = 2 * fe.interface_damping / fe.element_omega(e);
    }
  fe.owned_particle.assign(P.size(), 0);
  ghost.assign(P.size(), 0);
  for (std::size_t a = 0; a < nn; ++a)
    if (fe.node_owned[a]) {
      fe.owned_particle[fe.node_particle[a]] = 1;
      ghost[fe.node_particle[a]] = band_node[a];
    }
  for (uint32_t p : fe.slave_particle) fe.owned_particle[p] = ghost[p] = 1;
  // A mesh body next to a peridynamic body without a shared node would see the particles
  // only through their bonds to its nodes, never through its elements: refused.
  if (any_mesh && fe.shared_nodes() == 0 && std::any_of(ghost.begin(), ghost.end(), [](uint8_t g) { return g != 0; }))
    throw Error("a finite-element body from a mesh lies within a horizon of a peridynamic body but none of its nodes "
                "is a particle: the coupling needs an overlap of at least one element whose nodes include the "
                "particles there (mesh nodes on the peridynamic lattice; docs/input.md, \"Finite-element bodies\")");
  s.fe = std::make_shared<FeRegion>(std::move(fe));
  s.fe_coupling = s.fe;  // the same object, for the rooms below fe/ (state/system.hpp)
}

}  // namespace horizon
