#pragma once
// Shared checks of the history models (elastic_plastic, viscoelastic; test_elastic_plastic.cpp
// and test_viscoelastic.cpp):
// - MaterialPoint: a lattice block just large enough that its centre particle has a full
//   family (partial volumes), deformed homogeneously, u = eps (X - X_c), on every particle;
//   the stress at the centre is the collapsed force state sigma = sum_j T_j (x) xi_j V_j
//   (seed 003 digest sec. 7.3 and 13.3: the classical stress for a homogeneous deformation,
//   first Piola). A strain history is driven step by step through the general force pass
//   (compute_forces) and commit_history, as a solver does, and strain components can be
//   solved for so that stress components vanish or take a value (uniaxial stress, creep);
// - a small impact deck (a striker bonded to a bar) for the ledger, momentum and thread
//   checks; a small static block for Newton (finite-difference tangent) against ADR.
#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <omp.h>

#include "horizon/deck/deck.hpp"
#include "horizon/kernels/affine.hpp"
#include "horizon/solver/explicit.hpp"
#include "horizon/solver/forces.hpp"
#include "horizon/solver/forces_general.hpp"
#include "horizon/solver/static_driver.hpp"
#include "../unit/test_helpers.hpp"
#include "verification_support.hpp"

namespace horizon::verification {

using Strain3 = std::array<std::array<double, 3>, 3>;

struct MaterialPoint {
  test::BlockSpec spec;
  System s;
  std::size_t centre = 0;
  double time = 0;

  // A block of (2 ceil(r + 1/2) + 1)^d points, r = horizon/spacing, partial volumes.
  MaterialPoint(const MaterialConfig& mat, int dimension, PlaneMode plane, double r) {
    spec.dimension = dimension;
    spec.plane = plane;
    spec.horizon_factor = r;
    spec.partial_volume = true;
    const int n = 2 * static_cast<int>(std::ceil(r + 0.5)) + 1;
    spec.n = {n, n, dimension == 3 ? n : 1};
    s = test::make_block(spec, mat);
    Vec3 c;
    for (int a = 0; a < dimension; ++a) c[a] = (n / 2) * spec.spacing;
    double best = 1e300;
    for (std::size_t i = 0; i < s.particles.size(); ++i)
      if (norm2(s.particles.X[i] - c) < best) {
        best = norm2(s.particles.X[i] - c);
        centre = i;
      }
  }

  // The stress at the centre under u = eps (X - X_c) at time t (the trial state: nothing
  // is committed).
  Eigen::Matrix3d stress(const Strain3& eps, double t) {
    auto& P = s.particles;
    const Vec3 xc = P.X[centre];
    for (std::size_t i = 0; i < P.size(); ++i) P.u[i] = test::apply(eps, P.X[i] - xc);
    s.time = t;
    s.dt = t - time;
    // A model's pair form of the pass (Model::takes_pair_pass) keeps no force state per
    // bond: the stress is read from its vector form, the reference it agrees with.
    const bool pair = s.models.size() == 1 && s.models[0].takes_pair_pass(s) && !general_reference();
    if (pair) set_general_reference(true);
    compute_forces(s, false);
    if (pair) set_general_reference(false);
    Eigen::Matrix3d sigma = Eigen::Matrix3d::Zero();
    const auto& B = s.bonds;
    for (uint64_t k = B.begin(centre); k < B.end(centre); ++k) {
      const Vec3 xi = P.X[B.nbr[k]] - xc;
      // The force state of bond k: the vector pass's T, or the scalar pass's q Y
      // (solver/forces_ordinary.cpp), whichever the pass wrote.
      const auto& M = s.model;
      const Vec3 Y = (P.X[B.nbr[k]] + P.u[B.nbr[k]]) - (P.X[centre] + P.u[centre]);
      Vec3 T = M.force_state.size() == B.size() ? M.force_state[k] : Vec3{};
      if (M.force_state.size() != B.size() && M.force_scalar.size() == B.size()) T = M.force_scalar[k] * Y;
      if (M.force_state.size() != B.size() && !M.affine_record.empty()) {
        // The affine pass's record (solver/forces_affine.cpp): T = omega (M_i xi + g_i Y).
        const double xv[3] = {xi.x, xi.y, xi.z}, yv[3] = {Y.x, Y.y, Y.z};
        double t[3];
        kernels::affine_force_state(M.affine_record.data() + kernels::kAffineRecord * centre,
                                           B.intact[k] ? B.weight[k] : 0.0, xv, yv, t);
        T = {t[0], t[1], t[2]};
      }
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) sigma(a, b) += T[a] * xi[b] * B.volume[k];
    }
    return sigma;
  }
  // Accepts the last stress() evaluation as the new state.
  void commit(double t) {
    commit_history(s);
    time = t;
  }
};

