// The position-aware linear solid (material/models/pals.hpp) and the linearised LPS
// (material/models/linear_lps.hpp):
// - PALS's Lagrange multipliers against Peridigm's Pals_Simple_Shear gold (its 7 x 7 x 7
//   cube, delta = 0.43071428: the centre and a corner particle);
// - PALS is exact for homogeneous small strains at every particle, corners and faces
//   included (its constraints): theta = tr E under any strain, W = mu D:D under each of
//   the six deviatoric modes and W = kappa theta^2/2 under isotropic expansion, where the
//   LPS is off by tens of per cent at the corner;
// - the forces of both models are minus the gradient of their stored energy;
// - the linearised LPS is linear in the displacements, agrees with the LPS at small
//   strain, and differs from it by O(strain) at large strain (LinearLPSBar's 10 %).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "horizon/material/model.hpp"
#include "horizon/material/models/pals.hpp"
#include "horizon/solver/forces.hpp"
#include "horizon/solver/forces_general.hpp"
#include "test_helpers.hpp"

namespace horizon {
namespace {

using test::BlockSpec;
using test::Strain;

// The family of particle (i, j, k) of Peridigm's 7 x 7 x 7 cube of unit side (cells of
// 1/7, volume 1/343), horizon 0.43071428: bond vectors and omega V (omega = 1).
void cube_family(int i, int j, int k, std::vector<Vec3>& xi, std::vector<double>& wv) {
  const double h = 1.0 / 7, delta = 0.43071428;
  xi.clear(), wv.clear();
  for (int a = 0; a < 7; ++a)
    for (int b = 0; b < 7; ++b)
      for (int c = 0; c < 7; ++c) {
        const Vec3 x{(a - i) * h, (b - j) * h, (c - k) * h};
        const double r = std::sqrt(dot(x, x));
        if (r > 0 && r <= delta) xi.push_back(x), wv.push_back(h * h * h);
      }
}

TEST(Pals, MultipliersMatchPeridigmGold) {
  std::vector<Vec3> xi;
  std::vector<double> wv;
  double lam[6], mu[6];
  // The centre particle (element 172 of the gold's cube): cubic symmetry.
  cube_family(3, 3, 3, xi, wv);
  ASSERT_TRUE(pals::dilatation_multipliers(xi, wv, lam));
  ASSERT_TRUE(pals::deviatoric_multipliers(xi, wv, mu));
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(lam[a], 498.75859950859916, 1e-9);
    EXPECT_NEAR(lam[3 + a], 0.0, 1e-9);
    EXPECT_NEAR(mu[a], 3255.297048228792, 1e-8);
    EXPECT_NEAR(mu[3 + a], 629.1344808722481, 1e-9);
  }
  // A corner (element 1: the gold's z axis runs the other way, so its xz and yz
  // multipliers have the sign opposite to this corner's).
  cube_family(0, 0, 0, xi, wv);
  ASSERT_TRUE(pals::dilatation_multipliers(xi, wv, lam));
  ASSERT_TRUE(pals::deviatoric_multipliers(xi, wv, mu));
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(lam[a], 6859.601881548003, 1e-7);
    EXPECT_NEAR(lam[3 + a], -4665.8277742142, 1e-7);
    EXPECT_NEAR(mu[a], 6459.203766285153, 1e-7);
    EXPECT_NEAR(mu[3 + a], 5812.4233083634435, 1e-7);
  }
  // A family of one bond cannot carry six constraints.
  EXPECT_FALSE(pals::dilatation_multipliers({Vec3{1, 0, 0}}, {1.0}, lam));
}

MaterialConfig material(const std::string& model) {
  MaterialConfig m = test::make_material(model, 7e10, 0.3, 2700);
  fill_model_defaults(m);
  return m;
}

BlockSpec cube(int n = 6) {
  BlockSpec b;
  b.n = {n, n, n};
  b.horizon_factor = 3.015;
  return b;
}

void impose_strain(System& s, const Strain& eps) {
  for (std::size_t i = 0; i < s.particles.size(); ++i) s.particles.u[i] = test::apply(eps, s.particles.X[i]);
}

// The largest |W_i/W - 1| over the particles and the dilatation's |theta_i/tr E - 1|
// (PALS: its own field; the LPS: the general pass's theta).
struct Errors {
  double energy = 0, dilatation = 0;
  double interior_energy = 0;  // over the particles whose family is complete
};

