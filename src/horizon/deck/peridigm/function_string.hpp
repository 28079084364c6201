#pragma once
// Peridigm's function strings (boundary-condition values read by its run-time compiler,
// RTCompiler): a C subset of statements that set `value` from x, y, z and t, e.g.
//   if(t <= 0.2) { value = 1000*t; } else { value = 200; }
// translated into one muParser expression in x, y, z, t (nested ternaries), which
// Horizon's Expression evaluates. docs/peridigm.md lists the grammar.
#include <cstddef>
#include <stdexcept>
#include <string>

namespace horizon::peridigm {

// A mistake in a function string, at a character offset into it.
struct FunctionStringError : std::runtime_error {
  FunctionStringError(std::size_t at, const std::string& what) : std::runtime_error(what), offset(at) {}
  std::size_t offset;
};

// The muParser expression equal to the function string's final `value` (or to the
// string itself when it is a bare expression). `\{` and `\}` (the escapes Peridigm's
// decks carry) read as braces. Throws FunctionStringError.
std::string function_string_to_muparser(const std::string& text);

// Peridigm's YAML decks write `\{` and `\}` inside double-quoted strings, which YAML
// rejects (unknown escape). Each becomes a space and the brace, so that every other
// character keeps its line and column. Text without a line starting `Peridigm:` is
// returned unchanged.
std::string unescape_peridigm_braces(const std::string& yaml_text);

}  // namespace horizon::peridigm
