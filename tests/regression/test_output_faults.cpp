// Faults on output, each on the real `horizon` binary and a small deck: a file-size limit
// (as a full disk looks to a writer), a full tmpfs, an output directory that cannot be
// created or written, SIGKILL at any moment, SIGTERM and SIGINT. In every case the files
// already written stay valid (the PVD index parses and every frame it lists reads back
// whole), the message says what happened, and the exit status is the documented one
// (docs/reliability.md: 5 output error, 130 SIGINT, 143 SIGTERM).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <thread>

#include "horizon/output/pvd.hpp"
#include "horizon/output/vtu.hpp"
#include "../test_paths.hpp"

namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("horizon_faults_" + name + "_" + std::to_string(getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

// A 2-D plate of 800 particles (a frame is ~80 kB); `frames` frames over `end_time`.
std::string plate_deck(double end_time, int frames) {
  std::ostringstream d;
  d << "dimension: 2\nplane: stress\nthickness: 1.0e-3\nspacing: 5.0e-4\nhorizon_factor: 3\n"
       "materials:\n  glass: {model: pmb, density: 2440, youngs_modulus: 72.0e9}\n"
       "bodies:\n  - {name: plate, material: glass, shape: {box: {min: [0, 0], max: [0.02, 0.01]}}}\n"
       "initial_conditions:\n  - {velocity: [\"10*x/0.02\", 0]}\n"
       "solver: {type: explicit, end_time: "
    << end_time << "}\noutput: {frames: " << frames << ", history_every: 10}\n";
  return d.str();
}

// A 1-D bar of 20 particles: a frame is ~3 kB, so the index (~90 bytes a frame) grows
// past a file-size limit of 16 kB after some 180 frames.
std::string bar_deck(int frames) {
  std::ostringstream d;
  d << "dimension: 1\narea: 1.0e-6\nspacing: 1.0e-3\nhorizon_factor: 3\n"
       "materials:\n  steel: {model: pmb, density: 7800, youngs_modulus: 200.0e9}\n"
       "bodies:\n  - {name: bar, material: steel, shape: {box: {min: [0], max: [0.02]}}}\n"
       "initial_conditions:\n  - {velocity: [\"x/0.02\"]}\n"
       "solver: {type: explicit, end_time: 1.0e-4}\noutput: {frames: "
    << frames << ", history_every: 10}\n";
  return d.str();
}

struct Child {
  pid_t pid = -1;
  fs::path log;
};

// Starts `horizon run deck -o out -q` with stderr to a log; `limit_bytes` > 0 sets
// RLIMIT_FSIZE in the child (what `ulimit -f` does).
Child start(const fs::path& deck, const fs::path& out, long limit_bytes = 0) {
  Child c;
  c.log = deck.parent_path() / (out.filename().string() + ".log");
  const std::string bin = HORIZON_BINARY, d = deck.string(), o = out.string(), l = c.log.string();
  c.pid = fork();
  if (c.pid == 0) {
    if (!std::freopen(l.c_str(), "w", stderr)) _exit(126);
    if (limit_bytes > 0) {
      rlimit r{static_cast<rlim_t>(limit_bytes), static_cast<rlim_t>(limit_bytes)};
      setrlimit(RLIMIT_FSIZE, &r);
    }
    execl(bin.c_str(), bin.c_str(), "run", d.c_str(), "-o", o.c_str(), "-q", "--threads", "1",
          static_cast<char*>(nullptr));
    _exit(127);
  }
  return c;
}

struct Ended {
  bool exited = false;
  int code = -1;    // exit status when exited
  int signal = 0;   // the signal that killed it otherwise
  std::string log;
};

Ended wait_for(const Child& c) {
  int st = 0;
  waitpid(c.pid, &st, 0);
  Ended e;
  e.exited = WIFEXITED(st);
  e.code = e.exited ? WEXITSTATUS(st) : -1;
  e.signal = WIFSIGNALED(st) ? WTERMSIG(st) : 0;
  std::ifstream in(c.log);
  std::ostringstream s;
  s << in.rdbuf();
  e.log = s.str();
  return e;
}

Ended run(const fs::path& deck, const fs::path& out, long limit_bytes = 0) { return wait_for(start(deck, out, limit_bytes)); }

// The output's promise: the index parses, and every frame it lists reads back whole
// (read_vtu checks the XML and the size of every array of the appended block). Returns
// the number of frames.
std::size_t expect_valid_output(const fs::path& out, std::size_t points = 800) {
  const auto entries = horizon::read_pvd((out / "frames.pvd").string());
  for (const auto& [time, file] : entries) {
    const horizon::Frame f = horizon::read_vtu(file);
    EXPECT_EQ(f.points.size(), points) << file;
    EXPECT_DOUBLE_EQ(f.time, time) << file;
  }
  return entries.size();
}

void wait_for_file(const fs::path& p) {
  for (int k = 0; k < 400 && !fs::exists(p); ++k) std::this_thread::sleep_for(std::chrono::milliseconds(25));
}

// A run of `deck` under a file-size limit of 16 kB (RLIMIT_FSIZE, what `ulimit -f` sets,
// limits each file): the frames fit, the growing index outgrows it after some 180 frames
// and write(2) fails with EFBIG. SIGXFSZ is ignored, so the process is not killed but
// reports the error and exits 5; the index on disk is the last complete one, no `.tmp`
// is left, and the summary (small) still made it and says what happened.
void expect_output_error_run(const std::string& name, const std::string& deck) {
  const fs::path d = scratch(name);
  std::ofstream(d / "bar.yaml") << deck;
  const Ended e = run(d / "bar.yaml", d / "out", 16 << 10);
  ASSERT_TRUE(e.exited) << "killed by signal " << e.signal;
  EXPECT_EQ(e.code, 5) << e.log;
  EXPECT_NE(e.log.find("output error"), std::string::npos) << e.log;
  EXPECT_NE(e.log.find("File too large"), std::string::npos) << e.log;
  const std::size_t frames = expect_valid_output(d / "out", 20);
  EXPECT_GE(frames, 100u);
  EXPECT_LT(frames, 401u);
  EXPECT_NE(e.log.find("frames.pvd lists the " + std::to_string(frames) + " complete frames"), std::string::npos)
      << e.log;
  for (const auto& f : fs::directory_iterator(d / "out")) EXPECT_NE(f.path().extension(), ".tmp") << f.path();
  std::ifstream js(d / "out" / "summary.json");
  ASSERT_TRUE(js);
  EXPECT_EQ(nlohmann::json::parse(js)["status"], "output error");
  fs::remove_all(d);
}

}  // namespace

// An explicit run on a file-size limit (expect_output_error_run above).
TEST(OutputFaults, FileSizeLimitStopsWithStatus5AndValidFrames) {
  expect_output_error_run("fsize", bar_deck(400));
}

// A real full disk: a 2 MiB tmpfs (needs root and a kernel that lets the test mount;
// skipped otherwise).
TEST(OutputFaults, FullDiskStopsWithStatus5AndValidFrames) {
  const fs::path d = scratch("tmpfs");
  fs::create_directories(d / "disk");
  if (geteuid() != 0 || mount("tmpfs", (d / "disk").c_str(), "tmpfs", 0, "size=2m") != 0)
    GTEST_SKIP() << "cannot mount a tmpfs here (needs root)";
  std::ofstream(d / "plate.yaml") << plate_deck(2e-5, 200);
  const Ended e = run(d / "plate.yaml", d / "disk" / "out");
  EXPECT_TRUE(e.exited);
  EXPECT_EQ(e.code, 5) << e.log;
  EXPECT_NE(e.log.find("No space left on device"), std::string::npos) << e.log;
  const std::size_t frames = expect_valid_output(d / "disk" / "out");
  EXPECT_GE(frames, 2u);
  EXPECT_LT(frames, 201u);
  umount((d / "disk").c_str());
  fs::remove_all(d);
}

// The output directory cannot be created (its parent is a file): refused before the
// set-up, with the path and the system's reason.
TEST(OutputFaults, UncreatableOutputDirectoryIsStatus5BeforeTheRun) {
  const fs::path d = scratch("notdir");
  std::ofstream(d / "plate.yaml") << plate_deck(1e-6, 2);
  std::ofstream(d / "afile") << "x";
  const Ended e = run(d / "plate.yaml", d / "afile" / "out");
  EXPECT_EQ(e.code, 5) << e.log;
  EXPECT_NE(e.log.find("cannot create the output directory"), std::string::npos) << e.log;
  EXPECT_NE(e.log.find("afile/out"), std::string::npos) << e.log;
  EXPECT_NE(e.log.find("Not a directory"), std::string::npos) << e.log;
  fs::remove_all(d);
}

// A directory without write permission (root writes anywhere: then a read-only bind
// mount stands in for it; skipped when neither is possible).
TEST(OutputFaults, UnwritableOutputDirectoryIsStatus5BeforeTheRun) {
  const fs::path d = scratch("readonly");
  std::ofstream(d / "plate.yaml") << plate_deck(1e-6, 2);
  fs::create_directories(d / "ro" / "frames");
  bool mounted = false;
  if (geteuid() == 0) {
    mounted = mount((d / "ro").c_str(), (d / "ro").c_str(), nullptr, MS_BIND, nullptr) == 0 &&
              mount(nullptr, (d / "ro").c_str(), nullptr, MS_BIND | MS_REMOUNT | MS_RDONLY, nullptr) == 0;
    if (!mounted) {
      umount((d / "ro").c_str());
      GTEST_SKIP() << "root, and cannot make a read-only bind mount here";
    }
  } else {
    fs::permissions(d / "ro", fs::perms::owner_read | fs::perms::owner_exec);
    fs::permissions(d / "ro" / "frames", fs::perms::owner_read | fs::perms::owner_exec);
  }
  const Ended e = run(d / "plate.yaml", d / "ro");
  if (mounted) umount((d / "ro").c_str());
  EXPECT_EQ(e.code, 5) << e.log;
  EXPECT_NE(e.log.find("is not writable"), std::string::npos) << e.log;
  fs::permissions(d / "ro", fs::perms::owner_all);
  fs::permissions(d / "ro" / "frames", fs::perms::owner_all);
  fs::remove_all(d);
}

// SIGKILL cannot be caught: at whatever moment it lands (here at 6 random moments of a
// run writing a frame every few steps, most of them mid-write), the index and every
// frame it lists are whole, because each file is complete before it is renamed into
// place.
TEST(OutputFaults, SigkillAtAnyMomentLeavesValidFrames) {
  const fs::path d = scratch("sigkill");
  std::ofstream(d / "plate.yaml") << plate_deck(1.0, 100000);
  std::mt19937 rng(15);
  std::uniform_int_distribution<int> delay_ms(20, 400);
  for (int trial = 0; trial < 6; ++trial) {
    const fs::path out = d / ("out" + std::to_string(trial));
    const Child c = start(d / "plate.yaml", out);
    wait_for_file(out / "frames.pvd");
    std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms(rng)));
    kill(c.pid, SIGKILL);
    const Ended e = wait_for(c);
    EXPECT_EQ(e.signal, SIGKILL);
    EXPECT_GE(expect_valid_output(out), 1u) << "trial " << trial;
  }
  fs::remove_all(d);
}

