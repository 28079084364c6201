// Kernel benchmarks (Google Benchmark): the force pass of the PMB (breaking, damage,
// force in one pass), the two passes of the LPS (dilatation; force), the neighbour
// search, and a memory-bandwidth probe (STREAM triad), on 3-D blocks of n^3 particles
// with horizon = 3 spacings. Throughput is in directed bonds per second.
//   build/bench/bench_kernels --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
// bench/scaling.py runs these and fits the growth exponent, the thread speed-up and the
// fraction of the bandwidth bound (docs/benchmarks.md).
#include <benchmark/benchmark.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <vector>

#include "horizon/family/neighbors.hpp"
#include "horizon/geometry/lattice.hpp"
#include "horizon/solver/forces.hpp"
#include "horizon/solver/build.hpp"

namespace {

using namespace horizon;

// `model` may end in "+sc": the material's surface_correction on (more bond kinds, the
// same loops: docs/benchmarks.md "Surface correction").
Config block_config(int n, const std::string& model_key, bool damage) {
  const bool corrected = model_key.size() > 3 && model_key.ends_with("+sc");
  const std::string model = corrected ? model_key.substr(0, model_key.size() - 3) : model_key;
  Config c;
  c.dimension = 3;
  c.spacing = 1e-3;
  c.horizon = 3e-3;
  MaterialConfig m;
  m.name = "m";
  m.model = model;
  m.density = 2000;
  m.youngs_modulus = 1e9;
  m.poissons_ratio = 0.25;
  m.bulk_modulus = m.youngs_modulus / (3 * (1 - 2 * m.poissons_ratio));
  m.shear_modulus = m.youngs_modulus / (2 * (1 + m.poissons_ratio));
  m.damage.enabled = damage;
  m.damage.critical_stretch = 1.0;  // never reached: measures the check, not the breaking
  if (corrected) m.parameters["surface_correction"] = 1;
  c.materials.push_back(m);
  const double L = n * c.spacing;
  c.bodies.push_back({"block", "m", Shape::box({0, 0, 0}, {L, L, L})});
  return c;
}

// One block per (n, model), built once and kept: the 1e6-particle block takes seconds.
System& block(int n, const std::string& model) {
  static std::map<std::pair<int, std::string>, std::unique_ptr<System>> cache;
  auto& slot = cache[{n, model}];
  if (!slot) {
    cache.clear();  // one block in memory at a time
    auto& fresh = cache[{n, model}];
    fresh = std::make_unique<System>(build_system(block_config(n, model, true)));
    for (std::size_t i = 0; i < fresh->particles.size(); ++i) fresh->particles.u[i] = fresh->particles.X[i] * 1e-4;
    return *fresh;
  }
  return *slot;
}

void report(benchmark::State& state, const System& s) {
  state.counters["particles"] = static_cast<double>(s.particles.size());
  state.counters["bonds"] = static_cast<double>(s.bonds.size());
  state.counters["kinds"] = static_cast<double>(s.bonds.kinds.size());
  state.counters["bonds_per_s"] = benchmark::Counter(static_cast<double>(s.bonds.size()) *
                                                         static_cast<double>(state.iterations()),
                                                     benchmark::Counter::kIsRate);
  state.SetLabel(kernel_path_name());
}

void BM_PmbForce(benchmark::State& state) {
  omp_set_num_threads(static_cast<int>(state.range(1)));
  System& s = block(static_cast<int>(state.range(0)), "pmb");
  for (auto _ : state) {
    compute_forces(s, false);
    benchmark::DoNotOptimize(s.particles.f.data());
  }
  report(state, s);
}

// The same force pass with each bond stored once (j > i only), its force added to
// both ends: half the square roots and divisions, but the force on j is scattered to
// another particle's row, so threads need atomics and the sum order depends on the
// thread count. Measured here to decide the storage (docs/benchmarks.md); scalar, like
// the portable path of compute_forces, which it should be compared with.
void BM_PmbHalfBonds(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(1));
  omp_set_num_threads(threads);
  System& s = block(static_cast<int>(state.range(0)), "pmb");
  compute_forces(s, false);
  const auto& B = s.bonds;
  const auto& M = s.model;
  const std::size_t n = s.particles.size();
  std::vector<double> f(3 * n);
  for (auto _ : state) {
    std::fill(f.begin(), f.end(), 0.0);
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      const Point4 pi = M.packed[i];
      double fx = 0, fy = 0, fz = 0;
      for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
        const uint32_t j = B.nbr[k];
        if (j < i || !B.intact[k]) continue;
        const KindCoefficients& c = M.kind[B.kind[k]];
        const Point4 pj = M.packed[j];
        const double Yx = pj.x - pi.x, Yy = pj.y - pi.y, Yz = pj.z - pi.z;
        const double r = std::sqrt(Yx * Yx + Yy * Yy + Yz * Yz), e = r - c.length;
        const double stretch = e * c.inv_length;
        if (stretch > std::min(pi.w, pj.w)) continue;
        const double a = c.pair * e / r;
        fx += a * Yx, fy += a * Yy, fz += a * Yz;
        if (threads == 1) {
          f[3 * j] -= a * Yx, f[3 * j + 1] -= a * Yy, f[3 * j + 2] -= a * Yz;
        } else {
#pragma omp atomic
          f[3 * j] -= a * Yx;
#pragma omp atomic
          f[3 * j + 1] -= a * Yy;
#pragma omp atomic
          f[3 * j + 2] -= a * Yz;
        }
      }
#pragma omp atomic
      f[3 * i] += fx;
#pragma omp atomic
      f[3 * i + 1] += fy;
#pragma omp atomic
      f[3 * i + 2] += fz;
    }
    benchmark::DoNotOptimize(f.data());
  }
  report(state, s);
  state.SetLabel("scalar, bonds once");
}

