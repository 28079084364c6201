// Bodies of their own horizons (BodyConfig::horizon; docs/input.md "Bodies of different
// horizons"): each particle's family holds the points within its own body's horizon, as
// Peridigm's directed neighbour lists do (its MultipleHorizons gold). The counts and
// weighted volumes of a small two-body cloud against their closed forms, the LPS forces
// against a direct O(N^2) evaluation of Peridigm's directed sums, momentum, the one-horizon
// deck left as it was, the errors; and the Peridigm importer's mapping of Blocks with
// different horizons, a horizon that varies in space, the Discretization's Horizon and
// the Restart and element-horizon-intersection refusals.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "horizon/core/error.hpp"
#include "horizon/deck/deck.hpp"
#include "horizon/solver/build.hpp"
#include "horizon/solver/forces.hpp"

namespace horizon {
namespace {

namespace fs = std::filesystem;

// MultipleHorizons's cluster: a centre, its six axis neighbours at 1 (three of them at
// 1.000000000002) and a point at 45 degrees in the x-z plane, each with its volume.
struct Point {
  double x, y, z, v;
};
std::vector<Point> cluster(double x0) {
  return {{x0, 0, 0, 0.1},
          {x0 + 1, 0, 0, 0.2},
          {x0, 1, 0, 0.3},
          {x0, 0, 1, 0.4},
          {x0 - 1.000000000002, 0, 0, 0.5},
          {x0, -1.000000000002, 0, 0.4},
          {x0, 0, -1.000000000002, 0.3},
          {x0 + 0.70710678118655, 0, 0.70710678118655, 0.2}};
}

std::string fmt_point(double x, double y, double z, double v) { return fmt::format("[{}, {}, {}, {}]", x, y, z, v); }

std::string points_yaml(const std::vector<Point>& p) {
  std::string s = "[";
  for (std::size_t i = 0; i < p.size(); ++i)
    s += fmt_point(p[i].x, p[i].y, p[i].z, p[i].v) + (i + 1 < p.size() ? ", " : "");
  return s + "]";
}

// Two bodies: `wide` (horizon 1.001, the deck's) at x = 0 and `narrow` (0.999999999999)
// at x = 5; a third cluster at x = 25 mixes them: its centre in `narrow`, the rest `wide`.
std::string deck(const std::string& narrow_horizon = "0.999999999999", const std::string& extra = "") {
  std::vector<Point> wide = cluster(0), narrow = cluster(5), mixed = cluster(25);
  narrow.push_back(mixed[0]);
  wide.insert(wide.end(), mixed.begin() + 1, mixed.end());
  return "dimension: 3\nspacing: 0.1\nhorizon: 1.001\n"
         "materials:\n  m1: {model: lps, density: 2200, bulk_modulus: 14.9e9, shear_modulus: 8.94e9}\n"
         "  m2: {model: lps, density: 2200, bulk_modulus: 14.9e9, shear_modulus: 8.94e9}\n"
         "bodies:\n"
         "  - {name: wide, material: m1, shape: {points: " + points_yaml(wide) + "}}\n"
         "  - {name: narrow, material: m2, horizon: " + narrow_horizon + ", shape: {points: " + points_yaml(narrow) +
         "}}\n"
         "solver: {type: explicit, end_time: 1.0e-6}\n" + extra;
}

std::size_t family_count(const System& s, std::size_t i) {
  std::size_t n = 0;
  for (uint64_t k = s.bonds.begin(i); k < s.bonds.end(i); ++k) n += s.bonds.kinds[s.bonds.kind[k]].one_way ? 0 : 1;
  return n;
}

std::size_t at(const System& s, double x, double y, double z) {
  for (std::size_t i = 0; i < s.particles.size(); ++i)
    if (norm(s.particles.X[i] - Vec3{x, y, z}) < 1e-9) return i;
  ADD_FAILURE() << "no particle at " << x << " " << y << " " << z;
  return 0;
}

TEST(BodyHorizons, FamiliesAreEachParticlesOwnHorizon) {
  System s = build_system(parse_deck(deck(), "two_horizons.yaml"));
  EXPECT_TRUE(s.one_way_bonds);
  // MultipleHorizons's gold: block 1 (1.001) centre 7 neighbours, weighted volume
  // sum_j |xi|^2 V_j = 0.2 + 0.3 + 0.4 + (1 + 2e-12)^2 (0.5 + 0.4 + 0.3) + 0.2 = 2.3 (+4.8e-12);
  // block 2 (1 - 1e-12) centre none (every neighbour at 1 or beyond), its (6, 0, 0) one:
  // the 45-degree point at 2 sin(22.5 deg), m = (2 - sqrt 2) 0.2.
  const double far = 1.000000000002;
  const std::size_t c1 = at(s, 0, 0, 0), c2 = at(s, 5, 0, 0), p2 = at(s, 6, 0, 0);
  EXPECT_EQ(family_count(s, c1), 7u);
  EXPECT_NEAR(s.model.weighted_volume[c1], 0.2 + 0.3 + 0.4 + far * far * 1.2 + 0.2, 1e-14);
  EXPECT_EQ(family_count(s, c2), 0u);
  EXPECT_EQ(s.model.weighted_volume[c2], 0.0);
  EXPECT_EQ(family_count(s, p2), 1u);
  const double diag2 = std::pow(1 - 0.70710678118655, 2) + std::pow(0.70710678118655, 2);
  EXPECT_NEAR(s.model.weighted_volume[p2], diag2 * 0.2, 1e-14);
  // The mixed cluster: its centre (narrow) lists none; each wide neighbour lists it (the
  // gold's (26, 0, 0) of horizon 2.1 lists all seven; here (26, 0, 0) of 1.001 lists the
  // centre and the 45-degree point): the pair is a bond at both ends, one-way at the centre.
  const std::size_t c3 = at(s, 25, 0, 0), p3 = at(s, 26, 0, 0);
  EXPECT_EQ(family_count(s, c3), 0u);
  EXPECT_EQ(s.bonds.end(c3) - s.bonds.begin(c3), 7u);  // the seven that list it
  EXPECT_EQ(family_count(s, p3), 2u);
  EXPECT_NEAR(s.model.weighted_volume[p3], 1.0 * 0.1 + diag2 * 0.2, 1e-14);
}

TEST(BodyHorizons, ForcesAreThoseOfTheDirectedFamilies) {
  System s = build_system(parse_deck(deck(), "two_horizons.yaml"));
  const auto& P = s.particles;
  const std::size_t n = P.size();
  // A deformation with a stretch, a shear and a rotation-free wobble.
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& X = P.X[i];
    s.particles.u[i] = {1e-3 * X.x + 2e-4 * std::sin(3 * X.z), 5e-4 * X.z + 1e-4 * X.x * X.y, -3e-4 * X.z};
  }
  compute_forces(s, false);
  // Peridigm's LPS over directed families N(i) = {j : |xi| <= delta_i} (Silling et al.
  // 2007, eq. 112-113; omega = 1): theta_i = (3/m_i) sum_N(i) |xi| e V_j,
  // t_ij = (3K theta_i/m_i) |xi| + (15 mu/m_i) (e - theta_i |xi|/3),
  // f_i = sum_N(i) t_ij M V_j - sum_{j: i in N(j)} t_ji M_ji V_j (M = Y/|Y|).
  const double K = 14.9e9, mu = 8.94e9;
  std::vector<double> delta(n), m(n, 0), theta(n, 0);
  for (std::size_t i = 0; i < n; ++i) delta[i] = P.block[i] == 0 ? 1.001 : 0.999999999999;
  auto in = [&](std::size_t i, std::size_t j) {
    return j != i && norm(P.X[j] - P.X[i]) <= delta[i] * (1 + 1e-13);
  };
  auto y = [&](std::size_t i) { return P.X[i] + P.u[i]; };
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j)
      if (in(i, j)) m[i] += std::pow(norm(P.X[j] - P.X[i]), 2) * P.volume[j];
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j)
      if (in(i, j) && m[i] > 0) {
        const double L = norm(P.X[j] - P.X[i]);
        theta[i] += 3 / m[i] * L * (norm(y(j) - y(i)) - L) * P.volume[j];
      }
  auto t = [&](std::size_t i, std::size_t j) {
    const double L = norm(P.X[j] - P.X[i]), e = norm(y(j) - y(i)) - L;
    return 3 * K * theta[i] / m[i] * L + 15 * mu / m[i] * (e - theta[i] * L / 3);
  };
  Vec3 total{};
  double scale = 0;
  for (std::size_t i = 0; i < n; ++i) {
    Vec3 f{};
    for (std::size_t j = 0; j < n; ++j) {
      const Vec3 Y = y(j) - y(i);
      const Vec3 M = Y / norm(Y);
      if (in(i, j)) f += t(i, j) * P.volume[j] * M;
      if (in(j, i)) f += t(j, i) * P.volume[j] * M;  // -t_ji M_ji, M_ji = -M
    }
    scale = std::max(scale, norm(f));
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(P.f[i][c], f[c], 1e-9 * scale + 1e-6) << i << " " << c;
    total += P.f[i] * P.volume[i];
  }
  ASSERT_GT(scale, 1e6);
  // Momentum: every pair's forces are equal and opposite, one-way or not.
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(total[c], 0.0, 1e-12 * scale);
  EXPECT_GT(stable_time_step(s), 0.0);
}

