#include "horizon/deck/peridigm/xml.hpp"

#include <fmt/format.h>

#include <cctype>
#include <cstdlib>
#include <map>
#include <vector>

#include "horizon/core/error.hpp"

namespace horizon::peridigm {

namespace {

// Writes YAML tokens at the line and column of the XML they come from: newlines are
// copied, everything else becomes spaces, and a token longer than the XML it replaces
// pushes the rest of its line right (the "debt" is paid back from the following spaces).
class Mirror {
 public:
  explicit Mirror(const std::string& src) : src_(src) {}

  void at(std::size_t offset, const std::string& token, std::size_t span) {
    advance(offset);
    out_ += token;
    if (token.size() > span) debt_ += token.size() - span;
    for (std::size_t k = token.size(); k < span; ++k) out_ += ' ';
    pos_ = offset + span;
  }
  std::string finish() {
    advance(src_.size());
    return out_;
  }

 private:
  void advance(std::size_t to) {
    for (; pos_ < to; ++pos_) {
      if (src_[pos_] == '\n') {
        out_ += '\n';
        debt_ = 0;
      } else if (debt_ > 0) {
        --debt_;
      } else {
        out_ += ' ';
      }
    }
  }
  const std::string& src_;
  std::string out_;
  std::size_t pos_ = 0, debt_ = 0;
};

struct Attribute {
  std::string value;        // entities decoded
  std::size_t offset = 0;   // the opening quote
  std::size_t span = 0;     // quotes included
};

std::string decode(const std::string& s) {
  std::string r;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '&') {
      const auto semi = s.find(';', i);
      const std::string e = semi == std::string::npos ? "" : s.substr(i + 1, semi - i - 1);
      const char* rep = e == "amp" ? "&" : e == "lt" ? "<" : e == "gt" ? ">" : e == "quot" ? "\"" : e == "apos" ? "'" : nullptr;
      if (rep) {
        r += rep;
        i = semi;
        continue;
      }
    }
    r += s[i];
  }
  return r;
}

std::string quoted(const std::string& s) {
  std::string r = "'";
  for (char c : s) r += c == '\'' ? std::string("''") : std::string(1, c);
  return r + "'";
}

bool is_number(const std::string& s) {
  if (s.empty()) return false;
  char* end = nullptr;
  std::strtod(s.c_str(), &end);
  return *end == '\0';
}

}  // namespace

bool looks_like_xml(const std::string& text) {
  const auto first = text.find_first_not_of(" \t\r\n");
  return first != std::string::npos && text[first] == '<';
}

