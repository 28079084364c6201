// The correspondence model (material/models/correspondence.hpp; docs/models/
// correspondence.md) through the whole chain: deck or block, build_system, the general
// force pass, the solvers. Each figure is checked against an analytic value with its
// tolerance stated; docs/verification.md, "The correspondence model" lists them.
#include <gtest/gtest.h>
#include <omp.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "horizon/loading/loads.hpp"
#include "horizon/material/classical/stress_laws.hpp"
#include "horizon/material/models/correspondence.hpp"
#include "horizon/kernels/affine.hpp"
#include "horizon/solver/explicit.hpp"
#include "horizon/solver/forces.hpp"
#include "horizon/solver/static_driver.hpp"
#include "../unit/test_helpers.hpp"
#include "verification_support.hpp"

namespace horizon::verification {
namespace {

using Mat3 = Eigen::Matrix3d;
using test::BlockSpec;

constexpr double kE = 70e9, kNu = 0.3, kRho = 2700;

MaterialConfig corr_material(const std::string& law, double stabilization, InfluenceKind omega = InfluenceKind::constant) {
  MaterialConfig m = test::make_material("correspondence", kE, kNu, kRho, omega);
  m.choices["stress_law"] = law;
  m.parameters["stabilization"] = stabilization;
  if (law == "j2") {
    m.parameters["yield_stress"] = 200e6;
    m.parameters["hardening_modulus"] = 1e9;
  }
  fill_model_defaults(m);
  return m;
}

correspondence::LawSettings law_of(const MaterialConfig& m, int d, PlaneMode plane) {
  correspondence::LawSettings s;
  const std::string& law = m.choices.at("stress_law");
  s.law = law == "neo_hookean" ? correspondence::StressLaw::neo_hookean
          : law == "j2"        ? correspondence::StressLaw::j2
                               : correspondence::StressLaw::linear_elastic;
  s.elastic = classical::elastic_from_bulk_shear(m.bulk_modulus, m.shear_modulus);
  s.j2 = {m.parameters.at("yield_stress"), m.parameters.at("hardening_modulus")};
  s.dimension = d;
  s.plane = plane;
  return s;
}

// The force state of bond k of particle i at the last pass, from whichever form of the
// general pass ran: the vector form's T_k, or the affine form's record of i
// (solver/forces_affine.cpp: T = omega (M_i xi + g_i Y)).
Vec3 force_state(const System& s, std::size_t i, uint64_t k) {
  const auto& M = s.model;
  const auto& B = s.bonds;
  if (M.force_state.size() == B.size()) return M.force_state[k];
  if (!B.intact[k]) return {};
  const auto& P = s.particles;
  const std::size_t j = B.nbr[k];
  const Vec3 xi = P.X[j] - P.X[i], Y = (P.X[j] + P.u[j]) - (P.X[i] + P.u[i]);
  const double xv[3] = {xi.x, xi.y, xi.z}, yv[3] = {Y.x, Y.y, Y.z};
  double t[3];
  kernels::affine_force_state(M.affine_record.data() + kernels::kAffineRecord * i, B.weight[k], xv,
                                     yv, t);
  return {t[0], t[1], t[2]};
}

// sum_k T_k (x) xi_k V_k over particle i's bonds: P_i exactly (seed 003 digest sec. 13
// check 5; the stabilisation adds nothing to it).
Mat3 collapsed_stress(const System& s, std::size_t i) {
  Mat3 S = Mat3::Zero();
  const auto& B = s.bonds;
  for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
    if (!B.intact[k]) continue;
    const Vec3 T = force_state(s, i, k);
    const Vec3 xi = s.particles.X[B.nbr[k]] - s.particles.X[i];
    S += B.volume[k] * correspondence::to_eigen(T) * correspondence::to_eigen(xi).transpose();
  }
  return S;
}

// Lattice distance of every particle to the nearest face of the block, in spacings.
std::vector<double> depths(const System& s, const BlockSpec& b) {
  const int dim = b.dimension;
  const double h = b.spacing, last[3] = {b.n[0] - 1.0, b.n[1] - 1.0, b.n[2] - 1.0};
  std::vector<double> out(s.particles.size(), 1e300);
  for (std::size_t i = 0; i < out.size(); ++i)
    for (int k = 0; k < dim; ++k) {
      const double index = s.particles.X[i][k] / h;
      out[i] = std::min({out[i], index, last[k] - index});
    }
  return out;
}

// --- patch test -----------------------------------------------------------------------

// A homogeneous deformation (stretch + shear + rotation, F below) of a block with partial
// volumes: at every particle at least one horizon from the faces the model's stress
// (the collapsed stress of its force states) is the classical law's P(F) to 1e-10
// (relative), its energy density the law's W, and two horizons in the force density
// vanishes (1e-10 of |P|/h). 3-D and 2-D plane strain and plane stress; the three laws
// (j2 beyond yield: the stretch is 0.6 %, yield at 0.29 %).
TEST(Correspondence, PatchTestReproducesClassicalStress) {
  test::SingleThread one;
  struct Case {
    int d;
    PlaneMode plane;
  };
  for (const Case c : {Case{3, PlaneMode::none}, Case{2, PlaneMode::strain}, Case{2, PlaneMode::stress}}) {
    BlockSpec b;
    b.dimension = c.d;
    b.plane = c.plane;
    if (c.d == 3) {
      b.n = {13, 13, 13};
    } else {
      b.n = {15, 15, 1};
    }
    b.partial_volume = true;
    Mat3 Fa;
    if (c.d == 3)
      Fa = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix() *
           (Mat3() << 1.006, 0.002, 0.0, 0.0, 0.998, 0.001, 0.0015, 0.0, 1.001).finished();
    else
      Fa = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix() *
           (Mat3() << 1.006, 0.002, 0.0, 0.001, 0.998, 0.0, 0.0, 0.0, 1.0).finished();
    for (const char* law : {"linear_elastic", "neo_hookean", "j2"}) {
      const MaterialConfig mat = corr_material(law, 0.1);
      System s = test::make_block(b, mat);
      for (std::size_t i = 0; i < s.particles.size(); ++i) {
        const Eigen::Vector3d X = correspondence::to_eigen(s.particles.X[i]);
        s.particles.u[i] = correspondence::to_vec3(Fa * X - X + Eigen::Vector3d(1e-4, -2e-4, 0));
      }
      compute_forces(s, true);
      correspondence::History h0, h1;
      double work = 0;
      const classical::LawResult exact = correspondence::evaluate_law(law_of(mat, c.d, c.plane), Fa, h0, h1, work);
      if (std::string(law) == "j2") {
        EXPECT_GT(h1.plastic.alpha, 0) << "beyond yield";
      }
      const double delta = b.horizon_factor;
      const std::vector<double> depth = depths(s, b);
      int checked = 0;
      for (std::size_t i = 0; i < s.particles.size(); ++i) {
        if (depth[i] < delta) continue;
        const Mat3 P = collapsed_stress(s, i);
        EXPECT_LT((P - exact.P).topLeftCorner(c.d, c.d).norm(), 1e-10 * exact.P.norm()) << law << " " << i;
        EXPECT_NEAR(s.particles.energy[i], exact.W, 1e-10 * exact.W) << law << " " << i;
        if (depth[i] >= 2 * delta) {
          EXPECT_LT(norm(s.particles.f[i]), 1e-10 * exact.P.norm() / b.spacing) << law << " " << i;
        }
        ++checked;
      }
      EXPECT_GT(checked, 0);
    }
  }
}

// --- wave in a bar: zero-energy modes -----------------------------------------------

// RMS over the particles of |u_i - (the omega V-weighted mean of u over i's family)|:
// what a smooth field barely has and a zero-energy (hourglass) pattern has at full size.
double roughness(const System& s) {
  const auto& B = s.bonds;
  const auto& P = s.particles;
  double sum = 0;
  for (std::size_t i = 0; i < P.size(); ++i) {
    Vec3 mean;
    double w = 0;
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
      if (!B.intact[k]) continue;
      const double wk = B.weight[k] * B.volume[k];
      mean += wk * P.u[B.nbr[k]];
      w += wk;
    }
    sum += norm2(P.u[i] - mean / w);
  }
  return std::sqrt(sum / static_cast<double>(P.size()));
}

