#pragma once
// Shared helpers of the verification tests: a deck turned into a running simulation
// through the same library calls `horizon run` chains, and the small measurements the
// checks make on it (arrival of a pulse at a station, a least-squares displacement
// gradient, the output directory under the build tree).
#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "horizon/deck/deck.hpp"
#include "horizon/driver/run.hpp"
#include "horizon/loading/loads.hpp"
#include "horizon/solver/explicit.hpp"
#include "horizon/solver/build.hpp"
#include "../test_paths.hpp"

namespace horizon::verification {

// A 2-D plane-stress strip under uniaxial stress, the deck of the correspondence J2 and
// neo-Hookean checks (defined and described in test_correspondence.cpp); `material` is the
// material map's inside.
std::string strip_deck(const std::string& material, double end_strain, int load_steps);

inline std::string source_path(const std::string& relative) { return std::string(HORIZON_SOURCE_DIR) + "/" + relative; }

inline std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// A fresh directory for a test's output, under the build tree (beside the horizon
// executable), so that runs never write into the source tree.
// The directory is named after the running test too: ctest runs each test in its own
// process, two at a time, and two tests that share a run (a cached function) would
// otherwise write, and wipe, the same directory at once.
inline std::filesystem::path output_dir(const std::string& name) {
  std::string leaf = name;
  if (const auto* test = ::testing::UnitTest::GetInstance()->current_test_info())
    leaf += std::string(".") + test->test_suite_name() + "." + test->name();
  const auto dir = std::filesystem::path(HORIZON_BINARY).parent_path() / "test-output" / leaf;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// Prints a measured figure so that it shows in the test log (ctest -V, or the test
// binary run directly), and records it in the XML report.
inline void report(const std::string& key, double value, const std::string& text) {
  std::printf("[ figure ] %s\n", text.c_str());
  std::fflush(stdout);
  ::testing::Test::RecordProperty(key, std::to_string(value));
}

inline nlohmann::json read_json(const std::filesystem::path& path) {
  return nlohmann::json::parse(read_text(path.string()));
}

// A deck made ready to step: system, loads and explicit solver, initialised exactly as
// run_deck does (initial conditions, then the solver's first force pass). Not movable:
// the solver keeps references to the system and the loads.
struct Simulation {
  Config config;
  System system;
  Loads loads;
  std::unique_ptr<ExplicitSolver> solver;

  explicit Simulation(Config c) : config(std::move(c)), system(build_system(config)), loads(config, system) {
    loads.apply_initial_conditions(config, system);
    solver = std::make_unique<ExplicitSolver>(system, loads, run_time_step(config, system), config.solver.damping);
    solver->initialize();
  }
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  // Steps until solver time reaches `end` (the last step may overshoot by < dt), calling
  // observe() after every step.
  void run_to(double end, const std::function<void()>& observe = {}) {
    while (solver->time() < end - 1e-12 * end) {
      solver->step(false);
      if (observe) observe();
    }
  }

  // Index of the particle nearest to x.
  std::size_t nearest(const Vec3& x) const {
    std::size_t best = 0;
    double d = 1e300;
    for (std::size_t i = 0; i < system.particles.size(); ++i)
      if (norm2(system.particles.X[i] - x) < d) {
        d = norm2(system.particles.X[i] - x);
        best = i;
      }
    return best;
  }
};

// A sampled signal s(t) at a station, and when the first pulse passes it. The first
// pulse is the first stretch where the signal stays above a quarter of its overall
// maximum (later pulses, such as reflections, may follow). Its arrival is the time its
// leading edge reaches half of the pulse's own maximum, interpolated linearly between
// samples: the half-maximum of the leading edge is insensitive to the slow,
// short-wavelength tail that dispersion leaves behind a pulse.
struct StationRecord {
  std::vector<double> t, s;

  void add(double time, double value) {
    t.push_back(time);
    s.push_back(value);
  }
  // [first, last] samples of the first pulse; empty when the signal never rises.
  std::optional<std::pair<std::size_t, std::size_t>> first_pulse() const {
    double top = 0;
    for (double x : s) top = std::max(top, x);
    if (!(top > 0)) return std::nullopt;
    std::size_t a = 0;
    while (a < s.size() && s[a] < 0.25 * top) ++a;
    std::size_t b = a;
    while (b + 1 < s.size() && s[b + 1] >= 0.25 * top) ++b;
    return std::make_pair(a, b);
  }
  double peak() const {
    const auto p = first_pulse();
    double m = 0;
    if (p)
      for (std::size_t k = p->first; k <= p->second; ++k) m = std::max(m, s[k]);
    return m;
  }
  std::optional<double> half_max_arrival() const {
    const auto p = first_pulse();
    if (!p || p->first == 0) return std::nullopt;
    const double half = 0.5 * peak();
    for (std::size_t k = 1; k <= p->second; ++k)
      if (s[k - 1] < half && s[k] >= half) return t[k - 1] + (t[k] - t[k - 1]) * (half - s[k - 1]) / (s[k] - s[k - 1]);
    return std::nullopt;
  }
  // Time of the first pulse's maximum, from the parabola through the largest sample and
  // its neighbours.
  std::optional<double> peak_time() const {
    const auto p = first_pulse();
    if (!p) return std::nullopt;
    std::size_t k = p->first;
    for (std::size_t i = p->first; i <= p->second; ++i)
      if (s[i] > s[k]) k = i;
    if (k == 0 || k + 1 >= s.size()) return std::nullopt;
    const double a = s[k - 1], b = s[k], c = s[k + 1];
    const double den = a - 2 * b + c;
    const double shift = den != 0 ? 0.5 * (a - c) / den : 0.0;
    return t[k] + shift * (t[k + 1] - t[k - 1]) / 2;
  }
};

// Least-squares fit u(X) = a + G X over the chosen particles; returns G (G(r, c) =
// du_r/dX_c), the displacement gradient of a homogeneous deformation.
inline Eigen::Matrix3d displacement_gradient(const Particles& P, const std::vector<std::size_t>& ids) {
  Eigen::Matrix4d A = Eigen::Matrix4d::Zero();
  Eigen::Matrix<double, 4, 3> rhs = Eigen::Matrix<double, 4, 3>::Zero();
  for (std::size_t i : ids) {
    const Eigen::Vector4d row(1.0, P.X[i].x, P.X[i].y, P.X[i].z);
    A += row * row.transpose();
    for (int c = 0; c < 3; ++c) rhs.col(c) += row * P.u[i][c];
  }
  const Eigen::Matrix<double, 4, 3> coef = A.ldlt().solve(rhs);
  Eigen::Matrix3d G;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) G(r, c) = coef(c + 1, r);
  return G;
}

// Force that particle j exerts on particle i through bond k of i's row [N], from the
// unified form of state/system.hpp: (t_ij + t_ji) Y/|Y| V_i V_j with
// t_ij = omega (P_i |xi| + Q_i e + R_i e/|xi|). Needs the P_i of the last force pass.
inline Vec3 pair_force(const System& s, std::size_t i, uint64_t k) {
  const auto& P = s.particles;
  const auto& B = s.bonds;
  const auto& M = s.model;
  if (!B.intact[k]) return {};
  const uint32_t j = B.nbr[k];
  const Vec3 Y = P.X[j] + P.u[j] - P.X[i] - P.u[i];
  const double y = norm(Y), L = B.length[k], e = y - L;
  const double ti = M.P[i] * L + M.deviatoric_coef[i] * e + M.pair_coef[i] / L * e;
  const double tj = M.P[j] * L + M.deviatoric_coef[j] * e + M.pair_coef[j] / L * e;
  return Y * (B.weight[k] * (ti + tj) / y * B.volume[k] * P.volume[i]);
}

// The force transmitted across the plane X[axis] = at through the patch lo <= X[a] <= hi
// of the two other axes a: the sum of the pair forces of the bonds that cross the plane
// there (the Lehoucq-Silling force flux), the force the material on the high side
// exerts on the low side. A bond is counted where its segment meets the plane; one that
// meets it exactly on the patch's edge counts half (a quarter at a corner), so that
// patches that tile the plane share the bonds between them.
inline Vec3 force_through_patch(const System& s, int axis, double at, double lo, double hi) {
  const auto& P = s.particles;
  const auto& B = s.bonds;
  const double tol = 1e-9 * s.spacing;
  auto weight = [&](double c) {
    if (std::abs(c - lo) < tol || std::abs(c - hi) < tol) return 0.5;
    return c > lo && c < hi ? 1.0 : 0.0;
  };
  Vec3 F;
  for (std::size_t i = 0; i < P.size(); ++i) {
    if (P.X[i][axis] > at) continue;
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
      const Vec3& xj = P.X[B.nbr[k]];
      if (xj[axis] < at) continue;
      const double f = (at - P.X[i][axis]) / (xj[axis] - P.X[i][axis]);
      const Vec3 cross_at = P.X[i] + (xj - P.X[i]) * f;
      double w = 1;
      for (int a = 0; a < 3; ++a)
        if (a != axis) w *= weight(cross_at[a]);
      if (w > 0) F += pair_force(s, i, k) * w;
    }
  }
  return F;
}

