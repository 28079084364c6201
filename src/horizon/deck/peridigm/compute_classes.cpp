// Peridigm's compute classes (survey sec. 1.9) as native history columns
// (output.history_columns, driver/history_columns.hpp).
#include <fmt/format.h>

#include <cstdlib>

#include "horizon/deck/peridigm/sections.hpp"

namespace horizon::peridigm {

using namespace horizon::deck;

namespace {

// Peridigm's variable names and the native quantities they read.
const std::vector<std::pair<std::string, std::string>> kVariables = {
    {"Displacement", "displacement"},       {"Velocity", "velocity"},
    {"Force", "force"},                     {"Force_Density", "force_density"},
    {"Coordinates", "position"},            {"Model_Coordinates", "reference_position"},
    {"Volume", "volume"},                   {"Damage", "damage"},
    {"Kinetic_Energy", "kinetic_energy"},   {"Stored_Elastic_Energy", "strain_energy"},
    {"Linear_Momentum", "linear_momentum"}, {"Angular_Momentum", "angular_momentum"},
};

// Peridigm's variables that are the models' output fields in Horizon (only the models
// that write them answer: correspondence; lps and elastic_plastic with shear_correction).
const std::vector<std::pair<std::string, std::string>> kFields = {
    {"Von_Mises_Stress", "von_mises_stress"},
    {"Equivalent_Plastic_Strain", "equivalent_plastic_strain"},
    {"Surface_Correction_Factor", "shear_correction_factor"}};

// Sets the column's `quantity` or `field` from Peridigm's Variable.
void set_variable(const DeckContext& ctx, const Item& item, YAML::Node& col) {
  const std::string v = read_string(ctx, item);
  std::vector<std::string> names;
  for (const auto& [p, q] : kVariables) {
    if (p == v) {
      col["quantity"] = q;
      return;
    }
    names.push_back(p);
  }
  for (const auto& [p, f] : kFields) {
    if (p == v) {
      col["field"] = f;
      return;
    }
    names.push_back(p);
  }
  fail_choice(ctx, item, v, names, "variable Horizon's history columns read");
}

std::string reduction(const DeckContext& ctx, const Item& item) {
  const std::string w = squash_words(read_string(ctx, item));
  if (w == "sum") return "sum";
  if (w == "minimum") return "min";
  if (w == "maximum") return "max";
  fail_choice(ctx, item, read_string(ctx, item), {"Sum", "Minimum", "Maximum"}, "calculation type");
}

}  // namespace

ComputeClasses read_compute_classes(const DeckContext& ctx, const Item& item, const std::vector<std::string>& node_sets,
                                    const std::set<int>& blocks) {
  ComputeClasses out;
  for (const auto& e : map_entries(ctx, item)) {
    const Item kind_item = MapReader(ctx, e.value, {"Compute Class", "X", "Y", "Z", "Variable", "Output Label",
                                                    "Verbose", "Block", "Node Set", "Calculation Type", "Block ID",
                                                    "dt"})
                               .get("Compute Class", "Nearest_Point_Data, Block_Data or Node_Set_Data");
    const std::string kind = read_string(ctx, kind_item);
    const std::string w = squash_words(kind);
    std::vector<std::string> keys = {"Compute Class", "Variable", "Output Label", "Verbose"};
    if (w == "nearestpointdata") keys.insert(keys.end(), {"X", "Y", "Z"});
    else if (w == "blockdata") keys.insert(keys.end(), {"Block", "Calculation Type"});
    else if (w == "nodesetdata") keys.insert(keys.end(), {"Node Set", "Calculation Type"});
    else if (w == "jintegral")
      // Peridigm's JIntegral class (Block ID, dt; PrecrackJIntegral): a J-integral about a
      // crack tip, whose definition its users' guide does not give. Horizon computes no
      // J-integral (docs/peridigm.md, "Compute classes").
      ctx.fail(kind_item.mark, kind_item.path + ": Peridigm's JIntegral compute class is not mapped: Horizon computes "
                                                "no J-integral (the classes it reads: Nearest_Point_Data, Block_Data, "
                                                "Node_Set_Data)");
    else
      fail_choice(ctx, kind_item, kind, {"Nearest_Point_Data", "Block_Data", "Node_Set_Data"},
                  "compute class Horizon reads");
    MapReader m(ctx, e.value, keys);
    if (auto v = m.find("Verbose")) read_bool(ctx, *v);
    const Item label_item = m.get("Output Label", "the name of the output variable");
    const std::string label = read_string(ctx, label_item);
    if (!out.labels.insert(label).second)
      ctx.fail(label_item.mark, label_item.path + ": two compute classes write the Output Label '" + label + "'");
    YAML::Node col;
    col["name"] = label;
    set_variable(ctx, m.get("Variable", "the variable, e.g. Displacement or Force"), col);
    if (w == "nearestpointdata") {
      YAML::Node at(YAML::NodeType::Sequence);
      at.SetStyle(YAML::EmitterStyle::Flow);
      for (const char* k : {"X", "Y", "Z"})
        at.push_back(fmt::format("{}", read_number(ctx, m.get(k, "the point's coordinate"))));
      col["nearest"] = at;
    } else {
      if (w == "blockdata") {
        const Item b = m.get("Block", "a block name, e.g. block_1");
        const std::string name = read_string(ctx, b);
        const int id = name.rfind("block_", 0) == 0 ? std::atoi(name.c_str() + 6) : 0;
        if (id < 1 || !blocks.count(id)) {
          std::vector<std::string> known;
          for (int k : blocks) known.push_back(fmt::format("block_{}", k));
          fail_choice(ctx, b, name, known, "block");
        }
        col["body"] = fmt::format("block_{}", id);
      } else {
        const Item n = m.get("Node Set", "the name of a node set defined in Boundary Conditions");
        const std::string set = read_string(ctx, n);
        check_reference(ctx, n, set, node_sets, "node set");
        out.node_sets.insert(set);
        col["region"] = set;
      }
      col["reduce"] = reduction(ctx, m.get("Calculation Type", "Sum, Minimum or Maximum"));
    }
    out.columns.push_back(col);
  }
  return out;
}

bool add_global_column(const std::string& variable, YAML::Node& columns) {
  static const std::vector<std::pair<std::string, std::string>> globals = {
      {"Global_Kinetic_Energy", "kinetic_energy"},
      {"Global_Linear_Momentum", "linear_momentum"},
      {"Global_Angular_Momentum", "angular_momentum"},
      {"Global_Strain_Energy", "strain_energy"}};
  for (const auto& [name, q] : globals) {
    if (name != variable) continue;
    YAML::Node col;
    col["name"] = name;
    col["quantity"] = q;
    columns.push_back(col);
    return true;
  }
  return false;
}

}  // namespace horizon::peridigm
