// The `horizon` Python module (pybind11): decks from files, text or dicts, edited as YAML
// trees; runs taken to the end or step by step with a callback; particle fields as NumPy
// views of the run's own arrays. The pure-Python part is python/horizon/__init__.py.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <yaml-cpp/yaml.h>

#include <cstdlib>
#include <fstream>
#include <limits>
#include <memory>
#include <filesystem>
#include <optional>
#include <sstream>
#include <variant>

#include "horizon/core/error.hpp"
#include "horizon/core/version.hpp"
#include "horizon/deck/deck.hpp"
#include "horizon/deck/peridigm/peridigm.hpp"
#include "horizon/deck/peridigm/xml.hpp"
#include "horizon/driver/run.hpp"
#include "horizon/loading/loads.hpp"
#include "horizon/material/model.hpp"
#include "horizon/output/render.hpp"
#include "horizon/output/resolve_frame.hpp"
#include "horizon/output/vtu.hpp"
#include "horizon/solver/explicit.hpp"

namespace py = pybind11;
using namespace horizon;

namespace {

// --- YAML <-> Python ---------------------------------------------------------------

YAML::Node to_yaml(const py::handle& o) {
  if (o.is_none()) return YAML::Node(YAML::NodeType::Null);
  if (py::isinstance<py::bool_>(o)) return YAML::Node(o.cast<bool>() ? "true" : "false");
  if (py::isinstance<py::int_>(o)) return YAML::Node(o.cast<long long>());
  if (py::isinstance<py::float_>(o)) return YAML::Node(o.cast<double>());
  if (py::isinstance<py::str>(o)) return YAML::Node(o.cast<std::string>());
  if (py::isinstance<py::dict>(o)) {
    YAML::Node n(YAML::NodeType::Map);
    for (const auto& kv : o.cast<py::dict>()) n[py::str(kv.first).cast<std::string>()] = to_yaml(kv.second);
    return n;
  }
  if (py::isinstance<py::list>(o) || py::isinstance<py::tuple>(o) || py::hasattr(o, "tolist")) {
    py::object seq = py::hasattr(o, "tolist") ? o.attr("tolist")() : py::reinterpret_borrow<py::object>(o);
    if (!py::isinstance<py::list>(seq) && !py::isinstance<py::tuple>(seq)) return to_yaml(seq);
    YAML::Node n(YAML::NodeType::Sequence);
    for (const auto& item : seq) n.push_back(to_yaml(item));
    return n;
  }
  if (py::hasattr(o, "__float__")) return YAML::Node(py::float_(py::reinterpret_borrow<py::object>(o)).cast<double>());
  throw py::type_error("cannot put a " + py::str(o.get_type()).cast<std::string>() + " in a deck");
}

py::object scalar_to_python(const YAML::Node& n) {
  const std::string s = n.Scalar();
  if (n.Tag() == "!") return py::str(s);  // quoted: a string
  if (s == "true" || s == "True" || s == "yes" || s == "on") return py::bool_(true);
  if (s == "false" || s == "False" || s == "no" || s == "off") return py::bool_(false);
  if (s == "~" || s == "null" || s.empty()) return py::none();
  char* end = nullptr;
  const long long i = std::strtoll(s.c_str(), &end, 10);
  if (!s.empty() && *end == '\0') return py::int_(i);
  const double d = std::strtod(s.c_str(), &end);
  if (!s.empty() && *end == '\0') return py::float_(d);
  return py::str(s);
}

py::object to_python(const YAML::Node& n) {
  switch (n.Type()) {
    case YAML::NodeType::Map: {
      py::dict d;
      for (const auto& kv : n) d[py::str(kv.first.Scalar())] = to_python(kv.second);
      return d;
    }
    case YAML::NodeType::Sequence: {
      py::list l;
      for (const auto& item : n) l.append(to_python(item));
      return l;
    }
    case YAML::NodeType::Scalar:
      return scalar_to_python(n);
    default:
      return py::none();
  }
}

// "materials.glass.density", "loads[1].traction[0]" or a list of keys and indices.
std::vector<std::variant<std::string, std::size_t>> split_path(const py::handle& path) {
  std::vector<std::variant<std::string, std::size_t>> keys;
  if (py::isinstance<py::str>(path)) {
    const std::string p = path.cast<std::string>();
    std::string cur;
    auto flush = [&] {
      if (!cur.empty()) keys.emplace_back(cur);
      cur.clear();
    };
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (p[i] == '.') {
        flush();
      } else if (p[i] == '[') {
        flush();
        const auto close = p.find(']', i);
        if (close == std::string::npos) throw py::key_error("unclosed [ in '" + p + "'");
        keys.emplace_back(static_cast<std::size_t>(std::stoul(p.substr(i + 1, close - i - 1))));
        i = close;
      } else {
        cur += p[i];
      }
    }
    flush();
  } else {
    for (const auto& k : path) {
      if (py::isinstance<py::int_>(k)) keys.emplace_back(k.cast<std::size_t>());
      else keys.emplace_back(py::str(k).cast<std::string>());
    }
  }
  if (keys.empty()) throw py::key_error("empty deck path");
  return keys;
}

