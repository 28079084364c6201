#pragma once
// Strain and stress per particle, for output (pictures, stress concentrations): the
// nonlocal deformation gradient of Silling et al. 2007 (seed 003 eq. 17, 19-20),
//   F_i = (sum_j omega V_j Y_ij (x) xi_ij) K_i^-1,   K_i = sum_j omega V_j xi_ij (x) xi_ij
// over the intact bonds, the small strain eps = (F + F^T)/2 - I, and Hooke's law with the
// material's E and nu (3-D; 2-D plane stress or plane strain; 1-D sigma = E eps). It is
// exact for homogeneous deformations (eq. 20) and smooths over a horizon otherwise. It
// is a post-processing measure: the forces never use it.
#include <array>
#include <vector>

#include "horizon/deck/config.hpp"
#include "horizon/state/system.hpp"

namespace horizon {

// Per particle: xx, yy, zz, xy, yz, xz. A particle whose intact bonds do not span the
// dimension (K singular) gets zeros.
using SymTensor = std::array<double, 6>;

std::vector<SymTensor> strain_field(const System& s);
std::vector<SymTensor> stress_field(const System& s, const std::vector<MaterialConfig>& materials, PlaneMode plane);
double von_mises(const SymTensor& sigma);

}  // namespace horizon