struct WaveRun {
  std::vector<double> roughness;  // at the end of each transit [m]
  int steps = 0;
};

// A 3-D bar of 36 x 5 x 5 particles (h = 1 mm, horizon 2h, partial volumes), linear
// elastic correspondence, free ends, at rest but for two smooth velocity pulses (Gaussian,
// 1 m/s peak, width 0.08 L) at its quarter points moving towards each other (no net
// momentum). Explicit, 0.8 of the stable step, for `transits` times L/c, c = sqrt(E/rho).
WaveRun wave_in_bar(double stabilization, int transits) {
  BlockSpec b;
  b.n = {36, 5, 5};
  b.horizon_factor = 2;
  b.partial_volume = true;
  System s = test::make_block(b, corr_material("linear_elastic", stabilization));
  const double L = (b.n[0] - 1) * b.spacing, v0 = 1.0;
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    const double a = (s.particles.X[i].x - 0.25 * L) / (0.08 * L), c = (s.particles.X[i].x - 0.75 * L) / (0.08 * L);
    s.particles.v[i] = {v0 * (std::exp(-a * a) - std::exp(-c * c)), 0, 0};
  }
  Loads loads;
  ExplicitSolver solver(s, loads, 0.8 * stable_time_step(s), 0.0);
  solver.initialize();
  WaveRun r;
  const double transit = L / std::sqrt(kE / kRho);
  for (int t = 1; t <= transits; ++t) {
    while (solver.time() < t * transit) {
      solver.step(false);
      ++r.steps;
    }
    r.roughness.push_back(roughness(s));
  }
  return r;
}

