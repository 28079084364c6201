// Families and precracks (family/neighbors.hpp, family/precrack.hpp): the cell-list
// search against brute force, the family rule |xi| <= horizon (relative tolerance
// 1e-10), the partial-volume rule, and precracks that cut exactly the bonds that
// cross them, checked against geometry written out independently here.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>
#include <vector>

#include "horizon/deck/deck.hpp"
#include "horizon/family/neighbors.hpp"
#include "horizon/family/precrack.hpp"
#include "horizon/solver/build.hpp"
#include "test_helpers.hpp"

namespace horizon {
namespace {

// Same rows, same order, same reference data, bit for bit.
void expect_same_bonds(const Bonds& a, const Bonds& b) {
  ASSERT_EQ(a.offset, b.offset);
  ASSERT_EQ(a.nbr, b.nbr);
  EXPECT_EQ(a.length, b.length);
  EXPECT_EQ(a.volume, b.volume);
  EXPECT_EQ(a.weight, b.weight);
  EXPECT_EQ(a.intact, b.intact);
}

// Every row sorted, j in row i iff i in row j, and the reference data as documented.
void expect_well_formed(const Bonds& b, const std::vector<Vec3>& X, const std::vector<double>& V, double radius) {
  std::set<std::pair<uint32_t, uint32_t>> pairs;
  for (std::size_t i = 0; i < b.particles(); ++i)
    for (uint64_t k = b.begin(i); k < b.end(i); ++k) {
      const uint32_t j = b.nbr[k];
      if (k > b.begin(i)) {
        EXPECT_LT(b.nbr[k - 1], j) << "row " << i << " not sorted";
      }
      EXPECT_NE(j, i);
      EXPECT_EQ(b.length[k], norm(X[j] - X[i]));
      EXPECT_LE(b.length[k], radius * (1 + 1e-10));
      EXPECT_EQ(b.volume[k], V[j]);
      EXPECT_EQ(b.weight[k], 1.0);
      EXPECT_EQ(b.intact[k], 1);
      pairs.insert({static_cast<uint32_t>(i), j});
    }
  for (const auto& [i, j] : pairs) EXPECT_TRUE(pairs.count({j, i})) << "bond " << i << "-" << j << " one-sided";
}

TEST(Family, CellListMatchesBruteForceOnRandomClouds) {
  test::Rng rng(2024);
  for (int dimension : {2, 3}) {
    std::vector<Vec3> X;
    std::vector<double> V;
    for (int i = 0; i < 1500; ++i) {
      X.push_back({rng.uniform(-0.3, 0.7), rng.uniform(0, 0.5), dimension == 3 ? rng.uniform(0.1, 0.4) : 0.0});
      V.push_back(rng.uniform(0.5, 1.5));
    }
    const double radius = dimension == 3 ? 0.07 : 0.04;
    const Bonds cells = find_neighbors(X, V, radius);
    expect_same_bonds(cells, find_neighbors_brute_force(X, V, radius));
    expect_well_formed(cells, X, V, radius);
    EXPECT_GT(cells.size(), 10 * X.size()) << "the cloud should be dense enough to test something";

    // A far outlier makes the box sparse: the grid coarsens its cells, results stay the same.
    X.push_back({1e3, -2e3, dimension == 3 ? 5e2 : 0.0});
    V.push_back(1.0);
    expect_same_bonds(find_neighbors(X, V, radius), find_neighbors_brute_force(X, V, radius));
  }
}

// Lattice points at exactly 3 spacings (on the horizon sphere) belong to the family,
// even when round-off puts |xi| a few ulps above the horizon.
TEST(Family, CellListMatchesBruteForceOnLatticeWithPointsOnTheHorizon) {
  const double h = 1e-3;  // not a binary fraction: |xi| = 3h is computed with round-off
  for (int dimension : {2, 3}) {
    for (const Vec3 origin : {Vec3{}, Vec3{0.1234, -5.67, 7.89}}) {
      std::vector<Vec3> X;
      std::vector<double> V;
      const int n = dimension == 3 ? 10 : 20;
      for (int k = 0; k < (dimension == 3 ? n : 1); ++k)
        for (int j = 0; j < n; ++j)
          for (int i = 0; i < n; ++i) {
            Vec3 x = origin + Vec3{i * h, j * h, k * h};
            if (dimension == 2) x.z = 0;
            X.push_back(x);
            V.push_back(dimension == 3 ? h * h * h : h * h * 1e-3);
          }
      const double radius = 3 * h;
      const Bonds cells = find_neighbors(X, V, radius);
      expect_same_bonds(cells, find_neighbors_brute_force(X, V, radius));
      expect_well_formed(cells, X, V, radius);

      // An interior particle has every lattice point with |n| <= 3: 122 in 3-D
      // (including the 6 on the sphere at (+-3, 0, 0) ...), 28 in 2-D.
      const std::size_t centre = dimension == 3 ? (5 * n + 5) * n + 5 : 10 * n + 10;
      const std::size_t want = dimension == 3 ? 122 : 28;
      EXPECT_EQ(cells.end(centre) - cells.begin(centre), want);
      const std::size_t on_sphere = centre + 3;  // (i + 3, j, k)
      const auto row_begin = cells.nbr.begin() + static_cast<int64_t>(cells.begin(centre));
      const auto row_end = cells.nbr.begin() + static_cast<int64_t>(cells.end(centre));
      EXPECT_TRUE(std::binary_search(row_begin, row_end, static_cast<uint32_t>(on_sphere)));
    }
  }
}

// The family rule: |xi| <= horizon with a relative tolerance of 1e-10.
TEST(Family, FamilyRuleRelativeTolerance) {
  const double d = 1.7e-3;
  const std::vector<double> V{1, 1};
  auto bonded = [&](double distance) {
    const std::vector<Vec3> X{{0.25, 0.5, 0.75}, Vec3{0.25, 0.5, 0.75} + Vec3{0.6, 0.0, 0.8} * distance};
    const Bonds a = find_neighbors(X, V, d), b = find_neighbors_brute_force(X, V, d);
    EXPECT_EQ(a.size(), b.size());
    return a.size() == 2;
  };
  EXPECT_TRUE(bonded(0.5 * d));
  EXPECT_TRUE(bonded(d));
  EXPECT_TRUE(bonded(d * (1 + 0.5e-10)));
  EXPECT_FALSE(bonded(d * (1 + 2e-10)));
  EXPECT_FALSE(bonded(d * (1 + 1e-6)));
}

// Partial volumes: a neighbour at r > delta - h/2 keeps the fraction (delta + h/2 - r)/h
// of its volume; the others keep all of it.
TEST(Family, PartialVolumeRule) {
  const double h = 0.5, delta = 3.2 * h;
  std::vector<Vec3> X;
  std::vector<double> V;
  for (int j = 0; j < 12; ++j)
    for (int i = 0; i < 12; ++i) {
      X.push_back({i * h, j * h, 0});
      V.push_back(1.0 + 0.01 * i);
    }
  const Bonds full = find_neighbors(X, V, delta);
  Bonds partial = full;
  apply_partial_volume(partial, delta, h);
  int scaled = 0;
  for (std::size_t i = 0; i < X.size(); ++i)
    for (uint64_t k = full.begin(i); k < full.end(i); ++k) {
      const double r = norm(X[full.nbr[k]] - X[i]);
      const double factor = r <= delta - 0.5 * h ? 1.0 : (delta + 0.5 * h - r) / h;
      EXPECT_NEAR(partial.volume[k], factor * V[full.nbr[k]], 1e-15);
      if (factor < 1) ++scaled;
    }
  EXPECT_GT(scaled, 0);
}

// ---------------------------------------------------------------------------------
// Precracks.

double cross2(const Vec3& a, const Vec3& b) { return a.x * b.y - a.y * b.x; }

// Independent 2-D test: solve a + t (b - a) = p + s (q - p); the bond is cut when
// 0 < t < 1 and 0 < s < 1. The lattices below avoid the degenerate cases (a point on
// the crack line, the crack passing through a lattice point), and this checks it.
bool segment_cut(const Vec3& a, const Vec3& b, const Vec3& p, const Vec3& q) {
  const Vec3 r = b - a, w = q - p;
  const double den = cross2(r, w);
  if (den == 0) return false;  // parallel: no crossing
  const double t = cross2(p - a, w) / den, s = cross2(p - a, r) / den;
  const double tol = 1e-9;
  if (t > -tol && t < 1 + tol && s > -tol && s < 1 + tol) {
    EXPECT_GT(std::min({std::abs(t), std::abs(t - 1), std::abs(s), std::abs(s - 1)}), tol)
        << "degenerate test geometry: the bond touches the crack";
  }
  return t > 0 && t < 1 && s > 0 && s < 1;
}

using BondSet = std::set<std::pair<uint32_t, uint32_t>>;

BondSet bond_set(const Bonds& b) {
  BondSet s;
  for (std::size_t i = 0; i < b.particles(); ++i)
    for (uint64_t k = b.begin(i); k < b.end(i); ++k) s.insert({static_cast<uint32_t>(i), b.nbr[k]});
  return s;
}

// Cuts with cut_bonds and checks the result bond by bond against `is_cut`.
template <class IsCut>
void check_cut(const std::vector<Vec3>& X, double radius, const std::vector<Precrack>& cracks, int dimension,
               IsCut is_cut, std::size_t at_least) {
  const std::vector<double> V(X.size(), 1.0);
  const Bonds before = find_neighbors(X, V, radius);
  Bonds after = before;
  const std::size_t removed = cut_bonds(after, X, cracks, dimension);
  const BondSet kept = bond_set(after);
  std::size_t expected_removed = 0;
  for (const auto& [i, j] : bond_set(before)) {
    const bool cut = is_cut(X[i], X[j]);
    if (cut) ++expected_removed;
    EXPECT_EQ(kept.count({i, j}), cut ? 0u : 1u)
        << "bond " << i << "-" << j << (cut ? " should be cut" : " should be kept");
  }
  EXPECT_EQ(removed, expected_removed);
  EXPECT_EQ(after.size(), before.size() - removed);
  EXPECT_EQ(removed % 2, 0u) << "both directions of a bond go together";
  EXPECT_GE(removed, at_least) << "the crack should cut a fair number of bonds";
  // The kept bonds keep their reference data.
  for (std::size_t i = 0; i < after.particles(); ++i)
    for (uint64_t k = after.begin(i); k < after.end(i); ++k)
      EXPECT_EQ(after.length[k], norm(X[after.nbr[k]] - X[i]));
}

TEST(Precrack, SegmentCutsExactlyTheBondsThatCrossIt) {
  std::vector<Vec3> X;
  for (int j = 0; j < 14; ++j)
    for (int i = 0; i < 18; ++i) X.push_back({1.0 * i, 1.0 * j, 0});
  // An edge crack between lattice rows, its tip between columns; and an inclined one.
  const Precrack edge{{{-1.0, 5.5, 0}, {7.3, 5.5, 0}}};
  const Precrack inclined{{{3.2, 1.7, 0}, {12.6, 9.35, 0}}};
  for (const auto& c : {edge, inclined}) {
    SCOPED_TRACE("crack from (" + std::to_string(c.points[0].x) + ", " + std::to_string(c.points[0].y) + ")");
    check_cut(X, 3.0, {c}, 2, [&](const Vec3& a, const Vec3& b) { return segment_cut(a, b, c.points[0], c.points[1]); },
              100);
  }
  // Both at once: a bond is cut when it crosses either.
  check_cut(X, 3.0, {edge, inclined}, 2,
            [&](const Vec3& a, const Vec3& b) {
              return segment_cut(a, b, edge.points[0], edge.points[1]) ||
                     segment_cut(a, b, inclined.points[0], inclined.points[1]);
            },
            200);
}

TEST(Precrack, SegmentTouchingCases) {
  const Precrack c{{{0, 0, 0}, {1, 0, 0}}};
  auto cut = [&](Vec3 a, Vec3 b) {
    const bool x = crosses(a, b, c, 2);
    EXPECT_EQ(x, crosses(b, a, c, 2)) << "direction must not matter";
    return x;
  };
  EXPECT_TRUE(cut({0.5, -1, 0}, {0.5, 1, 0}));      // through the middle
  EXPECT_TRUE(cut({0.2, -0.5, 0}, {2.0, 1.5, 0}));  // oblique
  EXPECT_FALSE(cut({1.5, -1, 0}, {1.5, 1, 0}));     // crosses only the extension beyond the tip
  EXPECT_FALSE(cut({-0.5, -1, 0}, {-0.5, 1, 0}));   // ... and beyond the other end
  EXPECT_FALSE(cut({1.5, 0, 0}, {1.5, 1, 0}));      // touches the extension
  EXPECT_FALSE(cut({0.5, 0, 0}, {0.5, 1, 0}));      // touches the crack itself: ends are not strictly apart
  EXPECT_FALSE(cut({-1, 0, 0}, {2, 0, 0}));         // along the crack line
  EXPECT_FALSE(cut({0.3, 0.2, 0}, {0.8, 0.7, 0}));  // on one side
  EXPECT_TRUE(cut({1, -1, 0}, {1, 1, 0}));          // through the tip: the crack's end lies on the bond
  EXPECT_FALSE(crosses({0.5, -1, 0}, {0.5, 1, 0}, Precrack{{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}}}, 2))
      << "a 2-D crack is a segment";
}

// Independent 3-D test for a convex polygon: the crossing point of the plane lies on
// the inner side of every edge.
bool convex_polygon_cut(const Vec3& a, const Vec3& b, const std::vector<Vec3>& poly) {
  const Vec3 n = cross(poly[1] - poly[0], poly[2] - poly[0]);
  const double da = dot(a - poly[0], n), db = dot(b - poly[0], n);
  EXPECT_GT(std::min(std::abs(da), std::abs(db)), 1e-9 * norm(n)) << "a lattice point on the crack plane";
  if (!(da * db < 0)) return false;
  const Vec3 x = a + (b - a) * (da / (da - db));
  double closest = 1e300;
  bool inside = true;
  for (std::size_t k = 0; k < poly.size(); ++k) {
    const double side = dot(cross(poly[(k + 1) % poly.size()] - poly[k], x - poly[k]), n);
    closest = std::min(closest, std::abs(side));
    inside = inside && side > 0;
  }
  if (inside) {
    EXPECT_GT(closest, 1e-9) << "degenerate test geometry: crossing point on a polygon edge";
  }
  return inside;
}

std::vector<Vec3> cube_lattice(int n) {
  std::vector<Vec3> X;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) X.push_back({1.0 * i, 1.0 * j, 1.0 * k});
  return X;
}

