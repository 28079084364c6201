#pragma once
// The shear correction factor of the ordinary state-based solids (lps, elastic_plastic;
// Peridigm's "Apply Shear Correction Factor"): a per-particle factor s_i on the deviatoric
// modulus, alpha_i = s_i alpha, that makes a particle with a truncated family store the
// continuum's deviatoric energy mu eps:eps under a homogeneous shear, as a particle with a
// whole family does. docs/models.md "Shear correction factor" has the derivation; in short:
//
// The LPS's deviatoric energy density (Silling et al. 2007 eq. 93; Mitchell SAND2011-3166)
// is W_d = (alpha/2) sum_j omega V_j (e^d_j)^2 with alpha = 15 mu/m_i (3-D), e^d = e -
// theta |xi|/d. Under a small homogeneous strain E (traceless), e_j = xi.E.xi/|xi| and
// theta = (d/m) E:S with S = sum_j omega V_j xi (x) xi, m = tr S. Summed over an
// orthonormal basis E_a of the traceless symmetric tensors (the pure shears in the
// coordinate planes and the in-plane normal shears: every orientation of shear at once),
//   sum_a sum_j omega V (e^d_j(E_a))^2 = (1 - 1/d) m - |dev S|^2 / m,
// since sum_a (n.E_a.n)^2 = |n (x) n - I/d|^2 = 1 - 1/d for a unit n. The continuum's
// value, and that of any family with an isotropic S (a whole family on a cubic lattice),
// is (1 - 1/d) m; the factor is their ratio,
//   s_i = 1 / (1 - |dev S_i|^2 / ((1 - 1/d) m_i^2)),
// so that the particle's deviatoric energy, averaged over the orientations of a shear,
// is mu eps:eps. It depends on the family through S alone, is 1 for an isotropic S and
// the same for a family and the family rotated (SurfaceFactorCube's rotated block), and
// is at least 1 (a truncated family loses deviatoric stiffness to the dilatation it
// picks up under shear). Derived here: Peridigm's definition is in its code alone, not
// in its users' guide or a paper (docs/peridigm.md).
#include "horizon/material/surface_correction.hpp"

namespace horizon {

// Below this fraction of (1 - 1/d) m the family has no deviatoric stiffness to correct
// (all bonds collinear: e^d = 0 for every deformation, BondBreakingInitialVelocity-EP's
// one-bond families): the factor is 1 there, not the round-off's ratio.
constexpr double kShearCorrectionFloor = 1e-9;

// s_i of a family (bond vectors xi, weights omega V) in `dimension` (2 or 3; in 2-D S is
// the in-plane 2 x 2 tensor). 1 for a family without bonds or without deviatoric stiffness.
double shear_correction_factor(const FamilyView& family, int dimension);

}  // namespace horizon
