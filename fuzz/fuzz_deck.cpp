// libFuzzer target over the deck reader and the whole set-up before the first step
// (driver/run.hpp set_up: geometry, families, precracks, model constants, loads, initial
// conditions, the time step). Any input must end in a value or a horizon::Error; any other
// exception, a crash, a sanitizer report, a hang or an out-of-memory is a bug.
// Built with -DHORIZON_FUZZ=ON (clang); run by scripts/fuzz-deck.sh (docs/reliability.md).
#include <omp.h>

#include <cstddef>
#include <cstdint>
#include <string>

#include "horizon/core/error.hpp"
#include "horizon/deck/deck.hpp"
#include "horizon/driver/run.hpp"

namespace {
// The memory guard's limit under the fuzzer: decks estimated above it are refused before
// allocation (the guard is what is under test), which keeps each input quick.
constexpr double kFuzzMemoryLimit = 64.0 * 1024 * 1024;
}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  omp_set_num_threads(1);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    horizon::Config config = horizon::parse_deck(text, "fuzz.yaml");
    config.memory_limit_bytes = kFuzzMemoryLimit;
    const horizon::PreparedRun u = horizon::prepare_run(config);
    (void)u;
  } catch (const horizon::Error&) {
    // A clean refusal: what every bad deck must end in.
  }
  return 0;
}
