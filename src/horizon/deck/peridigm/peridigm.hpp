#pragma once
// Peridigm decks read by Horizon: a deck whose top-level key is `Peridigm` (Sandia's
// Peridigm input format, YAML form) is translated here into a native deck tree, which
// the native reader then reads as usual. docs/peridigm.md maps every supported key;
// any other key is an error naming it with its line and column (Peridigm itself ignores
// keys it does not know; Horizon does not).
#include <yaml-cpp/yaml.h>

#include <string>

namespace horizon::peridigm {

// True for a map whose only key is `Peridigm`.
bool is_peridigm_deck(const YAML::Node& root);

// The native deck equivalent to a Peridigm deck (`root` is the whole document). Files
// the deck names (text-file discretisations, node-set files) are read relative to the
// folder of `file`; their points are written inline. Throws DeckError with the
// Peridigm deck's file:line:column.
YAML::Node to_native(const YAML::Node& root, const std::string& file);

// The native deck as YAML text (`horizon convert`), with a header naming the source.
std::string native_yaml(const YAML::Node& native, const std::string& source);

}  // namespace horizon::peridigm
