#include "horizon/deck/materials.hpp"
#include "horizon/deck/thermal.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "horizon/material/model.hpp"

#include "horizon/material/constants.hpp"

namespace horizon::deck {

namespace {

// The four isotropic constants, tagged by the key that names them in the deck.
enum Constant { E, NU, K, G };
const char* const kConstantKeys[4] = {"youngs_modulus", "poissons_ratio", "bulk_modulus", "shear_modulus"};

struct Given {
  Constant which;
  double value;
  Item item;
};

Given read_constant(const DeckContext& ctx, Constant which, const Item& item) {
  const double v = read_number(ctx, item);
  if (which == NU) {
    // nu -> 1/2 sends the bulk modulus to infinity; nu <= -1 makes the shear modulus
    // non-positive. Either way no stable isotropic solid.
    if (!(v > -1 && v < 0.5)) {
      ctx.fail(item.mark, item.path + ": expected a Poisson's ratio in (-1, 0.5), found " + text_of(item) +
                              " (at 0.5 and above the bulk modulus is infinite or negative: the material "
                              "would be incompressible or unstable)");
    }
  } else if (!(v > 0)) {
    ctx.fail(item.mark, item.path + ": expected a modulus > 0 [Pa], found " + text_of(item));
  }
  return {which, v, item};
}

// Young's modulus and Poisson's ratio from any two constants (the isotropic relations,
// e.g. Sadd, Elasticity, Table 4.1).
void to_e_nu(const Given& a, const Given& b, double& e, double& nu) {
  double c[4] = {0, 0, 0, 0};
  c[a.which] = a.value;
  c[b.which] = b.value;
  const int mask = (1 << a.which) | (1 << b.which);
  if (mask == ((1 << E) | (1 << NU))) {
    e = c[E], nu = c[NU];
  } else if (mask == ((1 << E) | (1 << K))) {
    e = c[E], nu = (3 * c[K] - c[E]) / (6 * c[K]);
  } else if (mask == ((1 << E) | (1 << G))) {
    e = c[E], nu = c[E] / (2 * c[G]) - 1;
  } else if (mask == ((1 << K) | (1 << NU))) {
    nu = c[NU], e = 3 * c[K] * (1 - 2 * c[NU]);
  } else if (mask == ((1 << K) | (1 << G))) {
    e = 9 * c[K] * c[G] / (3 * c[K] + c[G]);
    nu = (3 * c[K] - 2 * c[G]) / (2 * (3 * c[K] + c[G]));
  } else {  // G and nu
    nu = c[NU], e = 2 * c[G] * (1 + c[NU]);
  }
}

std::string plane_words(const DeckContext& ctx) {
  if (ctx.dimension == 1) return "in 1-D";
  if (ctx.dimension == 3) return "in 3-D";
  return ctx.plane == PlaneMode::stress ? "in 2-D plane stress" : "in 2-D plane strain";
}

void read_elastic_constants(const DeckContext& ctx, const MapReader& m, MaterialConfig& mat, const ModelTraits& traits) {
  std::vector<Given> given;
  for (int c = E; c <= G; ++c)
    if (auto item = m.find(kConstantKeys[c])) given.push_back(read_constant(ctx, static_cast<Constant>(c), *item));
  const std::string path = m.self().path;
  const bool pmb = traits.elastic == ElasticInput::one_modulus;
  const std::string& model_name = traits.name;
  const std::string all_four = "youngs_modulus, poissons_ratio, bulk_modulus, shear_modulus";

  if (given.empty()) {
    const Item& self = m.self();
    ctx.fail(self.key_mark.value_or(self.mark),
             path + ": missing elastic constants (" +
                 (pmb ? "model " + model_name + " needs one of youngs_modulus, bulk_modulus, shear_modulus)"
                      : "model " + model_name + " needs two of " + all_four + ")"));
  }
  if (given.size() > 2) {
    ctx.fail(*given[2].item.key_mark, path + ": give at most two of " + all_four + "; found " +
                                          std::to_string(given.size()) +
                                          " (two fix an isotropic material, more over-determine it)");
  }

  double e = 0, nu = 0;
  if (pmb) {
    // A bond-based model has one constant: its Poisson's ratio is fixed by the dimension.
    const double fixed = bond_based_poisson_ratio(ctx.dimension, ctx.plane);
    const std::string fixed_text = fixed == 0.25 ? "1/4" : "1/3";
    const std::string why = "model " + model_name + " is bond-based, which fixes Poisson's ratio at " + fixed_text + " " +
                            plane_words(ctx) + "; give one modulus only, or use model: lps for a free " +
                            "Poisson's ratio";
    if (given.size() == 1 && given[0].which == NU) {
      ctx.fail(*given[0].item.key_mark, path +
                                            ": poissons_ratio alone does not set the stiffness; give "
                                            "youngs_modulus, bulk_modulus or shear_modulus");
    }
    const Given nu_given{NU, fixed, m.self()};
    if (given.size() == 1) {
      to_e_nu(given[0], nu_given, e, nu);
    } else {
      to_e_nu(given[0], given[1], e, nu);
      if (std::abs(nu - fixed) > 1e-3) {
        const Given& bad = given[1].which == NU ? given[1] : given[0].which == NU ? given[0] : given[1];
        const std::string found = bad.which == NU ? "poissons_ratio is " + text_of(bad.item)
                                                  : std::string(kConstantKeys[given[0].which]) + " and " +
                                                        kConstantKeys[given[1].which] +
                                                        " imply poissons_ratio = " + fmt::format("{:.4g}", nu);
        ctx.fail(bad.item.mark, bad.item.path + ": " + found + ", but " + why);
      }
      // Keep the moduli as given: derive the others from the first with the exact ratio.
      const Given& modulus = given[0].which == NU ? given[1] : given[0];
      to_e_nu(modulus, nu_given, e, nu);
    }
  } else {
    if (given.size() < 2) {
      ctx.fail(*given[0].item.key_mark, path + ": model " + model_name + " needs two elastic constants (any two of " + all_four +
                                            "); found only " + kConstantKeys[given[0].which]);
    }
    to_e_nu(given[0], given[1], e, nu);
    if (!(nu > -1 && nu < 0.5)) {
      ctx.fail(given[1].item.mark, given[1].item.path + ": " + kConstantKeys[given[0].which] + " = " +
                                       text_of(given[0].item) + " and " + kConstantKeys[given[1].which] + " = " +
                                       text_of(given[1].item) + " imply poissons_ratio = " + fmt::format("{:.4g}", nu) +
                                       ", outside (-1, 0.5): no stable isotropic material has these constants");
    }
  }
  mat.youngs_modulus = e;
  mat.poissons_ratio = nu;
  mat.bulk_modulus = e / (3 * (1 - 2 * nu));
  mat.shear_modulus = e / (2 * (1 + nu));
  // The constants as written stay exact; only the missing ones are derived.
  for (const auto& g : given) {
    if (g.which == E) mat.youngs_modulus = g.value;
    if (g.which == K) mat.bulk_modulus = g.value;
    if (g.which == G) mat.shear_modulus = g.value;
  }
}

std::string law_owners(bool energy) {
  std::string names;
  for (const auto& e : model_registry())
    if (energy ? e.traits.energy_law : e.traits.critical_stretch_law) names += (names.empty() ? "" : ", ") + e.traits.name;
  return names;
}

DamageConfig read_damage(const DeckContext& ctx, const Item& item, const ModelTraits& traits) {
  MapReader m(ctx, item,
              {"law", "critical_stretch", "fracture_energy", "alpha", "breaks", "broken_bonds", "failure_length_exponent"});
  DamageConfig d;
  d.enabled = true;
  const std::string& name = traits.name;
  if (auto law = m.find("law")) d.energy_law = choose_word(ctx, *law, {"critical_stretch", "energy"}) == 1;
  if (traits.energy_law && !traits.critical_stretch_law) {
    // Tupek's brittle failure (thesis sec. 6.1.3): the energy law with G_c only.
    if (auto law = m.find("law"); law && !d.energy_law) {
      ctx.fail(law->mark, law->path + ": model " + name + " breaks bonds by energy (law: energy, thesis eq. 6.10), "
                                      "not by critical stretch");
    }
    for (const char* key : {"critical_stretch", "alpha", "breaks"})
      if (auto k = m.find(key))
        ctx.fail(*k->key_mark, k->path + ": does not apply to law: energy of model " + name + "; give "
                                         "fracture_energy (and broken_bonds)");
    d.energy_law = true;
    d.fracture_energy = read_positive(ctx, m.get("fracture_energy", "G_c [J/m^2], > 0"));
    if (auto b = m.find("broken_bonds"))
      d.broken_bonds_compression = choose_word(ctx, *b, {"compression_only", "off"}) == 0;
    if (auto p = m.find("failure_length_exponent")) {
      d.failure_length_exponent = read_number(ctx, *p);
      if (!(d.failure_length_exponent >= 0 && d.failure_length_exponent <= 2))
        ctx.fail(p->mark, p->path + ": expected a number in [0, 2] (p of s_c = beta omega |xi|^-p; 2 is the thesis's "
                                    "eq. 6.3), found " + text_of(*p));
    }
    return d;
  }
  if (d.energy_law) {
    const Item law = *m.find("law");
    ctx.fail(law.mark, law.path + ": law: energy belongs to model " + law_owners(true) + "; model " + name +
                           " uses law: critical_stretch");
  }
  if (auto b = m.find("broken_bonds")) {
    ctx.fail(*b->key_mark, b->path + ": applies to model " + law_owners(true) + " only (broken " + name +
                               " bonds never act)");
  }
  if (auto p = m.find("failure_length_exponent")) {
    ctx.fail(*p->key_mark, p->path + ": applies to model " + law_owners(true) + " only (law: energy)");
  }
  const auto which = m.exactly_one({"critical_stretch", "fracture_energy"}, true);
  if (*which == "critical_stretch") {
    const Item cs = *m.find("critical_stretch");
    // A number, or an expression in t (Peridigm's Time Dependent Critical Stretch): s0(t)
    // at each step.
    const Expression e = read_scalar_expr(ctx, cs);
    if (!e.is_constant()) {
      const double s0 = e(0.0);
      if (!(s0 > 0)) ctx.fail(cs.mark, cs.path + ": the critical stretch at t = 0 must be > 0, found " + std::to_string(s0));
      d.critical_stretch = s0;
      d.critical_stretch_in_time = e;
    } else {
      d.critical_stretch = read_positive(ctx, cs);
    }
  }
  else
    d.fracture_energy = read_positive(ctx, *m.find("fracture_energy"));
  if (auto a = m.find("alpha")) d.alpha = read_non_negative(ctx, *a);
  if (auto b = m.find("breaks")) {
    d.break_after_force = choose_word(ctx, *b, {"before_force", "after_force"}) == 1;
  }
  return d;
}

// A model's own parameter, checked against its declared range.
double read_parameter(const DeckContext& ctx, const Item& item, const ParameterSpec& p) {
  using R = ParameterSpec::Range;
  switch (p.range) {
    case R::boolean: return read_bool(ctx, item) ? 1.0 : 0.0;
    case R::positive: return read_positive(ctx, item);
    case R::non_negative: return read_non_negative(ctx, item);
    case R::fraction: {
      const double v = read_number(ctx, item);
      if (!(v >= 0 && v <= 1))
        ctx.fail(item.mark, item.path + ": expected a number in [0, 1] (" + p.meaning + "), found " + text_of(item));
      return v;
    }
    case R::any: break;
  }
  return read_number(ctx, item);
}

const char* influence_name(InfluenceKind k) {
  switch (k) {
    case InfluenceKind::constant: return "constant";
    case InfluenceKind::inverse: return "inverse";
    case InfluenceKind::linear: return "linear";
    case InfluenceKind::gaussian: return "gaussian";
    case InfluenceKind::tupek: return "tupek";
    case InfluenceKind::inverse_length: return "inverse_length";
  }
  return "constant";
}

}  // namespace

void derive_from_micromodulus(MaterialConfig& mat, const Config& config) {
  if (!mat.micromodulus) return;
  // c is linear in E (docs/models.md sec. 2): E = c / c(E = 1).
  const Dimensioning dims{config.dimension, config.plane, config.thickness, config.area, config.horizon};
  const double nu = bond_based_poisson_ratio(config.dimension, config.plane);
  mat.youngs_modulus = *mat.micromodulus / pmb_micromodulus(1.0, mat.influence, dims);
  mat.poissons_ratio = nu;
  mat.bulk_modulus = mat.youngs_modulus / (3 * (1 - 2 * nu));
  mat.shear_modulus = mat.youngs_modulus / (2 * (1 + nu));
}

namespace {
const std::vector<std::string> kCommonKeys = {"model",         "density",      "youngs_modulus", "poissons_ratio",
                                               "bulk_modulus",  "shear_modulus", "influence",      "damage",
                                               "micromodulus", "thermal"};
}  // namespace

MaterialConfig read_material(const DeckContext& ctx, const std::string& name, const Item& item) {
  // The keys every material may have, and those its model declares: known only once the
  // model is read, so the map is first read for `model` alone.
  std::vector<std::string> every = kCommonKeys;
  for (const auto& e : model_registry()) {
    for (const auto& p : e.traits.parameters) every.push_back(p.key);
    for (const auto& c : e.traits.choices) every.push_back(c.key);
  }
  const MapReader any(ctx, item, every);
  MaterialConfig mat;
  mat.name = name;
  if (!any.has("model") && any.has("thermal")) {
    // A material of heat alone (docs/input.md, "Materials of heat alone"): a thermal map and
    // the density where heat is stored; solver.type heat only (check_thermal, deck.cpp).
    // Its mechanics are never computed: the placeholder model (pmb, E = 1, Poisson's ratio
    // the bond-based one) only lets the run's set-up pass.
    const MapReader m(ctx, item, {"density", "thermal"});
    mat.mechanics = false;
    mat.model = "pmb";
    mat.density = m.find("density") ? read_positive(ctx, *m.find("density")) : 1.0;
    mat.youngs_modulus = 1;
    mat.poissons_ratio = bond_based_poisson_ratio(ctx.dimension, ctx.plane);
    mat.bulk_modulus = 1 / (3 * (1 - 2 * mat.poissons_ratio));
    mat.shear_modulus = 1 / (2 * (1 + mat.poissons_ratio));
    for (const auto& p : find_model("pmb")->traits.parameters)
      if (p.default_value) mat.parameters[p.key] = *p.default_value;
    for (const auto& c : find_model("pmb")->traits.choices) mat.choices[c.key] = c.choices[0];
    mat.influence = find_model("pmb")->traits.default_influence;
    mat.thermal = read_thermal_material(ctx, *m.find("thermal"));
    return mat;
  }
  const Item model_item = any.get("model", "the material model: " + [] {
    std::string s;
    for (const auto& n : model_names()) s += (s.empty() ? "" : ", ") + n;
    return s;
  }());
  std::vector<std::string> words;
  for (const auto& e : model_registry()) {
    words.push_back(e.traits.name);
    for (const auto& a : e.traits.aliases) words.push_back(a);
  }
  const ModelTraits& traits = find_model(words[choose_word(ctx, model_item, words)])->traits;
  mat.model = traits.name;

  std::vector<std::string> allowed = kCommonKeys;
  for (const auto& p : traits.parameters) allowed.push_back(p.key);
  for (const auto& c : traits.choices) allowed.push_back(c.key);
  for (const auto& key : every)
    if (std::find(allowed.begin(), allowed.end(), key) == allowed.end())
      if (auto k = any.find(key)) {
        std::string owners;
        for (const auto& e : model_registry()) {
          bool has = false;
          for (const auto& p : e.traits.parameters) has = has || p.key == key;
          for (const auto& c : e.traits.choices) has = has || c.key == key;
          if (has) owners += (owners.empty() ? "" : ", ") + e.traits.name;
        }
        ctx.fail(*k->key_mark, k->path + ": applies to model " + owners + " only");
      }
  const MapReader m(ctx, item, allowed);

  if (ctx.dimension < traits.min_dimension) {
    ctx.fail(model_item.mark, model_item.path + ": model " + traits.name + " needs dimension " +
                                  std::to_string(traits.min_dimension) + " or 3" +
                                  (traits.energy_law ? " (its influence functions (6.6)/(6.7) are 2-D and 3-D)" : ""));
  }
  for (const auto& p : traits.parameters) {
    if (auto k = m.find(p.key))
      mat.parameters[p.key] = read_parameter(ctx, *k, p);
    else if (p.default_value)
      mat.parameters[p.key] = *p.default_value;
    else
      m.fail_missing(p.key, p.meaning);
  }
  for (const auto& c : traits.choices)
    mat.choices[c.key] = c.choices[m.find(c.key) ? choose_word(ctx, *m.find(c.key), c.choices) : 0];

  mat.influence = traits.default_influence;
  mat.density = read_positive(ctx, m.get("density", "mass density [kg/m^3], > 0"));
  if (auto c = m.find("micromodulus")) {
    // The bond-based models' one constant given directly (as LAMMPS's pair_coeff for peri/pmb).
    if (traits.elastic != ElasticInput::one_modulus) {
      ctx.fail(*c->key_mark, c->path + ": micromodulus applies to bond-based models only; model " + traits.name +
                                       " takes two of youngs_modulus, poissons_ratio, bulk_modulus, shear_modulus");
    }
    for (const char* key : kConstantKeys) {
      if (auto other = m.find(key)) {
        ctx.fail(*other->key_mark,
                 other->path + ": give either micromodulus or one modulus for model " + traits.name + ", not both");
      }
    }
    mat.micromodulus = read_positive(ctx, *c);
  } else {
    read_elastic_constants(ctx, m, mat, traits);
  }
  if (auto i = m.find("influence")) {
    std::vector<std::pair<std::string, InfluenceKind>> all;
    for (InfluenceKind k : {InfluenceKind::constant, InfluenceKind::inverse, InfluenceKind::linear,
                            InfluenceKind::gaussian, InfluenceKind::tupek, InfluenceKind::inverse_length})
      all.emplace_back(influence_name(k), k);
    mat.influence = read_enum<InfluenceKind>(ctx, *i, all);
    const auto& ok = traits.influences;
    if (std::find(ok.begin(), ok.end(), mat.influence) == ok.end()) {
      std::string list;
      for (InfluenceKind k : ok) list += (list.empty() ? "" : ", ") + std::string(influence_name(k));
      std::string owners;
      for (const auto& e : model_registry()) {
        const auto& o = e.traits.influences;
        if (std::find(o.begin(), o.end(), mat.influence) != o.end()) owners += (owners.empty() ? "" : ", ") + e.traits.name;
      }
      ctx.fail(i->mark, i->path + ": model " + traits.name + " takes influence " + list +
                            (ok.size() == 1 && ok[0] == InfluenceKind::tupek
                                 ? " (the normalised functions (6.6)/(6.7) its calibration assumes)"
                                 : "") +
                            "; influence: " + influence_name(mat.influence) + " belongs to model " + owners);
    }
  }
  if (auto d = m.find("damage")) mat.damage = read_damage(ctx, *d, traits);
  if (auto t = m.find("thermal")) mat.thermal = read_thermal_material(ctx, *t);
  // A boolean `fracture: false` (bonds of this material never break) contradicts a damage map.
  for (const auto& p : traits.parameters)
    if (p.key == "fracture" && p.range == ParameterSpec::Range::boolean && mat.damage.enabled &&
        mat.parameters[p.key] == 0) {
      const Item f = *m.find("fracture");
      ctx.fail(*f.key_mark, f.path + ": fracture: false suppresses bond failure; leave out the damage map too");
    }
  return mat;
}

}  // namespace horizon::deck