TEST(Precrack, PolygonCutsExactlyTheBondsThatCrossIt) {
  const std::vector<Vec3> X = cube_lattice(10);
  // A convex quadrilateral in the inclined plane z = 4.37 - 0.1 (x - 4.5) - 0.2 (y - 4.5).
  auto on_plane = [](double x, double y) { return Vec3{x, y, 4.37 - 0.1 * (x - 4.5) - 0.2 * (y - 4.5)}; };
  const Precrack quad{{on_plane(-1.1, -0.9), on_plane(6.3, -1.2), on_plane(5.1, 6.7), on_plane(-0.8, 7.2)}};
  check_cut(X, 2.5, {quad}, 3, [&](const Vec3& a, const Vec3& b) { return convex_polygon_cut(a, b, quad.points); },
            300);

  // A non-convex L-shaped polygon in z = 4.5: the union of two rectangles.
  const Precrack ell{{{1.3, 1.3, 4.5}, {7.7, 1.3, 4.5}, {7.7, 3.6, 4.5}, {3.4, 3.6, 4.5}, {3.4, 8.2, 4.5},
                      {1.3, 8.2, 4.5}}};
  auto in_ell = [](double x, double y) {
    return (x > 1.3 && x < 7.7 && y > 1.3 && y < 3.6) || (x > 1.3 && x < 3.4 && y > 1.3 && y < 8.2);
  };
  check_cut(X, 2.5, {ell}, 3,
            [&](const Vec3& a, const Vec3& b) {
              if (!((a.z - 4.5) * (b.z - 4.5) < 0)) return false;
              const double t = (4.5 - a.z) / (b.z - a.z);
              const Vec3 x = a + (b - a) * t;
              return in_ell(x.x, x.y);
            },
            300);
}

