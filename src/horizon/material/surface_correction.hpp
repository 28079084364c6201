#pragma once
// Surface correction by the energy method (Madenci and Oterkus 2014, "Peridynamic Theory
// and Its Applications", sec. 4.2; compared with the other corrections by Le and Bobaru
// 2018, "Surface corrections for peridynamic models in elasticity and fracture", Comput.
// Mech. 61:499-518): a particle near a free surface has a truncated family and stores
// less (PMB) or more (LPS) energy under a uniform strain than an interior particle of the
// same lattice. For each axis d a model-given measure W of a uniform deformation along d
// (the PMB: its energy under a uniaxial stress; the LPS: its dilatation) gives a factor
// per particle,
//   G_i^d = W_inf^d / W_i^d,
// a bond takes the mean of its ends per axis and the ellipse rule between the axes along
// its direction n (Madenci and Oterkus sec. 4.2),
//   g_ij = [ (n_x/G_x)^2 + (n_y/G_y)^2 + (n_z/G_z)^2 ]^(-1/2),   G_d = (G_i^d + G_j^d)/2,
// and the bond's influence weight omega_ij becomes omega_ij g_ij (symmetric: g_ij = g_ji).
// Scaling the weight leaves the force loops as they are: a bond kind's weight is read
// once per kind (family/bonds.hpp), so the bonds are regrouped into kinds by weight.
// docs/models.md "Surface correction".
#include <functional>
#include <utility>
#include <vector>

#include "horizon/core/vec3.hpp"
#include "horizon/material/model.hpp"

namespace horizon {

// A particle's family as the correction sees it: bond vectors xi and omega V_j (partial
// volumes and the current weights included).
struct FamilyView {
  std::vector<Vec3> xi;
  std::vector<double> wv;
};

// The model's measure (any constant factor) of a family under a uniform deformation of
// unit size along `axis` (0, 1, 2): an energy density, or the LPS's dilatation.
using AxisEnergy = std::function<double(const FamilyView& family, int axis)>;

// The family of an interior particle of a lattice with the deck's spacing, family radius,
// partial-volume rule and the material's influence function (the reference "inf": the
// lattice's own discretisation error cancels in the ratio, seed 002 digest sec. 4).
FamilyView interior_family(const Config& cfg, const MaterialConfig& mat);

// The continuum family of the same horizon and influence function: a lattice of
// kContinuumCells cells per horizon (the quadrature of the integrals that calibrate the
// material constants, to about 1e-3).
constexpr int kContinuumCells = 24;
FamilyView continuum_family(const Config& cfg, const MaterialConfig& mat);

// What W_inf is taken from: an interior particle of the deck's lattice (the seed's choice:
// the lattice's own discretisation error stays), or the continuum (that error is
// corrected too, in the interior as at the surfaces).
enum class Reference { lattice, continuum };

// Fixed-point passes of axis_factors the models use: measured on the thin PMB plate and
// the LPS bar section (docs/verification.md), more passes change the result by < 0.2 %.
constexpr int kSurfacePasses = 10;

// Particle i's family with its bonds' current weights.
FamilyView family_of(const System& s, uint32_t i);

// The factors G_i^d = W_inf^d / W_i^d of the particles of `in` (1 on axes beyond the
// deck's dimension and for particles without bonds). With iterations > 1 the measure is
// taken again with the bond factors of the previous pass and the factors multiplied by
// the new ratios (a fixed-point iteration towards W_i^d = W_inf^d, as far as the ellipse
// rule allows).
std::vector<Vec3> axis_factors(const ModelSetup& in, const AxisEnergy& energy, int iterations = 1,
                               Reference reference = Reference::lattice);

// Multiplies omega_ij of every bond whose two ends are particles of `in` by the ellipse
// rule's g_ij of their factors, regroups the bond kinds by weight, and recomputes the
// weighted volume m of those particles. Bonds to other materials keep their weight.
// Returns the range [min, max] of g over the bonds scaled.
std::pair<double, double> apply_axis_factors(const ModelSetup& in, const std::vector<Vec3>& factor);

}  // namespace horizon