std::string path_text(const py::handle& path) { return py::str(path).cast<std::string>(); }

// --- Deck --------------------------------------------------------------------------

struct Deck {
  YAML::Node root;
  std::string name;

  static Deck from_text(const std::string& text, const std::string& name) {
    Deck d;
    d.name = name;
    try {
      d.root = YAML::Load(peridigm::looks_like_xml(text) ? peridigm::xml_to_yaml(text, name) : text);
    } catch (const YAML::Exception& e) {
      throw DeckError(DeckLocation{name, e.mark.line + 1, e.mark.column + 1}, "YAML syntax error: " + e.msg);
    }
    return d;
  }
  static Deck from_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error("cannot open deck '" + path + "'");
    std::ostringstream text;
    text << in.rdbuf();
    return from_text(text.str(), path);
  }

  YAML::Node locate(const py::handle& path, bool create) {
    const auto keys = split_path(path);
    YAML::Node node = root;
    for (const auto& k : keys) {
      if (std::holds_alternative<std::size_t>(k)) {
        const std::size_t i = std::get<std::size_t>(k);
        if (!node.IsSequence() || i >= node.size())
          throw py::key_error("deck path '" + path_text(path) + "': index " + std::to_string(i) + " is not in a list there");
        node.reset(node[i]);
      } else {
        const std::string& key = std::get<std::string>(k);
        if (!node.IsMap() && !(create && node.IsNull()))
          throw py::key_error("deck path '" + path_text(path) + "': '" + key + "' is not under a map");
        if (!create && !node[key]) throw py::key_error("deck path '" + path_text(path) + "': no key '" + key + "'");
        YAML::Node next = node[key];
        node.reset(next);
      }
    }
    return node;
  }

  Config config() const { return parse_deck_node(root, name); }
};

// --- Simulation --------------------------------------------------------------------

struct Simulation {
  Config config;
  RunOptions options;
  std::unique_ptr<ExplicitRun> run;  // explicit decks
  bool implicit = false;
  bool implicit_done = false;
  int implicit_exit = 0;
  std::vector<std::string> warnings;

  Simulation(const Deck& deck, std::optional<std::string> output_dir, double coarsen, std::optional<double> end_time,
             int threads, bool quiet) {
    config = deck.config();
    warnings = config.warnings;
    options.output_dir = output_dir;
    options.coarsen = coarsen;
    options.end_time = end_time;
    options.threads = threads;
    options.quiet = quiet;
    options.handle_signals = false;
    implicit = config.solver.type != SolverType::explicit_dynamic;
    if (!implicit) run = std::make_unique<ExplicitRun>(config, options);
  }

  ExplicitRun& explicit_run(const char* what) {
    if (!run)
      throw Error(std::string(what) + " needs an explicit run; static and implicit_dynamic decks run to the end with run()");
    return *run;
  }
};

