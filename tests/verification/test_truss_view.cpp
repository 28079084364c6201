// The truss view (output/truss.hpp; seed 002 sec. 6): a PMB bar's bond network written by
// write_truss_file, read back from the file and assembled into a finite-element truss
// model (Eigen sparse) by this test alone, solves the same static problem as Horizon's
// static solver. With the trusses' geometric update (corotational trusses, Newton) the
// displacements agree to 1e-10 relative; the small-strain linear assembly K u = f agrees
// to the size of the geometric nonlinearity (the strain), which is reported.
#include <gtest/gtest.h>

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "horizon/core/error.hpp"
#include "horizon/loading/loads.hpp"
#include "horizon/output/truss.hpp"
#include "horizon/solver/static_driver.hpp"
#include "../single_thread.hpp"
#include "verification_support.hpp"

namespace horizon::verification {
namespace {

struct TrussFile {
  std::vector<Vec3> x;
  std::vector<double> mass;
  struct Element {
    int i, j;
    double L, EA;
  };
  std::vector<Element> trusses;
};

// Reads the documented format (docs/input.md, "horizon export-truss").
TrussFile read_truss_file(const std::string& path) {
  std::ifstream in(path);
  TrussFile f;
  std::string line, word;
  std::size_t nodes = 0, trusses = 0;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    s >> word;
    if (word == "nodes") {
      s >> nodes;
      for (std::size_t k = 0; k < nodes && std::getline(in, line);) {
        if (line[0] == '#') continue;
        std::istringstream r(line);
        int id;
        Vec3 x;
        double m, v;
        r >> id >> x.x >> x.y >> x.z >> m >> v;
        f.x.push_back(x);
        f.mass.push_back(m);
        ++k;
      }
    } else if (word == "trusses") {
      s >> trusses;
      for (std::size_t k = 0; k < trusses && std::getline(in, line);) {
        if (line[0] == '#') continue;
        std::istringstream r(line);
        int id;
        TrussFile::Element e;
        double A, E;
        r >> id >> e.i >> e.j >> e.L >> e.EA >> A >> E;
        EXPECT_NEAR(A * E / e.EA, 1.0, 1e-12);
        --e.i, --e.j;
        f.trusses.push_back(e);
        ++k;
      }
    }
  }
  EXPECT_EQ(f.x.size(), nodes);
  EXPECT_EQ(f.trusses.size(), trusses);
  return f;
}

// Newton on the truss model with prescribed displacements: the internal force of truss
// i-j on i is N n, N = EA (l - L)/L, n = (y_j - y_i)/l; its stiffness block
// k = EA/L n n^T + N/l (I - n n^T) (e.g. Bathe, Finite Element Procedures, sec. 6.3.1).
// linear: one solve with the stiffness at u = 0 and no geometric update.
std::vector<Vec3> solve_trusses(const TrussFile& f, const std::vector<Vec3>& prescribed,
                                const std::vector<uint8_t>& fixed, bool linear) {
  const std::size_t n = f.x.size();
  std::vector<int> dof(n, -1);
  int nfree = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (!fixed[i]) dof[i] = nfree++;
  std::vector<Vec3> u(n);
  for (std::size_t i = 0; i < n; ++i)
    if (fixed[i]) u[i] = prescribed[i];
  for (int iter = 0; iter < 20; ++iter) {
    std::vector<Eigen::Triplet<double>> trip;
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(3 * nfree);
    // linear: K_ff du_f = -K_fc u_c, the same as one Newton step from u_f = 0 without
    // the geometric term; so assemble at the reference and the linear residual.
    for (const auto& t : f.trusses) {
      const Vec3 d = (f.x[t.j] + (linear ? Vec3{} : u[t.j])) - (f.x[t.i] + (linear ? Vec3{} : u[t.i]));
      const double l = norm(d);
      const Vec3 nv = d / l;
      const double N = linear ? 0.0 : t.EA * (l - t.L) / t.L;
      Eigen::Matrix3d k;
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) k(a, b) = (t.EA / t.L - N / l) * nv[a] * nv[b] + (a == b ? N / l : 0.0);
      Vec3 F = nv * N;  // on i; -F on j
      if (linear) {
        const Vec3 du = u[t.j] - u[t.i];
        for (int a = 0; a < 3; ++a) F[a] = k(a, 0) * du.x + k(a, 1) * du.y + k(a, 2) * du.z;
      }
      const int di = dof[t.i], dj = dof[t.j];
      for (int a = 0; a < 3; ++a) {
        if (di >= 0) rhs[3 * di + a] += F[a];
        if (dj >= 0) rhs[3 * dj + a] -= F[a];
        for (int b = 0; b < 3; ++b) {
          if (di >= 0) trip.emplace_back(3 * di + a, 3 * di + b, k(a, b));
          if (dj >= 0) trip.emplace_back(3 * dj + a, 3 * dj + b, k(a, b));
          if (di >= 0 && dj >= 0) {
            trip.emplace_back(3 * di + a, 3 * dj + b, -k(a, b));
            trip.emplace_back(3 * dj + a, 3 * di + b, -k(a, b));
          }
        }
      }
    }
    Eigen::SparseMatrix<double> K(3 * nfree, 3 * nfree);
    K.setFromTriplets(trip.begin(), trip.end());
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> chol(K);
    EXPECT_EQ(chol.info(), Eigen::Success);
    const Eigen::VectorXd du = chol.solve(rhs);
    double dmax = 0, umax = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (dof[i] < 0) continue;
      const Vec3 d{du[3 * dof[i]], du[3 * dof[i] + 1], du[3 * dof[i] + 2]};
      u[i] += d;
      dmax = std::max(dmax, norm(d));
      umax = std::max(umax, norm(u[i]));
    }
    if (linear || dmax <= 1e-15 * umax) break;
  }
  return u;
}

