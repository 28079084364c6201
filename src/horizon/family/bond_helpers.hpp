#pragma once
// Helpers over the bond rows (family/bonds.hpp) that the force passes, the tangent and
// the writers share.
#include <cstdint>
#include <vector>

#include "horizon/family/bonds.hpp"

namespace horizon {

// Index of bond j->i for every bond i->j (rows are sorted by neighbour). `partial`: rows
// another MPI rank holds are empty here (local rows, parallel/decomposition.hpp); a bond
// into such a row gets itself as its reverse (its row is never summed on this rank).
std::vector<uint64_t> reverse_bonds(const Bonds& B, bool partial = false);

}  // namespace horizon
