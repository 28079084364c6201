// Kernels of O'Grady's bond-pair model (material/models/bond_pair.hpp; seed 001):
// - the pair gradient against finite differences of 1 + cos theta (eq. 4.1);
// - the elastic-perfectly-plastic return mapping (eq. 4.8, digest sec. 3.5), signed and
//   of the kink vector (flat shells);
// - the moment-curvature law of a beam of bond pairs under uniform curvature,
//   M = sum_j omega alpha V |xi| sin(kink_e), against the classical rectangle
//   M = M_y (3/2 - (kappa_y/kappa)^2/2) and the limits M_inf/M_y = 3/2 (omega = 1) and
//   4/3 (omega = |xi|) (digest sec. 3.5);
// - the analytic tangent of the model (Model::stiffness: pairs, signed plastic pairs,
//   isotropic-curvature correction, extension springs with the 2-D dilatation, ghost
//   nodes across clamped and simply supported edges) against central finite differences
//   of the force pass, for a beam, plates and a flat shell at a random deformation, with
//   elastic-perfectly-plastic pairs (signed kink, kink vector of a flat shell) too;
//   symmetry;
// - the errors of a tube deck (structure.cylinder_radius).
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "horizon/deck/deck.hpp"
#include "horizon/loading/loads.hpp"
#include "horizon/material/models/bond_pair.hpp"
#include "horizon/solver/equilibrium.hpp"
#include "horizon/solver/forces.hpp"
#include "horizon/solver/tangent.hpp"
#include "test_helpers.hpp"