// Zero-energy modes in a wave run (default stabilisation G_s = 1 against none); r(t) the
// roughness after each transit, m5(r) the mean over the first or the last five transits.
// Measured (deterministic, any thread count):
//   stabilised:   r = 1.2e-8 m after one transit; m5 last / m5 first = 1.36 (the pulses
//                 disperse: the short waves they shed add roughness), max / first = 1.92;
//   unstabilised: r = 3.7e-8 m after one transit, 7.3e-8 m after twenty, 3.6 times the
//                 stabilised run; its excess over the stabilised run grows by 1.33 from the
//                 first five transits to the last five.
// Asserted: stabilised m5 last / m5 first < 1.6 and max / first < 2.5 (bounded);
// unstabilised r(20) > 2.5 r_stabilised(20), and the excess grows (ratio > 1.2). The
// growth is slow, not explosive: with an elastic law the discrete energy
// sum_i Omega(F_i) V_i is positive semi-definite, so the near-zero-energy patterns are
// neutrally stable; the step-free smooth pulses excite them at the free ends and surfaces
// and nothing takes the energy back.
TEST(Correspondence, WaveInBarRoughnessBoundedOnlyWithStabilisation) {
  test::SingleThread one;
  const int transits = 20;
  const WaveRun on = wave_in_bar(1.0, transits), off = wave_in_bar(0.0, transits);
  auto mean5 = [](const std::vector<double>& v, std::size_t from) {
    double m = 0;
    for (std::size_t k = from; k < from + 5; ++k) m += v[k];
    return m / 5;
  };
  std::vector<double> excess(transits);
  for (int t = 0; t < transits; ++t) excess[t] = off.roughness[t] - on.roughness[t];
  const double on_mean_growth = mean5(on.roughness, transits - 5) / mean5(on.roughness, 0);
  const double on_max_growth = *std::max_element(on.roughness.begin(), on.roughness.end()) / on.roughness[0];
  const double off_over_on = off.roughness.back() / on.roughness.back();
  const double excess_growth = mean5(excess, transits - 5) / mean5(excess, 0);
  report("wave_roughness_stabilised", on_mean_growth,
         fmt::format("wave in bar, 20 transits, G_s = 1: roughness {:.2e} m after one transit, last/first five "
                     "{:.2f}, max/first {:.2f} ({} steps)",
                     on.roughness[0], on_mean_growth, on_max_growth, on.steps));
  report("wave_roughness_unstabilised", off_over_on,
         fmt::format("wave in bar, 20 transits, G_s = 0: roughness {:.2e} m after one transit, {:.2e} after 20 "
                     "({:.2f} times the stabilised run); its excess grows {:.2f} times ({} steps)",
                     off.roughness[0], off.roughness.back(), off_over_on, excess_growth, off.steps));
  EXPECT_LT(on_mean_growth, 1.6);
  EXPECT_LT(on_max_growth, 2.5);
  EXPECT_GT(off_over_on, 2.5);
  EXPECT_GT(excess_growth, 1.2);
}

// --- the zero-energy witness through the model ------------------------------------

// Seed 000 digest sec. 10 item 1 (and the idea of sec. 13.3) on a 3-D block with partial
// volumes: the checkerboard u = a (-1)^(i+j+k) e leaves F = I at every particle whose
// family is whole (its odd-parity bonds come in +-xi pairs) while it strains those bonds
// by 2a/|xi|. Without stabilisation: W_i = 0 one horizon in and f_i = 0 two horizons in
// (1e-10 of the scale E 2a/h, resp. E 2a/h^2). With G_s = 0.1: W_i = (G/2) 4 a^2
// sum_odd omega V_j and f_i = -4 G a (-1)^(i+j+k) e sum_odd omega V_j to 1e-9.
TEST(Correspondence, ZeroEnergyWitness) {
  test::SingleThread one;
  BlockSpec b;
  b.n = {15, 15, 15};
  b.partial_volume = true;
  const double a = 1e-7;
  const Vec3 e{0.6, -0.8, 0.0};
  for (const double gs : {0.0, 0.1}) {
    const MaterialConfig mat = corr_material("linear_elastic", gs);
    System s = test::make_block(b, mat);
    std::vector<double> sign(s.particles.size());
    for (std::size_t i = 0; i < s.particles.size(); ++i) {
      const Vec3& X = s.particles.X[i];
      const long p = std::lround(X.x / b.spacing) + std::lround(X.y / b.spacing) + std::lround(X.z / b.spacing);
      sign[i] = p % 2 == 0 ? 1.0 : -1.0;
      s.particles.u[i] = (a * sign[i]) * e;
    }
    compute_forces(s, true);
    const Dimensioning dims{3, PlaneMode::none, 1, 1, s.horizon};
    const double c = equivalent_micromodulus(mat.bulk_modulus, mat.shear_modulus, InfluenceKind::constant, dims);
    const double G = gs * c / s.horizon, scale = kE * 2 * a / b.spacing;
    const std::vector<double> depth = depths(s, b);
    int checked = 0;
    for (std::size_t i = 0; i < s.particles.size(); ++i) {
      if (depth[i] < b.horizon_factor) continue;
      double odd = 0, strain = 0;
      const auto& B = s.bonds;
      for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
        const std::size_t j = B.nbr[k];
        if (sign[j] != sign[i]) odd += B.weight[k] * B.volume[k];
        strain = std::max(strain, std::abs(norm(s.particles.position(j) - s.particles.position(i)) - B.length[k]) / B.length[k]);
      }
      EXPECT_GT(strain, 0.5 * a / b.spacing) << "the bonds are strained";
      if (gs == 0) {
        EXPECT_LT(std::abs(s.particles.energy[i]), 1e-10 * scale * a / b.spacing) << i;
        if (depth[i] >= 2 * b.horizon_factor) {
          EXPECT_LT(norm(s.particles.f[i]), 1e-10 * scale / b.spacing) << i;
          ++checked;
        }
      } else {
        EXPECT_NEAR(s.particles.energy[i] / (0.5 * G * 4 * a * a * odd), 1.0, 1e-9) << i;
        if (depth[i] >= 2 * b.horizon_factor) {
          const Vec3 expected = (-4 * G * a * sign[i] * odd) * e;
          EXPECT_LT(norm(s.particles.f[i] - expected), 1e-9 * norm(expected)) << i;
          ++checked;
        }
      }
    }
    EXPECT_GT(checked, 0);
  }
}

// --- rigid motion and momentum --------------------------------------------------------

