// The CUDA backend (cuda_backend.hpp): device copies of the flat arrays and one kernel per
// stage of a step, each a thread per particle calling the portable row function of
// kernels/flat_system.hpp, in the order advance_flat calls them on the host. A row is
// summed by one thread in bond order, so with -fmad=false (cmake/cuda.cmake) the device
// computes the host's operations in the host's order.
//
// Compiled with nvcc 13.0 (sm_90) on a machine without a GPU: it has never run.
#include "horizon/cuda/cuda_backend.hpp"
#include "horizon/cuda/cuda_ordinary.hpp"

#include <cuda_runtime.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace horizon::cuda {

namespace {

using kernels::FlatSystem;

// A failed CUDA call is a bug or a lost device: say where and stop.
void check(cudaError_t e, const char* what) {
  if (e == cudaSuccess) return;
  std::fprintf(stderr, "horizon cuda: %s: %s\n", what, cudaGetErrorString(e));
  std::abort();
}

constexpr int kBlock = 256;

__global__ void kick_drift_kernel(FlatSystem s) {
  const uint64_t i = blockIdx.x * static_cast<uint64_t>(blockDim.x) + threadIdx.x;
  if (i < s.n) kernels::kick_drift_row(s, i);
}
__global__ void pack_kernel(FlatSystem s) {
  const uint64_t i = blockIdx.x * static_cast<uint64_t>(blockDim.x) + threadIdx.x;
  if (i < s.n) kernels::pack_row(s, i);
}
__global__ void bond_based_kernel(FlatSystem s) {
  const uint64_t i = blockIdx.x * static_cast<uint64_t>(blockDim.x) + threadIdx.x;
  if (i < s.n) kernels::bond_based_row(s, i);
}
__global__ void dilatation_kernel(FlatSystem s) {
  const uint64_t i = blockIdx.x * static_cast<uint64_t>(blockDim.x) + threadIdx.x;
  if (i < s.n) kernels::dilatation_row(s, i);
}
__global__ void pressure_kernel(FlatSystem s) {
  const uint64_t i = blockIdx.x * static_cast<uint64_t>(blockDim.x) + threadIdx.x;
  if (i < s.n) kernels::pressure_row(s, i);
}
__global__ void force_kernel(FlatSystem s) {
  const uint64_t i = blockIdx.x * static_cast<uint64_t>(blockDim.x) + threadIdx.x;
  if (i < s.n) kernels::force_row(s, i);
}
// Tupek's nonlinear solid (FlatSystem::tupek): its three stages of the force pass.
__global__ void tupek_pack_kernel(FlatSystem s) {
  const uint64_t i = blockIdx.x * static_cast<uint64_t>(blockDim.x) + threadIdx.x;
  if (i < s.n) kernels::tupek_pack_row(s, i);
}
__global__ void tupek_theta_kernel(FlatSystem s) {
  const uint64_t i = blockIdx.x * static_cast<uint64_t>(blockDim.x) + threadIdx.x;
  if (i < s.n) kernels::tupek_theta_row(s, i);
}
__global__ void tupek_force_kernel(FlatSystem s) {
  const uint64_t i = blockIdx.x * static_cast<uint64_t>(blockDim.x) + threadIdx.x;
  if (i < s.n) kernels::tupek_row(s, i);
}
// Its stable step (kernels::flat_tupek_stable_step): each row's S, then the smallest row
// step, a minimum over the warp (fmin, which skips NaN as the host's r < dt ? r : dt does)
// and one atomicMin a warp on the bits of a positive double (their order is the values').
__global__ void tupek_coupling_kernel(FlatSystem s, double* S) {
  const uint64_t i = blockIdx.x * static_cast<uint64_t>(blockDim.x) + threadIdx.x;
  if (i < s.n) S[i] = kernels::tupek_coupling_row(kernels::tupek_pass(s), i);
}
__global__ void tupek_stable_kernel(FlatSystem s, const double* S, unsigned long long* best) {
  const uint64_t i = blockIdx.x * static_cast<uint64_t>(blockDim.x) + threadIdx.x;
  double r = INFINITY;
  if (i < s.n) r = kernels::tupek_stable_row(kernels::tupek_pass(s), S, s.contact_stiffness[i], s.density[i], i);
  for (int o = 16; o > 0; o /= 2) r = fmin(r, __shfl_down_sync(0xffffffffu, r, o));
  if ((threadIdx.x & 31u) == 0 && r == r) atomicMin(best, static_cast<unsigned long long>(__double_as_longlong(r)));
}
// The correspondence model's pass (FlatSystem::correspondence, kernels/flat_affine.hpp):
// the breaking sweep with the law, the pair sum, the commit.
__global__ void affine_break_kernel(FlatSystem s) {
  const uint64_t i = blockIdx.x * static_cast<uint64_t>(blockDim.x) + threadIdx.x;
  if (i < s.n) kernels::flat_affine_break_row(s, i);
}
__global__ void affine_sum_kernel(FlatSystem s) {
  const uint64_t i = blockIdx.x * static_cast<uint64_t>(blockDim.x) + threadIdx.x;
  if (i < s.n) kernels::flat_affine_sum_row(s, i);
}
__global__ void affine_commit_kernel(FlatSystem s) {
  const uint64_t i = blockIdx.x * static_cast<uint64_t>(blockDim.x) + threadIdx.x;
  if (i < s.n) kernels::flat_affine_commit_row(s, i);
}
__global__ void kick_kernel(FlatSystem s) {
  const uint64_t i = blockIdx.x * static_cast<uint64_t>(blockDim.x) + threadIdx.x;
  if (i < s.n) kernels::kick_row(s, i);
}
__global__ void save_tracked_kernel(FlatSystem s) {
  const uint64_t m = blockIdx.x * static_cast<uint64_t>(blockDim.x) + threadIdx.x;
  if (m < s.ntracked) kernels::save_tracked_row(s, m);
}
// One thread: the loads' work of the step, summed in the host's order.
__global__ void book_load_work_kernel(FlatSystem s) { kernels::book_load_work(s); }

// One device array per host array.
template <class T>
T* upload(const T* host, uint64_t count, std::vector<void*>& owned) {
  T* d = nullptr;
  if (count == 0) return nullptr;
  check(cudaMalloc(&d, count * sizeof(T)), "cudaMalloc");
  owned.push_back(d);
  if (host) check(cudaMemcpy(d, host, count * sizeof(T), cudaMemcpyHostToDevice), "cudaMemcpy to the device");
  return d;
}
template <class T>
void download_array(T* host, const T* device, uint64_t count) {
  if (count) check(cudaMemcpy(host, device, count * sizeof(T), cudaMemcpyDeviceToHost), "cudaMemcpy to the host");
}

}  // namespace

