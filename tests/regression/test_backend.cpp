// The explicit backends against each other (solver.backend, --backend; docs/design.md
// "Backends and portable kernels"). The flat backend steps a copy of the run's state with
// the portable row functions of kernels/flat_system.hpp (the code the CUDA backend
// launches), which sum each row in the fast loops' eight lanes and book the ledger's terms
// in the CPU's order: a run with backend flat must give the CPU backend's bits, so these
// tests ask for identical bytes (history.csv, every frame, checkpoints, summary.json's
// state_crc32 and final figures), not a tolerance; with damping, the damped energy to
// 1e-12 (it is summed per particle first). The runs: the glass demo (examples/glass_branching.yaml,
// tractions held fixed, a branching crack) coarsened 4 times, and a PMB and an LPS impact
// of a striker on a bar (initial velocity, bonds breaking). Then what the flat (and CUDA)
// backend refuses, each refusal with its message, naming the deck and the key.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <fmt/format.h>

#include "horizon/core/error.hpp"
#include "horizon/deck/deck.hpp"
#include "horizon/driver/run.hpp"
#include "horizon/material/models/ordinary_lanes.hpp"
#include "../test_paths.hpp"

namespace fs = std::filesystem;

namespace horizon {
namespace {

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Per process: ctest -j runs the tests of this file side by side (and other checkouts'
// tests share /tmp), and two refusal tests once removed each other's directory.
fs::path scratch(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("horizon_test_backend_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

struct Output {
  std::string history;
  std::map<std::string, std::string> frames;  // every file of the output directory but summary.json
  nlohmann::json summary;
  int exit_code = -1;
};

// Runs deck text with a backend; returns what it wrote.
// With `file`, that deck (a file beside its data files; `deck` unused).
Output run(const std::string& deck, const std::string& name, const std::string& backend, double coarsen = 1,
           int threads = 0, const fs::path& deck_file = {}) {
  const fs::path dir = scratch(name + "_" + backend);
  fs::path file = deck_file;
  if (file.empty()) {
    file = dir / (name + ".yaml");
    std::ofstream(file) << deck;
  }
  RunOptions o;
  o.quiet = true;
  o.handle_signals = false;
  o.output_dir = (dir / "out").string();
  o.coarsen = coarsen;
  o.backend = backend;
  o.threads = threads;
  Output out;
  out.exit_code = run_deck(load_deck(file.string()), o);
  for (const auto& e : fs::recursive_directory_iterator(dir / "out"))
    if (e.is_regular_file() && e.path().filename() != "summary.json")
      out.frames[fs::relative(e.path(), dir / "out").string()] = slurp(e.path());
  out.history = slurp(dir / "out" / "history.csv");
  out.summary = nlohmann::json::parse(slurp(dir / "out" / "summary.json"));
  fs::remove_all(dir);
  return out;
}

// The two runs wrote the same bytes, and their summaries the same figures.
void expect_same(const Output& flat, const Output& cpu, const std::string& what) {
  EXPECT_EQ(flat.exit_code, 0);
  EXPECT_EQ(cpu.exit_code, 0);
  EXPECT_EQ(flat.summary["backend"], "flat");
  EXPECT_EQ(cpu.summary["backend"], "cpu");
  EXPECT_EQ(flat.history, cpu.history) << what << ": history.csv";
  ASSERT_EQ(flat.frames.size(), cpu.frames.size());
  for (const auto& [path, bytes] : cpu.frames) {
    ASSERT_TRUE(flat.frames.count(path)) << path;
    EXPECT_TRUE(flat.frames.at(path) == bytes) << what << ": " << path << " differs";
  }
  EXPECT_EQ(flat.summary["state_crc32"], cpu.summary["state_crc32"]);
  EXPECT_EQ(flat.summary["steps"], cpu.summary["steps"]);
  EXPECT_EQ(flat.summary["energy"], cpu.summary["energy"]);
  EXPECT_EQ(flat.summary["damage"], cpu.summary["damage"]);
  std::printf("[ figure ] %s: flat and cpu backends, %s steps: the same bytes (history.csv, %zu files), state_crc32 "
              "%s, summary energy %s\n",
              what.c_str(), cpu.summary["steps"].dump().c_str(), cpu.frames.size(),
              cpu.summary["state_crc32"].dump().c_str(), cpu.summary["energy"].dump().c_str());
}

// examples/glass_branching.yaml with fewer frames; coarsened 4 times (4000 particles).
std::string glass_deck() {
  std::string deck = slurp(fs::path(HORIZON_SOURCE_DIR) / "examples" / "glass_branching.yaml");
  const std::string output = "output: {directory: out/glass_branching, frames: 43, history_every: 10}";
  const std::size_t at = deck.find(output);
  if (at == std::string::npos) return "";
  return deck.replace(at, output.size(), "output: {directory: out/glass_branching, frames: 4, history_every: 10}");
}

const std::string kPmb = "{model: pmb, density: 7850, youngs_modulus: 200.0e9, damage: {critical_stretch: 0.002}}";
const std::string kLps =
    "{model: lps, density: 7850, youngs_modulus: 200.0e9, poissons_ratio: 0.3, damage: {critical_stretch: 0.002}}";

// A striker at 40 m/s on a bar (the verification tests' impact): bonds break at the contact.
std::string impact_deck(const std::string& material, const std::string& extra = "",
                        const std::string& solver_extra = "") {
  return fmt::format(R"(dimension: 3
spacing: 1.0e-3
horizon: 3.0e-3
materials:
  steel: {}
bodies:
  - name: striker
    material: steel
    shape: {{box: {{min: [0, 0, 0], max: [0.006, 0.004, 0.004]}}}}
  - name: bar
    material: steel
    shape: {{box: {{min: [0.006, 0, 0], max: [0.018, 0.004, 0.004]}}}}
regions:
  striker: {{box: {{min: [0, 0, 0], max: [0.006, 0.004, 0.004]}}}}
  end: {{box: {{min: [0.017, 0, 0], max: [0.018, 0.004, 0.004]}}}}
initial_conditions:
  - {{region: striker, velocity: [40, 6.5, 0]}}
{}solver: {{type: explicit, end_time: 3.0e-6, safety_factor: 0.5, energy_balance_warning: 0.5{}}}
output: {{frames: 3, history_every: 7}}
)",
                     material, extra, solver_extra);
}

TEST(Backend, GlassDemoFlatGivesTheCpuBits) {
  const std::string deck = glass_deck();
  ASSERT_FALSE(deck.empty()) << "examples/glass_branching.yaml's output line changed";
  const Output cpu = run(deck, "glass", "cpu", 4);
  const Output flat = run(deck, "glass", "flat", 4);
  // The crack has grown (the demo breaks bonds) and the tractions did work.
  EXPECT_GT(cpu.summary["damage"]["mean"].get<double>(), 0.01);
  expect_same(flat, cpu, "glass_branching --coarsen 4");
}

TEST(Backend, PmbImpactFlatGivesTheCpuBits) {
  const Output cpu = run(impact_deck(kPmb), "pmb_impact", "cpu");
  const Output flat = run(impact_deck(kPmb), "pmb_impact", "flat");
  EXPECT_GT(cpu.summary["damage"]["mean"].get<double>(), 0);
  expect_same(flat, cpu, "pmb impact");
}

TEST(Backend, LpsImpactFlatGivesTheCpuBits) {
  const Output cpu = run(impact_deck(kLps), "lps_impact", "cpu");
  const Output flat = run(impact_deck(kLps), "lps_impact", "flat");
  EXPECT_GT(cpu.summary["damage"]["mean"].get<double>(), 0);
  expect_same(flat, cpu, "lps impact");
}

// Prescribed conditions (issue 30 part B): a clamped end (displacement), the striker's
// y-velocity held (velocity) and a traction on the end's free component, with their
// reactions in history.csv and their work in the ledger.
TEST(Backend, PrescribedConditionsFlatGiveTheCpuBits) {
  const std::string loads =
      "loads:\n  - {region: end, displacement: [0, null, 0]}\n  - {region: striker, velocity: [null, 3, null]}\n"
      "  - {region: end, traction: [0, 2.0e8, 0]}\n";
  const Output cpu = run(impact_deck(kPmb, loads), "prescribed", "cpu");
  const Output flat = run(impact_deck(kPmb, loads), "prescribed", "flat");
  EXPECT_NE(cpu.history.find("end:displacement_fx"), std::string::npos);
  EXPECT_GT(cpu.summary["damage"]["mean"].get<double>(), 0);
  expect_same(flat, cpu, "pmb impact, prescribed conditions");
  const Output lps_cpu = run(impact_deck(kLps, loads), "prescribed_lps", "cpu");
  const Output lps_flat = run(impact_deck(kLps, loads), "prescribed_lps", "flat");
  expect_same(lps_flat, lps_cpu, "lps impact, prescribed conditions");
}

// Loads and conditions that vary in time and space: FlatBackend evaluates them on the host
// before each step (the CPU's expressions at the CPU's times) into the flat arrays.
TEST(Backend, LoadsThatVaryFlatGiveTheCpuBits) {
  const std::string loads =
      "loads:\n  - {region: end, displacement: [\"-2.0*t*(1 + 100*y)\", null, 0]}\n"
      "  - {region: striker, velocity: [null, \"6.5*cos(1.0e6*t)\", null]}\n"
      "  - {region: end, traction: [0, \"2.0e8*min(t/1.0e-6, 1)*(1 + 50*z)\", 0]}\n";
  for (const std::string& material : {kPmb, kLps}) {
    const Output cpu = run(impact_deck(material, loads), "varying", "cpu");
    const Output flat = run(impact_deck(material, loads), "varying", "flat");
    EXPECT_NE(cpu.history.find("end:traction_fy"), std::string::npos);
    expect_same(flat, cpu, material == kPmb ? "pmb impact, loads that vary" : "lps impact, loads that vary");
  }
  // The glass demo with its tractions ramped up over 5 us.
  std::string deck = glass_deck();
  for (const char* sign : {"[0, 2.0e6]", "[0, -2.0e6]"}) {
    const std::size_t at = deck.find(sign);
    ASSERT_NE(at, std::string::npos);
    const std::string ramp = std::string("[0, \"") + (sign[4] == '-' ? "-" : "") + "2.0e6*min(t/5.0e-6, 1)\"]";
    deck.replace(at, std::string(sign).size(), ramp);
  }
  const Output cpu = run(deck, "glass_ramp", "cpu", 4);
  const Output flat = run(deck, "glass_ramp", "flat", 4);
  expect_same(flat, cpu, "glass_branching --coarsen 4, tractions ramped");
}

// Critical stretches that vary in time (damage.critical_stretch as an expression in t):
// FlatBackend sets them before each step at the step's new time, as ExplicitSolver::step
// sets them before its force pass. PMB and LPS impacts with s0 growing from 0.001.
TEST(Backend, CriticalStretchInTimeFlatGivesTheCpuBits) {
  for (const char* model : {"pmb", "lps"}) {
    const std::string material = fmt::format(
        "{{model: {}, density: 7850, youngs_modulus: 200.0e9, {}damage: {{critical_stretch: "
        "\"0.001*(1 + t/1.0e-6)\"}}}}",
        model, std::string(model) == "lps" ? "poissons_ratio: 0.3, " : "");
    const Output cpu = run(impact_deck(material), "s0_in_time", "cpu");
    const Output flat = run(impact_deck(material), "s0_in_time", "flat");
    EXPECT_GT(cpu.summary["damage"]["mean"].get<double>(), 0);
    expect_same(flat, cpu, std::string(model) + " impact, critical stretch in time");
    // The schedule matters: s0 held at its first value breaks other bonds.
    std::string fixed = material;
    fixed.replace(fixed.find("\"0.001*(1 + t/1.0e-6)\""), 22, "0.001");
    EXPECT_NE(run(impact_deck(fixed), "s0_fixed", "cpu").summary["state_crc32"], cpu.summary["state_crc32"]);
  }
}

// damage.breaks: after_force: a breaking bond carries its force in its pass (the fast
// loops' kAfter rows; FlatSystem::break_after). PMB and LPS impacts.
TEST(Backend, BreakAfterForceFlatGivesTheCpuBits) {
  for (const std::string& material : {kPmb, kLps}) {
    std::string after = material;
    after.replace(after.find("critical_stretch: 0.002}"), 24, "critical_stretch: 0.002, breaks: after_force}");
    const Output cpu = run(impact_deck(after), "after_force", "cpu");
    const Output flat = run(impact_deck(after), "after_force", "flat");
    EXPECT_GT(cpu.summary["damage"]["mean"].get<double>(), 0);
    EXPECT_NE(cpu.summary["state_crc32"], run(impact_deck(material), "before_force", "cpu").summary["state_crc32"]);
    expect_same(flat, cpu, (material == kPmb ? "pmb" : "lps") + std::string(" impact, breaks: after_force"));
  }
}

// An irregular cloud (a points body whose bonds carry their own lengths,
// Bonds::length_per_bond): the flat rows finish each bond's constants from its |xi| as the
// fast loops do (kernels::flat_kind). A jittered block of 12 x 10 x 8 points pulled apart
// and squeezed (tests/unit/test_clouds.cpp's deck), PMB with the compression term and LPS
// breaking after the force, both with short-range contact.
std::string cloud_deck(const std::string& material) {
  std::string points;
  uint64_t state = 42;
  auto next = [&state] {  // a fixed sequence in [-1, 1) (Knuth's MMIX LCG)
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) / 4503599627370496.0 - 1.0;
  };
  const double h = 1e-3;
  for (int k = 0; k < 8; ++k)
    for (int j = 0; j < 10; ++j)
      for (int i = 0; i < 12; ++i) {
        const double x = (i + 0.5 + 0.3 * next()) * h, y = (j + 0.5 + 0.3 * next()) * h, z = (k + 0.5 + 0.3 * next()) * h;
        points += fmt::format("{}[{:.17g}, {:.17g}, {:.17g}, 1.0e-9]", points.empty() ? "" : ", ", x, y, z);
      }
  return fmt::format(R"yaml(dimension: 3
spacing: 1.0e-3
horizon: 3.015e-3
materials:
  m: {}
bodies:
  - {{name: b, material: m, shape: {{points: [{}]}}}}
contact:
  short_range: {{stiffness_factor: 15, reference_fraction: 0.9, max_distance: 1.35}}
initial_conditions:
  - {{velocity: ["100*(x-0.006)/0.006", "-50*(y-0.005)/0.005", 0]}}
solver: {{type: explicit, end_time: 1.0e-6, time_step: 5.0e-8}}
output: {{frames: 2, history_every: 5, damage_measure: volume}}
)yaml",
                     material, points);
}

TEST(Backend, IrregularCloudFlatGivesTheCpuBits) {
  const std::string pmb =
      "{model: pmb, density: 2200, micromodulus: 1.0e21, damage: {critical_stretch: 0.002, alpha: 0.25}}";
  const std::string lps = "{model: lps, density: 2200, bulk_modulus: 14.9e9, shear_modulus: 14.9e9, damage: "
                          "{critical_stretch: 0.002, alpha: 0.25, breaks: after_force}}";
  for (const std::string& material : {pmb, lps}) {
    const Output cpu = run(cloud_deck(material), "cloud", "cpu");
    const Output flat = run(cloud_deck(material), "cloud", "flat");
    EXPECT_GT(cpu.summary["damage"]["mean"].get<double>(), 0);
    expect_same(flat, cpu, material == pmb ? "pmb cloud" : "lps cloud, breaks: after_force");
  }
}

// Mass-proportional damping (issue 30 part B, the ledger's damped energy): the flat rows
// book it per particle over the steps and sum the particles at a copy, ExplicitSolver::step
// sums each step's particles first, so the damped energy (and the balance error made with
// it) may differ in the last bits; the state does not (damping enters the kicks alone).
TEST(Backend, DampedRunFlatGivesTheCpuStateAndLedger) {
  const std::string deck = impact_deck(kPmb, "loads:\n  - {region: end, displacement: [0, null, 0]}\n", ", damping: 20000");
  const Output cpu = run(deck, "damped", "cpu");
  const Output flat = run(deck, "damped", "flat");
  EXPECT_EQ(flat.exit_code, 0);
  EXPECT_EQ(flat.summary["state_crc32"], cpu.summary["state_crc32"]);
  for (const auto& [path, bytes] : cpu.frames)
    if (path != "history.csv") {
      EXPECT_TRUE(flat.frames.at(path) == bytes) << path << " differs";
    }
  const double dc = cpu.summary["energy"]["damped"].get<double>(), df = flat.summary["energy"]["damped"].get<double>();
  EXPECT_GT(dc, 0);
  EXPECT_LE(std::abs(df - dc), 1e-12 * dc);
  // history.csv: every column the same text but damped_energy and energy_balance_error.
  std::istringstream a(cpu.history), b(flat.history);
  std::string la, lb;
  std::getline(a, la), std::getline(b, lb);
  ASSERT_EQ(la, lb);
  const std::string header = la;
  int rows = 0;
  while (std::getline(a, la)) {
    ASSERT_TRUE(std::getline(b, lb));
    std::istringstream ca(la), cb(lb), names(header);
    std::string x, y, name;
    while (std::getline(names, name, ',')) {
      std::getline(ca, x, ',');
      std::getline(cb, y, ',');
      if (name == "damped_energy") EXPECT_LE(std::abs(std::stod(x) - std::stod(y)), 1e-12 * std::abs(std::stod(x))) << la;
      else if (name == "energy_balance_error") EXPECT_LE(std::abs(std::stod(x) - std::stod(y)), 1e-12) << la;
      else EXPECT_EQ(x, y) << name << " in " << la;
    }
    ++rows;
  }
  EXPECT_GT(rows, 2);
  std::printf("[ figure ] damped pmb impact: damped energy %.17g (cpu) %.17g (flat), %.1e relative\n", dc, df,
              std::abs(df - dc) / dc);
}

// Short-range contact (issue 30 part B): the Kalthoff-Winkler PMB example (a velocity
// condition, precracks, contact between the crack faces and beyond the families),
// coarsened 4 times, 25 us; and the striker on the bar through contact alone.
TEST(Backend, ShortRangeContactFlatGivesTheCpuBits) {
  std::string deck = slurp(fs::path(HORIZON_SOURCE_DIR) / "examples" / "kalthoff_winkler_pmb.yaml");
  const std::string end = "end_time: 7.0e-5";
  ASSERT_NE(deck.find(end), std::string::npos);
  deck.replace(deck.find(end), end.size(), "end_time: 2.5e-5");
  const Output cpu = run(deck, "kalthoff", "cpu", 4);
  const Output flat = run(deck, "kalthoff", "flat", 4);
  EXPECT_GT(cpu.summary["damage"]["mean"].get<double>(), 0);
  expect_same(flat, cpu, "kalthoff_winkler_pmb --coarsen 4, 25 us");
  // The striker meets the bar through contact alone (no bonds between the bodies): the
  // pairs are beyond the families, in the host's lists; without contact it passes through.
  const std::string unbonded = "bonds_between_bodies: false\n";
  const std::string contact = unbonded + "contact: {short_range: {max_distance: 1.35}}\n";
  const Output lps_cpu = run(impact_deck(kLps, contact), "contact_lps", "cpu");
  const Output lps_flat = run(impact_deck(kLps, contact), "contact_lps", "flat");
  const Output lps_apart = run(impact_deck(kLps, unbonded), "contact_lps_apart", "cpu");
  EXPECT_NE(lps_cpu.summary["state_crc32"], lps_apart.summary["state_crc32"]);
  expect_same(lps_flat, lps_cpu, "lps striker on a bar through short-range contact");
  const Output pmb_cpu = run(impact_deck(kPmb, contact), "contact_pmb", "cpu");
  const Output pmb_flat = run(impact_deck(kPmb, contact), "contact_pmb", "flat");
  expect_same(pmb_flat, pmb_cpu, "pmb striker on a bar through short-range contact");
}

// Tupek's nonlinear solid (kernels/tupek.hpp: the rows NonlinearSolid::force_pass calls,
// over the flat arrays): a bar pulled apart from its middle (bonds break in tension by the
// energy law), and the same with a clamped end (displacement), a held velocity and a
// traction, their reactions and work; then a striker meeting a bar through short-range
// contact alone (the model drops the bonds between bodies: the pairs beyond the families
// in the host's lists, the family contact of broken bonds in the rows). CPU and flat
// backends on 1 and 2 threads: the same bytes, all four.
const std::string kTupek = "{model: nonlinear_solid, density: 7850, youngs_modulus: 200.0e9, poissons_ratio: 0.3, "
                           "damage: {law: energy, fracture_energy: 200.0}}";

std::string pulled_bar_deck(const std::string& loads) {
  return fmt::format(R"yaml(dimension: 3
spacing: 1.0e-3
horizon: 3.0e-3
materials:
  steel: {}
bodies:
  - {{name: bar, material: steel, shape: {{box: {{min: [0, 0, 0], max: [0.012, 0.004, 0.004]}}}}}}
regions:
  left: {{box: {{min: [0, 0, 0], max: [0.001, 0.004, 0.004]}}}}
  right: {{box: {{min: [0.011, 0, 0], max: [0.012, 0.004, 0.004]}}}}
initial_conditions:
  - {{region: all, velocity: ["2000*(x-0.006)", "300*(y-0.002)", "0"]}}
{}solver: {{type: explicit, end_time: 6.0e-6, safety_factor: 0.5, energy_balance_warning: 0.5}}
output: {{frames: 3, history_every: 7}}
)yaml",
                     kTupek, loads);
}

void expect_same_on_threads(const std::string& deck, const std::string& name, const std::string& what) {
  const Output cpu = run(deck, name, "cpu", 1, 1);
  EXPECT_GT(cpu.summary["damage"]["mean"].get<double>(), 0) << what << ": the run is meant to break bonds";
  EXPECT_GT(cpu.summary["energy"]["dissipated"].get<double>(), 0) << what;
  expect_same(run(deck, name, "flat", 1, 1), cpu, what + ", 1 thread");
  expect_same(run(deck, name, "flat", 1, 2), cpu, what + ", flat on 2 threads");
  const Output cpu2 = run(deck, name, "cpu", 1, 2);
  EXPECT_EQ(cpu2.history, cpu.history) << what << ": cpu on 2 threads";
  EXPECT_EQ(cpu2.summary["state_crc32"], cpu.summary["state_crc32"]) << what << ": cpu on 2 threads";
}

// solver.verlet: peridigm (the Peridigm importer's step, issue 30): Peridigm's kicks, the
// force pass on y = (X + u_n) + dt v(n+1/2) (FlatSystem::positions), prescribed
// displacements moved by their increments (a clamp held at 0, whose increment is 0, and
// one that varies) and keeping the second half kick. PMB and LPS, 1 and 2 threads.
TEST(Backend, PeridigmVerletFlatGivesTheCpuBits) {
  const std::string held =
      "loads:\n  - {region: end, displacement: [0, null, 0]}\n  - {region: striker, velocity: [null, 3, null]}\n"
      "  - {region: end, traction: [0, 2.0e8, 0]}\n";
  const std::string varying =
      "loads:\n  - {region: end, displacement: [\"-2.0*t*(1 + 100*y)\", null, 0]}\n"
      "  - {region: striker, velocity: [null, \"6.5*cos(1.0e6*t)\", null]}\n";
  expect_same_on_threads(impact_deck(kPmb, varying, ", verlet: peridigm"), "peridigm_varying",
                         "pmb impact, verlet: peridigm, loads that vary");
  expect_same_on_threads(impact_deck(kLps, held, ", verlet: peridigm"), "peridigm_held",
                         "lps impact, verlet: peridigm, loads held");
  // A Peridigm deck as the importer reads it (solver.verlet: peridigm, prescribed
  // displacements at both ends): every output file the same bytes.
  const fs::path bar = fs::path(HORIZON_SOURCE_DIR) / "tests" / "peridigm" / "tension_bar_bond_based.yaml";
  const Output bar_cpu = run("", "peridigm_bar", "cpu", 1, 0, bar);
  EXPECT_NE(bar_cpu.frames.count("tension_bar_bond_based.e"), 0u);
  expect_same(run("", "peridigm_bar", "flat", 1, 0, bar), bar_cpu, "tests/peridigm/tension_bar_bond_based");
  // The step is Peridigm's: not the bits of verlet: horizon.
  EXPECT_NE(run(impact_deck(kPmb, held, ", verlet: peridigm"), "peridigm_vs", "cpu").summary["state_crc32"],
            run(impact_deck(kPmb, held), "peridigm_vs", "cpu").summary["state_crc32"]);
}

TEST(Backend, NonlinearSolidFlatGivesTheCpuBits) {
  expect_same_on_threads(pulled_bar_deck(""), "tupek_pulled", "nonlinear_solid bar pulled apart");
  const std::string loads =
      "loads:\n  - {region: left, displacement: [0, null, 0]}\n  - {region: right, velocity: [null, 3, null]}\n"
      "  - {region: right, traction: [\"4.0e8*min(t/2.0e-6, 1)\", 0, 0]}\n";
  expect_same_on_threads(pulled_bar_deck(loads), "tupek_loaded", "nonlinear_solid bar, prescribed conditions");
  const std::string contact = "contact: {short_range: {max_distance: 1.35}}\n";
  const std::string striker =
      "{model: nonlinear_solid, density: 7850, youngs_modulus: 200.0e9, poissons_ratio: 0.3, "
      "damage: {law: energy, fracture_energy: 20.0}}";
  std::string deck = impact_deck(striker, contact);
  const std::string v = "velocity: [40, 6.5, 0]";
  ASSERT_NE(deck.find(v), std::string::npos);
  deck.replace(deck.find(v), v.size(), "velocity: [200, 30, 0]");
  expect_same_on_threads(deck, "tupek_contact", "nonlinear_solid striker on a bar through short-range contact");
}

// The adaptive step (solver.adaptive_time_step): the flat backend computes the nonlinear
// solid's stable step over its copy with the host's rows (kernels::flat_tupek_stable_step)
// and takes each step with the solver's dt, the loads that vary at the summed times. The
// Kalthoff-Winkler example (2-D, plane strain, precracks, a velocity condition, contact,
// the failure-length exponent 0, a new step every 10) coarsened 4 times, 25 us; the pulled
// bar with its ramped traction, a new step every 3.
TEST(Backend, NonlinearSolidAdaptiveStepFlatGivesTheCpuBits) {
  std::string deck = slurp(fs::path(HORIZON_SOURCE_DIR) / "examples" / "kalthoff_winkler.yaml");
  const std::string end = "end_time: 7.0e-5";
  ASSERT_NE(deck.find(end), std::string::npos);
  deck.replace(deck.find(end), end.size(), "end_time: 2.5e-5");
  const Output cpu = run(deck, "kalthoff_adaptive", "cpu", 4, 1);
  EXPECT_GT(cpu.summary["energy"]["dissipated"].get<double>(), 0);
  EXPECT_LT(cpu.summary["time_step_range"][0].get<double>(), cpu.summary["time_step_range"][1].get<double>());
  expect_same(run(deck, "kalthoff_adaptive", "flat", 4, 1), cpu, "kalthoff_winkler --coarsen 4, 25 us, adaptive step");
  std::string bar = pulled_bar_deck(
      "loads:\n  - {region: left, displacement: [0, null, 0]}\n"
      "  - {region: right, traction: [\"4.0e8*min(t/2.0e-6, 1)\", 0, 0]}\n");
  const std::string solver = "energy_balance_warning: 0.5";
  ASSERT_NE(bar.find(solver), std::string::npos);
  bar.replace(bar.find(solver), solver.size(), solver + ", adaptive_time_step: true, adaptive_every: 3");
  const Output bar_cpu = run(bar, "tupek_adaptive", "cpu", 1, 1);
  EXPECT_GT(bar_cpu.summary["energy"]["dissipated"].get<double>(), 0);
  expect_same(run(bar, "tupek_adaptive", "flat", 1, 2), bar_cpu, "nonlinear_solid bar, adaptive step, ramped traction");
}

// The ordinary history models (kernels/flat_ordinary.hpp: the scalar pass's sweeps and
// the models' rows in the AVX-512 lanes' order, their commit in place): elastic_plastic
// and viscoelastic on the striker-on-bar impact (yielding, bonds breaking), with
// prescribed conditions and loads that vary, with breaks: after_force and the family's
// short-range contact, and viscoelastic in 2-D plane strain (its relaxing pressure). CPU
// and flat backends on 1 and 2 threads: the same bytes (history.csv with the plastic and
// viscous dissipation, every frame with the models' fields, state_crc32). The CPU's rows
// sum in the lanes only on a machine with AVX-512 (lanes::wide()); elsewhere they sum in
// bond order and the flat rows agree with them to round-off, not bits.
const std::string kEps = "{model: elastic_plastic, density: 7850, youngs_modulus: 200.0e9, poissons_ratio: 0.3, "
                         "yield_stress: 150.0e6, hardening_modulus: 2.0e9, damage: {critical_stretch: 0.01}}";
const std::string kVes = "{model: viscoelastic, density: 7850, youngs_modulus: 200.0e9, poissons_ratio: 0.3, "
                         "lambda_1: 0.4, tau_1: 2.0e-7, lambda_2: 0.3, tau_2: 1.0e-6, damage: {critical_stretch: 0.003}}";
const std::string kOrdinaryLoads =
    "loads:\n  - {region: end, displacement: [\"-2.0*t*(1 + 100*y)\", null, 0]}\n"
    "  - {region: striker, velocity: [null, \"6.5*cos(1.0e6*t)\", null]}\n"
    "  - {region: end, traction: [0, \"2.0e8*min(t/1.0e-6, 1)\", 0]}\n";

// The impact at 100 m/s (viscoelastic: it relaxes and breaks bonds in 3 us).
std::string ordinary_impact_deck(const std::string& material, const std::string& extra = "") {
  std::string deck = impact_deck(material, extra);
  const std::string v = "velocity: [40, 6.5, 0]";
  deck.replace(deck.find(v), v.size(), "velocity: [100, 6.5, 0]");
  return deck;
}

std::string after_force_with_contact(std::string material) {
  const std::string c = "damage: {critical_stretch: ";
  material.replace(material.find(c), c.size(), "damage: {breaks: after_force, critical_stretch: ");
  return material;
}

// elastic_plastic at the impact's 40 m/s: it yields (the striker's end) and breaks bonds.
// (At 100 m/s its dissipated energy turns negative on the CPU as on the flat rows: bonds
// that reached the critical stretch by plastic flow break in tension at particles in
// compression, and leaving theta they raise the stored energy more than they held; a
// property of the model, docs/models/elastic_plastic.md "Energy, damage".)
TEST(Backend, ElasticPlasticFlatGivesTheCpuBits) {
  if (!lanes::wide()) GTEST_SKIP() << "the CPU's ordinary rows sum in bond order here (no AVX-512)";
  expect_same_on_threads(impact_deck(kEps), "eps_impact", "elastic_plastic impact");
  expect_same_on_threads(impact_deck(kEps, kOrdinaryLoads), "eps_loads",
                         "elastic_plastic impact, prescribed conditions and loads that vary");
  expect_same_on_threads(impact_deck(after_force_with_contact(kEps), "contact: {short_range: {max_distance: 1.35}}\n"),
                         "eps_after", "elastic_plastic impact, breaks: after_force, short-range contact");
}

TEST(Backend, ViscoelasticFlatGivesTheCpuBits) {
  if (!lanes::wide()) GTEST_SKIP() << "the CPU's ordinary rows sum in bond order here (no AVX-512)";
  expect_same_on_threads(ordinary_impact_deck(kVes), "ves_impact", "viscoelastic impact");
  expect_same_on_threads(ordinary_impact_deck(kVes, kOrdinaryLoads), "ves_loads",
                         "viscoelastic impact, prescribed conditions and loads that vary");
  expect_same_on_threads(
      ordinary_impact_deck(after_force_with_contact(kVes), "contact: {short_range: {max_distance: 1.35}}\n"),
      "ves_after", "viscoelastic impact, breaks: after_force, short-range contact");
  // 2-D plane strain: the dilatation's relaxing part (Viscoelastic::pressure).
  const std::string plate = fmt::format(R"yaml(dimension: 2
plane: strain
thickness: 0.001
spacing: 1.0e-3
horizon: 3.0e-3
materials:
  steel: {}
bodies:
  - {{name: plate, material: steel, shape: {{box: {{min: [0, 0], max: [0.02, 0.01]}}}}}}
regions:
  left: {{box: {{min: [0, 0], max: [0.001, 0.01]}}}}
initial_conditions:
  - {{region: all, velocity: ["3000*(x-0.01)", "-800*(y-0.005)"]}}
loads:
  - {{region: left, velocity: [null, 2]}}
solver: {{type: explicit, end_time: 4.0e-6, safety_factor: 0.5, energy_balance_warning: 0.5}}
output: {{frames: 3, history_every: 7}}
)yaml",
                                        kVes);
  expect_same_on_threads(plate, "ves_plane", "viscoelastic plate, plane strain");
}

