#include "horizon/deck/deck.hpp"

#include "horizon/material/model.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "horizon/core/error.hpp"
#include "horizon/deck/conditions.hpp"
#include "horizon/deck/contact.hpp"
#include "horizon/deck/exodus_variables.hpp"
#include "horizon/deck/history_columns.hpp"
#include "horizon/deck/materials.hpp"
#include "horizon/deck/peridigm/function_string.hpp"
#include "horizon/deck/peridigm/peridigm.hpp"
#include "horizon/deck/peridigm/xml.hpp"
#include "horizon/deck/reader.hpp"
#include "horizon/deck/shapes.hpp"
#include "horizon/deck/thermal.hpp"

namespace horizon {

namespace {

using namespace deck;

const std::vector<std::string> kTopKeys = {
    "dimension",      "plane",           "thickness",          "area",      "spacing", "horizon",
    "horizon_factor", "lattice_origin",  "partial_volume",     "materials", "bodies",  "precracks",
    "regions",        "no_fail_regions", "initial_conditions", "loads",     "solver",  "output",
    "contact",        "thermal",
    "structure",      "bonds_between_bodies", "family_box"};

// A key that only makes sense in one dimension is an error in the others.
void only_in_dimension(const DeckContext& ctx, const MapReader& m, const char* key, int dimension) {
  if (ctx.dimension == dimension) return;
  if (auto item = m.find(key)) {
    ctx.fail(*item->key_mark, item->path + ": applies to " + std::to_string(dimension) +
                                  "-D decks only; this deck has dimension: " + std::to_string(ctx.dimension));
  }
}

// structure: {type: beam | plate | shell, supports: [{axis, at, kind}], cylinder_radius}
// (docs/input.md).
void read_structure(DeckContext& ctx, const MapReader& top, const Item& dim, Config& config) {
  const auto item = top.find("structure");
  if (!item) return;
  MapReader m(ctx, *item, {"type", "supports", "cylinder_radius"});
  const Item type = m.get("type", "beam (dimension 1), plate or shell (dimension 2)");
  StructureConfig& sc = config.structure;
  sc.kind = read_enum<StructureKind>(
      ctx, type, {{"beam", StructureKind::beam}, {"plate", StructureKind::plate}, {"shell", StructureKind::shell}});
  const int needed = sc.kind == StructureKind::beam ? 1 : 2;
  if (config.dimension != needed) {
    ctx.fail(type.mark, type.path + ": a " + type.node.Scalar() + " is a " + std::to_string(needed) +
                            "-D lattice of nodes in 3-D space; it needs dimension: " + std::to_string(needed) +
                            ", this deck has dimension: " + dim.node.Scalar());
  }
  if (auto p = top.find("plane")) {
    ctx.fail(*p->key_mark, p->path + ": applies to 2-D solids only; a " + type.node.Scalar() +
                               " has no plane mode (its bending and membrane laws are plane stress)");
  }
  config.plane = PlaneMode::stress;
  if (auto sup = m.find("supports")) {
    if (!sup->node.IsSequence()) fail_expected(ctx, *sup, "a list of supports, each {axis, at, kind}");
    for (const auto& i : read_list(ctx, *sup)) {
      MapReader s(ctx, i, {"axis", "at", "kind"});
      SupportConfig support;
      const std::vector<std::string> axes = {"x", "y"};
      const Item axis = s.get("axis", needed == 1 ? "x (the beam's axis)" : "x or y (the normal of the edge)");
      support.axis = static_cast<int>(choose_word(ctx, axis, std::vector<std::string>(axes.begin(), axes.begin() + needed)));
      support.at = read_number(ctx, s.get("at", "the coordinate of the support [m]"));
      support.kind = read_enum<SupportKind>(ctx, s.get("kind", "clamped or simply_supported"),
                                            {{"clamped", SupportKind::clamped},
                                             {"simply_supported", SupportKind::simply_supported}});
      for (const auto& other : sc.supports)
        if (other.axis == support.axis && other.at == support.at)
          ctx.fail(i.mark, i.path + ": a second support at the same place");
      sc.supports.push_back(support);
    }
  }
  if (auto r = m.find("cylinder_radius")) {
    if (sc.kind != StructureKind::shell)
      ctx.fail(*r->key_mark, r->path + ": a curved surface is a shell; this structure is a " + type.node.Scalar());
    sc.cylinder_radius = read_positive(ctx, *r);
    ctx.cylinder = true;
    if (!sc.supports.empty())
      ctx.fail(*r->key_mark, r->path + ": supports on a cylinder are not implemented; hold its nodes with "
                                       "displacement loads");
  }
  ctx.motion_components = 3;
  ctx.structure = true;
}

void read_lattice(DeckContext& ctx, const MapReader& m, Config& config) {
  const Item dim = m.get("dimension", "1, 2 or 3");
  config.dimension = static_cast<int>(choose_word(ctx, dim, {"1", "2", "3"})) + 1;
  ctx.dimension = config.dimension;
  read_structure(ctx, m, dim, config);

  only_in_dimension(ctx, m, "plane", 2);
  only_in_dimension(ctx, m, "thickness", 2);
  only_in_dimension(ctx, m, "area", 1);
  if (config.structure.kind != StructureKind::none) {
    if (auto t = m.find("thickness")) config.thickness = read_positive(ctx, *t);
  } else if (config.dimension == 2) {
    config.plane = read_enum<PlaneMode>(ctx, m.get("plane", "a 2-D deck is plane stress or plane strain"),
                                        {{"stress", PlaneMode::stress}, {"strain", PlaneMode::strain}});
    if (auto t = m.find("thickness")) config.thickness = read_positive(ctx, *t);
  }
  ctx.plane = config.plane;
  ctx.thickness = config.thickness;
  if (auto a = m.find("area"); a && config.dimension == 1) config.area = read_positive(ctx, *a);

  const Item spacing = m.get("spacing", "the lattice spacing [m], > 0");
  config.spacing = read_positive(ctx, spacing);

  const std::string which = *m.exactly_one({"horizon", "horizon_factor"}, true);
  const Item h = *m.find(which);
  if (which == "horizon") {
    config.horizon = read_positive(ctx, h);
    if (config.horizon < config.spacing * (1 - 1e-12)) {
      ctx.fail(h.mark, "horizon: expected a horizon of at least one spacing (" + text_of(spacing) + "), found " +
                           text_of(h) + "; a smaller horizon leaves the particles without bonds");
    }
  } else {
    const double factor = read_positive(ctx, h);
    if (factor < 1 - 1e-12) {
      ctx.fail(h.mark, "horizon_factor: expected at least 1 (the horizon in lattice spacings), found " + text_of(h) +
                           "; a smaller horizon leaves the particles without bonds");
    }
    config.horizon = factor * config.spacing;
  }
  const double ratio = config.horizon / config.spacing;
  if (ratio < 3 * (1 - 1e-9)) {
    ctx.warn(h.mark, fmt::format("{}: the horizon is only {:.3g} lattice spacings; 3 or more are usual (with fewer, "
                                 "crack paths and wave speeds follow the lattice)",
                                 which, ratio));
  }

  if (auto o = m.find("lattice_origin")) config.lattice_origin = read_vector(ctx, *o);
  if (auto p = m.find("partial_volume")) config.partial_volume = read_partial_volume(ctx, *p);
}

void read_materials(const DeckContext& ctx, const MapReader& m, Config& config) {
  const Item item = m.get("materials", "a map from material name to its properties");
  const auto entries = map_entries(ctx, item);
  if (entries.empty()) {
    ctx.fail(item.mark, "materials: expected at least one material, e.g. materials: {glass: {model: pmb, ...}}");
  }
  for (const auto& e : entries) config.materials.push_back(read_material(ctx, e.key, e.value));
  for (auto& mat : config.materials) derive_from_micromodulus(mat, config);
  // A model that owns the force pass (ModelTraits::exclusive, material/model.hpp) shares a
  // run only with materials of its own model.
  for (std::size_t q = 1; q < entries.size(); ++q) {
    const ModelTraits& a = find_model(config.materials[0].model)->traits;
    const ModelTraits& b = find_model(config.materials[q].model)->traits;
    if ((a.exclusive || b.exclusive) && a.name != b.name) {
      const ModelTraits& excl = a.exclusive ? a : b;
      const Item model = entries[q].value.node["model"] ? Item{entries[q].value.node["model"],
                                                               child_path(entries[q].value.path, "model"),
                                                               entries[q].value.node["model"].Mark(), std::nullopt}
                                                        : entries[q].value;
      ctx.fail(model.mark, model.path + ": model " + b.name + " cannot share a run with material '" +
                               config.materials[0].name + "' (model " + a.name + "): bodies of model " + excl.name +
                               " interact only with " + excl.name + " bodies; use model " + excl.name +
                               " for every material (e.g. with fracture: false for a projectile)");
    }
  }
  // A thin structure takes a structural model (ModelTraits::structural), and a structural
  // model needs a structure.
  for (std::size_t q = 0; q < entries.size(); ++q) {
    const ModelTraits& t = find_model(config.materials[q].model)->traits;
    const Item& e = entries[q].value;
    const Item model = e.node["model"] ? Item{e.node["model"], child_path(e.path, "model"), e.node["model"].Mark(),
                                              std::nullopt}
                                       : e;
    const bool structure = config.structure.kind != StructureKind::none;
    if (structure && !t.structural) {
      std::string which;
      for (const auto& r : model_registry())
        if (r.traits.structural) which += (which.empty() ? "" : ", ") + r.traits.name;
      ctx.fail(model.mark, model.path + ": model " + t.name + " is a solid; the nodes of a structure (beam, plate, "
                                        "shell) take model " + which);
    }
    if (!structure && t.structural) {
      ctx.fail(model.mark, model.path + ": model " + t.name + " models beams, plates and shells; give structure: "
                                        "{type: beam | plate | shell} (docs/input.md)");
    }
  }
  // One breaking order for the whole run: the force pass applies it to every bond.
  const MaterialConfig* first_damaged = nullptr;
  for (std::size_t q = 0; q < entries.size(); ++q) {
    const MaterialConfig& mat = config.materials[q];
    if (!mat.damage.enabled) continue;
    if (!first_damaged) {
      first_damaged = &mat;
    } else if (mat.damage.break_after_force != first_damaged->damage.break_after_force) {
      ctx.fail(entries[q].value.mark, entries[q].value.path + ": damage.breaks differs from material '" +
                                          first_damaged->name +
                                          "'; the breaking order (before_force or after_force) is one for the whole run");
    }
  }
}

std::vector<std::string> read_regions(const DeckContext& ctx, const MapReader& m, Config& config) {
  std::vector<std::string> names;
  const auto item = m.find("regions");
  if (!item) return names;
  for (const auto& e : map_entries(ctx, *item)) {
    if (e.key == "all") {
      ctx.fail(*e.value.key_mark, e.value.path + ": 'all' is reserved (it means every particle); choose another name");
    }
    config.regions.emplace(e.key, read_shape(ctx, e.value));
    names.push_back(e.key);
  }
  return names;
}

// A finite-element body made of a mesh's elements (fe/fe_region.hpp): all hex8 or all
// tet4, none inverted (the Jacobian at every corner of a hexahedron, the signed volume of
// a tetrahedron, > 0 with the mesh's node order: Gmsh reference manual sec. 10.2 and the
// Exodus II manual share it); `element`, when given, names that type.
void read_fe_mesh(const DeckContext& ctx, const MeshSelection& sel, const MapReader& b, BodyConfig& body) {
  const Mesh& mesh = *sel.mesh;
  if (sel.set)
    ctx.fail(sel.mark, sel.path + ": a finite-element body takes a block of the mesh " + sel.file +
                           " (or all of it), not a set: sets select regions");
  auto name = [](CellType t) -> std::string {
    return t == CellType::hex8 ? "hex8" : t == CellType::tet4 ? "tet4" : cell_type_name(t);
  };
  if (sel.cells.empty()) ctx.fail(sel.mark, sel.path + ": the block of the mesh " + sel.file + " holds no element");
  const CellType type = mesh.cell_type[sel.cells.front()];
  for (uint32_t e : sel.cells) {
    const CellType t = mesh.cell_type[e];
    if (t != CellType::hex8 && t != CellType::tet4)
      ctx.fail(sel.mark, fmt::format("{}: element {} of the mesh {} is a {}; finite-element bodies take 8-node "
                                     "hexahedra (hex8) and 4-node tetrahedra (tet4) only",
                                     sel.path, e + 1, sel.file, name(t)));
    if (t != type)
      ctx.fail(sel.mark, fmt::format("{}: the mesh {} mixes {} and {} elements; a deck's finite elements are of one "
                                     "type (choose one block with block:)",
                                     sel.path, sel.file, name(type), name(t)));
  }
  const FeElement element = type == CellType::hex8 ? FeElement::hex8 : FeElement::tet4;
  if (auto e = b.find("element"); e && body.element != element)
    ctx.fail(e->mark, fmt::format("{}: the mesh {} holds {} elements; leave element out or write element: {}", e->path,
                                  sel.file, name(type), name(type)));
  if (auto hg = b.find("hourglass"); hg && element != FeElement::hex8)
    ctx.fail(*hg->key_mark, hg->path + ": hourglass control applies to hex8 elements only (the mesh " + sel.file +
                                 " holds tetrahedra)");
  body.element = element;
  // Inverted elements: a corner whose edges form a left-handed triple (hex8: each corner's
  // three edges in the parent cube's axis order; tet4: corner 0).
  static constexpr int kHexCorner[8][4] = {{0, 1, 3, 4}, {1, 0, 5, 2}, {2, 3, 1, 6}, {3, 2, 7, 0},
                                           {4, 5, 0, 7}, {5, 4, 6, 1}, {6, 7, 2, 5}, {7, 6, 4, 3}};
  for (uint32_t e : sel.cells) {
    const auto& c = mesh.cell_nodes[e];
    auto triple = [&](int o, int a, int bb, int d) {
      const Vec3& x0 = mesh.nodes[c[static_cast<std::size_t>(o)]];
      return dot(mesh.nodes[c[static_cast<std::size_t>(a)]] - x0,
                 cross(mesh.nodes[c[static_cast<std::size_t>(bb)]] - x0, mesh.nodes[c[static_cast<std::size_t>(d)]] - x0));
    };
    bool bad = false;
    if (type == CellType::tet4) {
      bad = !(triple(0, 1, 2, 3) > 0);
    } else {
      for (const auto& k : kHexCorner) bad = bad || !(triple(k[0], k[1], k[2], k[3]) > 0);
    }
    if (bad)
      ctx.fail(sel.mark, fmt::format("{}: element {} ({}) of the mesh {} is inverted or degenerate (a corner with a "
                                     "non-positive Jacobian: its nodes are not in the {} order)",
                                     sel.path, e + 1, name(type), sel.file,
                                     type == CellType::hex8 ? "Gmsh/Exodus hexahedron" : "Gmsh/Exodus tetrahedron"));
  }
  body.fe_mesh = sel.mesh;
  body.fe_cells = sel.cells;
  body.fe_mesh_scale = sel.scale;
}

// A body's own horizon (BodyConfig::horizon): a number in (0, deck horizon], or an
// expression in x, y, z checked at each particle when the system is built.
void read_body_horizon(const DeckContext& ctx, const Item& h, const Config& config, BodyConfig& body) {
  if (body.discretization == Discretization::fe)
    ctx.fail(*h.key_mark, h.path + ": applies to peridynamic bodies only");
  const Expression e = read_scalar_expr(ctx, h);
  if (e.is_constant()) {
    const double v = e(0);
    if (!(v > 0)) ctx.fail(h.mark, h.path + ": expected a horizon > 0, found " + text_of(h));
    if (v > config.horizon * (1 + 1e-12))
      ctx.fail(h.mark, fmt::format("{}: {} is larger than the deck's horizon {}, which bounds every body's (the "
                                   "families are searched within it); set horizon: {} at the top",
                                   h.path, text_of(h), config.horizon, text_of(h)));
  }
  body.horizon = e;
}

void read_bodies(const DeckContext& ctx, const MapReader& m, Config& config) {
  const Item item = m.get("bodies", "a list of bodies, each {name, material, shape}");
  if (!item.node.IsSequence()) fail_expected(ctx, item, "a list of bodies (lines starting with '- ')");
  const auto items = read_list(ctx, item);
  if (items.empty()) ctx.fail(item.mark, "bodies: expected at least one body");
  std::vector<std::string> materials;
  for (const auto& mat : config.materials) materials.push_back(mat.name);
  for (std::size_t i = 0; i < items.size(); ++i) {
    MapReader b(ctx, items[i],
                {"name", "material", "shape", "discretization", "element", "hourglass", "j2", "element_size", "horizon"});
    BodyConfig body;
    body.name = "body" + std::to_string(i + 1);
    if (auto n = b.find("name")) {
      body.name = read_string(ctx, *n);
      for (const auto& other : config.bodies) {
        if (other.name == body.name) ctx.fail(n->mark, n->path + ": two bodies are named '" + body.name + "'");
      }
    }
    const Item mat = b.get("material", "the name of one of the materials");
    body.material = read_string(ctx, mat);
    check_reference(ctx, mat, body.material, materials, "material");
    const Item shape = b.get("shape", "e.g. {box: {min: [..], max: [..]}}");
    body.shape = read_shape(ctx, shape);
    check_bounded(ctx, shape, body.shape);
    if (body.shape.kind() == Shape::Kind::points && body.shape.point_volumes().empty()) {
      ctx.fail(shape.mark, shape.path +
                               ": a body made of listed points needs a volume with each point ([x, y, z, volume]); "
                               "a mesh's set: selects a region and belongs under regions");
    }
    // Finite-element bodies (fe/fe_region.hpp; docs/input.md, "Finite-element bodies").
    if (auto d = b.find("discretization"))
      body.discretization = read_enum<Discretization>(ctx, *d, {{"peridynamic", Discretization::peridynamic},
                                                                {"fe", Discretization::fe}});
    const bool fe = body.discretization == Discretization::fe;
    for (const char* key : {"element", "hourglass", "j2", "element_size"})
      if (auto k = b.find(key); k && !fe)
        ctx.fail(*k->key_mark, k->path + ": applies to finite-element bodies only (discretization: fe)");
    if (auto e = b.find("element"))
      body.element = read_enum<FeElement>(ctx, *e, {{"hex8", FeElement::hex8}, {"tet4", FeElement::tet4}});
    if (auto hg = b.find("hourglass")) {
      if (body.element != FeElement::hex8)
        ctx.fail(*hg->key_mark, hg->path + ": hourglass control applies to hex8 elements only");
      body.hourglass = read_non_negative(ctx, *hg);
      if (body.hourglass > 1) ctx.fail(hg->mark, hg->path + ": expected a coefficient in [0, 1] (typically 0.05 to 0.15)");
    }
    if (auto j = b.find("j2")) {
      // J2 plasticity of the elements (classical/strain_laws.hpp, small strain).
      MapReader jm(ctx, *j, {"yield_stress", "hardening_modulus"});
      body.fe_yield_stress = read_positive(ctx, jm.get("yield_stress", "the initial yield stress sigma_y [Pa]"));
      if (auto hm = jm.find("hardening_modulus")) body.fe_hardening_modulus = read_non_negative(ctx, *hm);
    }
    if (auto es = b.find("element_size")) {
      body.fe_element_size = read_int(ctx, *es);
      if (body.fe_element_size < 1 || body.fe_element_size > 16)
        ctx.fail(es->mark, es->path + ": expected a whole number of spacings from 1 to 16 (the elements' edge: nodes "
                                      "on every n-th lattice point)");
    }
    if (fe) {
      if (auto sel = read_mesh_selection(ctx, shape)) {
        if (auto es = b.find("element_size"))
          ctx.fail(*es->key_mark, es->path + ": applies to box finite-element bodies only (a mesh body's elements "
                                             "are the mesh's)");
        read_fe_mesh(ctx, *sel, b, body);
      } else if (body.shape.kind() != Shape::Kind::box) {
        ctx.fail(shape.mark, shape.path + ": a finite-element body's shape is a box (its elements fill the box on the "
                                          "lattice's grid) or a mesh ({mesh: {file, block}}: its hex8 or tet4 elements)");
      }
    }
    if (fe && ctx.dimension != 3)
      ctx.fail(b.find("discretization")->mark, "discretization: fe needs a 3-D deck (dimension: 3)");
    if (auto h = b.find("horizon")) read_body_horizon(ctx, *h, config, body);
    config.bodies.push_back(std::move(body));
  }
}

// A solver key that applies to some solver types only is an error in the others.
void only_for(const DeckContext& ctx, const MapReader& m, const char* key, bool applies, const char* which,
              const std::string& type) {
  if (applies) return;
  if (auto item = m.find(key)) {
    ctx.fail(*item->key_mark, item->path + ": applies to " + which + " only; this deck has type: " + type);
  }
}

const std::vector<std::string> kSolverKeys = {
    "type", "end_time", "time_step", "safety_factor", "damping", "method", "linear_solver", "tangent",
    "tolerance", "max_iterations", "load_steps", "max_step_cuts", "max_break_rounds", "condition_number",
    "adaptive_time_step", "adaptive_every", "energy_balance_warning", "backend", "initial_acceleration",
    "on_failure", "verlet", "positions", "load_times", "solver_starts"};

// solver.load_times: the pseudo-times of a static run's load steps, from 0, increasing
// (docs/input.md "Static solves"). They replace load_steps and end_time.
void read_load_times(const DeckContext& ctx, const MapReader& s, SolverConfig& sc) {
  const auto item = s.find("load_times");
  if (!item) return;
  for (const char* other : {"load_steps", "end_time"})
    if (auto o = s.find(other))
      ctx.fail(*o->key_mark, fmt::format("{}: give load_times or {}, not both (load_times sets the load steps and "
                                         "the end time: its last value)", o->path, other));
  if (!item->node.IsSequence())
    fail_expected(ctx, *item, "a list of pseudo-times from 0, increasing (e.g. [0, 0.1, 0.5, 1.0])");
  const std::vector<Item> times = read_list(ctx, *item);
  if (times.size() < 2)
    fail_expected(ctx, *item, "at least two pseudo-times (the start, 0, and the end of the first load step)");
  for (std::size_t k = 0; k < times.size(); ++k) {
    const double t = read_number(ctx, times[k]);
    if (k == 0 && t != 0) fail_expected(ctx, times[k], "0 (the load path starts at pseudo-time 0)");
    if (k > 0 && !(t > sc.load_times.back()))
      ctx.fail(times[k].mark, fmt::format("{}: expected a pseudo-time after the one before it ({}), found {}",
                                          times[k].path, sc.load_times.back(), text_of(times[k])));
    sc.load_times.push_back(t);
  }
  sc.load_steps = static_cast<int>(sc.load_times.size()) - 1;
  sc.end_time = sc.load_times.back();
}

// solver.solver_starts: pseudo-times where a Peridigm solver list starts again (a deck's
// Solver2 after its Solver1; docs/peridigm.md), each the end of a load step before the last.
void read_solver_starts(const DeckContext& ctx, const MapReader& s, SolverConfig& sc) {
  const auto item = s.find("solver_starts");
  if (!item) return;
  const int n = std::max(1, sc.load_steps);
  for (const Item& v : read_list(ctx, *item)) {
    const double t = read_number(ctx, v);
    bool step = false;
    if (!sc.load_times.empty()) {
      for (std::size_t k = 1; k + 1 < sc.load_times.size(); ++k) step = step || sc.load_times[k] == t;
    } else {
      const double h = sc.end_time / n, k = std::round(t / h);
      step = k >= 1 && k <= n - 1 && std::abs(t - k * h) <= 1e-12 * sc.end_time;
    }
    if (!step)
      ctx.fail(v.mark, fmt::format("{}: expected the end of a load step before the last (a pseudo-time of "
                                   "load_times, or end_time k / load_steps), found {}", v.path, text_of(v)));
    if (!sc.solver_starts.empty() && !(t > sc.solver_starts.back()))
      ctx.fail(v.mark, fmt::format("{}: expected a pseudo-time after the one before it ({})", v.path,
                                   sc.solver_starts.back()));
    sc.solver_starts.push_back(t);
  }
}

// One solver map (the deck's `solver`, or one stage of a staged deck) into `sc`.
void read_solver_map(const DeckContext& ctx, const Item& item, const Config& config, SolverConfig& sc) {
  MapReader s(ctx, item, kSolverKeys);
  std::string type = "explicit";
  if (auto t = s.find("type")) {
    sc.type = read_enum<SolverType>(ctx, *t,
                                    {{"explicit", SolverType::explicit_dynamic},
                                     {"static", SolverType::static_equilibrium},
                                     {"implicit_dynamic", SolverType::implicit_dynamic},
                                     {"heat", SolverType::heat}});
    type = t->node.Scalar();
  }
  const bool is_explicit = sc.type == SolverType::explicit_dynamic;
  const bool is_static = sc.type == SolverType::static_equilibrium;
  const bool is_heat = sc.type == SolverType::heat;
  const char* kStatic = "type: static";
  const char* kImplicit = "type: static and implicit_dynamic";
  only_for(ctx, s, "safety_factor", is_explicit || is_heat, "type: explicit and heat", type);
  only_for(ctx, s, "time_step", !is_static, "type: explicit, implicit_dynamic and heat", type);
  only_for(ctx, s, "damping", !is_static && !is_heat, "type: explicit and implicit_dynamic", type);
  only_for(ctx, s, "method", is_static, kStatic, type);
  only_for(ctx, s, "load_steps", is_static, kStatic, type);
  only_for(ctx, s, "load_times", is_static, kStatic, type);
  only_for(ctx, s, "solver_starts", is_static, kStatic, type);
  only_for(ctx, s, "max_step_cuts", is_static, kStatic, type);
  only_for(ctx, s, "on_failure", is_static, kStatic, type);
  if (auto f = s.find("on_failure"))
    sc.switch_on_failure = read_enum<bool>(ctx, *f, {{"stop", false}, {"explicit", true}});
  only_for(ctx, s, "positions", is_static, kStatic, type);
  if (auto p = s.find("positions"))
    sc.peridigm_positions = read_enum<bool>(ctx, *p, {{"horizon", false}, {"peridigm", true}});
  only_for(ctx, s, "verlet", is_explicit, "type: explicit", type);
  if (auto v = s.find("verlet")) {
    sc.peridigm_verlet = read_enum<bool>(ctx, *v, {{"horizon", false}, {"peridigm", true}});
    if (sc.peridigm_verlet && s.has("damping"))
      ctx.fail(*s.find("damping")->key_mark, s.find("damping")->path + ": verlet: peridigm has no damping (Peridigm's Verlet has none)");
  }
  only_for(ctx, s, "initial_acceleration", sc.type == SolverType::implicit_dynamic, "type: implicit_dynamic", type);
  if (auto a = s.find("initial_acceleration"))
    sc.zero_initial_acceleration = read_enum<bool>(ctx, *a, {{"equilibrium", false}, {"zero", true}});
  for (const char* key : {"linear_solver", "tangent", "tolerance", "max_iterations", "max_break_rounds",
                          "condition_number"})
    only_for(ctx, s, key, !is_explicit && !is_heat, kImplicit, type);

  if (is_static) {
    // The pseudo-time of a static run: loads are evaluated at t = end_time * k / load_steps.
    sc.end_time = 1.0;
    if (auto e = s.find("end_time")) sc.end_time = read_positive(ctx, *e);
  } else {
    sc.end_time = read_positive(ctx, s.get("end_time", "the simulated time [s], > 0"));
  }
  if (sc.type == SolverType::implicit_dynamic) {
    sc.time_step = read_positive(ctx, s.get("time_step", "the fixed time step of the implicit solver [s], > 0"));
  } else if (auto dt = s.find("time_step")) {
    sc.time_step = read_positive(ctx, *dt);
  }
  if (auto f = s.find("safety_factor")) {
    const double v = read_number(ctx, *f);
    if (!(v > 0 && v <= 1)) {
      ctx.fail(f->mark,
               f->path + ": expected a number in (0, 1] (a fraction of the stable time step), found " + text_of(*f));
    }
    sc.safety_factor = v;
  }
  if (auto d = s.find("damping")) sc.damping = read_non_negative(ctx, *d);
  if (auto w = s.find("energy_balance_warning")) sc.energy_balance_warning = read_positive(ctx, *w);

  if (auto me = s.find("method")) {
    sc.method = read_enum<StaticMethod>(ctx, *me, {{"newton", StaticMethod::newton}, {"adr", StaticMethod::adr}});
  }
  const bool newton = !is_static || sc.method == StaticMethod::newton;
  only_for(ctx, s, "linear_solver", newton, "method: newton", "static with method: adr");
  only_for(ctx, s, "tangent", newton, "method: newton", "static with method: adr");
  if (auto l = s.find("linear_solver")) {
    sc.linear_solver = read_enum<LinearSolverKind>(ctx, *l,
                                                   {{"cg", LinearSolverKind::cg},
                                                    {"cholesky", LinearSolverKind::cholesky},
                                                    {"matrix_free", LinearSolverKind::matrix_free}});
  }
  if (auto tg = s.find("tangent")) {
    sc.tangent = read_enum<TangentKind>(
        ctx, *tg, {{"analytic", TangentKind::analytic}, {"finite_difference", TangentKind::finite_difference}});
    if (sc.tangent == TangentKind::finite_difference && sc.linear_solver == LinearSolverKind::matrix_free) {
      ctx.fail(tg->mark, tg->path + ": the finite-difference tangent is assembled; use linear_solver: cg or "
                                    "cholesky with it (matrix_free uses the analytic tangent)");
    }
  }
  if (auto tol = s.find("tolerance")) {
    const double v = read_number(ctx, *tol);
    if (!(v > 0 && v < 1)) {
      ctx.fail(tol->mark, tol->path + ": expected a number in (0, 1) (the residual norm relative to the applied "
                                      "load at convergence), found " + text_of(*tol));
    }
    sc.tolerance = v;
  }
  auto at_least = [&](const Item& i, int low) {
    const int v = read_int(ctx, i);
    if (v < low) fail_expected(ctx, i, "a whole number >= " + std::to_string(low));
    return v;
  };
  if (auto it = s.find("max_iterations")) sc.max_iterations = at_least(*it, 1);
  if (auto ls = s.find("load_steps")) sc.load_steps = at_least(*ls, 1);
  read_load_times(ctx, s, sc);
  read_solver_starts(ctx, s, sc);
  if (auto mc = s.find("max_step_cuts")) sc.max_step_cuts = at_least(*mc, 0);
  if (auto mb = s.find("max_break_rounds")) sc.max_break_rounds = at_least(*mb, 1);
  if (auto cn = s.find("condition_number")) sc.condition_number = read_bool(ctx, *cn);
  only_for(ctx, s, "adaptive_time_step", is_explicit, "type: explicit", type);
  only_for(ctx, s, "adaptive_every", is_explicit, "type: explicit", type);
  if (auto a = s.find("adaptive_time_step")) {
    sc.adaptive_time_step = read_bool(ctx, *a);
    bool nonlinear = !config.materials.empty();
    for (const auto& mat : config.materials) nonlinear = nonlinear && find_model(mat.model)->traits.adaptive_time_step;
    if (sc.adaptive_time_step && !nonlinear) {
      ctx.fail(a->mark, a->path + ": the adaptive time step follows the current stiffness of the models "
                                  "nonlinear_solid, correspondence and extended_correspondence; the other models keep the step "
                                  "fixed at the start");
    }
    if (sc.adaptive_time_step && sc.time_step) {
      ctx.fail(a->mark, a->path + ": give either time_step (fixed) or adaptive_time_step: true, not both");
    }
  }
  // The explicit backend (solver/backend.hpp): which runs it takes is known once the
  // system is built (driver/backends.cpp refuses the others, naming this key).
  only_for(ctx, s, "backend", is_explicit, "type: explicit", type);
  if (auto b = s.find("backend")) {
    const std::vector<std::string> names = {"cpu", "flat", "cuda"};
    sc.backend = names[choose_word(ctx, *b, names)];
    sc.backend_at = fmt::format("{}:{}:{}", ctx.file, b->mark.line + 1, b->mark.column + 1);
    if (sc.peridigm_verlet && sc.backend != "cpu")
      ctx.fail(b->mark, b->path + ": verlet: peridigm runs on backend: cpu only (the solver's own passes)");
  }
  if (auto a = s.find("adaptive_every")) {
    sc.adaptive_every = at_least(*a, 1);
    if (!sc.adaptive_time_step) {
      ctx.fail(*a->key_mark, a->path + ": applies with adaptive_time_step: true only");
    }
  }
}

// `solver`: one solver map, or a list of stages run in turn (docs/input.md "Solver
// stages"): a static solve, then an explicit run that starts from its last equilibrium
// at the static end_time (Peridigm's QuasiStatic solver followed by Verlet).
void read_solver(const DeckContext& ctx, const MapReader& m, Config& config) {
  const Item solver = m.get("solver", "at least {end_time: ...}");
  if (!solver.node.IsSequence()) {
    read_solver_map(ctx, solver, config, config.solver);
    if (config.solver.switch_on_failure) {
      const Item f = *MapReader(ctx, solver, kSolverKeys).find("on_failure");
      ctx.fail(f.mark, f.path + ": explicit applies to the static stage of a staged run (solver: a list of a "
                                "static stage and an explicit one), which it starts early");
    }
    return;
  }
  const std::vector<Item> stages = read_list(ctx, solver);
  if (stages.size() != 2)
    fail_expected(ctx, solver, "a map (one solver) or a list of two stages (a static solve, then an explicit run "
                               "from its state)");
  SolverConfig first;
  read_solver_map(ctx, stages[0], config, first);
  if (!first.solver_starts.empty())
    ctx.fail(*MapReader(ctx, stages[0], kSolverKeys).find("solver_starts")->key_mark,
             stages[0].path + ".solver_starts: not in a staged run's static stage (a static run's Exodus files only)");
  read_solver_map(ctx, stages[1], config, config.solver);
  auto type_mark = [&](const Item& stage) {
    const auto t = MapReader(ctx, stage, kSolverKeys).find("type");
    return t ? t->mark : stage.mark;
  };
  if (first.type != SolverType::static_equilibrium)
    ctx.fail(type_mark(stages[0]), stages[0].path + ": the first stage must be type: static (Horizon stages a "
                                                    "static solve followed by an explicit run)");
  if (config.solver.type != SolverType::explicit_dynamic)
    ctx.fail(type_mark(stages[1]), stages[1].path + ": the second stage must be type: explicit (Horizon stages a "
                                                    "static solve followed by an explicit run)");
  if (config.solver.adaptive_time_step)
    ctx.fail(stages[1].mark, stages[1].path + ": adaptive_time_step is not available in a staged run");
  // With on_failure: explicit the explicit stage may end where the static one does: it
  // runs only when an increment fails, from there (Peridigm's Switch to Verlet).
  if (!(config.solver.end_time > first.end_time) &&
      !(first.switch_on_failure && config.solver.end_time >= first.end_time)) {
    const Item e = *MapReader(ctx, stages[1], kSolverKeys).find("end_time");
    ctx.fail(e.mark, fmt::format("{}: expected a time after the static stage's end_time {} (the explicit stage "
                                 "runs from there)", e.path, first.end_time));
  }
  config.solver.start_time = first.end_time;
  config.static_stage = first;
}

// What a static stage cannot take (the static solver's limits: solver/static_driver.hpp),
// an error at the stage list.
void check_stages(const DeckContext& ctx, const MapReader& m, const Config& config) {
  if (!config.static_stage) return;
  const Item solver = *m.find("solver");
  auto refuse = [&](const std::string& what) {
    ctx.fail(solver.mark, solver.path + ": a staged run (static, then explicit) cannot have " + what +
                              ": the static stage has no such forces");
  };
  if (config.contact.short_range.enabled || !config.contact.indenters.empty() ||
      !config.contact.projectiles.empty())
    refuse("contact (short-range, indenters or projectiles)");
  if (config.thermal.enabled) refuse("a thermal section");
  for (const auto& b : config.bodies)
    if (b.discretization == Discretization::fe) refuse("finite-element bodies");
  if (config.structure.kind != StructureKind::none) refuse("a structure (beam, plate)");
}

void read_output(const DeckContext& ctx, const MapReader& m, Config& config) {
  const auto item = m.find("output");
  if (!item) return;
  MapReader o(ctx, *item, {"directory", "frames", "history_every", "progress_every", "damage_measure", "checkpoint",
                           "format", "exodus_file", "exodus_files", "history_columns"});
  if (auto f = o.find("format")) {
    config.output.format = read_enum<OutputConfig::Format>(
        ctx, *f, {{"vtu", OutputConfig::Format::vtu}, {"exodus", OutputConfig::Format::exodus}, {"both", OutputConfig::Format::both}});
  }
  if (auto e = o.find("exodus_file")) {
    if (!config.output.writes_exodus())
      ctx.fail(*e->key_mark, e->path + ": applies with format: exodus or both only");
    config.output.exodus_file = read_string(ctx, *e);
    if (config.output.exodus_file.empty() || config.output.exodus_file.find('/') != std::string::npos)
      fail_expected(ctx, *e, "a file name (inside output.directory)");
  }
  if (auto h = o.find("history_columns")) config.output.history_columns = read_history_columns(ctx, *h, config);
  if (auto files = o.find("exodus_files")) {
    if (!files->node.IsSequence() || files->node.size() == 0)
      fail_expected(ctx, *files, "a list of {file: NAME.e, every: N}");
    for (std::size_t k = 0; k < files->node.size(); ++k) {
      const Item entry{files->node[k], index_path(files->path, k), files->node[k].Mark(), std::nullopt};
      MapReader e(ctx, entry, {"file", "every", "variables", "velocity", "first_step", "last_step", "explicit_every"});
      OutputConfig::ExodusFile f;
      const Item name = e.get("file", "the Exodus file's name, inside output.directory");
      f.file = read_string(ctx, name);
      if (f.file.empty() || f.file.find('/') != std::string::npos)
        fail_expected(ctx, name, "a file name (inside output.directory)");
      for (const auto& other : config.output.exodus_files)
        if (other.file == f.file) ctx.fail(name.mark, name.path + ": the file '" + f.file + "' is named twice");
      if (config.output.writes_exodus() && f.file == config.output.exodus_file)
        ctx.fail(name.mark, name.path + ": '" + f.file + "' is already output.exodus_file");
      if (auto ev = e.find("every")) {
        f.every = read_int(ctx, *ev);
        if (f.every < 1) fail_expected(ctx, *ev, "a whole number >= 1");
      }
      if (auto ee = e.find("explicit_every")) {
        if (!config.static_stage)
          ctx.fail(*ee->key_mark, ee->path + ": applies to staged runs (solver: a static and an explicit stage) only");
        f.explicit_every = read_int(ctx, *ee);
        if (f.explicit_every < 1) fail_expected(ctx, *ee, "a whole number >= 1");
      }
      if (auto fs = e.find("first_step")) {
        f.first_step = read_int(ctx, *fs);
        if (f.first_step < 0) fail_expected(ctx, *fs, "a step number >= 0");
      }
      if (auto ls = e.find("last_step")) {
        f.last_step = read_int(ctx, *ls);
        if (f.last_step < f.first_step)
          fail_expected(ctx, *ls, "a step number >= first_step (" + std::to_string(f.first_step) + ")");
      }
      if (auto vars = e.find("variables")) {
        // Lambda, Deformation_Gradient, Contact_Force_Density, Horizon, a model field
        // variable or a history column (driver/exodus_output.hpp).
        std::vector<std::string> known = {"Lambda", "Deformation_Gradient", "Contact_Force_Density", "Horizon",
                                          "Flux_Divergence"};
        for (const auto& m : model_field_variables()) known.push_back(m);
        for (const auto& c : config.output.history_columns) known.push_back(c.name);
        if (!vars->node.IsSequence()) fail_expected(ctx, *vars, "a list of variable names");
        for (std::size_t v = 0; v < vars->node.size(); ++v) {
          const Item var{vars->node[v], index_path(vars->path, v), vars->node[v].Mark(), std::nullopt};
          const std::string name = read_string(ctx, var);
          if (std::find(known.begin(), known.end(), name) == known.end()) {
            std::string list;
            for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
            ctx.fail(var.mark, var.path + ": unknown variable '" + name + "'; known: " + list +
                                   " (the last ones: output.history_columns)");
          }
          if (std::find(f.variables.begin(), f.variables.end(), name) != f.variables.end())
            ctx.fail(var.mark, var.path + ": '" + name + "' is named twice");
          if (name == "Flux_Divergence" && !(config.thermal.enabled && config.thermal.conduction))
            ctx.fail(var.mark, var.path + ": Flux_Divergence is the heat conduction's; the deck needs a conducting "
                                          "thermal section");
          f.variables.push_back(name);
        }
      }
      if (auto vel = e.find("velocity")) {
        f.verlet_velocity = read_enum<bool>(ctx, *vel, {{"state", false}, {"verlet", true}});
        if (f.verlet_velocity && config.solver.type != SolverType::explicit_dynamic)
          ctx.fail(vel->mark, vel->path + ": verlet applies to explicit runs (solver.type explicit) only");
      }
      config.output.exodus_files.push_back(f);
    }
  }
  if (auto d = o.find("damage_measure")) {
    config.output.damage_measure =
        read_enum<DamageMeasure>(ctx, *d, {{"weighted", DamageMeasure::weighted}, {"volume", DamageMeasure::volume}});
  }
  auto at_least = [&](const Item& i, int low) {
    const int v = read_int(ctx, i);
    if (v < low) fail_expected(ctx, i, "a whole number >= " + std::to_string(low));
    return v;
  };
  if (auto d = o.find("directory")) {
    config.output.directory = read_string(ctx, *d);
    if (config.output.directory.empty()) fail_expected(ctx, *d, "a directory name");
  }
  if (auto f = o.find("frames")) config.output.frames = at_least(*f, 1);
  if (auto h = o.find("history_every")) config.output.history_every = at_least(*h, 1);
  if (auto p = o.find("progress_every")) config.output.progress_every = at_least(*p, 0);
  if (auto c = o.find("checkpoint")) {
    if (config.solver.type != SolverType::explicit_dynamic)
      ctx.fail(*c->key_mark, c->path + ": checkpoints are written by explicit runs only (solver.type explicit)");
    MapReader cp(ctx, *c, {"every"});
    config.output.checkpoint_every = at_least(cp.get("every", "the steps between checkpoints"), 1);
  }
  if (auto f = o.find("exodus_files"); f && config.output.checkpoint_every)
    ctx.fail(*f->key_mark, f->path + ": exodus output is not written with checkpoints");
  if (auto f = o.find("format"); f && config.output.writes_exodus()) {
    // A restart rewrites frames.pvd's list; the Exodus file has no such index yet.
    if (config.output.checkpoint_every)
      ctx.fail(f->mark, f->path + ": exodus output is not written with checkpoints; use format: vtu");
    if (config.solver.type == SolverType::heat)
      ctx.fail(f->mark, f->path + ": a heat run writes Exodus files through output.exodus_files only");
  }
}

// The thermal section and the materials' thermal maps go together; the heat time step
// belongs to heat runs, the time scale to coupled explicit ones.
void check_thermal(const DeckContext& ctx, const MapReader& m, const Config& config) {
  const Item materials = *m.find("materials");
  const auto thermal = m.find("thermal");
  for (const auto& mat : config.materials) {
    const YAML::Node node = materials.node[mat.name];
    if (thermal && !mat.thermal.enabled) {
      ctx.fail(node.Mark(), "materials." + mat.name +
                                ": the deck has a thermal section, so every material needs a thermal map, e.g. "
                                "thermal: {conductivity: 30, specific_heat: 880}");
    }
    if (!thermal && mat.thermal.enabled) {
      ctx.fail(node["thermal"].Mark(), "materials." + mat.name +
                                           ".thermal: a thermal map needs the deck's thermal section (at least "
                                           "thermal: {initial_temperature: ...}); see docs/input.md");
    }
  }
  const SolverType type = config.solver.type;
  if (type == SolverType::heat && !thermal) {
    const MapReader s(ctx, *m.find("solver"), {"type", "end_time", "time_step", "safety_factor", "damping", "method",
                                               "linear_solver", "tangent", "tolerance", "max_iterations", "load_steps",
                                               "max_step_cuts", "max_break_rounds", "condition_number",
                                               "adaptive_time_step", "adaptive_every", "energy_balance_warning",
                                               "backend"});
    ctx.fail(s.find("type")->mark, "solver.type: heat needs a thermal section (thermal: {initial_temperature: ...})");
  }
  if (!thermal) return;
  const MapReader t(ctx, *thermal, {"initial_temperature", "kernel", "calibration", "integration", "quadrature",
                                    "time_scale", "conduction", "boundary"});
  const bool conduction = config.thermal.conduction;
  const bool steady = config.thermal.integration == HeatIntegration::steady;
  // Conduction needs each material's conductivity and heat capacity (a steady solve the
  // conductivity alone: no heat is stored); a prescribed field (conduction: false) neither.
  for (const auto& mat : config.materials) {
    if (!conduction) continue;
    const ThermalMaterialConfig& th = mat.thermal;
    if (th.conductivity > 0 && (th.specific_heat > 0 || steady)) continue;
    ctx.fail(materials.node[mat.name]["thermal"].Mark(),
             "materials." + mat.name + ".thermal: expected " +
                 (th.conductivity > 0 ? "specific_heat" : "conductivity") +
                 " (heat conduction needs the conductivity k [W/(m K)] and the specific heat c [J/(kg K)]; "
                 "thermal.conduction: false prescribes the temperature instead)");
  }
  // A material of heat alone (no model): heat runs only, and a density where heat is stored.
  for (const auto& mat : config.materials) {
    if (mat.mechanics) continue;
    const YAML::Node node = materials.node[mat.name];
    if (type != SolverType::heat)
      ctx.fail(node.Mark(), "materials." + mat.name + ": a material without a model has no mechanics; it runs with "
                            "solver.type: heat only (give it a model and its moduli for this solver)");
    if (!steady && !node["density"])
      ctx.fail(node.Mark(), "materials." + mat.name + ": expected density (the heat capacity per volume is rho c; "
                            "only thermal.integration: steady stores no heat)");
  }
  if (steady) {
    const Item it = *t.find("integration");
    if (type != SolverType::heat)
      ctx.fail(it.mark, it.path + ": steady applies to solver.type: heat (a steady solve at each step)");
    if (!config.solver.time_step)
      ctx.fail(it.mark, it.path + ": steady needs solver.time_step (the time between two steady solves: the "
                                  "load step [s])");
    // Without a temperature or a film somewhere the steady temperature is fixed only up to a
    // constant (and a source has no steady state).
    bool anchored = false;
    for (const auto& bc : config.thermal.boundary)
      anchored = anchored || bc.kind != ThermalBoundaryKind::flux;
    if (!anchored)
      ctx.fail(it.mark, it.path + ": steady needs a temperature or convection condition in thermal.boundary (with "
                                  "neither the steady temperature is not unique)");
  }
  if (!conduction && type == SolverType::heat)
    ctx.fail(t.find("conduction")->mark, "thermal.conduction: false leaves solver.type: heat nothing to solve");
  if (conduction && (type == SolverType::static_equilibrium || type == SolverType::implicit_dynamic)) {
    ctx.fail(thermal->key_mark ? *thermal->key_mark : thermal->mark,
             "thermal: heat conduction runs with solver type heat (heat alone) or explicit (coupled); this deck has "
             "a static or implicit_dynamic solver (a prescribed temperature field, thermal.conduction: false, runs "
             "with any solver)");
  }
  if (auto s = t.find("time_scale"); s && type == SolverType::heat) {
    ctx.fail(*s->key_mark, s->path + ": applies to coupled runs (solver type explicit) only; a heat run takes "
                                     "solver.time_step");
  }
  if (type == SolverType::heat && config.thermal.integration == HeatIntegration::implicit_euler &&
      !config.solver.time_step) {
    ctx.fail(t.find("integration")->mark, "thermal.integration: implicit needs solver.time_step (the heat step [s]; "
                                          "backward Euler is stable for any size)");
  }
  for (const auto& mat : config.materials)
    if (mat.thermal.expansion != 0 && type == SolverType::heat) {
      ctx.warn(materials.node[mat.name]["thermal"]["expansion"].Mark(),
               "materials." + mat.name + ".thermal.expansion: a heat run has no mechanics; the expansion is unused");
    }
}

Config read_config(DeckContext& ctx, const Item& root) {
  Config config;
  config.deck_file = ctx.file;
  MapReader m(ctx, root, kTopKeys);
  read_lattice(ctx, m, config);
  read_materials(ctx, m, config);
  const std::vector<std::string> regions = read_regions(ctx, m, config);
  const std::size_t lattice_warnings = ctx.warnings ? ctx.warnings->size() : 0;
  read_bodies(ctx, m, config);
  // Bodies of listed points have no lattice: the warning about few lattice spacings per
  // horizon (read_lattice) does not apply to them.
  bool all_points = true;
  for (const auto& b : config.bodies) all_points = all_points && b.shape.kind() == Shape::Kind::points;
  if (all_points && ctx.warnings && lattice_warnings > 0) {
    auto& w = *ctx.warnings;
    w.erase(std::remove_if(w.begin(), w.end(),
                           [](const std::string& x) { return x.find("lattice spacings; 3 or more") != std::string::npos; }),
            w.end());
  }
  if (auto p = m.find("precracks"))
    for (const auto& i : read_list(ctx, *p)) config.precracks.push_back(read_precrack(ctx, i));
  if (auto b = m.find("bonds_between_bodies")) {
    config.bonds_between_bodies = read_bool(ctx, *b);
    if (!config.bonds_between_bodies)
      for (const auto& body : config.bodies)
        if (body.discretization == Discretization::fe)
          ctx.fail(*b->key_mark, b->path + ": false is not supported with finite-element bodies (body '" +
                                     body.name + "')");
  }
  if (auto b = m.find("family_box")) {
    // Peridigm's box neighbourhood (PdQuickGrid's default): half-widths per axis, >= 0.
    const Vec3 h = read_vector(ctx, *b);
    for (int k = 0; k < 3; ++k)
      if (!(h[k] >= 0) || (k >= config.dimension && h[k] != 0))
        ctx.fail(b->mark, b->path + ": expected the box's half-widths [hx, hy, hz], each >= 0 (0 beyond the deck's "
                                    "dimension)");
    if (!(norm(h) > 0)) ctx.fail(b->mark, b->path + ": the box is empty (every half-width is 0)");
    for (const auto& body : config.bodies)
      if (body.discretization == Discretization::fe)
        ctx.fail(*b->key_mark, b->path + ": not supported with finite-element bodies (body '" + body.name + "')");
    if (config.partial_volume)
      ctx.fail(*b->key_mark, b->path + ": not supported with partial_volume (its fractions assume a sphere)");
    config.family_box = h;
  }
  if (auto n = m.find("no_fail_regions")) {
    if (!n->node.IsSequence()) fail_expected(ctx, *n, "a list of region names, e.g. [top, bottom]");
    for (const auto& i : read_list(ctx, *n)) {
      if (i.node.IsScalar() && i.node.Scalar() == "all") {
        ctx.fail(i.mark, i.path +
                             ": 'all' would make every bond unbreakable; to switch fracture off, leave out "
                             "the materials' damage maps");
      }
      config.no_fail_regions.push_back(read_region_name(ctx, i, regions));
    }
  }
  if (auto ic = m.find("initial_conditions"))
    for (const auto& i : read_list(ctx, *ic))
      config.initial_conditions.push_back(read_initial_condition(ctx, i, regions));
  if (auto l = m.find("loads"))
    for (const auto& i : read_list(ctx, *l)) config.loads.push_back(read_load(ctx, i, regions));
  if (auto c = m.find("contact")) config.contact = read_contact(ctx, *c, config.bodies);
  read_solver(ctx, m, config);
  if (!config.contact.projectiles.empty() && config.solver.type != SolverType::explicit_dynamic) {
    const Item p = *MapReader(ctx, *m.find("contact"), {"short_range", "indenters", "projectiles"}).find("projectiles");
    ctx.fail(*p.key_mark, p.path + ": rigid projectiles run with solver type explicit only");
  }
  if (config.solver.type != SolverType::explicit_dynamic || config.structure.kind != StructureKind::none) {
    const auto items = read_list(ctx, *m.find("bodies"));
    for (std::size_t i = 0; i < config.bodies.size(); ++i)
      if (config.bodies[i].discretization == Discretization::fe) {
        const Item d = *MapReader(ctx, items[i], {"name", "material", "shape", "discretization", "element",
                                                  "hourglass", "j2", "element_size", "horizon"}).find("discretization");
        ctx.fail(d.mark, d.path + ": finite-element bodies run with solver type explicit, in solid decks (no "
                                  "structure)");
      }
  }
  if (auto t = m.find("thermal")) config.thermal = read_thermal(ctx, *t, regions);
  check_thermal(ctx, m, config);
  check_stages(ctx, m, config);
  read_output(ctx, m, config);
  return config;
}

}  // namespace

Config parse_deck(const std::string& yaml_text, const std::string& file_name) {
  DeckContext ctx{file_name, 3, PlaneMode::none, nullptr};
  YAML::Node root;
  try {
    // Peridigm's XML decks become YAML with the same lines and columns (deck/peridigm/xml.hpp).
    root = YAML::Load(peridigm::looks_like_xml(yaml_text) ? peridigm::xml_to_yaml(yaml_text, file_name)
                                                          : peridigm::unescape_peridigm_braces(yaml_text));
  } catch (const YAML::Exception& e) {
    ctx.fail(e.mark, "YAML syntax error: " + e.msg);
  }
  return parse_deck_node(root, file_name);
}

Config parse_deck_node(const YAML::Node& given, const std::string& file_name) {
  std::vector<std::string> warnings;
  DeckContext ctx{file_name, 3, PlaneMode::none, &warnings};
  if (!given.IsDefined() || given.IsNull()) {
    ctx.fail(YAML::Mark(),
             "the deck is empty; expected a map of keys such as dimension, spacing, horizon, "
             "materials, bodies, solver (see docs/input.md)");
  }
  if (!given.IsMap()) {
    ctx.fail(given.Mark(),
             "expected the deck to be a map of 'key: value' lines (dimension, spacing, ...), found " + describe(given));
  }
  // A Peridigm deck (top-level key Peridigm) is translated to a native one first
  // (deck/peridigm/); its own mistakes are reported at their place in it.
  // (YAML::Node assignment rebinds shared nodes, so the translation gets its own.)
  YAML::Node translated;
  const bool peridigm_deck = peridigm::is_peridigm_deck(given);
  if (peridigm_deck) translated.reset(peridigm::to_native(given, file_name));
  const YAML::Node& root = peridigm_deck ? translated : given;
  Config config;
  try {
    config = read_config(ctx, Item{root, "", root.Mark(), std::nullopt});
  } catch (const YAML::Exception& e) {
    // A safety net: the readers above check types before converting, so this is a bug.
    ctx.fail(e.mark, "cannot read the deck: " + e.msg);
  }
  config.warnings = std::move(warnings);
  return config;
}

std::string convert_peridigm_deck(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open deck '" + path + "': " + std::strerror(errno));
  std::ostringstream text;
  text << in.rdbuf();
  DeckContext ctx{path, 3, PlaneMode::none, nullptr};
  YAML::Node root;
  try {
    root = YAML::Load(peridigm::looks_like_xml(text.str()) ? peridigm::xml_to_yaml(text.str(), path)
                                                           : peridigm::unescape_peridigm_braces(text.str()));
  } catch (const YAML::Exception& e) {
    ctx.fail(e.mark, "YAML syntax error: " + e.msg);
  }
  if (!peridigm::is_peridigm_deck(root))
    ctx.fail(root.Mark(), "not a Peridigm deck: expected one top-level key, Peridigm");
  const YAML::Node native = peridigm::to_native(root, path);
  const std::string out = peridigm::native_yaml(native, path);
  parse_deck(out, path + " (converted)");  // the translation must read back
  return out;
}

Config load_deck(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open deck '" + path + "': " + std::strerror(errno));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw Error("cannot read deck '" + path + "'");
  return parse_deck(text.str(), path);
}

}  // namespace horizon
