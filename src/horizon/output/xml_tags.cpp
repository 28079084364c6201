#include "horizon/output/xml_tags.hpp"

#include <cctype>

#include "horizon/core/error.hpp"

namespace horizon {

namespace {

bool is_space(char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; }

std::string unescape(std::string_view s) {
  static const std::pair<std::string_view, char> entities[] = {
      {"&amp;", '&'}, {"&lt;", '<'}, {"&gt;", '>'}, {"&quot;", '"'}, {"&apos;", '\''}};
  std::string out;
  for (size_t i = 0; i < s.size();) {
    bool replaced = false;
    if (s[i] == '&') {
      for (const auto& [entity, c] : entities) {
        if (s.substr(i, entity.size()) == entity) {
          out += c;
          i += entity.size();
          replaced = true;
          break;
        }
      }
    }
    if (!replaced) out += s[i++];
  }
  return out;
}

// Reads one tag starting just after its '<'; returns the position after its '>'.
size_t read_tag(std::string_view text, size_t i, XmlTag& tag, const std::string& source) {
  auto cut_off = [&]() {
    return Error(source + ": XML tag <" + tag.name + "> is cut off (file truncated?)");
  };
  if (i < text.size() && text[i] == '/') {
    tag.closing = true;
    ++i;
  }
  while (i < text.size() && !is_space(text[i]) && text[i] != '/' && text[i] != '>')
    tag.name += text[i++];
  if (tag.name.empty()) throw Error(source + ": malformed XML: a tag without a name");
  while (true) {
    while (i < text.size() && is_space(text[i])) ++i;
    if (i >= text.size()) throw cut_off();
    if (text[i] == '>') return i + 1;
    if (text[i] == '/') {
      if (i + 1 >= text.size()) throw cut_off();
      if (text[i + 1] != '>') throw Error(source + ": malformed XML in tag <" + tag.name + ">");
      tag.self_closing = true;
      return i + 2;
    }
    std::string key;
    while (i < text.size() && !is_space(text[i]) && text[i] != '=' && text[i] != '>')
      key += text[i++];
    while (i < text.size() && is_space(text[i])) ++i;
    if (i >= text.size()) throw cut_off();
    if (text[i] != '=')
      throw Error(source + ": malformed XML: attribute '" + key + "' of <" + tag.name +
                  "> has no value");
    ++i;
    while (i < text.size() && is_space(text[i])) ++i;
    if (i >= text.size()) throw cut_off();
    const char quote = text[i];
    if (quote != '"' && quote != '\'')
      throw Error(source + ": malformed XML: attribute '" + key + "' of <" + tag.name +
                  "> is not quoted");
    const size_t end = text.find(quote, i + 1);
    if (end == std::string_view::npos) throw cut_off();
    tag.attributes[key] = unescape(text.substr(i + 1, end - i - 1));
    i = end + 1;
  }
}

}  // namespace

std::vector<XmlTag> scan_xml_tags(std::string_view text, const std::string& source) {
  std::vector<XmlTag> tags;
  size_t i = 0;
  while ((i = text.find('<', i)) != std::string_view::npos) {
    const std::string_view rest = text.substr(i);
    // Declarations, comments and doctype carry nothing we read; skip them whole.
    std::string_view close;
    if (rest.starts_with("<?")) close = "?>";
    else if (rest.starts_with("<!--")) close = "-->";
    else if (rest.starts_with("<!")) close = ">";
    if (!close.empty()) {
      const size_t end = text.find(close, i);
      if (end == std::string_view::npos)
        throw Error(source + ": XML declaration or comment is cut off (file truncated?)");
      i = end + close.size();
      continue;
    }
    XmlTag tag;
    i = read_tag(text, i + 1, tag, source);
    tags.push_back(std::move(tag));
  }
  return tags;
}

std::string xml_escape(std::string_view text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  }
  return out;
}

}  // namespace horizon
