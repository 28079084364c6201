// Peridynamic Riemann problem (Tupek thesis sec. 5.3; digest sec. 10.6), reduced:
// a 2 m x 1 m bar whose halves close at +-1200 m/s, lambda_bar = mu_bar = 10 GPa (plane
// strain reading: E = 13.75 GPa, nu = 0.375), rho = 1180, delta = 0.05 m. The interface is
// pre-broken (bonds crossing x = 0 broken, acting in compression only, eq. 6.9).
// Metric: the deepest interpenetration, max over rows of (max x of the left half - min x
// of the right half), in spacings. The LPS (m = 1/2) interpenetrates; the log strain
// (m = 0) does not, and its adaptive time step shrinks.
#include <gtest/gtest.h>

#include "horizon/loading/loads.hpp"
#include "horizon/solver/explicit.hpp"
#include "horizon/solver/forces.hpp"
#include "../unit/test_helpers.hpp"

namespace horizon {
namespace {

struct RiemannResult {
  double depth = -1e300;  // in spacings (< 0: the halves are still apart in every row)
  double dt_ratio = 1;
};

RiemannResult riemann(double m, double end_time) {
  test::BlockSpec b;
  b.dimension = 2;
  b.plane = PlaneMode::strain;
  b.spacing = 1.0 / 60;  // 120 x 60 = 7,200 particles (the thesis: 20,000 and ~35,000)
  b.horizon_factor = 3.0;
  b.n = {120, 60, 1};
  MaterialConfig mat = test::make_material("nonlinear_solid", 13.75e9, 0.375, 1180, InfluenceKind::tupek);
  mat.parameters["seth_hill_m"] = m;
  Config c = test::block_config(b, mat);
  c.horizon = 0.05;
  System s = build_system(c);
  const double mid = 0.5 * (b.n[0] - 1) * b.spacing;
  auto left = [&](std::size_t i) { return s.particles.X[i].x < mid; };
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    s.particles.v[i] = {left(i) ? 1200.0 : -1200.0, 0, 0};
    for (uint64_t k = s.bonds.begin(i); k < s.bonds.end(i); ++k)
      if (left(i) != left(s.bonds.nbr[k])) s.bonds.intact[k] = 0;
  }
  Loads loads;
  ExplicitSolver solver(s, loads, 0.5 * stable_time_step(s), 0.0);
  solver.initialize();
  const double dt0 = solver.dt();
  double dt_min = dt0;
  RiemannResult r;
  while (solver.time() < end_time) {
    solver.set_dt(0.5 * stable_time_step(s));
    dt_min = std::min(dt_min, solver.dt());
    solver.step(false);
  }
  const int rows = b.n[1];
  std::vector<double> maxl(rows, -1e300), minr(rows, 1e300);
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    const int row = static_cast<int>(std::lround(s.particles.X[i].y / b.spacing));
    const double x = s.particles.position(i).x;
    if (left(i))
      maxl[row] = std::max(maxl[row], x);
    else
      minr[row] = std::min(minr[row], x);
  }
  for (int q = 0; q < rows; ++q) r.depth = std::max(r.depth, (maxl[q] - minr[q]) / b.spacing);
  r.dt_ratio = dt_min / dt0;
  return r;
}

TEST(TupekRiemann, LogStrainStopsInterpenetrationLpsDoesNot) {
  const double end = 1.0e-4;
  const RiemannResult lps = riemann(0.5, end), log_strain = riemann(0.0, end);
  RecordProperty("lps_depth", std::to_string(lps.depth));
  RecordProperty("log_depth", std::to_string(log_strain.depth));
  std::printf("interpenetration depth [spacings]: m = 1/2: %.3f, m = 0: %.3f; dt_min/dt0 m = 0: %.3f, m = 1/2: %.3f\n",
              lps.depth, log_strain.depth, log_strain.dt_ratio, lps.dt_ratio);
  EXPECT_GT(lps.depth, 1.0) << "the LPS lets the halves pass through each other";
  EXPECT_LT(log_strain.depth, 0.0) << "the log strain keeps them apart";
  EXPECT_LT(log_strain.dt_ratio, 0.9) << "the adaptive step engages for m = 0";
}

}  // namespace
}  // namespace horizon
