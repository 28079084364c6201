#pragma once
// Reading a deck: YAML text -> a validated Config. Every mistake is a DeckError with
// file:line:column, the key path, what was expected and what was found; dubious but
// legal choices land in Config::warnings. The format is documented in docs/input.md.
#include <string>

#include "horizon/deck/config.hpp"

namespace horizon {

// Reads and parses the deck at `path`; a file that cannot be read is a horizon::Error.
Config load_deck(const std::string& path);

// Parses deck text; `file_name` is only used in messages and Config::deck_file.
Config parse_deck(const std::string& yaml_text, const std::string& file_name);

}  // namespace horizon
