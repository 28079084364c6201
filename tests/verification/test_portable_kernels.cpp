// The device-portable kernels (src/horizon/kernels/, issue 30) against the host's own
// passes: a run stepped over flat arrays with the portable row functions
// (kernels/flat_system.hpp advance_flat, the code the CUDA backend launches) gives the
// SIMD fast loops' answer on 40 steps of a breaking impact, PMB and LPS: the same
// displacements, velocities, damage, strain and kinetic energy and dissipation, bit for bit,
// and the same broken bonds (model_checks.hpp impact_deck at 40 m/s, bonds breaking at a
// stretch of 0.2 %). The portable rows sum each row in the fast loops' eight lanes, in
// the same order, so the bits agree (tests/regression/test_backend.cpp runs whole decks).
//
// The correspondence model stepped over a flat copy (J2, stabilised: advance_flat with
// kernels/flat_affine.hpp's rows and commit) gives the host's steps' bits too.
//
// The correspondence model (stabilised; linear elastic, neo-Hookean and J2 with its
// history in flat arrays) and Tupek's nonlinear solid: 40
// steps of a breaking run (the impact; a bar pulled apart for the nonlinear solid), and
// after each of the host's steps the same force pass computed again over flat copies with
// the portable kernels alone (kernels/affine.hpp: the breaking sweep, kernels/laws.hpp law_row,
// the stabilisation energy, the pair sum; kernels/tupek.hpp: the strain and force rows),
// from the pass's inputs (the packed positions and critical stretches) and the copies' own
// broken flags, records and damage weights: the same forces, energies, damage,
// dissipation and broken bonds, bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "horizon/kernels/affine.hpp"
#include "horizon/kernels/laws.hpp"
#include "horizon/kernels/tupek.hpp"
#include "horizon/material/models/nonlinear_solid.hpp"
#include "horizon/solver/flat_copy.hpp"
#include "horizon/solver/forces.hpp"
#include "horizon/solver/forces_general.hpp"
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

// The correspondence model stepped over a flat copy (kernels/flat_affine.hpp: the affine
// pass's rows and the commit, through advance_flat) against the host's steps: J2,
// stabilised, bonds breaking; the same state, damage, dissipation (the broken bonds' energy
// and the plastic work) and energies, bit for bit.
TEST(PortableKernels, CorrespondenceFlatRunMatchesTheHostSteps) {
  test::SingleThread one;
  const std::string material =
      "{model: correspondence, density: 7850, youngs_modulus: 200.0e9, poissons_ratio: 0.3, stabilization: 0.5, "
      "stress_law: j2, yield_stress: 4.0e8, hardening_modulus: 2.0e9, damage: {critical_stretch: 0.002}}";
  Simulation sim(parse_deck(impact_deck(material, 40, 1.0), "portable.yaml"));
  ASSERT_EQ(flat_unsupported(sim.system, sim.loads), "");
  FlatStorage copy = flat_copy(sim.system, sim.solver->dt(), sim.config.solver.damping);
  ASSERT_TRUE(copy.affine.on);
  const kernels::FlatSystem view = copy.view();
  const uint64_t broken_before = sim.system.broken;
  for (int n = 0; n < 40; ++n) sim.solver->step(true);
  const uint64_t flat_broken = kernels::advance_flat(view, 40);
  const System& s = sim.system;
  EXPECT_GT(flat_broken, 0u);
  EXPECT_EQ(flat_broken, s.broken - broken_before);
  EXPECT_EQ(copy.intact, s.bonds.intact);
  EXPECT_LE(relative(copy.u, flat(s.particles.u)), 0.0);
  EXPECT_LE(relative(copy.v, flat(s.particles.v)), 0.0);
  EXPECT_LE(relative(copy.damage, s.particles.damage), 0.0);
  EXPECT_LE(relative(copy.dissipated, s.dissipated_at), 0.0);
  EXPECT_LE(relative(copy.affine.record, s.model.affine_record), 0.0);
  const kernels::FlatTotals t = kernels::flat_totals(view);
  EXPECT_LE(rel(t.kinetic, kinetic_energy(s)), 0.0);
  EXPECT_LE(rel(t.strain, strain_energy(s)), 0.0);
  double plastic = 0;
  for (double d : copy.dissipated) plastic += d;
  std::printf("[ figure ] correspondence j2: flat rows against the host's steps, 40 steps, %llu bonds broken, "
              "dissipated %.6e J: |du|/|u| = %.1e, strain %.1e relative\n",
              static_cast<unsigned long long>(flat_broken), plastic, relative(copy.u, flat(s.particles.u)),
              rel(t.strain, strain_energy(s)));
}
TEST(PortableKernels, LpsFlatRunMatchesTheFastLoops) { compare(kLps, true); }