// Secant solve of g(x) = 0 from two starting points (g smooth and nearly linear here).
inline double secant(const std::function<double(double)>& g, double x0, double x1, double tol) {
  double g0 = g(x0), g1 = g(x1);
  for (int it = 0; it < 50 && std::abs(g1) > tol && g1 != g0; ++it) {
    const double x2 = x1 - g1 * (x1 - x0) / (g1 - g0);
    x0 = x1;
    g0 = g1;
    x1 = x2;
    g1 = g(x1);
  }
  return x1;
}

// A material of `model` with E, nu and its deck parameters (defaults filled in).
inline MaterialConfig model_material(const std::string& model, double E, double nu, double density,
                                     const std::vector<std::pair<std::string, double>>& parameters) {
  MaterialConfig m = test::make_material(model, E, nu, density);
  for (const auto& [k, v] : parameters) m.parameters[k] = v;
  fill_model_defaults(m);
  return m;
}

// Linear and angular momentum of the system (about the origin, current positions).
inline std::pair<Vec3, Vec3> momenta(const System& s) {
  const auto& P = s.particles;
  Vec3 p, L;
  for (std::size_t i = 0; i < P.size(); ++i) {
    const double m = P.density[i] * P.volume[i];
    p += P.v[i] * m;
    L += cross(P.X[i] + P.u[i], P.v[i]) * m;
  }
  return {p, L};
}

// A steel striker (6 x 4 x 4 mm) bonded to a bar (12 x 4 x 4 mm) of the same material
// `material_yaml`, spacing 1 mm, horizon 3 mm; the striker moves at (v, v/6, 0), off
// the axis, so that the bodies also turn.
inline std::string impact_deck(const std::string& material_yaml, double v, double end_time) {
  return fmt::format(R"(dimension: 3
spacing: 1.0e-3
horizon: 3.0e-3
materials:
  steel: {}
bodies:
  - name: striker
    material: steel
    shape: {{box: {{min: [0, 0, 0], max: [0.006, 0.004, 0.004]}}}}
  - name: bar
    material: steel
    shape: {{box: {{min: [0.006, 0, 0], max: [0.018, 0.004, 0.004]}}}}
regions:
  striker: {{box: {{min: [0, 0, 0], max: [0.006, 0.004, 0.004]}}}}
initial_conditions:
  - {{region: striker, velocity: [{}, {}, 0]}}
solver: {{type: explicit, end_time: {}, safety_factor: 0.5}}
)",
                     material_yaml, v, v / 6, end_time);
}

// Runs a deck's explicit dynamics to its end, the ledger brought up to date every step.
struct ImpactRun {
  double max_balance_error = 0;
  Ledger ledger;
  std::vector<Vec3> u, v;
  std::vector<double> dissipated_at;
  Vec3 p0, L0, p1, L1;
  uint64_t broken = 0;
  int steps = 0;
};

inline ImpactRun run_impact(const std::string& deck, int threads) {
  const int saved = omp_get_max_threads();
  omp_set_num_threads(threads);
  Simulation sim(parse_deck(deck, "impact.yaml"));
  ImpactRun r;
  std::tie(r.p0, r.L0) = momenta(sim.system);
  sim.run_to(sim.config.solver.end_time, [&] {
    sim.solver->update_kinetic();
    ++r.steps;
  });
  omp_set_num_threads(saved);
  r.ledger = sim.solver->ledger();
  std::tie(r.p1, r.L1) = momenta(sim.system);
  r.u = sim.system.particles.u;
  r.v = sim.system.particles.v;
  r.dissipated_at = sim.system.dissipated_at;
  r.broken = sim.system.broken;
  return r;
}

// The same, with the ledger's strain energy brought up to date every step and the
// largest |balance error| over the run.
inline ImpactRun run_impact_ledger(const std::string& deck) {
  test::SingleThread one;
  Simulation sim(parse_deck(deck, "impact.yaml"));
  ImpactRun r;
  while (sim.solver->time() < sim.config.solver.end_time * (1 - 1e-12)) {
    sim.solver->step(true);
    r.max_balance_error = std::max(r.max_balance_error, std::abs(sim.solver->ledger().balance_error()));
    ++r.steps;
  }
  r.ledger = sim.solver->ledger();
  return r;
}

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