const char* kDeck = R"(
dimension: 3
spacing: 1.0e-3
horizon: 3.0e-3
partial_volume: true
materials:
  steel: {model: pmb, density: 7800, youngs_modulus: 200.0e9}
bodies:
  - {name: bar, material: steel, shape: {box: {min: [0, 0, 0], max: [0.012, 0.005, 0.005]}}}
regions:
  left:  {box: {min: [0, 0, 0], max: [0.001, 0.005, 0.005]}}
  right: {box: {min: [0.011, 0, 0], max: [0.012, 0.005, 0.005]}}
loads:
  - {region: left, displacement: [0, 0, 0]}
  - {region: right, displacement: [1.0e-6, 2.0e-7, 0]}
solver: {type: static, method: newton, linear_solver: cholesky, tolerance: 1.0e-13}
)";

TEST(TrussView, TrussModelSolvesTheSameStaticProblem) {
  test::SingleThread one;
  const auto dir = output_dir("truss_view");
  Config config = parse_deck(kDeck, (dir / "deck.yaml").string());
  System system = build_system(config);
  Loads loads(config, system);
  StaticSolver solver(system, loads, config.solver);
  loads.apply_initial_conditions(config, system);
  solver.initialize();

  // The export is of the reference configuration, before the solve.
  const std::string path = (dir / "trusses.txt").string();
  const TrussNetwork net = truss_network(system);
  write_truss_file(path, system, net);
  while (!solver.done()) ASSERT_TRUE(solver.advance()) << solver.failure();

  const TrussFile f = read_truss_file(path);
  const auto& P = system.particles;
  ASSERT_EQ(f.x.size(), P.size());
  EXPECT_EQ(2 * f.trusses.size(), system.bonds.size());
  double mass = 0;
  for (double m : f.mass) mass += m;
  EXPECT_NEAR(mass / (7800 * 12 * 5 * 5 * 1e-9), 1.0, 1e-12);

  std::vector<uint8_t> fixed(P.size(), 0);
  std::vector<Vec3> prescribed(P.size());
  for (const char* r : {"left", "right"})
    for (uint32_t i : region_particles(config, system, r)) {
      fixed[i] = 1;
      prescribed[i] = P.u[i];
    }
  const std::vector<Vec3> nonlinear = solve_trusses(f, prescribed, fixed, false);
  const std::vector<Vec3> linear = solve_trusses(f, prescribed, fixed, true);
  double dn = 0, dl = 0, umax = 0;
  for (std::size_t i = 0; i < P.size(); ++i) {
    dn = std::max(dn, norm(nonlinear[i] - P.u[i]));
    dl = std::max(dl, norm(linear[i] - P.u[i]));
    umax = std::max(umax, norm(P.u[i]));
  }
  report("truss_view_nonlinear", dn / umax,
         fmt::format("PMB bar 12 x 5 x 5 mm (PV), {} trusses: truss FE (Newton, geometric update) against Horizon's "
                     "static solver: max |du| / max |u| = {:.1e}",
                     f.trusses.size(), dn / umax));
  report("truss_view_linear", dl / umax,
         fmt::format("the same with the linear truss stiffness (K u = f at the reference): {:.1e} (strain 8.3e-5: "
                     "the geometric nonlinearity Horizon's solver keeps)",
                     dl / umax));
  EXPECT_LT(dn / umax, 1e-10);
  EXPECT_LT(dl / umax, 1e-4);
}

TEST(TrussView, StateBasedMaterialsAreRefused) {
  std::string deck = kDeck;
  deck.replace(deck.find("model: pmb"), 10, "model: lps");
  deck.replace(deck.find("youngs_modulus: 200.0e9"), 23, "youngs_modulus: 200.0e9, poissons_ratio: 0.3");
  Config config = parse_deck(deck, "deck.yaml");
  const System system = build_system(config);
  try {
    truss_network(system);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("state-based (dilatation) part"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace horizon::verification
