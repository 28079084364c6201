// Compile check of the portable law kernels for the device (issue 30): the finite-strain
// laws of the correspondence model (kernels/laws.hpp: law_row for the linear elastic,
// neo-Hookean and J2 laws; the SVD and polar decomposition of kernels/eigen3.hpp; the
// rate-form step of kernels/hypoelastic.hpp; extended correspondence's law step: the Hencky
// map of kernels/hencky.hpp around the strain law of kernels/strain_laws.hpp; the law at a
// point with plane stress's iteration and the thermal split, kernels/plane_stress.hpp; the
// general pass's bond force state, kernels/force_state.hpp; bond-associated correspondence's
// rows, kernels/bond_associated.hpp), each
// instantiated in a __global__ function of one thread a particle (or a bond) over flat arrays, as a
// device pass of correspondence would call them. Built by cmake/cuda.cmake (an object
// library: nothing runs it), so bench/gpu/device_check.sh compiles them in its one call;
// `-Xptxas -v` on this file gives their registers and spills (docs/design.md). Extended
// correspondence's law row (kernels/extended_law.hpp): the moment map row, the pair form's
// whole law row and the volumetric gradient's bond terms, over CSR bonds as a device pass
// of the pair form would hold them.
#include <cstdint>

#include "horizon/kernels/bond_associated.hpp"
#include "horizon/kernels/eigen3.hpp"
#include "horizon/kernels/extended.hpp"
#include "horizon/kernels/extended_law.hpp"
#include "horizon/kernels/force_state.hpp"
#include "horizon/kernels/hencky.hpp"
#include "horizon/kernels/hypoelastic.hpp"
#include "horizon/kernels/laws.hpp"
#include "horizon/kernels/plane_stress.hpp"
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

// Extended correspondence, one particle a thread over CSR bonds (offset, nbr, per-bond w =
// omega V_j, 1/|xi|, acting flags): the moment map and K^-1 of the acting set, factorised.
__global__ void moment_map_rows(const uint64_t* offset, const uint32_t* nbr, const double* X, const double* w,
                                const uint8_t* acts, std::size_t n, int d, double tolerance, const double* min_weight,
                                double* M, double* inv, double* Kinv, uint8_t* ok) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i >= n) return;
  auto bond = [&](uint64_t k, double* xi, double& wk) {
    if (!acts[k]) return false;
    for (int a = 0; a < 3; ++a) xi[a] = X[3 * nbr[k] + a] - X[3 * i + a];
    wk = w[k];
    return true;
  };
  double acting = 0;
  ok[i] = moment_map_row(offset[i], offset[i + 1], bond, d, tolerance, min_weight[i], M + 36 * i, inv + 36 * i,
                         Kinv + 9 * i, acting)
              ? 1
              : 0;
}

// The pair form's law row of one particle: E = M^-1 S, then the law, the stabilisation
// (midpoint residual with the neighbours' E), the record A and P K^-1.
__global__ void extended_pair_law_rows(const uint64_t* offset, const uint32_t* nbr, const double* X,
                                       const double* w, const double* inv_length, const uint8_t* acts,
                                       const double* eps, std::size_t n, ExtendedLawConstants c, const double* inv,
                                       const double* S, const double* N, const double* Kinv,
                                       const ExtendedLawHistory* committed, double dt, const double* ks,
                                       const uint8_t* e_ok, double* E, double* rforce, ExtendedLawHistory* trial,
                                       double* A, double* PK, double* W, uint8_t* on) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i >= n) return;
  moment_solve(inv + 36 * i, S + 6 * i, E + 6 * i);
  auto bond = [&](uint64_t k, StabilisationBond& b) {
    if (!acts[k]) return false;
    const uint32_t j = nbr[k];
    for (int a = 0; a < 3; ++a) b.n[a] = inv_length[k] * (X[3 * j + a] - X[3 * i + a]);
    b.eps = eps[k], b.w = w[k];
    b.mid = e_ok[j] != 0;
    b.Ej = E + 6 * j;
    b.ksj = ks[j];
    return true;
  };
  ExtendedLawRow out;
  double Ws = 0;
  on[i] = extended_pair_law_row(c, inv + 36 * i, E + 6 * i, N + 9 * i, Kinv + 9 * i, committed[i], dt, ks[i],
                                offset[i], offset[i + 1], bond, rforce, trial[i], out, A + 6 * i, Ws)
              ? 1
              : 0;
  for (int k = 0; k < 9; ++k) PK[9 * i + k] = out.PK[k];
  W[i] = out.W + Ws;
}

