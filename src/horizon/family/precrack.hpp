#pragma once
// Precracks: a bond whose reference segment X_i -> X_j crosses a precrack is removed
// from both families before the run (a bond filter, as in Peridigm), so the crack
// faces carry no force and the weighted volumes see the cut.
#include <utility>
#include <vector>

#include "horizon/core/vec3.hpp"
#include "horizon/family/bonds.hpp"

namespace horizon {

struct Precrack {
  std::vector<Vec3> points;  // 2-D: a segment (2 points, in x-y); 3-D: a planar polygon, or a disk's centre
  // 3-D disk (radius > 0): the points of the plane through points[0] normal to `normal`
  // (a unit vector) within `radius` of points[0] (Peridigm's Disk bond filter).
  double radius = 0;
  Vec3 normal{};
  // 3-D surface (facets not empty): planar polygons, e.g. the elements of a shell mesh
  // (Peridigm's Exodus Mesh bond filter); a bond crosses the surface when it crosses any
  // facet. `boxes` holds each facet's bounding box (lo, hi), filled by set_facets.
  std::vector<std::vector<Vec3>> facets{};
  std::vector<std::pair<Vec3, Vec3>> boxes{};
  // false: crossing bonds are removed (the default). true: they stay in the families as
  // broken bonds (intact = 0), which the nonlinear solid lets push in compression
  // (Tupek eq. 6.9): a pre-fractured interface that still resists interpenetration
  // (the Riemann problem, thesis sec. 5.3). Other models never load broken bonds.
  bool keep_broken = false;
  // 3-D rectangle stated as Peridigm's Rectangular_Plane bond filter states it (rectangle
  // true): `normal` (unit), the lower left corner, the bottom vector as given (Peridigm does
  // not normalise it: PrecrackedPlateTwoCracks gives (1, 4, 0) with the normal (0, 1, 0)),
  // and the bottom and side lengths; the side runs along bottom x normal. `points` holds
  // the corners of the region it tests (for the bounding box). crosses_rectangle.
  bool rectangle = false;
  Vec3 corner{}, bottom{};
  double bottom_length = 0, side_length = 0;
};

// Peridigm's Rectangular_Plane test of the bond from a to b (its users' guide and its
// FinitePlane filter, read for the rule; its tolerances are part of it): the segment meets
// the plane through the corner at t = ((corner - a).n)/((b - a).n), in [0, 1] (a segment
// with |(b - a).n| < 1e-14 meets nothing), at x = a + t (b - a); with d = x - corner, s =
// bottom x normal, it crosses when -1e-15 < d.s, d.s/side_length < 1 + 1e-15, -1e-15 < d.bottom
// and d.bottom/bottom_length < 1 + 1e-15. The rounding is Peridigm's: with its element
// centres, PrecrackedPlate's and PrecrackedPlateTwoCracks's golds' neighbour counts at every
// point (the bottom (1, 4, 0) weighs the rounding of x.y by 4 at the edge x = 0).
bool crosses_rectangle(const Vec3& a, const Vec3& b, const Precrack& crack);

// Sets a surface precrack's facets and their bounding boxes.
void set_facets(Precrack& crack, std::vector<std::vector<Vec3>> facets);

// The crack's bounding box: its points, the disk's square about its centre, or every
// facet's corners.
void bounding_box(const Precrack& crack, Vec3& lo, Vec3& hi);

// True when the open segment a-b crosses the crack. In 2-D the two segments must
// properly intersect: a and b strictly on opposite sides of the crack line, and the
// crack's ends on opposite sides of (or on) the bond line. In 3-D a and b lie strictly
// on opposite sides of the polygon's plane and the crossing point is inside the polygon.
bool crosses(const Vec3& a, const Vec3& b, const Precrack& crack, int dimension);

// Removes every bond that crosses a crack (or marks it broken when every crack it
// crosses has keep_broken); returns the number of directed bonds cut either way.
std::size_t cut_bonds(Bonds& bonds, const std::vector<Vec3>& X, const std::vector<Precrack>& cracks, int dimension);

}  // namespace horizon
