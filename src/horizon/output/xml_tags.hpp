#pragma once
// A small scanner for the XML that Horizon writes itself (VTU headers, PVD indexes):
// the tags and their attributes, in document order. It is not a general XML parser
// (no DTDs, CDATA or namespaces); it reads our own files back and rejects anything it
// cannot follow with a message that names the file.
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace horizon {

struct XmlTag {
  std::string name;
  std::map<std::string, std::string> attributes;  // values already unescaped
  bool closing = false;                           // </name>
  bool self_closing = false;                      // <name ... />

  // The attribute's value, or nullptr when the tag does not have it.
  const std::string* find(const std::string& key) const {
    auto it = attributes.find(key);
    return it == attributes.end() ? nullptr : &it->second;
  }
};

// Tags of `text`, skipping the declaration, comments and character data.
// Throws horizon::Error naming `source` on a tag that is cut off or malformed.
std::vector<XmlTag> scan_xml_tags(std::string_view text, const std::string& source);

// Escapes &, <, >, " and ' so that any string can sit inside a quoted attribute.
std::string xml_escape(std::string_view text);

}  // namespace horizon