// The vector form's stabilisation of a row (capped, midpoint residual): R, W_s, the work.
__global__ void vector_stabilisation_rows(const uint64_t* offset, const uint32_t* nbr, const double* X,
                                          const double* w, const uint8_t* acts, const double* eps, std::size_t n,
                                          const double* E, const double* ks, const uint8_t* e_ok, double r_c,
                                          const double* rp_committed, double* rp_trial, double* rforce, double* R,
                                          double* W) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i >= n) return;
  auto bond = [&](uint64_t k, VectorStabilisationBond& b) {
    if (!acts[k]) return false;
    const uint32_t j = nbr[k];
    for (int a = 0; a < 3; ++a) b.xi[a] = X[3 * j + a] - X[3 * i + a];
    b.eps = eps[k], b.w = w[k];
    b.mid = e_ok[j] != 0;
    b.Ej = E + 6 * j;
    b.ksj = ks[j];
    return true;
  };
  VectorStabilisation st;
  vector_stabilisation_row(offset[i], offset[i + 1], bond, E + 6 * i, ks[i], r_c > 0, r_c, rp_committed, rp_trial,
                           rforce, st);
  for (int k = 0; k < 9; ++k) R[9 * i + k] = st.R[k];
  W[i] = st.W + st.work;
}

// The vector form's bond sweeps of a row: the strains and their sum S (sweep 1), then the
// force states with a = dual(S), b = dual(R) of the row (sweep 2).
__global__ void vector_form_rows(const uint64_t* offset, const uint32_t* nbr, const double* X, const double* y,
                                 const double* w, const double* omega, std::size_t n, double m, int d,
                                 const double* a, const double* b, const double* ks, const double* rforce,
                                 double* eps, double* S, double* T) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i >= n) return;
  double Si[6] = {};
  for (uint64_t k = offset[i]; k < offset[i + 1]; ++k) {
    double xi[3], Y[3];
    for (int q = 0; q < 3; ++q) xi[q] = X[3 * nbr[k] + q] - X[3 * i + q], Y[q] = y[3 * nbr[k] + q] - y[3 * i + q];
    eps[k] = vector_strain_add(Si, xi, Y, w[k], m, d);
    vector_bond_force(a + 6 * i, b + 6 * i, ks[i], omega[k], m, d, xi, Y, rforce[k], T + 3 * k);
  }
  for (int q = 0; q < 6; ++q) S[6 * i + q] = Si[q];
}

// The volumetric gradient's bond terms of a row: N = sum w Y (x) xi, and sum w P_j xi.
__global__ void pressure_rows(const uint64_t* offset, const uint32_t* nbr, const double* X, const double* y,
                              const double* w, std::size_t n, const double* PK, double* N, double* f) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i >= n) return;
  double Ni[9] = {}, fi[3] = {};
  for (uint64_t k = offset[i]; k < offset[i + 1]; ++k) {
    const uint32_t j = nbr[k];
    double xi[3], Y[3], t[3];
    for (int a = 0; a < 3; ++a) xi[a] = X[3 * j + a] - X[3 * i + a], Y[a] = y[3 * j + a] - y[3 * i + a];
    gradient_outer_add(Ni, w[k], Y, xi);
    pressure_bond_term(PK + 9 * j, w[k], xi, t);
    for (int a = 0; a < 3; ++a) fi[a] += t[a];
  }
  for (int k = 0; k < 9; ++k) N[9 * i + k] = Ni[k];
  for (int a = 0; a < 3; ++a) f[3 * i + a] = fi[a];
}

