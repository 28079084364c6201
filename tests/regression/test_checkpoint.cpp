// Checkpoint and restart (output/checkpoint.hpp, docs/input.md output.checkpoint): a run
// with fracture and contact, straight against checkpoint + restart, must end with the
// same bytes in its last frame, history.csv and frames.pvd and the same summary figures;
// a damaged checkpoint and a checkpoint of another deck are clear errors.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "horizon/core/error.hpp"
#include "horizon/deck/deck.hpp"
#include "horizon/driver/run.hpp"
#include "horizon/solver/explicit.hpp"

namespace fs = std::filesystem;
using namespace horizon;

namespace {

// A reduced LAMMPS impact (bench/lammps/pmb.yaml at twice its spacing): a rigid sphere
// driven into a cylinder cracks it (critical stretch with alpha, bonds broken after the
// force pass) and pushes the broken pieces into short-range contact. 120 steps.
std::string impact_deck(const std::string& material) {
  return R"(dimension: 3
spacing: 0.001
horizon: 0.0030001
lattice_origin: [0, 0, 0]
partial_volume: lammps
materials:
  target: )" + material + R"(
bodies:
  - {name: target, material: target, shape: {cylinder: {from: [0, -0.005, 0], to: [0, 0, 0], radius: 0.005}}}
contact:
  short_range: {stiffness_factor: 15, reference_fraction: 0.9, max_distance: 1.35}
  indenters:
    - {name: indenter, center: [0, "0.0025 - 100*t", 0], radius: 0.0025, stiffness: 1.0e17}
solver: {end_time: 1.2e-5, time_step: 1.0e-7}
output: {frames: 4, history_every: 10, damage_measure: volume, checkpoint: {every: 50}}
)";
}

const char* kPmb =
    "{model: pmb, density: 2200, micromodulus: 2.1e21, damage: {critical_stretch: 0.0005, alpha: 0.25, breaks: "
    "after_force}}";
// A history model (per-bond plastic extension, its energy ledger) through Model::checkpoint.
const char* kPlastic =
    "{model: elastic_plastic, density: 2200, youngs_modulus: 30.0e9, poissons_ratio: 0.25, yield_stress: 20.0e6, "
    "damage: {critical_stretch: 0.002}}";

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

RunOptions quiet(const fs::path& dir) {
  RunOptions o;
  o.quiet = true;
  o.handle_signals = false;
  o.threads = 2;
  o.output_dir = dir.string();
  return o;
}

// The straight run, and a run killed 7 steps after its checkpoint at step 100 (its
// later history rows never saved, a frame written past the checkpoint) and restarted.
void check_restart(const std::string& material, const std::string& name) {
  const fs::path root = fs::temp_directory_path() / ("horizon_checkpoint_" + name);
  fs::remove_all(root);
  const Config c = parse_deck(impact_deck(material), name + ".yaml");

  ExplicitRun straight(c, quiet(root / "straight"));
  straight.advance(std::numeric_limits<int64_t>::max());
  ASSERT_EQ(straight.finish(), 0);
  ASSERT_EQ(straight.steps(), 120);
  EXPECT_GT(straight.ledger().dissipated, 0) << "the deck must break bonds";

  {
    ExplicitRun killed(c, quiet(root / "restarted"));
    killed.advance(107);  // checkpoints at 50 and 100; frame 3 at step 90
    ASSERT_EQ(killed.steps(), 107);
  }  // dropped without finish(): no history.csv, no summary.json
  ASSERT_TRUE(fs::exists(root / "restarted" / "checkpoint.hzc"));
  EXPECT_FALSE(fs::exists(root / "restarted" / "history.csv"));

  RunOptions o = quiet(root / "restarted");
  o.restart = (root / "restarted" / "checkpoint.hzc").string();
  ExplicitRun restarted(c, o);
  EXPECT_EQ(restarted.steps(), 100);
  restarted.advance(std::numeric_limits<int64_t>::max());
  ASSERT_EQ(restarted.finish(), 0);

  for (const char* f : {"frames/frame_00004.vtu", "frames/frame_00003.vtu", "history.csv", "frames.pvd"})
    EXPECT_EQ(slurp(root / "straight" / f), slurp(root / "restarted" / f)) << name << ": " << f << " differs";
  const auto &a = straight.summary(), &b = restarted.summary();
  for (const char* key : {"energy", "damage", "loads", "steps", "time", "status", "particles", "bonds"}) {
    if (!a.contains(key)) continue;
    EXPECT_EQ(a[key].dump(), b[key].dump()) << name << ": summary " << key << " differs";
  }
  fs::remove_all(root);
}

}  // namespace

TEST(Checkpoint, RestartIsBitIdenticalWithFractureAndContact) { check_restart(kPmb, "pmb"); }

TEST(Checkpoint, RestartIsBitIdenticalForAHistoryModel) { check_restart(kPlastic, "plastic"); }

TEST(Checkpoint, DamagedOrForeignCheckpointsAreClearErrors) {
  const fs::path root = fs::temp_directory_path() / "horizon_checkpoint_bad";
  fs::remove_all(root);
  Config c = parse_deck(impact_deck(kPmb), "impact.yaml");
  c.solver.end_time = 6e-6;  // checkpoint at step 50 of 60
  {
    ExplicitRun run(c, quiet(root / "run"));
    run.advance(std::numeric_limits<int64_t>::max());
    run.finish();
  }
  const fs::path good = root / "run" / "checkpoint.hzc";
  const std::string bytes = slurp(good);
  ASSERT_GT(bytes.size(), 1000u);
  auto restart_from = [&](const Config& deck, const std::string& content) -> std::string {
    const fs::path p = root / "bad.hzc";
    std::ofstream(p, std::ios::binary) << content;
    RunOptions o = quiet(root / "again");
    o.restart = p.string();
    try {
      ExplicitRun run(deck, o);
    } catch (const Error& e) {
      return e.what();
    }
    return "no error";
  };
  auto expect_error = [](const std::string& message, const std::string& part) {
    EXPECT_NE(message.find("bad.hzc"), std::string::npos) << message;
    EXPECT_NE(message.find(part), std::string::npos) << message;
  };
  expect_error(restart_from(c, bytes.substr(0, bytes.size() - 100)), "truncated");
  expect_error(restart_from(c, bytes.substr(0, 10)), "truncated");
  std::string flipped = bytes;
  flipped[bytes.size() / 2] = static_cast<char>(flipped[bytes.size() / 2] ^ 0x10);
  expect_error(restart_from(c, flipped), "checksum mismatch");
  expect_error(restart_from(c, "spacing: 0.001\n" + std::string(100, ' ')), "not a Horizon checkpoint");
  std::string version = bytes;
  version[8] = 9;
  expect_error(restart_from(c, version), "format version 9");

  // Another deck: a finer lattice has more particles.
  Config finer = c;
  finer.spacing = 0.0009;
  const std::string m = restart_from(finer, bytes);
  expect_error(m, "particles");
  EXPECT_NE(m.find("does not belong to this deck"), std::string::npos) << m;
  // Another model for the same particles.
  Config other = parse_deck(impact_deck(kPlastic), "impact.yaml");
  const std::string mm = restart_from(other, bytes);
  expect_error(mm, "model");
  EXPECT_NE(mm.find("'pmb'"), std::string::npos) << mm;
  fs::remove_all(root);
}