bool device_available(std::string& why) {
  int count = 0;
  const cudaError_t e = cudaGetDeviceCount(&count);
  if (e != cudaSuccess) {
    why = std::string("no CUDA device: ") + cudaGetErrorString(e);
    return false;
  }
  if (count == 0) {
    why = "no CUDA device";
    return false;
  }
  return true;
}

double copy_bandwidth(uint64_t bytes) {
  void *a = nullptr, *b = nullptr;
  check(cudaMalloc(&a, bytes), "cudaMalloc");
  check(cudaMalloc(&b, bytes), "cudaMalloc");
  check(cudaMemset(a, 1, bytes), "cudaMemset");
  cudaEvent_t start, stop;
  check(cudaEventCreate(&start), "cudaEventCreate");
  check(cudaEventCreate(&stop), "cudaEventCreate");
  check(cudaMemcpy(b, a, bytes, cudaMemcpyDeviceToDevice), "cudaMemcpy");  // warm-up
  const int repeat = 10;
  check(cudaEventRecord(start), "cudaEventRecord");
  for (int k = 0; k < repeat; ++k) check(cudaMemcpy(b, a, bytes, cudaMemcpyDeviceToDevice), "cudaMemcpy");
  check(cudaEventRecord(stop), "cudaEventRecord");
  check(cudaEventSynchronize(stop), "cudaEventSynchronize");
  float ms = 0;
  check(cudaEventElapsedTime(&ms, start, stop), "cudaEventElapsedTime");
  cudaEventDestroy(start);
  cudaEventDestroy(stop);
  cudaFree(a);
  cudaFree(b);
  return 2.0 * static_cast<double>(bytes) * repeat / (1e-3 * ms);
}

