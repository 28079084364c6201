#include "horizon/deck/shapes.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

#include "horizon/deck/suggest.hpp"
#include "horizon/geometry/surface.hpp"

namespace horizon::deck {

namespace {

const std::vector<std::string> kShapeKinds = {"box",   "cylinder", "disk",     "sphere", "half_space",
                                              "union", "subtract", "points",   "mesh",  "surface"};
const char* const kAxisNames[3] = {"x", "y", "z"};

// In 2-D a disk is a cylinder along z through the plane; its ends lie far outside any
// sensible thickness so that only the in-plane circle matters.
constexpr double kThroughThickness = 1e3;

Shape read_box(const DeckContext& ctx, const Item& item) {
  MapReader m(ctx, item, {"min", "max"});
  const Item min_item = m.get("min", "the lowest corner, one coordinate per axis");
  const Item max_item = m.get("max", "the highest corner, one coordinate per axis");
  Vec3 min = read_vector(ctx, min_item);
  Vec3 max = read_vector(ctx, max_item);
  if (ctx.cylinder) {
    // A cylindrical shell's nodes leave the plane: a box of its deck selects by (x, y)
    // of the wrapped positions, through any z (docs/input.md, structure).
    min.z = -kThroughThickness;
    max.z = kThroughThickness;
  }
  for (int k = 0; k < ctx.dimension; ++k) {
    if (!(min[k] < max[k])) {
      ctx.fail(max_item.mark, max_item.path + ": a box needs min < max along every axis; along " + kAxisNames[k] +
                                  " min is " + text_of(read_list(ctx, min_item)[k]) + " and max is " +
                                  text_of(read_list(ctx, max_item)[k]));
    }
  }
  return Shape::box(min, max);
}

Shape read_sphere(const DeckContext& ctx, const Item& item) {
  MapReader m(ctx, item, {"center", "radius"});
  const Vec3 center = read_vector(ctx, m.get("center", "the centre point"));
  const double radius = read_positive(ctx, m.get("radius", "[m], > 0"));
  return Shape::sphere(center, radius);
}

Shape read_disk(const DeckContext& ctx, const Item& item, const YAML::Mark& key_mark) {
  if (ctx.dimension != 2) {
    ctx.fail(key_mark, item.path + ": disk is a 2-D shape (a cylinder through the thickness); in a " +
                           std::to_string(ctx.dimension) + "-D deck use " + (ctx.dimension == 3 ? "cylinder" : "box"));
  }
  MapReader m(ctx, item, {"center", "radius"});
  const Vec3 center = read_vector(ctx, m.get("center", "the centre point"));
  const double radius = read_positive(ctx, m.get("radius", "[m], > 0"));
  return Shape::cylinder(center - Vec3{0, 0, kThroughThickness}, center + Vec3{0, 0, kThroughThickness}, radius);
}

Shape read_cylinder(const DeckContext& ctx, const Item& item, const YAML::Mark& key_mark) {
  if (ctx.dimension == 1) ctx.fail(key_mark, item.path + ": cylinder needs a 2-D or 3-D deck; in 1-D use box");
  MapReader m(ctx, item, {"center", "axis", "length", "from", "to", "radius"});
  const double radius = read_positive(ctx, m.get("radius", "[m], > 0"));
  if (m.has("from") || m.has("to")) {
    for (const char* key : {"center", "axis", "length"}) {
      if (auto other = m.find(key)) {
        ctx.fail(*other->key_mark, other->path +
                                       ": give the cylinder either as {center, axis, length, radius} "
                                       "or as {from, to, radius}, not both");
      }
    }
    const Vec3 from = read_vector(ctx, m.get("from", "one end of the axis"));
    const Item to_item = m.get("to", "the other end of the axis");
    const Vec3 to = read_vector(ctx, to_item);
    if (!(norm(to - from) > 0)) ctx.fail(to_item.mark, to_item.path + ": the cylinder's ends 'from' and 'to' coincide");
    return Shape::cylinder(from, to, radius);
  }
  const Vec3 center = read_vector(ctx, m.get("center", "the centre point; or give 'from' and 'to'"));
  const Item axis_item = m.get("axis", "x, y or z");
  const int axis = static_cast<int>(choose_word(ctx, axis_item, {"x", "y", "z"}));
  const double length = read_positive(ctx, m.get("length", "[m] along the axis, > 0"));
  Vec3 half;
  half[axis] = 0.5 * length;
  return Shape::cylinder(center - half, center + half, radius);
}

Shape read_half_space(const DeckContext& ctx, const Item& item) {
  MapReader m(ctx, item, {"point", "normal"});
  const Vec3 point = read_vector(ctx, m.get("point", "a point on the bounding plane"));
  const Item normal_item = m.get("normal", "the outward normal of the bounding plane");
  const Vec3 normal = read_vector(ctx, normal_item);
  if (!(norm(normal) > 0)) ctx.fail(normal_item.mark, normal_item.path + ": the normal must not be zero");
  return Shape::half_space(point, normal);
}

std::string group_names(const std::vector<MeshGroup>& groups) {
  std::string out;
  for (const auto& g : groups) out += (out.empty() ? "" : ", ") + g.name;
  return out.empty() ? "none" : out;
}

// A mesh shape's file, scale and cells: all of them, one block's, or (regions) those
// touching a node or side set.
MeshSelection select_mesh(const DeckContext& ctx, const Item& item, const YAML::Mark& key_mark) {
  if (ctx.dimension == 1) ctx.fail(key_mark, item.path + ": a mesh needs a 2-D or 3-D deck");
  MeshSelection sel;
  sel.mark = item.mark;
  sel.path = item.path;
  MapReader m(ctx, item, {"file", "block", "set", "scale"});
  const Item file_item = m.get("file", "the mesh file: .msh (Gmsh 4.1) or .exo, .e, .g (Exodus II), relative to the deck");
  std::filesystem::path file = read_string(ctx, file_item);
  if (file.is_relative()) file = std::filesystem::path(ctx.file).parent_path() / file;
  sel.file = file.lexically_normal().string();
  const std::string key = sel.file + "#" + std::to_string(ctx.dimension);
  if (auto it = ctx.meshes->find(key); it != ctx.meshes->end()) {
    sel.mesh = it->second;
  } else {
    try {
      sel.mesh = std::make_shared<const Mesh>(read_mesh(sel.file, ctx.dimension));
    } catch (const Error& e) {
      ctx.fail(file_item.mark, file_item.path + ": " + e.what());
    }
    ctx.meshes->emplace(key, sel.mesh);
  }
  const Mesh& mesh = *sel.mesh;
  if (auto sc = m.find("scale")) sel.scale = read_positive(ctx, *sc);
  const auto which = m.exactly_one({"block", "set"}, false);
  if (which == "block") {
    const Item b = *m.find("block");
    const std::string name = read_string(ctx, b);
    const MeshGroup* g = mesh.find_block(name);
    if (!g)
      ctx.fail(b.mark, b.path + ": the mesh " + sel.file + " has no block '" + name + "'; its blocks: " +
                           group_names(mesh.blocks));
    sel.cells = g->members;
  } else if (which == "set") {
    const Item st = *m.find("set");
    const std::string name = read_string(ctx, st);
    sel.set = mesh.find_set(name);
    if (!sel.set)
      ctx.fail(st.mark, st.path + ": the mesh " + sel.file + " has no set '" + name + "'; its sets: " +
                            group_names(mesh.sets));
    sel.cells = mesh.cells_touching(*sel.set);
    if (sel.cells.empty()) ctx.fail(st.mark, st.path + ": no element of the mesh touches set '" + name + "'");
  } else {
    sel.cells.resize(mesh.cell_nodes.size());
    for (uint32_t e = 0; e < sel.cells.size(); ++e) sel.cells[e] = e;
  }
  return sel;
}

// A mesh file's elements as particles (geometry/mesh.hpp). A set's region also holds the
// set's nodes themselves: the finite-element nodes of a body made from the same mesh
// (fe/fe_region.hpp) sit there.
Shape read_mesh_shape(const DeckContext& ctx, const Item& item, const YAML::Mark& key_mark) {
  const MeshSelection sel = select_mesh(ctx, item, key_mark);
  const Mesh& mesh = *sel.mesh;
  const double scale = sel.scale;
  std::vector<Vec3> points;
  std::vector<double> measures;
  const bool with_measures = sel.set == nullptr;
  // Full volumes, as a body of listed points carries: 2-D areas times the thickness.
  const double measure_scale = std::pow(scale, ctx.dimension) * (ctx.dimension == 2 ? ctx.thickness : 1.0);
  for (uint32_t e : sel.cells) {
    points.push_back(scale == 1 ? mesh.centroid[e] : mesh.centroid[e] * scale);
    if (with_measures) measures.push_back(mesh.measure[e] * measure_scale);
  }
  if (sel.set)
    for (uint32_t n : sel.set->members) points.push_back(scale == 1 ? mesh.nodes[n] : mesh.nodes[n] * scale);
  return Shape::points(std::move(points), std::move(measures));
}

// points: a list of [x, y, z] or [x, y, z, volume] rows (one coordinate per axis), or
// {file: name} naming a text file of such rows (whitespace-separated; lines starting
// with # are comments; a relative name is relative to the deck's folder).
Shape read_points(const DeckContext& ctx, const Item& item) {
  const int d = ctx.dimension;
  std::vector<Vec3> at;
  std::vector<double> volumes;
  std::size_t with_volume = 0;
  auto add = [&](const std::vector<double>& row, const std::function<void(const std::string&)>& fail) {
    if (row.size() != static_cast<std::size_t>(d) && row.size() != static_cast<std::size_t>(d + 1))
      fail("expected " + std::to_string(d) + " coordinates, or " + std::to_string(d) + " and a volume, found " +
           std::to_string(row.size()) + " numbers");
    Vec3 x;
    for (int k = 0; k < d; ++k) x[k] = row[static_cast<std::size_t>(k)];
    at.push_back(x);
    if (row.size() == static_cast<std::size_t>(d + 1)) {
      if (!(row.back() > 0)) fail("a point's volume must be > 0, found " + fmt::format("{}", row.back()));
      volumes.push_back(row.back());
      ++with_volume;
    } else {
      volumes.push_back(0);
    }
  };
  if (item.node.IsMap()) {
    MapReader m(ctx, item, {"file"});
    const Item f = m.get("file", "a text file of points, one 'x y z [volume]' row per line");
    std::filesystem::path path = read_string(ctx, f);
    if (path.is_relative()) path = std::filesystem::path(ctx.file).parent_path() / path;
    std::ifstream in(path);
    if (!in) ctx.fail(f.mark, f.path + ": cannot open the points file '" + path.string() + "'");
    std::string line;
    int line_no = 0;
    while (std::getline(in, line)) {
      ++line_no;
      const auto first = line.find_first_not_of(" \t\r");
      if (first == std::string::npos || line[first] == '#') continue;
      std::istringstream row(line);
      std::vector<double> values;
      std::string word;
      while (row >> word) {
        char* end = nullptr;
        const double v = std::strtod(word.c_str(), &end);
        if (end == word.c_str() || *end != '\0' || !std::isfinite(v))
          ctx.fail(f.mark, fmt::format("{}: {}:{}: expected a number, found '{}'", f.path, path.string(), line_no, word));
        values.push_back(v);
      }
      add(values, [&](const std::string& msg) { ctx.fail(f.mark, fmt::format("{}: {}:{}: {}", f.path, path.string(), line_no, msg)); });
    }
    if (at.empty()) ctx.fail(f.mark, f.path + ": the points file '" + path.string() + "' holds no points");
  } else {
    if (!item.node.IsSequence()) fail_expected(ctx, item, "a list of points [x, y, z] or [x, y, z, volume], or {file: name}");
    const auto rows = read_list(ctx, item);
    if (rows.empty()) ctx.fail(item.mark, item.path + ": expected at least one point");
    for (const auto& r : rows) {
      if (!r.node.IsSequence()) fail_expected(ctx, r, "a point [x, y, z] or [x, y, z, volume]");
      std::vector<double> values;
      for (const auto& c : read_list(ctx, r)) values.push_back(read_number(ctx, c));
      add(values, [&](const std::string& msg) { ctx.fail(r.mark, r.path + ": " + msg); });
    }
  }
  if (with_volume != 0 && with_volume != at.size())
    ctx.fail(item.mark, item.path + ": give a volume with every point or with none");
  if (with_volume == 0) volumes.clear();
  return Shape::points(std::move(at), std::move(volumes));
}

std::vector<Shape> read_parts(const DeckContext& ctx, const Item& item, std::size_t at_least, const char* what) {
  if (!item.node.IsSequence()) fail_expected(ctx, item, std::string("a list of shapes (") + what + ")");
  const auto items = read_list(ctx, item);
  if (items.size() < at_least) {
    ctx.fail(item.mark, item.path + ": expected at least " + std::to_string(at_least) + " shapes (" + what +
                            "), found " + std::to_string(items.size()));
  }
  std::vector<Shape> parts;
  for (const auto& i : items) parts.push_back(read_shape(ctx, i));
  return parts;
}

// {surface: part.stl, scale: 0.001}: the solid inside a closed triangulated surface
// (geometry/surface.hpp), read through Gmsh; the file relative to the deck's folder.
Shape read_surface_shape(const DeckContext& ctx, const Item& item, const std::vector<Entry>& entries) {
  const Entry* file = nullptr;
  const Entry* scale = nullptr;
  for (const auto& e : entries) {
    if (e.key == "surface") file = &e;
    else if (e.key == "scale") scale = &e;
    else
      ctx.fail(*e.value.key_mark, item.path + ": a surface shape has the keys surface (the file) and scale; found '" +
                                      e.key + "'");
  }
  const YAML::Mark key_mark = *file->value.key_mark;
  if (ctx.dimension != 3) {
    ctx.fail(key_mark, file->value.path + ": a surface encloses a solid: it needs a 3-D deck (this one is " +
                           std::to_string(ctx.dimension) + "-D)");
  }
  std::filesystem::path path = read_string(ctx, file->value);
  if (path.is_relative()) path = std::filesystem::path(ctx.file).parent_path() / path;
  const double factor = scale ? read_positive(ctx, scale->value) : 1.0;
  try {
    return Shape::surface(std::make_shared<const ClosedSurface>(read_surface(path.lexically_normal().string(), factor)));
  } catch (const Error& e) {
    ctx.fail(key_mark, file->value.path + ": " + e.what());
  }
}

}  // namespace

std::optional<MeshSelection> read_mesh_selection(const DeckContext& ctx, const Item& item) {
  if (!item.node.IsDefined() || !item.node.IsMap() || item.node.size() != 1) return std::nullopt;
  const auto entries = map_entries(ctx, item);
  if (entries.front().key != "mesh") return std::nullopt;
  return select_mesh(ctx, entries.front().value, *entries.front().value.key_mark);
}

Shape read_shape(const DeckContext& ctx, const Item& item) {
  const std::string expected =
      "a shape: a map with one key, one of " + join_words(kShapeKinds) + " (e.g. {box: {min: [..], max: [..]}})";
  if (!item.node.IsDefined() || !item.node.IsMap() || item.node.size() == 0) fail_expected(ctx, item, expected);
  const auto entries = map_entries(ctx, item);
  for (const auto& e : entries)
    if (e.key == "surface") return read_surface_shape(ctx, item, entries);
  if (entries.size() > 1) {
    ctx.fail(*entries[1].value.key_mark, item.path + ": a shape has exactly one key naming its kind; found '" +
                                             entries[0].key + "' and '" + entries[1].key +
                                             "' (to combine shapes use union: [..] or subtract: [..])");
  }
  const Entry& e = entries.front();
  const YAML::Mark key_mark = *e.value.key_mark;
  if (e.key == "box") return read_box(ctx, e.value);
  if (e.key == "sphere") return read_sphere(ctx, e.value);
  if (e.key == "disk") return read_disk(ctx, e.value, key_mark);
  if (e.key == "cylinder") return read_cylinder(ctx, e.value, key_mark);
  if (e.key == "half_space") return read_half_space(ctx, e.value);
  if (e.key == "mesh") return read_mesh_shape(ctx, e.value, key_mark);

  if (e.key == "points") return read_points(ctx, e.value);
  if (e.key == "union") return Shape::union_of(read_parts(ctx, e.value, 1, "the shape is all of them together"));
  if (e.key == "subtract") {
    return Shape::difference(read_parts(ctx, e.value, 2, "the first shape minus all later ones"));
  }
  std::string message = e.value.path + ": unknown shape '" + e.key + "'";
  if (const auto guess = closest_word(e.key, kShapeKinds)) message += "; did you mean '" + *guess + "'?";
  message += "; shapes: " + join_words(kShapeKinds);
  ctx.fail(key_mark, message);
}

void check_bounded(const DeckContext& ctx, const Item& item, const Shape& shape) {
  constexpr double kUnbounded = 1e299;
  const Box3 b = shape.bounds();
  for (int k = 0; k < ctx.dimension; ++k) {
    if (std::abs(b.min[k]) >= kUnbounded || std::abs(b.max[k]) >= kUnbounded) {
      ctx.fail(item.mark, item.path + ": a body must be bounded, but this shape reaches to infinity along " +
                              kAxisNames[k] + " (a half_space is unbounded: subtract it from a box instead)");
    }
  }
}

}  // namespace horizon::deck