// Bitwise equality of two arrays of doubles (counts the entries that differ).
std::size_t differing(const double* a, const double* b, std::size_t n) {
  std::size_t bad = 0;
  for (std::size_t i = 0; i < n; ++i) bad += std::memcmp(a + i, b + i, sizeof(double)) != 0;
  return bad;
}

// The verdict on 40 passes through the kernels: bonds broke, as many as the host's pass
// broke, and no entry differs from the host's.
void expect_same_as_host(const char* model, uint64_t broken, uint64_t host_broken, std::size_t bad) {
  EXPECT_GT(broken, 0u) << "the impact is meant to break bonds";
  EXPECT_EQ(broken, host_broken);
  EXPECT_EQ(bad, 0u) << "the kernels' pass differs from the host's";
  std::printf("[ figure ] %s: 40 passes of a breaking impact through the portable kernels, %llu bonds broken, "
              "%zu entries differing from the host's pass\n",
              model, static_cast<unsigned long long>(broken), bad);
}

// The correspondence model's pass recomputed through the kernels alone, for the law of
// `law` (kernels/laws.hpp law_row: linear elastic, neo-Hookean, J2 with its history kept in
// flat arrays and committed after each step, its plastic work booked as the model's commit
// books it).
void correspondence_through_kernels(const char* name, const std::string& law, int law_kind) {
  test::SingleThread one;
  const std::string material =
      "{model: correspondence, density: 7850, youngs_modulus: 200.0e9, poissons_ratio: 0.3, stabilization: 0.5, " +
      law + "damage: {critical_stretch: 0.002}}";
  Simulation sim(parse_deck(impact_deck(material, 40, 1.0), "portable.yaml"));
  System& s = sim.system;
  ASSERT_TRUE(affine_general_pass(s));
  const std::size_t n = s.particles.size(), nb = s.bonds.size();
  const MaterialConfig& mat = sim.config.materials[0];
  kernels::LawConstants c;
  c.law = law_kind;
  c.lambda = mat.bulk_modulus - 2.0 * mat.shear_modulus / 3.0, c.mu = mat.shear_modulus, c.kappa = mat.bulk_modulus;
  c.yield_stress = Model::parameter(mat, "yield_stress"), c.hardening = Model::parameter(mat, "hardening_modulus");
  double G = 0;  // the stabilisation modulus, g_i of every record that carries stress
  for (std::size_t i = 0; i < n; ++i) G = std::max(G, s.model.affine_record[kernels::kAffineRecord * i + 9]);
  ASSERT_GT(G, 0);
  // The copy's own state of the pass: flags, damage weights, records, last positions, the
  // law's history.
  std::vector<uint8_t> intact = s.bonds.intact;
  std::vector<double> weight = s.model.intact_weight, record = s.model.affine_record, dissipated = s.dissipated_at;
  std::vector<Vec3> y_old = s.model.affine_position;
  std::vector<Point4> ref(n);
  for (std::size_t i = 0; i < n; ++i) ref[i] = {s.particles.X[i].x, s.particles.X[i].y, s.particles.X[i].z, 0.0};
  std::vector<kernels::J2History> committed(n, kernels::J2History{}), trial(n);
  std::vector<double> f(3 * n), energy(n), damage(n), work(n);
  uint64_t broken = 0, host_broken = 0;
  std::size_t bad = 0;
  double plastic = 0;
  for (int step = 0; step < 40; ++step) {
    const uint64_t before = s.broken;
    sim.solver->step(true);
    host_broken += s.broken - before;
    kernels::AffineSweep<KindCoefficients, BondKind> sw;
    sw.pt = s.model.packed.data();  // the pass's inputs: y and s0
    sw.ref = ref.data();
    sw.y_old = y_old.data();
    sw.record = record.data();
    sw.kc = s.model.kind.data();
    sw.kind_record = s.model.kind_dilatation.data();
    sw.kinds = s.bonds.kinds.data();
    sw.nbr = s.bonds.nbr.data();
    sw.kind = s.bonds.kind.data();
    sw.offset = s.bonds.offset.data();
    sw.intact = intact.data();
    sw.intact_weight = weight.data();
    sw.total = nb;
    sw.after = s.model.break_after_force;
    sw.contact = s.contact.acts_on_family();
    for (std::size_t i = 0; i < n; ++i) {
      double sums[18];
      const kernels::AffineBreak o = kernels::affine_break_row(sw, i, sums);
      broken += o.broken;
      if (o.lost != 0) dissipated[i] += o.lost * s.particles.volume[i];
      if (o.broken) weight[i] = kernels::intact_weight_lanes(sw.offset, sw.intact, sw.kind, sw.kc, i);
      damage[i] = kernels::damage_fraction(weight[i], s.model.damage_total[i]);
      double* rec = record.data() + kernels::kAffineRecord * i;
      const kernels::AffineRow row = kernels::law_row(sums, 3, 1e-4, c, G, committed[i], trial[i], work[i], rec);
      double W = row.carries ? row.W : 0.0;
      if (row.carries)
        for (uint64_t k = s.bonds.begin(i); k < s.bonds.end(i); ++k) {
          if (!intact[k]) continue;
          const Point4 pi = sw.pt[i], pj = sw.pt[s.bonds.nbr[k]], xi = ref[i], xj = ref[s.bonds.nbr[k]];
          const double Y[3] = {pj.x - pi.x, pj.y - pi.y, pj.z - pi.z};
          const double x[3] = {xj.x - xi.x, xj.y - xi.y, xj.z - xi.z};
          W += kernels::stabilization_energy(row.F, G, s.bonds.weight[k] * s.bonds.volume[k], x, Y);
        }
      energy[i] = W;
    }
    for (std::size_t i = 0; i < n; ++i) {
      double w = 0;
      kernels::affine_sum_row(sw, i, f.data() + 3 * i, w);
      energy[i] += w;
    }
    for (std::size_t i = 0; i < n; ++i) y_old[i] = {sw.pt[i].x, sw.pt[i].y, sw.pt[i].z};
    // The step's commit (Correspondence::commit): the trial history, the plastic work.
    for (std::size_t i = 0; i < n; ++i) {
      committed[i] = trial[i];
      if (work[i] != 0) dissipated[i] += work[i] * s.particles.volume[i];
      plastic += work[i] * s.particles.volume[i];
    }
    bad += differing(f.data(), &s.particles.f[0].x, 3 * n) + differing(energy.data(), s.particles.energy.data(), n) +
           differing(damage.data(), s.particles.damage.data(), n) +
           differing(dissipated.data(), s.dissipated_at.data(), n) + (intact != s.bonds.intact ? 1 : 0);
  }
  if (law_kind == kernels::kJ2Law) {
    EXPECT_GT(plastic, 0) << "the impact is meant to yield";
    std::printf("[ figure ] %s: plastic work of the 40 passes %.6e J\n", name, plastic);
  }
  expect_same_as_host(name, broken, host_broken, bad);
}