struct FlatRun::Impl {
  FlatSystem d;  // device pointers
  FlatSystem h;  // the host arrays copied from
  std::vector<void*> owned;
  cudaEvent_t start = nullptr, stop = nullptr;
  double seconds = 0;
  unsigned grid = 0, tracked_grid = 0;
  double* S = nullptr;                   // stable_time_step's per-row sums (n), on first use
  unsigned long long* best = nullptr;    // its minimum's bits
  kernels::FlatOrdinary ordinary;        // elastic_plastic, viscoelastic: device pointers (cuda_ordinary.hpp)
};

FlatRun::FlatRun(const FlatSystem& h) : impl_(new Impl) {
  Impl& m = *impl_;
  FlatSystem& d = m.d;
  auto& o = m.owned;
  const uint64_t n = h.n, nb = h.nb;
  d = h;  // the scalars; every pointer is replaced below
  m.h = h;
  d.offset = upload(h.offset, n + 1, o);
  d.nbr = upload(h.nbr, nb, o);
  d.kind = upload(h.kind, nb, o);
  d.intact = upload(h.intact, nb, o);
  d.kinds = upload(h.kinds, h.nkinds, o);
  d.r_of = upload(h.r_of, nb, o);
  d.X = upload(h.X, 3 * n, o);
  d.u = upload(h.u, 3 * n, o);
  d.v = upload(h.v, 3 * n, o);
  d.f = upload(h.f, 3 * n, o);
  d.b = upload(h.b, 3 * n, o);
  d.density = upload(h.density, n, o);
  d.volume = upload(h.volume, n, o);
  d.critical_stretch = upload(h.critical_stretch, n, o);
  d.alpha = upload(h.alpha, n, o);
  d.no_fail = upload(h.no_fail, n, o);
  d.min_stretch = upload(h.min_stretch, n, o);
  d.min_stretch_next = upload(h.min_stretch_next, n, o);
  d.dilatation_coef = upload(h.dilatation_coef, n, o);
  d.Q = upload(h.Q, n, o);
  d.R = upload(h.R, n, o);
  d.weighted_volume = upload(h.weighted_volume, n, o);
  d.theta = upload(h.theta, n, o);
  d.P = upload(h.P, n, o);
  d.intact_weight = upload(h.intact_weight, n, o);
  d.damage_total = upload(h.damage_total, n, o);
  d.damage = upload(h.damage, n, o);
  d.energy = upload(h.energy, n, o);
  d.dissipated = upload(h.dissipated, n, o);
  d.y4 = upload(h.y4, 4 * n, o);
  d.broken = upload(h.broken, n, o);
  d.fixed = upload(h.fixed, h.fixed ? n : 0, o);
  d.fixed_value = upload(h.fixed_value, h.fixed_value ? 3 * n : 0, o);
  d.fixed_mid = upload(h.fixed_mid, h.fixed_mid ? 3 * n : 0, o);
  d.fixed_v = upload(h.fixed_v, h.fixed_v ? 3 * n : 0, o);
  d.fixed_rate = upload(h.fixed_rate, h.fixed_rate ? 3 * n : 0, o);  // solver.verlet: peridigm
  d.positions = upload(h.positions, h.positions ? 3 * n : 0, o);
  d.b_next = upload(h.b_next, h.b_next ? 3 * n : 0, o);
  d.b_before = upload(h.b_before, h.b_before ? 3 * h.ntracked : 0, o);
  d.tracked = upload(h.tracked, h.ntracked, o);
  d.u_before = upload(h.u_before, 3 * h.ntracked, o);
  d.v_before = upload(h.v_before, 3 * h.ntracked, o);
  d.entry_slot = upload(h.entry_slot, h.nentries, o);
  d.entry_mask = upload(h.entry_mask, h.nentries, o);
  d.entry_reaction = upload(h.entry_reaction, 3 * h.nentries, o);
  d.ledger = upload(h.ledger, h.ledger ? 1 : 0, o);
  d.damped = upload(h.damped, h.damped ? n : 0, o);
  d.nonfinite = upload(h.nonfinite, h.nonfinite ? 1 : 0, o);
  d.speed2_before = upload(h.speed2_before, h.damped ? n : 0, o);
  const uint64_t tn = h.tupek ? n : 0;  // the nonlinear solid's arrays
  d.eps = upload(h.eps, h.tupek ? nb : 0, o);
  d.seth_m = upload(h.seth_m, tn, o);
  d.lambda_bar = upload(h.lambda_bar, tn, o);
  d.mu_bar = upload(h.mu_bar, tn, o);
  d.beta = upload(h.beta, tn, o);
  d.compression_only = upload(h.compression_only, tn, o);
  d.failure_scale = upload(h.failure_scale, h.tupek ? h.nkinds : 0, o);
  d.nonlocal_damage = upload(h.nonlocal_damage, tn, o);
  d.contact_stiffness = upload(h.contact_stiffness, tn, o);
  d.length_of = upload(h.length_of, h.length_of ? nb : 0, o);
  if (h.correspondence) {  // kernels/flat_affine.hpp FlatAffine: null host arrays stay null
    const kernels::FlatAffine& a = h.affine;
    kernels::FlatAffine& da = d.affine;
    const uint64_t nk = h.nkinds;
    da.laws = upload(a.laws, a.nlaws, o);
    da.material = upload(a.material, n, o);
    da.ref = upload(a.ref, n, o);
    da.kind_record = upload(a.kind_record, nk, o);
    da.bond_kinds = upload(a.bond_kinds, nk, o);
    da.omega_volume = upload(a.omega_volume, nk, o);
    da.record = upload(a.record, kernels::kAffineRecord * n, o);
    da.y_old = upload(a.y_old, n, o);
    da.work = upload(a.work, n, o);
    da.von_mises = upload(a.von_mises, n, o);
    da.singular = upload(a.singular, n, o);
    da.F_pass = upload(a.F_pass, 9 * n, o);
    da.j2_committed = upload(a.j2_committed, a.j2_committed ? n : 0, o);
    da.j2_trial = upload(a.j2_trial, a.j2_trial ? n : 0, o);
    da.lambda3_committed = upload(a.lambda3_committed, a.lambda3_committed ? n : 0, o);
    da.lambda3_trial = upload(a.lambda3_trial, a.lambda3_trial ? n : 0, o);
    da.hypo_committed = upload(a.hypo_committed, a.hypo_committed ? n : 0, o);
    da.hypo_trial = upload(a.hypo_trial, a.hypo_trial ? n : 0, o);
    da.u_committed = upload(a.u_committed, a.u_committed ? 3 * n : 0, o);
    da.yield_factor = upload(a.yield_factor, a.yield_factor ? n : 0, o);
    da.kinv = upload(a.kinv, a.kinv ? 9 * n : 0, o);
    da.F = upload(a.F, a.F ? 9 * n : 0, o);
    da.sigma = upload(a.sigma, a.sigma ? 9 * n : 0, o);
    da.d = upload(a.d, a.d ? 9 * n : 0, o);
  }
  if (h.ordinary) d.ordinary = upload_ordinary(*h.ordinary, n, nb, h.nkinds, m.ordinary, o);
  m.grid = static_cast<unsigned>((n + kBlock - 1) / kBlock);
  m.tracked_grid = static_cast<unsigned>((h.ntracked + kBlock - 1) / kBlock);
  check(cudaEventCreate(&m.start), "cudaEventCreate");
  check(cudaEventCreate(&m.stop), "cudaEventCreate");
}

