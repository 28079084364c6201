#pragma once
// The linearised LPS (Peridigm's "Linear LPS Partial Volume"): the linear peridynamic
// solid of Silling et al. 2007 sec. 15 (seed 003 eq. 104-113) linearised about the
// reference configuration (S. A. Silling, "Linearized theory of peridynamic states",
// J. Elasticity 99:85-111, 2010): the extension of a bond is the displacement difference
// along the reference bond, and the force state lies along the reference bond,
//   e = eta . xi/|xi|,  eta = u_j - u_i,        theta = (d/m) sum_j omega |xi| e V_j,
//   t = (d k' theta/m) omega |xi| + alpha omega (e - theta |xi|/d),   T = t xi/|xi|,
//   W = k' theta^2/2 + (alpha/2) sum_j omega (e - theta |xi|/d)^2 V_j,
// with the LPS constants k', alpha = 15 mu/m (3-D; 8 mu/m in 2-D) of material/constants.hpp.
// The forces are linear in the displacements: under a uniform strain they differ from the
// LPS's by terms of the strain's square (LinearLPSBar's 10 % strain: 3.5 % of the force).
// Checked against Peridigm's LinearLPSBar gold to 1e-14 relative (docs/peridigm.md).
#include "horizon/material/model.hpp"

namespace horizon {

ModelEntry linear_lps_model();

}  // namespace horizon