namespace {

// A run stopped by `sig` after its first frames: it stops after the step, writes a final
// frame, history and summary (status `interrupted`), names the signal and exits `code`.
void expect_interrupted_run(const std::string& name, int sig, const std::string& sig_name, int code) {
  const fs::path d = scratch(name);
  std::ofstream(d / "plate.yaml") << plate_deck(1.0, 5);
  const Child c = start(d / "plate.yaml", d / "out");
  wait_for_file(d / "out" / "frames.pvd");
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  kill(c.pid, sig);
  const Ended e = wait_for(c);
  ASSERT_TRUE(e.exited) << "killed by signal " << e.signal;
  EXPECT_EQ(e.code, code) << e.log;
  EXPECT_NE(e.log.find(sig_name + " at step"), std::string::npos) << e.log;
  EXPECT_GE(expect_valid_output(d / "out"), 2u);
  std::ifstream js(d / "out" / "summary.json");
  ASSERT_TRUE(js);
  EXPECT_EQ(nlohmann::json::parse(js)["status"], "interrupted");
  fs::remove_all(d);
}

}  // namespace

// SIGTERM (what a batch system sends at the end of a job's time): exit 143 (128 + 15).
TEST(OutputFaults, SigtermWritesAFinalFrameAndExits143) { expect_interrupted_run("sigterm", SIGTERM, "SIGTERM", 143); }

