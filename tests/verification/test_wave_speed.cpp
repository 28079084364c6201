#include <gtest/gtest.h>
#include <chrono>
#include <cstdio>
#include "verification_support.hpp"

namespace horizon::verification {
namespace {

std::string rep(std::string s, const std::string& a, const std::string& b) { auto p = s.find(a); return s.replace(p, a.size(), b); }

const char* const k3D = R"(dimension: 3
spacing: 1.0e-3
horizon: 3.0e-3
partial_volume: PV
materials:
  steel: {model: lps, density: 8000, youngs_modulus: 200.0e9, poissons_ratio: 0.25}
bodies:
  - {name: bar, material: steel, shape: {box: {min: [0, 0, 0], max: [0.36, WW, WW]}}}
initial_conditions:
  - velocity: ["abs(x-0.06) < 0.05 ? 0.5*(1+cos(pi*(x-0.06)/0.05)) : 0", 0, 0]
solver: {end_time: 6.0e-5}
)";

void one(std::string deck) {
  auto t0 = std::chrono::steady_clock::now();
  Simulation sim(parse_deck(deck, "3d"));
  auto& P = sim.system.particles;
  const double xa = P.X[sim.nearest({0.13, 0, 0})].x, xb = P.X[sim.nearest({0.28, 0, 0})].x;
  std::vector<std::size_t> la, lb;
  for (std::size_t i = 0; i < P.size(); ++i) {
    if (std::abs(P.X[i].x - xa) < 1e-6) la.push_back(i);
    if (std::abs(P.X[i].x - xb) < 1e-6) lb.push_back(i);
  }
  StationRecord ra, rb;
  auto mean = [&](const std::vector<std::size_t>& l) { double s = 0; for (auto i : l) s += P.v[i].x; return s / l.size(); };
  sim.run_to(6e-5, [&] {
    ra.add(sim.solver->time(), mean(la));
    rb.add(sim.solver->time(), mean(lb));
  });
  const double dx = xb - xa;
  const double c_half = dx / (*rb.half_max_arrival() - *ra.half_max_arrival());
  const double c_peak = dx / (*rb.peak_time() - *ra.peak_time());
  double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("3D n=%zu bonds=%zu: c0 5000 half %.2f peak %.2f  steps %ld peaks %g %g  %.1fs\n", P.size(), sim.system.bonds.size(), c_half, c_peak, (long)sim.solver->steps(), ra.peak(), rb.peak(), secs);
}
TEST(WaveSpeed, Bar3D) {
  one(rep(rep(rep(k3D, "WW", "0.01"), "WW", "0.01"), "PV", "true"));
  one(rep(rep(rep(k3D, "WW", "0.01"), "WW", "0.01"), "PV", "false"));
}

}  // namespace
}  // namespace horizon::verification