Errors errors(System& s, const BlockSpec& b, const Strain& eps, const MaterialConfig& m) {
  impose_strain(s, eps);
  compute_forces(s, true);
  const double tr = eps[0][0] + eps[1][1] + eps[2][2];
  const double w = test::classical_energy(eps, 3, m.bulk_modulus, m.shear_modulus);
  std::vector<ModelField> fields;
  s.models[0].fields(s, fields);
  std::vector<double> theta = s.model.theta;
  for (const auto& f : fields)
    if (f.name == "dilatation") theta = f.values;
  Errors e;
  // Interior: the family (radius horizon, or horizon + spacing/2 with partial volumes)
  // lies inside the block.
  const double reach = b.horizon_factor + (b.partial_volume ? 0.5 : 0.0);
  std::vector<std::size_t> inside;
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    bool in = true;
    for (int k = 0; k < 3; ++k) {
      const double index = s.particles.X[i][k] / b.spacing;
      in = in && index >= reach - 1e-9 && index <= b.n[k] - 1 - reach + 1e-9;
    }
    if (in) inside.push_back(i);
  }
  EXPECT_FALSE(inside.empty());
  for (std::size_t i : inside) e.interior_energy = std::max(e.interior_energy, std::abs(s.particles.energy[i] / w - 1));
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    e.energy = std::max(e.energy, std::abs(s.particles.energy[i] / w - 1));
    if (tr != 0) e.dilatation = std::max(e.dilatation, std::abs(theta[i] / tr - 1));
  }
  return e;
}

// On Peridigm's lattice (delta = 3.015 h, full volumes) and on Horizon's usual one (3 h,
// partial volumes): PALS exact everywhere; the LPS off at the surface by more than 10 %,
// and inside by its lattice error (11-17 % on the first, under 3 % on the second: the
// bulk, where the two models agree in the continuum limit).
void check_homogeneous(const BlockSpec& b, double lps_interior) {
  const MaterialConfig pals_mat = material("pals"), lps_mat = material("lps");
  System pals = test::make_block(b, pals_mat), lps = test::make_block(b, lps_mat);
  const double g = 1e-7;  // small: the extension |Y| - |xi| is linear to 1e-7
  // theta = tr E under a general strain, at every particle.
  Strain general{{{1.0, 0.35, -0.2}, {0.35, -0.6, 0.45}, {-0.2, 0.45, 0.3}}};
  for (auto& row : general)
    for (double& v : row) v *= g;
  EXPECT_LT(errors(pals, b, general, pals_mat).dilatation, 1e-5);
  EXPECT_GT(errors(lps, b, general, lps_mat).dilatation, 0.1);  // the LPS's corners
  // Isotropic expansion: W = kappa theta^2/2 (the LPS too: its theta is exact there).
  Strain iso{};
  for (int a = 0; a < 3; ++a) iso[a][a] = g;
  EXPECT_LT(errors(pals, b, iso, pals_mat).energy, 1e-5);
  EXPECT_LT(errors(lps, b, iso, lps_mat).energy, 1e-5);
  // The six deviatoric modes: W = mu D:D at every particle for PALS.
  for (int mode = 0; mode < 6; ++mode) {
    Strain d{};
    if (mode < 3) {
      for (int a = 0; a < 3; ++a) d[a][a] = (a == mode ? 2.0 / 3 : -1.0 / 3) * g;
    } else {
      const int a = mode == 5 ? 1 : 0, c = mode == 3 ? 1 : 2;
      d[a][c] = d[c][a] = g;
    }
    const Errors p = errors(pals, b, d, pals_mat), l = errors(lps, b, d, lps_mat);
    std::printf("[ energy ] delta %.3f h%s mode %d: W/W_exact - 1: pals worst %.1e; lps interior %.4f, worst %.4f\n",
                b.horizon_factor, b.partial_volume ? " (partial volumes)" : "", mode, p.energy, l.interior_energy,
                l.energy);
    EXPECT_LT(p.energy, 1e-5) << "mode " << mode;
    EXPECT_LT(l.interior_energy, lps_interior) << "mode " << mode;
    EXPECT_GT(l.energy, 0.1) << "mode " << mode;
  }
}

TEST(Pals, ExactForHomogeneousStrainsAtEveryParticle) {
  const test::SingleThread single;
  check_homogeneous(cube(9), 0.17);  // the centre particle has its whole family
  BlockSpec pv = cube(10);
  pv.horizon_factor = 3;
  pv.partial_volume = true;
  check_homogeneous(pv, 0.03);
}

