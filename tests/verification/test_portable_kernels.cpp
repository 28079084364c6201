// The device-portable kernels (src/horizon/kernels/, issue 30) against the host's own
// passes: a run stepped over flat arrays with the portable row functions
// (kernels/flat_system.hpp advance_flat, the code the CUDA backend launches) gives the
// SIMD fast loops' answer on 40 steps of a breaking impact, PMB and LPS: the same
// displacements, velocities, damage, strain and kinetic energy and dissipation, bit for bit,
// and the same broken bonds (model_checks.hpp impact_deck at 40 m/s, bonds breaking at a
// stretch of 0.2 %). The portable rows sum each row in the fast loops' eight lanes, in
// the same order, so the bits agree (tests/regression/test_backend.cpp runs whole decks).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "horizon/solver/flat_copy.hpp"
#include "horizon/solver/forces.hpp"
#include "model_checks.hpp"

namespace horizon::verification {
namespace {

const std::string kPmb = "{model: pmb, density: 7850, youngs_modulus: 200.0e9, damage: {critical_stretch: 0.002}}";
const std::string kLps =
    "{model: lps, density: 7850, youngs_modulus: 200.0e9, poissons_ratio: 0.3, damage: {critical_stretch: 0.002}}";

// max_i |a_i - b_i| / max_i |b_i| over the components.
double relative(const std::vector<double>& a, const std::vector<double>& b) {
  double diff = 0, scale = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    diff = std::max(diff, std::abs(a[i] - b[i]));
    scale = std::max(scale, std::abs(b[i]));
  }
  return scale > 0 ? diff / scale : diff;
}
std::vector<double> flat(const std::vector<Vec3>& a) {
  std::vector<double> out;
  for (const Vec3& x : a) out.insert(out.end(), {x.x, x.y, x.z});
  return out;
}
double rel(double a, double b) { return std::abs(a - b) / std::max(std::abs(b), 1e-300); }

void compare(const std::string& material, bool state_based) {
  test::SingleThread one;
  Simulation sim(parse_deck(impact_deck(material, 40, 1.0), "portable.yaml"));
  ASSERT_EQ(flat_unsupported(sim.system, sim.loads), "");
  ASSERT_EQ(sim.system.model.state_based, state_based);
  FlatStorage copy = flat_copy(sim.system, sim.solver->dt(), sim.config.solver.damping);
  const kernels::FlatSystem view = copy.view();
  const uint64_t broken_before = sim.system.broken;
  for (int n = 0; n < 40; ++n) sim.solver->step(true);
  const uint64_t flat_broken = kernels::advance_flat(view, 40);
  const System& s = sim.system;
  ASSERT_GT(s.broken - broken_before, 0u);  // the impact breaks bonds
  EXPECT_EQ(flat_broken, s.broken - broken_before);
  EXPECT_EQ(copy.intact, s.bonds.intact);
  EXPECT_LE(relative(copy.u, flat(s.particles.u)), 0.0);
  EXPECT_LE(relative(copy.v, flat(s.particles.v)), 0.0);
  EXPECT_LE(relative(copy.damage, s.particles.damage), 0.0);
  EXPECT_LE(relative(copy.dissipated, s.dissipated_at), 0.0);
  const kernels::FlatTotals t = kernels::flat_totals(view);
  EXPECT_LE(rel(t.kinetic, kinetic_energy(s)), 0.0);
  EXPECT_LE(rel(t.strain, strain_energy(s)), 0.0);
  double mean = 0;
  for (double d : s.particles.damage) mean += d;
  mean /= static_cast<double>(s.particles.size());
  EXPECT_GT(mean, 0);
  EXPECT_LE(rel(t.mean_damage, mean), 0.0);
  std::printf("[ figure ] %s: flat portable rows against the fast loops (%s), 40 steps, %llu bonds broken: "
              "|du|/|u| = %.1e, |dv|/|v| = %.1e, damage %.1e, kinetic %.1e, strain %.1e relative; mean damage %.6f\n",
              state_based ? "lps" : "pmb", kernel_path_name(), static_cast<unsigned long long>(flat_broken),
              relative(copy.u, flat(s.particles.u)), relative(copy.v, flat(s.particles.v)),
              relative(copy.damage, s.particles.damage), rel(t.kinetic, kinetic_energy(s)),
              rel(t.strain, strain_energy(s)), mean);
  // Written back, the copy is the system's state (what a backend's frame copy does).
  flat_write_back(copy, sim.system);
  EXPECT_LE(relative(flat(s.particles.u), copy.u), 0);
}

TEST(PortableKernels, PmbFlatRunMatchesTheFastLoops) { compare(kPmb, false); }
TEST(PortableKernels, LpsFlatRunMatchesTheFastLoops) { compare(kLps, true); }

TEST(PortableKernels, FlatCopyNamesWhatItDoesNotTake) {
  const std::string plastic =
      "{model: elastic_plastic, density: 7850, youngs_modulus: 200.0e9, poissons_ratio: 0.3, yield_stress: 100.0e6}";
  Simulation sim(parse_deck(impact_deck(plastic, 40, 1.0), "portable.yaml"));
  EXPECT_EQ(flat_unsupported(sim.system, sim.loads), "a model without the unified per-bond form (ModelTraits::unified)");
}

}  // namespace
}  // namespace horizon::verification
