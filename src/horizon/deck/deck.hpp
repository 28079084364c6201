#pragma once
// Reading a deck: YAML text -> a validated Config. Every mistake is a DeckError with
// file:line:column, the key path, what was expected and what was found; dubious but
// legal choices land in Config::warnings. The format is documented in docs/input.md.
#include <yaml-cpp/yaml.h>

#include <string>

#include "horizon/deck/config.hpp"

namespace horizon {

// Reads and parses the deck at `path`; a file that cannot be read is a horizon::Error.
Config load_deck(const std::string& path);

// Parses deck text; `file_name` is only used in messages and Config::deck_file.
Config parse_deck(const std::string& yaml_text, const std::string& file_name);

// `horizon convert`: the native deck (YAML text) equivalent to the Peridigm deck at
// `path`, checked by reading it back. Not a Peridigm deck: a DeckError.
std::string convert_peridigm_deck(const std::string& path);

// Reads an already parsed deck (the Python module edits decks as YAML trees). Values
// keep the line and column they were read at; values set in code have none.
Config parse_deck_node(const YAML::Node& root, const std::string& file_name);

}  // namespace horizon