// A free 3-D block (9^3, partial volumes, G_s = 0.5): a rigid rotation by ~1 rad plus a
// translation gives no force (1e-9 of the force density of a 0.1 % strain) for the
// neo-Hookean and J2 laws, and a translation none for the small-strain law; a random
// deformation keeps sum_i V_i f_i = 0 (1e-12 of sum |V f|) and, for the objective laws,
// sum_i V_i y_i x f_i = 0 (1e-12 of the same times the block size).
TEST(Correspondence, RigidMotionAndMomentum) {
  test::SingleThread one;
  BlockSpec b;
  b.n = {9, 9, 9};
  b.partial_volume = true;
  const Mat3 Q = Eigen::AngleAxisd(1.1, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  const double scale = kE * 1e-3 / b.spacing;
  for (const char* law : {"linear_elastic", "neo_hookean", "j2"}) {
    const bool objective = std::string(law) != "linear_elastic";
    System s = test::make_block(b, corr_material(law, 0.5));
    for (std::size_t i = 0; i < s.particles.size(); ++i) {
      const Eigen::Vector3d X = correspondence::to_eigen(s.particles.X[i]);
      const Eigen::Vector3d y = (objective ? Q * X : X) + Eigen::Vector3d(0.3, -0.1, 0.2);
      s.particles.u[i] = correspondence::to_vec3(y - X);
    }
    compute_forces(s, false);
    double fmax = 0;
    for (const Vec3& f : s.particles.f) fmax = std::max(fmax, norm(f));
    EXPECT_LT(fmax, 1e-9 * scale) << law;

    test::Rng rng(17);
    for (std::size_t i = 0; i < s.particles.size(); ++i)
      s.particles.u[i] = 0.002 * s.particles.X[i] +
                         Vec3{rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)} * (2e-3 * b.spacing);
    compute_forces(s, false);
    Vec3 lin, ang;
    double total = 0;
    for (std::size_t i = 0; i < s.particles.size(); ++i) {
      const double V = s.particles.volume[i];
      lin += V * s.particles.f[i];
      ang += V * cross(s.particles.position(i), s.particles.f[i]);
      total += V * norm(s.particles.f[i]);
    }
    EXPECT_LT(norm(lin), 1e-12 * total) << law;
    if (objective) {
      EXPECT_LT(norm(ang), 1e-12 * total * 9 * b.spacing) << law;
    }
  }
}

// --- static solves: neo-Hookean and J2 uniaxial stress --------------------------------

}  // namespace

// A 2-D plane-stress strip, 27 x 7 particles (h = 1 mm, horizon 3h, partial volumes),
// its first and last six columns (two horizons) held in x at u = eps_end * X (ramped over
// the load steps), its middle row held in y, free laterally; static Newton with the
// finite-difference tangent. The grips are two horizons deep so that no free particle
// has a neighbour whose family the end of the strip truncates (T_ji uses K_j): the
// discrete correspondence solution is then exactly the homogeneous uniaxial-stress state
// (the lateral faces carry P22 = 0), and the end reaction over the section is the
// nominal stress P11 of the law. (With grips one horizon deep the truncated shape tensors
// of the end particles pull on the first free columns and the strip stretches unevenly.)
std::string strip_deck(const std::string& material, double end_strain, int load_steps) {
  return fmt::format(R"(dimension: 2
plane: stress
thickness: 1.0e-3
spacing: 1.0e-3
horizon_factor: 3
partial_volume: true
lattice_origin: [0, 0]
materials:
  m: {{{}}}
bodies:
  - {{name: strip, material: m, shape: {{box: {{min: [-0.0005, -0.0035], max: [0.0265, 0.0035]}}}}}}
regions:
  left:   {{box: {{min: [-0.0005, -0.0035], max: [0.0055, 0.0035]}}}}
  right:  {{box: {{min: [0.0205, -0.0035], max: [0.0265, 0.0035]}}}}
  middle: {{box: {{min: [-0.0005, -0.0001], max: [0.0265, 0.0001]}}}}
loads:
  - {{region: left,   displacement: ["{}*x", null]}}
  - {{region: right,  displacement: ["{}*x", null]}}
  - {{region: middle, displacement: [null, 0]}}
solver: {{type: static, method: newton, linear_solver: cholesky, tolerance: 1.0e-9, load_steps: {}}}
)",
                     material, end_strain, end_strain, load_steps);
}

namespace {

struct StripResult {
  double nominal = 0;  // right reaction / reference section [Pa]
  double lateral = 0;  // lateral stretch of the top row
  int64_t iterations = 0, steps = 0;
  bool ok = false;
};

StripResult run_strip(const std::string& material, double end_strain, int load_steps) {
  const Config config = parse_deck(strip_deck(material, end_strain, load_steps), "strip.yaml");
  System system = build_system(config);
  Loads loads(config, system);
  StaticSolver solver(system, loads, config.solver);
  loads.apply_initial_conditions(config, system);
  solver.initialize();
  StripResult r;
  r.ok = true;
  while (!solver.done())
    if (!solver.advance()) {
      ADD_FAILURE() << solver.failure();
      r.ok = false;
      return r;
    }
  r.iterations = solver.total_iterations();
  r.steps = solver.steps();
  for (const auto& L : loads.loads())
    if (L.name.rfind("right", 0) == 0) r.nominal = L.reaction.x / (7e-3 * config.thickness);
  // Lateral stretch from the top and bottom rows (y = +-3 mm) at mid-length.
  double top = 0, bottom = 0;
  for (std::size_t i = 0; i < system.particles.size(); ++i) {
    const Vec3& X = system.particles.X[i];
    if (std::abs(X.x - 0.013) > 1e-6) continue;
    if (std::abs(X.y - 0.003) < 1e-6) top = system.particles.position(i).y;
    if (std::abs(X.y + 0.003) < 1e-6) bottom = system.particles.position(i).y;
  }
  r.lateral = (top - bottom) / 0.006;
  return r;
}

// Neo-Hookean uniaxial stress at stretch lambda: F = diag(lambda, b, b) with P22 = 0,
// P22 = mu J^(-2/3) (b - I1/(3b)) + kappa (J-1) J / b (b by bisection), and
// P11 = mu J^(-2/3) (lambda - I1/(3 lambda)) + kappa (J-1) J / lambda.
double neo_hookean_uniaxial(double mu, double kappa, double lambda, double& b) {
  auto P = [&](double bb, double s) {
    const double J = lambda * bb * bb, I1 = lambda * lambda + 2 * bb * bb;
    return mu * std::pow(J, -2.0 / 3) * (s - I1 / (3 * s)) + kappa * (J - 1) * J / s;
  };
  double lo = 0.3, hi = 1.0;
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    (P(mid, mid) > 0 ? hi : lo) = mid;
  }
  b = 0.5 * (lo + hi);
  return P(b, lambda);
}

