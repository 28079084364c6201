// Damage band width with and without the damage-dependent influence function (Tupek
// thesis sec. 7.1, eq. 7.1-7.2; seed 000 digest sec. 6.1 and pitfall 10 of sec. 10).
// A plane-strain strip of 6061-T6 (Table 7.1, the Johnson-Cook law on the extended
// correspondence model, failure strain 0.15), 20 x 10 mm, spacing 0.5 mm, delta = 1.5 mm,
// with an edge notch 3 mm deep at mid-length, pulled at +-10 m/s for 0.2 ms: a crack runs
// from the notch across the strip. Metric: per lattice row, the width (along the pull) of
// the particles that carry no stress (failed), in horizons, averaged over the rows the
// crack crossed. With omega_D (D_c = 0.99) a failed particle leaves its neighbours'
// families and the band stays about one horizon wide. Without it (D_c = 1) a failed
// particle stays in its neighbours' nonlocal strain while it flows freely, they see its
// motion as strain and fail in turn: the band widens. docs/verification.md has the figures
// (and those at spacing 0.25 mm).
#include <gtest/gtest.h>

#include <map>
#include <string>

#include <fmt/format.h>

#include "horizon/material/model.hpp"
#include "../single_thread.hpp"
#include "verification_support.hpp"

namespace horizon::verification {
namespace {

struct Band {
  double mean_width = 0;  // in horizons
  int failed = 0, rows = 0;
  double balance = 0;
};

Band damage_band(double critical_damage) {
  const std::string deck = fmt::format(R"(dimension: 2
plane: strain
thickness: 1.0e-3
spacing: 0.5e-3
horizon: 1.5e-3
materials:
  al: {{model: extended_correspondence, stress_law: johnson_cook, density: 2700, youngs_modulus: 72.0e9,
        poissons_ratio: 0.343, yield_stress: 250.0e6, hardening_coefficient: 365.0e6, hardening_exponent: 0.04,
        rate_coefficient: 0.002, failure_d1: 0.15, strain_measure: hencky, stabilization: 0.1,
        critical_damage: {}}}
bodies:
  - {{name: strip, material: al, shape: {{box: {{min: [0, 0], max: [0.020, 0.010]}}}}}}
precracks:
  - {{from: [0.01, 0.0101], to: [0.01, 0.007]}}
regions:
  l: {{box: {{min: [0, 0], max: [0.0012, 0.010]}}}}
  r: {{box: {{min: [0.0188, 0], max: [0.020, 0.010]}}}}
loads:
  - {{region: l, velocity: [-10, 0]}}
  - {{region: r, velocity: [10, 0]}}
solver: {{type: explicit, end_time: 2.0e-4, safety_factor: 0.5}}
)",
                                       critical_damage);
  test::SingleThread one;
  Simulation sim(parse_deck(deck, "band.yaml"));
  Band b;
  while (sim.solver->time() < sim.config.solver.end_time * (1 - 1e-12)) {
    sim.solver->step(true);
    b.balance = std::max(b.balance, std::abs(sim.solver->ledger().balance_error()));
  }
  const System& s = sim.system;
  std::vector<ModelField> fields;
  for (const auto& m : s.models) m->fields(s, fields);
  const std::vector<double>* failed = nullptr;
  for (const auto& f : fields)
    if (f.name == "carries_no_stress") failed = &f.values;
  EXPECT_NE(failed, nullptr);
  if (!failed) return b;
  const double h = sim.config.spacing, delta = sim.config.horizon;
  std::map<long, std::pair<double, double>> rows;  // row -> (min x, max x) of failed particles
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    if ((*failed)[i] < 0.5) continue;
    ++b.failed;
    const long row = std::lround(s.particles.X[i].y / h);
    const double x = s.particles.X[i].x;
    auto [it, fresh] = rows.try_emplace(row, x, x);
    if (!fresh) it->second = {std::min(it->second.first, x), std::max(it->second.second, x)};
  }
  double sum = 0;
  for (const auto& [row, ext] : rows) sum += (ext.second - ext.first + h) / delta;
  b.rows = static_cast<int>(rows.size());
  b.mean_width = rows.empty() ? 0 : sum / rows.size();
  return b;
}

TEST(DamageBand, DamageDependentInfluenceKeepsTheBandNarrow) {
  const Band with = damage_band(0.99), without = damage_band(1.0);
  report("band_width", with.mean_width,
         fmt::format("damage band (notched plane-strain strip, Johnson-Cook, spacing 0.5 mm, delta 1.5 mm): with "
                     "omega_D {} failed particles over {} rows, mean width {:.2f} delta, max |balance error| {:.1e}; "
                     "without omega_D {} failed over {} rows, mean width {:.2f} delta, max |balance error| {:.1e}",
                     with.failed, with.rows, with.mean_width, with.balance, without.failed, without.rows,
                     without.mean_width, without.balance));
  ASSERT_GE(with.rows, 4) << "the crack has to cross several rows";
  EXPECT_LT(with.mean_width, 1.5);
  EXPECT_GT(without.mean_width, 1.5 * with.mean_width);
  EXPECT_GT(without.failed, 1.5 * with.failed);
  EXPECT_LT(with.balance, 0.02);
  EXPECT_LT(without.balance, 0.02);
}

}  // namespace
}  // namespace horizon::verification
