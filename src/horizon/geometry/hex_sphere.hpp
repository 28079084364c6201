#pragma once
// The part of a trilinear hexahedron inside a sphere, as Peridigm's element-horizon
// intersections count it (its Discretization's `Compute Element-Horizon Intersections`,
// `Element-Horizon Intersection Recursion Level` L and `... Number Of Samples` n: each
// neighbour's volume cut by the horizon sphere). Peridigm documents neither rule; both
// were fitted to the NeighborhoodVolume gold (docs/peridigm.md, "Element-horizon
// intersections"), where they give every Neighborhood_Volume of its 580 hexahedra to 1e-16
// and every Number_Of_Neighbors exactly:
//
//   volume(P, level): P's 8 corners all inside the sphere (|x - c| <= r): P's volume
//     (the trilinear map's, 2 x 2 x 2 Gauss points); at level == L: the sum over the
//     n^3 parametric cell centres xi_k = -1 + (2k + 1)/n inside the sphere of
//     det J(xi_k) (2/n)^3 (the midpoint rule on P's own map); else the sum over P's
//     8 children (the parametric bisection of P) at level + 1. Starts at level 0.
//   meets(P): the sphere meets the element itself (min over xi of |x(xi) - c| <= r),
//     whether or not a sample falls inside: the gold counts, among its neighbours,
//     elements the sphere grazes whose sampled volume is 0, and leaves out elements
//     whose convex hull it meets but not the (curved-faced) element.
//
// A hexahedron is given by its 8 corners in Exodus order (bottom face 0-3, top 4-7, both
// counter-clockwise seen from above), its parametric cube [-1, 1]^3.
#include <array>

#include "horizon/core/vec3.hpp"

namespace horizon {

using Hex8 = std::array<Vec3, 8>;

// The trilinear map's volume: 2 x 2 x 2 Gauss points (exact for it).
double hex8_volume(const Hex8& p);

// Peridigm's sampled volume of p inside the sphere (centre, radius) with recursion level
// `levels` >= 0 and `samples` >= 1 per axis (above).
double hex_sphere_volume(const Hex8& p, const Vec3& centre, double radius, int levels, int samples);

// Whether the sphere meets the element: a corner inside, else a branch and bound over
// parametric boxes (the trilinear image of a box lies in its corners' convex hull, so in
// their bounding box) down to boxes 2^-kHexSphereDepth of the element, where the bound
// decides: exact but for spheres that miss the element by less than about that fraction
// of its size.
constexpr int kHexSphereDepth = 12;
bool hex_meets_sphere(const Hex8& p, const Vec3& centre, double radius);

}  // namespace horizon
