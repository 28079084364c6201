#include "horizon/deck/conditions.hpp"

#include <algorithm>
#include <cmath>

namespace horizon::deck {

namespace {

// A planar polygon's unit normal, or an error at `poly` when its corners lie on one line
// or off one plane.
Vec3 polygon_normal(const DeckContext& ctx, const Item& poly, const std::vector<Item>& corners,
                    const std::vector<Vec3>& p) {
  // The first corner that is not on the line through the first two fixes the plane, and
  // every corner must lie in that plane.
  double size = 0;
  for (const auto& q : p) size = std::max(size, norm(q - p[0]));
  Vec3 normal;
  for (std::size_t i = 2; i < p.size() && !(norm(normal) > 1e-9 * size * size); ++i)
    normal = cross(p[1] - p[0], p[i] - p[0]);
  if (!(norm(normal) > 1e-9 * size * size)) {
    ctx.fail(poly.mark, poly.path + ": the polygon's points lie on one line; it encloses no area");
  }
  normal = normal / norm(normal);
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (std::abs(dot(p[i] - p[0], normal)) > 1e-6 * size) {
      ctx.fail(corners[i].mark, corners[i].path +
                                    ": this point is off the plane of the polygon's first points; "
                                    "a precrack polygon must be planar");
    }
  }
  return normal;
}

std::vector<Vec3> read_polygon(const DeckContext& ctx, const Item& poly) {
  if (!poly.node.IsSequence()) fail_expected(ctx, poly, "a list of at least 3 points [x, y, z]");
  const auto corners = read_list(ctx, poly);
  if (corners.size() < 3) {
    ctx.fail(poly.mark, poly.path + ": a polygon needs at least 3 points, found " + std::to_string(corners.size()));
  }
  std::vector<Vec3> p;
  for (const auto& c : corners) p.push_back(read_vector(ctx, c));
  polygon_normal(ctx, poly, corners, p);
  return p;
}

// disk: {center: [x, y, z], normal: [nx, ny, nz], radius: r} (Peridigm's Disk bond filter).
PrecrackConfig read_disk(const DeckContext& ctx, const Item& item, PrecrackConfig crack) {
  MapReader d(ctx, item, {"center", "normal", "radius"});
  crack.points = {read_vector(ctx, d.get("center", "the disk's centre [x, y, z]"))};
  const Item n_item = d.get("normal", "the normal of the disk's plane [nx, ny, nz]");
  const Vec3 n = read_vector(ctx, n_item);
  if (!(norm(n) > 0)) ctx.fail(n_item.mark, n_item.path + ": the normal must not be zero");
  crack.normal = n / norm(n);
  crack.radius = read_positive(ctx, d.get("radius", "the disk's radius, > 0"));
  return crack;
}

// rectangle: {corner, normal, bottom, bottom_length, side_length}: Peridigm's
// Rectangular_Plane bond filter as it states it (family/precrack.hpp crosses_rectangle).
PrecrackConfig read_rectangle(const DeckContext& ctx, const Item& item, PrecrackConfig crack) {
  MapReader r(ctx, item, {"corner", "normal", "bottom", "bottom_length", "side_length"});
  crack.rectangle = true;
  crack.corner = read_vector(ctx, r.get("corner", "the rectangle's lower left corner [x, y, z]"));
  const Item n_item = r.get("normal", "the unit normal of the rectangle's plane [nx, ny, nz]");
  crack.normal = read_vector(ctx, n_item);
  if (!(std::abs(norm(crack.normal) - 1) < 1e-9)) ctx.fail(n_item.mark, n_item.path + ": the normal must be a unit vector");
  const Item b_item = r.get("bottom", "the direction of the bottom edge [x, y, z]");
  crack.bottom = read_vector(ctx, b_item);
  // Only the bottom vector's part in the plane spans the rectangle; it must not vanish.
  const Vec3 in_plane = crack.bottom - crack.normal * dot(crack.bottom, crack.normal);
  if (!(norm(in_plane) > 1e-9)) ctx.fail(b_item.mark, b_item.path + ": the bottom vector must not be along the normal");
  crack.bottom_length = read_positive(ctx, r.get("bottom_length", "the bottom edge's length, > 0"));
  crack.side_length = read_positive(ctx, r.get("side_length", "the side edge's length, > 0"));
  // The region it tests: (x - corner).bottom in [0, bottom_length] and (x - corner).side
  // in [0, side_length] on the plane, |side| = |in_plane|.
  const double q = dot(in_plane, in_plane);
  const Vec3 along_b = in_plane * (crack.bottom_length / q);
  const Vec3 along_s = cross(crack.bottom, crack.normal) * (crack.side_length / q);
  crack.points = {crack.corner, crack.corner + along_b, crack.corner + along_b + along_s, crack.corner + along_s};
  return crack;
}

// facets: [polygon, polygon, ...]: one crack surface of planar polygons (a shell mesh's
// elements; Peridigm's Exodus Mesh bond filter).
PrecrackConfig read_facets(const DeckContext& ctx, const Item& item, PrecrackConfig crack) {
  if (!item.node.IsSequence()) fail_expected(ctx, item, "a list of polygons [[x, y, z], [x, y, z], [x, y, z], ...]");
  std::vector<std::vector<Vec3>> facets;
  for (const auto& f : read_list(ctx, item)) facets.push_back(read_polygon(ctx, f));
  if (facets.empty()) ctx.fail(item.mark, item.path + ": expected at least one polygon");
  set_facets(crack, std::move(facets));
  return crack;
}

}  // namespace

