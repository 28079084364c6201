// The affine general force pass (solver/forces_affine.cpp, issue 31 scope 2) against the
// vector one it replaces for the correspondence model (Model::force_state, kept as the
// reference behind set_general_reference): 40 steps of an impact that yields and breaks
// bonds (model_checks.hpp impact_deck at 40 m/s, bonds breaking at a stretch of 0.2 %) give the same displacements to 1e-12 relative and velocities to 1e-11 (the pair
// form sums the same terms in another order: round-off only), the same broken bonds, the same
// energy ledger to 1e-9 of the initial energy (the booking of a broken bond rebuilds the
// last pass's force state from its record), and the same bits on 1 and 2 threads and
// whichever rows the affine sweeps take (AVX-512 or the portable lanes,
// solver/affine_sweeps.hpp; set_kernel_path(avx2) and (scalar) take the portable ones).
// The extended model's pair form runs its sweeps in eight lanes on AVX-512 machines and
// bond by bond elsewhere (extended::set_pair_lanes): both meet the same tolerances.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <omp.h>

#include "horizon/material/models/extended_correspondence.hpp"
#include "horizon/solver/forces.hpp"
#include "horizon/solver/forces_general.hpp"
#include "model_checks.hpp"

namespace horizon::verification {
namespace {

const std::string kDamage = ", damage: {critical_stretch: 0.002}}";
const std::string kJ2 =
    "{model: correspondence, density: 7850, youngs_modulus: 200.0e9, poissons_ratio: 0.3, stress_law: j2, "
    "yield_stress: 100.0e6, hardening_modulus: 2.0e9" + kDamage;
const std::string kNeo =
    "{model: correspondence, density: 7850, youngs_modulus: 200.0e9, poissons_ratio: 0.3, stress_law: neo_hookean, "
    "stabilization: 0.5" + kDamage;

struct Run {
  std::vector<Vec3> u, v;
  uint64_t broken = 0;
  double dissipated = 0, initial = 0, balance = 0;
};

Run run(const std::string& text, bool reference, int threads, KernelPath path = KernelPath::automatic,
        bool lanes = true) {
  const int saved = omp_get_max_threads();
  omp_set_num_threads(threads);
  set_general_reference(reference);
  set_kernel_path(path);
  extended::set_pair_lanes(lanes);
  Simulation sim(parse_deck(text, "general.yaml"));
  if (sim.system.models[0].traits().affine)
    EXPECT_EQ(affine_general_pass(sim.system), !reference);
  else
    EXPECT_TRUE(sim.system.models[0].takes_pair_pass(sim.system)) << "the deck is meant for the pair form";
  for (int n = 0; n < 40; ++n) sim.solver->step(true);
  set_general_reference(false);
  set_kernel_path(KernelPath::automatic);
  extended::set_pair_lanes(true);
  omp_set_num_threads(saved);
  Run r;
  r.u = sim.system.particles.u;
  r.v = sim.system.particles.v;
  r.broken = sim.system.broken;
  r.dissipated = sim.solver->ledger().dissipated;
  r.initial = sim.solver->ledger().initial;
  r.balance = sim.solver->ledger().balance_error();
  return r;
}

void check(const std::string& name, const std::string& text, bool pair_lanes = false) {
  const Run ref = run(text, true, 1), fast = run(text, false, 1), two = run(text, false, 2);
  const double du = max_difference(fast.u, ref.u), dv = max_difference(fast.v, ref.v);
  const double dd = std::abs(fast.dissipated - ref.dissipated) / ref.initial;
  report("general_pass_" + name, std::max(du, dv),
         fmt::format("{}: affine or pair form against the vector general pass, 40 steps of a breaking impact ({} bonds broken): "
                     "|du|/|u| = {:.1e}, |dv|/|v| = {:.1e}, dissipated {:.6e} against {:.6e} J ({:.1e} of the "
                     "initial energy), balance error {:.2e} against {:.2e}",
                     name, fast.broken, du, dv, fast.dissipated, ref.dissipated, dd, fast.balance, ref.balance));
  EXPECT_GT(ref.broken, 0u) << "the run is meant to break bonds";
  EXPECT_EQ(fast.broken, ref.broken);
  EXPECT_LE(du, 1e-12);
  // The velocities carry the last step's forces, whose round-off the yielding and the
  // breaking amplify more: 1.1e-12 measured for j2 with 3,652 bonds broken.
  EXPECT_LE(dv, 1e-11);
  EXPECT_LE(dd, 1e-9);
  EXPECT_TRUE(same_bits(fast.u, two.u)) << "the fast form differs between 1 and 2 threads";
  EXPECT_TRUE(same_bits(fast.v, two.v));
  for (const KernelPath path : {KernelPath::avx2, KernelPath::scalar}) {
    const Run other = run(text, false, 1, path);
    EXPECT_TRUE(same_bits(fast.u, other.u)) << "the fast form differs between its rows (" << int(path) << ")";
    EXPECT_TRUE(same_bits(fast.v, other.v));
  }
  if (!pair_lanes) return;
  // The extended model's pair form bond by bond (machines without AVX-512) against the
  // same reference: the same tolerances.
  const Run plain = run(text, false, 1, KernelPath::automatic, false);
  const double pu = max_difference(plain.u, ref.u), pv = max_difference(plain.v, ref.v);
  report("general_pass_" + name + "_bond_order", std::max(pu, pv),
         fmt::format("{}: the pair form bond by bond (without the lanes) against the vector general pass: "
                     "|du|/|u| = {:.1e}, |dv|/|v| = {:.1e}, dissipated {:.1e} of the initial energy from the vector's",
                     name, pu, pv, std::abs(plain.dissipated - ref.dissipated) / ref.initial));
  EXPECT_EQ(plain.broken, ref.broken);
  EXPECT_LE(pu, 1e-12);
  EXPECT_LE(pv, 1e-11);
  EXPECT_LE(std::abs(plain.dissipated - ref.dissipated) / ref.initial, 1e-9);
}

TEST(GeneralPass, CorrespondenceJ2MatchesTheVectorPass) {
  check("correspondence_j2", impact_deck(kJ2, 40, 1.0));
}

TEST(GeneralPass, CorrespondenceNeoHookeanMatchesTheVectorPass) {
  check("correspondence_neo_hookean", impact_deck(kNeo, 40, 1.0));
}

// Tupek's extended correspondence takes the pair form (extended_correspondence.cpp
// pair_forces): the Taylor bar's settings (hencky strains, J2, the midpoint stabilisation
// residual, the volume from the classical nonlocal F) and the bench deck's (the thesis's
// logarithmic bond strains, m = 0, the full residual, the averaged volume).
const std::string kExtended =
    "{model: extended_correspondence, density: 7850, youngs_modulus: 200.0e9, poissons_ratio: 0.3, stress_law: j2, "
    "yield_stress: 100.0e6, hardening_modulus: 2.0e9, stabilization: 0.1";

TEST(GeneralPass, ExtendedHenckyMidpointMatchesTheVectorPass) {
  check("extended_hencky_midpoint",
        impact_deck(kExtended + ", strain_measure: hencky, stabilization_residual: midpoint, volumetric_strain: "
                                "gradient" + kDamage,
                    40, 1.0),
        true);
}

TEST(GeneralPass, ExtendedLogarithmicFullMatchesTheVectorPass) {
  check("extended_log_full", impact_deck(kExtended + kDamage, 40, 1.0), true);
}

}  // namespace
}  // namespace horizon::verification