TEST(PortableKernels, CorrespondencePassThroughTheKernels) {
  correspondence_through_kernels("correspondence", "", kernels::kLinearElasticLaw);
}

TEST(PortableKernels, CorrespondenceNeoHookeanPassThroughTheKernels) {
  correspondence_through_kernels("correspondence neo_hookean", "stress_law: neo_hookean, ", kernels::kNeoHookeanLaw);
}

TEST(PortableKernels, CorrespondenceJ2PassThroughTheKernels) {
  correspondence_through_kernels("correspondence j2", "stress_law: j2, yield_stress: 4.0e8, hardening_modulus: 2.0e9, ",
                                 kernels::kJ2Law);
}

TEST(PortableKernels, NonlinearSolidPassThroughTheKernels) {
  test::SingleThread one;
  // One bar pulled apart from its middle (the model drops the bonds between bodies, so the
  // impact deck's striker would meet the bar by contact alone): bonds break in tension.
  const std::string deck = R"yaml(dimension: 3
spacing: 1.0e-3
horizon: 3.0e-3
materials:
  steel: {model: nonlinear_solid, density: 7850, youngs_modulus: 200.0e9, poissons_ratio: 0.3,
          damage: {law: energy, fracture_energy: 200.0}}
bodies:
  - {name: bar, material: steel, shape: {box: {min: [0, 0, 0], max: [0.012, 0.004, 0.004]}}}
initial_conditions:
  - {region: all, velocity: ["2000*(x-0.006)", "300*(y-0.002)", "0"]}
solver: {type: explicit, end_time: 1.0, safety_factor: 0.5}
)yaml";
  Simulation sim(parse_deck(deck, "portable.yaml"));
  System& s = sim.system;
  const NonlinearState* N = nonlinear_state(s);
  ASSERT_NE(N, nullptr);
  const std::size_t n = s.particles.size(), nb = s.bonds.size();
  std::vector<uint8_t> intact = s.bonds.intact;
  std::vector<double> eps(nb), theta(n), f(3 * n), energy(n), damage(n), dissipated = s.dissipated_at;
  uint64_t broken = 0, host_broken = 0;
  std::size_t bad = 0;
  for (int step = 0; step < 40; ++step) {
    const uint64_t before = s.broken;
    sim.solver->step(true);
    host_broken += s.broken - before;
    kernels::TupekPass<KindCoefficients> tp;
    tp.pt = s.model.packed.data();  // the pass's input: y
    tp.kc = s.model.kind.data();
    tp.nbr = s.bonds.nbr.data();
    tp.kind = s.bonds.kind.data();
    tp.offset = s.bonds.offset.data();
    tp.intact = intact.data();
    tp.eps = eps.data();
    tp.m = N->m.data();
    tp.lambda_bar = N->lambda_bar.data();
    tp.mu_bar = N->mu_bar.data();
    tp.theta = theta.data();
    tp.beta = N->beta.data();
    tp.compression_only = N->compression_only.data();
    tp.failure_scale = N->failure_scale.data();
    tp.exponent_two = N->failure_exponent_two;
    tp.contact = s.contact.enabled();
    for (std::size_t i = 0; i < n; ++i) theta[i] = kernels::tupek_strain_row(tp, i);
    for (std::size_t i = 0; i < n; ++i) {
      const kernels::TupekRow o = kernels::tupek_force_row(tp, i);
      f[3 * i] = o.f[0], f[3 * i + 1] = o.f[1], f[3 * i + 2] = o.f[2];
      broken += o.broken;
      if (o.lost != 0) dissipated[i] += o.lost * s.particles.volume[i];
      energy[i] = kernels::tupek_row_energy(o, N->lambda_bar[i], N->mu_bar[i], theta[i]);
      damage[i] = kernels::damage_fraction(o.intact_w, o.total_w);
    }
    bad += differing(f.data(), &s.particles.f[0].x, 3 * n) + differing(energy.data(), s.particles.energy.data(), n) +
           differing(damage.data(), s.particles.damage.data(), n) + differing(theta.data(), N->theta.data(), n) +
           differing(eps.data(), N->bond_strain.data(), nb) +
           differing(dissipated.data(), s.dissipated_at.data(), n) + (intact != s.bonds.intact ? 1 : 0);
  }
  expect_same_as_host("nonlinear_solid", broken, host_broken, bad);
}

TEST(PortableKernels, FlatCopyNamesWhatItDoesNotTake) {
  const std::string extended = "{model: extended_correspondence, density: 7850, youngs_modulus: 200.0e9, poissons_ratio: 0.3}";
  Simulation sim(parse_deck(impact_deck(extended, 40, 1.0), "portable.yaml"));
  EXPECT_EQ(flat_unsupported(sim.system, sim.loads),
            "a model without flat rows (the unified models, nonlinear_solid, elastic_plastic, viscoelastic, "
            "microplastic, pals and correspondence have them)");
}

}  // namespace
}  // namespace horizon::verification
