// The command line as a user meets it: version, check, errors, Ctrl-C and a run that
// blows up. Each test runs the real binary.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>

#include "horizon/output/pvd.hpp"
#include "horizon/output/vtu.hpp"
#include "../test_paths.hpp"

namespace fs = std::filesystem;

namespace {

struct Result {
  int status = -1;
  std::string output;
};

// env: variable assignments put before the command ("NAME=value ").
Result run(const std::string& args, const std::string& env = "") {
  const std::string cmd = env + std::string(HORIZON_BINARY) + " " + args + " 2>&1";
  Result r;
  FILE* p = popen(cmd.c_str(), "r");
  char buf[4096];
  while (std::fgets(buf, sizeof buf, p)) r.output += buf;
  const int st = pclose(p);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("horizon_cli_" + name + "_" + std::to_string(getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

void write(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

// A small 2-D plate that runs long enough to be interrupted.
std::string plate_deck(double end_time, const std::string& extra_solver = "") {
  std::ostringstream d;
  d << "dimension: 2\nplane: stress\nthickness: 1.0e-3\nspacing: 5.0e-4\nhorizon_factor: 3\n"
       "materials:\n  glass: {model: pmb, density: 2440, youngs_modulus: 72.0e9}\n"
       "bodies:\n  - {name: plate, material: glass, shape: {box: {min: [0, 0], max: [0.02, 0.01]}}}\n"
       "initial_conditions:\n  - {velocity: [\"10*x/0.02\", 0]}\n"
       "solver: {type: explicit, end_time: "
    << end_time << extra_solver << "}\noutput: {frames: 5, history_every: 10}\n";
  return d.str();
}

}  // namespace

TEST(Cli, VersionPrintsTheVersion) {
  const Result r = run("--version");
  EXPECT_EQ(r.status, 0);
  EXPECT_NE(r.output.find("horizon 0."), std::string::npos) << r.output;
}

// `horizon models` prints the registry: every model with its own deck parameters.
TEST(Cli, ModelsListsTheRegistryWithParameters) {
  const Result r = run("models");
  EXPECT_EQ(r.status, 0);
  for (const char* word : {"pmb:", "lps:", "nonlinear_solid (alias tupek):", "seth_hill_m: ", "(default 0)"})
    EXPECT_NE(r.output.find(word), std::string::npos) << word << " not in:\n" << r.output;
}

TEST(Cli, CheckReportsParticlesBondsAndTimeStep) {
  const fs::path d = scratch("check");
  write(d / "plate.yaml", plate_deck(1e-6));
  const Result r = run("check " + (d / "plate.yaml").string());
  EXPECT_EQ(r.status, 0) << r.output;
  // 40 x 20 lattice points.
  EXPECT_NE(r.output.find("particles       800"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("stable step"), std::string::npos);
  EXPECT_NE(r.output.find("deck is valid"), std::string::npos);
}

TEST(Cli, CheckOfAStaticDeckReportsLoadStepsNotATimeStep) {
  const fs::path d = scratch("check_static");
  std::string deck = plate_deck(1e-6);
  const std::string expl = "solver: {type: explicit, end_time: 1e-06}";
  ASSERT_NE(deck.find(expl), std::string::npos) << deck;
  deck.replace(deck.find(expl), expl.size(), "solver: {type: static, method: adr, load_steps: 7}");
  write(d / "plate.yaml", deck);
  const Result r = run("check " + (d / "plate.yaml").string());
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("adaptive dynamic relaxation"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("load steps      7"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("stable step"), std::string::npos) << r.output;
}

// A static Newton solve with the Cholesky factorisation writes the same bytes on 1 and 2
// threads. CHOLMOD's supernodal factorisation calls OpenBLAS, whose own threads (set by
// OMP_NUM_THREADS or OPENBLAS_NUM_THREADS) changed the order of its sums and so the
// result; solver/linear.cpp pin_blas_threads keeps BLAS on one thread.
TEST(Cli, CholeskyStaticSolveIsTheSameOnOneAndTwoThreads) {
  const fs::path d = scratch("cholesky_threads");
  const std::string deck = std::string(HORIZON_SOURCE_DIR) + "/examples/plate_navier.yaml";
  std::string crc[2];
  for (int t = 1; t <= 2; ++t) {
    const fs::path out = d / ("t" + std::to_string(t));
    const std::string n = std::to_string(t);
    const Result r = run("run -q " + deck + " -o " + out.string(), "OMP_NUM_THREADS=" + n + " OPENBLAS_NUM_THREADS=" + n + " ");
    ASSERT_EQ(r.status, 0) << r.output;
    std::ifstream in(out / "summary.json");
    const nlohmann::json j = nlohmann::json::parse(in);
    ASSERT_TRUE(j.contains("state_crc32")) << j.dump();
    crc[t - 1] = j["state_crc32"].dump();
  }
  EXPECT_EQ(crc[0], crc[1]);
}

TEST(Cli, DeckErrorNamesFileLineAndColumn) {
  const fs::path d = scratch("error");
  std::string deck = plate_deck(1e-6);
  deck.replace(deck.find("density: 2440"), 13, "densty: 2440");
  write(d / "bad.yaml", deck);
  const Result r = run("check " + (d / "bad.yaml").string());
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("bad.yaml:7:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("density"), std::string::npos) << r.output;
}

// HORIZON_KERNEL_PATH picks the fast loops' path of a run (solver/forces.hpp): a value it
// does not know is a clear error, not a silent fall-back to another path.
TEST(Cli, UnknownKernelPathIsAnError) {
  const fs::path d = scratch("kernel_path");
  write(d / "plate.yaml", plate_deck(1e-7));
  const Result bad = run("run " + (d / "plate.yaml").string() + " -q -o " + (d / "bad").string() + " --threads 1",
                         "HORIZON_KERNEL_PATH=avx3 ");
  EXPECT_EQ(bad.status, 1) << bad.output;
  EXPECT_NE(bad.output.find("HORIZON_KERNEL_PATH=avx3: expected automatic, avx2, scalar or general"),
            std::string::npos)
      << bad.output;
  const Result good = run("run " + (d / "plate.yaml").string() + " -q -o " + (d / "good").string() + " --threads 1",
                          "HORIZON_KERNEL_PATH=avx2 ");
  EXPECT_EQ(good.status, 0) << good.output;
  fs::remove_all(d);
}

TEST(Cli, MissingDeckIsAnErrorNotACrash) {
  const Result r = run("run /nonexistent/deck.yaml");
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("/nonexistent/deck.yaml"), std::string::npos) << r.output;
}

TEST(Cli, InterruptWritesAFinalFrameAndAValidIndex) {
  const fs::path d = scratch("interrupt");
  write(d / "plate.yaml", plate_deck(1.0));  // far more steps than the test waits for
  const std::string cmd = std::string(HORIZON_BINARY);
  const std::string deck = (d / "plate.yaml").string();
  const std::string out = (d / "out").string();
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    std::freopen("/dev/null", "w", stderr);
    execl(cmd.c_str(), cmd.c_str(), "run", deck.c_str(), "-o", out.c_str(), "-q", static_cast<char*>(nullptr));
    _exit(127);
  }
  // Wait until the run has started writing, then interrupt it.
  for (int k = 0; k < 200 && !fs::exists(d / "out" / "frames.pvd"); ++k)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  kill(pid, SIGINT);
  int st = 0;
  waitpid(pid, &st, 0);
  ASSERT_TRUE(WIFEXITED(st));
  EXPECT_EQ(WEXITSTATUS(st), 130);
  const auto entries = horizon::read_pvd((d / "out" / "frames.pvd").string());
  ASSERT_GE(entries.size(), 2u);
  for (const auto& e : entries) EXPECT_EQ(horizon::read_vtu(e.second).points.size(), 800u) << e.second;
  const horizon::Frame last = horizon::read_vtu(entries.back().second);
  EXPECT_GT(last.step, 0);
  EXPECT_EQ(last.points.size(), 800u);
  std::ifstream js(d / "out" / "summary.json");
  const auto j = nlohmann::json::parse(js);
  EXPECT_EQ(j["status"], "interrupted");
  EXPECT_EQ(j["steps"].get<int64_t>(), last.step);
}

// An adaptive run whose step shrinks (a nonlinear-solid plate squeezed to the stiff side
// of its bond law) takes more steps than `check` estimates from the reference state. It
// still writes its frames and history rows by time: before the fix every step past the
// estimate counted as the last one and wrote a frame and a row (a 28,421-particle Taylor
// bar wrote 6,800 frames of 4.8 MB).
TEST(Cli, AdaptiveRunPastItsEstimatedStepsWritesItsFramesByTime) {
  const fs::path d = scratch("adaptive");
  write(d / "squeeze.yaml",
        "dimension: 2\nplane: stress\nthickness: 1.0e-3\nspacing: 5.0e-4\nhorizon_factor: 3\n"
        "materials:\n  steel: {model: nonlinear_solid, density: 7850, youngs_modulus: 200.0e9, poissons_ratio: 0.3}\n"
        "bodies:\n  - {name: plate, material: steel, shape: {box: {min: [0, 0], max: [0.01, 0.01]}}}\n"
        "initial_conditions:\n  - {velocity: [\"-2000*(x-0.005)/0.005\", 0]}\n"
        "solver: {type: explicit, end_time: 3.0e-6, safety_factor: 0.5, adaptive_time_step: true, adaptive_every: 1}\n"
        "output: {frames: 4, history_every: 10}\n");
  const Result check = run("check " + (d / "squeeze.yaml").string());
  ASSERT_EQ(check.status, 0) << check.output;
  const auto at = check.output.find("steps");
  ASSERT_NE(at, std::string::npos) << check.output;
  const long estimated = std::stol(check.output.substr(check.output.find_first_of("0123456789", at)));
  const Result r = run("run " + (d / "squeeze.yaml").string() + " -o " + (d / "out").string() + " -q");
  ASSERT_EQ(r.status, 0) << r.output;
  std::ifstream js(d / "out" / "summary.json");
  const auto j = nlohmann::json::parse(js);
  const int64_t steps = j["steps"].get<int64_t>();
  ASSERT_GT(steps, estimated + 3) << "the step did not shrink enough to test the case";
  EXPECT_NEAR(j["time"].get<double>(), 3.0e-6, 1e-18);
  // The initial frame and four by time, the last at the end time.
  const auto entries = horizon::read_pvd((d / "out" / "frames.pvd").string());
  EXPECT_EQ(entries.size(), 5u);
  EXPECT_EQ(horizon::read_vtu(entries.back().second).step, steps);
  // History: the initial row, every 10th step and the last.
  std::ifstream h(d / "out" / "history.csv");
  std::string line;
  int rows = -1;  // the header
  while (std::getline(h, line)) ++rows;
  EXPECT_EQ(rows, 1 + steps / 10 + (steps % 10 != 0));
}

TEST(Cli, NonFiniteStateStopsWithParticleAndStep) {
  const fs::path d = scratch("nonfinite");
  // Fifty times the stable step: the explicit scheme diverges within a few hundred steps.
  write(d / "plate.yaml", plate_deck(2e-3, ", time_step: 5.0e-6"));
  const Result r = run("run " + (d / "plate.yaml").string() + " -o " + (d / "out").string() + " -q");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("non-finite at step"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("particle"), std::string::npos) << r.output;
  const auto entries = horizon::read_pvd((d / "out" / "frames.pvd").string());
  const horizon::Frame last = horizon::read_vtu(entries.back().second);
  for (double u : last.field("displacement")->data) ASSERT_TRUE(std::isfinite(u));
}

// The energy-balance warning (solver.energy_balance_warning, default 5 %): a run whose
// ledger error exceeds it says so on stderr and in summary.json, and still completes.
// The plate's error is ~1e-4 (velocity Verlet's O(dt^2)): above a threshold of 1e-9,
// below the default.
TEST(Cli, EnergyBalanceAboveTheThresholdWarnsInLogAndSummary) {
  const fs::path d = scratch("energy");
  write(d / "strict.yaml", plate_deck(2e-6, ", energy_balance_warning: 1.0e-9"));
  write(d / "default.yaml", plate_deck(2e-6));
  const Result strict = run("run " + (d / "strict.yaml").string() + " -o " + (d / "strict").string() + " -q");
  EXPECT_EQ(strict.status, 0) << strict.output;
  EXPECT_NE(strict.output.find("horizon: warning: the energy balance error reached"), std::string::npos)
      << strict.output;
  std::ifstream js(d / "strict" / "summary.json");
  const auto j = nlohmann::json::parse(js);
  const double error = j["energy"]["max_abs_balance_error"];
  EXPECT_GT(error, 1e-9);
  EXPECT_LT(error, 0.05);
  ASSERT_TRUE(j.contains("warnings"));
  EXPECT_NE(j["warnings"][0].get<std::string>().find("above solver.energy_balance_warning (1e-07 %)"), std::string::npos)
      << j["warnings"];
  // The warning names the terms the balance counts, as summary.json does.
  EXPECT_NE(j["warnings"][0].get<std::string>().find("the balance counts kinetic, strain, dissipated, damped, initial, "
                                                      "external_work (summary.json energy.balance_terms)"),
            std::string::npos)
      << j["warnings"];
  EXPECT_EQ(j["energy"]["balance_terms"].size(), 6u);

  const Result quiet = run("run " + (d / "default.yaml").string() + " -o " + (d / "default").string() + " -q");
  EXPECT_EQ(quiet.status, 0) << quiet.output;
  EXPECT_EQ(quiet.output.find("warning"), std::string::npos) << quiet.output;
  std::ifstream jd(d / "default" / "summary.json");
  EXPECT_FALSE(nlohmann::json::parse(jd).contains("warnings"));
  fs::remove_all(d);
}