// Stretch to 50 % (lambda = 1.5) in 10 load steps: the nominal stress within 1 % of the
// analytic one (measured: to 1e-6), the lateral stretch within 0.1 %, and Newton with
// the finite-difference tangent converges in a few iterations per step.
TEST(Correspondence, NeoHookeanUniaxialStretchFiftyPercent) {
  test::SingleThread one;
  const double E = 1e7, nu = 0.45;
  const StripResult r =
      run_strip(fmt::format("model: correspondence, stress_law: neo_hookean, stabilization: 0.1, density: 1000, "
                            "youngs_modulus: {}, poissons_ratio: {}",
                            E, nu),
                0.5, 10);
  ASSERT_TRUE(r.ok);
  double b = 0;
  const double P11 = neo_hookean_uniaxial(E / (2 * (1 + nu)), E / (3 * (1 - 2 * nu)), 1.5, b);
  report("neo_hookean_uniaxial_50", r.nominal / P11,
         fmt::format("neo-Hookean strip stretched 50 %: nominal stress {:.6e} Pa, analytic {:.6e} ({:+.2e}); "
                     "lateral stretch {:.6f}, analytic {:.6f}; {} Newton iterations in {} steps",
                     r.nominal, P11, r.nominal / P11 - 1, r.lateral, b, r.iterations, r.steps));
  EXPECT_NEAR(r.nominal / P11, 1.0, 0.01);
  EXPECT_NEAR(r.lateral / b, 1.0, 1e-3);
  EXPECT_LE(r.iterations, 6 * r.steps) << "Newton with the finite-difference tangent";
}

// J2 with linear hardening in uniaxial stress, stretched 2 % in 4 load steps (yield at
// 0.29 %). In the unrotated Hencky frame the closed form is alpha = (E e - sigma_y)/(E + H)
// with e = ln(lambda), tau11 = sigma_y + H alpha, and P11 = tau11 / lambda; within 1 %.
TEST(Correspondence, J2UniaxialStressPlasticHardening) {
  test::SingleThread one;
  const double E = 70e9, sy = 200e6, H = 1e9, strain = 0.02;
  const StripResult r = run_strip(fmt::format("model: correspondence, stress_law: j2, stabilization: 0.1, density: "
                                              "2700, youngs_modulus: {}, poissons_ratio: 0.3, yield_stress: {}, "
                                              "hardening_modulus: {}",
                                              E, sy, H),
                                  strain, 4);
  ASSERT_TRUE(r.ok);
  const double lambda = 1 + strain, e = std::log(lambda);
  const double alpha = (E * e - sy) / (E + H), P11 = (sy + H * alpha) / lambda;
  report("j2_uniaxial", r.nominal / P11,
         fmt::format("J2 strip stretched 2 %: nominal stress {:.6e} Pa, analytic {:.6e} ({:+.2e}); alpha {:.4e}; "
                     "{} Newton iterations in {} steps",
                     r.nominal, P11, r.nominal / P11 - 1, alpha, r.iterations, r.steps));
  EXPECT_NEAR(r.nominal / P11, 1.0, 0.01);
}

// --- plate with a hole -------------------------------------------------------------