FlatRun::~FlatRun() {
  for (void* p : impl_->owned) cudaFree(p);
  if (impl_->start) cudaEventDestroy(impl_->start);
  if (impl_->stop) cudaEventDestroy(impl_->stop);
  delete impl_;
}

void FlatRun::advance(int64_t steps, void (*after_forces)(void*), void* ctx, void (*before_step)(void*, int64_t)) {
  Impl& m = *impl_;
  const FlatSystem& d = m.d;
  if (d.n == 0 || steps <= 0) return;
  check(cudaEventRecord(m.start), "cudaEventRecord");
  for (int64_t k = 0; k < steps; ++k) {
    // kernels/flat_system.hpp advance_flat, stage by stage.
    if (before_step) {
      before_step(ctx, k);
      auto up = [&](double* dev, const double* host, uint64_t count) {
        if (dev && host) check(cudaMemcpy(dev, host, count * sizeof(double), cudaMemcpyHostToDevice), "cudaMemcpy to the device");
      };
      up(d.fixed_value, m.h.fixed_value, 3 * d.n);
      up(d.fixed_mid, m.h.fixed_mid, 3 * d.n);
      up(d.fixed_v, m.h.fixed_v, 3 * d.n);
      up(d.fixed_rate, m.h.fixed_rate, 3 * d.n);
      up(d.b_next, m.h.b_next, 3 * d.n);
      if (d.critical_stretch_varies) up(const_cast<double*>(d.critical_stretch), m.h.critical_stretch, d.n);
    }
    if (d.ntracked) save_tracked_kernel<<<m.tracked_grid, kBlock>>>(d);
    kick_drift_kernel<<<m.grid, kBlock>>>(d);
    if (d.ordinary) {
      ordinary_pass(d, m.grid, kBlock);
    } else if (d.correspondence) {
      pack_kernel<<<m.grid, kBlock>>>(d);
      affine_break_kernel<<<m.grid, kBlock>>>(d);
      affine_sum_kernel<<<m.grid, kBlock>>>(d);
      affine_commit_kernel<<<m.grid, kBlock>>>(d);
    } else if (d.tupek) {
      tupek_pack_kernel<<<m.grid, kBlock>>>(d);
      tupek_theta_kernel<<<m.grid, kBlock>>>(d);
      tupek_force_kernel<<<m.grid, kBlock>>>(d);
    } else if (!d.state_based) {
      pack_kernel<<<m.grid, kBlock>>>(d);
      bond_based_kernel<<<m.grid, kBlock>>>(d);
    } else {
      pack_kernel<<<m.grid, kBlock>>>(d);
      dilatation_kernel<<<m.grid, kBlock>>>(d);
      pressure_kernel<<<m.grid, kBlock>>>(d);
      force_kernel<<<m.grid, kBlock>>>(d);
    }
    if (after_forces) {
      download_array(m.h.y4, d.y4, 4 * d.n);
      download_array(m.h.f, d.f, 3 * d.n);
      download_array(m.h.energy, d.energy, d.n);
      after_forces(ctx);
      check(cudaMemcpy(d.f, m.h.f, 3 * d.n * sizeof(double), cudaMemcpyHostToDevice), "cudaMemcpy to the device");
      check(cudaMemcpy(d.energy, m.h.energy, d.n * sizeof(double), cudaMemcpyHostToDevice), "cudaMemcpy to the device");
    }
    kick_kernel<<<m.grid, kBlock>>>(d);
    if (d.ntracked) book_load_work_kernel<<<1, 1>>>(d);
  }
  check(cudaGetLastError(), "kernel launch");
  check(cudaEventRecord(m.stop), "cudaEventRecord");
  check(cudaEventSynchronize(m.stop), "a step on the device");
  float ms = 0;
  check(cudaEventElapsedTime(&ms, m.start, m.stop), "cudaEventElapsedTime");
  m.seconds += 1e-3 * ms;
}

