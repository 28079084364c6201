#include "horizon/deck/reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>

#include "horizon/core/error.hpp"
#include "horizon/deck/suggest.hpp"

namespace horizon::deck {

namespace {

DeckLocation location(const std::string& file, const YAML::Mark& at) {
  DeckLocation where{file, 0, 0};
  if (!at.is_null() && at.line >= 0) {  // yaml-cpp counts from 0, people from 1
    where.line = at.line + 1;
    where.column = at.column + 1;
  }
  return where;
}

std::string prefix(const std::string& path) { return path.empty() ? std::string() : path + ": "; }

bool is_scalar(const YAML::Node& node) { return node.IsDefined() && node.IsScalar(); }

// Parses the whole text as a finite number; "1e-3", "+2", "-0.5" but not "1e-3x" or "inf".
std::optional<double> parse_number(std::string_view text) {
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  double value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(value)) return std::nullopt;
  return value;
}

std::string lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace

void DeckContext::fail(const YAML::Mark& at, const std::string& message) const {
  throw DeckError(location(file, at), message);
}

void DeckContext::warn(const YAML::Mark& at, const std::string& message) const {
  if (!warnings) return;
  const DeckLocation where = location(file, at);
  // The same "file:line:column: " prefix as DeckError's messages.
  warnings->push_back(where.line > 0
                          ? fmt::format("{}:{}:{}: warning: {}", where.file, where.line, where.column, message)
                          : fmt::format("{}: warning: {}", where.file, message));
}

std::string child_path(const std::string& path, std::string_view key) {
  return path.empty() ? std::string(key) : path + "." + std::string(key);
}

std::string index_path(const std::string& path, std::size_t index) { return path + "[" + std::to_string(index) + "]"; }

// A scalar as a message quotes it: control characters (a binary file read as a deck) as
// a byte count, and long text cut to its first 60 characters.
std::string quote_scalar(const std::string& s) {
  std::size_t control = 0;
  for (unsigned char ch : s) control += (ch < 0x20 && ch != '\t') || ch == 0x7f;
  if (control > 0) return "binary data (" + std::to_string(s.size()) + " bytes, not text)";
  if (s.size() > 60) return "'" + s.substr(0, 60) + "...' (" + std::to_string(s.size()) + " characters)";
  return "'" + s + "'";
}

std::string describe(const YAML::Node& node) {
  if (!node.IsDefined()) return "nothing";
  switch (node.Type()) {
    case YAML::NodeType::Null:
      return "an empty value";
    case YAML::NodeType::Scalar:
      return quote_scalar(node.Scalar());
    case YAML::NodeType::Sequence:
      return "a list of " + std::to_string(node.size()) + (node.size() == 1 ? " item" : " items");
    case YAML::NodeType::Map:
      return "a map";
    default:
      return "nothing";
  }
}

void fail_expected(const DeckContext& ctx, const Item& item, std::string_view expected) {
  ctx.fail(item.mark, prefix(item.path) + "expected " + std::string(expected) + ", found " + describe(item.node));
}

std::vector<Entry> map_entries(const DeckContext& ctx, const Item& item) {
  std::vector<Entry> entries;
  if (!item.node.IsDefined() || item.node.IsNull()) return entries;
  if (!item.node.IsMap()) fail_expected(ctx, item, "a map of 'key: value' lines");
  for (auto it = item.node.begin(); it != item.node.end(); ++it) {
    const YAML::Node key = it->first;
    const YAML::Node value = it->second;
    if (!is_scalar(key)) {
      ctx.fail(key.Mark(), prefix(item.path) + "a key must be a plain word, found " + describe(key));
    }
    const std::string name = key.Scalar();
    const std::string path = child_path(item.path, name);
    for (const auto& e : entries) {
      if (e.key == name) {
        ctx.fail(key.Mark(), path + ": duplicate key '" + name + "' (first given at line " +
                                 std::to_string(e.value.key_mark->line + 1) + ")");
      }
    }
    const bool empty = value.IsNull() || value.Mark().is_null();
    entries.push_back({name, Item{value, path, empty ? key.Mark() : value.Mark(), key.Mark()}});
  }
  return entries;
}

MapReader::MapReader(const DeckContext& ctx, const Item& item, std::vector<std::string> allowed)
    : ctx_(ctx), item_(item), entries_(map_entries(ctx, item)) {
  for (const auto& e : entries_) {
    if (std::find(allowed.begin(), allowed.end(), e.key) != allowed.end()) continue;
    std::string message = e.value.path + ": unknown key '" + e.key + "'";
    if (const auto guess = closest_word(e.key, allowed))
      message += "; did you mean '" + *guess + "'?";
    else
      message += "; valid keys here: " + join_words(allowed);
    ctx.fail(*e.value.key_mark, message);
  }
}

std::optional<Item> MapReader::find(std::string_view key) const {
  for (const auto& e : entries_)
    if (e.key == key) return e.value;
  return std::nullopt;
}

Item MapReader::get(std::string_view key, std::string_view what) const {
  if (auto item = find(key)) return *item;
  fail_missing(key, what);
}

void MapReader::fail_missing(std::string_view key, std::string_view what) const {
  std::string message = prefix(item_.path) + "missing required key '" + std::string(key) + "'";
  if (!what.empty()) message += " (" + std::string(what) + ")";
  ctx_.fail(item_.key_mark.value_or(item_.mark), message);
}

std::optional<std::string> MapReader::exactly_one(const std::vector<std::string>& keys, bool required) const {
  std::optional<Entry> first;
  for (const auto& e : entries_) {
    if (std::find(keys.begin(), keys.end(), e.key) == keys.end()) continue;
    if (first) {
      ctx_.fail(*e.value.key_mark, prefix(item_.path) + "give only one of " + join_words(keys, "'") + "; found both '" +
                                       first->key + "' and '" + e.key + "'");
    }
    first = e;
  }
  if (first) return first->key;
  if (required) {
    ctx_.fail(item_.key_mark.value_or(item_.mark),
              prefix(item_.path) + "missing required key: give one of " + join_words(keys, "'"));
  }
  return std::nullopt;
}

std::string text_of(const Item& item) { return is_scalar(item.node) ? item.node.Scalar() : describe(item.node); }

double read_number(const DeckContext& ctx, const Item& item) {
  if (!is_scalar(item.node)) fail_expected(ctx, item, "a number");
  const std::string& text = item.node.Scalar();
  if (const auto value = parse_number(text)) return *value;
  std::string message = prefix(item.path) + "expected a number, found '" + text + "'";
  const std::size_t space = text.find(' ');
  if (space != std::string::npos && parse_number(std::string_view(text).substr(0, space)))
    message += " (write the number alone: every value in a deck is in SI units)";
  else if (text.find_first_of("*/()^") != std::string::npos)
    message += " (expressions in t, x, y, z are allowed only in loads and initial_conditions)";
  ctx.fail(item.mark, message);
}

double read_positive(const DeckContext& ctx, const Item& item) {
  const double value = read_number(ctx, item);
  if (!(value > 0)) ctx.fail(item.mark, prefix(item.path) + "expected a number > 0, found " + text_of(item));
  return value;
}

double read_non_negative(const DeckContext& ctx, const Item& item) {
  const double value = read_number(ctx, item);
  if (!(value >= 0)) ctx.fail(item.mark, prefix(item.path) + "expected a number >= 0, found " + text_of(item));
  return value;
}

int read_int(const DeckContext& ctx, const Item& item) {
  if (!is_scalar(item.node)) fail_expected(ctx, item, "a whole number");
  const auto value = parse_number(item.node.Scalar());
  if (!value || *value != std::floor(*value) || std::abs(*value) > 2e9) fail_expected(ctx, item, "a whole number");
  return static_cast<int>(*value);
}

bool read_bool(const DeckContext& ctx, const Item& item) {
  if (is_scalar(item.node)) {
    const std::string s = lower(item.node.Scalar());
    if (s == "true" || s == "yes" || s == "on") return true;
    if (s == "false" || s == "no" || s == "off") return false;
  }
  fail_expected(ctx, item, "true or false");
}

std::string read_string(const DeckContext& ctx, const Item& item) {
  if (!is_scalar(item.node)) fail_expected(ctx, item, "a name or text");
  return item.node.Scalar();
}

std::size_t choose_word(const DeckContext& ctx, const Item& item, const std::vector<std::string>& valid) {
  if (!is_scalar(item.node)) fail_expected(ctx, item, "one of " + join_words(valid));
  const std::string s = item.node.Scalar();
  for (std::size_t i = 0; i < valid.size(); ++i)
    if (valid[i] == s) return i;
  fail_choice(ctx, item, s, valid, "one of");
}

void fail_choice(const DeckContext& ctx, const Item& item, const std::string& found,
                 const std::vector<std::string>& valid, std::string_view what) {
  std::string message =
      prefix(item.path) + "expected " + std::string(what) + " " + join_words(valid) + "; found '" + found + "'";
  if (const auto guess = closest_word(found, valid)) message += "; did you mean '" + *guess + "'?";
  ctx.fail(item.mark, message);
}

void check_reference(const DeckContext& ctx, const Item& item, const std::string& name,
                     const std::vector<std::string>& valid, std::string_view what, std::string_view note) {
  if (std::find(valid.begin(), valid.end(), name) != valid.end()) return;
  std::string message = prefix(item.path) + "unknown " + std::string(what) + " '" + name + "'";
  if (const auto guess = closest_word(name, valid)) message += "; did you mean '" + *guess + "'?";
  if (valid.empty())
    message += " (no " + std::string(what) + "s are defined";
  else
    message += " (defined " + std::string(what) + "s: " + join_words(valid);
  if (!note.empty()) message += "; " + std::string(note);
  message += ")";
  ctx.fail(item.mark, message);
}

std::vector<Item> read_list(const DeckContext& ctx, const Item& item) {
  std::vector<Item> items;
  if (!item.node.IsDefined() || item.node.IsNull()) return items;
  if (!item.node.IsSequence()) fail_expected(ctx, item, "a list (lines starting with '- ', or [a, b, ...])");
  std::size_t i = 0;
  for (const auto& child : item.node) {
    const YAML::Mark mark = child.Mark().is_null() ? item.mark : child.Mark();
    items.push_back(Item{child, index_path(item.path, i), mark, std::nullopt});
    ++i;
  }
  return items;
}

namespace {
// The components of a vector, checked for count.
std::vector<Item> components(const DeckContext& ctx, const Item& item, std::string_view kind) {
  const int n = ctx.dimension;
  const std::string expected = std::to_string(n) + (n == 1 ? " component" : " components");
  if (!item.node.IsDefined() || !item.node.IsSequence()) {
    fail_expected(ctx, item,
                  "a list of " + expected + " (" + std::string(kind) + "), e.g. " +
                      (n == 1   ? "[0]"
                       : n == 2 ? "[0, 0]"
                                : "[0, 0, 0]"));
  }
  auto items = read_list(ctx, item);
  if (static_cast<int>(items.size()) != n) {
    ctx.fail(item.mark, prefix(item.path) + "expected " + expected + " (one per axis of a " + std::to_string(n) +
                            "-D deck), found " + std::to_string(items.size()));
  }
  return items;
}
}  // namespace

Vec3 read_vector(const DeckContext& ctx, const Item& item) {
  Vec3 v;
  const auto items = components(ctx, item, "numbers");
  for (std::size_t k = 0; k < items.size(); ++k) v[static_cast<int>(k)] = read_number(ctx, items[k]);
  return v;
}

Vec3Expr read_vector_expr(const DeckContext& ctx, const Item& item, bool allow_free) {
  Vec3Expr v;
  const auto items = components(ctx, item, allow_free ? "numbers, expressions or null" : "numbers or expressions");
  for (std::size_t k = 0; k < items.size(); ++k) {
    const Item& c = items[k];
    if (c.node.IsNull()) {
      if (!allow_free) {
        ctx.fail(c.mark, c.path + ": this component cannot be left free (empty or null); write 0 for none");
      }
      continue;  // not prescribed
    }
    if (!is_scalar(c.node)) {
      fail_expected(
          ctx, c,
          allow_free ? "a number, an expression in t, x, y, z, or null" : "a number or an expression in t, x, y, z");
    }
    const std::string& text = c.node.Scalar();
    if (const auto value = parse_number(text)) {
      v[k] = Expression(*value);
      continue;
    }
    try {
      v[k] = Expression(text);
    } catch (const Error& e) {
      ctx.fail(c.mark, c.path + ": " + e.what() + " (variables: t, x, y, z; e.g. \"-20*min(t/1e-6, 1)\")");
    }
    // A constant expression is evaluated once, here: 1/0, sqrt(-1), log(0) are caught at
    // their line (expressions in t, x, y, z are checked where they apply, loads.cpp).
    if (v[k]->is_constant() && !std::isfinite((*v[k])(0))) {
      ctx.fail(c.mark, c.path + ": the expression '" + text + "' is " + (std::isnan((*v[k])(0)) ? "not a number" : "infinite") +
                           " (a division by zero, or a function outside its domain); expected a finite value");
    }
  }
  if (!allow_free)
    for (int k = ctx.dimension; k < 3; ++k) v[k] = Expression(0.0);
  return v;
}

Expression read_scalar_expr(const DeckContext& ctx, const Item& item) {
  if (!is_scalar(item.node)) fail_expected(ctx, item, "a number or an expression in t, x, y, z");
  const std::string& text = item.node.Scalar();
  if (const auto value = parse_number(text)) return Expression(*value);
  try {
    return Expression(text);
  } catch (const Error& e) {
    ctx.fail(item.mark, item.path + ": " + e.what() + " (variables: t, x, y, z; e.g. \"293 + 10*sin(x/0.01)\")");
  }
}

}  // namespace horizon::deck