// microplastic (kernels/flat_ordinary.hpp micro_flat_row: the AVX-512 lanes' micro_body):
// the striker-on-bar impact, which yields (the plastic stretch of the striker's bonds) and
// breaks bonds, then with prescribed conditions and loads that vary, then with breaks:
// after_force and the family's short-range contact.
const std::string kMicro = "{model: microplastic, density: 7850, youngs_modulus: 200.0e9, yield_stretch: 0.0005, "
                           "damage: {critical_stretch: 0.002}}";

TEST(Backend, MicroplasticFlatGivesTheCpuBits) {
  if (!lanes::wide()) GTEST_SKIP() << "the CPU's ordinary rows sum in bond order here (no AVX-512)";
  const Output cpu = run(impact_deck(kMicro), "micro_impact", "cpu", 1, 1);
  EXPECT_GT(cpu.summary["energy"]["dissipated"].get<double>(), 0);  // it yields and breaks
  EXPECT_GT(cpu.summary["damage"]["mean"].get<double>(), 0);
  expect_same_on_threads(impact_deck(kMicro), "micro_impact", "microplastic impact");
  expect_same_on_threads(impact_deck(kMicro, kOrdinaryLoads), "micro_loads",
                         "microplastic impact, prescribed conditions and loads that vary");
  expect_same_on_threads(impact_deck(after_force_with_contact(kMicro), "contact: {short_range: {max_distance: 1.35}}\n"),
                         "micro_after", "microplastic impact, breaks: after_force, short-range contact");
}