namespace horizon {
namespace {

TEST(BondPairKernels, GradientMatchesFiniteDifferences) {
  const Vec3 Y{1.0, 0.2, -0.1}, Yp{-0.9, 0.1, 0.3};
  const PairGradient g = bond_pair_gradient(Y, Yp);
  auto f = [](const Vec3& a, const Vec3& b) { return 1 + dot(a, b) / (norm(a) * norm(b)); };
  EXPECT_NEAR(g.one_plus_cos, f(Y, Yp), 1e-15);
  const double h = 1e-6;
  for (int c = 0; c < 3; ++c) {
    Vec3 e{};
    e[c] = h;
    EXPECT_NEAR(g.dY[c], (f(Y + e, Yp) - f(Y - e, Yp)) / (2 * h), 1e-8);
    EXPECT_NEAR(g.dYp[c], (f(Y, Yp + e) - f(Y, Yp - e)) / (2 * h), 1e-8);
  }
  // A straight pair carries no force (theta = pi).
  const PairGradient s = bond_pair_gradient({1, 0, 0}, {-2, 0, 0});
  EXPECT_EQ(s.one_plus_cos, 0.0);
  EXPECT_EQ(norm(s.dY), 0.0);
}

TEST(BondPairKernels, ReturnMappingLoadAndUnload) {
  const double c = 0.01;
  EXPECT_EQ(plastic_offset(0.005, 0, c), 0.0);              // elastic
  EXPECT_NEAR(plastic_offset(0.03, 0, c), 0.02, 1e-15);      // yields: elastic part stays at c
  EXPECT_NEAR(plastic_offset(0.025, 0.02, c), 0.02, 1e-15);  // unloading is elastic
  EXPECT_NEAR(plastic_offset(0.0, 0.02, c), 0.01, 1e-15);    // reverse yield at -c
  EXPECT_NEAR(critical_kink(0.3, 0.002, 0.1), 2 * 0.3 * 0.002 / 0.1, 1e-15);
}

// The kink vector's return mapping (flat shells): radial return onto the circle
// |d - p| = c, elastic inside it, and a change of the kink's plane moves the offset along
// the new trial direction.
TEST(BondPairKernels, KinkVectorReturnMapping) {
  const double c = 0.01;
  Kink p = plastic_offset(Kink{0.003, 0.004}, Kink{}, c);  // |d| = 0.005: elastic
  EXPECT_EQ(p.n, 0.0);
  EXPECT_EQ(p.t, 0.0);
  p = plastic_offset(Kink{0.03, 0.04}, Kink{}, c);  // |d| = 0.05: offset 0.04 along d
  EXPECT_NEAR(p.n, 0.024, 1e-15);
  EXPECT_NEAR(p.t, 0.032, 1e-15);
  EXPECT_NEAR(std::hypot(0.03 - p.n, 0.04 - p.t), c, 1e-15);
  const Kink q = plastic_offset(Kink{0.03, 0.035}, p, c);  // back inside the circle: unchanged
  EXPECT_EQ(q.n, p.n);
  EXPECT_EQ(q.t, p.t);
  // Bent about the other axis: the trial (0.006 - 0.024, 0.032 - 0.032) = (-0.018, 0) yields
  // at n = -c.
  const Kink r = plastic_offset(Kink{0.006, 0.032}, p, c);
  EXPECT_NEAR(r.n, 0.024 - 0.008, 1e-15);
  EXPECT_NEAR(r.t, 0.032, 1e-15);
  // One component alone is the signed return mapping.
  EXPECT_NEAR(plastic_offset(Kink{0.03, 0}, Kink{}, c).n, plastic_offset(0.03, 0, c), 1e-15);
}

// Moment of the pairs of one node of a beam under uniform curvature kappa, loaded
// monotonically from 0: M = dW/dkappa = sum_j omega alpha V |xi| sin(min(kappa |xi|, c)),
// over both orientations (the energy-conjugate moment, digest sec. 3.5).
double pair_moment(double kappa, double c, int per_horizon, bool by_length, double dx, double alpha) {
  double M = 0;
  for (int k = 1; k <= per_horizon; ++k) {
    const double L = k * dx, w = by_length ? L : 1.0;
    double tp = 0;
    for (int step = 1; step <= 20; ++step) tp = plastic_offset(kappa * L * step / 20, tp, c);
    M += 2 * w * alpha * dx * L * std::sin(kappa * L - tp);
  }
  return M;
}

TEST(BondPairKernels, MomentCurvatureOfElasticPerfectlyPlasticPairs) {
  // A rectangle b x t, delta = 200 dx (the lattice sums approach the integrals of sec. 3.5).
  const int N = 200;
  const double t = 0.1, delta = 0.3, dx = delta / N, E = 200e9, b = 0.1, eps_c = 0.002;
  const double EI = E * b * t * t * t / 12, c = critical_kink(delta, eps_c, t);
  for (bool by_length : {false, true}) {
    double m = 0;
    for (int k = 1; k <= N; ++k) m += 2 * (by_length ? k * dx : 1.0) * (k * dx) * (k * dx) * dx;
    const double alpha = EI / m;                  // eq. 4.4
    const double kappa_y = c / delta;             // the longest pairs yield first: 2 eps_c / t
    EXPECT_NEAR(kappa_y, 2 * eps_c / t, 1e-12);
    const double My = pair_moment(kappa_y, c, N, by_length, dx, alpha);
    EXPECT_NEAR(My / (EI * kappa_y), 1.0, 1e-4);  // M_y = EI kappa_y = sigma_y b t^2/6
    const double limit = pair_moment(1000 * kappa_y, c, N, by_length, dx, alpha) / My;
    const double expected = by_length ? 4.0 / 3.0 : 1.5;
    std::printf("[ figure ] omega = %s: M_inf/M_y = %.4f (expected %.4f)\n", by_length ? "|xi|" : "1", limit, expected);
    EXPECT_NEAR(limit, expected, 0.02 * expected);
    if (!by_length)
      for (double r : {1.25, 1.5, 2.0, 3.0, 5.0}) {
        const double M = pair_moment(r * kappa_y, c, N, false, dx, alpha) / My;
        const double classical = 1.5 - 0.5 / (r * r);
        std::printf("[ figure ] kappa/kappa_y = %.2f: M/M_y = %.4f (classical %.4f)\n", r, M, classical);
        EXPECT_NEAR(M, classical, 0.03 * classical);
      }
  }
}

double max_abs(const SparseMatrix& K) {
  double m = 0;
  for (int c = 0; c < K.outerSize(); ++c)
    for (SparseMatrix::InnerIterator it(K, c); it; ++it) m = std::max(m, std::abs(it.value()));
  return m;
}

struct TangentCheck {
  double fd_error = 0, asymmetry = 0;
  double flowing = 0;  // the plastic work a commit would book (> 0: some pairs flow)
  std::size_t dofs = 0;
};

// The analytic tangent against finite differences (probe 1e-6 dx) at a random
// deformation: transverse w of amplitude `w_amp` dx, a homogeneous in-plane strain of
// about u_amp (and a random in-plane field of u_amp dx when asked); the supported lines
// held at w = 0 as the supports hold them.
TangentCheck check_tangent(const std::string& deck, double w_amp, double u_amp, const std::string& what,
                           bool random_in_plane = false) {
  const Config config = parse_deck(deck, what + ".yaml");
  System s = build_system(config);
  Loads loads(config, s);
  loads.apply_initial_conditions(config, s);
  test::Rng rng(11);
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    const Vec3& X = s.particles.X[i];
    Vec3& u = s.particles.u[i];
    u.z = s.spacing * (w_amp * std::sin(3 * X.x + 2 * X.y) + 0.2 * w_amp * rng.uniform(-1, 1));
    // In-plane: a homogeneous stretch along the support lines' normals (the ghosts, even
    // in the tangential component, continue it exactly), plus a random
    // field when asked.
    u.x = u_amp * 0.5 * X.x;
    if (s.dimension == 2) u.y = -u_amp * 0.3 * X.y;
    if (random_in_plane) {
      u.x += s.spacing * u_amp * rng.uniform(-1, 1);
      if (s.dimension == 2) u.y += s.spacing * u_amp * rng.uniform(-1, 1);
    }
  }
  const DofMap d = make_dof_map(s, loads);
  // The supports hold their lines at w = 0 (the ghosts mirror about them).
  for (std::size_t i = 0; i < s.particles.size(); ++i)
    for (int c = 0; c < 3; ++c)
      if (s.active(c) && d.dof(i, c) < 0) s.particles.u[i][c] = 0;
  {
    FixedBonds fixed(s);
    compute_forces(s, false);
  }
  SparseMatrix K;
  EXPECT_TRUE(model_tangent(s, d, K)) << what;
  const SparseMatrix Kfd = finite_difference_tangent(s, d);
  const double scale = max_abs(K);
  TangentCheck r;
  r.dofs = d.size();
  for (const auto& m : s.models) r.flowing += m->pending_dissipation(s);
  r.fd_error = max_abs(SparseMatrix(K - Kfd)) / scale;
  r.asymmetry = max_abs(SparseMatrix(K - SparseMatrix(K.transpose()))) / scale;
  std::printf("[ figure ] bond_pair tangent, %s (%zu dofs): |K - K_fd|/|K| = %.2e, asymmetry %.1e\n", what.c_str(),
              r.dofs, r.fd_error, r.asymmetry);
  return r;
}

std::string plate_tangent_deck(const std::string& type, double nu, const std::string& material_extra,
                               const std::string& supports) {
  return fmt::format(R"(dimension: 2
structure:
  type: {}
  supports:
{}thickness: 0.01
spacing: 0.1
horizon_factor: 3
lattice_origin: [0.0, 0.0]
materials:
  steel: {{model: bond_pair, density: 7800, youngs_modulus: 200e9, poissons_ratio: {}{}}}
bodies:
  - {{name: plate, material: steel, shape: {{box: {{min: [0.0, 0.0], max: [1.2, 0.9]}}}}}}
solver: {{type: static}}
)",
                     type, supports, nu, material_extra);
}

