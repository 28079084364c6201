#include "horizon/deck/history_columns.hpp"

#include <algorithm>
#include <cctype>

namespace horizon::deck {

std::vector<HistoryColumnConfig> read_history_columns(const DeckContext& ctx, const Item& item, const Config& config) {
  if (!item.node.IsSequence())
    fail_expected(ctx, item, "a list of columns, e.g. [{name: top_force, quantity: force, body: top, reduce: sum}]");
  std::vector<HistoryColumnConfig> out;
  for (const Item& e : read_list(ctx, item)) {
    MapReader m(ctx, e, {"name", "quantity", "field", "body", "region", "reduce", "nearest"});
    HistoryColumnConfig c;
    const Item name = m.get("name", "the column's name (letters, digits, _)");
    c.name = read_string(ctx, name);
    const bool plain = !c.name.empty() && std::all_of(c.name.begin(), c.name.end(), [](char ch) {
      return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '.' || ch == '-';
    });
    if (!plain) fail_expected(ctx, name, "a column name of letters, digits, '_', '.' or '-'");
    for (const auto& o : out)
      if (o.name == c.name) ctx.fail(name.mark, name.path + ": two history columns are named '" + c.name + "'");
    // A model's output field (checked against the models' fields when the run starts),
    // or one of the particles' quantities.
    if (*m.exactly_one({"quantity", "field"}, true) == "field") {
      const Item f = *m.find("field");
      c.field = read_string(ctx, f);
      if (c.field.empty()) fail_expected(ctx, f, "the name of a model's output field, e.g. von_mises_stress");
    } else {
    c.quantity = read_enum<HistoryQuantity>(
        ctx, m.get("quantity", "displacement, velocity, force, kinetic_energy, ..."),
        {{"displacement", HistoryQuantity::displacement},
         {"velocity", HistoryQuantity::velocity},
         {"force", HistoryQuantity::force},
         {"force_density", HistoryQuantity::force_density},
         {"position", HistoryQuantity::position},
         {"reference_position", HistoryQuantity::reference_position},
         {"volume", HistoryQuantity::volume},
         {"damage", HistoryQuantity::damage},
         {"kinetic_energy", HistoryQuantity::kinetic_energy},
         {"strain_energy", HistoryQuantity::strain_energy},
         {"linear_momentum", HistoryQuantity::linear_momentum},
         {"angular_momentum", HistoryQuantity::angular_momentum}});
    }
    if (auto b = m.find("body")) {
      c.body = read_string(ctx, *b);
      std::vector<std::string> names;
      for (const auto& body : config.bodies) names.push_back(body.name);
      check_reference(ctx, *b, c.body, names, "body");
    }
    if (auto r = m.find("region")) {
      c.region = read_string(ctx, *r);
      std::vector<std::string> names;
      for (const auto& [k, v] : config.regions) names.push_back(k);
      check_reference(ctx, *r, c.region, names, "region");
    }
    if (auto n = m.find("nearest")) {
      for (const char* k : {"body", "region", "reduce"})
        if (auto it = m.find(k))
          ctx.fail(*it->key_mark, it->path + ": a column read at the nearest particle has no " + k);
      c.reduce = HistoryReduce::nearest;
      c.at = read_vector(ctx, *n);
    } else if (auto r = m.find("reduce")) {
      c.reduce = read_enum<HistoryReduce>(
          ctx, *r, {{"sum", HistoryReduce::sum}, {"min", HistoryReduce::min}, {"max", HistoryReduce::max}});
    }
    out.push_back(c);
  }
  return out;
}

}  // namespace horizon::deck
