#include "horizon/material/model.hpp"

#include "horizon/core/error.hpp"

namespace horizon {

double Model::parameter(const MaterialConfig& m, const std::string& key) {
  const auto it = m.parameters.find(key);
  if (it == m.parameters.end())
    throw Error("material '" + m.name + "' (model " + m.model + ") has no parameter '" + key +
                "': the deck fills in every declared parameter; a material built in code must set it");
  return it->second;
}

const std::string& Model::choice(const MaterialConfig& m, const std::string& key) {
  const auto it = m.choices.find(key);
  if (it == m.choices.end())
    throw Error("material '" + m.name + "' (model " + m.model + ") has no choice '" + key +
                "': the deck fills in every declared choice; a material built in code must set it");
  return it->second;
}

const ModelEntry* find_model(const std::string& name) {
  for (const auto& e : model_registry()) {
    if (e.traits.name == name) return &e;
    for (const auto& a : e.traits.aliases)
      if (a == name) return &e;
  }
  return nullptr;
}

std::vector<std::string> model_names() {
  std::vector<std::string> names;
  for (const auto& e : model_registry()) names.push_back(e.traits.name);
  return names;
}

void fill_model_defaults(MaterialConfig& m) {
  const ModelEntry* e = find_model(m.model);
  if (!e) return;
  for (const auto& p : e->traits.parameters)
    if (p.default_value && !m.parameters.count(p.key)) m.parameters[p.key] = *p.default_value;
  for (const auto& c : e->traits.choices)
    if (!m.choices.count(c.key)) m.choices[c.key] = c.choices.front();
}

}  // namespace horizon
