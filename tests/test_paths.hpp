#pragma once
// Where the tests find the source tree and the horizon program. The two strings live in
// one file generated per build folder (test_paths.cpp, tests/CMakeLists.txt), so that no
// test object depends on the checkout's path and a compiler cache can share the objects
// between checkouts.
namespace horizon::test_paths {
extern const char* const source_dir;
extern const char* const binary;
}  // namespace horizon::test_paths

#define HORIZON_SOURCE_DIR (::horizon::test_paths::source_dir)
#define HORIZON_BINARY (::horizon::test_paths::binary)
