#pragma once
// Proportional microplastic bonds (seed 002, Macek and Silling, sec. 2.2, eq. 19-21): a
// bond-based material whose bonds are elastic-perfectly plastic springs,
//   f = c (s - sbar),  d sbar/dt = ds/dt while |s - sbar| = s_Y (at yield), else 0,
// with the same yield stretch s_Y in tension and compression, so that -c s_Y <= f <= c s_Y
// (the seed's Fig. 2; eq. 21 as printed has the yield condition inverted, digest sec. 13:
// the plastic stretch changes only at yield). c is the PMB micromodulus of the same
// Young's modulus (material/constants.hpp); bonds break at a critical stretch on the
// total stretch s. The seed suggests s_Y = sigma_ut/(2E) (eq. 50) from the ultimate
// tensile stress, since bonds of different orientations yield at different loads.
// Force state of bond i->j: T = omega (c/2) (s - sbar) Y/|Y|, so that (T_ij - T_ji) V_j is
// the pair force omega c (s - sbar) V_j along the bond (as PMB's t = c s/2). The plastic
// stretch is kept per directed bond; both copies of a bond see the same stretch bit for
// bit and so carry the same history. docs/models/microplastic.md.
#include "horizon/kernels/microplastic.hpp"
#include "horizon/material/model.hpp"

namespace horizon {

// The return map of one bond and the critical stretch equivalent to a PMB bond's
// (kernels/microplastic.hpp has both, with their derivations).
using kernels::microplastic_critical_stretch;
using kernels::microplastic_return;

ModelEntry microplastic_model();

}  // namespace horizon
