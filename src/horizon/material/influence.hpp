#pragma once
// Influence functions omega(|xi|) (Silling et al. 2007, seed 003 eq. 82 and sec. 15;
// the forms are those of Seleson and Parks 2011 / Peridigm's influence functions).
#include <algorithm>
#include <cmath>

#include "horizon/deck/config.hpp"

namespace horizon {

inline double influence(InfluenceKind kind, double r, double horizon) {
  switch (kind) {
    case InfluenceKind::constant: return 1.0;
    case InfluenceKind::inverse: return horizon / r;                 // delta/|xi|
    case InfluenceKind::inverse_length: return 1.0 / r;              // 1/|xi| (Peridigm's "1.0/zeta")
    // Clamped at 0: with partial volumes, families reach horizon + spacing/2 and a
    // negative weight would subtract those bonds from m and from the force.
    case InfluenceKind::linear: return std::max(0.0, 1.0 - r / horizon);  // 1 - |xi|/delta
    case InfluenceKind::gaussian: return std::exp(-(r * r) / (horizon * horizon));
    // The shape of (6.6)/(6.7), (3r + delta)(delta - r)^3/delta^4; the nonlinear solid
    // multiplies in the normalisation of its dimension (material/models/nonlinear_solid.hpp).
    case InfluenceKind::tupek: {
      const double d = std::max(0.0, horizon - r);
      return (3 * r + horizon) * d * d * d / (horizon * horizon * horizon * horizon);
    }
  }
  return 1.0;
}

// Radial moment  int_0^delta omega(r) r^p dr  by composite Gauss-Legendre quadrature
// (64 panels x 5 points: exact to round-off for the polynomial forms and far below
// the lattice error for the Gaussian).
double influence_moment(InfluenceKind kind, double horizon, int p);

}  // namespace horizon
