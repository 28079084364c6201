// Results do not depend on the number of threads (DESIGN.md, "Data"): each particle's
// sums run over its own row in a fixed order. 50 explicit steps with bond breaking on
// 1 and on 2 threads must give the same displacements, bit for bit.
#include <gtest/gtest.h>
#include <omp.h>

#include <cstdio>
#include <cstring>
#include <vector>

#include "horizon/deck/deck.hpp"
#include "horizon/loading/loads.hpp"
#include "horizon/solver/explicit.hpp"
#include "horizon/solver/forces.hpp"
#include "test_helpers.hpp"

namespace horizon {
namespace {

// A small piece of the glass-branching example (2-D PMB, plane stress, fracture energy
// 3.8 J/m^2, notch to the centre), pulled apart fast enough to break bonds in 50 steps.
const char* const kGlassDeck = R"deck(dimension: 2
plane: stress
thickness: 1.0e-3
spacing: 2.5e-4
horizon: 1.0e-3
materials:
  glass:
    model: pmb
    density: 2440
    youngs_modulus: 72.0e9
    damage: {fracture_energy: 3.8}
bodies:
  - name: plate
    material: glass
    shape: {box: {min: [-0.005, -0.0025], max: [0.005, 0.0025]}}
precracks:
  - {from: [-0.0051, 0.0], to: [0.0, 0.0]}
regions:
  top:    {box: {min: [-0.005, 0.00225], max: [0.005, 0.0025]}}
  bottom: {box: {min: [-0.005, -0.0025], max: [0.005, -0.00225]}}
initial_conditions:
  - {velocity: ["0.1*sin(3000*x)", "600*y"]}
loads:
  - {region: top,    traction: [0, 2.0e8]}
  - {region: bottom, traction: [0, -2.0e8]}
solver: {end_time: 1.0e-5, safety_factor: 0.8}
)deck";

struct RunResult {
  std::vector<Vec3> u, v;
  std::vector<double> damage, dissipated_at;
  uint64_t broken = 0;
};

RunResult run_glass(int threads) {
  omp_set_num_threads(threads);
  const Config config = parse_deck(kGlassDeck, "glass_threads.yaml");
  System s = build_system(config);
  Loads loads(config, s);
  loads.apply_initial_conditions(config, s);
  ExplicitSolver solver(s, loads, config.solver.safety_factor * stable_time_step(s), 0.0);
  solver.initialize();
  for (int step = 0; step < 50; ++step) solver.step(step % 10 == 0);
  return {s.particles.u, s.particles.v, s.particles.damage, s.dissipated_at, s.broken};
}

// A 3-D LPS block with a critical stretch, random initial velocities.
RunResult run_lps(int threads) {
  omp_set_num_threads(threads);
  test::BlockSpec b;
  b.n = {7, 7, 7};
  b.horizon_factor = 3;
  b.partial_volume = true;
  MaterialConfig mat = test::make_material("lps", 1e9, 0.3, 1000, InfluenceKind::inverse);
  mat.damage.enabled = true;
  mat.damage.critical_stretch = 1e-3;
  System s = test::make_block(b, mat);
  test::Rng rng(99);
  for (auto& v : s.particles.v) v = Vec3{rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-2, 2)};
  Loads loads;
  ExplicitSolver solver(s, loads, 0.8 * stable_time_step(s), 0.0);
  solver.initialize();
  for (int step = 0; step < 50; ++step) solver.step(step % 10 == 0);
  return {s.particles.u, s.particles.v, s.particles.damage, s.dissipated_at, s.broken};
}

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

void expect_identical(const RunResult& one, const RunResult& two, const char* name) {
  std::printf("[ threads ] %s: %llu bonds broken on 1 thread, %llu on 2\n", name,
              static_cast<unsigned long long>(one.broken), static_cast<unsigned long long>(two.broken));
  EXPECT_GT(one.broken, 0u) << name << ": the run is meant to break bonds";
  EXPECT_EQ(one.broken, two.broken) << name;
  EXPECT_TRUE(same_bits(one.u, two.u)) << name << ": displacements differ between 1 and 2 threads";
  EXPECT_TRUE(same_bits(one.v, two.v)) << name << ": velocities differ";
  EXPECT_TRUE(same_bits(one.damage, two.damage)) << name << ": damage differs";
  EXPECT_TRUE(same_bits(one.dissipated_at, two.dissipated_at)) << name << ": dissipated energy differs";
}

class Threads : public ::testing::Test {
 protected:
  void SetUp() override { saved_ = omp_get_max_threads(); }
  void TearDown() override { omp_set_num_threads(saved_); }
  int saved_ = 1;
};

TEST_F(Threads, GlassPmbWithDamageIsBitIdenticalOnOneAndTwoThreads) {
  const RunResult one = run_glass(1), two = run_glass(2);
  expect_identical(one, two, "2-D PMB glass");
}

TEST_F(Threads, Lps3dWithDamageIsBitIdenticalOnOneAndTwoThreads) {
  const RunResult one = run_lps(1), two = run_lps(2);
  expect_identical(one, two, "3-D LPS");
}

}  // namespace
}  // namespace horizon
