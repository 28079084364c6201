#pragma once
// Output is never half-written: every file goes to `path + ".tmp"` first and is renamed
// into place only once it is complete, so a reader (or a crash) sees either the old file
// or the new one, never a torn one.
#include <functional>
#include <ostream>
#include <string>

namespace horizon {

// Writes `bytes` to `path` atomically, creating parent directories as needed.
// Throws horizon::Error naming the path when anything fails.
void write_file_atomic(const std::string& path, const std::string& bytes);

// Same, but the content is produced by `write` into a binary stream; lets large files
// be streamed without building them in memory first.
void write_file_atomic(const std::string& path,
                       const std::function<void(std::ostream&)>& write);

}  // namespace horizon
