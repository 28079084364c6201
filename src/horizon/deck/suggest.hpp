#pragma once
// "Did you mean ...?": the closest valid word to a misspelt key or value.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace horizon::deck {

// Edit distance counting insertions, deletions, substitutions and swaps of two
// neighbouring letters as one edit each (optimal string alignment).
int edit_distance(std::string_view a, std::string_view b);

// The valid word that `word` most likely meant: the same word up to case, '_' and '-',
// or one within two edits (and fewer edits than the word has letters, so that short
// words do not match anything). None when nothing is that close.
std::optional<std::string> closest_word(std::string_view word, const std::vector<std::string>& valid);

// "a, b, c" for messages.
std::string join_words(const std::vector<std::string>& words, std::string_view quote = "");

}  // namespace horizon::deck