// A 10 x 4 x 4 mm block pulled by +-traction on its end layers, held against rigid motion
// by three supports (as examples/block_tension_static.yaml), solved statically.
inline Config static_block_deck(const std::string& material_yaml, double traction, const std::string& solver_yaml) {
  return parse_deck(fmt::format(R"(dimension: 3
spacing: 1.0e-3
horizon: 3.0e-3
partial_volume: true
materials:
  solid: {}
bodies:
  - name: block
    material: solid
    shape: {{box: {{min: [0, 0, 0], max: [0.010, 0.004, 0.004]}}}}
regions:
  left:   {{box: {{min: [0, 0, 0], max: [0.0012, 0.004, 0.004]}}}}
  right:  {{box: {{min: [0.0088, 0, 0], max: [0.010, 0.004, 0.004]}}}}
  pin:    {{box: {{min: [0, 0, 0], max: [0.001, 0.001, 0.001]}}}}
  roller: {{box: {{min: [0.009, 0, 0], max: [0.010, 0.001, 0.001]}}}}
  guide:  {{box: {{min: [0, 0.003, 0], max: [0.001, 0.004, 0.001]}}}}
loads:
  - {{region: left,   traction: [{}, 0, 0]}}
  - {{region: right,  traction: [{}, 0, 0]}}
  - {{region: pin,    displacement: [0, 0, 0]}}
  - {{region: roller, displacement: [null, 0, 0]}}
  - {{region: guide,  displacement: [null, null, 0]}}
solver: {}
)",
                                material_yaml, -traction, traction, solver_yaml),
                    "static_block.yaml");
}

// Runs a static deck to its end; returns the displacements (empty on failure).
inline std::vector<Vec3> solve_static(const Config& config, std::string* failure = nullptr) {
  test::SingleThread one;
  System s = build_system(config);
  Loads loads(config, s);
  loads.apply_initial_conditions(config, s);
  StaticSolver solver(s, loads, config.solver);
  solver.initialize();
  while (!solver.done())
    if (!solver.advance()) {
      if (failure) *failure = solver.failure();
      return {};
    }
  return s.particles.u;
}

inline double max_difference(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  double d = 0, m = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    d = std::max(d, norm(a[i] - b[i]));
    m = std::max(m, norm(b[i]));
  }
  return d / m;
}

// Largest |f_i| after a rigid motion u = (R - I) X + c of a block of `mat`, relative to
// the force scale of a strain of 1e-3 (E 1e-3 V / spacing).
inline double rigid_motion_force(const MaterialConfig& mat, int dimension, PlaneMode plane) {
  test::SingleThread one;
  test::BlockSpec b;
  b.dimension = dimension;
  b.plane = plane;
  b.n = {7, 6, dimension == 3 ? 5 : 1};
  b.horizon_factor = 3;
  b.partial_volume = true;
  System s = test::make_block(b, mat);
  const double a = 0.6, c = std::cos(a), sn = std::sin(a);
  // A rotation about (1, 1, 1)/sqrt(3) in 3-D, about z in 2-D.
  Eigen::Matrix3d R = dimension == 3 ? Eigen::AngleAxisd(a, Eigen::Vector3d(1, 1, 1).normalized()).toRotationMatrix()
                                     : (Eigen::Matrix3d() << c, -sn, 0, sn, c, 0, 0, 0, 1).finished();
  const Vec3 shift{0.3, -0.2, dimension == 3 ? 0.1 : 0.0};
  auto& P = s.particles;
  for (std::size_t i = 0; i < P.size(); ++i) {
    const Eigen::Vector3d X(P.X[i].x, P.X[i].y, P.X[i].z);
    const Eigen::Vector3d y = R * X;
    P.u[i] = Vec3{y.x(), y.y(), y.z()} - P.X[i] + shift;
  }
  for (int pass = 0; pass < 3; ++pass) {  // the history stays at rest: the trial is the committed state
    s.time = 1e-6 * (pass + 1);
    s.dt = 1e-6;
    compute_forces(s, false);
    commit_history(s);
  }
  double fmax = 0;
  for (const auto& f : P.f) fmax = std::max(fmax, norm(f));
  return fmax / (mat.youngs_modulus * 1e-3 / b.spacing);
}

}  // namespace horizon::verification
