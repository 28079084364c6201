#pragma once
// Shared helpers of the verification tests: a deck turned into a running simulation
// through the same library calls `horizon run` chains, and the small measurements the
// checks make on it (arrival of a pulse at a station, a least-squares displacement
// gradient, the output directory under the build tree).
#include <Eigen/Dense>

#include <array>
#include <cmath>
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
#include "horizon/solver/system.hpp"

namespace horizon::verification {

inline std::string source_path(const std::string& relative) { return std::string(HORIZON_SOURCE_DIR) + "/" + relative; }

inline std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// A fresh directory for a test's output, under the build tree (beside the horizon
// executable), so that runs never write into the source tree.
inline std::filesystem::path output_dir(const std::string& name) {
  const auto dir = std::filesystem::path(HORIZON_BINARY).parent_path() / "test-output" / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
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

// A sampled signal s(t) at a station, and the time its leading edge first reaches half
// of the signal's maximum, interpolated linearly between samples. The half-maximum of
// the leading edge is insensitive to the slow, short-wavelength tail that dispersion
// leaves behind the pulse.
struct StationRecord {
  std::vector<double> t, s;

  void add(double time, double value) {
    t.push_back(time);
    s.push_back(value);
  }
  double peak() const {
    double m = 0;
    for (double x : s) m = std::max(m, x);
    return m;
  }
  std::optional<double> half_max_arrival() const {
    const double half = 0.5 * peak();
    if (!(half > 0)) return std::nullopt;
    for (std::size_t k = 1; k < s.size(); ++k)
      if (s[k - 1] < half && s[k] >= half) return t[k - 1] + (t[k] - t[k - 1]) * (half - s[k - 1]) / (s[k] - s[k - 1]);
    return std::nullopt;
  }
  // Time of the maximum, from the parabola through the largest sample and its neighbours.
  std::optional<double> peak_time() const {
    std::size_t k = 0;
    for (std::size_t i = 1; i < s.size(); ++i)
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

}  // namespace horizon::verification