// pals (kernels/flat_ordinary.hpp pals_flat_row: kernels::pals_row in bond order, as the
// CPU's Pals::force_row; the breaking sweep and the sum in the lanes): the impact that
// breaks bonds, with loads that vary, with breaks: after_force and short-range contact.
const std::string kPals = "{model: pals, density: 7850, youngs_modulus: 200.0e9, poissons_ratio: 0.3, "
                          "damage: {critical_stretch: 0.002}}";

TEST(Backend, PalsFlatGivesTheCpuBits) {
  if (!lanes::wide()) GTEST_SKIP() << "the CPU's ordinary sweeps sum in bond order here (no AVX-512)";
  const Output cpu = run(impact_deck(kPals), "pals_impact", "cpu", 1, 1);
  EXPECT_GT(cpu.summary["damage"]["mean"].get<double>(), 0);
  expect_same_on_threads(impact_deck(kPals), "pals_impact", "pals impact");
  expect_same_on_threads(impact_deck(kPals, kOrdinaryLoads), "pals_loads",
                         "pals impact, prescribed conditions and loads that vary");
  expect_same_on_threads(impact_deck(after_force_with_contact(kPals), "contact: {short_range: {max_distance: 1.35}}\n"),
                         "pals_after", "pals impact, breaks: after_force, short-range contact");
}

