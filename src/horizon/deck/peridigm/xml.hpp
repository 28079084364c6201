#pragma once
// Peridigm's XML decks (Teuchos ParameterLists) as YAML: <ParameterList name="X"> is a
// map X, <Parameter name="K" type="T" value="V"/> the key K. The YAML is written in flow
// style with every key and value at the line and column of its XML attribute, so that
// messages about it point into the XML file.
#include <string>

namespace horizon::peridigm {

// True when the text's first non-blank character is '<'.
bool looks_like_xml(const std::string& text);

// The YAML text (top-level key Peridigm) of a Peridigm XML deck; malformed XML is a
// DeckError at its line and column.
std::string xml_to_yaml(const std::string& xml, const std::string& file);

}  // namespace horizon::peridigm
