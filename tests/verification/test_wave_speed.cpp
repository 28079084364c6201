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
  - {name: bar, material: steel, shape: {box: {min: [0, 0, 0], max: [LL, WW, WW]}}}
initial_conditions:
  - velocity: ["abs(x-CC) < HH ? 0.5*(1+cos(pi*(x-CC)/HH)) : 0", 0, 0]
solver: {end_time: 6.0e-5}
)";

void one(std::string deck, double x0, double x1, double tend) {
  auto t0 = std::chrono::steady_clock::now();
  Simulation sim(parse_deck(deck, "3d"));
  auto& P = sim.system.particles;
  std::vector<double> xs;
  std::vector<std::vector<std::size_t>> layers;
  std::vector<StationRecord> rec;
  for (double x = x0; x <= x1 + 1e-9; x += 0.02) {
    const double xa = P.X[sim.nearest({x, 0, 0})].x;
    xs.push_back(xa);
    layers.emplace_back();
    for (std::size_t i = 0; i < P.size(); ++i)
      if (std::abs(P.X[i].x - xa) < 1e-6) layers.back().push_back(i);
  }
  rec.resize(xs.size());
  auto mean = [&](const std::vector<std::size_t>& l) { double s = 0; for (auto i : l) s += P.v[i].x; return s / l.size(); };
  sim.run_to(tend, [&] {
    for (std::size_t k = 0; k < xs.size(); ++k) rec[k].add(sim.solver->time(), mean(layers[k]));
  });
  double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("3D n=%zu bonds=%zu steps %ld %.1fs\n", P.size(), sim.system.bonds.size(), (long)sim.solver->steps(), secs);
  for (std::size_t k = 1; k < xs.size(); ++k)
    std::printf("  x %.3f-%.3f  c_half %.1f  ta %.3e  peak %.4f\n", xs[k-1], xs[k], (xs[k]-xs[k-1])/(*rec[k].half_max_arrival()-*rec[k-1].half_max_arrival()), *rec[k].half_max_arrival(), rec[k].peak());
  std::printf("  overall %.1f\n", (xs.back()-xs[0])/(*rec.back().half_max_arrival()-*rec[0].half_max_arrival()));
}
std::string mk(std::string L, std::string W, std::string C, std::string H, std::string pv) {
  std::string d = k3D;
  d = rep(d, "LL", L); d = rep(rep(d, "WW", W), "WW", W); d = rep(rep(d, "CC", C), "CC", C);
  d = rep(rep(d, "HH", H), "HH", H); return rep(d, "PV", pv);
}
TEST(WaveSpeed, Bar3D) {
  one(mk("0.40", "0.01", "0.04", "0.03", "true"), 0.08, 0.34, 6.6e-5);
  one(mk("0.40", "0.01", "0.04", "0.03", "false"), 0.08, 0.34, 6.6e-5);
  one(mk("0.40", "0.008", "0.04", "0.03", "false"), 0.08, 0.34, 6.6e-5);
}

}  // namespace
}  // namespace horizon::verification
