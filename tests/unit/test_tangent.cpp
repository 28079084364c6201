// The tangent stiffness of solver/tangent.hpp: the analytic assembly (unified bond form,
// LPS dilatation coupling up to two horizons) against central finite differences of
// compute_forces on small randomly deformed blocks with some broken bonds, PMB, LPS and
// a mixed PMB/LPS body, 2-D and 3-D; symmetry; the matrix-free product and diagonal;
// the ADR stiffness bound against the assembled row sums; loose unknowns held.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "horizon/material/model.hpp"
#include "horizon/solver/equilibrium.hpp"
#include "horizon/solver/forces.hpp"
#include "horizon/solver/linear.hpp"
#include "horizon/solver/tangent.hpp"
#include "test_helpers.hpp"

namespace horizon {
namespace {

using test::BlockSpec;

double max_abs(const SparseMatrix& K) {
  double m = 0;
  for (int c = 0; c < K.outerSize(); ++c)
    for (SparseMatrix::InnerIterator it(K, c); it; ++it) m = std::max(m, std::abs(it.value()));
  return m;
}

// A small random deformation (a stretch, a shear and a random field of 2 % of the
// spacing) and about 5 % of the bonds broken (both directions).
void deform(System& s, uint64_t seed) {
  test::Rng rng(seed);
  const int d = s.dimension;
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    const Vec3& X = s.particles.X[i];
    Vec3 u{3e-3 * X.x + 1e-3 * X.y, -1e-3 * X.y + 2e-3 * X.x, d == 3 ? 1.5e-3 * X.z : 0.0};
    for (int c = 0; c < d; ++c) u[c] += 0.02 * s.spacing * rng.uniform(-1, 1);
    if (d < 3) u.z = 0;
    if (d < 2) u.y = 0;
    s.particles.u[i] = u;
  }
  const auto rev = reverse_bonds(s.bonds);
  for (std::size_t k = 0; k < s.bonds.size(); ++k)
    if (k < rev[k] && rng.uniform() < 0.05) s.bonds.intact[k] = s.bonds.intact[rev[k]] = 0;
}

// The dofs, with every seventh component held (prescribed), as constraints would.
DofMap some_held(const System& s) {
  DofMap d;
  d.dimension = s.dimension;
  d.index.assign(3 * s.particles.size(), -1);
  int count = 0;
  for (std::size_t i = 0; i < s.particles.size(); ++i)
    for (int c = 0; c < s.dimension; ++c) {
      if (++count % 7 == 0) continue;
      d.index[3 * i + c] = static_cast<int32_t>(d.particle.size());
      d.particle.push_back(static_cast<uint32_t>(i));
      d.component.push_back(static_cast<uint8_t>(c));
    }
  return d;
}

struct Comparison {
  double fd_error = 0;        // max |K - K_fd| / max |K|
  double asymmetry = 0;       // max |K - K^T| / max |K|
  double product_error = 0;   // |K x - op(x)| / |K x|
  double diagonal_error = 0;  // max |diag K - op.diagonal()| / max |diag K|
  double bound_ratio = 0;     // min over rows of bound / sum_j |K_ij| (>= 1)
};

Comparison compare(System& s, const DofMap& d) {
  Comparison r;
  {
    FixedBonds fixed(s);
    compute_forces(s, false);
  }
  const SparseMatrix K = assemble_tangent(s, d);
  const SparseMatrix Kfd = finite_difference_tangent(s, d);
  const double scale = max_abs(K);
  r.fd_error = max_abs(SparseMatrix(K - Kfd)) / scale;
  r.asymmetry = max_abs(SparseMatrix(K - SparseMatrix(K.transpose()))) / scale;

  test::Rng rng(99);
  Eigen::VectorXd x(K.rows());
  for (Eigen::Index k = 0; k < x.size(); ++k) x[k] = rng.uniform(-1, 1);
  const TangentOperator op(s, d);
  Eigen::VectorXd y;
  op.apply(x, y);
  const Eigen::VectorXd Kx = K.transpose() * x;  // the stored matrix is K^T
  r.product_error = (Kx - y).norm() / Kx.norm();
  const Eigen::VectorXd diag = K.diagonal();
  r.diagonal_error = (diag - op.diagonal()).cwiseAbs().maxCoeff() / diag.cwiseAbs().maxCoeff();

  const Eigen::VectorXd bound = stiffness_row_bound(s, d, linearize(s));
  Eigen::VectorXd rows = Eigen::VectorXd::Zero(K.rows());
  for (int c = 0; c < K.outerSize(); ++c)  // column c of the stored K^T is row c of K
    for (SparseMatrix::InnerIterator it(K, c); it; ++it) rows[c] += std::abs(it.value());
  r.bound_ratio = 1e300;
  for (Eigen::Index k = 0; k < rows.size(); ++k) {
    const double V = s.particles.volume[d.particle[static_cast<std::size_t>(k)]];
    if (rows[k] > 0) r.bound_ratio = std::min(r.bound_ratio, bound[k] * V / rows[k]);
  }
  return r;
}

void check(System& s, const std::string& what) {
  deform(s, 7);
  for (const DofMap& d : {make_free_dof_map(s), some_held(s)}) {
    const Comparison r = compare(s, d);
    std::printf("[ figure ] %s (%zu dofs): |K - K_fd|/|K| = %.2e, asymmetry %.1e, matrix-free %.1e, diagonal %.1e, "
                "ADR bound / row sum >= %.3f\n",
                what.c_str(), d.size(), r.fd_error, r.asymmetry, r.product_error, r.diagonal_error, r.bound_ratio);
    EXPECT_LT(r.fd_error, 1e-6) << what;
    EXPECT_LT(r.asymmetry, 1e-12) << what;
    EXPECT_LT(r.product_error, 1e-12) << what;
    EXPECT_LT(r.diagonal_error, 1e-12) << what;
    EXPECT_GE(r.bound_ratio, 1.0 - 1e-12) << what;
  }
}

BlockSpec spec(int dimension, int n, double m, bool pv) {
  BlockSpec b;
  b.dimension = dimension;
  b.plane = dimension == 2 ? PlaneMode::stress : PlaneMode::none;
  b.n = {n, n, dimension == 3 ? n : 1};
  b.horizon_factor = m;
  b.partial_volume = pv;
  return b;
}

TEST(Tangent, PmbMatchesFiniteDifferences3D) {
  test::SingleThread one;
  System s = test::make_block(spec(3, 5, 2.0, true), test::make_material("pmb", 70e9, 0.25));
  check(s, "PMB 3-D");
}

TEST(Tangent, LpsMatchesFiniteDifferences3D) {
  test::SingleThread one;
  System s = test::make_block(spec(3, 5, 2.0, true), test::make_material("lps", 70e9, 0.3));
  check(s, "LPS 3-D");
}

TEST(Tangent, PmbMatchesFiniteDifferences2D) {
  test::SingleThread one;
  System s = test::make_block(spec(2, 8, 3.0, false), test::make_material("pmb", 70e9, 1.0 / 3));
  check(s, "PMB 2-D");
}

TEST(Tangent, LpsMatchesFiniteDifferences2D) {
  test::SingleThread one;
  System s = test::make_block(spec(2, 8, 3.0, true), test::make_material("lps", 70e9, 0.3,
                                                                         2000.0, InfluenceKind::linear));
  check(s, "LPS 2-D");
}

// A body half PMB, half LPS: bonds across the interface mix the coefficients of both ends.
TEST(Tangent, MixedPmbLpsBodyMatchesFiniteDifferences) {
  test::SingleThread one;
  const BlockSpec b = spec(2, 8, 3.0, false);
  MaterialConfig lps = test::make_material("lps", 70e9, 0.3);
  MaterialConfig pmb = test::make_material("pmb", 50e9, 1.0 / 3);
  pmb.name = "soft";
  Config c = test::block_config(b, lps);
  c.materials.push_back(pmb);
  const double h = b.spacing;
  c.bodies = {BodyConfig{"left", lps.name, Shape::box({-0.5 * h, -0.5 * h, -0.5 * h}, {3.5 * h, 7.5 * h, 0.5 * h})},
              BodyConfig{"right", pmb.name, Shape::box({3.5 * h, -0.5 * h, -0.5 * h}, {7.5 * h, 7.5 * h, 0.5 * h})}};
  System s = build_system(c);
  check(s, "mixed PMB/LPS 2-D");
}

// The correspondence model's analytic tangent (Model::stiffness, the pair form of
// kernels/affine.hpp differentiated, reaching two horizons)
// against central differences of its force pass: linear elastic and neo-Hookean laws with
// the Silling 2017 stabilisation, J2 past yield (the law's consistent tangent from the
// committed state), 3-D and 2-D plane stress, on the randomly deformed blocks with broken
// bonds above. The FD tangent is what the static solvers took before.
double correspondence_tangent_error(int dimension, const std::string& law, double stabilization, double strain) {
  test::SingleThread one;
  BlockSpec b = spec(dimension, dimension == 3 ? 5 : 7, dimension == 3 ? 2.0 : 3.0, false);
  MaterialConfig m = test::make_material("correspondence", 70e9, 0.3);
  m.choices["stress_law"] = law;
  m.parameters["stabilization"] = stabilization;
  if (law == "j2") {
    m.parameters["yield_stress"] = 100e6;
    m.parameters["hardening_modulus"] = 2e9;
  }
  fill_model_defaults(m);
  System s = test::make_block(b, m);
  deform(s, 11);
  for (auto& u : s.particles.u) u *= strain / 3e-3;  // the deformation's scale
  double worst = 0;
  for (const DofMap& d : {make_free_dof_map(s), some_held(s)}) {
    {
      FixedBonds fixed(s);
      compute_forces(s, false);
    }
    SparseMatrix K;
    EXPECT_TRUE(model_tangent(s, d, K)) << law;
    const SparseMatrix Kfd = finite_difference_tangent(s, d);
    const double error = max_abs(SparseMatrix(K - Kfd)) / max_abs(Kfd);
    std::printf("[ figure ] correspondence %s %d-D (stabilization %g, strain %g, %zu dofs): |K - K_fd|/|K| = %.2e\n",
                law.c_str(), dimension, stabilization, strain, d.size(), error);
    worst = std::max(worst, error);
  }
  return worst;
}

TEST(Tangent, CorrespondenceLinearElasticMatchesFiniteDifferences) {
  EXPECT_LT(correspondence_tangent_error(3, "linear_elastic", 1.0, 3e-3), 1e-6);
  EXPECT_LT(correspondence_tangent_error(3, "linear_elastic", 0.0, 3e-3), 1e-6);
  EXPECT_LT(correspondence_tangent_error(2, "linear_elastic", 0.5, 3e-3), 1e-6);
}

TEST(Tangent, CorrespondenceNeoHookeanAndJ2MatchFiniteDifferences) {
  EXPECT_LT(correspondence_tangent_error(3, "neo_hookean", 1.0, 2e-2), 1e-6);
  EXPECT_LT(correspondence_tangent_error(3, "j2", 1.0, 3e-3), 1e-5);  // past yield (100 MPa at 1.4e-3)
}

// The tangent is the model's only where it holds every particle: a second material (here
// another correspondence material) leaves the static solvers the finite differences.
TEST(Tangent, CorrespondenceTangentNeedsEveryParticle) {
  test::SingleThread one;
  const BlockSpec b = spec(2, 6, 3.0, false);
  MaterialConfig m = test::make_material("correspondence", 70e9, 0.3);
  fill_model_defaults(m);
  MaterialConfig other = m;
  other.name = "other";
  Config c = test::block_config(b, m);
  c.materials.push_back(other);
  const double h = b.spacing;
  c.bodies = {BodyConfig{"left", m.name, Shape::box({-0.5 * h, -0.5 * h, -0.5 * h}, {2.5 * h, 5.5 * h, 0.5 * h})},
              BodyConfig{"right", other.name, Shape::box({2.5 * h, -0.5 * h, -0.5 * h}, {5.5 * h, 5.5 * h, 0.5 * h})}};
  System s = build_system(c);
  SparseMatrix K;
  EXPECT_FALSE(model_tangent(s, make_free_dof_map(s), K));
}

}  // namespace
}  // namespace horizon

