// Bodies from closed triangulated surfaces (geometry/surface.hpp; docs/input.md "Shapes",
// `surface`): STL files written by the test -- a cube, a sphere of 1984 triangles and a
// plate with a through hole (a solid of genus one) -- fill to the solid's volume within
// one lattice layer: |N h^3 - V| <= A h, with V and A the polyhedron's volume and area.
// ASCII and binary STL read the same. Points on faces, edges and vertices are inside;
// rays through edges and vertices count once (the tie rule), checked against the
// generalized winding number, +-1 inside a closed surface and 0 outside (Jacobson, Kavan and Sorkine-Hornung, "Robust inside-outside
// segmentation using generalized winding numbers", ACM TOG 32(4), 2013, eq. 2 with the
// solid angle of Van Oosterom and Strackee, IEEE TBME 30(2), 1983). An open surface and
// one that passes through itself are refused, naming where, with the deck's line and
// column of the `surface` key.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "horizon/core/error.hpp"
#include "horizon/geometry/lattice.hpp"
#include "horizon/geometry/surface.hpp"
#include "verification_support.hpp"

namespace horizon::verification {
namespace {

using Tri = std::array<Vec3, 3>;

// STL as the format's authors describe it (3D Systems, "StereoLithography Interface
// Specification", 1988): ASCII facets, or an 80-byte header, a uint32 count and 50 bytes
// a triangle (normal, three corners as float32, a uint16).
void write_stl(const std::vector<Tri>& tris, const std::string& path, bool binary) {
  std::ofstream out(path, std::ios::binary);
  if (!binary) {
    out << "solid test\n";
    out.precision(9);
    for (const auto& t : tris) {
      out << " facet normal 0 0 0\n  outer loop\n";
      for (const auto& v : t) out << "   vertex " << static_cast<float>(v.x) << " " << static_cast<float>(v.y) << " " << static_cast<float>(v.z) << "\n";
      out << "  endloop\n endfacet\n";
    }
    out << "endsolid test\n";
    return;
  }
  const std::string header(80, ' ');
  out.write(header.data(), 80);
  const auto n = static_cast<uint32_t>(tris.size());
  out.write(reinterpret_cast<const char*>(&n), 4);
  for (const auto& t : tris) {
    const Vec3 nn = cross(t[1] - t[0], t[2] - t[0]);
    float f[12] = {static_cast<float>(nn.x), static_cast<float>(nn.y), static_cast<float>(nn.z)};
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) f[3 + 3 * k + c] = static_cast<float>(t[static_cast<std::size_t>(k)][c]);
    out.write(reinterpret_cast<const char*>(f), sizeof f);
    const uint16_t attr = 0;
    out.write(reinterpret_cast<const char*>(&attr), 2);
  }
}

// The quadrangle a b c d (in order) as two triangles.
void quad(std::vector<Tri>& t, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  t.push_back({a, b, c});
  t.push_back({a, c, d});
}

std::vector<Tri> cube(const Vec3& lo, const Vec3& hi) {
  auto P = [&](int i, int j, int k) { return Vec3{i ? hi.x : lo.x, j ? hi.y : lo.y, k ? hi.z : lo.z}; };
  std::vector<Tri> t;
  quad(t, P(0, 0, 0), P(0, 1, 0), P(1, 1, 0), P(1, 0, 0));  // outward normals
  quad(t, P(0, 0, 1), P(1, 0, 1), P(1, 1, 1), P(0, 1, 1));
  quad(t, P(0, 0, 0), P(1, 0, 0), P(1, 0, 1), P(0, 0, 1));
  quad(t, P(0, 1, 0), P(0, 1, 1), P(1, 1, 1), P(1, 1, 0));
  quad(t, P(0, 0, 0), P(0, 0, 1), P(0, 1, 1), P(0, 1, 0));
  quad(t, P(1, 0, 0), P(1, 1, 0), P(1, 1, 1), P(1, 0, 1));
  return t;
}

// Latitude-longitude sphere: 32 meridians, 31 bands, fans at the poles: 1984 triangles.
std::vector<Tri> sphere(const Vec3& c, double r, int n = 32) {
  auto P = [&](int i, int j) {
    const double th = M_PI * i / n, ph = 2 * M_PI * j / n;
    if (i == 0) return c + Vec3{0, 0, r};
    if (i == n) return c - Vec3{0, 0, r};
    return c + Vec3{r * std::sin(th) * std::cos(ph), r * std::sin(th) * std::sin(ph), r * std::cos(th)};
  };
  std::vector<Tri> t;
  for (int j = 0; j < n; ++j) {
    t.push_back({P(0, j), P(1, j), P(1, j + 1)});
    for (int i = 1; i < n - 1; ++i) quad(t, P(i, j), P(i + 1, j), P(i + 1, j + 1), P(i, j + 1));
    t.push_back({P(n - 1, j), P(n, j), P(n - 1, j + 1)});
  }
  return t;
}

// A square plate L x L x th with a centred through hole, a regular n-gon of radius r
// (n a multiple of 8, so that the square's corners lie at the polygon's angles): the
// ring between the polygon and its radial projection onto the square, top and bottom,
// and the outer and inner walls. Volume th (L^2 - n r^2 sin(2 pi / n) / 2).
std::vector<Tri> holed_plate(double L, double th, double r, int n) {
  std::vector<Vec3> in, out;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n;
    const Vec3 d{std::cos(a), std::sin(a), 0};
    in.push_back(Vec3{L / 2, L / 2, 0} + d * r);
    const double s = (L / 2) / std::max(std::abs(d.x), std::abs(d.y));
    Vec3 o = Vec3{L / 2, L / 2, 0} + d * s;
    o.x = std::abs(o.x - L) < 1e-12 * L ? L : (std::abs(o.x) < 1e-12 * L ? 0 : o.x);
    o.y = std::abs(o.y - L) < 1e-12 * L ? L : (std::abs(o.y) < 1e-12 * L ? 0 : o.y);
    out.push_back(o);
  }
  const Vec3 up{0, 0, th};
  std::vector<Tri> t;
  for (int i = 0; i < n; ++i) {
    const int k = (i + 1) % n;
    quad(t, in[i] + up, out[i] + up, out[k] + up, in[k] + up);  // top
    quad(t, in[i], in[k], out[k], out[i]);                      // bottom
    quad(t, out[i], out[k], out[k] + up, out[i] + up);          // outer wall
    quad(t, in[i], in[i] + up, in[k] + up, in[k]);              // hole wall
  }
  return t;
}