const char* kPlateSupports =
    "    - {axis: x, at: 0.0, kind: simply_supported}\n    - {axis: y, at: 0.0, kind: clamped}\n"
    "    - {axis: x, at: 1.2, kind: clamped}\n";

// The tolerance: central differences with a probe of 1e-6 dx leave about 1e-8 of the
// largest entry (round-off of the forces over the probe); 1e-6 is the bound the unified
// tangent meets (tests/unit/test_tangent.cpp).
constexpr double kTangentTolerance = 1e-6;

TEST(BondPairTangent, BeamMatchesFiniteDifferences) {
  const std::string deck = R"(dimension: 1
structure:
  type: beam
  supports:
    - {axis: x, at: 0.0, kind: clamped}
    - {axis: x, at: 1.0, kind: simply_supported}
area: 0.01
spacing: 0.05
horizon_factor: 3
lattice_origin: [0.0]
materials:
  steel: {model: bond_pair, density: 7800, youngs_modulus: 200e9, poissons_ratio: 0.3, pair_weight: length}
bodies:
  - {name: beam, material: steel, shape: {box: {min: [0.0], max: [1.0]}}}
solver: {type: static}
)";
  const TangentCheck r = check_tangent(deck, 0.3, 0, "beam");
  EXPECT_LT(r.fd_error, kTangentTolerance);
  EXPECT_LT(r.asymmetry, 1e-12);
}