TEST(BodyHorizons, OneHorizonLeavesTheBondsAsTheyWere) {
  // Every body of the deck's horizon: no one-way bond, the same bonds as without the key
  // (the unified fast loops stay).
  const System a = build_system(parse_deck(deck("1.001"), "same.yaml"));
  std::string plain = deck("1.001");
  const std::string key = ", horizon: 1.001";
  plain.replace(plain.find(key), key.size(), "");
  const System b = build_system(parse_deck(plain, "plain.yaml"));
  EXPECT_FALSE(a.one_way_bonds);
  EXPECT_EQ(a.bonds.nbr, b.bonds.nbr);
  EXPECT_EQ(a.bonds.offset, b.bonds.offset);
  EXPECT_EQ(a.model.weighted_volume, b.model.weighted_volume);
}

TEST(BodyHorizons, ExpressionHorizonAndErrors) {
  // A horizon in x: 0.9 + x/100 is 1.15 at x = 25 (the mixed cluster's centre, which then
  // lists all seven) -- larger than the deck's 1.001, an error naming the body and point.
  try {
    build_system(parse_deck(deck("0.9 + x/100"), "expr.yaml"));
    ADD_FAILURE() << "expected an error";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("bodies.narrow.horizon: 1.15"), std::string::npos) << what;
    EXPECT_NE(what.find("at the particle (25, 0, 0)"), std::string::npos) << what;
  }
  // Below the deck's: 0.9004 + x/250 is 1.0004 at x = 25, where the mixed centre lists all
  // seven, and 0.9204 at x = 5, where the centre lists none; (6, 0, 0): the 45-degree point.
  System s = build_system(parse_deck(deck("0.9004 + x/250"), "expr.yaml"));
  EXPECT_EQ(family_count(s, at(s, 25, 0, 0)), 7u);
  EXPECT_EQ(family_count(s, at(s, 5, 0, 0)), 0u);
  EXPECT_EQ(family_count(s, at(s, 6, 0, 0)), 1u);
  // Every pair is then in both families or in neither: no one-way bond, the fast loops.
  EXPECT_FALSE(s.one_way_bonds);
  // A number above the deck's horizon, at its line and column.
  try {
    parse_deck(deck("1.5"), "big.yaml");
    ADD_FAILURE() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("larger than the deck's horizon 1.001"), std::string::npos) << e.what();
  }
  // Options that read one horizon for every bond.
  EXPECT_THROW(build_system(parse_deck(deck("0.5", "partial_volume: true\n"), "pv.yaml")), Error);
  // A pmb material in bodies of two horizons: its micromodulus depends on the horizon.
  std::string shared = deck("0.5");
  shared.replace(shared.find("material: m2"), 12, "material: m1");
  const std::size_t m1 = shared.find("  m1: {"), end = shared.find('\n', m1);
  shared.replace(m1, end - m1, "  m1: {model: pmb, density: 2200, youngs_modulus: 70.0e9}");
  try {
    build_system(parse_deck(shared, "shared.yaml"));
    ADD_FAILURE() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("give each horizon its own material"), std::string::npos) << e.what();
  }
}

