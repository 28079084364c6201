// Edge-on impact of a notched PMMA plate at the coarsest resolution of Tupek's Table 6.1
// (thesis sec. 6.2.1; digest ../shared/reference/notes/000_tupek.md sec. 5.4): the deck
// examples/edge_on_impact.yaml with its spacing set to 1 mm, which gives the thesis's
// 9,856 plate particles (88 x 112, delta = 5.5 mm), run to t = 0.2 ms at 15 m/s.
// Checked against the thesis's row for 9,856 particles (crack 4 mm, dissipated 2.5 J per
// metre of thickness, 620 J/m^2 per crack length) and against the energy rule
// (elastic + kinetic + dissipated within 1 % of the initial kinetic energy).
// The finer rows (>= 40,000 particles, within 10 % of G_c) take 15 minutes each and are
// in docs/verification.md with their commands.
#include <gtest/gtest.h>

#include <cstdio>

#include <fmt/format.h>

#include "verification_support.hpp"

namespace horizon::verification {
namespace {

TEST(EdgeOnImpact, CoarsestRowOfTable61) {
  Config config = load_deck(source_path("examples/edge_on_impact.yaml"));
  config.spacing = 1.0e-3;  // 88 x 112 plate particles
  const auto out = output_dir("edge_on_impact_9856");
  RunOptions options;
  options.output_dir = out.string();
  options.quiet = true;
  ASSERT_EQ(run_deck(config, options), 0);

  const auto j = read_json(out / "summary.json");
  ASSERT_EQ(j["status"], "completed");
  // Plate: 88 x 112 = 9,856; projectile: 20 x 20 on the same lattice.
  EXPECT_EQ(j["particles"].get<std::size_t>(), 9856u + 400u);
  EXPECT_NEAR(j["time"].get<double>(), 2.0e-4, 1e-7);

  // Energy: the ledger balances against the projectile's kinetic energy (issue: 1 %).
  // Measured 3.3e-4.
  const double balance = j["energy"]["max_abs_balance_error"];
  EXPECT_LT(balance, 0.01);

  const auto& f = j["fracture"];
  const double dissipated = f["dissipated_energy_per_thickness"];  // [J/m]
  const double length = f["crack_length"];                         // [m]
  const double per_length = f["energy_per_crack_length"];          // [J/m^2]
  report("edge_on_9856_dissipated", dissipated,
         fmt::format("edge-on impact, 9,856 particles, 0.2 ms: crack {:.1f} mm, dissipated {:.2f} J/m, {:.0f} J/m^2 "
                     "(thesis: 4 mm, 2.5 J, 620 J/m^2), max |balance error| {:.1e}",
                     length * 1e3, dissipated, per_length, balance));
  // Thesis Table 6.1, 9,856 particles: 2.5 J and 620 J/m^2, within 10 %. Measured 2.65 J/m
  // (+6 %) and 588 J/m^2 (-5 %). The crack length was counted in pixels there (4 mm);
  // ours follows the damaged path from the notch tip (damage >= 0.35): 4.5 mm.
  EXPECT_NEAR(dissipated, 2.5, 0.25);
  EXPECT_NEAR(per_length, 620.0, 62.0);
  EXPECT_GT(length, 3.0e-3);
  EXPECT_LT(length, 6.0e-3);
  // The coarse mesh overestimates G_c (thesis: 620 for 400); the crack runs straight on
  // the notch line (Mode I).
  EXPECT_GT(per_length, 400.0);
  const auto& tip = j["crack"]["tip"];
  EXPECT_LT(std::abs(tip[1].get<double>()), 2.0e-3);
  if (!HasFailure()) std::filesystem::remove_all(out / "frames");
}

}  // namespace
}  // namespace horizon::verification
