#include "horizon/deck/contact.hpp"

#include <algorithm>
#include <cctype>

namespace horizon::deck {

PartialVolume read_partial_volume(const DeckContext& ctx, const Item& item) {
  if (item.node.IsScalar()) {
    std::string s = item.node.Scalar();
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (s == "true" || s == "yes" || s == "on") return PartialVolumeRule::linear;
    if (s == "false" || s == "no" || s == "off") return PartialVolumeRule::none;
  }
  return read_enum<PartialVolumeRule>(
      ctx, item,
      {{"none", PartialVolumeRule::none}, {"linear", PartialVolumeRule::linear}, {"lammps", PartialVolumeRule::lammps}});
}

namespace {

ShortRangeContactConfig read_short_range(const DeckContext& ctx, const Item& item) {
  ShortRangeContactConfig c;
  c.enabled = true;
  if (item.node.IsScalar()) {
    c.enabled = read_bool(ctx, item);
    return c;
  }
  MapReader m(ctx, item, {"stiffness_factor", "reference_fraction", "max_distance"});
  if (auto f = m.find("stiffness_factor")) c.stiffness_factor = read_positive(ctx, *f);
  if (auto f = m.find("reference_fraction")) {
    c.reference_fraction = read_positive(ctx, *f);
    if (c.reference_fraction >= 1) {
      ctx.fail(f->mark, f->path + ": expected a fraction below 1 of the reference distance, found " + text_of(*f) +
                            " (at 1 or more, bonds at rest would already push apart)");
    }
  }
  if (auto f = m.find("max_distance")) c.max_distance = read_positive(ctx, *f);
  return c;
}

IndenterConfig read_indenter(const DeckContext& ctx, const Item& item, std::size_t index) {
  MapReader m(ctx, item, {"name", "center", "radius", "stiffness"});
  IndenterConfig c;
  c.name = "indenter" + std::to_string(index + 1);
  if (auto n = m.find("name")) c.name = read_string(ctx, *n);
  c.center = read_vector_expr(ctx, m.get("center", "the centre, numbers or expressions in t, e.g. [0, \"0.002 - 100*t\", 0]"),
                              false);
  c.radius = read_positive(ctx, m.get("radius", "the sphere's radius [m], > 0"));
  c.stiffness = read_positive(ctx, m.get("stiffness", "K in the force density K (R - r)^2 [N/m^5], > 0"));
  return c;
}

}  // namespace

ContactConfig read_contact(const DeckContext& ctx, const Item& item) {
  MapReader m(ctx, item, {"short_range", "indenters"});
  ContactConfig c;
  if (auto s = m.find("short_range")) c.short_range = read_short_range(ctx, *s);
  if (auto l = m.find("indenters")) {
    if (!l->node.IsSequence()) fail_expected(ctx, *l, "a list of indenters, each {center, radius, stiffness}");
    const auto items = read_list(ctx, *l);
    for (std::size_t i = 0; i < items.size(); ++i) {
      c.indenters.push_back(read_indenter(ctx, items[i], i));
      for (std::size_t q = 0; q + 1 < c.indenters.size(); ++q)
        if (c.indenters[q].name == c.indenters.back().name)
          ctx.fail(items[i].mark, items[i].path + ": two indenters are named '" + c.indenters.back().name + "'");
    }
  }
  return c;
}

}  // namespace horizon::deck
