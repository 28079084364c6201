#pragma once
// Precracks: a bond whose reference segment X_i -> X_j crosses a precrack is removed
// from both families before the run (a bond filter, as in Peridigm), so the crack
// faces carry no force and the weighted volumes see the cut.
#include <vector>

#include "horizon/core/vec3.hpp"
#include "horizon/family/bonds.hpp"

namespace horizon {

struct Precrack {
  std::vector<Vec3> points;  // 2-D: a segment (2 points, in x-y); 3-D: a planar polygon
  // false: crossing bonds are removed (the default). true: they stay in the families as
  // broken bonds (intact = 0), which the nonlinear solid lets push in compression
  // (Tupek eq. 6.9): a pre-fractured interface that still resists interpenetration
  // (the Riemann problem, thesis sec. 5.3). Other models never load broken bonds.
  bool keep_broken = false;
};

// True when the open segment a-b crosses the crack. In 2-D the two segments must
// properly intersect: a and b strictly on opposite sides of the crack line, and the
// crack's ends on opposite sides of (or on) the bond line. In 3-D a and b lie strictly
// on opposite sides of the polygon's plane and the crossing point is inside the polygon.
bool crosses(const Vec3& a, const Vec3& b, const Precrack& crack, int dimension);

// Removes every bond that crosses a crack (or marks it broken when every crack it
// crosses has keep_broken); returns the number of directed bonds cut either way.
std::size_t cut_bonds(Bonds& bonds, const std::vector<Vec3>& X, const std::vector<Precrack>& cracks, int dimension);

}  // namespace horizon
