// Directed bond evaluations per second of the CUDA backend (issue 30's figures), on the
// cubic lattice of tests/gpu/lattice.hpp (horizon 3 spacings, 122 neighbours inside):
//   bench_cuda MODEL NX NY NZ STEPS     (MODEL pmb, lps or tupek: the nonlinear solid, log strain)
// prints the lattice, the device time of STEPS steps after one warm-up step, the bond
// evaluations per second (directed bonds x steps / time; LPS visits each bond twice a
// step and counts once), and the device's copy bandwidth measured in the same run. The
// striker keeps the bonds breaking near it; the rest is elastic.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "horizon/cuda/cuda_backend.hpp"
#include "../../tests/gpu/lattice.hpp"

int main(int argc, char** argv) {
  if (argc != 6) {
    std::fprintf(stderr, "usage: bench_cuda pmb|lps|tupek NX NY NZ STEPS\n");
    return 2;
  }
  const std::string model = argv[1];
  const int nx = std::atoi(argv[2]), ny = std::atoi(argv[3]), nz = std::atoi(argv[4]);
  const long steps = std::atol(argv[5]);
  std::string why;
  if (!horizon::cuda::device_available(why)) {
    std::printf("SKIPPED: %s\n", why.c_str());
    return 77;
  }
  const auto t0 = std::chrono::steady_clock::now();
  horizon::test::Lattice L = model == "tupek" ? horizon::test::make_tupek_lattice(nx, ny, nz)
                                              : horizon::test::make_lattice(nx, ny, nz, model == "lps");
  const double build = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const horizon::kernels::FlatSystem view = L.view();
  horizon::cuda::FlatRun run(view);
  run.advance(1);  // warm-up
  run.device_seconds();
  run.advance(steps);
  const double seconds = run.device_seconds();
  run.download(view);
  const auto totals = horizon::kernels::flat_totals(view);
  const double bonds = static_cast<double>(L.nbr.size());
  const double bandwidth = horizon::cuda::copy_bandwidth(1ull << 32);
  // Bytes a directed bond streams per step (neighbour 4, kind 4, intact 1; LPS adds |Y|
  // written and read, 16, and reads the row's bonds twice, 9 more; the nonlinear solid
  // reads the row's bonds in both sweeps and writes and reads its strain, 16).
  const double bytes = model == "lps" || model == "tupek" ? 34.0 : 9.0;
  std::printf("bench_cuda %s: %llu particles, %.4g directed bonds (lattice built in %.1f s), %ld steps in %.4g s "
              "on the device: %.4g directed bond evaluations per second; %.0f B/bond streamed is %.3g TB/s, "
              "%.1f %% of the measured copy bandwidth %.3g TB/s (read + write); kinetic %.6g J, mean damage %.6g\n",
              model.c_str(), static_cast<unsigned long long>(L.n), bonds, build, steps, seconds,
              bonds * steps / seconds, bytes, bytes * bonds * steps / seconds * 1e-12,
              100 * bytes * bonds * steps / seconds / bandwidth, bandwidth * 1e-12, totals.kinetic,
              totals.mean_damage);
  return 0;
}