// SIGINT (Ctrl-C): the same with 130.
TEST(OutputFaults, SigintWritesAFinalFrameAndExits130) { expect_interrupted_run("sigint", SIGINT, "SIGINT", 130); }

// The static and heat drivers keep the same promise as the explicit one.
TEST(OutputFaults, StaticRunOnAFileSizeLimitStopsWithStatus5AndValidFrames) {
  expect_output_error_run("static",
                          "dimension: 1\narea: 1.0e-6\nspacing: 1.0e-3\nhorizon_factor: 3\n"
                          "materials:\n  steel: {model: pmb, density: 7800, youngs_modulus: 200.0e9}\n"
                          "bodies:\n  - {name: bar, material: steel, shape: {box: {min: [0], max: [0.02]}}}\n"
                          "regions:\n  left: {box: {min: [0], max: [0.0025]}}\n"
                          "  right: {box: {min: [0.0175], max: [0.02]}}\n"
                          "loads:\n  - {region: left, displacement: [0]}\n"
                          "  - {region: right, displacement: [\"1e-6*t\"]}\n"
                          "solver: {type: static, load_steps: 400}\noutput: {frames: 400}\n");
}

TEST(OutputFaults, HeatRunOnAFileSizeLimitStopsWithStatus5AndValidFrames) {
  expect_output_error_run("heat",
                          "dimension: 1\narea: 1.0e-6\nspacing: 1.0e-3\nhorizon_factor: 3\n"
                          "materials:\n  steel:\n    model: pmb\n    density: 7800\n    youngs_modulus: 200.0e9\n"
                          "    thermal: {conductivity: 45, specific_heat: 460, reference_temperature: 293}\n"
                          "bodies:\n  - {name: bar, material: steel, shape: {box: {min: [0], max: [0.02]}}}\n"
                          "thermal: {initial_temperature: \"293 + 50*x/0.02\", integration: implicit}\n"
                          "solver: {type: heat, end_time: 0.4, time_step: 0.001}\noutput: {frames: 400}\n");
}