double volume_of(const std::vector<Tri>& t) {
  double v = 0;
  for (const auto& x : t) v += dot(x[0], cross(x[1], x[2]));
  return std::abs(v) / 6;
}
double area_of(const std::vector<Tri>& t) {
  double a = 0;
  for (const auto& x : t) a += 0.5 * norm(cross(x[1] - x[0], x[2] - x[0]));
  return a;
}

// Generalized winding number of the triangles at p (Jacobson et al. 2013, eq. 2; solid
// angles by Van Oosterom and Strackee 1983): +-1 inside a closed surface (the sign is
// its orientation's), 0 outside.
double winding_number(const std::vector<Tri>& tris, const Vec3& p) {
  double w = 0;
  for (const auto& t : tris) {
    const Vec3 a = t[0] - p, b = t[1] - p, c = t[2] - p;
    const double la = norm(a), lb = norm(b), lc = norm(c);
    const double det = dot(a, cross(b, c));
    const double den = la * lb * lc + dot(a, b) * lc + dot(b, c) * la + dot(c, a) * lb;
    w += 2 * std::atan2(det, den);
  }
  return w / (4 * M_PI);
}

std::size_t fill_count(const Shape& s, double h, std::vector<Vec3>* at = nullptr) {
  Particles p;
  LatticeSpec spec;
  spec.spacing = h;
  spec.cell_volume = h * h * h;
  const std::size_t n = fill_shape(p, s, spec, 1000, 0, 0);
  if (at) *at = p.X;
  return n;
}