namespace horizon {
namespace {

// Unknowns without stiffness (a node no intact bond or pair holds): hold_loose_dofs
// gives an empty row the mean diagonal, so that Cholesky is defined and the step there is
// zero when nothing loads the node; rows with entries are left alone.
TEST(Tangent, LooseUnknownsAreHeld) {
  SparseMatrix K(3, 3);
  std::vector<Eigen::Triplet<double, int>> t = {{0, 0, 2.0}, {0, 2, -1.0}, {2, 0, -1.0}, {2, 2, 4.0}};
  K.setFromTriplets(t.begin(), t.end());
  EXPECT_EQ(hold_loose_dofs(K), 1);
  EXPECT_DOUBLE_EQ(K.coeff(1, 1), 3.0);  // mean of 2 and 4
  EXPECT_DOUBLE_EQ(K.coeff(0, 0), 2.0);
  EXPECT_DOUBLE_EQ(K.coeff(2, 0), -1.0);
  EXPECT_EQ(hold_loose_dofs(K), 0);
  LinearSolver cholesky(LinearSolverKind::cholesky);
  Eigen::VectorXd r(3), x;
  r << 1.0, 0.0, 2.0;
  ASSERT_TRUE(cholesky.solve(K, Eigen::VectorXd(), r, x, 1e-12, 10).ok);
  EXPECT_EQ(x[1], 0.0);
}

}  // namespace
}  // namespace horizon
