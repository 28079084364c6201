// The shear correction factor of the ordinary state-based solids (material/
// shear_correction.hpp; Peridigm's Apply Shear Correction Factor): s_i = 1/(1 - |dev S|^2/
// ((1 - 1/d) m^2)) from the family's second moment S = sum omega V xi (x) xi. Closed forms
// of the factor on small families, its invariance under rotation, and in the lps and
// elastic_plastic force states: a corner particle's deviatoric energy, summed over the five
// orthonormal traceless strains, is the continuum's 5 mu eps^2 with the factor, and 1/s_i
// of it without.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "horizon/material/constants.hpp"
#include "horizon/material/shear_correction.hpp"
#include "horizon/solver/forces.hpp"
#include "test_helpers.hpp"

namespace horizon {
namespace {

// The lattice family of radius r (in spacings) with omega V = 1, less the bonds `drop` rejects.
template <class Drop>
FamilyView lattice_family(double r, int dimension, Drop drop) {
  FamilyView f;
  const int n = static_cast<int>(std::ceil(r));
  const int nz = dimension == 3 ? n : 0;
  for (int k = -nz; k <= nz; ++k)
    for (int j = -n; j <= n; ++j)
      for (int i = -n; i <= n; ++i) {
        const Vec3 xi{1.0 * i, 1.0 * j, 1.0 * k};
        const double l2 = dot(xi, xi);
        if (l2 == 0 || l2 > r * r || drop(xi)) continue;
        f.xi.push_back(xi);
        f.wv.push_back(1.0);
      }
  return f;
}

TEST(ShearCorrection, WholeLatticeFamilyIsOne) {
  // A whole family on a cubic (square) lattice has S = (m/d) I: no correction.
  for (double r : {1.0, 2.0, 3.015, 4.0}) {
    EXPECT_NEAR(shear_correction_factor(lattice_family(r, 3, [](const Vec3&) { return false; }), 3), 1.0, 1e-13) << r;
    EXPECT_NEAR(shear_correction_factor(lattice_family(r, 2, [](const Vec3&) { return false; }), 2), 1.0, 1e-13) << r;
  }
}

TEST(ShearCorrection, ClosedFormsOfTruncatedFamilies) {
  // The six nearest neighbours less +z: S = diag(2, 2, 1), m = 5, |dev S|^2 = 2/3:
  // s = 1/(1 - (2/3)/((2/3) 25)) = 25/24.
  const FamilyView five = lattice_family(1.0, 3, [](const Vec3& x) { return x.z > 0; });
  ASSERT_EQ(five.xi.size(), 5u);
  EXPECT_NEAR(shear_correction_factor(five, 3), 25.0 / 24.0, 1e-14);
  // The in-plane family of a one-layer plate (3-D, z = 0 only): S = diag(a, a, 0),
  // |dev S|^2 = (2/3) a^2, m = 2a: s = 1/(1 - 1/4) = 4/3 whatever the radius.
  for (double r : {1.0, 2.0, 3.015})
    EXPECT_NEAR(shear_correction_factor(lattice_family(r, 3, [](const Vec3& x) { return x.z != 0; }), 3), 4.0 / 3.0,
                1e-13)
        << r;
  // 2-D: the four nearest neighbours less +y: S = diag(2, 1), m = 3, |dev S|^2 = 1/2:
  // s = 1/(1 - (1/2)/((1/2) 9)) = 9/8.
  EXPECT_NEAR(shear_correction_factor(lattice_family(1.0, 2, [](const Vec3& x) { return x.y > 0; }), 2), 9.0 / 8.0,
              1e-14);
}

TEST(ShearCorrection, SameForARotatedFamily) {
  // A corner family (x, y, z <= 0 of radius 3.015), and the same bonds rotated: the factor
  // depends on the invariants of S alone (Peridigm's SurfaceFactorCube compares a cube and
  // the cube rotated 30 degrees about z, then y).
  FamilyView f = lattice_family(3.015, 3, [](const Vec3& x) { return x.x > 0 || x.y > 0 || x.z > 0; });
  const double s = shear_correction_factor(f, 3);
  EXPECT_GT(s, 1.1);
  const double a = 0.5236, b = 0.5236, c = 1.1;
  auto rotate = [&](Vec3 v) {
    v = {std::cos(a) * v.x - std::sin(a) * v.y, std::sin(a) * v.x + std::cos(a) * v.y, v.z};
    v = {std::cos(b) * v.x + std::sin(b) * v.z, v.y, -std::sin(b) * v.x + std::cos(b) * v.z};
    return Vec3{v.x, std::cos(c) * v.y - std::sin(c) * v.z, std::sin(c) * v.y + std::cos(c) * v.z};
  };
  for (auto& x : f.xi) x = rotate(x);
  EXPECT_NEAR(shear_correction_factor(f, 3), s, 1e-12 * s);
}

TEST(ShearCorrection, NoDeviatoricStiffnessNoFactor) {
  // Collinear bonds: e^d = 0 under any deformation (BondBreakingInitialVelocity-EP's
  // families of one bond); no family at all.
  FamilyView line;
  line.xi = {Vec3{1.05, 0, 0}, Vec3{-2.1, 0, 0}};
  line.wv = {1.0, 0.5};
  EXPECT_EQ(shear_correction_factor(line, 3), 1.0);
  EXPECT_EQ(shear_correction_factor(FamilyView{}, 3), 1.0);
}

// The five orthonormal traceless strains: shears in the coordinate planes, and the two
// normal ones.
std::vector<test::Strain> deviatoric_basis() {
  const double r2 = 1 / std::sqrt(2.0), r6 = 1 / std::sqrt(6.0);
  std::vector<test::Strain> out(5, test::Strain{});
  out[0][0][1] = out[0][1][0] = r2;
  out[1][1][2] = out[1][2][1] = r2;
  out[2][0][2] = out[2][2][0] = r2;
  out[3][0][0] = r2, out[3][1][1] = -r2;
  out[4][0][0] = r6, out[4][1][1] = r6, out[4][2][2] = -2 * r6;
  return out;
}

std::vector<double> model_field(const System& s, const std::string& name) {
  std::vector<ModelField> fields;
  for (const auto& m : s.models) m->fields(s, fields);
  for (const auto& f : fields)
    if (f.name == name) return f.values;
  return {};
}

// The particle at lattice point (i, j, k) of spacing h.
std::size_t particle_at(const System& s, double i, double j, double k, double h) {
  for (std::size_t p = 0; p < s.particles.size(); ++p) {
    const Vec3 d = s.particles.X[p] - Vec3{i * h, j * h, k * h};
    if (dot(d, d) < 1e-6 * h * h) return p;
  }
  ADD_FAILURE() << "no particle at " << i << " " << j << " " << k;
  return 0;
}

// The corner particle of a 6^3 block (delta = 3 h): sum over the basis of its deviatoric
// energy W - k' theta^2/2, over the continuum's 5 mu eps^2.
double corner_deviatoric_ratio(const std::string& model, bool corrected, double* factor) {
  const test::SingleThread single;
  test::BlockSpec b;
  b.n = {6, 6, 6};
  MaterialConfig mat = test::make_material(model, 7.0e10, 0.3);
  if (model == "elastic_plastic") mat.parameters["yield_stress"] = 1e12;
  mat.parameters["shear_correction"] = corrected ? 1.0 : 0.0;
  System s = test::make_block(b, mat);
  const double kk = lps_bulk_modulus(mat.bulk_modulus, mat.shear_modulus, test::dimensioning_of(test::block_config(b, mat)));
  const std::size_t corner = particle_at(s, 0, 0, 0, b.spacing);
  const double eps = 1e-7;
  double sum = 0;
  for (test::Strain e : deviatoric_basis()) {
    for (auto& row : e)
      for (double& v : row) v *= eps;
    for (std::size_t i = 0; i < s.particles.size(); ++i) s.particles.u[i] = test::apply(e, s.particles.X[i]);
    compute_forces(s, true);
    const double theta = model == "lps" ? s.model.theta[corner] : model_field(s, "dilatation").at(corner);
    sum += s.particles.energy[corner] - 0.5 * kk * theta * theta;
  }
  const std::vector<double> f = model_field(s, "shear_correction_factor");
  EXPECT_EQ(f.empty(), !corrected);
  if (corrected) {
    *factor = f.at(corner);
    // The block's particle (3, 3, 3) has its whole family: s = 1.
    EXPECT_NEAR(f.at(particle_at(s, 3, 3, 3, b.spacing)), 1.0, 1e-12);
  }
  return sum / (5 * mat.shear_modulus * eps * eps);
}

TEST(ShearCorrection, CornerParticleStoresTheContinuumsDeviatoricEnergy) {
  for (const std::string model : {"lps", "elastic_plastic"}) {
    double s = 0;
    const double with = corner_deviatoric_ratio(model, true, &s);
    const double without = corner_deviatoric_ratio(model, false, nullptr);
    EXPECT_GT(s, 1.2) << model;  // a corner: an eighth of the family and more
    EXPECT_NEAR(with, 1.0, 1e-5) << model;
    EXPECT_NEAR(without * s, 1.0, 1e-5) << model;
  }
}

}  // namespace
}  // namespace horizon