py::array vec_view(py::object owner, std::vector<Vec3>& v, bool writeable) {
  static_assert(sizeof(Vec3) == 3 * sizeof(double));
  py::array a(py::dtype::of<double>(), {static_cast<py::ssize_t>(v.size()), py::ssize_t{3}},
              {static_cast<py::ssize_t>(sizeof(Vec3)), static_cast<py::ssize_t>(sizeof(double))},
              reinterpret_cast<double*>(v.data()), owner);
  if (!writeable) a.attr("flags").attr("writeable") = false;
  return a;
}

template <class T>
py::array scalar_view(py::object owner, std::vector<T>& v, bool writeable) {
  py::array a(py::dtype::of<T>(), {static_cast<py::ssize_t>(v.size())}, {static_cast<py::ssize_t>(sizeof(T))},
              v.data(), owner);
  if (!writeable) a.attr("flags").attr("writeable") = false;
  return a;
}

py::dict frame_dict(const Frame& f) {
  py::dict d;
  d["time"] = f.time;
  d["step"] = f.step;
  py::array_t<double> pts({static_cast<py::ssize_t>(f.points.size()), py::ssize_t{3}});
  auto p = pts.mutable_unchecked<2>();
  for (std::size_t i = 0; i < f.points.size(); ++i)
    for (int k = 0; k < 3; ++k) p(static_cast<py::ssize_t>(i), k) = f.points[i][k];
  d["points"] = pts;
  py::dict fields;
  for (const auto& ff : f.fields) {
    const auto n = static_cast<py::ssize_t>(f.points.size());
    py::array_t<double> a = ff.components == 1 ? py::array_t<double>({n}) : py::array_t<double>({n, py::ssize_t{3}});
    std::copy(ff.data.begin(), ff.data.end(), a.mutable_data());
    fields[py::str(ff.name)] = a;
  }
  d["fields"] = fields;
  return d;
}

}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "Horizon, a peridynamics engine: the compiled core (use the horizon package)";
  m.attr("__version__") = version_string;

  static py::exception<Error> error_type(m, "Error", PyExc_RuntimeError);
  static py::exception<DeckError> deck_error_type(m, "DeckError", error_type.ptr());
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const DeckError& e) {
      py::object ex = py::reinterpret_borrow<py::object>(deck_error_type.ptr())(e.what());
      ex.attr("file") = e.where().file;
      ex.attr("line") = e.where().line;
      ex.attr("column") = e.where().column;
      ex.attr("message") = e.message();
      PyErr_SetObject(deck_error_type.ptr(), ex.ptr());
    } catch (const Error& e) {
      PyErr_SetString(error_type.ptr(), e.what());
    }
  });

  py::class_<Deck>(m, "Deck", "A deck as a YAML tree: native, or Peridigm's (translated when it runs)")
      .def_static("from_file", &Deck::from_file, py::arg("path"), "Reads a deck file (native or Peridigm YAML).")
      .def_static("from_text", &Deck::from_text, py::arg("text"), py::arg("name") = "<string>",
                  "Parses deck text; `name` is the file name messages show.")
      .def_static(
          "from_dict",
          [](const py::dict& d, const std::string& name) {
            Deck deck;
            deck.root = to_yaml(d);
            deck.name = name;
            return deck;
          },
          py::arg("data"), py::arg("name") = "<dict>", "A deck from nested dicts and lists.")
      .def_property_readonly("name", [](const Deck& d) { return d.name; })
      .def_property_readonly("is_peridigm", [](const Deck& d) { return peridigm::is_peridigm_deck(d.root); })
      .def(
          "set", [](Deck& d, const py::handle& path, const py::handle& value) { d.locate(path, true) = to_yaml(value); },
          py::arg("path"), py::arg("value"),
          "Sets a value: deck.set('materials.glass.density', 2500), deck.set('loads[0].traction', [0, 3e6]); "
          "missing map keys are created.")
      .def(
          "get", [](Deck& d, const py::handle& path) { return to_python(d.locate(path, false)); }, py::arg("path"))
      .def("to_dict", [](const Deck& d) { return to_python(d.root); })
      .def("to_yaml",
           [](const Deck& d) {
             YAML::Emitter e;
             e.SetDoublePrecision(17);
             e << d.root;
             return std::string(e.c_str()) + "\n";
           })
      .def(
          "native",
          [](const Deck& d) {
            Deck n;
            n.name = d.name;
            n.root = peridigm::is_peridigm_deck(d.root) ? peridigm::to_native(d.root, d.name) : YAML::Clone(d.root);
            return n;
          },
          "The native deck: a Peridigm deck translated, a native one copied.")
      .def(
          "check",
          [](const Deck& d, double coarsen) {
            Config c = d.config();
            RunOptions o;
            o.coarsen = coarsen;
            apply_run_options(c, o);
            const System s = build_system(c);
            const CheckReport r = check_system(c, s);
            py::dict out;
            out["particles"] = r.particles;
            out["bonds"] = r.bonds;
            out["precrack_bonds"] = r.precrack_bonds;
            out["memory_bytes"] = r.memory_bytes;
            out["stable_dt"] = r.stable_dt;
            out["dt"] = r.dt;
            out["steps"] = r.steps;
            out["warnings"] = c.warnings;
            out["report"] = format_check(c, r);
            return out;
          },
          py::arg("coarsen") = 1.0, "Validates the deck and builds its particles: what `horizon check` prints.");

  py::class_<Simulation>(m, "Simulation", "A run of a deck")
      .def(py::init<const Deck&, std::optional<std::string>, double, std::optional<double>, int, bool>(),
           py::arg("deck"), py::arg("output_dir") = py::none(), py::arg("coarsen") = 1.0,
           py::arg("end_time") = py::none(), py::arg("threads") = 0, py::arg("quiet") = true)
      .def(
          "_advance",
          [](Simulation& s, int64_t n) {
            ExplicitRun& r = s.explicit_run("step()");
            if (r.finished()) throw Error("the run is finished");
            py::gil_scoped_release release;
            return r.advance(n);
          },
          py::arg("n"))
      .def(
          "_stop", [](Simulation& s, const std::string& why) { s.explicit_run("stop()").stop(why); }, py::arg("reason"))
      .def("_finish",
           [](Simulation& s) {
             if (s.run) {
               py::gil_scoped_release release;
               return s.run->finish();
             }
             if (!s.implicit_done) {
               py::gil_scoped_release release;
               s.implicit_exit = run_implicit_deck(s.config, s.options);
               s.implicit_done = true;
             }
             return s.implicit_exit;
           })
      .def_property_readonly("is_explicit", [](const Simulation& s) { return static_cast<bool>(s.run); })
      .def_property_readonly("done", [](const Simulation& s) { return s.run ? s.run->done() : s.implicit_done; })
      .def_property_readonly("finished",
                             [](const Simulation& s) { return s.run ? s.run->finished() : s.implicit_done; })
      .def_property_readonly("time", [](Simulation& s) { return s.explicit_run("time").time(); })
      .def_property_readonly("dt", [](Simulation& s) { return s.explicit_run("dt").dt(); })
      .def_property_readonly("steps", [](Simulation& s) { return s.explicit_run("steps").steps(); })
      .def_property_readonly("total_steps", [](Simulation& s) { return s.explicit_run("total_steps").total_steps(); })
      .def_property_readonly("status", [](Simulation& s) { return s.run ? s.run->status() : std::string(); })
      .def_property_readonly("exit_code", [](Simulation& s) { return s.run ? s.run->exit_code() : s.implicit_exit; })
      .def_property_readonly("warnings", [](const Simulation& s) { return s.warnings; })
      .def_property_readonly("output_dir",
                             [](const Simulation& s) {
                               return s.options.output_dir ? *s.options.output_dir : s.config.output.directory;
                             })
      .def("_history_csv", [](Simulation& s) { return s.explicit_run("history").history_csv(); })
      .def("_summary_json", [](Simulation& s) { return s.run ? s.run->summary().dump() : std::string(); })
      .def_property_readonly("particles", [](Simulation& s) { return s.explicit_run("particles").system().particles.size(); })
      .def_property_readonly("bonds", [](Simulation& s) { return s.explicit_run("bonds").system().initial_bonds; })
      .def_property_readonly("broken_bonds", [](Simulation& s) { return s.explicit_run("bonds").system().broken; })
      .def_property_readonly("block_names", [](Simulation& s) { return s.explicit_run("blocks").system().block_names; })
      // NumPy views of the run's arrays (no copy); each keeps the simulation alive.
      .def_property_readonly("positions",
                             [](py::object self) {
                               auto& s = self.cast<Simulation&>();
                               return vec_view(self, s.explicit_run("positions").system().particles.X, false);
                             })
      .def_property_readonly("displacement",
                             [](py::object self) {
                               auto& s = self.cast<Simulation&>();
                               return vec_view(self, s.explicit_run("displacement").system().particles.u, true);
                             })
      .def_property_readonly("velocity",
                             [](py::object self) {
                               auto& s = self.cast<Simulation&>();
                               return vec_view(self, s.explicit_run("velocity").system().particles.v, true);
                             })
      .def_property_readonly("force_density",
                             [](py::object self) {
                               auto& s = self.cast<Simulation&>();
                               return vec_view(self, s.explicit_run("force_density").system().particles.f, false);
                             })
      .def_property_readonly("damage",
                             [](py::object self) {
                               auto& s = self.cast<Simulation&>();
                               return scalar_view(self, s.explicit_run("damage").system().particles.damage, false);
                             })
      .def_property_readonly("volume",
                             [](py::object self) {
                               auto& s = self.cast<Simulation&>();
                               return scalar_view(self, s.explicit_run("volume").system().particles.volume, false);
                             })
      .def_property_readonly("density",
                             [](py::object self) {
                               auto& s = self.cast<Simulation&>();
                               return scalar_view(self, s.explicit_run("density").system().particles.density, false);
                             })
      .def_property_readonly("block",
                             [](py::object self) {
                               auto& s = self.cast<Simulation&>();
                               return scalar_view(self, s.explicit_run("block").system().particles.block, false);
                             })
      .def_property_readonly("energy_density",
                             [](py::object self) {
                               auto& s = self.cast<Simulation&>();
                               return scalar_view(self, s.explicit_run("energy").system().particles.energy, false);
                             })
      .def(
          "frame",
          [](Simulation& s) {
            ExplicitRun& r = s.explicit_run("frame()");
            return frame_dict(make_frame(r.system(), r.time(), r.steps()));
          },
          "Every field of the current state (a copy), the models' own fields included, as in a frame file.")
      .def("energy",
           [](Simulation& s) {
             const Ledger& g = s.explicit_run("energy()").ledger();
             py::dict d;
             d["kinetic"] = g.kinetic;
             d["strain"] = g.strain;
             d["external_work"] = g.external_work;
             d["dissipated"] = g.dissipated;
             d["damped"] = g.damped;
             d["balance_error"] = g.balance_error();
             return d;
           })
      .def("reactions", [](Simulation& s) {
        py::dict d;
        for (const auto& L : s.explicit_run("reactions()").loads().loads())
          d[py::str(L.name)] = py::make_tuple(L.reaction.x, L.reaction.y, L.reaction.z);
        return d;
      });

  m.def(
      "read_frame", [](const std::string& path) { return frame_dict(read_vtu(resolve_frame(path))); }, py::arg("path"),
      "A frame (.vtu), the last frame of a .pvd index or of a run's output folder, as a dict of NumPy arrays.");
  m.def(
      "render",
      [](const std::string& path, const std::string& field, std::optional<std::string> output, int width,
         double scale) {
        const std::string frame = resolve_frame(path);
        RenderOptions o;
        o.field = field;
        o.width = width;
        o.displacement_scale = scale;
        const std::string png =
            output ? *output : (std::filesystem::path(frame).parent_path() / (field + ".png")).string();
        render_png(read_vtu(frame), o, png);
        return png;
      },
      py::arg("path"), py::arg("field") = "damage", py::arg("output") = py::none(), py::arg("width") = 1200,
      py::arg("scale") = 1.0, "Draws a frame (or a run folder's last frame) to PNG; returns the PNG's path.");
  m.def("models", &describe_models, "The material models and their deck parameters (`horizon models`).");
  m.def("convert_peridigm", &convert_peridigm_deck, py::arg("path"),
        "The native deck (YAML text) equivalent to a Peridigm deck (`horizon convert`).");
}
