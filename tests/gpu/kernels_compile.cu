// Compile check of the portable law kernels for the device (issue 30): the finite-strain
// laws of the correspondence model (kernels/laws.hpp: law_row for the linear elastic,
// neo-Hookean and J2 laws; the SVD and polar decomposition of kernels/eigen3.hpp; the
// rate-form step of kernels/hypoelastic.hpp; extended correspondence's law step: the Hencky
// map of kernels/hencky.hpp around the strain law of kernels/strain_laws.hpp; the rows of
// microplastic, PALS and the linearised LPS, PALS's multipliers, and the bond-pair model's
// pairs and springs: kernels/microplastic.hpp, pals.hpp, linear_lps.hpp, bond_pair.hpp), each
// instantiated in a __global__ function of one thread a particle over flat arrays, as a
// device pass of correspondence would call them. Built by cmake/cuda.cmake (an object
// library: nothing runs it), so bench/gpu/device_check.sh compiles them in its one call;
// `-Xptxas -v` on this file gives their registers and spills (docs/design.md).
#include <cstdint>

#include "horizon/kernels/bond_pair.hpp"
#include "horizon/kernels/eigen3.hpp"
#include "horizon/kernels/extended.hpp"
#include "horizon/kernels/hencky.hpp"
#include "horizon/kernels/hypoelastic.hpp"
#include "horizon/kernels/laws.hpp"
#include "horizon/kernels/linear_lps.hpp"
#include "horizon/kernels/microplastic.hpp"
#include "horizon/kernels/pals.hpp"
#include "horizon/kernels/strain_laws.hpp"

namespace horizon::kernels {

// Row i of the affine pass's law for n particles: sums (18 each) to records (kAffineRecord
// each), J2 history in and out, the von Mises stress, the energy and the plastic work.
__global__ void law_rows(const double* sums, std::size_t n, int d, double tolerance, LawConstants c, double G,
                         const J2History* committed, J2History* trial, double* work, double* rec, double* von_mises,
                         double* energy) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i >= n) return;
  const AffineRow row =
      law_row(sums + 18 * i, d, tolerance, c, G, committed[i], trial[i], work[i], rec + kAffineRecord * i);
  von_mises[i] = row.von_mises;
  energy[i] = row.carries ? row.W : 0.0;
}

// The J2 return map alone (from F), and the neo-Hookean law alone.
__global__ void j2_points(const double* F, std::size_t n, LawConstants c, const J2History* committed,
                          J2History* trial, double* work, double* P) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i >= n) return;
  LawStress r;
  j2_stress(c.mu, c.kappa, c.yield_stress, c.hardening, committed[i], F + 9 * i, trial[i], work[i], r);
  for (int k = 0; k < 9; ++k) P[9 * i + k] = r.P[k];
}

__global__ void neo_hookean_points(const double* F, std::size_t n, double mu, double kappa, double* P, double* W) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i >= n) return;
  LawStress r;
  neo_hookean_stress(mu, kappa, F + 9 * i, r);
  for (int k = 0; k < 9; ++k) P[9 * i + k] = r.P[k];
  W[i] = r.W;
}

// The SVD and the polar decomposition with ln U.
__global__ void polar_points(const double* F, std::size_t n, double* R, double* log_U, uint8_t* ok) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i >= n) return;
  ok[i] = polar_log3(F + 9 * i, R + 9 * i, log_U + 9 * i) ? 1 : 0;
}

// The rate-form step (hypoelastic laws) of one particle from its F and F_dot.
__global__ void hypo_points(const double* F, const double* Fdot, std::size_t n, HypoConstants c, double yield,
                            const HypoHistory* committed, HypoHistory* trial, double dt, double* work, double* P,
                            double* d) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i >= n) return;
  LawStress r;
  hypo_step(c, yield, committed[i], F + 9 * i, dt, Fdot + 9 * i, 0.0, trial[i], work[i], r, d + 9 * i);
  for (int k = 0; k < 9; ++k) P[9 * i + k] = r.P[k];
}

// Extended correspondence's law step of one particle (the model's run_law): the Green strain
// E to its Hencky strain, its trace from Fbar (volumetric_strain gradient), the law there
// (elastic, j2 or Johnson-Cook), the pressure split and the stress back (history in and out
// as row-major E_p, alpha and the damage D).
__global__ void hencky_law_points(const double* E, const double* Fbar, std::size_t n, int d, StrainLawConstants p,
                                  const double* Ep_n, const double* alpha_n, const double* D_n, double dt, double* Ep,
                                  double* alpha, double* D, double* S, double* pressure_map, double* W,
                                  double* work) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i >= n) return;
  double N[9], l[3], strain[9];
  hencky_of_green3(E + 9 * i, 1e-6, N, l, strain);
  volumetric_gradient_strain(Fbar + 9 * i, d, strain);
  StrainLawPoint pt;
  strain_law_point(p, Ep_n + 9 * i, alpha_n[i], D_n[i], strain, dt, Ep + 9 * i, alpha[i], D[i], pt);
  volumetric_pressure_split(Fbar + 9 * i, d, pt.S, pressure_map + 9 * i);
  green_stress_of_hencky3(N, l, pt.S, S + 9 * i);
  W[i] = pt.W;
  work[i] = pt.plastic_work;
}

// Eigen's symmetric eigen-solver alone.
__global__ void sym_eigen_points(const double* A, std::size_t n, double* eval, double* Q, uint8_t* ok) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i >= n) return;
  ok[i] = sym_eigen3(A + 9 * i, eval + 3 * i, Q + 9 * i) ? 1 : 0;
}

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