PrecrackConfig read_precrack(const DeckContext& ctx, const Item& item) {
  MapReader m(ctx, item, {"from", "to", "polygon", "disk", "facets", "rectangle", "bonds"});
  PrecrackConfig crack;
  if (ctx.dimension == 1) ctx.fail(item.mark, item.path + ": precracks need a 2-D or 3-D deck");
  // bonds: removed (default) drops the crossing bonds; broken keeps them as broken bonds,
  // which model nonlinear_solid lets push in compression (Tupek eq. 6.9).
  if (auto b = m.find("bonds")) crack.keep_broken = choose_word(ctx, *b, {"removed", "broken"}) == 1;
  if (ctx.dimension == 2) {
    // A segment in the plane, cut through the whole thickness.
    for (const char* key : {"polygon", "disk", "facets", "rectangle"})
      if (auto p = m.find(key))
        ctx.fail(*p->key_mark, p->path + ": in a 2-D deck a precrack is a segment: {from: [x, y], to: [x, y]}");
    const Vec3 from = read_vector(ctx, m.get("from", "one end of the crack segment"));
    const Item to_item = m.get("to", "the other end of the crack segment");
    const Vec3 to = read_vector(ctx, to_item);
    if (!(norm(to - from) > 0)) ctx.fail(to_item.mark, to_item.path + ": the crack's ends 'from' and 'to' coincide");
    crack.points = {from, to};
    return crack;
  }
  for (const char* key : {"from", "to"}) {
    if (auto p = m.find(key)) {
      ctx.fail(*p->key_mark, p->path +
                                 ": in a 3-D deck a precrack is a planar polygon: "
                                 "{polygon: [[x, y, z], [x, y, z], [x, y, z], ...]}, a disk, a rectangle or facets");
    }
  }
  const auto shape = m.exactly_one({"polygon", "disk", "facets", "rectangle"}, true);
  if (*shape == "disk") return read_disk(ctx, *m.find("disk"), crack);
  if (*shape == "rectangle") return read_rectangle(ctx, *m.find("rectangle"), crack);
  if (*shape == "facets") return read_facets(ctx, *m.find("facets"), crack);
  crack.points = read_polygon(ctx, m.get("polygon", "the crack's corners, at least 3 points in one plane"));
  return crack;
}

std::string read_region_name(const DeckContext& ctx, const Item& item, const std::vector<std::string>& regions) {
  const std::string name = read_string(ctx, item);
  if (name == "all") return "";
  check_reference(ctx, item, name, regions, "region", "'all' means every particle");
  return name;
}

InitialConditionConfig read_initial_condition(const DeckContext& ctx, const Item& item,
                                              const std::vector<std::string>& regions) {
  MapReader m(ctx, item, {"region", "velocity", "displacement"});
  InitialConditionConfig ic;
  if (auto r = m.find("region")) ic.region = read_region_name(ctx, *r, regions);
  const bool v = m.has("velocity"), u = m.has("displacement");
  if (!v && !u) {
    ctx.fail(item.mark, item.path + ": missing required key: give velocity, displacement or both");
  }
  if (v) ic.velocity = read_vector_expr(ctx, *m.find("velocity"), true);
  if (u) ic.displacement = read_vector_expr(ctx, *m.find("displacement"), true);
  return ic;
}

LoadConfig read_load(const DeckContext& ctx, const Item& item, const std::vector<std::string>& regions) {
  MapReader m(ctx, item, {"region", "traction", "displacement", "velocity", "body_force", "force", "pressure", "normal"});
  LoadConfig load;
  const std::string kind =
      *m.exactly_one({"traction", "displacement", "velocity", "body_force", "force", "pressure"}, true);
  if (kind == "force") load.kind = LoadKind::force;
  if (kind == "pressure") {
    load.kind = LoadKind::pressure;
    if (!ctx.structure) {
      ctx.fail(*m.find("pressure")->key_mark, item.path + ".pressure: applies to structures (beam, plate, shell) "
                                              "only; a solid takes traction or body_force");
    }
  }
  if (kind == "traction") load.kind = LoadKind::traction;
  if (kind == "displacement") load.kind = LoadKind::displacement;
  if (kind == "velocity") load.kind = LoadKind::velocity;
  if (kind == "body_force") load.kind = LoadKind::body_force;

  if (auto r = m.find("region"))
    load.region = read_region_name(ctx, *r, regions);
  else if (load.kind != LoadKind::body_force)
    m.fail_missing("region", "where the " + kind + " acts: a name from regions, or all");

  // Prescribed motion may leave components free (null); forces may not.
  const bool motion = load.kind == LoadKind::displacement || load.kind == LoadKind::velocity;
  load.value = read_vector_expr(ctx, *m.find(kind), motion);

  if (auto n = m.find("normal")) {
    if (load.kind != LoadKind::traction) {
      ctx.fail(*n->key_mark, n->path + ": 'normal' applies to traction only, not to " + kind);
    }
    const std::vector<std::string> axes = {"x", "y", "z"};
    load.normal_axis =
        static_cast<int>(choose_word(ctx, *n, std::vector<std::string>(axes.begin(), axes.begin() + ctx.dimension)));
  }
  return load;
}

}  // namespace horizon::deck