void FlatRun::set_dt(double dt) {
  impl_->d.dt = dt;
  impl_->h.dt = dt;
}

double FlatRun::stable_time_step() {
  Impl& m = *impl_;
  const FlatSystem& d = m.d;
  if (!d.tupek || d.n == 0) return INFINITY;
  if (!m.S) {
    check(cudaMalloc(&m.S, d.n * sizeof(double)), "cudaMalloc");
    m.owned.push_back(m.S);
    check(cudaMalloc(&m.best, sizeof(unsigned long long)), "cudaMalloc");
    m.owned.push_back(m.best);
  }
  const double inf = INFINITY;
  unsigned long long bits = 0;
  std::memcpy(&bits, &inf, sizeof bits);
  check(cudaMemcpy(m.best, &bits, sizeof bits, cudaMemcpyHostToDevice), "cudaMemcpy to the device");
  tupek_coupling_kernel<<<m.grid, kBlock>>>(d, m.S);
  tupek_stable_kernel<<<m.grid, kBlock>>>(d, m.S, m.best);
  check(cudaGetLastError(), "kernel launch");
  download_array(&bits, m.best, 1);
  double dt = 0;
  std::memcpy(&dt, &bits, sizeof dt);
  return dt;
}

bool FlatRun::nonfinite() const {
  const FlatSystem& d = impl_->d;
  if (!d.nonfinite) return false;
  uint8_t flag = 0;
  download_array(&flag, d.nonfinite, 1);
  return flag != 0;
}