// A checkpoint written by a flat run is the CPU run's (the same bytes), and a restart from
// it with backend flat ends where the uninterrupted CPU run ends.
void expect_checkpoint_and_restart(const std::string& deck, const std::string& name, double coarsen) {
  const Output cpu = run(deck, name, "cpu", coarsen);
  const fs::path dir = scratch(name + "_restart");
  const fs::path file = dir / (name + ".yaml");
  std::ofstream(file) << deck;
  RunOptions o;
  o.quiet = true;
  o.handle_signals = false;
  o.output_dir = (dir / "out").string();
  o.coarsen = coarsen;
  o.backend = "flat";
  ASSERT_EQ(run_deck(load_deck(file.string()), o), 0);
  EXPECT_TRUE(slurp(dir / "out" / "checkpoint.hzc") == cpu.frames.at("checkpoint.hzc")) << name << ": the checkpoints differ";
  o.restart = (dir / "out" / "checkpoint.hzc").string();
  ASSERT_EQ(run_deck(load_deck(file.string()), o), 0);
  EXPECT_EQ(slurp(dir / "out" / "history.csv"), cpu.history) << name;
  const auto summary = nlohmann::json::parse(slurp(dir / "out" / "summary.json"));
  EXPECT_EQ(summary["state_crc32"], cpu.summary["state_crc32"]) << name;
  EXPECT_EQ(summary["steps"], cpu.summary["steps"]) << name;
  fs::remove_all(dir);
}