// A block pulled along x by equal and opposite tractions on its end layers, run with
// damping to rest (config.solver.end_time), and what it shows at rest.
struct TensionResult {
  double youngs_interior = 0;  // interior stress / interior axial strain
  double youngs_apparent = 0;  // traction / interior axial strain
  double youngs_section = 0;   // traction / mean axial strain of the whole section (middle half)
  double poisson = 0;          // -lateral / axial strain, interior
  double poisson_section = 0;  // the same over the whole section (middle half)
  double interior_stress = 0;  // [Pa]
  double end_force = 0;        // total force of the traction on the "right" region [N]
  double traction = 0;         // [Pa]
  std::size_t interior_particles = 0;
};

// The block is config.bodies[0], a box with a square section; the traction is the x
// component of the load on region "right". At rest:
// - interior strains: the least-squares displacement gradient over the particles more
//   than one horizon from every surface;
// - interior stress: the force through the interior square of the mid-plane (the bonds
//   that cross it there, force_through_patch) over its area;
// - section strains: the gradient over every particle of the middle half of the block.
inline TensionResult measure_tension(Config config) {
  TensionResult r;
  for (const auto& L : config.loads)
    if (L.region == "right") r.traction = (*L.value[0])(0, 0, 0, 0);
  const Box3 box = config.bodies.at(0).shape.bounds();
  Simulation sim(std::move(config));
  const System& s = sim.system;
  const auto& P = s.particles;

  sim.run_to(sim.config.solver.end_time);
  sim.solver->step(true);  // brings the ledger's energies up to date
  const Ledger& g = sim.solver->ledger();
  EXPECT_LT(g.kinetic, 1e-9 * g.strain) << "the block is not at rest: run longer or damp more";

  const double d = s.horizon;
  std::vector<std::size_t> interior, middle;
  for (std::size_t i = 0; i < P.size(); ++i) {
    bool inside = true;
    for (int k = 0; k < 3; ++k) inside = inside && P.X[i][k] > box.min[k] + d && P.X[i][k] < box.max[k] - d;
    if (inside) interior.push_back(i);
    const double xi = (P.X[i].x - box.min.x) / (box.max.x - box.min.x);
    if (xi > 0.25 && xi < 0.75) middle.push_back(i);
  }
  r.interior_particles = interior.size();
  const Eigen::Matrix3d G = displacement_gradient(P, interior);
  const Eigen::Matrix3d Gs = displacement_gradient(P, middle);
  // Uniaxial stress along x: no shear, equal lateral strains (the square section).
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      if (a != b) {
        EXPECT_LT(std::abs(G(a, b)), 1e-3 * G(0, 0)) << "G(" << a << "," << b << ")";
      }
    }
  EXPECT_NEAR(G(1, 1) / G(2, 2), 1.0, 1e-6);

  // The interior square of the mid-plane (between two lattice layers when the block has
  // an even number of layers).
  EXPECT_NEAR(box.max.y - box.min.y, box.max.z - box.min.z, 1e-12) << "a square section";
  const double lo = box.min.y + d, hi = box.max.y - d;
  const Vec3 F = force_through_patch(s, 0, 0.5 * (box.min.x + box.max.x), lo, hi);
  for (const auto& L : sim.loads.loads())
    if (L.name.rfind("right:", 0) == 0) r.end_force = L.reaction.x;
  r.interior_stress = F.x / ((hi - lo) * (hi - lo));
  r.youngs_interior = r.interior_stress / G(0, 0);
  r.youngs_apparent = r.traction / G(0, 0);
  r.youngs_section = r.traction / Gs(0, 0);
  r.poisson = -0.5 * (G(1, 1) + G(2, 2)) / G(0, 0);
  r.poisson_section = -0.5 * (Gs(1, 1) + Gs(2, 2)) / Gs(0, 0);
  return r;
}

}  // namespace horizon::verification
