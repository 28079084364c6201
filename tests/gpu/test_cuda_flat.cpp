// The CUDA backend (src/horizon/cuda/) against the host's portable rows (label gpu;
// bench/gpu/device_check.sh runs it on the device machine): a striker breaking into a bar
// of a cubic lattice, PMB and LPS, without and with loads (lattice.hpp add_loads: a clamped
// end, a held velocity, a body force, and their work), 200 steps on the device (in two
// calls, with a copy back between them) and on the host with kernels::advance_flat. The
// device runs the host's operations in the host's order (one thread a row, the lanes of
// kernels::for_each_lane, -fmad=false), so the
// answers should be the same bits; the test asks for final mean damage and kinetic
// energy within 1e-9 relative (issue 30) and prints whether the bits agree.
// Exits 77 (ctest: skipped) with a message when no CUDA device is present.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

#include "horizon/cuda/cuda_backend.hpp"
#include "lattice.hpp"

namespace {

using horizon::test::Lattice;

double rel(double a, double b) { return std::abs(a - b) / std::max(std::abs(b), 1e-300); }

bool compare(bool lps, bool loads) {
  const char* name = loads ? (lps ? "lps with loads" : "pmb with loads") : (lps ? "lps" : "pmb");
  Lattice host = horizon::test::make_lattice(24, 10, 10, lps);
  if (loads) horizon::test::add_loads(host, 24, 1e9);
  Lattice dev = host;
  const horizon::kernels::FlatSystem hv = host.view(), dv = dev.view();
  const uint64_t broken = horizon::kernels::advance_flat(hv, 200);
  {
    horizon::cuda::FlatRun run(dv);
    run.advance(120);
    run.download(dv);  // a frame's copy in the middle changes nothing on the device
    run.advance(80);
    run.download(dv);
  }
  const auto h = horizon::kernels::flat_totals(hv), d = horizon::kernels::flat_totals(dv);
  const bool same_u = std::memcmp(host.u.data(), dev.u.data(), host.u.size() * sizeof(double)) == 0;
  const bool same_intact = host.intact == dev.intact;
  const bool same_work = host.ledger == dev.ledger && host.entry_reaction == dev.entry_reaction;
  std::printf("%s: %llu particles, %llu bonds, %llu broken on the host; kinetic %.17g (host) %.17g (device), "
              "mean damage %.17g (host) %.17g (device); displacements %s, intact flags %s, loads' work %.17g (host) "
              "%.17g (device), %s\n",
              name, static_cast<unsigned long long>(host.n), static_cast<unsigned long long>(host.nbr.size()),
              static_cast<unsigned long long>(broken), h.kinetic, d.kinetic, h.mean_damage, d.mean_damage,
              same_u ? "the same bits" : "differ", same_intact ? "the same" : "differ", host.ledger[0], dev.ledger[0],
              same_work ? "the same bits" : "differ");
  bool ok = true;
  if (loads && !(rel(dev.ledger[0], host.ledger[0]) <= 1e-9 && host.ledger[0] != 0))
    std::printf("%s: FAILED: the loads' work differs (or is 0)\n", name), ok = false;
  if (!(broken > 0 && h.mean_damage > 0)) std::printf("%s: FAILED: the impact broke no bond\n", name), ok = false;
  if (!(rel(d.kinetic, h.kinetic) <= 1e-9)) std::printf("%s: FAILED: kinetic energy differs by %.3g relative\n", name, rel(d.kinetic, h.kinetic)), ok = false;
  if (!(rel(d.mean_damage, h.mean_damage) <= 1e-9))
    std::printf("%s: FAILED: mean damage differs by %.3g relative\n", name, rel(d.mean_damage, h.mean_damage)), ok = false;
  return ok;
}

}  // namespace

int main() {
  std::string why;
  if (!horizon::cuda::device_available(why)) {
    std::printf("SKIPPED: %s (the GPU tests need a CUDA device)\n", why.c_str());
    return 77;
  }
  const bool pmb = compare(false, false), lps = compare(true, false);
  const bool loaded = compare(false, true) && compare(true, true);
  std::printf("%s\n", pmb && lps && loaded ? "PASSED" : "FAILED");
  return pmb && lps && loaded ? 0 : 1;
}
