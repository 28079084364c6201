#include "horizon/deck/suggest.hpp"

#include <algorithm>
#include <cctype>

namespace horizon::deck {

int edit_distance(std::string_view a, std::string_view b) {
  const std::size_t n = a.size(), m = b.size();
  std::vector<std::vector<int>> d(n + 1, std::vector<int>(m + 1, 0));
  for (std::size_t i = 0; i <= n; ++i) d[i][0] = static_cast<int>(i);
  for (std::size_t j = 0; j <= m; ++j) d[0][j] = static_cast<int>(j);
  for (std::size_t i = 1; i <= n; ++i) {
    for (std::size_t j = 1; j <= m; ++j) {
      const int cost = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  }
  return d[n][m];
}

namespace {
// Lower case without separators: "Youngs-Modulus" and "youngsmodulus" compare equal.
std::string normalised(std::string_view word) {
  std::string s;
  for (char c : word) {
    if (c == '_' || c == '-' || c == ' ') continue;
    s += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  return s;
}
}  // namespace

std::optional<std::string> closest_word(std::string_view word, const std::vector<std::string>& valid) {
  const std::string w = normalised(word);
  std::optional<std::string> best;
  int best_distance = 3;
  for (const auto& v : valid) {
    if (v == word) continue;
    if (normalised(v) == w) return v;
    const int d = std::min(edit_distance(word, v), edit_distance(w, normalised(v)));
    if (d < best_distance && d < static_cast<int>(word.size())) {
      best = v;
      best_distance = d;
    }
  }
  return best;
}

std::string join_words(const std::vector<std::string>& words, std::string_view quote) {
  std::string s;
  for (std::size_t i = 0; i < words.size(); ++i) {
    if (i > 0) s += ", ";
    s += quote;
    s += words[i];
    s += quote;
  }
  return s;
}

}  // namespace horizon::deck
