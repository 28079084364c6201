// The ordinary history models on the device (cuda_ordinary.hpp): the three kernels of
// kernels::flat_ordinary_forces and the copies of kernels::FlatOrdinary's arrays. Compiled
// with --fmad=false as cuda_backend.cu (cmake/cuda.cmake), so the rows compute the host's
// operations in the host's order (the lanes of kernels::for_each_lane, bond order for the
// rare events). Compiled with nvcc 13.0 (sm_90) on a machine without a GPU: never run.
#include "horizon/cuda/cuda_ordinary.hpp"

#include <cuda_runtime.h>

#include <cstdio>
#include <cstdlib>

namespace horizon::cuda {

namespace {

void check(cudaError_t e, const char* what) {
  if (e == cudaSuccess) return;
  std::fprintf(stderr, "horizon cuda: %s: %s\n", what, cudaGetErrorString(e));
  std::abort();
}

template <class T>
T* up(const T* host, uint64_t count, std::vector<void*>& owned) {
  if (!host || count == 0) return nullptr;
  T* d = nullptr;
  check(cudaMalloc(&d, count * sizeof(T)), "cudaMalloc");
  owned.push_back(d);
  check(cudaMemcpy(d, host, count * sizeof(T), cudaMemcpyHostToDevice), "cudaMemcpy to the device");
  return d;
}
template <class T>
void down(T* host, const T* device, uint64_t count) {
  if (host && device && count) check(cudaMemcpy(host, device, count * sizeof(T), cudaMemcpyDeviceToHost), "cudaMemcpy to the host");
}

__global__ void ordinary_pack_kernel(kernels::FlatSystem s) {
  const uint64_t i = blockIdx.x * static_cast<uint64_t>(blockDim.x) + threadIdx.x;
  if (i < s.n) kernels::pack_row(s, i);
}
__global__ void ordinary_row_kernel(kernels::FlatSystem s) {
  const uint64_t i = blockIdx.x * static_cast<uint64_t>(blockDim.x) + threadIdx.x;
  if (i < s.n) kernels::ordinary_row(s, i);
}
__global__ void ordinary_sum_kernel(kernels::FlatSystem s) {
  const uint64_t i = blockIdx.x * static_cast<uint64_t>(blockDim.x) + threadIdx.x;
  if (i < s.n) kernels::ordinary_sum_row(s, i);
}
// One thread, after the sums: this pass's |Y| and q become the last pass's.
__global__ void ordinary_flip_kernel(kernels::FlatSystem s) { kernels::flip_ordinary(s); }

}  // namespace

const kernels::FlatOrdinary* upload_ordinary(const kernels::FlatOrdinary& h, uint64_t n, uint64_t nb,
                                             uint64_t nkinds, kernels::FlatOrdinary& d, std::vector<void*>& o) {
  d = h;  // the constants; every pointer is replaced below
  d.omega = up(h.omega, nkinds, o), d.vj = up(h.vj, nkinds, o);
  for (int b = 0; b < 2; ++b) d.r[b] = up(h.r[b], nb, o), d.q[b] = up(h.q[b], nb, o);
  d.rev = up(h.rev, nb, o), d.current = up(h.current, 1, o);
  d.booked = up(h.booked, nb, o), d.pending_set = up(h.pending_set, nb, o);
  d.pending_amount = up(h.pending_amount, nb, o);
  d.stored = up(h.stored, n, o), d.theta = up(h.theta, n, o);
  d.ep = up(h.ep, nb, o), d.eps_p = up(h.eps_p, n, o), d.lambda = up(h.lambda, n, o);
  d.shear_factor = up(h.shear_factor, n, o), d.flowed = up(h.flowed, n, o), d.yielded = up(h.yielded, n, o);
  d.dissipated_density = up(h.dissipated_density, n, o), d.theta_strain = up(h.theta_strain, n, o);
  for (int b = 0; b < kernels::kFlatBranches; ++b)
    d.back[b] = up(h.back[b], nb, o), d.theta_back[b] = up(h.theta_back[b], n, o);
  d.sbar = up(h.sbar, nb, o);
  d.pals_kinds = up(h.pals_kinds, nkinds, o), d.sigma = up(h.sigma, nb, o), d.tau = up(h.tau, nb, o);
  return up(&d, 1, o);
}

void download_ordinary(const kernels::FlatOrdinary& h, const kernels::FlatOrdinary& d, uint64_t n, uint64_t nb) {
  for (int b = 0; b < 2; ++b) down(h.r[b], d.r[b], nb), down(h.q[b], d.q[b], nb);
  down(h.current, d.current, 1);
  down(h.booked, d.booked, nb), down(h.pending_set, d.pending_set, nb), down(h.pending_amount, d.pending_amount, nb);
  down(h.stored, d.stored, n), down(h.theta, d.theta, n);
  down(h.ep, d.ep, nb), down(h.eps_p, d.eps_p, n), down(h.lambda, d.lambda, n);
  down(h.flowed, d.flowed, n), down(h.yielded, d.yielded, n);
  down(h.dissipated_density, d.dissipated_density, n), down(h.theta_strain, d.theta_strain, n);
  for (int b = 0; b < kernels::kFlatBranches; ++b) down(h.back[b], d.back[b], nb), down(h.theta_back[b], d.theta_back[b], n);
  down(h.sbar, d.sbar, nb);
}

void ordinary_pass(const kernels::FlatSystem& d, unsigned grid, int block) {
  ordinary_pack_kernel<<<grid, block>>>(d);
  ordinary_row_kernel<<<grid, block>>>(d);
  ordinary_sum_kernel<<<grid, block>>>(d);
  ordinary_flip_kernel<<<1, 1>>>(d);
}

}  // namespace horizon::cuda