TEST(Precrack, PolygonTouchingCases) {
  const Precrack sq{{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}};
  EXPECT_TRUE(crosses({0.5, 0.5, -1}, {0.5, 0.5, 1}, sq, 3));
  EXPECT_TRUE(crosses({0.5, 0.5, 1}, {0.2, 0.9, -0.3}, sq, 3));
  EXPECT_FALSE(crosses({1.5, 0.5, -1}, {1.5, 0.5, 1}, sq, 3));   // crosses the plane outside the polygon
  EXPECT_FALSE(crosses({0.5, 0.5, 0}, {0.5, 0.5, 1}, sq, 3));    // touches the polygon
  EXPECT_FALSE(crosses({0.5, 0.5, 0.1}, {0.7, 0.5, 0.9}, sq, 3));  // one side
  EXPECT_FALSE(crosses({-1, 0.5, 0}, {2, 0.5, 0}, sq, 3));       // in the plane
  EXPECT_FALSE(crosses({0.5, 0.5, -1}, {0.5, 0.5, 1}, Precrack{{{0, 0, 0}, {1, 0, 0}}}, 3))
      << "a 3-D crack needs at least three points";
}

// End to end: a deck's precrack removes exactly the crossing bonds in build_system.
TEST(Precrack, BuildSystemCutsTheDeckPrecrack) {
  const Config config = parse_deck(R"deck(dimension: 2
plane: stress
thickness: 1.0e-3
spacing: 1.0e-3
horizon_factor: 3
lattice_origin: [0, 0]
materials:
  glass: {model: pmb, density: 2440, youngs_modulus: 72.0e9}
bodies:
  - {name: plate, material: glass, shape: {box: {min: [-0.0005, -0.0005], max: [0.0195, 0.0115]}}}
precracks:
  - {from: [-0.001, 0.0055], to: [0.0083, 0.0055]}
solver: {end_time: 1.0e-6}
)deck",
                                   "precrack.yaml");
  const System s = build_system(config);
  ASSERT_EQ(s.particles.size(), 20u * 12u);
  const Bonds all = find_neighbors(s.particles.X, s.particles.volume, config.horizon);
  std::size_t crossing = 0;
  const Vec3 p{-0.001, 0.0055, 0}, q{0.0083, 0.0055, 0};
  for (const auto& [i, j] : bond_set(all)) crossing += segment_cut(s.particles.X[i], s.particles.X[j], p, q);
  EXPECT_GT(crossing, 0u);
  EXPECT_EQ(s.precrack_bonds, crossing);
  EXPECT_EQ(s.bonds.size(), all.size() - crossing);
  EXPECT_EQ(s.initial_bonds, s.bonds.size());
}

