#pragma once
// The linear peridynamic solid (LPS; Silling et al. 2007, seed 003 eq. 112-113; 2-D
// constants of digest sec. 8): t = (d k' theta/m) omega |xi| + (alpha mu/m) omega e^d,
// breaking at a critical stretch. docs/models/lps.md.
#include "horizon/material/model.hpp"

namespace horizon {

ModelEntry lps_model();

}  // namespace horizon
