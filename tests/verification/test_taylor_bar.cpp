// Taylor impact of a copper bar (Tupek thesis sec. 3.1.1, Table 3.1-3.2; seed 000 digest
// sec. 2.2), reduced: examples/taylor_bar.yaml and examples/taylor_bar_extended.yaml at a
// spacing of 1.0 mm (about 1,000 particles; the thesis's coarsest run has 2,394).
// Figures: the final length (the particles' axial extent plus what the lattice leaves out
// of the bar at its ends), the impact-face radius (the largest radial distance of the
// particles within one spacing of the wall, plus what the lattice leaves out at the
// mantle), the peak equivalent plastic strain, the energy ledger, and the particles' volume
// ratio J = det F (F the classical nonlocal deformation gradient, all weights 1), whose
// mean stays 1 in a plastic flow and falls when a model lets the bar collapse in volume.
// Full-size figures: docs/verification.md ("Taylor bar").
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <fmt/format.h>

#include "horizon/material/model.hpp"
#include "../single_thread.hpp"
#include "verification_support.hpp"
#include "../test_paths.hpp"

namespace horizon::verification {
namespace {

constexpr double kLength = 0.0324, kRadius = 0.0032, kSpacing = 1.0e-3, kWallDepth = 7.5e-5;

struct TaylorResult {
  double length = 0, face_radius = 0, peak_plastic = 0, mean_J = 0, balance = 0, dissipated_fraction = 0;
  double roughness = 0;  // see roughness() below
  double roughness2 = 0;  // the same against a quadratic fit
  double roughness_body = 0;  // the affine one over the particles more than 8 mm above the face (reference)
  double penetration = 0;  // the deepest any particle went into the wall over the run [m]
  int steps = 0;
};

Config taylor_deck(const std::string& example, const std::function<void(Config&)>& edit = {}) {
  Config c = load_deck((std::filesystem::path(HORIZON_SOURCE_DIR) / "examples" / example).string());
  RunOptions o;
  o.coarsen = kSpacing / c.spacing;
  apply_run_options(c, o);
  // The stable step includes the wall's penalty stiffness 2 K d at a depth of one spacing
  // (solver/build.cpp): at this coarse spacing that is 40 times the bonds' and 6 times
  // the cost. The bar's face goes far less deep into the wall: the test takes the same
  // bound at d = kWallDepth, 1/dt^2 = 1/dt_bonds^2 + 2 K d/(2 rho), x 0.5, and run_taylor
  // checks that no particle goes deeper.
  if (edit) edit(c);
  Config bonds_only = c;
  bonds_only.contact.indenters.clear();
  const double dt_bonds = stable_time_step(build_system(bonds_only));
  const double K = c.contact.indenters.front().stiffness, rho = c.materials.front().density;
  c.solver.time_step = 0.5 / std::sqrt(1 / (dt_bonds * dt_bonds) + 2 * K * kWallDepth / (2 * rho));
  return c;
}

TaylorResult run_taylor(Config c) {
  test::SingleThread one;
  Simulation sim(std::move(c));
  TaylorResult r;
  while (sim.solver->time() < sim.config.solver.end_time * (1 - 1e-12)) {
    sim.solver->step(true);
    r.balance = std::max(r.balance, std::abs(sim.solver->ledger().balance_error()));
    ++r.steps;
    const IndenterConfig& wall = sim.config.contact.indenters.front();
    const Vec3 c{0, (*wall.center[1])(0, 0, 0, 0), 0};
    const auto& P = sim.system.particles;
    for (std::size_t i = 0; i < P.size(); ++i)
      r.penetration = std::max(r.penetration, wall.radius - norm(P.position(i) - c));
  }
  const System& s = sim.system;
  const auto& P = s.particles;
  double zmin = 1e300, zmax = -1e300, Zmin = 1e300, Zmax = -1e300, R0 = 0;
  for (std::size_t i = 0; i < P.size(); ++i) {
    const Vec3 x = P.position(i);
    zmin = std::min(zmin, x.y), zmax = std::max(zmax, x.y);  // the bar lies along y
    Zmin = std::min(Zmin, P.X[i].y), Zmax = std::max(Zmax, P.X[i].y);
    R0 = std::max(R0, std::hypot(P.X[i].x, P.X[i].z));
  }
  const double h = sim.config.spacing;
  r.length = zmax - zmin + (kLength - (Zmax - Zmin));
  double rf = 0, Jsum = 0, Vsum = 0;
  for (std::size_t i = 0; i < P.size(); ++i) {
    const Vec3 x = P.position(i);
    if (x.y < zmin + h) rf = std::max(rf, std::hypot(x.x, x.z));
    Eigen::Matrix3d K = Eigen::Matrix3d::Zero(), N = Eigen::Matrix3d::Zero();
    for (uint64_t k = s.bonds.begin(i); k < s.bonds.end(i); ++k) {
      const uint32_t j = s.bonds.nbr[k];
      const Vec3 xi = P.X[j] - P.X[i], Y = P.position(j) - x;
      const Eigen::Vector3d a(xi.x, xi.y, xi.z), b(Y.x, Y.y, Y.z);
      K += a * a.transpose();
      N += b * a.transpose();
    }
    Jsum += (N * K.inverse()).determinant() * P.volume[i];
    Vsum += P.volume[i];
  }
  r.face_radius = rf + (kRadius - R0);
  // Roughness: the root mean square over the particles of |u_i - (a + G (X_i - X_i))|, the
  // deviation of each particle's displacement from the affine least-squares fit of u over
  // its reference neighbours within 2.01 spacings (itself included), in spacings. A smooth
  // field, however strongly deformed, deviates from its local linear fit by the curvature
  // term only (h^2 |grad grad u|, a few hundredths of a spacing here); a zero-energy mode
  // (particle-to-particle oscillation) deviates by its own amplitude.
  {
    double sum = 0, sum_body = 0;
    std::size_t count = 0, count_body = 0;
    const double reach = 2.01 * h;
    for (std::size_t i = 0; i < P.size(); ++i) {
      Eigen::Matrix4d A = Eigen::Matrix4d::Zero();
      Eigen::Matrix<double, 4, 3> b = Eigen::Matrix<double, 4, 3>::Zero();
      for (std::size_t j = 0; j < P.size(); ++j) {
        const Vec3 d = P.X[j] - P.X[i];
        if (norm(d) > reach) continue;
        const Eigen::Vector4d phi(1.0, d.x / h, d.y / h, d.z / h);
        A += phi * phi.transpose();
        b += phi * Eigen::RowVector3d(P.u[j].x, P.u[j].y, P.u[j].z);
      }
      if (A(0, 0) < 10) continue;  // too few neighbours for a fit
      const Eigen::Matrix<double, 4, 3> c = A.ldlt().solve(b);
      const Eigen::RowVector3d e = Eigen::RowVector3d(P.u[i].x, P.u[i].y, P.u[i].z) - c.row(0);
      sum += e.squaredNorm();
      ++count;
      if (P.X[i].y - Zmin > 8e-3) sum_body += e.squaredNorm(), ++count_body;
    }
    r.roughness = count ? std::sqrt(sum / static_cast<double>(count)) / h : 0.0;
    r.roughness_body = count_body ? std::sqrt(sum_body / static_cast<double>(count_body)) / h : 0.0;
  }
  // Roughness against a quadratic fit (10 terms, over the same neighbours within 2.01
  // spacings): a smooth field deviates by its third-derivative term only, so the mushroom's
  // curvature, which the affine fit counts, drops out; a particle-to-particle oscillation
  // (a zero-energy mode) still deviates by its amplitude. Particles whose neighbours do not
  // determine the ten terms (rank < 10) are left out.
  {
    double sum = 0;
    std::size_t count = 0;
    const double reach = 2.01 * h;
    using Vec10 = Eigen::Matrix<double, 10, 1>;
    for (std::size_t i = 0; i < P.size(); ++i) {
      Eigen::Matrix<double, 10, 10> A = Eigen::Matrix<double, 10, 10>::Zero();
      Eigen::Matrix<double, 10, 3> b = Eigen::Matrix<double, 10, 3>::Zero();
      int m = 0;
      for (std::size_t j = 0; j < P.size(); ++j) {
        const Vec3 d = P.X[j] - P.X[i];
        if (norm(d) > reach) continue;
        const double x = d.x / h, y = d.y / h, z = d.z / h;
        Vec10 phi;
        phi << 1.0, x, y, z, x * x, y * y, z * z, x * y, x * z, y * z;
        A += phi * phi.transpose();
        b += phi * Eigen::RowVector3d(P.u[j].x, P.u[j].y, P.u[j].z);
        ++m;
      }
      if (m < 15) continue;
      const Eigen::FullPivLU<Eigen::Matrix<double, 10, 10>> lu(A);
      if (lu.rank() < 10) continue;
      const Eigen::Matrix<double, 10, 3> c = lu.solve(b);
      const Eigen::RowVector3d e = Eigen::RowVector3d(P.u[i].x, P.u[i].y, P.u[i].z) - c.row(0);
      sum += e.squaredNorm();
      ++count;
    }
    r.roughness2 = count ? std::sqrt(sum / static_cast<double>(count)) / h : 0.0;
  }
  r.mean_J = Jsum / Vsum;
  std::vector<ModelField> fields;
  for (const auto& m : s.models) m->fields(s, fields);
  for (const auto& f : fields)
    if (f.name == "equivalent_plastic_strain")
      for (double v : f.values) r.peak_plastic = std::max(r.peak_plastic, v);
  const Ledger& L = sim.solver->ledger();
  r.dissipated_fraction = L.dissipated / L.initial;
  return r;
}

std::string describe(const TaylorResult& r) {
  return fmt::format("final length {:.2f} mm, face radius {:.2f} mm, peak plastic strain {:.2f}, mean J {:.3f}, "
                     "dissipated {:.1f} % of the impact energy, max |balance error| {:.1e}, deepest in the wall "
                     "{:.3f} mm, roughness {:.3g} spacings (quadratic fit {:.3g}, above 8 mm {:.3g}) ({} steps)",
                     r.length * 1e3, r.face_radius * 1e3, r.peak_plastic, r.mean_J, 100 * r.dissipated_fraction,
                     r.balance, r.penetration * 1e3, r.roughness, r.roughness2, r.roughness_body, r.steps);
}

// The thesis's model (correspondence + J2, delta = 3.01 spacings, no stabilisation):
// the shape of Table 3.2 within the band that this coarse lattice reaches, and the ledger
// through plasticity (issue: within 2 %).
TEST(TaylorBar, CorrespondenceJ2ReachesTheThesisShape) {
  const TaylorResult r = run_taylor(taylor_deck("taylor_bar.yaml"));
  report("taylor_corr_length", r.length, "Taylor bar, correspondence + J2, spacing 1 mm: " + describe(r));
  EXPECT_GT(r.length, 20.5e-3);
  EXPECT_LT(r.length, 23.0e-3);
  EXPECT_GT(r.face_radius, 5.2e-3);  // 7.1 mm at the thesis's 2,394 particles
  EXPECT_GT(r.peak_plastic, 1.5);
  EXPECT_NEAR(r.mean_J, 1.0, 0.02);
  EXPECT_GT(r.dissipated_fraction, 0.9);
  EXPECT_LT(r.balance, 0.02);
  EXPECT_LT(r.penetration, kWallDepth) << "the stable step assumes the wall's stiffness at kWallDepth";
}

// The extended model: Tupek's E_(0) (strain_measure seth_hill, m = 0) with a light
// stabilisation on the full residual loses volume under the large plastic flow (the first
// attempt's collapse; the Jensen defect of the averaged log strains, docs/models/
// extended_correspondence.md); the example (hencky, the volume from Fbar, G_s = 0.1 on
// the midpoint residual) keeps it, and flows further than the earlier capped setting
// (peak plastic strain 1.42 against 0.88 on this lattice).
TEST(TaylorBar, ExtendedHenckyKeepsVolumeSethHillDoesNot) {
  const TaylorResult hencky = run_taylor(taylor_deck("taylor_bar_extended.yaml"));
  const TaylorResult seth_hill = run_taylor(taylor_deck("taylor_bar_extended.yaml", [](Config& c) {
    auto& m = c.materials.front();
    m.choices["strain_measure"] = "seth_hill";
    m.parameters["seth_hill_m"] = 0.0;
    m.parameters["stabilization"] = 0.05;
    m.parameters["stabilization_yield"] = 0.0;
    m.choices["stabilization_residual"] = "full";
    m.choices["volumetric_strain"] = "average";
  }));
  report("taylor_ext_J", hencky.mean_J,
         "Taylor bar, extended correspondence + J2, spacing 1 mm, hencky: " + describe(hencky) +
             "; seth_hill m = 0, G_s = 0.05: " + describe(seth_hill));
  EXPECT_NEAR(hencky.mean_J, 1.0, 0.02);
  EXPECT_LT(seth_hill.mean_J, 0.9);
  EXPECT_GT(hencky.peak_plastic, 1.2);
  EXPECT_GT(hencky.length, 20.5e-3);
  EXPECT_LT(hencky.balance, 0.02);
}

// The correspondence instability at a horizon away from 3 spacings (thesis sec. 3.1.2,
// Fig. 3-2; digest sec. 2.3 and pitfall 2). With the old step (0.5 x the bonds' bound,
// the wall's penalty not in it) the plain model at delta = 2 spacings came apart
// (roughness 6.7e7 spacings); with the wall's stiffness in the step it does not: plain
// 0.32 spacings, extended 0.023 (the plain run at 3.01 spacings: 0.39 in
// CorrespondenceJ2ReachesTheThesisShape's figure). The witness left is the factor
// between the two models at delta = 2 spacings; the plain model's roughness mixes its
// mushroom's curvature and the ejected rim, so it does not single out delta.
TEST(TaylorBar, PlainCorrespondenceTurnsRoughAtTwoSpacingsExtendedDoesNot) {
  auto two_spacings = [](Config& c) { c.horizon = 2.0 * c.spacing; };
  const TaylorResult plain = run_taylor(taylor_deck("taylor_bar.yaml", two_spacings));
  const TaylorResult extended = run_taylor(taylor_deck("taylor_bar_extended.yaml", two_spacings));
  report("taylor_roughness_plain", plain.roughness,
         fmt::format("Taylor bar at delta = 2 spacings, roughness (spacings): plain correspondence {:.3g}, "
                     "extended {:.3g}",
                     plain.roughness, extended.roughness));
  EXPECT_TRUE(!(plain.roughness < 5 * extended.roughness)) << plain.roughness;  // NaN counts as rough
  EXPECT_LT(extended.roughness, 0.1);
  EXPECT_LT(extended.balance, 0.02);
}

// Not in the suite (DISABLED_): the settings screen of docs/verification.md ("The
// extended model's stiffness in flow"). Environment: TAYLOR_DECK (an example, default
// taylor_bar_extended.yaml), TAYLOR_GS (stabilization), TAYLOR_CAP (stabilization_yield),
// TAYLOR_PART (stabilization_residual), TAYLOR_VOL (volumetric_strain), TAYLOR_SOFT
// (stabilization_softening), TAYLOR_DELTA (horizon in spacings). Run with
// --gtest_also_run_disabled_tests --gtest_filter=TaylorBar.DISABLED_ScreenSettings.
TEST(TaylorBar, DISABLED_ScreenSettings) {
  const char* deck = std::getenv("TAYLOR_DECK");
  const TaylorResult r = run_taylor(taylor_deck(deck ? deck : "taylor_bar_extended.yaml", [](Config& c) {
    auto& m = c.materials.front();
    if (const char* v = std::getenv("TAYLOR_GS")) m.parameters["stabilization"] = std::stod(v);
    if (const char* v = std::getenv("TAYLOR_CAP")) m.parameters["stabilization_yield"] = std::stod(v);
    if (const char* v = std::getenv("TAYLOR_PART")) m.choices["stabilization_residual"] = v;
    if (const char* v = std::getenv("TAYLOR_DELTA")) c.horizon = std::stod(v) * c.spacing;
    if (const char* v = std::getenv("TAYLOR_VOL")) m.choices["volumetric_strain"] = v;
    if (const char* v = std::getenv("TAYLOR_SOFT")) m.choices["stabilization_softening"] = v;
  }));
  std::printf("SCREEN %s\n", describe(r).c_str());
  EXPECT_LT(r.balance, 0.05);
  EXPECT_GT(r.length, 15e-3);
}

}  // namespace
}  // namespace horizon::verification