// bonds: broken keeps the crossing bonds in the families, marked broken (intact = 0),
// so that the nonlinear solid can push through them in compression (Tupek eq. 6.9);
// the same bonds are found as with the default removal.
TEST(Precrack, BrokenBondsStayInTheFamilies) {
  std::vector<Vec3> X;
  for (int j = 0; j < 14; ++j)
    for (int i = 0; i < 18; ++i) X.push_back({1.0 * i, 1.0 * j, 0});
  const std::vector<double> V(X.size(), 1.0);
  const Precrack removed{{{-1.0, 5.5, 0}, {7.3, 5.5, 0}}};
  Precrack kept = removed;
  kept.keep_broken = true;
  const Bonds before = find_neighbors(X, V, 3.0);
  Bonds a = before, b = before;
  const std::size_t n_removed = cut_bonds(a, X, {removed}, 2);
  const std::size_t n_broken = cut_bonds(b, X, {kept}, 2);
  EXPECT_GT(n_removed, 100u);
  EXPECT_EQ(n_broken, n_removed);
  ASSERT_EQ(b.size(), before.size());
  std::size_t zero = 0;
  for (std::size_t i = 0; i < b.particles(); ++i)
    for (uint64_t k = b.begin(i); k < b.end(i); ++k) {
      const bool cut = segment_cut(X[i], X[b.nbr[k]], removed.points[0], removed.points[1]);
      EXPECT_EQ(b.intact[k], cut ? 0 : 1);
      zero += b.intact[k] == 0;
    }
  EXPECT_EQ(zero, n_broken);
  // A bond crossing both a removing and a keeping crack is removed.
  Bonds c = before;
  cut_bonds(c, X, {kept, removed}, 2);
  EXPECT_EQ(c.size(), a.size());
  // The deck key.
  const Config config = parse_deck(R"deck(dimension: 2
plane: strain
thickness: 1.0
spacing: 0.1
horizon: 0.3
materials:
  m: {model: nonlinear_solid, density: 1000, youngs_modulus: 1.0e9, poissons_ratio: 0.3}
bodies:
  - {name: bar, material: m, shape: {box: {min: [0, 0], max: [2, 1]}}}
precracks:
  - {from: [1.0, -0.01], to: [1.0, 1.01], bonds: broken}
solver: {end_time: 1.0e-6}
)deck",
                                   "broken.yaml");
  ASSERT_EQ(config.precracks.size(), 1u);
  EXPECT_TRUE(config.precracks[0].keep_broken);
}

}  // namespace
}  // namespace horizon
