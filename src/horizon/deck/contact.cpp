#include "horizon/deck/contact.hpp"

#include "horizon/contact/rigid_contact.hpp"

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

ShortRangeContactConfig read_short_range(const DeckContext& ctx, const Item& item,
                                         const std::vector<BodyConfig>& bodies) {
  ShortRangeContactConfig c;
  c.enabled = true;
  if (item.node.IsScalar()) {
    c.enabled = read_bool(ctx, item);
    return c;
  }
  MapReader m(ctx, item, {"law", "stiffness_factor", "reference_fraction", "max_distance", "contact_radius",
                          "spring_constant", "friction", "pairs", "search_radius", "search_every"});
  if (auto l = m.find("law"))
    c.law = read_enum<ShortRangeLaw>(ctx, *l, {{"lammps", ShortRangeLaw::lammps}, {"peridigm", ShortRangeLaw::peridigm}});
  // Each law's own keys; another law's key is an error.
  const bool pd = c.law == ShortRangeLaw::peridigm;
  for (const char* k : {"stiffness_factor", "reference_fraction", "max_distance", "contact_radius", "spring_constant",
                        "friction", "search_radius", "search_every"}) {
    const std::string key = k;
    const bool own = (key == "contact_radius" || key == "spring_constant" || key == "friction" ||
                      key == "search_radius" || key == "search_every") == pd;
    if (auto it = m.find(k); it && !own)
      ctx.fail(*it->key_mark, it->path + ": not a key of law " + (pd ? "peridigm" : "lammps") +
                                  (pd ? " (its keys: contact_radius, spring_constant, friction, search_radius, search_every)"
                                      : " (law peridigm has contact_radius, spring_constant, friction, search_radius, "
                                        "search_every)"));
  }
  if (auto f = m.find("stiffness_factor")) c.stiffness_factor = read_positive(ctx, *f);
  if (auto f = m.find("reference_fraction")) {
    c.reference_fraction = read_positive(ctx, *f);
    if (c.reference_fraction >= 1) {
      ctx.fail(f->mark, f->path + ": expected a fraction below 1 of the reference distance, found " + text_of(*f) +
                            " (at 1 or more, bonds at rest would already push apart)");
    }
  }
  if (auto f = m.find("max_distance")) c.max_distance = read_positive(ctx, *f);
  if (pd) {
    c.contact_radius = read_positive(ctx, m.get("contact_radius", "the contact radius R_c [m], > 0"));
    c.spring_constant = read_positive(ctx, m.get("spring_constant", "the spring constant k [Pa], > 0"));
    // Peridigm's search (ShortRangeContactConfig::search_radius): within search_radius
    // every search_every steps; a radius below R_c would leave touching pairs unlisted.
    if (auto r = m.find("search_radius")) {
      c.search_radius = read_positive(ctx, *r);
      if (c.search_radius < c.contact_radius)
        ctx.fail(r->mark, r->path + ": expected at least contact_radius (" + text_of(*m.find("contact_radius")) +
                              "), found " + text_of(*r));
    }
    if (auto e = m.find("search_every")) {
      if (!m.find("search_radius")) ctx.fail(*e->key_mark, e->path + ": needs search_radius (the search it spaces)");
      c.search_every = read_int(ctx, *e);
      if (c.search_every < 1) ctx.fail(e->mark, e->path + ": expected a number of steps >= 1, found " + text_of(*e));
    }
    if (auto f = m.find("friction")) {
      // A number, or an expression in t (Peridigm's Time Dependent Short Range Force).
      const Expression e = read_scalar_expr(ctx, *f);
      if (e.is_constant()) {
        c.friction = read_non_negative(ctx, *f);
      } else {
        c.friction = e(0.0);
        if (!(c.friction >= 0))
          ctx.fail(f->mark, f->path + ": the friction coefficient at t = 0 must be >= 0, found " + std::to_string(c.friction));
        c.friction_in_time = e;
      }
    }
  }
  if (auto p = m.find("pairs")) {
    if (!p->node.IsSequence()) fail_expected(ctx, *p, "a list of body pairs, e.g. [[disk, ball], [disk, disk]]");
    for (const Item& pair : read_list(ctx, *p)) {
      if (!pair.node.IsSequence() || pair.node.size() != 2) fail_expected(ctx, pair, "a pair of body names [a, b]");
      const auto ends = read_list(ctx, pair);
      std::string names[2];
      for (int e = 0; e < 2; ++e) {
        names[e] = read_string(ctx, ends[static_cast<std::size_t>(e)]);
        std::vector<std::string> known;
        for (const auto& b : bodies) known.push_back(b.name);
        if (std::find(known.begin(), known.end(), names[e]) == known.end())
          fail_choice(ctx, ends[static_cast<std::size_t>(e)], names[e], known, "body");
      }
      c.pairs.emplace_back(names[0], names[1]);
    }
  }
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

RigidShapeConfig read_rigid_shape(const DeckContext& ctx, const Item& item) {
  MapReader m(ctx, item, {"sphere", "ogive"});
  const std::string kind = *m.exactly_one({"sphere", "ogive"}, true);
  const Item body = *m.find(kind);
  RigidShapeConfig c;
  if (kind == "sphere") {
    MapReader s(ctx, body, {"radius"});
    c.kind = RigidShapeKind::sphere;
    c.radius = read_positive(ctx, s.get("radius", "the sphere's radius [m], > 0"));
    return c;
  }
  MapReader o(ctx, body, {"radius", "length", "crh", "axis"});
  c.kind = RigidShapeKind::ogive;
  c.radius = read_positive(ctx, o.get("radius", "the shank's radius [m], > 0"));
  c.length = read_non_negative(ctx, o.get("length", "the cylindrical shank's length behind the nose [m], >= 0"));
  const Item crh = o.get("crh", "the caliber-radius-head: the ogive's arc radius over the caliber, >= 0.5");
  c.crh = read_number(ctx, crh);
  if (!(c.crh >= 0.5))
    ctx.fail(crh.mark, crh.path + ": expected a caliber-radius-head >= 0.5 (0.5 is a hemispherical nose), found " +
                           text_of(crh));
  const Item axis = o.get("axis", "the direction the nose points to, e.g. [0, 0, -1]");
  c.axis = read_vector(ctx, axis);
  if (!(norm(c.axis) > 0)) fail_expected(ctx, axis, "a non-zero direction the nose points to");
  c.axis = c.axis / norm(c.axis);
  return c;
}

ProjectileConfig read_projectile(const DeckContext& ctx, const Item& item, std::size_t index) {
  MapReader m(ctx, item, {"name", "shape", "mass", "density", "position", "velocity", "contact", "filter"});
  ProjectileConfig c;
  c.name = "projectile" + std::to_string(index + 1);
  if (auto n = m.find("name")) c.name = read_string(ctx, *n);
  c.shape = read_rigid_shape(ctx, m.get("shape", "the body's shape, {sphere: {radius}} or {ogive: {radius, length, "
                                                  "crh, axis}}"));
  const std::string mass = *m.exactly_one({"mass", "density"}, true);
  if (mass == "mass") {
    c.mass = read_positive(ctx, *m.find("mass"));
  } else {
    RigidShape shape(c.shape);
    c.mass = read_positive(ctx, *m.find("density")) * shape.volume();
  }
  c.position = read_vector(ctx, m.get("position", "the initial position of the sphere's centre or the ogive's tip [m]"));
  c.velocity = read_vector(ctx, m.get("velocity", "the initial velocity [m/s]"));
  const Item law = m.get("contact", "the penalty contact, {law: linear | quadratic, stiffness: K}");
  MapReader l(ctx, law, {"law", "stiffness", "max_penetration"});
  if (auto w = l.find("law"))
    c.law = read_enum<ContactLaw>(ctx, *w, {{"linear", ContactLaw::linear}, {"quadratic", ContactLaw::quadratic}});
  c.stiffness = read_positive(ctx, l.get("stiffness", "K in the force density K d (linear) [N/m^4] or K d^2 "
                                                      "(quadratic) [N/m^5], > 0"));
  if (auto d = l.find("max_penetration")) {
    if (c.law != ContactLaw::quadratic)
      ctx.fail(d->key_mark ? *d->key_mark : d->mark,
               d->path + ": applies to law quadratic only (the linear law's stiffness does not depend on the depth)");
    c.max_penetration = read_positive(ctx, *d);
  }
  if (auto f = m.find("filter")) {
    MapReader fm(ctx, *f, {"cutoff"});
    c.filter_cutoff = read_positive(ctx, fm.get("cutoff", "the low-pass cutoff frequency [Hz], > 0"));
  }
  return c;
}

}  // namespace

ContactConfig read_contact(const DeckContext& ctx, const Item& item, const std::vector<BodyConfig>& bodies) {
  MapReader m(ctx, item, {"short_range", "indenters", "projectiles"});
  ContactConfig c;
  if (auto s = m.find("short_range")) c.short_range = read_short_range(ctx, *s, bodies);
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
  if (auto l = m.find("projectiles")) {
    if (ctx.dimension != 3 || ctx.structure)
      ctx.fail(*l->key_mark, l->path + ": rigid projectiles move in 3-D solid decks only (dimension: 3, no structure)");
    if (!l->node.IsSequence())
      fail_expected(ctx, *l, "a list of projectiles, each {shape, mass, position, velocity, contact}");
    const auto items = read_list(ctx, *l);
    for (std::size_t i = 0; i < items.size(); ++i) {
      c.projectiles.push_back(read_projectile(ctx, items[i], i));
      for (std::size_t q = 0; q + 1 < c.projectiles.size(); ++q)
        if (c.projectiles[q].name == c.projectiles.back().name)
          ctx.fail(items[i].mark, items[i].path + ": two projectiles are named '" + c.projectiles.back().name + "'");
    }
  }
  return c;
}

}  // namespace horizon::deck
