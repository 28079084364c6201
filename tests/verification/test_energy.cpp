// Check 3 (docs/verification.md): the total energy of an elastic impact is conserved
// within 0.5 %: the energy ledger's largest |balance error| over the run, as written to
// summary.json by run_deck (`horizon run`), is at most 5e-3.
//
// examples/elastic_impact.yaml: an aluminium striker (PMB) at 10 m/s against a steel bar
// (LPS), bonded where they touch (no contact model yet), no damage, no damping, no loads:
// K + U must stay equal to the striker's initial kinetic energy. The ledger is recorded
// at every step (history_every: 1), so the maximum is over every step.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <fmt/format.h>

#include "verification_support.hpp"

namespace horizon::verification {
namespace {

nlohmann::json run_impact(double safety_factor, const std::string& name) {
  Config config = load_deck(source_path("examples/elastic_impact.yaml"));
  config.solver.safety_factor = safety_factor;
  config.output.history_every = 1;
  config.output.frames = 1;
  RunOptions options;
  options.output_dir = output_dir(name).string();
  options.quiet = true;
  EXPECT_EQ(run_deck(config, options), 0);
  return read_json(std::filesystem::path(*options.output_dir) / "summary.json");
}

TEST(Energy, ElasticImpactConservesTotalEnergy) {
  const nlohmann::json j = run_impact(0.5, "elastic_impact");
  ASSERT_EQ(j["status"], "completed");
  const auto& e = j["energy"];
  // Initial energy: the striker's kinetic energy, 1/2 rho V v^2 with V = 10 x 6 x 6 mm^3.
  EXPECT_NEAR(e["initial"].get<double>(), 0.5 * 2700 * 0.01 * 0.006 * 0.006 * 100, 1e-9);
  EXPECT_EQ(e["dissipated"].get<double>(), 0.0);
  EXPECT_EQ(e["external_work"].get<double>(), 0.0);
  // The impact did happen: a good part of the energy is stored in the bodies at the end.
  EXPECT_GT(e["strain"].get<double>(), 0.05 * e["initial"].get<double>());
  const double max_error = e["max_abs_balance_error"];
  report("max_abs_balance_error", max_error,
         fmt::format("elastic impact, safety factor 0.5, {} steps: max |balance error| = {:.2e}",
                     j["steps"].get<int>(), max_error));
  EXPECT_LE(max_error, 5e-3);
}

// What remains is the time-integration error of velocity Verlet, which is second order:
// halving the time step divides the largest balance error by about 4. A leak in the
// ledger (a missing or double-counted term) would not shrink with the step.
TEST(Energy, BalanceErrorIsSecondOrderInTheTimeStep) {
  const double coarse = run_impact(0.5, "elastic_impact_dt")["energy"]["max_abs_balance_error"];
  const double fine = run_impact(0.25, "elastic_impact_dt2")["energy"]["max_abs_balance_error"];
  report("balance_error_ratio", coarse / fine,
         fmt::format("elastic impact: max |balance error| {:.2e} (safety 0.5), {:.2e} (0.25): ratio {:.2f}", coarse,
                     fine, coarse / fine));
  EXPECT_GT(coarse / fine, 3.0);
  EXPECT_LT(coarse / fine, 5.0);
}

}  // namespace
}  // namespace horizon::verification
