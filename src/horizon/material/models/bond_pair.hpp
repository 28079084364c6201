#pragma once
// O'Grady's bond-pair model of beams, plates and flat shells (seed 001: J. O'Grady,
// "Peridynamic beams, plates, and shells: a nonordinary, state-based model", PhD
// dissertation, UTSA 2014; digest ../shared/reference/notes/001_ogrady.md). Every bond xi
// of a node is paired with its opposite -xi; a rotational spring between the two resists
// the kink of the pair (bending). docs/models/bond_pair.md has the equations, the deck
// keys and the verification figures.
//
// Energy of one pair of node k, counted over both orientations of the family sum
// (digest sec. 0 item 2 and sec. 4.2: the force state is 2 x eq. (4.1)):
//   e = 2 omega alpha Vk Vj (1 + cos theta),  cos theta = Yhat<xi> . Yhat<-xi>   (eq. 3.1 / 4.1)
// with V the node's length (beam) or area (plate), alpha = EI/m (beam, eq. 4.4) or
// 2 G h^3 / (3 m) (plate, eq. 4.12), m = sum_j omega |xi|^2 V_j over a full family.
// The nodal forces are -de/dy of the three nodes of the pair, which is the consistent
// discretisation of digest sec. 4.2 (f_k = sum_j (T_k<xi_kj> - T_j<xi_jk>) V_j).
#include <algorithm>
#include <cmath>

#include "horizon/core/vec3.hpp"
#include "horizon/kernels/bond_pair.hpp"
#include "horizon/material/model.hpp"

namespace horizon {

// The pair algebra is kernels/bond_pair.hpp's (portable: the force pass calls it there);
// these are its forms over Vec3 for the tangent (stiffness) and the tests.

// d(1 + cos theta)/dY and d(1 + cos theta)/dY' of a pair with deformed bonds Y = y_j - y_k
// and Y' = y_j' - y_k: (Yhat' - cos theta Yhat)/|Y| (digest sec. 3.1, the second form of
// eq. 4.1, derived via a x (a x b) = (a.b) a - b), and the same with the roles swapped.
// Written with one square root and two divisions (the explicit pass is bound by their
// latency): with r = 1/(|Y||Y'|), cos theta = (Y.Y') r and
//   (Yhat' - cos theta Yhat)/|Y| = (Y' - (Y.Y'/|Y|^2) Y) r,   and symmetrically.
struct PairGradient {
  Vec3 dY, dYp;
  double one_plus_cos = 0;
};
inline PairGradient bond_pair_gradient(const Vec3& Y, const Vec3& Yp) {
  const kernels::BpGradient g = kernels::bp_gradient({Y.x, Y.y, Y.z}, {Yp.x, Yp.y, Yp.z});
  return {{g.dY.x, g.dY.y, g.dY.z}, {g.dYp.x, g.dYp.y, g.dYp.z}, g.one_plus_cos};
}

// A pair with a reference angle theta0 (a curved shell; the dissertation's ch. 6: "apply
// initial plastic deformations to all bond pairs that are not initially collinear"):
//   f = 1 - cos(theta - theta0) = 1 - c c0 - s s0,   c = cos theta, s = sin theta = sqrt(1 - c^2),
// zero at rest, invariant under rigid motions and uniform scaling, 1 + c for a straight
// pair (c0 = -1, s0 = 0). Returns f, f'(c) = -c0 + s0 c/s and f''(c) = s0/s^3 (s kept
// above 1e-9: the angle of a pair folded flat or pulled straight has no direction).
using ReferencedPair = kernels::BpReferenced;
inline ReferencedPair referenced_pair(double c, double c0, double s0) { return kernels::bp_referenced(c, c0, s0); }

// The signed kink of a pair in the transverse (z-only) mode: the deviation from straight
// Delta theta ~ (w_j + w_j' - 2 w_k)/|xi| (digest sec. 3.2, eqs. 4.2-4.3, and the recipe
// of sec. 3.5 for z-only beams and plates).
inline double signed_kink(double wj, double wjp, double wk, double length) {
  return kernels::bp_signed_kink(wj, wjp, wk, length);
}

// Elastic-perfectly-plastic return mapping of one pair (digest sec. 3.5 recipe, eq. 4.8):
// the trial elastic kink s - theta_p; beyond the critical kink theta_c the plastic offset
// grows so that the elastic part stays at +-theta_c. Returns the new plastic offset.
inline double plastic_offset(double s, double theta_p, double theta_c) {
  return kernels::bp_plastic_offset(s, theta_p, theta_c);
}

// The kink vector of a pair in a flat shell, in the pair's reference frame: the normal
// component n (along z, the plate's bending) and the in-plane component t (along
// z x xi/|xi|) of d = (u_j + u_j' - 2 u_k)/|xi|, the vector form of signed_kink. For a
// straight pair d = (Y + Y')/|xi| is zero under any rigid motion and any uniform stretch;
// its part along the pair (a difference of the two bonds' stretches, which leaves the
// angle unchanged) is dropped, so |(n, t)| is the kink angle Delta theta to first order.
using Kink = kernels::BpKink;

// The return mapping of plastic_offset for the kink vector (digest sec. 3.5 recipe with a
// circular yield surface |d - p| <= theta_c: the pair yields at the same kink whatever its
// plane, the isotropic choice; in 3-D the kink plane is not fixed, so the plastic offset is
// a vector): beyond theta_c the offset p moves along the trial elastic kink d - p (radial
// return) so that the elastic part stays on the circle. Returns the new offset.
inline Kink plastic_offset(const Kink& d, const Kink& p, double theta_c) { return kernels::bp_kink_offset(d, p, theta_c); }

// The critical kink of every pair: the longest pairs (|xi| = delta) reach it when the
// surface fibre (depth t) reaches the strain eps_c: Delta theta_c = 2 delta eps_c / t
// (digest sec. 3.5).
inline double critical_kink(double horizon, double strain, double depth) { return 2 * horizon * strain / depth; }

ModelEntry bond_pair_model();

}  // namespace horizon