void BM_PmbForceScalar(benchmark::State& state) {
  set_kernel_path(KernelPath::scalar);
  BM_PmbForce(state);
  set_kernel_path(KernelPath::automatic);
}

void BM_LpsDilatation(benchmark::State& state) {
  omp_set_num_threads(static_cast<int>(state.range(1)));
  System& s = block(static_cast<int>(state.range(0)), "lps");
  compute_forces(s, false);
  for (auto _ : state) {
    benchmark::DoNotOptimize(state_based_dilatation_pass(s));
  }
  report(state, s);
}

void BM_LpsForce(benchmark::State& state) {
  omp_set_num_threads(static_cast<int>(state.range(1)));
  System& s = block(static_cast<int>(state.range(0)), "lps");
  compute_forces(s, false);
  for (auto _ : state) {
    state_based_force_pass(s, false);
    benchmark::DoNotOptimize(s.particles.f.data());
  }
  report(state, s);
}

// The PMB force pass and both LPS passes with the surface correction on (the same loops,
// more bond kinds: material/surface_correction.hpp).
void BM_PmbForceCorrected(benchmark::State& state) {
  omp_set_num_threads(static_cast<int>(state.range(1)));
  System& s = block(static_cast<int>(state.range(0)), "pmb+sc");
  for (auto _ : state) {
    compute_forces(s, false);
    benchmark::DoNotOptimize(s.particles.f.data());
  }
  report(state, s);
}

void BM_LpsStepCorrected(benchmark::State& state) {
  omp_set_num_threads(static_cast<int>(state.range(1)));
  System& s = block(static_cast<int>(state.range(0)), "lps+sc");
  for (auto _ : state) {
    compute_forces(s, false);
    benchmark::DoNotOptimize(s.particles.f.data());
  }
  report(state, s);
}

// Both LPS passes, as compute_forces runs them.
void BM_LpsStep(benchmark::State& state) {
  omp_set_num_threads(static_cast<int>(state.range(1)));
  System& s = block(static_cast<int>(state.range(0)), "lps");
  for (auto _ : state) {
    compute_forces(s, false);
    benchmark::DoNotOptimize(s.particles.f.data());
  }
  report(state, s);
}

void BM_NeighborSearch(benchmark::State& state) {
  omp_set_num_threads(static_cast<int>(state.range(1)));
  const Config c = block_config(static_cast<int>(state.range(0)), "pmb", false);
  Particles p;
  fill_shape(p, c.bodies[0].shape, {3, c.spacing, 1e-9, std::nullopt}, 1000, 0, 0);
  std::size_t bonds = 0;
  for (auto _ : state) {
    Bonds b = find_neighbors(p.X, p.volume, c.horizon);
    bonds = b.size();
    benchmark::DoNotOptimize(b.nbr.data());
  }
  state.counters["bonds_per_s"] =
      benchmark::Counter(static_cast<double>(bonds) * static_cast<double>(state.iterations()),
                         benchmark::Counter::kIsRate);
}

// Memory bandwidth: the STREAM triad a = b + s c on arrays far larger than the caches.
// Bytes counted: 24 per element (read b, c; write a), as STREAM does.
void BM_Triad(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0));
  omp_set_num_threads(threads);
  const std::size_t n = std::size_t{1} << 25;  // 256 MiB per array
  std::vector<double> a(n), b(n, 1.0), c(n, 2.0);
  const double s = 3.0;
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) a[i] = 0;  // first touch by the threads that use it
  for (auto _ : state) {
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) a[i] = b[i] + s * c[i];
    benchmark::DoNotOptimize(a.data());
    benchmark::ClobberMemory();
  }
  state.counters["bytes_per_s"] = benchmark::Counter(24.0 * static_cast<double>(n) * static_cast<double>(state.iterations()),
                                                     benchmark::Counter::kIsRate);
}

}  // namespace

// Blocks of n^3 particles: n = 22 (1.06e4 particles), 47 (1.04e5), 100 (1e6; about
// 1.2e8 directed bonds); 1 and 2 threads. The LPS passes on the middle size only.
BENCHMARK(BM_PmbForce)
    ->ArgsProduct({{22, 47, 100}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(1.0);
BENCHMARK(BM_PmbForceScalar)->ArgsProduct({{47}, {1, 2}})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_PmbHalfBonds)->ArgsProduct({{47}, {1, 2}})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_LpsDilatation)->ArgsProduct({{47}, {1, 2}})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_LpsForce)->ArgsProduct({{47}, {1, 2}})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_LpsStep)->ArgsProduct({{47}, {1, 2}})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_PmbForceCorrected)->ArgsProduct({{47}, {1, 2}})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_LpsStepCorrected)->ArgsProduct({{47}, {1, 2}})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_NeighborSearch)->ArgsProduct({{47}, {1, 2}})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Triad)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();
