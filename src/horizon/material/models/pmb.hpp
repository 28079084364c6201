#pragma once
// The prototype microelastic brittle material (PMB; Silling and Askari 2005; seed 002
// eq. 22): t_ij = c s_ij / 2 along the deformed bond, c from Young's modulus
// (material/constants.hpp), breaking at a critical stretch. docs/models/pmb.md.
#include "horizon/material/model.hpp"

namespace horizon {

ModelEntry pmb_model();

}  // namespace horizon
