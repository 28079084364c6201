#pragma once
// The two bond sweeps of the affine general pass (solver/forces_affine.cpp) in the fast
// loops' lanes (solver/forces.cpp): bond k of a row goes to lane (k - row start) mod 8,
// each lane keeps its own partial sums (of K = sum w xi (x) xi and N = sum w Y (x) xi in
// the breaking sweep, of the pair form's three sums in the force sum), and the lanes are
// added as ((l0 + l1) + (l2 + l3)) + ((l4 + l5) + (l6 + l7)) at the end of
// the row. Two implementations follow this rule, chosen once per pass: AVX-512 (eight
// lanes in one register) and a portable one (eight scalar accumulators per sum), with the
// same IEEE operations in the same order, so the same bits on every machine and thread
// count (AVX2 machines take the portable rows: solver/affine_sweeps.cpp says why). The
// vector rows run the common case (no temperature-dependent critical stretch, no
// short-range contact between family pairs, bonds with kinds); the portable ones run all.
// A bond that breaks leaves the vector rows and is booked bond by bond in order, as
// forces_general.cpp books it.
#include <cstddef>
#include <cstdint>

#include "horizon/kernels/affine.hpp"
#include "horizon/state/system.hpp"

namespace horizon::affine_sweeps {

// What the sweep reads and writes, taken from the System once per pass, and what the
// breaking sweep leaves of a row (kernels/affine.hpp, where the portable rows live).
using Sweep = kernels::AffineSweep<KindCoefficients, BondKind>;
using BreakOut = kernels::AffineBreak;

// Row i: the critical-stretch breaking of its intact bonds, their smallest stretch, and
// over the bonds that act in this pass sums[0..8] = K, sums[9..17] = N (row-major; w the
// kind's omega V_j), what Model::affine_row reads.
using BreakRow = BreakOut (*)(const Sweep&, std::size_t, double* sums);

// Row i of the sum, once every row has its record: f_i = sum_j omega V_j ((M_i + M_j) xi +
// (g_i + g_j) Y) over the acting bonds (kernels/affine.hpp affine_pair_add and
// affine_pair_finish; w = the kind's omega V_j), plus the family contact of every bond
// (w: its energy density).
using SumRow = void (*)(const Sweep&, std::size_t, double* f, double& w);

// The rows for this pass: AVX-512 where the machine has it and the settings allow (as the
// fast loops: set_kernel_path's "scalar" or "avx2" takes the portable rows), else portable.
BreakRow break_row_for(const Sweep& s);
SumRow sum_row_for(const Sweep& s);

}  // namespace horizon::affine_sweeps
