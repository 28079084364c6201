#pragma once
// Errors a user can act on. A DeckError names the deck, line and column, the key,
// what was expected, and (when it looks like a typo) the closest valid key.
#include <stdexcept>
#include <string>

namespace horizon {

// Any error that should reach the user as a clean message (no crash, no trace).
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A file of a run's output could not be written (disk full, file-size limit, a directory
// that cannot be created or written). `horizon` exits with status 5 (docs/reliability.md).
class OutputError : public Error {
 public:
  using Error::Error;
};

// Where in a deck something was found. line and column are 1-based; 0 means unknown.
struct DeckLocation {
  std::string file;
  int line = 0;
  int column = 0;
};

class DeckError : public Error {
 public:
  DeckError(const DeckLocation& where, const std::string& message)
      : Error(format(where, message)), where_(where), message_(message) {}
  const DeckLocation& where() const { return where_; }
  const std::string& message() const { return message_; }

 private:
  static std::string format(const DeckLocation& w, const std::string& m) {
    std::string s = w.file;
    if (w.line > 0) s += ":" + std::to_string(w.line) + ":" + std::to_string(w.column);
    return s + ": error: " + m;
  }
  DeckLocation where_;
  std::string message_;
};

}  // namespace horizon
