// The CUDA backend (src/horizon/cuda/) against the host's portable rows (label gpu;
// bench/gpu/device_check.sh runs it on the device machine): a striker breaking into a bar
// of a cubic lattice, PMB, LPS, Tupek's nonlinear solid (its stable step too),
// elastic_plastic, viscoelastic, microplastic and pals (kernels/flat_ordinary.hpp) and the correspondence
// model (J2, stabilised: lattice.hpp make_affine_lattice), without
// and with loads (lattice.hpp add_loads: a clamped
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
#include <vector>

#include "horizon/cuda/cuda_backend.hpp"
#include "lattice.hpp"

namespace {

using horizon::test::Lattice;

double rel(double a, double b) { return std::abs(a - b) / std::max(std::abs(b), 1e-300); }

// model: "pmb", "lps", or "tupek" (the nonlinear solid with the log strain, m = 0) and
// "tupek_m05" (m = 1/2: the strain is sqrt(c) - 1, no log or expm1 whose device and host
// libraries may round differently).
bool compare(const std::string& model, bool loads, bool peridigm = false) {
  const std::string label = model + (loads ? " with loads" : "") + (peridigm ? ", verlet: peridigm" : "");
  const char* name = label.c_str();
  const bool tupek = model.rfind("tupek", 0) == 0, affine = model == "correspondence";
  const bool ordinary =
      model == "elastic_plastic" || model == "viscoelastic" || model == "microplastic" || model == "pals";
  Lattice host = tupek       ? horizon::test::make_tupek_lattice(24, 10, 10, model == "tupek_m05" ? 0.5 : 0.0)
                 : model == "microplastic" ? horizon::test::make_micro_lattice(24, 10, 10)
                 : model == "pals"         ? horizon::test::make_pals_lattice(24, 10, 10)
                 : ordinary ? horizon::test::make_ordinary_lattice(24, 10, 10, model == "elastic_plastic")
                 : affine   ? horizon::test::make_affine_lattice(24, 10, 10)
                            : horizon::test::make_lattice(24, 10, 10, model == "lps");
  if (loads) horizon::test::add_loads(host, 24, 1e9);
  if (peridigm) horizon::test::set_peridigm(host);
  Lattice dev = host;
  const horizon::kernels::FlatSystem hv = host.view(), dv = dev.view();
  const uint64_t broken = horizon::kernels::advance_flat(hv, 200);
  double device_dt = 0, host_dt = 0;
  {
    horizon::cuda::FlatRun run(dv);
    run.advance(120);
    run.download(dv);  // a frame's copy in the middle changes nothing on the device
    run.advance(80);
    run.download(dv);
    if (tupek) {  // the adaptive step's stable step of the final state, on the device and the host
      device_dt = run.stable_time_step();
      std::vector<double> S(host.n);
      host_dt = horizon::kernels::flat_tupek_stable_step(hv, S.data());
    }
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
  if (tupek) {
    const bool same_eps = std::memcmp(host.eps.data(), dev.eps.data(), host.eps.size() * sizeof(double)) == 0;
    std::printf("%s: bond strains %s; stable step %.17g (host) %.17g (device), %s\n", name,
                same_eps ? "the same bits" : "differ", host_dt, device_dt, host_dt == device_dt ? "the same bits" : "differ");
    if (!(rel(device_dt, host_dt) <= 1e-12 && host_dt > 0 && host_dt < INFINITY))
      std::printf("%s: FAILED: the stable step differs by %.3g relative\n", name, rel(device_dt, host_dt)), ok = false;
    double dh = 0, dd = 0;  // the energy of the broken bonds, summed in particle order
    for (uint64_t i = 0; i < host.n; ++i) dh += host.dissipated[i], dd += dev.dissipated[i];
    std::printf("%s: dissipated %.17g (host) %.17g (device)\n", name, dh, dd);
    if (!(dh > 0 && rel(dd, dh) <= 1e-9)) std::printf("%s: FAILED: the dissipation differs (or is 0)\n", name), ok = false;
  }
  if (affine) {  // the plastic work and the broken bonds' energy, and the law's history
    double dh = 0, dd = 0;
    for (uint64_t i = 0; i < host.n; ++i) dh += host.dissipated[i], dd += dev.dissipated[i];
    const bool same_history = std::memcmp(host.j2_committed.data(), dev.j2_committed.data(),
                                          host.n * sizeof(horizon::kernels::J2History)) == 0;
    std::printf("%s: dissipated %.17g (host) %.17g (device); J2 history %s\n", name, dh, dd,
                same_history ? "the same bits" : "differs");
    if (!(dh > 0 && rel(dd, dh) <= 1e-9)) std::printf("%s: FAILED: the dissipation differs (or is 0)\n", name), ok = false;
  }
  if (ordinary) {  // the history (e^dp or the back extensions), q and the dissipation (plastic or viscous, and the bonds')
    const std::vector<double>& hh = model == "elastic_plastic" ? host.o_ep : model == "microplastic" ? host.o_sbar : host.o_back[0];
    const std::vector<double>& dh_ = model == "elastic_plastic" ? dev.o_ep : model == "microplastic" ? dev.o_sbar : dev.o_back[0];
    const bool same_history = std::memcmp(hh.data(), dh_.data(), hh.size() * sizeof(double)) == 0 &&
                              host.o_current == dev.o_current &&
                              std::memcmp(host.o_q[0].data(), dev.o_q[0].data(), host.o_q[0].size() * sizeof(double)) == 0 &&
                              std::memcmp(host.o_q[1].data(), dev.o_q[1].data(), host.o_q[1].size() * sizeof(double)) == 0;
    double dh = 0, dd = 0;
    for (uint64_t i = 0; i < host.n; ++i) dh += host.dissipated[i], dd += dev.dissipated[i];
    std::printf("%s: history and force scalars %s; dissipated %.17g (host) %.17g (device)\n", name,
                same_history ? "the same bits" : "differ", dh, dd);
    if (!(dh != 0 && rel(dd, dh) <= 1e-9)) std::printf("%s: FAILED: the dissipation differs (or is 0)\n", name), ok = false;
  }
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
  const bool pmb = compare("pmb", false), lps = compare("lps", false);
  const bool loaded = compare("pmb", true) && compare("lps", true);
  // The nonlinear solid (kernels/tupek.hpp rows), the log strain and m = 1/2, and with loads.
  const bool tupek = compare("tupek", false) && compare("tupek_m05", false) && compare("tupek", true);
  // The ordinary history models (kernels/flat_ordinary.hpp), without and with loads.
  const bool ordinary = compare("elastic_plastic", false) && compare("viscoelastic", false) &&
                        compare("elastic_plastic", true) && compare("viscoelastic", true) &&
                        compare("microplastic", false) && compare("microplastic", true) && compare("pals", false) &&
                        compare("pals", true);
  // The correspondence model (kernels/flat_affine.hpp rows: J2, stabilised), with loads too.
  const bool affine = compare("correspondence", false) && compare("correspondence", true);
  // solver.verlet: peridigm (Peridigm's kicks, the positions apart from u, the clamp's increments).
  const bool peridigm = compare("pmb", true, true) && compare("lps", true, true) && compare("elastic_plastic", true, true);
  const bool ok = pmb && lps && loaded && tupek && ordinary && affine && peridigm;
  std::printf("%s\n", ok ? "PASSED" : "FAILED");
  return ok ? 0 : 1;
}