// The other models on an irregular cloud (issue 30): setup_model gives every model but pmb
// and lps kinds with their lengths (solver/build.cpp kinds_need_lengths, expand_kinds), as
// the CPU's passes read them, and the flat rows read the same kinds: the jittered block of
// IrregularCloudFlatGivesTheCpuBits (with its short-range contact) in steel, stretched until
// bonds break (nonlinear_solid and correspondence also with the adaptive step), cpu and
// flat on 1 and 2 threads, the same bytes. elastic_plastic and viscoelastic ask for the
// CPU's eight lanes (AVX-512), as their impacts below.
const std::string kCloudTupek = "{model: nonlinear_solid, density: 7850, youngs_modulus: 200.0e9, poissons_ratio: 0.3, "
                                "damage: {law: energy, fracture_energy: 200.0}}";

// The cloud deck with the adaptive step, a new step every 3 (nonlinear_solid, correspondence).
std::string adaptive(std::string deck) {
  const std::string fixed = "end_time: 1.0e-6, time_step: 5.0e-8}";
  deck.replace(deck.find(fixed), fixed.size(),
               "end_time: 1.0e-6, adaptive_time_step: true, adaptive_every: 3, safety_factor: 0.5}");
  return deck;
}

TEST(Backend, NonlinearSolidOnAnIrregularCloudFlatGivesTheCpuBits) {
  expect_same_on_threads(cloud_deck(kCloudTupek), "cloud_tupek", "nonlinear_solid cloud");
  expect_same_on_threads(adaptive(cloud_deck(kCloudTupek)), "cloud_tupek_adaptive",
                         "nonlinear_solid cloud, adaptive step");
}