TEST(BondPairTangent, PlatesMatchFiniteDifferences) {
  // nu = 1/3 (pairs and extension springs), nu = 0.3 (isotropic-curvature correction and
  // 2-D dilatation), both at a large deflection (0.3 dx) with in-plane motion.
  for (double nu : {1.0 / 3.0, 0.3}) {
    const TangentCheck r = check_tangent(plate_tangent_deck("plate", nu, "", kPlateSupports), 0.3, 0.01,
                                         fmt::format("plate nu = {:.3f}", nu));
    EXPECT_LT(r.fd_error, kTangentTolerance) << nu;
    // Symmetric at nu != 1/3 too: the ghost-ghost bonds complete a ghost's dilatation
    // (without them, 3e-4 of the largest entry near the supports).
    EXPECT_LT(r.asymmetry, 1e-12) << nu;
  }
}

TEST(BondPairTangent, FlatShellMatchesFiniteDifferences) {
  for (double nu : {1.0 / 3.0, 0.3}) {
    const TangentCheck r = check_tangent(plate_tangent_deck("shell", nu, "", kPlateSupports), 0.3, 0.01,
                                         fmt::format("shell nu = {:.3f}", nu));
    EXPECT_LT(r.fd_error, kTangentTolerance) << nu;
    // In a shell the support lines move in plane, and the ghosts mirror about the moved
    // line (the foot terms): the forces are then no energy gradient in the in-plane normal
    // component of the line's nodes, and the tangent, exact as it is, is not symmetric
    // there (docs/models/bond_pair.md). Also with a random in-plane field:
    const TangentCheck q = check_tangent(plate_tangent_deck("shell", nu, "", kPlateSupports), 0.3, 0.01,
                                         fmt::format("shell nu = {:.3f}, random in-plane", nu), true);
    EXPECT_LT(q.fd_error, kTangentTolerance) << nu;
  }
}

TEST(BondPairTangent, CurvedShellMatchesFiniteDifferences) {
  // A tube (structure.cylinder_radius): pairs with reference angles (f' d2c + f'' dc dc^T)
  // and chord springs, at a random deformation.
  const double pi = 3.14159265358979323846, dx = 2 * pi * 0.5 / 24;
  const std::string deck = fmt::format(R"(dimension: 2
structure: {{type: shell, cylinder_radius: 0.5}}
thickness: 0.01
spacing: {}
horizon_factor: 3
lattice_origin: [0.0, 0.0]
materials:
  steel: {{model: bond_pair, density: 7800, youngs_modulus: 200e9, poissons_ratio: 0.3333333333333333}}
bodies:
  - {{name: tube, material: steel, shape: {{box: {{min: [0.0, 0.0], max: [{}, {}]}}}}}}
solver: {{type: static}}
)",
                                       dx, 8 * dx, 2 * pi * 0.5 - dx / 2);
  const TangentCheck r = check_tangent(deck, 0.05, 0.01, "tube", true);
  EXPECT_LT(r.fd_error, kTangentTolerance);
  EXPECT_LT(r.asymmetry, 1e-10);  // no ghosts: an energy gradient
}

TEST(BondPairTangent, PlasticPairsMatchFiniteDifferences) {
  // Elastic-perfectly-plastic pairs (signed kink): at this deflection some pairs flow (the
  // yield strain is chosen so that no pair's kink lies within the probe of the yield kink,
  // where the force has a corner: at 0.0002 one does).
  const TangentCheck r = check_tangent(
      plate_tangent_deck("plate", 1.0 / 3.0, ", yield_strain: 0.00021, membrane: false", kPlateSupports), 0.05, 0,
      "plastic plate");
  EXPECT_GT(r.flowing, 0);
  EXPECT_LT(r.fd_error, kTangentTolerance);
  EXPECT_LT(r.asymmetry, 1e-12);
}

