#pragma once
// What the tests of decks run end to end share (the Peridigm importer's and the staged
// runs' tests): a fresh scratch folder per test, writing a deck, the error a deck gives,
// running a deck and reading back one of its Exodus files, a variable's index by name.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "horizon/core/error.hpp"
#include "horizon/deck/deck.hpp"
#include "horizon/driver/run.hpp"
#include "horizon/output/exodus.hpp"

namespace horizon::test {

// TMP/<suite>/<the running test's name>, emptied.
inline std::filesystem::path fresh_test_dir(const std::string& suite) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / suite /
                                    ::testing::UnitTest::GetInstance()->current_test_info()->name();
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

inline std::string write(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path) << text;
  return path.string();
}

// The error loading the deck gives ("no error" when it loads).
inline std::string error_of(const std::string& path) {
  try {
    load_deck(path);
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

// Runs a deck (its output under dir/out) and reads back the Exodus file `file`.
inline ExodusSeries run_and_read(const std::string& deck, const std::filesystem::path& dir, const std::string& file) {
  Config c = load_deck(deck);
  c.output.directory = (dir / "out").string();
  RunOptions o;
  o.quiet = true;
  EXPECT_EQ(run_deck(c, o), 0);
  return read_exodus_series((dir / "out" / file).string());
}

inline std::size_t index_of(const std::vector<std::string>& names, const std::string& name) {
  const auto it = std::find(names.begin(), names.end(), name);
  EXPECT_NE(it, names.end()) << name;
  return static_cast<std::size_t>(it - names.begin());
}

}  // namespace horizon::test
