#pragma once
// A closed triangulated surface as a solid: the body of `shape: {surface: part.stl}`
// (docs/input.md, "Shapes"). The inside test is ray parity: a point is inside when a ray
// from it along +z crosses the surface an odd number of times (the Jordan-Brouwer
// separation theorem), made exact for rays through edges and vertices by a tie rule
// (below), and points on the surface count as inside, as they do for the primitives.
//
// Tie rule (edges and vertices in the ray's path). In the xy-projection each triangle
// tests its three edges; an edge's orientation function is always evaluated with its
// end points in one canonical order (lexicographic in x, y), so the two triangles of an
// edge compute it bit for bit alike. A point on an edge's line belongs to the triangle
// whose interior lies on the line's positive side. This is the outcome of moving the
// point by (-e^2, e) for an infinitesimal e -- one perturbation for every triangle
// (symbolic perturbation, Edelsbrunner and Muecke, "Simulation of Simplicity", ACM TOG
// 9(1), 1990) -- so the count is that of a ray through no edge and no vertex: exactly one
// of two triangles meeting at an edge counts it, one of a fan around a vertex, and a
// silhouette edge (the surface folding back) counts twice or not at all. The same rule
// as the top-left fill convention of rasterizers (Pineda, "A parallel algorithm for
// polygon rasterization", SIGGRAPH 1988).
//
// A surface is refused when it is open (an edge used by an odd number of triangles:
// parity needs every edge used an even number of times) or when an edge passes through
// a triangle that shares no corner with it -- its inside, an edge or a corner, the edge's
// ends strictly on the two sides of its plane (the surface crosses itself; coplanar
// overlaps, a corner lying on another triangle and crossings at shared corners go
// unseen).
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "horizon/core/error.hpp"
#include "horizon/core/vec3.hpp"

namespace horizon {

struct Box3;

// A surface file that cannot be used; the message names the file and the place (an
// open edge's or a crossing's coordinates, in the file's units).
class SurfaceError : public Error {
 public:
  using Error::Error;
};

class ClosedSurface {
 public:
  // `file` names the surface in messages; `scale` multiplied the file's coordinates
  // into `vertices` (messages divide it out again).
  ClosedSurface(std::vector<Vec3> vertices, const std::vector<std::array<uint32_t, 3>>& triangles,
                std::string file, double scale = 1);

  bool contains(const Vec3& p) const;
  Vec3 min() const { return lo_; }
  Vec3 max() const { return hi_; }
  // The enclosed volume (divergence theorem over the triangles; orientation-free for a
  // single shell: |sum of signed tetrahedra|) and the area.
  double volume() const;
  double area() const;
  std::size_t triangle_count() const { return tri_.size(); }

 private:
  void check_closed() const;
  void check_self_intersection() const;
  std::string where(const Vec3& x) const;

  std::string file_;
  double scale_ = 1;
  std::vector<Vec3> v_;
  std::vector<std::array<uint32_t, 3>> tri_;
  Vec3 lo_, hi_;
  double tol_ = 0;  // on the surface: closer than this
  // Triangles by xy cell (their projected bounding box, widened by tol_).
  int nx_ = 1, ny_ = 1;
  double cx_ = 1, cy_ = 1;
  std::vector<uint32_t> cell_start_, cell_tri_;
};

// Reads a triangulated surface through the Gmsh library: STL (ASCII or binary), PLY
// (ASCII) and .msh (its triangles and quadrangles). Quadrangles are split in two, higher-order triangles
// taken by their corners; vertices at the same coordinates are one vertex.
ClosedSurface read_surface(const std::string& path, double scale);

}  // namespace horizon