// --- the Peridigm importer ---

std::string peridigm_deck(const std::string& name, const std::string& blocks, const std::string& extra = "",
                          const std::string& discretization = "") {
  const fs::path dir = fs::temp_directory_path() / "horizon_body_horizons" /
                       ::testing::UnitTest::GetInstance()->current_test_info()->name();
  fs::create_directories(dir);
  std::ofstream(dir / "points.txt") << "0 0 0 1 1\n1 0 0 1 1\n3 0 0 2 1\n4 0 0 2 1\n";
  const std::string text = "Peridigm:\n"
                           "  Discretization:\n"
                           "    Type: \"Text File\"\n"
                           "    Input Mesh File: \"points.txt\"\n" +
                           discretization +
                           "  Materials:\n"
                           "    Steel:\n"
                           "      Material Model: \"Elastic\"\n"
                           "      Density: 7800.0\n"
                           "      Bulk Modulus: 130.0e9\n"
                           "      Shear Modulus: 78.0e9\n"
                           "  Blocks:\n" +
                           blocks +
                           "  Solver:\n"
                           "    Final Time: 1.0e-5\n"
                           "    Verlet:\n"
                           "      Fixed dt: 1.0e-6\n" +
                           extra;
  std::ofstream(dir / name) << text;
  return (dir / name).string();
}