std::string xml_to_yaml(const std::string& xml, const std::string& file) {
  Mirror m(xml);
  auto line_col = [&](std::size_t offset) {
    int line = 1, col = 1;
    for (std::size_t i = 0; i < offset && i < xml.size(); ++i) {
      if (xml[i] == '\n') ++line, col = 1;
      else ++col;
    }
    return DeckLocation{file, line, col};
  };
  auto fail = [&](std::size_t offset, const std::string& msg) { throw DeckError(line_col(offset), msg); };

  std::vector<bool> first_child;  // per open ParameterList: no entry written yet
  // Per open ParameterList: the Parameters given so far, name -> (value as read, offset).
  // Teuchos's reader (ParameterList::set) keeps the later of two Parameters of one name;
  // Horizon reads a repeat with the same value as the one Parameter it is (as in Peridigm)
  // and refuses a repeat with another value, which is most likely a mistake in the deck.
  std::vector<std::map<std::string, std::pair<std::string, std::size_t>>> given;
  bool root_done = false;
  std::size_t i = 0;
  while (i < xml.size()) {
    const char c = xml[i];
    if (c != '<') {
      if (!std::isspace(static_cast<unsigned char>(c)))
        fail(i, "XML: expected <ParameterList> or <Parameter> elements, found text");
      ++i;
      continue;
    }
    if (xml.compare(i, 4, "<!--") == 0) {
      const auto end = xml.find("-->", i);
      if (end == std::string::npos) fail(i, "XML: unclosed comment");
      i = end + 3;
      continue;
    }
    if (xml.compare(i, 2, "<?") == 0) {
      const auto end = xml.find("?>", i);
      if (end == std::string::npos) fail(i, "XML: unclosed <?...?>");
      i = end + 2;
      continue;
    }
    const std::size_t start = i;
    const auto close = xml.find('>', i);
    if (close == std::string::npos) fail(i, "XML: unclosed element");
    const bool closing = xml[i + 1] == '/';
    const bool empty = xml[close - 1] == '/';
    std::size_t p = i + (closing ? 2 : 1);
    std::size_t q = p;
    while (q < close && !std::isspace(static_cast<unsigned char>(xml[q])) && xml[q] != '/' && xml[q] != '>') ++q;
    const std::string tag = xml.substr(p, q - p);
    i = close + 1;
    if (closing) {
      if (tag != "ParameterList" || first_child.empty())
        fail(start, "XML: unexpected </" + tag + ">");
      first_child.pop_back();
      given.pop_back();
      m.at(start, first_child.empty() ? "}}" : "}", 0);
      continue;
    }
    // Attributes.
    std::map<std::string, Attribute> attrs;
    while (q < close) {
      while (q < close && std::isspace(static_cast<unsigned char>(xml[q]))) ++q;
      if (q >= close || xml[q] == '/') break;
      std::size_t eq = xml.find('=', q);
      if (eq == std::string::npos || eq > close) fail(q, "XML: expected name=\"value\"");
      std::string key = xml.substr(q, eq - q);
      while (!key.empty() && std::isspace(static_cast<unsigned char>(key.back()))) key.pop_back();
      std::size_t v = eq + 1;
      while (v < close && std::isspace(static_cast<unsigned char>(xml[v]))) ++v;
      const char quote = xml[v];
      if (quote != '"' && quote != '\'') fail(v, "XML: expected a quoted attribute value");
      const auto vend = xml.find(quote, v + 1);
      if (vend == std::string::npos || vend > close) fail(v, "XML: unclosed attribute value");
      attrs[key] = Attribute{decode(xml.substr(v + 1, vend - v - 1)), v, vend - v + 1};
      q = vend + 1;
    }
    if (tag == "ParameterList") {
      if (root_done && first_child.empty()) fail(start, "XML: a second top-level <ParameterList>");
      if (first_child.empty()) {
        m.at(start, "{'Peridigm': {", 0);
        root_done = true;
      } else {
        auto name = attrs.find("name");
        if (name == attrs.end()) fail(start, "XML: <ParameterList> without a name");
        if (!first_child.back()) m.at(start, ",", 0);
        first_child.back() = false;
        m.at(name->second.offset, quoted(name->second.value) + ": {", name->second.span);
      }
      first_child.push_back(true);
      given.emplace_back();
      if (empty) {
        first_child.pop_back();
        given.pop_back();
        m.at(close, first_child.empty() ? "}}" : "}", 0);
      }
    } else if (tag == "Parameter") {
      if (first_child.empty()) fail(start, "XML: <Parameter> outside a <ParameterList>");
      auto name = attrs.find("name");
      auto value = attrs.find("value");
      if (name == attrs.end()) fail(start, "XML: <Parameter> without a name");
      if (value == attrs.end()) fail(start, "XML: <Parameter name=\"" + name->second.value + "\"> without a value");
      std::string type = attrs.count("type") ? attrs["type"].value : "string";
      std::string v = value->second.value;
      std::size_t after = i;  // past the element
      if (!empty) {
        const auto end = xml.find("</Parameter>", i);
        if (end == std::string::npos) fail(start, "XML: <Parameter> without </Parameter>");
        after = end + 12;
      }
      const auto [seen, fresh] = given.back().try_emplace(name->second.value, std::make_pair(v, start));
      if (!fresh) {
        if (seen->second.first != v)
          fail(value->second.offset,
               fmt::format("XML: parameter '{}' is given twice in this list with different values ('{}' at line {}, "
                           "'{}' here); Peridigm's reader keeps the later one; remove the one you do not mean",
                           name->second.value, seen->second.first, line_col(seen->second.second).line, v));
        i = after;  // the same value again: one Parameter
        continue;
      }
      std::string token;
      if ((type == "double" || type == "int") && is_number(v)) token = v;
      else if (type == "bool") token = (v == "true" || v == "True" || v == "1") ? "true" : (v == "false" || v == "False" || v == "0") ? "false" : quoted(v);
      else token = quoted(v);
      if (!first_child.back()) m.at(start, ",", 0);
      first_child.back() = false;
      if (value->second.offset > name->second.offset) {
        m.at(name->second.offset, quoted(name->second.value) + ":", name->second.span);
        m.at(value->second.offset, token, value->second.span);
      } else {
        m.at(name->second.offset, quoted(name->second.value) + ": " + token, name->second.span);
      }
      i = after;
    } else {
      fail(start, "XML: unexpected element <" + tag + ">; a Peridigm deck holds <ParameterList> and <Parameter>");
    }
  }
  if (!first_child.empty()) fail(xml.size(), "XML: <ParameterList> not closed");
  if (!root_done) fail(0, "XML: no <ParameterList>");
  return m.finish();
}

}  // namespace horizon::peridigm