// The total-form law at a point (kernels/plane_stress.hpp law_point: 2-D plane stress's
// secant iteration and the thermal split around the law of c), history in and out.
__global__ void law_point_points(const double* F, std::size_t n, LawConstants c, int dim, bool plane_stress,
                                 const double* eps, const J2History* committed, double* lambda3, J2History* trial,
                                 double* work, double* P, double* W) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i >= n) return;
  LawStress r;
  law_point(c, dim, plane_stress, eps[i], committed[i], F + 9 * i, lambda3[i], trial[i], work[i], r);
  for (int k = 0; k < 9; ++k) P[9 * i + k] = r.P[k];
  W[i] = r.W;
}

// Row i of the affine pass in 2-D plane stress (kernels/plane_stress.hpp law_point_row):
// sums to record with J2's history and the out-of-plane stretch in and out.
__global__ void law_point_rows(const double* sums, std::size_t n, double tolerance, LawConstants c, double G,
                               const J2History* committed, const double* lambda3_n, J2History* trial,
                               double* lambda3, double* work, double* rec, double* von_mises, double* energy) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i >= n) return;
  const AffineRow row = law_point_row(sums + 18 * i, 2, tolerance, c, true, G, committed[i], lambda3_n[i], trial[i],
                                      lambda3[i], work[i], rec + kAffineRecord * i);
  von_mises[i] = row.von_mises;
  energy[i] = row.carries ? row.W : 0.0;
}

// The general pass's force state of one bond (kernels/force_state.hpp), one thread a bond:
// the row's A and F (9 + 9 numbers per particle) read through the bond's row index.
__global__ void general_bond_states(const double* A, const double* F, const uint32_t* row, const double* xi,
                                    const double* Y, const double* omega, std::size_t bonds, double G, double Cc,
                                    double* T) {
  const std::size_t k = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (k >= bonds) return;
  const std::size_t i = row[k];
  correspondence_bond_state(A + 9 * i, F + 9 * i, G, omega[k], xi + 3 * k, Y + 3 * k, T + 3 * k);
  if (Cc != 0) peridigm_hourglass_add(F + 9 * i, Cc, omega[k], xi + 3 * k, Y + 3 * k, T + 3 * k);
}

// Bond-associated correspondence, one thread a row over its bonds (CSR offsets, neighbours,
// xi and Y per bond): the bond-level gradient, the total-form law with the bond's history,
// the bond's force term and S_i, then the second term with A = S_i K_i^-1.
__global__ void bond_associated_rows(const uint64_t* offset, const uint32_t* nbr, std::size_t n, const double* F,
                                     const double* Kinv, const double* m, const double* xi, const double* Y,
                                     const double* omega, const double* volume, LawConstants c, int dim,
                                     bool plane_stress, const J2History* committed, const double* lambda3_n,
                                     J2History* trial, double* lambda3, double* work, double* T) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i >= n) return;
  double S[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
  for (uint64_t k = offset[i]; k < offset[i + 1]; ++k) {
    const std::size_t j = nbr[k];
    const double* b = xi + 3 * k;
    const double bb = squared_norm3(b);
    double Fb[9];
    bond_level_gradient(F + 9 * i, F + 9 * j, b, Y + 3 * k, bb, Fb);
    LawStress r;
    lambda3[k] = lambda3_n[k];
    law_point(c, dim, plane_stress, 0.0, committed[k], Fb, lambda3[k], trial[k], work[k], r);
    if (!r.ok) continue;
    bond_associated_terms(r.P, b, bb, omega[k] / m[i], omega[k] / m[j], volume[k], T + 3 * k, S);
  }
  double A[9];
  mat3_mul(S, Kinv + 9 * i, A);
  for (uint64_t k = offset[i]; k < offset[i + 1]; ++k) bond_associated_tail(A, omega[k], xi + 3 * k, T + 3 * k);
}

}  // namespace horizon::kernels