// V_i f_i = -dU/du_i, U = sum W_i V_i, under a random deformation (central differences).
void check_gradient(const std::string& model) {
  const test::SingleThread single;
  const BlockSpec b = cube(5);
  System s = test::make_block(b, material(model));
  test::Rng rng(7);
  const double amp = 1e-3 * b.spacing;
  for (auto& u : s.particles.u) u = Vec3{rng.uniform(-amp, amp), rng.uniform(-amp, amp), rng.uniform(-amp, amp)};
  auto energy = [&] {
    compute_forces(s, true);
    double u = 0;
    for (std::size_t i = 0; i < s.particles.size(); ++i) u += s.particles.energy[i] * s.particles.volume[i];
    return u;
  };
  energy();
  const std::vector<Vec3> f = s.particles.f;
  double scale = 0;
  for (std::size_t i = 0; i < f.size(); ++i) scale = std::max(scale, norm(f[i]) * s.particles.volume[i]);
  const double eta = 1e-4 * amp;
  for (std::size_t i : {std::size_t{0}, s.particles.size() / 2 + 2, s.particles.size() - 1})
    for (int a = 0; a < 3; ++a) {
      const Vec3 u0 = s.particles.u[i];
      s.particles.u[i][a] = u0[a] + eta;
      const double up = energy();
      s.particles.u[i][a] = u0[a] - eta;
      const double um = energy();
      s.particles.u[i] = u0;
      EXPECT_NEAR(-(up - um) / (2 * eta), f[i][a] * s.particles.volume[i], 1e-6 * scale)
          << model << ", particle " << i << " axis " << a;
    }
}

TEST(Pals, ForceIsMinusGradientOfEnergy) { check_gradient("pals"); }

// PALS takes the scalar general pass (ModelTraits::ordinary, force_row); its forces and
// energies are the vector pass's (force_state) up to the order of the sums (the pass adds
// in the fast loops' eight lanes: material/models/ordinary_lanes.hpp), and the same bits
// on 1 and 2 threads.
TEST(Pals, ScalarPassIsTheVectorPassToRoundOff) {
  const BlockSpec b = cube(5);
  System s = test::make_block(b, material("pals"));
  test::Rng rng(11);
  const double amp = 1e-3 * b.spacing;
  for (auto& u : s.particles.u) u = Vec3{rng.uniform(-amp, amp), rng.uniform(-amp, amp), rng.uniform(-amp, amp)};
  auto forces = [&](bool reference, int threads) {
    const int saved = omp_get_max_threads();
    omp_set_num_threads(threads);
    set_general_reference(reference);
    compute_forces(s, true);
    set_general_reference(false);
    omp_set_num_threads(saved);
    return std::make_pair(s.particles.f, s.particles.energy);
  };
  const auto ref = forces(true, 1), fast = forces(false, 1), two = forces(false, 2);
  double fmax = 0, wmax = 0;
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    fmax = std::max(fmax, norm(ref.first[i]));
    wmax = std::max(wmax, std::abs(ref.second[i]));
  }
  ASSERT_GT(fmax, 0);
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(fast.first[i][a], ref.first[i][a], 1e-12 * fmax) << "particle " << i;
      EXPECT_EQ(two.first[i][a], fast.first[i][a]) << "particle " << i;
    }
    EXPECT_NEAR(fast.second[i], ref.second[i], 1e-12 * wmax);
    EXPECT_EQ(two.second[i], fast.second[i]);
  }
}
TEST(LinearLps, ForceIsMinusGradientOfEnergy) { check_gradient("linear_lps"); }

TEST(LinearLps, LinearInTheDisplacementsAndTheLpsAtSmallStrain) {
  const test::SingleThread single;
  const BlockSpec b = cube(5);
  System lin = test::make_block(b, material("linear_lps")), lps = test::make_block(b, material("lps"));
  Strain e{{{1.0, 0.3, 0.0}, {0.3, -0.4, 0.2}, {0.0, 0.2, 0.5}}};
  auto forces = [&](System& s, double scale) {
    Strain x = e;
    for (auto& row : x)
      for (double& v : row) v *= scale;
    impose_strain(s, x);
    compute_forces(s, false);
    return s.particles.f;
  };
  auto worst = [](const std::vector<Vec3>& a, const std::vector<Vec3>& c, double k) {
    double err = 0, big = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
      err = std::max(err, norm(a[i] - c[i] * k));
      big = std::max(big, norm(a[i]));
    }
    return err / big;
  };
  // Linear: f(2u) = 2 f(u) at a strain of 10 %.
  const auto f1 = forces(lin, 0.1), f2 = forces(lin, 0.2);
  EXPECT_LT(worst(f2, f1, 2.0), 1e-12);
  // Small strain: the LPS's forces to O(strain).
  const auto small_lin = forces(lin, 1e-7), small_lps = forces(lps, 1e-7);
  EXPECT_LT(worst(small_lin, small_lps, 1.0), 1e-5);
  // Large strain: they differ by O(strain).
  const auto big_lps = forces(lps, 0.1);
  EXPECT_GT(worst(f1, big_lps, 1.0), 1e-2);
}

}  // namespace
}  // namespace horizon
