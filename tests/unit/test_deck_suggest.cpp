// "Did you mean ...?": the typo suggestions behind the deck's unknown-key errors.
#include <gtest/gtest.h>

#include "horizon/deck/suggest.hpp"

namespace horizon::deck {
namespace {

TEST(DeckSuggest, EditDistanceCountsSwapsAsOneEdit) {
  EXPECT_EQ(edit_distance("density", "density"), 0);
  EXPECT_EQ(edit_distance("densty", "density"), 1);    // deletion
  EXPECT_EQ(edit_distance("denssity", "density"), 1);  // insertion
  EXPECT_EQ(edit_distance("dansity", "density"), 1);   // substitution
  EXPECT_EQ(edit_distance("desnity", "density"), 1);   // swap of neighbours
  EXPECT_EQ(edit_distance("", "abc"), 3);
}

TEST(DeckSuggest, ClosestWord) {
  const std::vector<std::string> keys = {"youngs_modulus", "poissons_ratio", "bulk_modulus", "shear_modulus",
                                         "density"};
  EXPECT_EQ(closest_word("youngs_modlus", keys), "youngs_modulus");
  EXPECT_EQ(closest_word("Youngs-Modulus", keys), "youngs_modulus");  // case and separators
  EXPECT_EQ(closest_word("poissonsratio", keys), "poissons_ratio");
  EXPECT_EQ(closest_word("densty", keys), "density");
  EXPECT_FALSE(closest_word("colour", keys).has_value());
  // Short words match only when fewer edits than letters were needed.
  EXPECT_FALSE(closest_word("ab", {"to"}).has_value());
  EXPECT_EQ(closest_word("x", {"y", "z", "x"}), std::nullopt);  // the word itself is not a suggestion
}

TEST(DeckSuggest, JoinWords) {
  EXPECT_EQ(join_words({"a", "b"}), "a, b");
  EXPECT_EQ(join_words({"a", "b"}, "'"), "'a', 'b'");
  EXPECT_EQ(join_words({}), "");
}

}  // namespace
}  // namespace horizon::deck