TEST(Backend, ElasticPlasticOnAnIrregularCloudFlatGivesTheCpuBits) {
  if (!lanes::wide()) GTEST_SKIP() << "the CPU's ordinary rows sum in bond order here (no AVX-512)";
  expect_same_on_threads(cloud_deck("{model: elastic_plastic, density: 7850, youngs_modulus: 200.0e9, "
                                    "poissons_ratio: 0.3, yield_stress: 150.0e6, hardening_modulus: 2.0e9, "
                                    "damage: {critical_stretch: 0.01}}"),
                         "cloud_eps", "elastic_plastic cloud");
}

TEST(Backend, ViscoelasticOnAnIrregularCloudFlatGivesTheCpuBits) {
  if (!lanes::wide()) GTEST_SKIP() << "the CPU's ordinary rows sum in bond order here (no AVX-512)";
  expect_same_on_threads(cloud_deck("{model: viscoelastic, density: 7850, youngs_modulus: 200.0e9, "
                                    "poissons_ratio: 0.3, lambda_1: 0.4, tau_1: 2.0e-7, lambda_2: 0.3, "
                                    "tau_2: 1.0e-6, damage: {critical_stretch: 0.003, breaks: after_force}}"),
                         "cloud_ves", "viscoelastic cloud, breaks: after_force");
}

TEST(Backend, MicroplasticAndPalsOnAnIrregularCloudFlatGiveTheCpuBits) {
  if (!lanes::wide()) GTEST_SKIP() << "the CPU's ordinary rows sum in bond order here (no AVX-512)";
  expect_same_on_threads(cloud_deck("{model: microplastic, density: 7850, youngs_modulus: 200.0e9, "
                                    "yield_stretch: 0.0005, damage: {critical_stretch: 0.002}}"),
                         "cloud_micro", "microplastic cloud");
  expect_same_on_threads(cloud_deck("{model: pals, density: 7850, youngs_modulus: 200.0e9, poissons_ratio: 0.3, "
                                    "damage: {critical_stretch: 0.002, breaks: after_force}}"),
                         "cloud_pals", "pals cloud, breaks: after_force");
}

TEST(Backend, CorrespondenceOnAnIrregularCloudFlatGivesTheCpuBits) {
  const std::string steel = "{model: correspondence, density: 7850, youngs_modulus: 200.0e9, poissons_ratio: 0.3, ";
  expect_same_on_threads(cloud_deck(steel + "stabilization: 0.5, damage: {critical_stretch: 0.002}}"), "cloud_corr",
                         "correspondence cloud, linear elastic, stabilised");
  expect_same_on_threads(cloud_deck(steel + "stress_law: j2, yield_stress: 4.0e8, hardening_modulus: 2.0e9, "
                                            "stabilization: 0.5, damage: {critical_stretch: 0.002}}"),
                         "cloud_corr_j2", "correspondence cloud, j2");
  expect_same_on_threads(adaptive(cloud_deck(steel + "stabilization: 0.5, damage: {critical_stretch: 0.002}}")),
                         "cloud_corr_adaptive", "correspondence cloud, adaptive step");
}

// The correspondence model (kernels/flat_affine.hpp: forces_affine.cpp's breaking sweep and
// pair sum, Correspondence::affine_row's law and energy, its commit, over the flat arrays):
// the striker on the bar, bonds breaking, for the linear elastic law stabilised, J2
// (plastic work into the ledger), neo-Hookean and the rate form hypoelastic_j2; CPU and
// flat backends on 1 and 2 threads, the same bytes (the frames hold the model's von Mises
// stress, equivalent plastic strain and singular flags, written back from the copy).
std::string correspondence(const std::string& law) {
  return "{model: correspondence, density: 7850, youngs_modulus: 200.0e9, poissons_ratio: 0.3, " + law +
         "damage: {critical_stretch: 0.002}}";
}
const std::string kJ2Law = "stress_law: j2, yield_stress: 4.0e8, hardening_modulus: 2.0e9, ";

TEST(Backend, CorrespondenceFlatGivesTheCpuBits) {
  const std::string linear = impact_deck(correspondence("stabilization: 0.5, "));
  expect_same(run(linear, "corr_linear", "flat"), run(linear, "corr_linear", "cpu"),
              "correspondence linear elastic, stabilised");
  expect_same_on_threads(impact_deck(correspondence(kJ2Law + "stabilization: 0.5, ")), "corr_j2",
                         "correspondence j2, stabilised");
  const std::string nh = impact_deck(correspondence("stress_law: neo_hookean, stabilization: 0.2, "));
  expect_same(run(nh, "corr_nh", "flat"), run(nh, "corr_nh", "cpu"), "correspondence neo_hookean");
  expect_same_on_threads(
      impact_deck(correspondence("stress_law: hypoelastic_j2, yield_stress: 4.0e8, hardening_modulus: 2.0e9, "
                                 "stabilization: 0.5, ")),
      "corr_hypo", "correspondence hypoelastic_j2");
}

