// The scalar general force pass (solver/forces_ordinary.cpp, issue 31) against the
// vector one it replaces for the ordinary models (Model::force_state, kept as the
// reference behind set_general_reference): for every model of the registry that takes it
// (ModelTraits::ordinary), 40 steps of an impact that yields and breaks bonds give the
// same displacements and velocities (to 1e-12 relative; the pass is built to give the
// same bits), the same broken bonds, and the same energy ledger up to the booking of
// broken bonds (history_ledger.hpp broken_bond_booking: t_old for T_old.Y/|Y|, a
// difference of t_old (1 - cos) of a bond's turn in one step, 4e-4 rad here; 1e-6 of the
// initial energy; an ordinary model's own booking cancels it exactly);
// the scalar pass gives the same bits on 1 and 2 threads, and its rows in bond order
// (machines without AVX-512, material/models/ordinary_lanes.hpp) the vector pass's bits. A run that mixes a unified
// model (LPS) with an ordinary one takes the scalar pass too, unified rows included.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <omp.h>

#include "horizon/material/models/ordinary_lanes.hpp"
#include "horizon/solver/forces.hpp"
#include "horizon/solver/forces_general.hpp"
#include "model_checks.hpp"

namespace horizon::verification {
namespace {

// A striker of material `a` bonded to a bar of material `b` (impact_deck's geometry), at
// 40 m/s, bonds breaking at a stretch of 0.2 %.
std::string deck(const std::string& a, const std::string& b) {
  return fmt::format(R"(dimension: 3
spacing: 1.0e-3
horizon: 3.0e-3
materials:
  a: {}
  b: {}
bodies:
  - {{name: striker, material: a, shape: {{box: {{min: [0, 0, 0], max: [0.006, 0.004, 0.004]}}}}}}
  - {{name: bar, material: b, shape: {{box: {{min: [0.006, 0, 0], max: [0.018, 0.004, 0.004]}}}}}}
regions:
  striker: {{box: {{min: [0, 0, 0], max: [0.006, 0.004, 0.004]}}}}
initial_conditions:
  - {{region: striker, velocity: [40, 6.7, 0]}}
solver: {{type: explicit, end_time: 1.0, safety_factor: 0.5}}
)",
                     a, b);
}

const std::string kDamage = ", damage: {critical_stretch: 0.002}}";
const std::string kPlastic =
    "{model: elastic_plastic, density: 7850, youngs_modulus: 200.0e9, poissons_ratio: 0.3, yield_stress: 100.0e6, "
    "hardening_modulus: 2.0e9" + kDamage;
const std::string kViscous =
    "{model: viscoelastic, density: 7850, youngs_modulus: 200.0e9, poissons_ratio: 0.3, lambda_1: 0.5, tau_1: 1.0e-6, "
    "lambda_2: 0.2, tau_2: 5.0e-6" + kDamage;
const std::string kMicro =
    "{model: microplastic, density: 7850, youngs_modulus: 200.0e9, yield_stretch: 0.0005" + kDamage;
const std::string kLps = "{model: lps, density: 7850, youngs_modulus: 200.0e9, poissons_ratio: 0.3" + kDamage;
const std::string kPals = "{model: pals, density: 7850, youngs_modulus: 200.0e9, poissons_ratio: 0.3" + kDamage;

struct Run {
  std::vector<Vec3> u, v;
  uint64_t broken = 0;
  double dissipated = 0, initial = 0, balance = 0;
  double plastic = 0;  // the largest entry of the models' output fields (plastic strain, ...)
};

Run run(const std::string& text, bool reference, int threads) {
  const int saved = omp_get_max_threads();
  omp_set_num_threads(threads);
  set_general_reference(reference);
  Simulation sim(parse_deck(text, "ordinary.yaml"));
  for (int n = 0; n < 40; ++n) sim.solver->step(true);
  set_general_reference(false);
  omp_set_num_threads(saved);
  Run r;
  r.u = sim.system.particles.u;
  r.v = sim.system.particles.v;
  r.broken = sim.system.broken;
  r.dissipated = sim.solver->ledger().dissipated;
  r.initial = sim.solver->ledger().initial;
  r.balance = sim.solver->ledger().balance_error();
  std::vector<ModelField> fields;
  for (const auto& m : sim.system.models) m->fields(sim.system, fields);
  for (const auto& f : fields)
    for (double x : f.values) r.plastic = std::max(r.plastic, std::abs(x));
  return r;
}

void check(const std::string& name, const std::string& text) {
  const Run ref = run(text, true, 1), fast = run(text, false, 1), two = run(text, false, 2);
  const double du = max_difference(fast.u, ref.u), dv = max_difference(fast.v, ref.v);
  const double dd = std::abs(fast.dissipated - ref.dissipated) / ref.initial;
  report("ordinary_pass_" + name, std::max(du, dv),
         fmt::format("{}: scalar against vector general pass, 40 steps of a breaking impact ({} bonds broken, "
                     "largest history field {:.3e}): |du|/|u| = {:.1e}, |dv|/|v| = {:.1e}, dissipated {:.6e} "
                     "against {:.6e} J ({:.1e} of the initial energy), balance error {:.2e} against {:.2e}",
                     name, fast.broken, fast.plastic, du, dv, fast.dissipated, ref.dissipated, dd, fast.balance,
                     ref.balance));
  EXPECT_GT(ref.broken, 0u) << "the run is meant to break bonds";
  EXPECT_EQ(fast.broken, ref.broken);
  EXPECT_LE(du, 1e-12);
  EXPECT_LE(dv, 1e-12);
  EXPECT_LE(dd, 1e-6);
  EXPECT_TRUE(same_bits(fast.u, two.u)) << "the scalar pass differs between 1 and 2 threads";
  EXPECT_TRUE(same_bits(fast.v, two.v));
  // The other choice of rows (ordinary_lanes.hpp: the lanes on AVX-512, the scalar rows in
  // bond order elsewhere), where this machine has it: the vector pass's answer too.
  const std::string best = lanes::lanes_target();
  const char* other_rows = best == "avx512" ? "scalar" : "avx512";
  if (lanes::set_lanes_target(other_rows)) {
    const Run other = run(text, false, 1);
    lanes::set_lanes_target("best");
    EXPECT_EQ(other.broken, ref.broken) << other_rows;
    EXPECT_LE(max_difference(other.u, ref.u), 1e-12) << other_rows;
    EXPECT_LE(max_difference(other.v, ref.v), 1e-12) << other_rows;
    if (std::string(other_rows) == "scalar") {  // bond order: the vector form's bits
      EXPECT_TRUE(same_bits(other.u, ref.u));
      EXPECT_TRUE(same_bits(other.v, ref.v));
    }
  }
}

// The ledger's committed t_n and e_n rebuilt from the last pass (history_ledger.hpp
// LedgerRows): after explicit steps, which keep no stored copies, passes that no commit
// follows (a static solver's) write the rebuilt values into the ledger's arrays and the
// next pass reads them back. A pass at the committed positions with no time passing
// then books no work (e = e_n bit for bit) and no change of W: its pending dissipation is
// 0 to round-off, and the second of two such passes (the stored arrays) books exactly
// what a single one (rebuilt) does.
TEST(OrdinaryPass, LedgerRebuiltFromTheLastPassMatchesTheStoredOne) {
  for (const std::string& m : {kPlastic, kViscous, kMicro}) {
    Simulation once(parse_deck(deck(m, m), "ledger.yaml")), twice(parse_deck(deck(m, m), "ledger.yaml"));
    for (int n = 0; n < 20; ++n) once.solver->step(true), twice.solver->step(true);
    ASSERT_GT(once.system.broken, 0u) << m;
    double pending[2] = {0, 0};
    for (int r = 0; r < 2; ++r) {
      Simulation& sim = r == 0 ? once : twice;
      sim.system.dt = 0;  // no time passes: the viscous branches hold
      for (int pass = 0; pass <= r; ++pass) compute_forces(sim.system, true);
      for (const auto& model : sim.system.models) pending[r] += model->pending_dissipation(sim.system);
    }
    const double scale = once.solver->ledger().initial;
    report("ordinary_ledger_rebuilt", std::abs(pending[0]) / scale,
           fmt::format("ledger rebuilt from the last pass: a pass at the committed state books {:.2e} J (of "
                       "{:.3e} J initial) rebuilt, {:.2e} J from the stored arrays",
                       pending[0], scale, pending[1]));
    EXPECT_EQ(pending[0], pending[1]) << m;
    EXPECT_LE(std::abs(pending[0]), 1e-12 * scale) << m;
  }
}

// The explicit step writes the models' history over the committed copy (history_ledger.hpp
// LedgerRows::in_place), which is right only if the commit comes before any other pass: a
// second pass would read the first one's history as committed. That must fail loudly.
TEST(OrdinaryPass, HistoryWrittenInPlaceMustBeCommittedBeforeTheNextPass) {
  if (!lanes::wide()) GTEST_SKIP() << "the scalar rows keep trial copies";
  for (const std::string& m : {kPlastic, kViscous, kMicro}) {
    Simulation sim(parse_deck(deck(m, m), "in_place.yaml"));
    for (int n = 0; n < 3; ++n) sim.solver->step(true);
    sim.system.model.commit_follows = true;  // as the explicit step says before its pass
    compute_forces(sim.system, true);
    sim.system.model.commit_follows = false;
    std::string message;
    try {
      compute_forces(sim.system, true);  // no commit in between
    } catch (const Error& e) {
      message = e.what();
    }
    EXPECT_NE(message.find("was not committed before another pass"), std::string::npos) << m << ": '" << message << "'";
  }
}

TEST(OrdinaryPass, ElasticPlasticMatchesTheVectorPass) {
  check("elastic_plastic", deck(kPlastic, kPlastic));
}

TEST(OrdinaryPass, ViscoelasticMatchesTheVectorPass) { check("viscoelastic", deck(kViscous, kViscous)); }

TEST(OrdinaryPass, MicroplasticMatchesTheVectorPass) { check("microplastic", deck(kMicro, kMicro)); }

TEST(OrdinaryPass, PalsMatchesTheVectorPass) { check("pals", deck(kPals, kPals)); }

TEST(OrdinaryPass, LpsBesideAnOrdinaryModelMatchesTheVectorPass) { check("lps_and_elastic_plastic", deck(kLps, kPlastic)); }

}  // namespace
}  // namespace horizon::verification
