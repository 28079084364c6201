#pragma once
// q = t/|Y| of a row's bonds for the ordinary models' rows (Model::force_row of the scalar
// general pass, solver/forces_ordinary.cpp), after the row's sums: the division of every
// bond in one loop apart from the sums' branches, vectorised for the machine (AVX-512,
// AVX2 or the build's SSE, chosen once at run time, as the fast loops are:
// solver/forces.cpp). A lane divides as the scalar code does (IEEE division), so every
// target gives the same bits as `t / r` bond by bond.
#include <cstdint>

namespace horizon::rows {

// q[k] = acts ? t[k] / r[k] : 0 for k in [first, last), acts = intact[k] != 0 (and r[k] > 0
// when `positive`).
void force_scalars(const double* t, const double* r, const uint8_t* intact, bool positive, uint64_t first,
                   uint64_t last, double* q);

}  // namespace horizon::rows
