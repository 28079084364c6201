// Peridigm's `Contact` section (survey sec. 1.4; Peridigm's users' guide SAND2012-7800):
// one or more `Short Range Force` models and the interactions that use them, as
// Horizon's short-range contact with law peridigm (state/short_range.hpp).
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <optional>

#include "horizon/core/error.hpp"
#include "horizon/core/expression.hpp"
#include "horizon/deck/peridigm/function_string.hpp"
#include "horizon/deck/peridigm/sections.hpp"

namespace horizon::peridigm {

using namespace horizon::deck;

std::string squash_words(const std::string& s) {
  std::string r;
  for (char c : s)
    if (c != ' ' && c != '_') r += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return r;
}

namespace {

struct Model {
  double radius = 0, spring = 0;
  std::string friction;  // a number, or a muParser expression in t; empty: none
  Item item;
};

Model read_model(const DeckContext& ctx, const Item& item, double horizon) {
  MapReader m(ctx, item, {"Contact Model", "Contact Radius", "Spring Constant", "Friction Coefficient", "Horizon"});
  const Item kind = m.get("Contact Model", "Short Range Force");
  const std::string w = squash_words(read_string(ctx, kind));
  if (w != "shortrangeforce" && w != "timedependentshortrangeforce")
    fail_choice(ctx, kind, read_string(ctx, kind), {"Short Range Force", "Time Dependent Short Range Force"},
                "Peridigm contact model Horizon reads");
  Model md{read_positive(ctx, m.get("Contact Radius", "the contact radius, > 0")),
           read_positive(ctx, m.get("Spring Constant", "the spring constant, > 0")), "", item};
  if (auto f = m.find("Friction Coefficient")) {
    // A number, or (Time Dependent Short Range Force) a function string of t, which
    // becomes the native friction's expression in t.
    const std::string text = f->node.IsScalar() ? f->node.Scalar() : "";
    char* end = nullptr;
    const double mu = std::strtod(text.c_str(), &end);
    const bool number = !text.empty() && end != text.c_str() &&
                        std::all_of(static_cast<const char*>(end), text.c_str() + text.size(), [](char c) { return std::isspace(static_cast<unsigned char>(c)); });
    if (number) {
      if (!(mu >= 0) || !std::isfinite(mu)) ctx.fail(f->mark, f->path + ": expected a number >= 0, found " + text_of(*f));
      if (mu > 0) md.friction = fmt::format("{}", mu);
    } else {
      std::string expr;
      try {
        expr = function_string_to_muparser(text);
        Expression e(expr);
        const double mu0 = e(0.0);
        if (!(mu0 >= 0)) throw FunctionStringError(0, "the coefficient at t = 0 is " + std::to_string(mu0) + ", not >= 0");
      } catch (const FunctionStringError& err) {
        ctx.fail(f->mark, f->path + ": cannot read the friction coefficient '" + text + "': " + err.what());
      } catch (const Error& err) {
        ctx.fail(f->mark, f->path + ": cannot read the friction coefficient '" + text + "': " + err.what());
      }
      md.friction = expr;
    }
  }
  if (auto h = m.find("Horizon"); h && read_positive(ctx, *h) != horizon)
    ctx.fail(h->mark, fmt::format("{}: the contact horizon must be the blocks' horizon ({}); Horizon has one "
                                  "horizon for the deck", h->path, horizon));
  return md;
}

}  // namespace

YAML::Node read_contact_section(const DeckContext& ctx, const Item& item, double horizon, const std::set<int>& blocks) {
  MapReader c(ctx, item, {"Verbose", "Search Radius", "Search Frequency", "Models", "Interactions"});
  if (auto v = c.find("Verbose")) read_bool(ctx, *v);
  // Peridigm searches for contact pairs within Search Radius every Search Frequency
  // steps, at the positions the step starts from, and only the pairs found touch until
  // the next search: the native search_radius and search_every (Contact_Ring's gold,
  // whose Search Radius is its Contact Radius, needs them; state/short_range.hpp).
  const Item radius = c.get("Search Radius", "the proximity-search radius, > 0");
  const double search_radius = read_positive(ctx, radius);
  const Item freq = c.get("Search Frequency", "the steps between proximity searches, >= 1");
  const int search_every = read_int(ctx, freq);
  if (search_every < 1) ctx.fail(freq.mark, freq.path + ": expected at least 1");
  std::map<std::string, Model> models;
  std::vector<std::string> model_names;
  for (const auto& e : map_entries(ctx, c.get("Models", "a map of contact models {Contact Model, Contact Radius, "
                                                        "Spring Constant}"))) {
    models.emplace(e.key, read_model(ctx, e.value, horizon));
    model_names.push_back(e.key);
  }
  const auto interactions = map_entries(ctx, c.get("Interactions", "a map of interactions {First Block, Second "
                                                                   "Block, Contact Model} or General Contact"));
  if (interactions.empty()) ctx.fail(item.mark, item.path + ".Interactions: expected at least one interaction");
  std::optional<std::string> used;  // the one model of the run
  std::optional<Item> used_at;
  std::set<std::string> named;  // the blocks the interactions name
  bool general = false;
  auto block_name = [&](const Item& b) {
    const std::string name = read_string(ctx, b);
    const int id = name.rfind("block_", 0) == 0 ? std::atoi(name.c_str() + 6) : 0;
    if (id < 1 || !blocks.count(id)) {
      std::vector<std::string> known;
      for (int k : blocks) known.push_back(fmt::format("block_{}", k));
      fail_choice(ctx, b, name, known, "block");
    }
    return fmt::format("block_{}", id);
  };
  for (const auto& e : interactions) {
    const bool is_general = squash_words(e.key) == "generalcontact";
    MapReader r(ctx, e.value,
                is_general ? std::vector<std::string>{"Contact Model"}
                           : std::vector<std::string>{"First Block", "Second Block", "Contact Model"});
    const Item mi = r.get("Contact Model", "the name of one of the contact Models");
    const std::string model = read_string(ctx, mi);
    check_reference(ctx, mi, model, model_names, "contact model");
    if (used && *used != model) {
      const Model &a = models.at(*used), &b = models.at(model);
      if (a.radius != b.radius || a.spring != b.spring || a.friction != b.friction)
        ctx.fail(mi.mark, fmt::format("{}: interactions with different contact models ('{}' here, '{}' at line {}) "
                                      "are not supported; Horizon has one contact law for the run",
                                      mi.path, model, *used, used_at->mark.line + 1));
    }
    used = model;
    used_at = mi;
    if (is_general) {
      general = true;
      continue;
    }
    named.insert(block_name(r.get("First Block", "a block name, e.g. block_1")));
    named.insert(block_name(r.get("Second Block", "a block name, e.g. block_2")));
  }
  const Model& m = models.at(*used);
  if (m.radius > search_radius)
    ctx.fail(radius.mark, fmt::format("{}: the search radius must be at least the Contact Radius ({}); a pair "
                                      "within it would not be found", radius.path, m.radius));
  // Peridigm's golds: an interaction of two blocks does not keep either from touching
  // itself. Contact_Perforation interacts block_1 with block_2 only, yet two particles of
  // block_2 that were never bonded (863 and 921, 0.54 apart at the start) repel in its
  // gold once damage has freed one; with the pair alone it differs from frame 7 on, with
  // every pair of the named blocks it matches. So the named blocks touch each other and
  // themselves (no gold has a block that no interaction names, so whether such a block
  // would touch too is not known).
  YAML::Node pairs(YAML::NodeType::Sequence);
  for (auto a = named.begin(); a != named.end(); ++a)
    for (auto b = a; b != named.end(); ++b) {
      YAML::Node pair(YAML::NodeType::Sequence);
      pair.SetStyle(YAML::EmitterStyle::Flow);
      pair.push_back(*a);
      pair.push_back(*b);
      pairs.push_back(pair);
    }
  YAML::Node sr;
  sr["law"] = "peridigm";
  sr["contact_radius"] = fmt::format("{}", m.radius);
  sr["spring_constant"] = fmt::format("{}", m.spring);
  if (!m.friction.empty()) sr["friction"] = m.friction;
  sr["search_radius"] = fmt::format("{}", search_radius);
  sr["search_every"] = search_every;
  // General Contact, or interactions that name every block: every pair of particles not
  // bonded at the start.
  if (!general && named.size() < blocks.size()) sr["pairs"] = pairs;
  YAML::Node out;
  out["short_range"] = sr;
  return out;
}

}  // namespace horizon::peridigm
