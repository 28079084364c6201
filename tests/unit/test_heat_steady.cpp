// Steady heat solves (thermal.integration: steady), materials of heat alone, the improved
// quadrature (thermal.quadrature: improved) and the Exodus Flux_Divergence of heat runs
// (docs/input.md "thermal", docs/models/heat.md "Steady solve" and "Improved quadrature").
//
// Closed form: a bar 0 <= x <= L = 1 with conductivity k and a uniform source q, its ends
// held at T(0) = T0, T(L) = T1: k T'' + q = 0 gives
//   T(x) = T0 + (T1 - T0) x / L + q x (L - x) / (2k),
// a quadratic. The nonlocal operator is exact on quadratics wherever the quadrature
// integrates g xi^2 as the calibration assumes: the discrete calibration over a full
// lattice family, or the improved quadrature at every particle. With the ends' layers one
// horizon deep held at the closed form (the nonlocal volume constraint), every free
// particle's family is full and the nonlocal steady temperature is the closed form itself.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "horizon/core/error.hpp"
#include "horizon/deck/deck.hpp"
#include "horizon/driver/run.hpp"
#include "horizon/output/exodus.hpp"
#include "deck_test_support.hpp"

namespace horizon {
namespace {

namespace fs = std::filesystem;

using test::error_of;
using test::index_of;
using test::run_and_read;
using test::write;

fs::path test_dir() { return test::fresh_test_dir("horizon_heat_steady"); }

// 16 particles of spacing 1/16 on [0, 1] (binary fractions: exact positions), horizon 3
// spacings; the end layers held at the closed form (300 K at x = 0, 300 + 100 t at x = 1),
// a source F t over the whole bar (a flux F over region all is F / (N h) = F per volume:
// the layer depth of `all` is N h = 1). Two load steps.
std::string bar_deck(const std::string& thermal_extra, double flux, double k = 2.0) {
  const std::string closed = "300 + 100*t*x + " + std::to_string(flux) + "*t*x*(1 - x)/(2*" + std::to_string(k) + ")";
  return "dimension: 1\n"
         "area: 1.0\n"
         "spacing: 0.0625\n"
         "horizon: 0.1875\n"
         "materials:\n"
         "  rod: {thermal: {conductivity: " + std::to_string(k) + "}}\n"
         "bodies:\n"
         "  - {name: rod, material: rod, shape: {box: {min: [0], max: [1]}}}\n"
         "regions:\n"
         "  left: {box: {min: [0], max: [0.1875]}}\n"
         "  right: {box: {min: [0.8125], max: [1]}}\n"
         "thermal:\n"
         "  initial_temperature: 300\n"
         "  integration: steady\n" + thermal_extra +
         "  boundary:\n"
         "    - {region: left, temperature: \"" + closed + "\"}\n"
         "    - {region: right, temperature: \"" + closed + "\"}\n"
         "    - {region: all, flux: \"" + std::to_string(flux) + "*t\"}\n"
         "solver: {type: heat, end_time: 1, time_step: 0.5}\n"
         "output:\n"
         "  exodus_files: [{file: bar.e, variables: [Flux_Divergence]}]\n";
}

struct BarResult {
  double worst = 0;             // largest |T - closed form| over the particles, last step
  double divergence_free = 0;   // largest |Flux_Divergence| at the free particles, last step
  double divergence_end = 0;    // |Flux_Divergence| at the first particle (x = h/2), last step
  std::size_t steps = 0;
  double last_time = 0;
};

BarResult run_bar(const std::string& thermal_extra, double flux) {
  const fs::path dir = test_dir();
  const double k = 2.0;
  const ExodusSeries e = run_and_read(write(dir / "bar.yaml", bar_deck(thermal_extra, flux, k)), dir, "bar.e");
  BarResult r;
  r.steps = e.steps.size();
  r.last_time = e.steps.back().time;
  const std::size_t T = index_of(e.layout.nodal, "Temperature"), D = index_of(e.layout.nodal, "Flux_Divergence");
  const auto& last = e.steps.back();
  for (std::size_t i = 0; i < e.layout.points.size(); ++i) {
    const double x = e.layout.points[i].x, t = 1.0;
    const double expected = 300 + 100 * t * x + flux * t * x * (1 - x) / (2 * k);
    r.worst = std::max(r.worst, std::abs(last.nodal[T][i] - expected));
    if (x > 0.1875 && x < 0.8125) r.divergence_free = std::max(r.divergence_free, std::abs(last.nodal[D][i] + flux));
    if (std::abs(x - 0.03125) < 1e-12) r.divergence_end = std::abs(last.nodal[D][i]);
  }
  return r;
}

TEST(HeatSteady, BarWithSourceIsTheClosedFormWithTheDiscreteCalibration) {
  // Discrete calibration: kappa from the lattice family's own second moment, so that the
  // one-point sum is exact on quadratics over a full family.
  const BarResult r = run_bar("  calibration: discrete\n", 50.0);
  EXPECT_EQ(r.steps, 3u);  // t = 0, 0.5, 1
  EXPECT_DOUBLE_EQ(r.last_time, 1.0);
  EXPECT_LT(r.worst, 1e-9);
  // At the free particles the conduction balances the source: L T = -q.
  EXPECT_LT(r.divergence_free, 1e-6);
}

TEST(HeatSteady, BarWithSourceIsTheClosedFormWithTheImprovedQuadrature) {
  const BarResult r = run_bar("  quadrature: improved\n", 50.0);
  EXPECT_LT(r.worst, 1e-9);
  EXPECT_LT(r.divergence_free, 1e-6);
}

TEST(HeatSteady, ImprovedQuadratureLeavesALinearFieldNoFluxDivergenceAtTheEnds) {
  // A linear field (no source): the improved weights integrate xi over the whole ball, so
  // even the end particle's one-sided family sees no divergence; the one-point rule leaves
  // it kappa T' sum g xi V_j (its family's first moment).
  // kappa = 2k / (A delta^2) (inverse kernel, 1-D; heat.hpp), the first moment from
  // x = h/2: sum over j = 1..3 of (1/(j h)) (j h) h = 3h, times T' = 100.
  const double h = 0.0625, kappa = 2 * 2.0 / (3 * h * 3 * h), one_sided = kappa * 100 * 3 * h;
  const BarResult improved = run_bar("  quadrature: improved\n", 0.0);
  EXPECT_LT(improved.worst, 1e-9);
  EXPECT_LT(improved.divergence_end, 1e-12 * one_sided);
  const BarResult one_point = run_bar("", 0.0);
  EXPECT_LT(one_point.worst, 1e-9);  // linear: exact with any kappa
  EXPECT_NEAR(one_point.divergence_end, one_sided, 1e-12 * one_sided);
}

TEST(HeatSteady, ImprovedQuadratureRefusesAFamilyTooSmall) {
  // A horizon of one spacing: the end particles have one neighbour, too few to integrate
  // both xi and xi^2 exactly; the run stops at its set-up naming the particle.
  const fs::path dir = test_dir();
  std::string deck = bar_deck("  quadrature: improved\n", 0.0);
  deck.replace(deck.find("horizon: 0.1875"), 15, "horizon: 0.0625");
  Config c = load_deck(write(dir / "bar.yaml", deck));
  c.output.directory = (dir / "out").string();
  RunOptions o;
  o.quiet = true;
  std::string error = "no error";
  try {
    run_deck(c, o);
  } catch (const Error& e) {
    error = e.what();
  }
  EXPECT_NE(error.find("too small or too flat"), std::string::npos) << error;
  EXPECT_NE(error.find("(0.03125, 0, 0)"), std::string::npos) << error;
}

TEST(HeatSteady, DeckErrors) {
  const fs::path dir = test_dir();
  auto error_with = [&](const std::string& from, const std::string& to, const std::string& base = "") {
    std::string deck = base.empty() ? bar_deck("", 1.0) : base;
    const auto at = deck.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    deck.replace(at, from.size(), to);
    return error_of(write(dir / "bad.yaml", deck));
  };
  EXPECT_EQ(error_of(write(dir / "good.yaml", bar_deck("", 1.0))), "no error");
  EXPECT_NE(error_with("time_step: 0.5", "safety_factor: 0.5").find("steady needs solver.time_step"), std::string::npos);
  EXPECT_NE(error_with("type: heat", "type: explicit").find("a material without a model has no mechanics"),
            std::string::npos);
  EXPECT_NE(error_with("integration: steady", "integration: implicit").find("expected specific_heat"),
            std::string::npos);
  EXPECT_NE(error_with("{conductivity: 2.000000}", "{conductivity: 2.000000, specific_heat: 1}",
                       bar_deck("", 1.0).replace(bar_deck("", 1.0).find("integration: steady"), 19,
                                                  "integration: implicit"))
                .find("expected density"),
            std::string::npos);
  EXPECT_NE(error_with("integration: steady\n", "integration: steady\n  quadrature: improved\n  calibration: discrete\n")
                .find("takes calibration: continuum"),
            std::string::npos);
  EXPECT_NE(error_with("integration: steady\n", "integration: steady\n  quadrature: halfway\n").find("halfway"),
            std::string::npos);
  // Only a source: no steady temperature.
  std::string flux_only = bar_deck("", 1.0);
  for (const char* side : {"left", "right"}) {
    const std::string line = std::string("    - {region: ") + side + ", temperature:";
    const auto at = flux_only.find(line);
    flux_only.erase(at, flux_only.find('\n', at) + 1 - at);
  }
  EXPECT_NE(error_of(write(dir / "flux.yaml", flux_only)).find("steady needs a temperature or convection condition"),
            std::string::npos);
  // Flux_Divergence needs conduction.
  const std::string mech = "dimension: 1\narea: 1.0\nspacing: 0.01\nhorizon: 0.03\n"
                           "materials:\n  rod: {model: pmb, density: 1, youngs_modulus: 1}\n"
                           "bodies:\n  - {name: rod, material: rod, shape: {box: {min: [0], max: [1]}}}\n"
                           "solver: {type: explicit, end_time: 1e-6}\n"
                           "output:\n  exodus_files: [{file: bar.e, variables: [Flux_Divergence]}]\n";
  EXPECT_NE(error_of(write(dir / "mech.yaml", mech)).find("Flux_Divergence is the heat conduction's"),
            std::string::npos);
  // A material without a model takes density and thermal only.
  EXPECT_NE(error_with("rod: {thermal:", "rod: {youngs_modulus: 5, thermal:").find("youngs_modulus"),
            std::string::npos);
}

}  // namespace
}  // namespace horizon
