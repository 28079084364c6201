#include "horizon/deck/deck.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "horizon/core/error.hpp"
#include "horizon/deck/conditions.hpp"
#include "horizon/deck/materials.hpp"
#include "horizon/deck/reader.hpp"
#include "horizon/deck/shapes.hpp"

namespace horizon {

namespace {

using namespace deck;

const std::vector<std::string> kTopKeys = {
    "dimension",      "plane",           "thickness",          "area",      "spacing", "horizon",
    "horizon_factor", "lattice_origin",  "partial_volume",     "materials", "bodies",  "precracks",
    "regions",        "no_fail_regions", "initial_conditions", "loads",     "solver",  "output"};

// A key that only makes sense in one dimension is an error in the others.
void only_in_dimension(const DeckContext& ctx, const MapReader& m, const char* key, int dimension) {
  if (ctx.dimension == dimension) return;
  if (auto item = m.find(key)) {
    ctx.fail(*item->key_mark, item->path + ": applies to " + std::to_string(dimension) +
                                  "-D decks only; this deck has dimension: " + std::to_string(ctx.dimension));
  }
}

void read_lattice(DeckContext& ctx, const MapReader& m, Config& config) {
  const Item dim = m.get("dimension", "1, 2 or 3");
  config.dimension = static_cast<int>(choose_word(ctx, dim, {"1", "2", "3"})) + 1;
  ctx.dimension = config.dimension;

  only_in_dimension(ctx, m, "plane", 2);
  only_in_dimension(ctx, m, "thickness", 2);
  only_in_dimension(ctx, m, "area", 1);
  if (config.dimension == 2) {
    config.plane = read_enum<PlaneMode>(ctx, m.get("plane", "a 2-D deck is plane stress or plane strain"),
                                        {{"stress", PlaneMode::stress}, {"strain", PlaneMode::strain}});
    if (auto t = m.find("thickness")) config.thickness = read_positive(ctx, *t);
  }
  ctx.plane = config.plane;
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
  if (auto p = m.find("partial_volume")) config.partial_volume = read_bool(ctx, *p);
}

void read_materials(const DeckContext& ctx, const MapReader& m, Config& config) {
  const Item item = m.get("materials", "a map from material name to its properties");
  const auto entries = map_entries(ctx, item);
  if (entries.empty()) {
    ctx.fail(item.mark, "materials: expected at least one material, e.g. materials: {glass: {model: pmb, ...}}");
  }
  for (const auto& e : entries) config.materials.push_back(read_material(ctx, e.key, e.value));
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

void read_bodies(const DeckContext& ctx, const MapReader& m, Config& config) {
  const Item item = m.get("bodies", "a list of bodies, each {name, material, shape}");
  if (!item.node.IsSequence()) fail_expected(ctx, item, "a list of bodies (lines starting with '- ')");
  const auto items = read_list(ctx, item);
  if (items.empty()) ctx.fail(item.mark, "bodies: expected at least one body");
  std::vector<std::string> materials;
  for (const auto& mat : config.materials) materials.push_back(mat.name);
  for (std::size_t i = 0; i < items.size(); ++i) {
    MapReader b(ctx, items[i], {"name", "material", "shape"});
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
    config.bodies.push_back(std::move(body));
  }
}

void read_solver(const DeckContext& ctx, const MapReader& m, Config& config) {
  MapReader s(ctx, m.get("solver", "at least {end_time: ...}"),
              {"type", "end_time", "time_step", "safety_factor", "damping"});
  if (auto t = s.find("type")) choose_word(ctx, *t, {"explicit"});
  config.solver.end_time = read_positive(ctx, s.get("end_time", "the simulated time [s], > 0"));
  if (auto dt = s.find("time_step")) config.solver.time_step = read_positive(ctx, *dt);
  if (auto f = s.find("safety_factor")) {
    const double v = read_number(ctx, *f);
    if (!(v > 0 && v <= 1)) {
      ctx.fail(f->mark,
               f->path + ": expected a number in (0, 1] (a fraction of the stable time step), found " + text_of(*f));
    }
    config.solver.safety_factor = v;
  }
  if (auto d = s.find("damping")) config.solver.damping = read_non_negative(ctx, *d);
}

void read_output(const DeckContext& ctx, const MapReader& m, Config& config) {
  const auto item = m.find("output");
  if (!item) return;
  MapReader o(ctx, *item, {"directory", "frames", "history_every", "progress_every"});
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
}

Config read_config(DeckContext& ctx, const Item& root) {
  Config config;
  config.deck_file = ctx.file;
  MapReader m(ctx, root, kTopKeys);
  read_lattice(ctx, m, config);
  read_materials(ctx, m, config);
  const std::vector<std::string> regions = read_regions(ctx, m, config);
  read_bodies(ctx, m, config);
  if (auto p = m.find("precracks"))
    for (const auto& i : read_list(ctx, *p)) config.precracks.push_back(read_precrack(ctx, i));
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
  read_solver(ctx, m, config);
  read_output(ctx, m, config);
  return config;
}

}  // namespace

Config parse_deck(const std::string& yaml_text, const std::string& file_name) {
  std::vector<std::string> warnings;
  DeckContext ctx{file_name, 3, PlaneMode::none, &warnings};
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    ctx.fail(e.mark, "YAML syntax error: " + e.msg);
  }
  if (!root.IsDefined() || root.IsNull()) {
    ctx.fail(YAML::Mark(),
             "the deck is empty; expected a map of keys such as dimension, spacing, horizon, "
             "materials, bodies, solver (see docs/input.md)");
  }
  if (!root.IsMap()) {
    ctx.fail(root.Mark(),
             "expected the deck to be a map of 'key: value' lines (dimension, spacing, ...), found " + describe(root));
  }
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

Config load_deck(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open deck '" + path + "': " + std::strerror(errno));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw Error("cannot read deck '" + path + "'");
  return parse_deck(text.str(), path);
}

}  // namespace horizon