// The forces against central differences of the booked strain energy (strain_energy,
// the ledger's E = sum_k w_k e_k) at the random deformation of check_tangent: max |F +
// dE/du| over the free components, relative to max |F|; `line_normal` apart: the in-plane
// normal components of the support lines' nodes (the foot terms, bond_pair.md).
struct GradientCheck {
  double error = 0, line_normal = 0, line_normal_force = 0;
};
GradientCheck check_energy_gradient(const std::string& deck, const std::string& what) {
  const Config config = parse_deck(deck, what + ".yaml");
  System s = build_system(config);
  Loads loads(config, s);
  loads.apply_initial_conditions(config, s);
  test::Rng rng(13);
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    const Vec3& X = s.particles.X[i];
    Vec3& u = s.particles.u[i];
    u.z = s.spacing * (0.3 * std::sin(3 * X.x + 2 * X.y) + 0.06 * rng.uniform(-1, 1));
    u.x = 0.005 * X.x + s.spacing * 0.01 * rng.uniform(-1, 1);
    u.y = -0.003 * X.y + s.spacing * 0.01 * rng.uniform(-1, 1);
  }
  auto on_line_normal = [&](std::size_t i, int c) {
    for (const auto& sup : config.structure.supports)
      if (sup.axis == c && std::abs(s.particles.X[i][c] - sup.at) < 1e-6 * s.spacing) return true;
    return false;
  };
  // Components that do not move (a plate's in-plane ones) stay at 0, and so do the held
  // ones (w on a support) and the in-plane normal components on a support line: then the
  // ghosts are the exact mirror image of the body (the foot terms vanish).
  const DofMap d = make_dof_map(s, loads);
  for (std::size_t i = 0; i < s.particles.size(); ++i)
    for (int c = 0; c < 3; ++c)
      if (!s.active(c) || d.dof(i, c) < 0 || on_line_normal(i, c)) s.particles.u[i][c] = 0;
  compute_forces(s, true);
  std::vector<Vec3> F(s.particles.size());
  double scale = 0;
  for (std::size_t i = 0; i < F.size(); ++i) {
    F[i] = s.particles.f[i] * s.particles.volume[i];
    for (int c = 0; c < 3; ++c)
      if (s.active(c) && d.dof(i, c) >= 0) scale = std::max(scale, std::abs(F[i][c]));
  }
  const double h = 1e-7 * s.spacing;
  GradientCheck r;
  for (std::size_t i = 0; i < F.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      if (!s.active(c) || d.dof(i, c) < 0) continue;
      const double u0 = s.particles.u[i][c];
      s.particles.u[i][c] = u0 + h;
      compute_forces(s, true);
      const double ep = strain_energy(s);
      s.particles.u[i][c] = u0 - h;
      compute_forces(s, true);
      const double em = strain_energy(s);
      s.particles.u[i][c] = u0;
      const double err = std::abs(F[i][c] + (ep - em) / (2 * h)) / scale;
      if (on_line_normal(i, c)) {
        r.line_normal = std::max(r.line_normal, err);
        r.line_normal_force = std::max(r.line_normal_force, std::abs(F[i][c]) / scale);
      } else {
        r.error = std::max(r.error, err);
      }
    }
  std::printf("[ figure ] bond_pair forces vs energy gradient, %s: max |F + dE/du|/max|F| = %.2e; support lines' "
              "in-plane normal components: %.2e, their force %.1e\n",
              what.c_str(), r.error, r.line_normal, r.line_normal_force);
  return r;
}