double FlatRun::device_seconds() {
  const double s = impl_->seconds;
  impl_->seconds = 0;
  return s;
}

void FlatRun::download(const FlatSystem& h) const {
  const FlatSystem& d = impl_->d;
  const uint64_t n = d.n, nb = d.nb;
  check(cudaDeviceSynchronize(), "cudaDeviceSynchronize");
  download_array(h.u, d.u, 3 * n);
  download_array(h.v, d.v, 3 * n);
  download_array(h.f, d.f, 3 * n);
  if (h.positions) download_array(h.positions, d.positions, 3 * n);
  download_array(h.intact, d.intact, nb);
  download_array(h.damage, d.damage, n);
  download_array(h.energy, d.energy, n);
  download_array(h.dissipated, d.dissipated, n);
  download_array(h.theta, d.theta, n);
  download_array(h.P, d.P, n);
  download_array(h.intact_weight, d.intact_weight, n);
  download_array(h.min_stretch, d.min_stretch, n);
  if (h.ledger) download_array(h.ledger, d.ledger, 1);
  download_array(h.u_before, d.u_before, 3 * d.ntracked);
  download_array(h.v_before, d.v_before, 3 * d.ntracked);
  download_array(h.entry_reaction, d.entry_reaction, 3 * d.nentries);
  if (h.damped) download_array(h.damped, d.damped, n);
  if (h.correspondence) {  // the model's state (solver/flat_affine_copy.cpp writes it back)
    const kernels::FlatAffine &a = h.affine, &da = d.affine;
    download_array(a.record, da.record, kernels::kAffineRecord * n);
    download_array(a.y_old, da.y_old, n);
    download_array(a.work, da.work, n);
    download_array(a.von_mises, da.von_mises, n);
    download_array(a.singular, da.singular, n);
    if (a.j2_committed) download_array(a.j2_committed, da.j2_committed, n), download_array(a.j2_trial, da.j2_trial, n);
    if (a.lambda3_committed)
      download_array(a.lambda3_committed, da.lambda3_committed, n), download_array(a.lambda3_trial, da.lambda3_trial, n);
    if (a.hypo_committed) {
      download_array(a.hypo_committed, da.hypo_committed, n);
      download_array(a.hypo_trial, da.hypo_trial, n);
      download_array(a.u_committed, da.u_committed, 3 * n);
      download_array(a.kinv, da.kinv, 9 * n);
      download_array(a.F, da.F, 9 * n);
      download_array(a.sigma, da.sigma, 9 * n);
      download_array(a.d, da.d, 9 * n);
    }
  }
  if (h.ordinary) download_ordinary(*h.ordinary, impl_->ordinary, n, nb);
  if (h.tupek) {
    download_array(h.eps, d.eps, nb);
    download_array(h.nonlocal_damage, d.nonlocal_damage, n);
  }
}

}  // namespace horizon::cuda
