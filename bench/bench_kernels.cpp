// Kernel benchmarks: the force pass (PMB, LPS) and the neighbour search on a 3-D
// block, horizon = 3 spacings. Throughput is reported as directed bonds per second.
//   build/bench/bench_kernels --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>
#include <omp.h>

#include "horizon/family/neighbors.hpp"
#include "horizon/geometry/lattice.hpp"
#include "horizon/solver/forces.hpp"
#include "horizon/solver/system.hpp"

namespace {

using namespace horizon;

Config block_config(int n, ModelKind model, bool damage) {
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
  c.materials.push_back(m);
  const double L = n * c.spacing;
  c.bodies.push_back({"block", "m", Shape::box({0, 0, 0}, {L, L, L})});
  return c;
}

System make_block(int n, ModelKind model) {
  System s = build_system(block_config(n, model, true));
  for (std::size_t i = 0; i < s.particles.size(); ++i) s.particles.u[i] = s.particles.X[i] * 1e-4;
  return s;
}

void force_pass(benchmark::State& state, ModelKind model) {
  omp_set_num_threads(static_cast<int>(state.range(1)));
  System s = make_block(static_cast<int>(state.range(0)), model);
  for (auto _ : state) {
    compute_forces(s, false);
    benchmark::DoNotOptimize(s.particles.f.data());
  }
  state.counters["bonds"] = static_cast<double>(s.bonds.size());
  state.counters["bonds_per_s"] = benchmark::Counter(static_cast<double>(s.bonds.size()) * state.iterations(),
                                                     benchmark::Counter::kIsRate);
}

void BM_PmbForce(benchmark::State& state) { force_pass(state, ModelKind::pmb); }
void BM_LpsForce(benchmark::State& state) { force_pass(state, ModelKind::lps); }

void BM_NeighborSearch(benchmark::State& state) {
  omp_set_num_threads(static_cast<int>(state.range(1)));
  const Config c = block_config(static_cast<int>(state.range(0)), ModelKind::pmb, false);
  Particles p;
  fill_shape(p, c.bodies[0].shape, {3, c.spacing, 1e-9, std::nullopt}, 1000, 0, 0);
  std::size_t bonds = 0;
  for (auto _ : state) {
    Bonds b = find_neighbors(p.X, p.volume, c.horizon);
    bonds = b.size();
    benchmark::DoNotOptimize(b.nbr.data());
  }
  state.counters["bonds_per_s"] =
      benchmark::Counter(static_cast<double>(bonds) * state.iterations(), benchmark::Counter::kIsRate);
}

}  // namespace

// Block of n^3 particles (n = 40: 64,000 particles, ~7e6 directed bonds), 1 and 2 threads.
BENCHMARK(BM_PmbForce)->Args({40, 1})->Args({40, 2})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_LpsForce)->Args({40, 1})->Args({40, 2})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_NeighborSearch)->Args({40, 1})->Args({40, 2})->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();