// The forces are the gradient of the booked energy near clamped and simply supported
// edges, at nu = 1/3 and at nu != 1/3 (isotropic-curvature correction and 2-D dilatation:
// before the ghost-ghost bonds completed a ghost node's dilatation, 0.3 of max |F| at
// nu = 0.3 and the explicit ledger of a shell pushed in plane lost 77 %).
TEST(BondPairTangent, ForcesAreTheBookedEnergyGradient) {
  for (double nu : {1.0 / 3.0, 0.3, 0.2})
    for (const char* type : {"plate", "shell"}) {
      const GradientCheck r = check_energy_gradient(plate_tangent_deck(type, nu, "", kPlateSupports),
                                                    fmt::format("{} nu = {:.3f}", type, nu));
      EXPECT_LT(r.error, 1e-6) << type << " " << nu;
      // A shell's support line is a symmetry line in plane: its nodes' normal components
      // feel no force while the body is its ghosts' mirror image (they stay at 0), though
      // the booked energy has a slope there (the foot terms; not asserted).
      EXPECT_LT(r.line_normal_force, 1e-9) << type << " " << nu;
    }
}

TEST(BondPairTangent, PlasticShellPairsMatchFiniteDifferences) {
  // Elastic-perfectly-plastic pairs of a flat shell (the kink vector, radial return): at
  // this deformation (bending and a random in-plane field) some pairs flow.
  const TangentCheck r = check_tangent(plate_tangent_deck("shell", 1.0 / 3.0, ", yield_strain: 0.00021", kPlateSupports),
                                       0.05, 0.01, "plastic shell", true);
  EXPECT_GT(r.flowing, 0);
  EXPECT_LT(r.fd_error, kTangentTolerance);
}

}  // namespace
}  // namespace horizon

namespace horizon {
namespace {

std::string tube_error_deck(const std::string& structure, double spacing, double arc_end) {
  return fmt::format(R"(dimension: 2
structure: {}
thickness: 0.01
spacing: {}
horizon_factor: 3
lattice_origin: [0.0, 0.0]
materials:
  steel: {{model: bond_pair, density: 7800, youngs_modulus: 200e9, poissons_ratio: 0.3333333333333333}}
bodies:
  - {{name: tube, material: steel, shape: {{box: {{min: [0.0, 0.0], max: [1.0, {}]}}}}}}
solver: {{type: static}}
)",
                     structure, spacing, arc_end);
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

// Curved shells refuse what they cannot model, with the deck's line and column or the
// reason.
TEST(BondPairTangent, CylinderDeckErrors) {
  const double pi = 3.14159265358979323846, dx = 2 * pi / 32;
  std::string e = error_of([&] { parse_deck(tube_error_deck("{type: plate, cylinder_radius: 1.0}", dx, 6), "t.yaml"); });
  EXPECT_NE(e.find("t.yaml:2:"), std::string::npos) << e;
  EXPECT_NE(e.find("a curved surface is a shell"), std::string::npos) << e;
  e = error_of([&] {
    parse_deck(tube_error_deck("{type: shell, supports: [{axis: x, at: 0.0, kind: clamped}], cylinder_radius: 1.0}",
                               dx, 6),
               "t.yaml");
  });
  EXPECT_NE(e.find("supports on a cylinder are not implemented"), std::string::npos) << e;
  // 2 pi R not a whole number of spacings.
  e = error_of([&] { build_system(parse_deck(tube_error_deck("{type: shell, cylinder_radius: 1.0}", 0.2, 6), "t.yaml")); });
  EXPECT_NE(e.find("whole number of spacings"), std::string::npos) << e;
  // A body that repeats the first row at 2 pi R.
  e = error_of(
      [&] { build_system(parse_deck(tube_error_deck("{type: shell, cylinder_radius: 1.0}", dx, 2 * pi), "t.yaml")); });
  EXPECT_NE(e.find("two nodes at one lattice point"), std::string::npos) << e;
  // Plastic pairs need straight reference pairs.
  e = error_of([&] {
    std::string deck = tube_error_deck("{type: shell, cylinder_radius: 1.0}", dx, 2 * pi - dx / 2);
    deck.replace(deck.find("0.3333333333333333}"), 19, "0.3333333333333333, yield_strain: 0.002}");
    build_system(parse_deck(deck, "t.yaml"));
  });
  EXPECT_NE(e.find("yield_strain needs a beam, a plate or a flat shell"), std::string::npos) << e;
  // A correct tube builds.
  EXPECT_EQ(error_of([&] {
              build_system(parse_deck(tube_error_deck("{type: shell, cylinder_radius: 1.0}", dx, 2 * pi - dx / 2), "t.yaml"));
            }),
            "");
}

}  // namespace
}  // namespace horizon