// The options of the pass: 2-D plane strain, no stabilisation, bonds breaking after the
// force, short-range contact between family pairs and beyond, prescribed conditions, two
// correspondence materials (with the adaptive step too), and a checkpoint (the models' committed and trial histories,
// records, positions) with its restart.
// solver.verlet: peridigm with the other models that have flat rows: elastic_plastic and
// viscoelastic (their pack_row reads FlatSystem::positions, as pack_positions reads
// System::positions), correspondence and the nonlinear solid (which packs X + u itself on
// the CPU, as tupek_pack_row does), each with Peridigm's kicks and increments; and each
// not the bits of verlet: horizon.
TEST(Backend, PeridigmVerletOtherModelsFlatGiveTheCpuBits) {
  auto pv = [](std::string d) {
    const std::string k = "energy_balance_warning: 0.5";
    return d.replace(d.find(k), k.size(), k + ", verlet: peridigm");
  };
  expect_same_on_threads(pv(impact_deck(kEps, kOrdinaryLoads)), "xp_eps", "eps peridigm");
  expect_same_on_threads(pv(ordinary_impact_deck(kVes, kOrdinaryLoads)), "xp_ves", "ves peridigm");
  expect_same_on_threads(pv(impact_deck(correspondence("stabilization: 0.5, "), kOrdinaryLoads)), "xp_corr", "corr peridigm");
  expect_same_on_threads(pv(pulled_bar_deck("")), "xp_tupek", "tupek peridigm");
  for (const std::string& d : {impact_deck(kEps, kOrdinaryLoads), ordinary_impact_deck(kVes, kOrdinaryLoads),
                               impact_deck(correspondence("stabilization: 0.5, "), kOrdinaryLoads), pulled_bar_deck("")})
    EXPECT_NE(run(pv(d), "xp_vs", "cpu").summary["state_crc32"], run(d, "xp_vs", "cpu").summary["state_crc32"]);
}

TEST(Backend, CorrespondenceOptionsFlatGiveTheCpuBits) {
  const std::string plate = R"yaml(dimension: 2
plane: strain
thickness: 1.0e-3
spacing: 5.0e-4
horizon: 1.5e-3
materials:
  steel: {model: correspondence, density: 7850, youngs_modulus: 200.0e9, poissons_ratio: 0.3, stabilization: 0.5,
          stress_law: j2, yield_stress: 3.0e8, hardening_modulus: 2.0e9, damage: {critical_stretch: 0.004}}
bodies:
  - {name: plate, material: steel, shape: {box: {min: [0, 0], max: [0.012, 0.006]}}}
initial_conditions:
  - {region: all, velocity: ["4000*(x-0.006)", "0"]}
solver: {type: explicit, end_time: 4.0e-6, safety_factor: 0.5, energy_balance_warning: 0.5}
output: {frames: 3, history_every: 7}
)yaml";
  expect_same_on_threads(plate, "corr_plane_strain", "correspondence j2, 2-D plane strain");
  // 2-D plane stress: the out-of-plane stretch's secant iteration in the flat row
  // (kernels/plane_stress.hpp law_point_row), its lambda3 committed per particle; J2 and
  // neo-Hookean (the iteration's two kinds of law), bonds breaking.
  std::string stress = plate;
  stress.replace(stress.find("plane: strain"), 13, "plane: stress");
  expect_same_on_threads(stress, "corr_plane_stress", "correspondence j2, 2-D plane stress");
  std::string neo = stress;
  neo.replace(neo.find("stress_law: j2"), 14, "stress_law: neo_hookean");
  expect_same_on_threads(neo, "corr_plane_stress_neo", "correspondence neo-Hookean, 2-D plane stress");
  std::string after = correspondence(kJ2Law + "stabilization: 0, ");
  after.replace(after.find("critical_stretch: 0.002}"), 24, "critical_stretch: 0.002, breaks: after_force}");
  expect_same_on_threads(impact_deck(after), "corr_after", "correspondence j2 unstabilised, breaks: after_force");
  const std::string contact = "contact: {short_range: {max_distance: 1.35}}\n";
  const std::string loads =
      "loads:\n  - {region: end, displacement: [0, null, 0]}\n  - {region: striker, velocity: [null, 3, null]}\n"
      "  - {region: end, traction: [0, \"2.0e8*min(t/1.0e-6, 1)\", 0]}\n";
  expect_same_on_threads(impact_deck(correspondence(kJ2Law + "stabilization: 0.5, "), contact + loads),
                         "corr_contact_loads", "correspondence j2, short-range contact and prescribed conditions");
  // Two correspondence materials (a J2 striker on a hypoelastic_j2 bar of another
  // stabilisation: per-material constants, both histories), and its checkpoint.
  std::string ck = impact_deck(correspondence(kJ2Law + "stabilization: 0.5, "));
  const std::string materials = "materials:\n  steel: {";
  ASSERT_NE(ck.find(materials), std::string::npos);
  ck.replace(ck.find(materials), materials.size(),
             "materials:\n  soft: {model: correspondence, density: 2700, youngs_modulus: 70.0e9, poissons_ratio: 0.33, "
             "stabilization: 0.2, stress_law: hypoelastic_j2, yield_stress: 2.0e8, hardening_modulus: 1.0e9, "
             "damage: {critical_stretch: 0.003}}\n  steel: {");
  const std::string bar = "  - name: bar\n    material: steel";
  ASSERT_NE(ck.find(bar), std::string::npos);
  ck.replace(ck.find(bar), bar.size(), "  - name: bar\n    material: soft");
  expect_same_on_threads(ck, "corr_two", "correspondence j2 striker on a hypoelastic_j2 bar");
  // The adaptive step (the model's stable step over the System, the fields copied back for
  // it every 3 steps; the rate form's F_dot over each step's own dt).
  std::string adaptive = ck;
  const std::string solver = "energy_balance_warning: 0.5";
  ASSERT_NE(adaptive.find(solver), std::string::npos);
  adaptive.replace(adaptive.find(solver), solver.size(), solver + ", adaptive_time_step: true, adaptive_every: 3");
  const Output adaptive_cpu = run(adaptive, "corr_adaptive", "cpu", 1, 1);
  EXPECT_LT(adaptive_cpu.summary["time_step_range"][0].get<double>(),
            adaptive_cpu.summary["time_step_range"][1].get<double>());
  expect_same(run(adaptive, "corr_adaptive", "flat", 1, 2), adaptive_cpu,
              "correspondence j2 striker on a hypoelastic_j2 bar, adaptive step");
  const std::string out = "output: {frames: 3, history_every: 7}";
  ASSERT_NE(ck.find(out), std::string::npos);
  ck.replace(ck.find(out), out.size(), "output: {frames: 3, history_every: 7, checkpoint: {every: 40}}");
  expect_checkpoint_and_restart(ck, "ck_corr", 1);
}

