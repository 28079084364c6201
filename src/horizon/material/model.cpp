#include "horizon/material/model.hpp"

#include <cstdio>
#include <limits>

#include "horizon/core/error.hpp"
#include "horizon/state/system.hpp"

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

void fill_state_based_coefficients(const ModelSetup& in, double spring_factor, bool isolated_allowed) {
  const MaterialConfig& mat = in.material;
  auto& M = in.system.model;
  const double spring =
      0.5 * spring_factor * equivalent_micromodulus(mat.bulk_modulus, mat.shear_modulus, mat.influence, in.dims);
  const double contact_c = equivalent_micromodulus(mat.bulk_modulus, mat.shear_modulus, InfluenceKind::constant, in.dims);
  double s0 = std::numeric_limits<double>::infinity();
  if (mat.damage.enabled)
    s0 = mat.damage.critical_stretch
             ? *mat.damage.critical_stretch
             : lps_critical_stretch(*mat.damage.fracture_energy, mat.bulk_modulus, mat.shear_modulus, in.dims);
  for (uint32_t i : in.particles) {
    // A row another MPI rank holds is empty here (local rows, parallel/decomposition.hpp).
    if (M.weighted_volume[i] <= 0 && in.system.computes_row(i) && !isolated_allowed)
      throw Error("particle " + std::to_string(i) + " has no neighbours: the horizon is smaller than the spacing");
    M.spring[i] = spring;
    M.contact_micromodulus[i] = contact_c;
    M.critical_stretch[i] = s0;
    M.alpha[i] = mat.damage.enabled ? mat.damage.alpha : 0.0;
  }
  M.state_based = true;
}

std::string describe_models() {
  std::string out;
  auto number = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return std::string(buf);
  };
  for (const auto& e : model_registry()) {
    const ModelTraits& t = e.traits;
    out += t.name;
    for (const auto& a : t.aliases) out += " (alias " + a + ")";
    out += ": " + t.summary + "\n";
    out += std::string("  elastic constants: ") +
           (t.elastic == ElasticInput::one_modulus ? "one modulus (or micromodulus)" : "any two of E, nu, K, G") +
           (t.structural ? std::string("; structures (beam, plate, shell) only")
                         : "; dimension " + (t.min_dimension > 1 ? std::to_string(t.min_dimension) + " or 3" : "1, 2 or 3")) +
           "; damage law " +
           (t.critical_stretch_law && t.energy_law ? "critical_stretch or energy"
            : t.energy_law                         ? "energy"
            : t.critical_stretch_law               ? "critical_stretch"
                                                   : "its own (model parameters)") +
           (t.exclusive ? "; shares a run only with its own model" : "") + "\n";
    for (const auto& p : t.parameters)
      out += "  " + p.key + ": " + p.meaning +
             (p.default_value ? " (default " +
                                    (p.range == ParameterSpec::Range::boolean ? std::string(*p.default_value != 0 ? "true" : "false")
                                                                              : number(*p.default_value)) +
                                    ")"
                              : " (required)") +
             "\n";
    for (const auto& c : t.choices) {
      out += "  " + c.key + ": " + c.meaning + " (";
      for (std::size_t q = 0; q < c.choices.size(); ++q) out += (q ? " | " : "") + c.choices[q];
      out += "; default " + c.choices.front() + ")\n";
    }
  }
  return out;
}

void fill_model_defaults(MaterialConfig& m) {
  const ModelEntry* e = find_model(m.model);
  if (!e) return;
  for (const auto& p : e->traits.parameters)
    if (p.default_value && !m.parameters.count(p.key)) m.parameters[p.key] = *p.default_value;
  for (const auto& c : e->traits.choices)
    if (!m.choices.count(c.key)) m.choices[c.key] = c.choices.front();
}

void commit_history(System& s) {
  for (std::size_t m = 0; m < s.models.size(); ++m) s.models[m].commit(s);
  if (s.fe_coupling) s.fe_coupling->commit(s);  // the elements' plastic history (fe/fe_region.hpp)
}

}  // namespace horizon