// examples/plate_with_hole.yaml at a coarser spacing, with the linear elastic
// correspondence model (default stabilisation G_s = 1): a plane-stress plate 91 x 91
// spacings (h = R/4.5, R = 2.5 mm; d/W = 5 mm / 50.6 mm = 0.099 on the lattice)
// under 10 MPa, static Newton (finite-difference tangent, Cholesky). E eps_yy / sigma is
// read as tests/verification/test_static_solvers.cpp does, from the bonds (x, +-h) on the
// ligament at x = R + h/2, 3h/2, 5h/2; K_t from them as below; reference 3.03 (Howland
// 1930; Peterson's chart 4.1), within 5 %. (G_s = 0.1 leaves an hourglass zig-zag along
// the hole: 3.28, 2.08, 1.38 at R = 5.5 h; G_s = 1 follows Kirsch.)
TEST(Correspondence, PlateWithHoleStressConcentration) {
  const double R = 0.0025, h = R / 4.5, sigma = 1e7, E = 70e9;
  const std::string deck = fmt::format(R"(dimension: 2
plane: stress
thickness: 1.0e-3
spacing: {h}
horizon_factor: 3
partial_volume: true
lattice_origin: [0, 0]
materials:
  aluminium: {{model: correspondence, stress_law: linear_elastic, density: 2700, youngs_modulus: {E}, poissons_ratio: 0.33}}
bodies:
  - name: plate
    material: aluminium
    shape:
      subtract:
        - {{box: {{min: [-0.0251, -0.0251], max: [0.0251, 0.0251]}}}}
        - {{disk: {{center: [0, 0], radius: {R}}}}}
regions:
  top:    {{box: {{min: [-0.0251, {ytop}], max: [0.0251, 0.0251]}}}}
  bottom: {{box: {{min: [-0.0251, -0.0251], max: [0.0251, {ybot}]}}}}
  x_mirror: {{box: {{min: [-0.00005, -0.0251], max: [0.00005, 0.0251]}}}}
  y_mirror: {{box: {{min: [-0.0251, -0.00005], max: [0.0251, 0.00005]}}}}
loads:
  - {{region: top,      traction: [0, {sigma}]}}
  - {{region: bottom,   traction: [0, -{sigma}]}}
  - {{region: x_mirror, displacement: [0, null]}}
  - {{region: y_mirror, displacement: [null, 0]}}
solver: {{type: static, method: newton, linear_solver: cholesky, tolerance: 1.0e-6}}
)",
                                       fmt::arg("h", h), fmt::arg("E", E), fmt::arg("R", R),
                                       fmt::arg("ytop", 45 * h - 1.5 * h), fmt::arg("ybot", -45 * h + 1.5 * h),
                                       fmt::arg("sigma", sigma));
  const Config config = parse_deck(deck, "plate_with_hole_correspondence.yaml");
  System s = build_system(config);
  Loads loads(config, s);
  StaticSolver solver(s, loads, config.solver);
  loads.apply_initial_conditions(config, s);
  solver.initialize();
  while (!solver.done()) ASSERT_TRUE(solver.advance()) << solver.failure();
  auto find = [&](double x, double y) {
    for (std::size_t i = 0; i < s.particles.size(); ++i)
      if (std::abs(s.particles.X[i].x - x) < 1e-3 * h && std::abs(s.particles.X[i].y - y) < 1e-3 * h) return i;
    ADD_FAILURE() << "no particle at " << x << ", " << y;
    return std::size_t{0};
  };
  double k[3] = {0, 0, 0};
  for (const double side : {-1.0, 1.0})
    for (int c = 0; c < 3; ++c) {
      const double x = side * (R + (c + 0.5) * h);
      const double eps = (s.particles.u[find(x, h)].y - s.particles.u[find(x, -h)].y) / (2 * h);
      k[c] += 0.5 * E * eps / sigma;
    }
  // K_t = 3a, a the least-squares scale of the classical ligament profile of a hole in an
  // infinite plate, sigma_yy/sigma = (2 + (R/r)^2 + 3 (R/r)^4)/2 (Kirsch 1898), through
  // the three points; a carries the finite-width factor (3.03/3 at d/W = 0.1).
  double num = 0, den = 0;
  for (int c = 0; c < 3; ++c) {
    const double q = R / (R + (c + 0.5) * h), f = 0.5 * (2 + q * q + 3 * q * q * q * q);
    num += k[c] * f;
    den += f * f;
  }
  const double kt = 3 * num / den;
  // The three-point extrapolation of test_static_solvers.cpp, for comparison (at R = 4.5 h it
  // is biased low: on the exact Kirsch field it gives `bias` times 3).
  auto extrapolate = [](const double* v) { return v[0] - 0.5 * (v[1] - v[0]) + 0.375 * (v[0] - 2 * v[1] + v[2]); };
  double kirsch[3];
  for (int c = 0; c < 3; ++c) {
    const double q = R / (R + (c + 0.5) * h);
    kirsch[c] = 0.5 * (2 + q * q + 3 * q * q * q * q);
  }
  const double extrapolated = extrapolate(k), bias = extrapolate(kirsch) / 3;
  const double reference = 3.03;
  report("correspondence_plate_hole_kt", kt,
         fmt::format("correspondence plate with hole ({} particles, R = 4.5 h, G_s = 1): Kt = {:.3f} ({:+.2f} % from "
                     "{}) by the Kirsch-profile fit; E eps_yy / sigma at R + h/2, 3h/2, 5h/2: {:.3f}, {:.3f}, {:.3f} "
                     "(Kirsch: {:.3f}, {:.3f}, {:.3f}); three-point extrapolation {:.3f} (its bias on the Kirsch field "
                     "{:+.1f} %); {} Newton iterations",
                     s.particles.size(), kt, 100 * (kt / reference - 1), reference, k[0], k[1], k[2], kirsch[0],
                     kirsch[1], kirsch[2], extrapolated, 100 * (bias - 1), solver.total_iterations()));
  EXPECT_NEAR(kt / reference, 1.0, 0.05);
}

// --- energy ledger -----------------------------------------------------------------

// examples/elastic_impact.yaml with both bodies correspondence (h = 1 mm, horizon 3h): a
// 10 x 6 x 6 mm striker at `speed` against a 20 x 6 x 6 mm bar of the same material,
// bonded where they touch; explicit, safety factor 0.5, the ledger at every step.
nlohmann::json impact(const std::string& law_keys, double speed, const std::string& name) {
  const std::string deck = fmt::format(R"(dimension: 3
spacing: 1.0e-3
horizon: 3.0e-3
materials:
  metal: {{model: correspondence, {}, density: 2700, youngs_modulus: 70.0e9, poissons_ratio: 0.3}}
bodies:
  - {{name: striker, material: metal, shape: {{box: {{min: [0, 0, 0], max: [0.01, 0.006, 0.006]}}}}}}
  - {{name: target, material: metal, shape: {{box: {{min: [0.01, 0, 0], max: [0.03, 0.006, 0.006]}}}}}}
regions:
  striker: {{box: {{min: [0, 0, 0], max: [0.01, 0.006, 0.006]}}}}
initial_conditions:
  - {{region: striker, velocity: [{}, 0, 0]}}
solver: {{type: explicit, end_time: 3.0e-5, safety_factor: 0.5}}
output: {{directory: out/correspondence_impact, frames: 1, history_every: 1}}
)",
                                       law_keys, speed);
  Config config = parse_deck(deck, name + ".yaml");
  RunOptions options;
  options.output_dir = output_dir(name).string();
  options.quiet = true;
  EXPECT_EQ(run_deck(config, options), 0);
  return read_json(std::filesystem::path(*options.output_dir) / "summary.json");
}

