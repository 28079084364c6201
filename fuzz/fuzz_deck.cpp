// libFuzzer target over the deck reader and the whole set-up before the first step
// (driver/run.hpp set_up: geometry, families, precracks, model constants, loads, initial
// conditions, the time step). Any input must end in a value or a horizon::Error; any other
// exception, a crash, a sanitizer report, a hang or an out-of-memory is a bug.
// Built with -DHORIZON_FUZZ=ON (clang); run by scripts/fuzz-deck.sh (docs/reliability.md).
#include <omp.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "horizon/core/error.hpp"
#include "horizon/deck/deck.hpp"
#include "horizon/driver/run.hpp"

namespace {
// The memory guard's limit under the fuzzer: decks estimated above it are refused before
// allocation (the guard is what is under test), which keeps each input quick.
constexpr double kFuzzMemoryLimit = 64.0 * 1024 * 1024;
}  // namespace

// Structure-aware mutation. Byte-level mutations (libFuzzer's own) mostly break the YAML,
// so the set-up behind the reader is reached mainly through the seeds; half of the
// mutations here instead keep the deck's structure and change one value: a number becomes
// an extreme, zero, negative, non-finite or huge count; a scalar becomes another word of
// the deck language; a line is duplicated (a key given twice, a load given twice) or
// dropped (a required key missing).
extern "C" std::size_t LLVMFuzzerMutate(uint8_t* data, std::size_t size, std::size_t max_size);

namespace {

bool number_char(char c) { return (c >= '0' && c <= '9') || c == '.' || c == 'e' || c == 'E' || c == '-' || c == '+'; }

// [begin, end) of every number token (a digit run with its sign, point and exponent).
std::vector<std::pair<std::size_t, std::size_t>> number_tokens(const std::string& t) {
  std::vector<std::pair<std::size_t, std::size_t>> out;
  for (std::size_t i = 0; i < t.size();) {
    if (t[i] >= '0' && t[i] <= '9') {
      std::size_t b = i;
      while (b > 0 && (t[b - 1] == '-' || t[b - 1] == '.' || t[b - 1] == '+')) --b;
      std::size_t e = i;
      while (e < t.size() && number_char(t[e])) ++e;
      out.emplace_back(b, e);
      i = e;
    } else {
      ++i;
    }
  }
  return out;
}

// [begin, end) of every scalar after ": " up to the end of the line, a comma or a brace.
std::vector<std::pair<std::size_t, std::size_t>> scalar_tokens(const std::string& t) {
  std::vector<std::pair<std::size_t, std::size_t>> out;
  for (std::size_t i = t.find(": "); i != std::string::npos; i = t.find(": ", i + 2)) {
    std::size_t b = i + 2, e = b;
    while (e < t.size() && t[e] != '\n' && t[e] != ',' && t[e] != '}' && t[e] != ']') ++e;
    if (e > b) out.emplace_back(b, e);
  }
  return out;
}

std::vector<std::pair<std::size_t, std::size_t>> lines(const std::string& t) {
  std::vector<std::pair<std::size_t, std::size_t>> out;
  for (std::size_t b = 0; b < t.size();) {
    std::size_t e = t.find('\n', b);
    e = e == std::string::npos ? t.size() : e + 1;
    out.emplace_back(b, e);
    b = e;
  }
  return out;
}

const char* const kNumbers[] = {"0", "-0", "-1", "1", "2", "3", "0.5", "1e-300", "1e-12", "1e-9", "1e9", "1e12",
                                "1e300", "-1e300", "1e999", ".nan", ".inf", "-.inf", "2147483648", "4294967297",
                                "9223372036854775808", "1e-323", "0x10", "1/0", "-2147483649"};
const char* const kWords[] = {"pmb", "lps", "nonlinear_solid", "elastic_plastic", "viscoelastic", "correspondence",
                              "extended_correspondence", "microplastic", "bond_pair", "static", "explicit",
                              "implicit_dynamic", "heat", "newton", "adr", "gaussian", "constant", "true", "false",
                              "[]", "{}", "~", "\"x/0\"", "\"sqrt(-1)\"", "\"t*1e300\"", "[0, 0, 0]", "[1, 2]",
                              "{box: {min: [0, 0, 0], max: [0, 0, 0]}}", "\"\"", "top", "left", "plate"};

}  // namespace

extern "C" std::size_t LLVMFuzzerCustomMutator(uint8_t* data, std::size_t size, std::size_t max_size,
                                               unsigned int seed) {
  std::minstd_rand rng(seed);
  if (rng() % 2 == 0 || size == 0) return LLVMFuzzerMutate(data, size, max_size);
  std::string t(reinterpret_cast<const char*>(data), size);
  auto pick = [&](std::size_t n) { return static_cast<std::size_t>(rng() % n); };
  switch (rng() % 4) {
    case 0: {
      const auto tok = number_tokens(t);
      if (tok.empty()) return LLVMFuzzerMutate(data, size, max_size);
      const auto [b, e] = tok[pick(tok.size())];
      t.replace(b, e - b, kNumbers[pick(std::size(kNumbers))]);
      break;
    }
    case 1: {
      const auto tok = scalar_tokens(t);
      if (tok.empty()) return LLVMFuzzerMutate(data, size, max_size);
      const auto [b, e] = tok[pick(tok.size())];
      t.replace(b, e - b, kWords[pick(std::size(kWords))]);
      break;
    }
    default: {
      const auto ls = lines(t);
      const auto [b, e] = ls[pick(ls.size())];
      if (rng() % 2 == 0)
        t.insert(b, t.substr(b, e - b));
      else
        t.erase(b, e - b);
      break;
    }
  }
  if (t.size() > max_size) return LLVMFuzzerMutate(data, size, max_size);
  std::memcpy(data, t.data(), t.size());
  return t.size();
}

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
