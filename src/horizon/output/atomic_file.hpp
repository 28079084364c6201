#pragma once
// Output is never half-written: every file goes to `path + ".tmp"` first and is renamed
// into place only once it is complete, so a reader (or a crash) sees either the old file
// or the new one, never a torn one.
#include <functional>
#include <ostream>
#include <string>

namespace horizon {

// Writes `bytes` to `path` atomically, creating parent directories as needed.
// Throws horizon::OutputError naming the path and the system's reason when anything fails.
void write_file_atomic(const std::string& path, const std::string& bytes);

// Same, but the content is produced by `write` into a binary stream; lets large files
// be streamed without building them in memory first.
void write_file_atomic(const std::string& path,
                       const std::function<void(std::ostream&)>& write);

// A run's closing files (history, summary) after the run itself: written atomically; when
// the run already stopped on an output error (`after_output_error`), a second failure is
// only reported on standard error, so that the run still ends with its own message and
// exit status; otherwise it throws as write_file_atomic does.
void write_result_file(const std::string& path, const std::string& bytes, bool after_output_error);

// Creates a run's output directory (and `sub` inside it) and proves it writable by
// writing and removing a probe file, so that a run that could not save its results
// fails before it starts. Throws horizon::OutputError.
void prepare_output_directory(const std::string& dir, const std::string& sub);

}  // namespace horizon
