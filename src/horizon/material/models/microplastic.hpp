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
#include "horizon/material/model.hpp"

namespace horizon {

// The return map of one bond (digest 002 sec. 2.2): r = s - sbar_old; if |r| > s_Y,
// sbar = s - sign(r) s_Y. Returns the new plastic stretch; the force is c (s - sbar).
inline double microplastic_return(double s, double sbar_old, double yield_stretch) {
  const double r = s - sbar_old;
  if (r > yield_stretch) return s - yield_stretch;
  if (r < -yield_stretch) return s + yield_stretch;
  return sbar_old;
}

// The critical stretch s0 of a microplastic bond that takes the same work to break as a
// PMB bond breaking at s_e (from the fracture energy): the work per bond is c |xi| s0^2/2
// elastic, and c |xi| (s_Y s0 - s_Y^2/2) with yield, monotonic loading (seed eq. 26; the
// integral of eq. 27-28 over the bonds crossing a plane is the same, so only the stretch
// function changes): s0 = (s_e^2 + s_Y^2)/(2 s_Y) when s_e > s_Y, else s_e.
inline double microplastic_critical_stretch(double elastic_equivalent, double yield_stretch) {
  if (elastic_equivalent <= yield_stretch) return elastic_equivalent;
  return (elastic_equivalent * elastic_equivalent + yield_stretch * yield_stretch) / (2 * yield_stretch);
}

ModelEntry microplastic_model();

}  // namespace horizon