TEST(Backend, FlatCheckpointAndRestartGiveTheCpuBits) {
  std::string deck = glass_deck();
  const std::string frames = "frames: 4, history_every: 10}";
  ASSERT_NE(deck.find(frames), std::string::npos);
  deck.replace(deck.find(frames), frames.size(), "frames: 4, history_every: 10, checkpoint: {every: 70}}");
  expect_checkpoint_and_restart(deck, "ck", 4);
  // The nonlinear solid with the adaptive step: the checkpoint holds its bond strains,
  // theta and nonlocal damage, which the flat backend writes back into the model's state.
  std::string bar = pulled_bar_deck("");
  const std::string solver = "energy_balance_warning: 0.5";
  bar.replace(bar.find(solver), solver.size(), solver + ", adaptive_time_step: true, adaptive_every: 4");
  const std::string out = "output: {frames: 3, history_every: 7}";
  ASSERT_NE(bar.find(out), std::string::npos);
  bar.replace(bar.find(out), out.size(), "output: {frames: 3, history_every: 7, checkpoint: {every: 50}}");
  expect_checkpoint_and_restart(bar, "ck_tupek", 1);
  // The ordinary models: the checkpoint holds their history (e^dp, the back extensions, sbar, the
  // ledger's flags and stored energy; the committed t and e rebuilt from |Y| and q). The
  // restart's first step is the CPU's (its ledger in arrays), then the flat rows.
  if (!lanes::wide()) return;  // (the CPU's ordinary rows sum in bond order here)
  for (const std::string& material : {kEps, kVes, kMicro, kPals}) {
    std::string deck = material == kVes ? ordinary_impact_deck(material, kOrdinaryLoads) : impact_deck(material, kOrdinaryLoads);
    const std::string o = "output: {frames: 3, history_every: 7}";
    deck.replace(deck.find(o), o.size(), "output: {frames: 3, history_every: 7, checkpoint: {every: 20}}");
    expect_checkpoint_and_restart(deck, material == kEps ? "ck_eps" : material == kVes ? "ck_ves" : material == kMicro ? "ck_micro" : "ck_pals", 1);
  }
}

// A step too large: the state turns non-finite (exit status 2). The flat backend finds the
// failing step again and leaves the System as ExplicitSolver::step does: the same message,
// history.csv, final frame and summary.
// The state fails at step 96: inside a run of quiet steps (history every 7 steps) and at a
// history row's step (every 8: the quiet steps before it were taken in an earlier call).
TEST(Backend, NonFiniteStateFlatGivesTheCpuEnd) {
  for (const char* every : {"history_every: 7", "history_every: 8"}) {
    std::string deck = impact_deck("{model: pmb, density: 7850, youngs_modulus: 200.0e9}");
    const std::string solver = "end_time: 3.0e-6, safety_factor: 0.5";
    ASSERT_NE(deck.find(solver), std::string::npos);
    deck.replace(deck.find(solver), solver.size(), "end_time: 1.0e-3, time_step: 1.0e-6");
    deck.replace(deck.find("history_every: 7"), 16, every);
    const Output cpu = run(deck, "non_finite", "cpu");
    const Output flat = run(deck, "non_finite", "flat");
    EXPECT_EQ(cpu.exit_code, 2);
    EXPECT_EQ(flat.exit_code, 2);
    EXPECT_NE(cpu.summary["message"].get<std::string>().find("non-finite at step 96"), std::string::npos)
        << cpu.summary["message"];
    EXPECT_EQ(flat.summary["message"], cpu.summary["message"]);
    EXPECT_EQ(flat.summary["state_crc32"], cpu.summary["state_crc32"]) << every;
    EXPECT_EQ(flat.history, cpu.history) << every;
    ASSERT_EQ(flat.frames.size(), cpu.frames.size());
    for (const auto& [path, bytes] : cpu.frames) EXPECT_TRUE(flat.frames.at(path) == bytes) << path << " differs";
  }
}

// The message of a run refused by a backend ("" if it ran).
std::string refusal(const std::string& deck, const std::string& backend = "flat") {
  const fs::path dir = scratch("refusal");
  const fs::path file = dir / "refused.yaml";
  std::ofstream(file) << deck;
  RunOptions o;
  o.quiet = true;
  o.handle_signals = false;
  o.output_dir = (dir / "out").string();
  o.backend = backend;
  std::string message;
  try {
    run_deck(load_deck(file.string()), o);
  } catch (const Error& e) {
    message = e.what();
  }
  fs::remove_all(dir);
  return message;
}

void expect_refused(const std::string& deck, const std::string& why) {
  const std::string m = refusal(deck);
  EXPECT_NE(m.find("refused.yaml: --backend flat cannot take this run: it has " + why), std::string::npos) << m;
  EXPECT_NE(m.find("use backend cpu"), std::string::npos) << m;
}

TEST(Backend, FlatRefusesWhatItDoesNotCover) {
  expect_refused(impact_deck("{model: extended_correspondence, density: 7850, youngs_modulus: 200.0e9, poissons_ratio: 0.3}"),
                 "model extended_correspondence (materials.steel.model), which has no flat rows");
  // The ordinary models' rows take one material.
  std::string two = impact_deck(kEps);
  two.replace(two.find("  steel: "), 9, "  soft: " + kLps + "\n  steel: ");
  two.replace(two.find("name: bar\n    material: steel"), 29, "name: bar\n    material: soft");
  expect_refused(two, "model elastic_plastic with other materials");
  expect_refused(impact_deck(kPmb, "contact: {short_range: {law: peridigm, contact_radius: 0.0009, spring_constant: "
                                   "1.0e11, friction: 0.3}}\n"),
                 "short-range contact with friction (contact.short_range.friction)");
  expect_refused(impact_deck("{model: pmb, density: 7850, youngs_modulus: 200.0e9, damage: {critical_stretch: 0.002}, "
                             "thermal: {conductivity: 30, specific_heat: 880}}",
                             "thermal: {initial_temperature: 300}\n"),
                 "heat conduction");
}

TEST(Backend, CudaIsRefusedWithoutCuda) {
  const std::string m = refusal(impact_deck(kPmb), "cuda");
  // A build without -DHORIZON_CUDA=ON, or one on a machine without a device.
  const bool no_build = m.find("refused.yaml: --backend cuda: this horizon was built without CUDA") != std::string::npos;
  const bool no_device = m.find("refused.yaml: --backend cuda: no CUDA device") != std::string::npos;
  EXPECT_TRUE(no_build || no_device || m.empty()) << m;
}

TEST(Backend, DeckKeyIsReadAndPlaced) {
  // solver.backend in the deck: the refusal names its line and column.
  const fs::path dir = scratch("deck_key");
  const fs::path file = dir / "keyed.yaml";
  const std::string after = "{model: extended_correspondence, density: 7850, youngs_modulus: 200.0e9, poissons_ratio: 0.3}";
  std::ofstream(file) << impact_deck(after, "", ", backend: flat");
  RunOptions o;
  o.quiet = true;
  o.handle_signals = false;
  o.output_dir = (dir / "out").string();
  std::string m;
  try {
    run_deck(load_deck(file.string()), o);
  } catch (const Error& e) {
    m = e.what();
  }
  EXPECT_NE(m.find("keyed.yaml:18:"), std::string::npos) << m;
  EXPECT_NE(m.find(": solver.backend: flat cannot take this run: it has model extended_correspondence (materials.steel.model)"),
            std::string::npos)
      << m;
  // A name that is none of the three: the deck's error, with the choices.
  std::ofstream(file) << impact_deck(kPmb, "", ", backend: gpu");
  try {
    load_deck(file.string());
    ADD_FAILURE() << "backend: gpu was read";
  } catch (const Error& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find("keyed.yaml:18:"), std::string::npos) << w;
    EXPECT_NE(w.find("cuda"), std::string::npos) << w;
  }
  // Explicit runs only.
  std::ofstream(file) << "dimension: 3\nspacing: 1.0e-3\nhorizon: 3.0e-3\nmaterials:\n  steel: " + kPmb +
                             "\nbodies:\n  - {name: bar, material: steel, shape: {box: {min: [0, 0, 0], max: [0.004, "
                             "0.004, 0.004]}}}\nsolver: {type: static, backend: flat}\n";
  try {
    load_deck(file.string());
    ADD_FAILURE() << "backend with type static was read";
  } catch (const Error& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find("solver.backend: applies to type: explicit only"), std::string::npos) << w;
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace horizon