// ASCII and binary files of one cube (10 mm, in millimetres, scale 0.001) read to the
// same surface and the same particles: 10^3 of them at the cells' centres.
TEST(SurfaceFill, CubeAsciiAndBinary) {
  const auto dir = output_dir("surface_cube");
  const auto tris = cube({0, 0, 0}, {10, 10, 10});
  write_stl(tris, (dir / "cube.stl").string(), false);
  write_stl(tris, (dir / "cube_bin.stl").string(), true);
  const auto ascii = std::make_shared<const ClosedSurface>(read_surface((dir / "cube.stl").string(), 1e-3));
  const auto binary = std::make_shared<const ClosedSurface>(read_surface((dir / "cube_bin.stl").string(), 1e-3));
  EXPECT_EQ(ascii->triangle_count(), 12u);
  EXPECT_EQ(binary->triangle_count(), 12u);
  EXPECT_NEAR(ascii->volume(), 1e-6, 1e-18);
  EXPECT_EQ(ascii->volume(), binary->volume());
  EXPECT_EQ(norm(ascii->min() - binary->min()) + norm(ascii->max() - binary->max()), 0.0);
  std::vector<Vec3> xa, xb;
  EXPECT_EQ(fill_count(Shape::surface(ascii), 1e-3, &xa), 1000u);
  EXPECT_EQ(fill_count(Shape::surface(binary), 1e-3, &xb), 1000u);
  ASSERT_EQ(xa.size(), xb.size());
  for (std::size_t i = 0; i < xa.size(); ++i) EXPECT_EQ(norm(xa[i] - xb[i]), 0.0);

  // On a face, an edge or a corner: inside; a hair outside: outside. Rays through the
  // faces' diagonal edges and through corners count once.
  const ClosedSurface& s = *ascii;
  const double mm = 1e-3, hair = 1e-9;
  for (const Vec3& p : {Vec3{5, 5, 10}, Vec3{0, 5, 5}, Vec3{10, 3, 7}, Vec3{10, 10, 4}, Vec3{0, 0, 0}, Vec3{10, 10, 10},
                        Vec3{3, 3, 10}, Vec3{2, 0, 2}})
    EXPECT_TRUE(s.contains(p * mm)) << p.x << " " << p.y << " " << p.z;
  for (const Vec3& p : {Vec3{5, 5, 10 + hair}, Vec3{-hair, 5, 5}, Vec3{10 + hair, 10, 4}, Vec3{5, 5, -1},
                        Vec3{0, 0, -1}, Vec3{10, 10, 11}, Vec3{3, 3, 12}, Vec3{0, 10, -3}})
    EXPECT_FALSE(s.contains(p * mm)) << p.x << " " << p.y << " " << p.z;
  for (const Vec3& p : {Vec3{3, 3, 5}, Vec3{7, 7, 1}, Vec3{5, 5, 5}, Vec3{1e-6, 1e-6, 5}, Vec3{9.999999, 9.999999, 5}})
    EXPECT_TRUE(s.contains(p * mm)) << p.x << " " << p.y << " " << p.z;
  EXPECT_FALSE(s.contains({std::nan(""), 5 * mm, 5 * mm}));

  // A flat "solid" (one triangle twice, back to back: every edge used twice) holds no
  // volume: only its own points are inside, and its grids stay small.
  const ClosedSurface flat({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}, {0, 2, 1}}, "flat");
  EXPECT_EQ(flat.volume(), 0.0);
  EXPECT_TRUE(flat.contains({0.25, 0.25, 0}));
  EXPECT_FALSE(flat.contains({0.25, 0.25, 1e-9}));
}

// The sphere (1984 triangles) and the holed plate fill to their volume within one layer;
// every lattice point's verdict agrees with the winding number's, and so do points
// straight under the sphere's vertices (their rays pass through the vertex fans).
TEST(SurfaceFill, SphereAndHoledPlateWithinOneLayer) {
  const auto dir = output_dir("surface_fill");
  struct Case {
    const char* name;
    std::vector<Tri> tris;
    double h;
  };
  const double R = 10e-3;
  std::vector<Case> cases;
  cases.push_back({"sphere", sphere({0.1e-3, -0.2e-3, 0.05e-3}, R), 2 * R / 46});  // ~1e5 box points
  cases.push_back({"holed_plate", holed_plate(20e-3, 3e-3, 5e-3, 48), 0.5e-3});
  for (auto& c : cases) {
    const std::string path = (dir / (std::string(c.name) + ".stl")).string();
    write_stl(c.tris, path, true);
    // The file holds float32 corners: compare against the polyhedron as stored.
    for (auto& t : c.tris)
      for (auto& v : t) v = {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)};
    const auto surface = std::make_shared<const ClosedSurface>(read_surface(path, 1.0));
    const double V = volume_of(c.tris), A = area_of(c.tris);
    EXPECT_NEAR(surface->volume() / V, 1.0, 1e-12) << c.name;
    std::vector<Vec3> at;
    const std::size_t n = fill_count(Shape::surface(surface), c.h, &at);
    const double filled = static_cast<double>(n) * c.h * c.h * c.h;
    report(std::string("surface_fill_") + c.name, std::abs(filled - V) / (A * c.h),
           fmt::format("{}: {} triangles, {} particles of spacing {:.3g} mm: filled volume {:+.2f} % of the solid's, "
                       "{:.3f} of one layer (area x spacing)",
                       c.name, surface->triangle_count(), n, c.h * 1e3, 100 * (filled / V - 1),
                       std::abs(filled - V) / (A * c.h)));
    EXPECT_LE(std::abs(filled - V), A * c.h) << c.name;
    // The verdicts against the winding number: every filled point has w = 1, and a sample
    // of the box's lattice points off the surface agree.
    std::size_t disagree = 0;
    for (std::size_t i = 0; i < at.size(); i += 7) disagree += std::abs(std::abs(winding_number(c.tris, at[i])) - 1) > 1e-6;
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(0, 1);
    for (int k = 0; k < 2000; ++k) {
      Vec3 p;
      for (int a = 0; a < 3; ++a) p[a] = surface->min()[a] + (surface->max()[a] - surface->min()[a]) * (1.2 * u(rng) - 0.1);
      const double w = winding_number(c.tris, p);
      if (std::abs(w - std::round(w)) > 1e-6) continue;  // on the surface
      disagree += surface->contains(p) != (std::abs(std::round(w)) == 1);
    }
    EXPECT_EQ(disagree, 0u) << c.name;
  }
  // Straight under each vertex of the sphere's upper half, a tenth of the radius down.
  const auto& s = cases[0].tris;
  const auto surface = std::make_shared<const ClosedSurface>(read_surface((dir / "sphere.stl").string(), 1.0));
  std::size_t checked = 0;
  for (const auto& t : s)
    for (const auto& v : t) {
      const Vec3 p = v - Vec3{0, 0, 0.1 * R};
      if (v.z <= 0.3 * R) continue;
      EXPECT_EQ(surface->contains(p), std::abs(std::round(winding_number(s, p))) == 1);
      ++checked;
    }
  EXPECT_GT(checked, 100u);
}

