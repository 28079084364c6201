// Checkpoint and restart (output/checkpoint.hpp, docs/input.md output.checkpoint): a run
// with fracture and contact, straight against checkpoint + restart, must end with the
// same bytes in its last frame, history.csv and frames.pvd and the same summary figures;
// a damaged checkpoint and a checkpoint of another deck are clear errors.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "horizon/core/error.hpp"
#include "horizon/deck/deck.hpp"
#include "horizon/driver/run.hpp"
#include "horizon/solver/explicit.hpp"
#include "../test_paths.hpp"

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
  // history.csv holds the rows up to the last checkpoint (written with it), the first rows
  // of the straight run's.
  const std::string early = slurp(root / "restarted" / "history.csv");
  EXPECT_GT(early.size(), 500u);
  EXPECT_EQ(slurp(root / "straight" / "history.csv").rfind(early, 0), 0u) << early;

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

namespace {

// `horizon run DECK -o OUT -q --threads 1 [--restart FILE]` as a child process.
pid_t start_horizon(const fs::path& deck, const fs::path& out, const std::string& restart = "") {
  const std::string bin = HORIZON_BINARY, d = deck.string(), o = out.string(), log = out.string() + ".log";
  const pid_t pid = fork();
  if (pid == 0) {
    if (!std::freopen(log.c_str(), "w", stderr)) _exit(126);
    if (restart.empty())
      execl(bin.c_str(), bin.c_str(), "run", d.c_str(), "-o", o.c_str(), "-q", "--threads", "1",
            static_cast<char*>(nullptr));
    else
      execl(bin.c_str(), bin.c_str(), "run", d.c_str(), "-o", o.c_str(), "-q", "--threads", "1", "--restart",
            restart.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  return pid;
}

int wait_status(pid_t pid) {
  int st = 0;
  waitpid(pid, &st, 0);
  return st;
}

}  // namespace

// A real crash: the `horizon` program killed with SIGKILL (which it cannot catch) right
// after its first checkpoint appeared, somewhere in the following steps. What it wrote
// stays whole (history.csv has the rows up to its last checkpoint; the frames and index
// are complete files), and restarted in the same directory it ends with every frame,
// frames.pvd and history.csv byte-identical to the uninterrupted run's.
TEST(Checkpoint, KilledWithSigkillRestartsWithNoLostOutput) {
  const fs::path root = fs::temp_directory_path() / ("horizon_checkpoint_kill_" + std::to_string(getpid()));
  fs::remove_all(root);
  fs::create_directories(root);
  std::string deck = impact_deck(kPmb);
  const auto at = deck.find("end_time: 1.2e-5");
  ASSERT_NE(at, std::string::npos);
  deck.replace(at, 16, "end_time: 4.0e-5");  // 400 steps
  const auto ck = deck.find("frames: 4, history_every: 10, damage_measure: volume, checkpoint: {every: 50}");
  ASSERT_NE(ck, std::string::npos);
  deck.replace(ck, 77, "frames: 20, history_every: 10, damage_measure: volume, checkpoint: {every: 20}");
  std::ofstream(root / "kill.yaml") << deck;

  const int straight = wait_status(start_horizon(root / "kill.yaml", root / "straight"));
  ASSERT_TRUE(WIFEXITED(straight) && WEXITSTATUS(straight) == 0) << slurp(root / "straight.log");

  const pid_t pid = start_horizon(root / "kill.yaml", root / "killed");
  for (int k = 0; k < 60000 && !fs::exists(root / "killed" / "checkpoint.hzc"); ++k)
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  kill(pid, SIGKILL);
  const int st = wait_status(pid);
  ASSERT_TRUE(WIFSIGNALED(st) && WTERMSIG(st) == SIGKILL) << "the run ended before it was killed";
  ASSERT_FALSE(fs::exists(root / "killed" / "summary.json"));

  // What the killed run left: the beginning of the straight run's history, and frames
  // equal to the straight run's.
  const std::string early = slurp(root / "killed" / "history.csv");
  ASSERT_GT(early.size(), 200u);
  EXPECT_EQ(slurp(root / "straight" / "history.csv").rfind(early, 0), 0u) << early;
  std::vector<std::pair<fs::path, std::string>> left;
  for (const auto& e : fs::directory_iterator(root / "killed" / "frames")) {
    if (e.path().extension() != ".vtu") continue;  // a frame.vtu.tmp cut short by the kill
    const fs::path rel = fs::path("frames") / e.path().filename();
    left.emplace_back(rel, slurp(e.path()));
    EXPECT_EQ(left.back().second, slurp(root / "straight" / rel)) << rel << " as the killed run left it";
  }
  EXPECT_GE(left.size(), 2u);

  const int again = wait_status(
      start_horizon(root / "kill.yaml", root / "killed", (root / "killed" / "checkpoint.hzc").string()));
  ASSERT_TRUE(WIFEXITED(again) && WEXITSTATUS(again) == 0) << slurp(root / "killed.log");
  for (const auto& [rel, bytes] : left) EXPECT_EQ(slurp(root / "killed" / rel), bytes) << rel << " changed";
  int compared = 0;
  for (const auto& e : fs::directory_iterator(root / "straight" / "frames")) {
    const fs::path rel = fs::path("frames") / e.path().filename();
    EXPECT_EQ(slurp(root / "killed" / rel), slurp(e.path())) << rel;
    ++compared;
  }
  EXPECT_EQ(compared, 21);
  for (const char* f : {"history.csv", "frames.pvd"})
    EXPECT_EQ(slurp(root / "killed" / f), slurp(root / "straight" / f)) << f;
  const auto a = nlohmann::json::parse(slurp(root / "straight" / "summary.json"));
  const auto b = nlohmann::json::parse(slurp(root / "killed" / "summary.json"));
  EXPECT_EQ(a["state_crc32"], b["state_crc32"]);
  fs::remove_all(root);
}