// Elastic (neo-Hookean, 10 m/s; default stabilisation): the largest |balance error| of the
// ledger over every step within 1 % of the energy brought in (the stabilisation energy is
// part of W_i).
// Elastic-plastic (J2, sigma_y = 200 MPa, 100 m/s: the impact stress rho c v/2 ~ 700 MPa
// yields the bar): the plastic work goes to the dissipated energy and the ledger still
// balances within 1 %.
TEST(Correspondence, ImpactEnergyLedger) {
  const nlohmann::json el = impact("stress_law: neo_hookean", 10.0, "correspondence_impact");
  ASSERT_EQ(el["status"], "completed");
  const auto& e = el["energy"];
  EXPECT_NEAR(e["initial"].get<double>(), 0.5 * 2700 * 0.01 * 0.006 * 0.006 * 100, 1e-9);
  EXPECT_GT(e["strain"].get<double>(), 0.05 * e["initial"].get<double>()) << "the impact happened";
  const double elastic_error = e["max_abs_balance_error"];
  const nlohmann::json pl =
      impact("stress_law: j2, yield_stress: 2.0e8, hardening_modulus: 1.0e9", 100.0, "correspondence_impact_j2");
  ASSERT_EQ(pl["status"], "completed");
  const auto& p = pl["energy"];
  const double plastic_error = p["max_abs_balance_error"];
  const double dissipated = p["dissipated"].get<double>() / p["initial"].get<double>();
  report("correspondence_impact_balance", elastic_error,
         fmt::format("correspondence impact: max |balance error| {:.2e} (neo-Hookean, 10 m/s, {} steps); {:.2e} "
                     "(J2, 100 m/s, plastic work {:.1f} % of the energy brought in)",
                     elastic_error, el["steps"].get<int>(), plastic_error, 100 * dissipated));
  EXPECT_LE(elastic_error, 1e-2);
  EXPECT_LE(plastic_error, 1e-2);
  EXPECT_GT(dissipated, 0.01) << "the bar yields";
}

// --- threads --------------------------------------------------------------------------

struct ThreadRun {
  std::vector<Vec3> u, v;
  std::vector<double> damage, dissipated_at;
};

// A 3-D J2 block (7^3, partial volumes) with a critical stretch, random initial
// velocities large enough to yield it and break bonds, 40 explicit steps: the
// displacements, velocities, damage and dissipated energies (plastic work and broken
// bonds) on 1 and 2 threads, bit for bit.
ThreadRun run_threads(int threads) {
  omp_set_num_threads(threads);
  BlockSpec b;
  b.n = {7, 7, 7};
  b.partial_volume = true;
  MaterialConfig mat = corr_material("j2", 0.1);
  mat.damage.enabled = true;
  mat.damage.critical_stretch = 2e-3;
  System s = test::make_block(b, mat);
  test::Rng rng(42);
  for (auto& v : s.particles.v) v = Vec3{rng.uniform(-20, 20), rng.uniform(-20, 20), rng.uniform(-20, 20)};
  Loads loads;
  ExplicitSolver solver(s, loads, 0.8 * stable_time_step(s), 0.0);
  solver.initialize();
  for (int step = 0; step < 40; ++step) solver.step(step % 10 == 0);
  EXPECT_GT(s.broken, 0u) << "bonds break";
  return {s.particles.u, s.particles.v, s.particles.damage, s.dissipated_at};
}

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

TEST(Correspondence, SameBitsOnOneAndTwoThreads) {
  const int saved = omp_get_max_threads();
  const ThreadRun one = run_threads(1), two = run_threads(2);
  omp_set_num_threads(saved);
  EXPECT_TRUE(same_bits(one.u, two.u));
  EXPECT_TRUE(same_bits(one.v, two.v));
  EXPECT_TRUE(same_bits(one.damage, two.damage));
  EXPECT_TRUE(same_bits(one.dissipated_at, two.dissipated_at));
}

// --- the stable step of a compressed state ------------------------------------------

struct CompressedRun {
  double dt_reference = 0, dt_current = 0;  // safety 1, before and after the compression [s]
  double max_speed = 0;                     // over the run [m/s]
  bool finite = true;
  int steps = 0;
};