const char* const kTwoGroups = "    One:\n      Block Names: \"block_1\"\n      Material: \"Steel\"\n      Horizon: 1.5\n"
                               "    Two:\n      Block Names: \"block_2\"\n      Material: \"Steel\"\n";

std::string error_of(const std::string& path) {
  try {
    convert_peridigm_deck(path);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(BodyHorizons, PeridigmBlocksOfDifferentHorizons) {
  // Two groups, 1.5 and 0.5: the deck's horizon is the larger, block_2 gets its own.
  YAML::Node n = YAML::Load(convert_peridigm_deck(
      peridigm_deck("two.yaml", std::string(kTwoGroups) + "      Horizon: 0.5\n")));
  EXPECT_EQ(n["horizon"].as<double>(), 1.5);
  EXPECT_FALSE(n["bodies"][0]["horizon"]);
  EXPECT_EQ(n["bodies"][1]["horizon"].as<double>(), 0.5);
  // A horizon in space (Peridigm's variable horizon): the expression, and the deck's
  // horizon its largest value at the points (0.5 + 0.25 x at x = 4: 1.5; block_1's 1.5).
  n = YAML::Load(convert_peridigm_deck(
      peridigm_deck("expr.yaml", std::string(kTwoGroups) + "      Horizon: \"0.5 + 0.25*x\"\n")));
  EXPECT_EQ(n["bodies"][1]["horizon"].as<std::string>(), "0.5 + 0.25*x");
  EXPECT_EQ(n["horizon"].as<double>(), 1.5);
  // One horizon for every group: no body key (the decks that ran before convert as before).
  n = YAML::Load(convert_peridigm_deck(
      peridigm_deck("same.yaml", std::string(kTwoGroups) + "      Horizon: 1.5\n")));
  EXPECT_FALSE(n["bodies"][1]["horizon"]);
  // The Discretization's Horizon: the horizon of the groups that give none.
  n = YAML::Load(convert_peridigm_deck(peridigm_deck("disc.yaml", kTwoGroups, "", "    Horizon: 0.5\n")));
  EXPECT_EQ(n["horizon"].as<double>(), 1.5);
  EXPECT_EQ(n["bodies"][1]["horizon"].as<double>(), 0.5);
  // A horizon in t, and one that is not positive at a point.
  EXPECT_NE(error_of(peridigm_deck("t.yaml", std::string(kTwoGroups) + "      Horizon: \"0.5 + t\"\n"))
                .find("a horizon is a function of x, y, z"),
            std::string::npos);
  EXPECT_NE(error_of(peridigm_deck("neg.yaml", std::string(kTwoGroups) + "      Horizon: \"1 - x/2\"\n"))
                .find("the horizon is -0.5 at the point (3, 0, 0) of block_2"),
            std::string::npos);
}

TEST(BodyHorizons, PeridigmRestartAndIntersectionsAreRefused) {
  const std::string groups = std::string(kTwoGroups) + "      Horizon: 1.5\n";
  const std::string restart = error_of(peridigm_deck("restart.yaml", groups, "  Restart:\n    Restart: true\n"));
  EXPECT_NE(restart.find(":25:14: error: Peridigm.Restart.Restart: Peridigm's restart"), std::string::npos) << restart;
  EXPECT_EQ(error_of(peridigm_deck("no_restart.yaml", groups, "  Restart:\n    Restart: false\n")), "");
  const std::string cut = error_of(peridigm_deck("cut.yaml", groups, "",
                                                 "    Compute Element-Horizon Intersections: true\n"
                                                 "    Element-Horizon Intersection Recursion Level: 2\n"));
  EXPECT_NE(cut.find("element-horizon intersections"), std::string::npos) << cut;
}

}  // namespace
}  // namespace horizon