std::string deck_with(const std::string& shape) {
  return "dimension: 3\nspacing: 1.0e-3\nhorizon: 3.0e-3\n"
         "materials:\n  steel: {model: pmb, density: 8000, youngs_modulus: 200.0e9}\n"
         "bodies:\n  - {name: part, material: steel, shape: " + shape + "}\n"
         "solver: {end_time: 1.0e-6}\n";
}

// Through the deck: the path relative to the deck's folder, the scale; an open surface,
// one passing through itself, a missing file and a 2-D deck are refused at the
// `surface` key's line and column.
TEST(SurfaceFill, DeckKeysAndErrors) {
  const auto dir = output_dir("surface_deck");
  std::filesystem::create_directories(dir / "parts");
  const std::string deck = (dir / "deck.yaml").string();
  auto tris = cube({0, 0, 0}, {10, 10, 10});
  write_stl(tris, (dir / "parts" / "cube.stl").string(), false);
  const Config config = parse_deck(deck_with("{surface: parts/cube.stl, scale: 0.001}"), deck);
  const System system = build_system(config);
  EXPECT_EQ(system.particles.size(), 1000u);

  auto error_of = [&](const std::string& shape) -> std::string {
    try {
      parse_deck(deck_with(shape), deck);
    } catch (const Error& e) {
      return e.what();
    }
    return "no error";
  };
  // One triangle missing: its three edges are open; the message names the first.
  std::vector<Tri> open = tris;
  open.erase(open.begin() + 3);  // top face, triangle (0,0,10) (10,10,10) (0,10,10)
  write_stl(open, (dir / "parts" / "open.stl").string(), true);
  std::string msg = error_of("{surface: parts/open.stl, scale: 0.001}");
  EXPECT_NE(msg.find("deck.yaml:7:43: error: bodies[0].shape.surface: "), std::string::npos) << msg;
  EXPECT_NE(msg.find("open.stl: the surface is open: the edge from (0, 0, 10) to (0, 10, 10) belongs to 1 triangle "
                     "(3 edges belong to an odd number of triangles, coordinates in the file's units)"),
            std::string::npos)
      << msg;
  // Two overlapping cubes in one file: each is closed, together they cross.
  std::vector<Tri> two = tris;
  const auto other = cube({5, 5, 5}, {15, 15, 15});
  two.insert(two.end(), other.begin(), other.end());
  write_stl(two, (dir / "parts" / "two.stl").string(), false);
  msg = error_of("{surface: parts/two.stl}");
  EXPECT_NE(msg.find("deck.yaml:7:43: error:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("two.stl: the surface intersects itself: the edge from"), std::string::npos) << msg;
  msg = error_of("{surface: parts/none.stl}");
  EXPECT_NE(msg.find("deck.yaml:7:43: error:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("none.stl': No such file"), std::string::npos) << msg;
  msg = error_of("{surface: parts/cube.stl, colour: red}");
  EXPECT_NE(msg.find("a surface shape has the keys surface (the file) and scale; found 'colour'"), std::string::npos) << msg;
  msg = error_of("{surface: parts/cube.obj}");
  EXPECT_NE(msg.find("unknown extension '.obj'"), std::string::npos) << msg;
}

}  // namespace
}  // namespace horizon::verification