// The face of the Taylor bar (docs/verification.md, "Taylor bar", "Time step"): plastic
// flow compresses the impact end to a stretch of 0.07 along the axis, and the reference
// tangent of the correspondence model grows as 1/lambda^2 along it (digest 000 sec. 10,
// pitfall 14), which the Silling-Askari bound of the reference state does not see. Here
// a J2 block (8^3, horizon 3 spacings, no stabilisation, as examples/taylor_bar.yaml) is
// given the isochoric compression F = diag(lambda^-1/2, lambda, lambda^-1/2), lambda =
// 0.1, at rest (the return maps it onto the yield surface at the first pass), and runs
// for 200 steps of half the reference bound: with the step fixed at the start, or with
// solver.adaptive_time_step (half the bound of the current state, recomputed every 5
// steps as the driver does; Model::spring_factors).
CompressedRun compressed_block(bool adaptive) {
  test::SingleThread one;
  BlockSpec b;
  b.n = {8, 8, 8};
  Config c = test::block_config(b, corr_material("j2", 0.0));
  c.solver.adaptive_time_step = adaptive;
  System s = build_system(c);
  CompressedRun r;
  r.dt_reference = stable_time_step(s);
  const double lambda = 0.1, a = 1 / std::sqrt(lambda);
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    const Vec3& X = s.particles.X[i];
    s.particles.u[i] = {(a - 1) * X.x, (lambda - 1) * X.y, (a - 1) * X.z};
  }
  r.dt_current = stable_time_step(s);
  Loads loads;
  ExplicitSolver solver(s, loads, 0.5 * r.dt_current, 0.0);
  solver.initialize();
  const double end = 200 * 0.5 * r.dt_reference;
  try {
    while (solver.time() < end) {
      if (adaptive && r.steps % 5 == 0) solver.set_dt(0.5 * stable_time_step(s));
      solver.step(true);
      ++r.steps;
      for (const Vec3& v : s.particles.v) r.max_speed = std::max(r.max_speed, std::sqrt(norm2(v)));
    }
  } catch (const NonFiniteState&) {
    r.finite = false;
  }
  return r;
}

// Measured: the current bound is 0.172 of the reference one (the mean of |F^-T n|^2 over a
// family is ~ (lambda^-2 + 2 lambda)/3 = 33 in the interior: 1/sqrt(33) = 0.174). With the
// step fixed at the start the block comes apart: 5.1e5 m/s within the 200 steps. With the
// adaptive step (1,129 steps) the largest speed is 293 m/s: the free faces of the
// flattened block (22 x 0.7 x 22 mm) flow plastically from the yield stress, and the
// lateral directions, stretched 3.2 times, are 10 times softer in the reference frame.
// (The ledger is no measure here: the compression imposed at rest is returned plastically
// at the first pass, work the ledger never saw.)
TEST(Correspondence, CompressedStateNeedsTheCurrentStableStep) {
  const CompressedRun fixed = compressed_block(false), adaptive = compressed_block(true);
  report("correspondence_compressed_dt_ratio", adaptive.dt_current / adaptive.dt_reference,
         fmt::format("compressed J2 block (lambda 0.1): current/reference stable step {:.3f} (fixed: {:.3f}); fixed "
                     "step: max speed {:.3g} m/s, finite {}, {} steps; adaptive: max speed {:.3g} m/s, {} steps",
                     adaptive.dt_current / adaptive.dt_reference, fixed.dt_current / fixed.dt_reference,
                     fixed.max_speed, fixed.finite, fixed.steps, adaptive.max_speed, adaptive.steps));
  EXPECT_DOUBLE_EQ(fixed.dt_current, fixed.dt_reference) << "without adaptive_time_step the step stays the reference one";
  EXPECT_DOUBLE_EQ(adaptive.dt_reference, fixed.dt_reference) << "the reference state has factor 1";
  EXPECT_LT(adaptive.dt_current, 0.3 * adaptive.dt_reference);
  EXPECT_GT(adaptive.dt_current, 0.1 * adaptive.dt_reference);
  EXPECT_TRUE(!fixed.finite || fixed.max_speed > 1e4) << "the fixed step comes apart";
  EXPECT_TRUE(adaptive.finite);
  EXPECT_LT(adaptive.max_speed, 1e3) << "the step from the current state holds";
}

// --- singular shape tensor through the model -----------------------------------------

// A particle left with two intact bonds (both directions broken by hand, as damage would)
// has a singular shape tensor: it carries no stress (all its T = 0, seed 000 digest sec.
// 6.1), the field singular_shape_tensor marks it, and every force stays finite.
TEST(Correspondence, SingularShapeTensorCarriesNoStress) {
  test::SingleThread one;
  BlockSpec b;
  b.n = {7, 7, 7};
  System s = test::make_block(b, corr_material("neo_hookean", 1.0));
  const std::size_t c = 3 * 49 + 3 * 7 + 3;  // the centre
  auto& B = s.bonds;
  int kept = 0;
  for (uint64_t k = B.begin(c); k < B.end(c); ++k) {
    if (kept < 2 && B.length[k] < 1.01 * b.spacing) {
      ++kept;
      continue;
    }
    B.intact[k] = 0;
    const std::size_t j = B.nbr[k];
    for (uint64_t q = B.begin(j); q < B.end(j); ++q)
      if (B.nbr[q] == c) B.intact[q] = 0;
  }
  refresh_damage(s);
  for (std::size_t i = 0; i < s.particles.size(); ++i) s.particles.u[i] = 0.01 * s.particles.X[i];
  s.particles.u[c] += Vec3{1e-5, -2e-5, 3e-5};
  compute_forces(s, true);
  for (uint64_t k = B.begin(c); k < B.end(c); ++k) EXPECT_EQ(norm(force_state(s, c, k)), 0.0);
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    EXPECT_TRUE(std::isfinite(s.particles.f[i].x) && std::isfinite(s.particles.f[i].y) &&
                std::isfinite(s.particles.f[i].z) && std::isfinite(s.particles.energy[i]))
        << i;
  }
  std::vector<ModelField> fields;
  s.models[0].fields(s, fields);
  bool found = false;
  for (const auto& f : fields)
    if (f.name == "singular_shape_tensor") {
      found = true;
      EXPECT_EQ(f.values[c], 1.0);
      EXPECT_EQ(f.values[0], 0.0);
    }
  EXPECT_TRUE(found);
}

}  // namespace
}  // namespace horizon::verification
