// Compile check of the portable kernels of microplastic, PALS, the linearised LPS and the
// bond-pair model for the device (issue 30; kernels/microplastic.hpp, pals.hpp,
// linear_lps.hpp, bond_pair.hpp): each row, PALS's multipliers, and the bond-pair model's
// pairs, springs and nodes instantiated in a __global__ function of one thread a particle
// (or a pair, a bond) over flat arrays, as a device pass would call them. Beside
// kernels_compile.cu in the same object library of cmake/cuda.cmake (nothing runs it), so
// bench/gpu/device_check.sh compiles them in its one call; `-Xptxas -v` on this file gives
// their registers and spills (docs/design.md).
#include <cstddef>
#include <cstdint>

#include "horizon/core/point4.hpp"
#include "horizon/kernels/bond_pair.hpp"
#include "horizon/kernels/linear_lps.hpp"
#include "horizon/kernels/microplastic.hpp"
#include "horizon/kernels/pals.hpp"

namespace horizon::kernels {

// A bond kind as the rows of microplastic, PALS and the linearised LPS read it (the host
// passes its BondKind), and three doubles for the positions and force states.
struct DevBondKind {
  double length, volume, fraction, weight;
};
struct DevVec {
  double x, y, z;
};

// Microplastic's row i over CSR bonds; the ledger's opening here only records e (a device
// pass would book the bonds broken since the commit as HistoryLedger::Row::open_bond does).
__global__ void microplastic_rows(MicroplasticRow<DevBondKind> a, const uint64_t* offset, std::size_t n,
                                  double* extension_trial, double* W, double* work, uint8_t* inelastic) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i >= n) return;
  const MicroplasticSums s = microplastic_row(a, offset[i], offset[i + 1], [&](uint64_t k, double e, double, double&) {
    extension_trial[k] = e;
    return false;
  });
  W[i] = s.W, work[i] = s.work, inelastic[i] = s.inelastic ? 1 : 0;
}

// PALS's row i, and one particle's multipliers from its family.
__global__ void pals_rows(PalsRow<DevBondKind> a, const uint64_t* offset, std::size_t n, double* theta, double* W) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i >= n) return;
  const PalsSums s = pals_row(a, offset[i], offset[i + 1]);
  theta[i] = s.theta, W[i] = s.W;
}
__global__ void pals_multiplier_points(const DevVec* xi, const double* ws, const double* wd, const uint64_t* offset,
                                       std::size_t n, double* multipliers, uint8_t* ok) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i >= n) return;
  const uint64_t b = offset[i], m = offset[i + 1] - b;
  double* lm = multipliers + 12 * i;
  ok[i] = pals_dilatation_multipliers(xi + b, ws + b, m, lm) && pals_deviatoric_multipliers(xi + b, wd + b, m, lm + 6);
}

// The linearised LPS's row i.
__global__ void linear_lps_rows(LinearLpsRow<DevBondKind, Point4, DevVec> a, const uint64_t* offset,
                                const double* weighted_volume, std::size_t n, double* theta, double* W) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i >= n) return;
  const LinearLpsSums s = linear_lps_row(a, static_cast<uint32_t>(i), offset[i], offset[i + 1], weighted_volume[i]);
  theta[i] = s.theta, W[i] = s.W;
}

// The bond-pair model's pair q (elastic, signed and shell forms) and spring b, their
// forces to per-pair arrays (a device pass would then gather them per node).
__global__ void bond_pair_pairs(const BpVec* y, const BpVec* X, const uint32_t* k, const uint32_t* j,
                                const uint32_t* jp, const double* coef, const double* inv_length, const double* c0,
                                const double* s0, const double* theta_p, std::size_t n, double theta_yield,
                                BpVec* Fj, BpVec* Fjp, BpVec* G, double* offset, double* energy) {
  const std::size_t q = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (q >= n) return;
  const BpElasticPair ep =
      bp_elastic_pair(bp_sub(y[j[q]], y[k[q]]), bp_sub(y[jp[q]], y[k[q]]), coef[q], c0[q], s0[q]);
  Fj[q] = ep.Fj, Fjp[q] = ep.Fjp;
  const BpKink d = bp_shell_kink(y[j[q]], y[jp[q]], y[k[q]], X[j[q]], X[jp[q]], X[k[q]], inv_length[q]);
  const BpShellPair sp =
      bp_shell_pair(d, {theta_p[2 * q], theta_p[2 * q + 1]}, theta_yield, coef[q], inv_length[q], X[j[q]], X[k[q]]);
  G[q] = sp.G;
  const double sk = bp_transverse_kink(y[j[q]].z, y[jp[q]].z, y[k[q]].z, X[j[q]].z, X[jp[q]].z, X[k[q]].z,
                                       inv_length[q]);
  const BpSignedPair gp = bp_signed_pair(sk, theta_p[q], theta_yield, coef[q], inv_length[q]);
  offset[q] = gp.offset + sp.offset.n;
  energy[q] = coef[q] * ep.f + sp.energy + gp.energy;
}
__global__ void bond_pair_springs(const BpVec* y, const uint32_t* k, const uint32_t* j, const double* length,
                                  const double* coef, const double* dil, const double* theta, const double* V,
                                  std::size_t n, double dil_coef, BpVec* f, double* energy) {
  const std::size_t b = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (b >= n) return;
  const BpVec Y = bp_sub(y[j[b]], y[k[b]]);
  const double L = bp_bond_length(Y), e = L - length[b];
  f[b] = bp_spring_force(Y, L, e, coef[b], dil_coef, dil[b], theta[k[b]], theta[j[b]], V[k[b]], V[j[b]]);
  energy[b] = bp_spring_energy(coef[b], e);
}

// The bond-pair model's nodes: force density, booked energy, damage and stable step.
__global__ void bond_pair_nodes(const BpVec* F, const double* volume, const double* weight, const double* failed,
                                const double* pairs, const double* density, const double* section, std::size_t n,
                                bool transverse, double bound, BpVec* f, double* energy, double* damage, double* dt) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i >= n) return;
  f[i] = bp_node_force(F[i], volume[i], transverse, weight[i]);
  energy[i] = bp_node_energy(energy[i], weight[i], volume[i]);
  damage[i] = bp_damage(failed[i], pairs[i]);
  dt[i] = bp_stable_step(bound, density[i], section[i]);
}

}  // namespace horizon::kernels
