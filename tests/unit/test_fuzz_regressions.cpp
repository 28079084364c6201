// Every input that once crashed, hung, exhausted memory or hit undefined behaviour in the
// deck reader or the set-up (found by the deck fuzzer, fuzz/fuzz_deck.cpp, or by hand),
// kept in tests/data/fuzz_regressions/ once fixed, with the extremes of docs/reliability.md
// (binary, 100,000 nested brackets, spacing 1e-9 m, an alias fan-out): each must
// now end the way the fuzz target demands, a value or a clean horizon::Error, within the
// fuzzer's memory limit. Under `make test-sanitize` this runs with ASan and UBSan too.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "horizon/core/error.hpp"
#include "horizon/deck/deck.hpp"
#include "horizon/driver/run.hpp"
#include "../single_thread.hpp"
#include "../test_paths.hpp"

namespace fs = std::filesystem;

namespace horizon {
namespace {

std::vector<fs::path> regression_inputs() {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(fs::path(HORIZON_SOURCE_DIR) / "tests" / "data" / "fuzz_regressions"))
    if (e.is_regular_file()) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

TEST(FuzzRegressions, EveryKeptInputEndsInAValueOrACleanError) {
  const test::SingleThread one;
  const auto files = regression_inputs();
  ASSERT_FALSE(files.empty());
  for (const auto& f : files) {
    std::ifstream in(f, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    const auto start = std::chrono::steady_clock::now();
    std::string outcome = "set up";
    try {
      Config config = parse_deck(text.str(), f.filename().string());
      config.memory_limit_bytes = 64.0 * 1024 * 1024;  // the fuzz target's limit
      const PreparedRun u = prepare_run(config);
      EXPECT_GT(u.system.particles.size(), 0u) << f;
    } catch (const Error& e) {
      outcome = e.what();
      // A clean error names the input and says something.
      EXPECT_GT(outcome.size(), 20u) << f;
    }
    // Anything else (another exception, a crash, a sanitizer report) fails the test run.
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_LT(s, 10.0) << f << " took " << s << " s (the fuzzer's -timeout)";
    std::printf("[ fuzz     ] %s: %.200s\n", f.filename().c_str(), outcome.c_str());
  }
}

}  // namespace
}  // namespace horizon
