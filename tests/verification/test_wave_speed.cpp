#include <gtest/gtest.h>
#include <cstdio>
#include "verification_support.hpp"

namespace horizon::verification {
namespace {

const char* const k1D = R"(dimension: 1
area: 1.0e-4
spacing: 1.0e-3
horizon: 3.0e-3
partial_volume: true
materials:
  steel: {model: pmb, density: 8000, youngs_modulus: 200.0e9}
bodies:
  - {name: bar, material: steel, shape: {box: {min: [0], max: [1.0]}}}
initial_conditions:
  - velocity: ["abs(x-0.2) < 0.05 ? 0.5*(1+cos(pi*(x-0.2)/0.05)) : 0"]
solver: {end_time: 1.5e-4}
)";

TEST(WaveSpeed, Bar1D) {
  Simulation sim(parse_deck(k1D, "1d"));
  const std::size_t a = sim.nearest({0.4, 0, 0}), b = sim.nearest({0.8, 0, 0});
  StationRecord ra, rb;
  sim.run_to(1.5e-4, [&] {
    ra.add(sim.solver->time(), sim.system.particles.v[a].x);
    rb.add(sim.solver->time(), sim.system.particles.v[b].x);
  });
  const double dx = sim.system.particles.X[b].x - sim.system.particles.X[a].x;
  const double c_half = dx / (*rb.half_max_arrival() - *ra.half_max_arrival());
  const double c_peak = dx / (*rb.peak_time() - *ra.peak_time());
  std::printf("1D: c0 5000 half %.2f peak %.2f  steps %ld peaks %g %g\n", c_half, c_peak, (long)sim.solver->steps(), ra.peak(), rb.peak());
}

}  // namespace
}  // namespace horizon::verification
