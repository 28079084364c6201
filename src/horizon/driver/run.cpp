#include "horizon/driver/run.hpp"
#include "horizon/driver/model_list.hpp"

#include <fmt/format.h>
#include <omp.h>
#include <sched.h>
#include <sys/resource.h>
#include <zlib.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "horizon/core/interrupt.hpp"
#include "horizon/core/progress.hpp"
#include "horizon/core/version.hpp"
#include "horizon/driver/exodus_output.hpp"
#include "horizon/driver/summary.hpp"
#include "horizon/fe/fe_region.hpp"
#include "horizon/damage/crack_angle.hpp"
#include "horizon/damage/crack_metrics.hpp"
#include "horizon/loading/loads.hpp"
#include "horizon/output/atomic_file.hpp"
#include "horizon/output/checkpoint.hpp"
#include "horizon/parallel/checkpoint_stream.hpp"
#include "horizon/output/pvd.hpp"
#include "horizon/parallel/decomposition.hpp"
#include "horizon/parallel/lead_view.hpp"
#include "horizon/solver/forces.hpp"
#include "horizon/output/vtu.hpp"
#include "horizon/solver/explicit.hpp"
#include "horizon/thermal/heat.hpp"

namespace horizon {

namespace fs = std::filesystem;

void apply_run_options(Config& c, const RunOptions& o) {
  if (o.output_dir) c.output.directory = *o.output_dir;
  if (o.end_time) c.solver.end_time = *o.end_time;
  if (o.max_memory_gib > 0) c.memory_limit_bytes = o.max_memory_gib * 1024.0 * 1024.0 * 1024.0;
  if (o.coarsen != 1) {
    c.spacing *= o.coarsen;
    c.horizon *= o.coarsen;
    if (c.solver.time_step) *c.solver.time_step *= o.coarsen;
  }
}

namespace {
// The stable step of the whole system: with local rows (parallel/decomposition.hpp) each
// rank sees its rows alone, and a model that owns its force pass its owned rows alone
// (nonlinear_solid); the minimum over ranks is the serial figure, bit for bit (a rank
// that holds every row finds it itself). Collective when decomposed: every rank calls it
// (the set-up's check, each adaptive step).
double whole_stable_step(const System& s) {
  const double dt = stable_time_step(s);
  return s.decomposition ? min_over_ranks(dt) : dt;
}
}  // namespace

double run_time_step(const Config& c, const System& s) {
  return c.solver.time_step ? *c.solver.time_step : c.solver.safety_factor * whole_stable_step(s);
}

int64_t step_count(const Config& c, double dt) {
  if (!(dt > 0 && std::isfinite(dt))) {
    throw Error(fmt::format("{}: the time step is {}: no particle has a bond that sets a stable step (a body of a "
                            "single particle, or bodies thinner than a spacing apart from each other?); check the "
                            "bodies, the spacing and the horizon",
                            c.deck_file, dt));
  }
  const double steps = std::ceil(c.solver.end_time / dt - 1e-9);
  if (!(steps <= kMaxSteps)) {
    throw Error(fmt::format("{}: the run would take {:.3g} steps of {:.4g} s to end_time {:.4g} s, more than the "
                            "{:g} a run may take; check solver.end_time and solver.time_step (units: seconds)",
                            c.deck_file, steps, dt, c.solver.end_time, kMaxSteps));
  }
  return static_cast<int64_t>(steps);
}

CheckReport check_system(const Config& c, const System& s) {
  CheckReport r;
  // With local particles (parallel/decomposition.hpp) a rank holds part of them.
  r.particles = s.decomposition && s.decomposition->local_particles ? s.decomposition->global_particles
                                                                    : s.particles.size();
  r.bonds = checkpoint_bond_count(s);  // the whole system's, also with local rows
  r.precrack_bonds = s.precrack_bonds;
  r.memory_bytes = memory_estimate(s);  // with local rows: this rank's
  r.stable_dt = whole_stable_step(s);
  if (s.fe) {
    r.fe_elements = s.fe->elements();
    r.fe_nodes = s.fe->nodes();
    r.fe_shared_nodes = s.fe->shared_nodes();
    r.fe_nodes_per_element = s.fe->nodes_per_element;
  }
  if (s.heat.active()) r.heat_stable_dt = heat_stable_step(s);
  if (c.solver.type == SolverType::heat) {
    r.stable_dt = r.heat_stable_dt;
    r.dt = c.solver.time_step ? *c.solver.time_step : c.solver.safety_factor * r.heat_stable_dt;
    r.steps = step_count(c, r.dt);
    return r;
  }
  if (c.solver.type == SolverType::static_equilibrium) {
    r.dt = c.solver.end_time / c.solver.load_steps;  // pseudo-time per load step
    r.steps = c.solver.load_steps;
  } else {
    r.dt = run_time_step(c, s);  // implicit dynamics requires solver.time_step (deck check)
    r.steps = step_count(c, r.dt);
  }
  return r;
}

PreparedRun prepare_run(const Config& c) {
  PreparedRun u;
  u.system = build_system(c);
  u.loads = Loads(c, u.system);
  u.loads.apply_initial_conditions(c, u.system);
  u.check = check_system(c, u.system);
  return u;
}

std::string format_check(const Config& c, const CheckReport& r) {
  std::ostringstream o;
  o << fmt::format("deck            {}\n", c.deck_file);
  o << fmt::format("dimension       {}{}\n", c.dimension,
                   c.dimension == 2 ? (c.plane == PlaneMode::stress ? " (plane stress)" : " (plane strain)") : "");
  o << fmt::format("particles       {}\n", r.particles);
  o << fmt::format("bonds           {} directed ({:.1f} per particle), {} cut by precracks\n", r.bonds,
                   r.particles ? static_cast<double>(r.bonds) / static_cast<double>(r.particles) : 0.0,
                   r.precrack_bonds);
  if (r.fe_elements)
    o << fmt::format("fe              {} {} elements, {} nodes ({} of them peridynamic particles)\n", r.fe_elements,
                     r.fe_nodes_per_element == 8 ? "hex8" : "tet4", r.fe_nodes, r.fe_shared_nodes);
  o << fmt::format("memory          {:.1f} MiB (estimate)\n", static_cast<double>(r.memory_bytes) / (1 << 20));
  if (r.heat_stable_dt > 0)
    o << fmt::format("heat            stable explicit heat step {:.4e} s ({}){}\n", r.heat_stable_dt,
                     c.thermal.integration == HeatIntegration::implicit_euler ? "backward Euler" : "forward Euler",
                     c.solver.type == SolverType::heat ? "" : fmt::format(", time scale {}", c.thermal.time_scale));
  if (c.solver.type == SolverType::heat) {
    o << fmt::format("solver          heat\n");
    o << fmt::format("time step       {:.4e} s, {} steps to t = {:.4e} s\n", r.dt, r.steps, c.solver.end_time);
    return o.str();
  }
  if (c.solver.type == SolverType::static_equilibrium) {
    o << fmt::format("solver          static, {}\n",
                     c.solver.method == StaticMethod::adr ? "adaptive dynamic relaxation" : "Newton-Raphson");
    o << fmt::format("load steps      {} to pseudo-time {:.4g} (tolerance {:.1e})\n", r.steps, c.solver.end_time,
                     c.solver.tolerance);
    return o.str();
  }
  const bool penalty = !c.contact.indenters.empty() || !c.contact.projectiles.empty();
  o << fmt::format("stable step     {:.4e} s ({}{})\n", r.stable_dt,
                   r.fe_elements ? "Silling-Askari bound and the elements'" : "Silling-Askari bound",
                   penalty ? ", with the contact penalty" : "");
  if (c.solver.type == SolverType::implicit_dynamic)
    o << fmt::format("time step       {:.4e} s (implicit Newmark, {:.1f} x the stable step)\n", r.dt,
                     r.dt / r.stable_dt);
  else
    o << fmt::format("time step       {:.4e} s{}\n", r.dt,
                     c.solver.time_step ? " (fixed)" : fmt::format(" (safety factor {})", c.solver.safety_factor));
  o << fmt::format("steps           {} to t = {:.4e} s\n", r.steps, c.solver.end_time);
  return o.str();
}

Frame make_frame(const System& s, double time, int64_t step) {
  const auto& P = s.particles;
  Frame f;
  f.time = time;
  f.step = step;
  f.dimension = s.dimension;
  f.points = P.X;
  auto vec = [&](const std::string& name, const std::vector<Vec3>& v) {
    FrameField ff{name, 3, {}};
    ff.data.reserve(3 * v.size());
    for (const auto& x : v) ff.data.insert(ff.data.end(), {x.x, x.y, x.z});
    f.fields.push_back(std::move(ff));
  };
  auto scal = [&](const std::string& name, auto get) {
    FrameField ff{name, 1, {}};
    ff.data.resize(P.size());
    for (std::size_t i = 0; i < P.size(); ++i) ff.data[i] = get(i);
    f.fields.push_back(std::move(ff));
  };
  vec("displacement", P.u);
  vec("velocity", P.v);
  vec("force_density", P.f);
  scal("damage", [&](std::size_t i) { return P.damage[i]; });
  scal("energy_density", [&](std::size_t i) { return P.energy[i]; });
  scal("block", [&](std::size_t i) { return static_cast<double>(P.block[i]); });
  scal("volume", [&](std::size_t i) { return P.volume[i]; });
  if (s.heat.active()) {
    scal("temperature", [&](std::size_t i) { return s.heat.T[i]; });
    vec("heat_flux", s.heat.flux);
  }
  // The models' own fields (material/model.hpp), once per name: a run with two materials
  // of one model writes its fields once.
  std::vector<ModelField> extra;
  for (const auto& m : s.models) m->fields(s, extra);
  for (auto& mf : extra) {
    bool seen = false;
    for (const auto& ff : f.fields) seen = seen || ff.name == mf.name;
    if (seen || mf.values.size() != P.size()) continue;
    f.fields.push_back(FrameField{mf.name, 1, std::move(mf.values)});
  }
  return f;
}

// CPU time of the process so far (all threads) [s]: with the wall time, it tells how
// much of the machine a run had (benchmarks on shared machines).
double cpu_seconds() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return static_cast<double>(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
}

void write_frame_files(const std::string& directory, const std::string& base, const Frame& f, double time,
                       PvdIndex& pvd, const Decomposition* dd) {
  const fs::path dir = directory;
  if (!dd) {
    const std::string name = "frames/" + base + ".vtu";
    write_vtu((dir / name).string(), f);
    pvd.add(time, name);
    pvd.write();
    return;
  }
  // One piece per rank, its own particles; the index once all pieces are complete.
  write_vtu((dir / "frames" / fmt::format("{}_p{}.vtu", base, dd->rank)).string(), frame_subset(f, dd->owned));
  any_rank(*dd, false);  // a barrier
  if (dd->rank != 0) return;
  std::vector<std::string> pieces;
  for (int r = 0; r < dd->size; ++r) pieces.push_back(fmt::format("{}_p{}.vtu", base, r));
  const std::string name = "frames/" + base + ".pvtu";
  write_pvtu((dir / name).string(), f, pieces);
  pvd.add(time, name);
  pvd.write();
}

double peak_memory_bytes() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return static_cast<double>(ru.ru_maxrss) * 1024.0;
}

namespace {

// Crack tracking for decks with precracks: the front of the damage grown from the
// first precrack's second point, along that precrack. A particle is cracked at damage
// >= kCrackDamage; the crack is the cracked particles joined to the precrack's tip
// (within one horizon of it) through hops of at most 1.5 spacings (connected_crack), so
// damage elsewhere (under an impactor) does not count. Its length is the furthest such
// particle's distance from the tip, measured along the precrack's direction.
constexpr double kCrackDamage = 0.35;

struct CrackTracker {
  bool active = false;
  Vec3 origin, direction;
  double band = 0, seed = 0, link = 0;
  std::vector<std::pair<double, double>> history;  // (time, length)

  std::vector<uint8_t> path(const System& s) const {
    return connected_crack(s.particles, origin, kCrackDamage, seed, link);
  }
  CrackFront front(const System& s, const std::vector<uint8_t>& on) const {
    return crack_front(s.particles, origin, direction, kCrackDamage, band, &on);
  }

  CrackTracker(const Config& c) {
    bool damage = false;
    for (const auto& m : c.materials) damage = damage || m.damage.enabled;
    if (!damage || c.precracks.empty() || c.precracks[0].points.size() < 2) return;
    const auto& pts = c.precracks[0].points;
    origin = pts[1];
    direction = pts[1] - pts[0];
    direction.z = 0;
    if (norm(direction) == 0) return;
    direction = direction / norm(direction);
    band = 1e300;
    seed = c.horizon;
    link = 1.5 * c.spacing;
    active = true;
  }
  void record(const System& s, double t) {
    if (!active) return;
    const CrackFront f = front(s, path(s));
    history.emplace_back(t, f.found ? f.length : 0.0);
  }
};

// Least-squares slope of length against time over samples with t in [t0, t1].
double fitted_speed(const std::vector<std::pair<double, double>>& h, double l0, double l1) {
  double n = 0, st = 0, sl = 0, stt = 0, stl = 0;
  for (const auto& [t, l] : h)
    if (l >= l0 && l <= l1) {
      n += 1;
      st += t;
      sl += l;
      stt += t * t;
      stl += t * l;
    }
  if (n < 3) return 0;
  const double den = n * stt - st * st;
  return den > 0 ? (n * stl - st * sl) / den : 0;
}

// Thermal shock figures (2-D): for each thermal boundary condition, the cracks crossing
// the lattice row 2 horizons inside its layer (damage >= kCrackDamage; cracks closer than
// 2 horizons count as one), their positions along the layer and their spacing
// (damage/crack_metrics.hpp, cracks_across_line).
// Every particle is read once, streamed through rank 0 in global order (stream_on_lead:
// O(N / ranks) held there, collective): first each layer's extent and mean position and the
// body's centre, then, on rank 0, the particles of each measuring row (a lattice row: small
// by nature), whose damage decides where a crack crosses. Returns the figures on rank 0
// (an empty object elsewhere).
nlohmann::ordered_json edge_cracks(const Config& c, const System& s, const Decomposition* d) {
  nlohmann::ordered_json out = nlohmann::ordered_json::object();
  const std::size_t nb = s.heat.boundary.size();
  // Per held particle: a bit per boundary layer it belongs to (its owner's lists).
  std::vector<uint32_t> member(s.particles.size(), 0);
  for (std::size_t n = 0; n < nb && n < 32; ++n)
    for (uint32_t i : s.heat.boundary[n].particles) member[i] |= 1u << n;
  struct Layer {
    double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300}, sum[2] = {0, 0};
    std::size_t count = 0;
    double at = 0;
    int normal = 0;
    std::vector<Vec3> row;  // (along, normal, -) of the particles on the measuring row
    std::vector<double> damage;
  };
  std::vector<Layer> layers(std::min<std::size_t>(nb, 32));
  Vec3 centre;
  std::size_t count = 0;
  stream_on_lead(
      s, d, 3,
      [&](uint32_t i, std::vector<double>& v) {
        v.push_back(s.particles.X[i].x);
        v.push_back(s.particles.X[i].y);
        v.push_back(static_cast<double>(member[i]));
      },
      [&](std::size_t, const double* v) {
        centre += Vec3{v[0], v[1], 0.0};
        ++count;
        const auto bits = static_cast<uint32_t>(v[2]);
        for (std::size_t n = 0; n < layers.size(); ++n) {
          if (!(bits >> n & 1u)) continue;
          Layer& L = layers[n];
          for (int k = 0; k < 2; ++k) L.lo[k] = std::min(L.lo[k], v[k]), L.hi[k] = std::max(L.hi[k], v[k]), L.sum[k] += v[k];
          ++L.count;
        }
      });
  centre = centre / static_cast<double>(std::max<std::size_t>(1, count));
  const double rows = std::round(2 * c.horizon / c.spacing) * c.spacing, tol = 0.5 * c.spacing;
  for (Layer& L : layers) {
    if (!L.count) continue;
    L.normal = L.hi[0] - L.lo[0] < L.hi[1] - L.lo[1] ? 0 : 1;
    const double mean = L.sum[L.normal] / static_cast<double>(L.count);
    L.at = mean + (centre[L.normal] > mean ? rows : -rows);
  }
  stream_on_lead(
      s, d, 3,
      [&](uint32_t i, std::vector<double>& v) {
        v.push_back(s.particles.X[i].x);
        v.push_back(s.particles.X[i].y);
        v.push_back(s.particles.damage[i]);
      },
      [&](std::size_t, const double* v) {
        for (Layer& L : layers)
          if (L.count && std::abs(v[L.normal] - L.at) <= tol) L.row.push_back({v[0], v[1], 0.0}), L.damage.push_back(v[2]);
      });
  for (std::size_t n = 0; n < layers.size(); ++n) {
    const Layer& L = layers[n];
    if (!L.count) continue;
    const LineCracks lc = cracks_across_line(L.row, L.damage, 1 - L.normal, L.normal, L.at, tol, kCrackDamage, 2 * c.horizon);
    nlohmann::ordered_json e;
    e["line"] = L.at;
    e["count"] = lc.positions.size();
    e["positions"] = lc.positions;
    e["mean_spacing"] = lc.mean_spacing;
    e["median_spacing"] = lc.median_spacing;
    out[s.heat.boundary[n].name] = e;
  }
  return out;
}

}  // namespace

std::string model_list(bool (*keep)(const ModelTraits&)) {
  std::string names;
  for (const ModelEntry& e : model_registry())
    if (keep(e.traits)) names += (names.empty() ? "" : ", ") + e.traits.name;
  return names;
}

std::string distributed_limits(const Config& c, const System& s, const RunOptions& o) {
  // The models a decomposed run can split (ModelTraits::unified or rows_local), from the
  // registry: no model is named here.
  // A model that owns its force pass sets rows_local when its pass computes the owned
  // rows alone and exchanges what they read of the neighbours (nonlinear_solid).
  auto split_models = [] { return model_list([](const ModelTraits& t) { return t.unified || t.rows_local; }); };
  for (const auto& m : s.models)
    if (!m->unified() && !m->traits().rows_local)
      return "model " + m->traits().name + " is not split over ranks (the models that are: " + split_models() + ")";
  // Heat conduction splits with either integration (each rank advances its owned
  // temperatures and receives its ghosts'; the backward-Euler step a distributed CG).
  // Finite-element regions split on the whole system held by every rank (fe/fe_region.hpp
  // FeRegion::split: the owner of a node evaluates its elements). Short-range contact
  // reads particles the split does not keep current (an interpolated particle within
  // reach is sent, not interpolated here), and the heat solver's boundary lists do not
  // know the elements: those stay on one rank.
  if (s.fe && s.contact.enabled())
    return "finite-element regions are not split over ranks with short-range contact (without it they are)";
  if (s.fe && s.heat.active())
    return "finite-element regions are not split over ranks with heat conduction (without it they are)";
  // Rigid projectiles split: each rank pushes its owned particles, the force on the body
  // is a grid sum (contact/rigid_contact.cpp) and every rank advances the same body.
  (void)c;
  (void)o;
  return "";
}

// The cores in this process's CPU affinity mask (0 when unknown).
static int affinity_cores() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof(set), &set) != 0) return 0;
  return CPU_COUNT(&set);
}

// state_digest of a run with local particles, on rank 0 (others get 0), without the
// whole state on rank 0: u, v and damage stream through it a slice of global ids at a
// time (parallel/lead_view.hpp) into three CRCs, joined as the CRC of u, then v, then
// damage of every particle (zlib crc32_combine). The one figure that reads every
// particle; at the end of the run only. Collective.
static uint32_t streamed_state_digest(const System& s, const Decomposition& d) {
  uLong crc[3] = {crc32(0L, Z_NULL, 0), crc32(0L, Z_NULL, 0), crc32(0L, Z_NULL, 0)};
  stream_on_lead(
      s, &d, 7,
      [&](uint32_t i, std::vector<double>& v) {
        const auto& P = s.particles;
        v.insert(v.end(), {P.u[i].x, P.u[i].y, P.u[i].z, P.v[i].x, P.v[i].y, P.v[i].z, P.damage[i]});
      },
      [&](std::size_t, const double* v) {
        static_assert(sizeof(Vec3) == 3 * sizeof(double));
        crc[0] = crc32(crc[0], reinterpret_cast<const Bytef*>(v), 3 * sizeof(double));
        crc[1] = crc32(crc[1], reinterpret_cast<const Bytef*>(v + 3), 3 * sizeof(double));
        crc[2] = crc32(crc[2], reinterpret_cast<const Bytef*>(v + 6), sizeof(double));
      });
  const auto n = static_cast<z_off_t>(d.global_particles);
  const uLong uv = crc32_combine(crc[0], crc[1], n * static_cast<z_off_t>(sizeof(Vec3)));
  return static_cast<uint32_t>(crc32_combine(uv, crc[2], n * static_cast<z_off_t>(sizeof(double))));
}

uint32_t state_digest(const System& s) {
  const auto& P = s.particles;
  uLong crc = crc32(0L, Z_NULL, 0);
  auto add = [&](const void* p, std::size_t bytes) {
    crc = crc32(crc, static_cast<const Bytef*>(p), static_cast<uInt>(bytes));
  };
  add(P.u.data(), P.u.size() * sizeof(Vec3));
  add(P.v.data(), P.v.size() * sizeof(Vec3));
  add(P.damage.data(), P.damage.size() * sizeof(double));
  return static_cast<uint32_t>(crc);
}

// The explicit run as an object: the constructor sets up the system, the solver and the
// output and writes the first frame; advance() takes steps; finish() writes history.csv
// and summary.json. run_deck is constructor, advance to the end, finish.
struct ExplicitRun::State {
  Config config;
  RunOptions options;
  std::chrono::steady_clock::time_point wall_start;
  System s;
  std::unique_ptr<Loads> loads;
  CheckReport check;
  fs::path dir;
  std::unique_ptr<PvdIndex> pvd;
  std::unique_ptr<ExodusOutput> exodus;  // output.format exodus
  std::unique_ptr<ExplicitSolver> solver;
  std::ostringstream history;
  double max_balance_error = 0;
  int frame_count = 0;
  std::unique_ptr<CrackTracker> crack;
  int64_t total = 0;
  bool adaptive = false;
  int adaptive_every = 1;
  double end_time = 0;
  double dt_nominal = 0, dt_min = 0, dt_max = 0;
  int64_t history_every = 1;
  int frames = 1;
  std::unique_ptr<Progress> progress;
  std::string status = "completed";
  int exit_code = 0;
  std::string message;
  int next_frame = 1;
  double cpu_start = 0;
  bool stopped = false;   // the loop has ended (end reached, interrupted, non-finite or stopped)
  bool finished = false;  // finish() has run
  nlohmann::ordered_json summary;
  // Coupled heat conduction (thermal/heat.hpp): after each mechanical step the temperature
  // advances time_scale times its step, in as many forward-Euler sub-steps as its stability
  // asks (one backward-Euler step when implicit); the next force pass sees the new thermal
  // strain (staggered, one-step lag).
  std::unique_ptr<HeatSolver> heat;
  double heat_stable = 0, heat_initial = 0;
  int heat_substeps = 1;
  // The thermal work by the trapezoidal rule (thermal/heat.hpp thermal_strain_work): a
  // heat step's change of the thermal strain is booked after the next force pass, which
  // is the first to see it, as the mean of its work at the force states before and after.
  std::vector<double> strain_change;
  double pending_work = 0;
  // A run split over MPI ranks (parallel/decomposition.hpp); null in serial runs. Rank 0
  // (lead) writes history.csv, summary.json, frames.pvd and the .pvtu of each frame; each
  // rank writes its own piece of every frame.
  std::unique_ptr<Decomposition> dd;
  bool lead = true;
  // With local particles (each rank holds only the particles it reads) rank 0 holds no
  // copy of the whole system (parallel/lead_view.hpp): `cracked` is the cracked particles
  // (damage >= kCrackDamage) of every rank, on rank 0 in global order, gathered by sync()
  // for the crack tracking and the summary's crack figures (they read no other particle:
  // damage/crack_metrics.hpp, crack_angle.hpp); empty on the other ranks.
  System cracked;
  std::size_t cracked_most = 0;  // the most particles `cracked` held
  bool local_particles() const { return dd && dd->local_particles && dd->size > 1; }
  // Before a history row, a frame, a checkpoint or the summary: the whole system's count of
  // broken bonds (s.broken) on every rank, and every particle's state on every rank
  // without local particles (gather_state); with local particles rank 0's `cracked`.
  void sync() {
    if (!dd) return;
    gather_state(s, *dd);
    if (local_particles()) {
      gather_cracked(s, dd.get(), kCrackDamage, cracked.particles);
      cracked_most = std::max(cracked_most, cracked.particles.size());
    }
  }
  // What the crack tracking reads after sync(): rank 0's cracked particles with local
  // particles (other ranks' figures are never written), else the system itself.
  const System& cracks() const { return local_particles() ? cracked : s; }

  void advance_heat() {
    if (!heat) return;
    Ledger& g = solver->ledger();
    if (!strain_change.empty()) g.thermal_work += pending_work + 0.5 * thermal_strain_work(s, strain_change);
    const std::vector<double> before = s.thermal_strain;
    const double h = solver->dt() * config.thermal.time_scale / heat_substeps;
    for (int k = 0; k < heat_substeps; ++k) heat->step(h);
    strain_change.assign(s.thermal_strain.size(), 0.0);
    if (before.size() == s.thermal_strain.size())
      for (std::size_t i = 0; i < before.size(); ++i) strain_change[i] = s.thermal_strain[i] - before[i];
    pending_work = 0.5 * thermal_strain_work(s, strain_change);
  }

  void record_history() {
    const Ledger& g = solver->ledger();
    // Exact sums and maxima over the owned particles (driver/summary.hpp; collective when
    // decomposed); s.broken and s.initial_bonds count the whole system's bonds.
    const DamageStats dstat = damage_stats(s);
    const double dmax = dstat.max, dmean = dstat.mean;
    const double broken_fraction =
        s.initial_bonds ? static_cast<double>(s.broken) / static_cast<double>(s.initial_bonds) : 0.0;
    max_balance_error = std::max(max_balance_error, std::abs(g.balance_error()));
    history << fmt::format("{:.9e},{},{:.6e},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.6e},{:.6e},{:.6f},{:.9f}",
                           solver->time(), solver->steps(), solver->dt(), g.kinetic, g.strain, g.external_work,
                           g.dissipated, g.damped, g.balance_error(), broken_fraction, dmax, dmean);
    for (const auto& L : loads->loads())
      history << fmt::format(",{:.9e},{:.9e},{:.9e}", L.reaction.x, L.reaction.y, L.reaction.z);
    for (const auto& p : loads->projectiles())
      for (const Vec3* q : {&p.x, &p.v, &p.a, &p.force, &p.a_filtered})
        history << fmt::format(",{:.9e},{:.9e},{:.9e}", q->x, q->y, q->z);
    if (s.block_names.size() > 1)
      for (const Vec3& v : body_velocities(s)) history << fmt::format(",{:.9e},{:.9e},{:.9e}", v.x, v.y, v.z);
    if (s.fe) history << fmt::format(",{:.9e}", s.fe->coupling_work);
    if (s.heat.active()) history << fmt::format(",{:.9e},{:.9e},", g.thermal_work, s.heat.time) << heat_history_row(s);
    history << "\n";
  }
  void write_frame() {
    if (exodus) exodus->write(s, dd.get(), solver->time());  // output.format exodus or both
    if (!config.output.writes_vtu()) {
      ++frame_count;
      return;
    }
    const std::string base = fmt::format("frame_{:05d}", frame_count++);
    if (s.heat.active()) update_heat_flux(s);
    write_frame_files(dir.string(), base, make_frame(s, solver->time(), solver->steps()), solver->time(), *pvd,
                      dd.get());
  }
  bool at_end() const {
    return adaptive ? solver->time() >= end_time * (1 - 1e-12) : solver->steps() >= total;
  }

  // Checkpoint and restart (output/checkpoint.hpp): the run's whole state, the solver's,
  // the system's and the loads', and the output bookkeeping (history rows so far, frames
  // and the PVD index), so that a restart continues history.csv and frames.pvd without
  // a lost or repeated row or frame.
  void checkpoint(StateArchive& a) {
    a.check("run", std::string("explicit"), "a run of kind");
    solver->checkpoint(a);
    checkpoint_system(s, a);
    loads->checkpoint(a);
    std::string rows = history.str();
    a.io("history", rows);
    a.io("max_balance_error", max_balance_error);
    a.io("frame_count", frame_count);
    a.io("next_frame", next_frame);
    a.io("total", total);
    a.io("dt_nominal", dt_nominal);
    a.io("dt_min", dt_min);
    a.io("dt_max", dt_max);
    std::vector<double> times, crack_rows;
    std::string files;
    for (const auto& [t, f] : pvd->entries()) times.push_back(t), files += f + "\n";
    for (const auto& [t, l] : crack->history) crack_rows.push_back(t), crack_rows.push_back(l);
    a.io("pvd_times", times);
    a.io("pvd_files", files);
    a.io("crack_history", crack_rows);
    a.io("heat_initial", heat_initial);
    a.io_particles("heat_strain_change", strain_change);  // per particle: from the owners on ranks
    a.io("heat_pending_work", pending_work);
    if (!a.loading()) return;
    history = std::ostringstream();
    history << rows;
    std::vector<std::pair<double, std::string>> entries;
    std::size_t at = 0;
    for (double t : times) {
      const std::size_t end = files.find('\n', at);
      if (end == std::string::npos) throw Error("checkpoint: the frame index is shorter than its list of times");
      entries.emplace_back(t, files.substr(at, end - at));
      at = end + 1;
    }
    pvd->set_entries(std::move(entries));
    crack->history.clear();
    for (std::size_t k = 0; k + 1 < crack_rows.size(); k += 2) crack->history.emplace_back(crack_rows[k], crack_rows[k + 1]);
  }
  std::string checkpoint_path() const { return (dir / "checkpoint.hzc").string(); }
  // Also rewrites history.csv with the rows so far, so that a run killed later keeps on
  // disk what its checkpoint holds. On several ranks every rank lists the same records;
  // the per-particle and per-bond ones are gathered from their owners onto rank 0
  // (gather_checkpoint), which alone writes: one file of the global state, in index
  // order, the same bytes a run on any rank count would restart from.
  void write_checkpoint() {
    if (dd && dd->local_particles && dd->size > 1) {
      write_checkpoint_streamed();
      return;
    }
    sync();  // the global broken-bond count (and every particle's state) on every rank
    CheckpointWriter w;
    checkpoint(w);
    if (dd) gather_checkpoint(s, *dd, w);
    std::string failure;
    if (lead) {
      try {
        // history.csv first: once the checkpoint file is on disk, so are its rows.
        write_file_atomic((dir / "history.csv").string(), history.str());
        w.write(checkpoint_path());
      } catch (const OutputError& e) {
        failure = e.what();
      }
    }
    // Every rank stops on rank 0's output error (the loop's collectives stay matched).
    if (dd ? any_rank(*dd, !failure.empty()) : !failure.empty())
      throw OutputError(lead ? failure : "rank 0 could not write the checkpoint");
  }
  // Local particles: no rank holds the whole file (parallel/checkpoint_stream.hpp): rank 0
  // writes the records as they come from the owners, in windows of global ids.
  void write_checkpoint_streamed() {
    s.broken = global_broken_bonds(s, *dd);  // the file's count is the whole system's
    CheckpointWriter records(CheckpointWriter::Keep::list);
    checkpoint(records);
    // Every record goes to rank 0's file as the run lists it (no copy of the state).
    auto send = [&](CheckpointStream* out) {
      CheckpointSender sender(s, *dd, records, out);
      checkpoint(sender);
      sender.end();
    };
    std::string failure;
    bool streamed = false;
    if (lead) {
      try {
        // history.csv first: once the checkpoint file is on disk, so are its rows.
        write_file_atomic((dir / "history.csv").string(), history.str());
        write_file_atomic(checkpoint_path(), [&](std::ostream& o) {
          streamed = true;
          CheckpointStream out(&o);
          send(&out);
        });
      } catch (const OutputError& e) {
        failure = e.what();
      }
      if (!streamed) {  // the file could not be opened: rank 0 still takes its part
        CheckpointStream none(nullptr);
        send(&none);
      }
    } else {
      send(nullptr);
    }
    if (any_rank(*dd, !failure.empty())) throw OutputError(lead ? failure : "rank 0 could not write the checkpoint");
  }
  void read_checkpoint(const std::string& path) {
    try {
      CheckpointReader in(path);
      if (dd && dd->local_particles && dd->size > 1) {
        // Each rank reads the entries of the particles and rows it holds.
        CheckpointWriter mine(CheckpointWriter::Keep::list);
        checkpoint(mine);
        pick_local_entries(s, *dd, mine, in);
      } else if (dd && dd->local_rows) {
        // The file holds the whole system's bonds: each rank keeps its own rows.
        CheckpointWriter mine(CheckpointWriter::Keep::list);
        checkpoint(mine);
        keep_local_bonds(s, *dd, mine.bond_records(), in);
      }
      checkpoint(in);
      in.finish();
    } catch (const Error& e) {
      throw Error(fmt::format("{}: --restart: {}", config.deck_file, e.what()));
    }
    steps_at_start = solver->steps();
  }
  int64_t steps_at_start = 0;  // a restart's first step - 1
};

ExplicitRun::ExplicitRun(Config config, const RunOptions& options) : st_(std::make_unique<State>()) {
  State& r = *st_;
  r.config = std::move(config);
  r.options = options;
  Config& c = r.config;
  if (c.solver.type != SolverType::explicit_dynamic)
    throw Error("a step-by-step run needs solver.type explicit; static and implicit_dynamic decks run to the end");
  r.lead = world_rank() == 0;
  if (!r.lead) r.options.quiet = true;
  apply_run_options(c, options);
  if (options.threads > 0) omp_set_num_threads(options.threads);
  // More threads than the cores this process may run on (mpirun binds each of 1 or 2
  // ranks to one core by default): the threads would share them. Said once, by rank 0.
  if (const int cores = affinity_cores(); r.lead && cores > 0 && omp_get_max_threads() > cores)
    fmt::print(stderr,
               "horizon: warning: {} threads but this process may run on {} core(s) only (CPU affinity); under "
               "mpirun give each rank its cores (--map-by slot:PE={} or --bind-to none)\n",
               omp_get_max_threads(), cores, omp_get_max_threads());
  r.wall_start = std::chrono::steady_clock::now();
  r.dir = c.output.directory;
  prepare_output_directory(r.dir.string(), "frames");  // before the (long) set-up

  // An MPI build holds on each rank only the bond rows it computes when the deck allows
  // it (local_rows_allowed): the split is decided before the families are built, and the
  // run decomposed before any pass over the rows. Other decks are built whole on every
  // rank and decomposed below.
  // HORIZON_MPI_WHOLE_SYSTEM=1 builds the whole system on every rank as before local rows
  // existed (the same bits; for the memory comparison of docs/benchmarks.md).
  // On more than one rank, a deck that local_particles_allowed also holds only the
  // particles it reads (local particles; a restart too: each rank reads its particles'
  // entries of the checkpoint by global id); HORIZON_MPI_LOCAL_PARTICLES=0 keeps every particle
  // on every rank with local rows (the comparison of docs/benchmarks.md).
  const char* whole = std::getenv("HORIZON_MPI_WHOLE_SYSTEM");
  const char* particles_env = std::getenv("HORIZON_MPI_LOCAL_PARTICLES");
  const bool local_rows = mpi_built() && local_rows_allowed(c) && !(whole && std::string(whole) == "1");
  const bool local_particles = local_rows && world_size() > 1 && local_particles_allowed(c) &&
                               !(particles_env && std::string(particles_env) == "0");
  if (local_particles) r.dd = std::make_unique<Decomposition>();
  r.s = local_particles ? build_system_split(c, *r.dd) : local_rows ? build_system_split(c) : build_system(c);
  if (local_rows) {
    if (const std::string why = distributed_limits(c, r.s, options); !why.empty())
      throw Error(fmt::format("{}: internal error: a deck built with local rows cannot be split: {}", c.deck_file, why));
    if (!r.dd) r.dd = std::make_unique<Decomposition>();
    r.dd->local_rows = true;
    decompose(r.s, *r.dd, c.spacing);
  }
  r.loads = std::make_unique<Loads>(c, r.s);
  r.loads->apply_initial_conditions(c, r.s);
  r.check = check_system(c, r.s);
  if (!options.quiet) fmt::print(stderr, "{}", format_check(c, r.check));

  r.pvd = std::make_unique<PvdIndex>((r.dir / "frames.pvd").string());
  if (c.output.writes_exodus())
    r.exodus = std::make_unique<ExodusOutput>((r.dir / c.output.exodus_file).string());

  r.solver = std::make_unique<ExplicitSolver>(r.s, *r.loads, r.check.dt, c.solver.damping);
  r.solver->initialize();
  if (mpi_built() && !r.dd) {
    // An MPI build decomposes every run it can, on one rank too, so that one rank and
    // many give the same bits (parallel/decomposition.hpp); a deck it cannot split runs
    // serially on one rank and is refused on more.
    const std::string why = distributed_limits(c, r.s, options);
    if (why.empty()) {
      r.dd = std::make_unique<Decomposition>();
      decompose(r.s, *r.dd, c.spacing);
    } else if (world_size() > 1) {
      throw Error(fmt::format("{}: this deck cannot run on {} MPI ranks yet: {}; run it on one rank",
                              c.deck_file, world_size(), why));
    }
  }
  if (r.s.heat.active()) {
    r.heat = std::make_unique<HeatSolver>(r.s, c.thermal.integration);
    r.heat_stable = heat_stable_step(r.s);
    r.heat_initial = heat_content(r.s);
    const double h = r.check.dt * c.thermal.time_scale;
    if (c.thermal.integration == HeatIntegration::explicit_euler)
      r.heat_substeps = std::max(1, static_cast<int>(std::ceil(h / (c.solver.safety_factor * r.heat_stable))));
    if (!options.quiet)
      fmt::print(stderr, "heat            {} Euler, {:.4e} s per step ({} x the mechanical step, {} sub-steps; "
                         "stable explicit heat step {:.4e} s)\n",
                 c.thermal.integration == HeatIntegration::implicit_euler ? "backward" : "forward", h,
                 c.thermal.time_scale, r.heat_substeps, r.heat_stable);
  }

  // History columns: the ledger, damage, and the force each load applies.
  r.history << "time,step,dt,kinetic_energy,strain_energy,external_work,dissipated_energy,damped_energy,"
               "energy_balance_error,broken_bond_fraction,damage_max,damage_mean";
  for (const auto& L : r.loads->loads()) r.history << "," << L.name << "_fx," << L.name << "_fy," << L.name << "_fz";
  // Each projectile: position, velocity, acceleration, the contact force on it, and the
  // low-pass acceleration (the acceleration itself without a filter).
  for (const auto& p : r.loads->projectiles())
    for (const char* q : {"x", "y", "z", "vx", "vy", "vz", "ax", "ay", "az", "fx", "fy", "fz", "ax_filtered",
                          "ay_filtered", "az_filtered"})
      r.history << "," << p.config().name << "_" << q;
  // With two or more bodies (a projectile and its target), each body's centre-of-mass velocity.
  if (r.s.block_names.size() > 1)
    for (const auto& name : r.s.block_names) r.history << "," << name << "_vx," << name << "_vy," << name << "_vz";
  // Finite-element regions: the work of the force-based coupling (fe/fe_region.hpp).
  if (r.s.fe) r.history << ",fe_coupling_work";
  if (r.s.heat.active()) r.history << ",thermal_work,heat_time," << heat_history_header(r.s);
  r.history << "\n";
  r.crack = std::make_unique<CrackTracker>(c);

  r.total = r.check.steps;
  // The adaptive step (models with ModelTraits::adaptive_time_step; the deck allows it for
  // no other): recomputed from the current bond stiffness every adaptive_every steps; the
  // run ends at end_time, frames fall due by time.
  r.adaptive = c.solver.adaptive_time_step;
  r.adaptive_every = std::max(1, c.solver.adaptive_every);
  r.end_time = c.solver.end_time;
  r.dt_nominal = r.dt_min = r.dt_max = r.check.dt;
  r.history_every = std::max(1, c.output.history_every);
  r.frames = std::max(1, c.output.frames);
  if (options.restart) {
    // The state of the checkpoint replaces the initial one; the index lists the frames
    // written before it (later ones, from an interrupted run, are written again).
    r.read_checkpoint(*options.restart);
    // Every rank holds the state of its particles now: the ghosts follow the loaded positions.
    if (r.dd) refresh_ghosts(r.s, *r.dd);
    if (r.lead) r.pvd->write();
    if (!options.quiet)
      fmt::print(stderr, "restart         from {} at step {}, t = {:.4e} s\n", *options.restart, r.solver->steps(),
                 r.solver->time());
  } else {
    // Local particles: the initial broken-bond count and rank 0's cracked particles (the
    // first row, the crack tracker's first record).
    if (r.local_particles()) r.sync();
    r.record_history();
    r.write_frame();
    r.crack->record(r.cracks(), 0);
  }

  if (options.handle_signals) install_interrupt_handler();
  r.progress = std::make_unique<Progress>(r.total, static_cast<double>(r.s.bonds.size()), c.output.progress_every);
  if (!r.options.quiet && r.dd && r.dd->size > 1)
    fmt::print(stderr,
               "ranks           {} (recursive coordinate bisection; {} particles on rank 0, {} held {}, {} bonds held "
               "{})\n",
               r.dd->size, r.dd->owned.size(), r.s.particles.size(),
               r.dd->local_particles ? "(with its ghosts)" : "(every particle)", r.s.bonds.size(),
               r.dd->local_rows ? "(its rows)" : "(the whole system on every rank)");
  r.cpu_start = cpu_seconds();
  r.stopped = r.at_end();
}

ExplicitRun::~ExplicitRun() = default;

int64_t ExplicitRun::advance(int64_t n) {
  State& r = *st_;
  int64_t taken = 0;
  if (r.stopped) return 0;
  const Config& c = r.config;
  ExplicitSolver& solver = *r.solver;
  try {
    while (taken < n && !r.at_end()) {
      const int64_t step = solver.steps() + 1;
      bool last = step == r.total;
      if (r.adaptive) {
        if (solver.steps() % r.adaptive_every == 0) r.dt_nominal = c.solver.safety_factor * whole_stable_step(r.s);
        double dt = r.dt_nominal;
        if (solver.time() + dt >= r.end_time * (1 - 1e-12)) dt = r.end_time - solver.time(), last = true;
        solver.set_dt(dt);
        r.dt_min = std::min(r.dt_min, r.dt_nominal);
        r.dt_max = std::max(r.dt_max, r.dt_nominal);
        r.total = std::max(r.total, step + 1);
      }
      const bool frame_due = r.adaptive ? last || (solver.time() + solver.dt()) * r.frames >= r.next_frame * r.end_time
                                        : step * r.frames >= static_cast<int64_t>(r.next_frame) * r.total;
      const bool history_due = step % r.history_every == 0 || last;
      solver.step(history_due || frame_due);
      r.advance_heat();
      ++taken;
      if (history_due || frame_due) r.sync();
      if (history_due) {
        r.record_history();
        r.crack->record(r.cracks(), solver.time());
      }
      if (frame_due) {
        r.write_frame();
        ++r.next_frame;
      }
      if (c.output.checkpoint_every > 0 && solver.steps() % c.output.checkpoint_every == 0 && !r.at_end())
        r.write_checkpoint();
      if (!r.options.quiet) r.progress->update(solver.steps(), solver.time());
      const bool interrupted = r.options.handle_signals && interrupt_requested();
      if (r.dd ? any_rank(*r.dd, interrupted) : interrupted) {
        r.status = "interrupted";
        r.exit_code = interrupt_exit_code();
        r.message = fmt::format("{} at step {}, t = {:.4e} s; a final frame was written", interrupt_name(),
                                solver.steps(), solver.time());
        r.stopped = true;
        return taken;
      }
    }
  } catch (const NonFiniteState& e) {
    r.status = "non-finite";
    r.exit_code = 2;
    r.message = e.what();
    r.stopped = true;
    return taken;
  } catch (const OutputError& e) {
    // The frames listed in frames.pvd are complete (written under a temporary name and
    // renamed); the one that failed is not listed. No final frame: the disk said no.
    r.status = "output error";
    r.exit_code = 5;
    r.message = fmt::format("output error: {}; stopped at step {}, frames.pvd lists the {} complete frames", e.what(),
                            solver.steps(), r.pvd->entries().size());
    r.stopped = true;
    return taken;
  }
  if (r.at_end()) r.stopped = true;
  return taken;
}

void ExplicitRun::stop(const std::string& reason) {
  State& r = *st_;
  if (r.stopped) return;
  r.status = "stopped";
  r.message = fmt::format("stopped at step {}, t = {:.4e} s ({}); a final frame was written", r.solver->steps(),
                          r.solver->time(), reason);
  r.stopped = true;
}

bool ExplicitRun::done() const { return st_->stopped; }
bool ExplicitRun::finished() const { return st_->finished; }
const System& ExplicitRun::system() const { return st_->s; }
System& ExplicitRun::system() { return st_->s; }
const Config& ExplicitRun::config() const { return st_->config; }
const Ledger& ExplicitRun::ledger() const { return st_->solver->ledger(); }
const Loads& ExplicitRun::loads() const { return *st_->loads; }
double ExplicitRun::time() const { return st_->solver->time(); }
double ExplicitRun::dt() const { return st_->solver->dt(); }
int64_t ExplicitRun::steps() const { return st_->solver->steps(); }
int64_t ExplicitRun::total_steps() const { return st_->total; }
const std::string& ExplicitRun::status() const { return st_->status; }
std::string ExplicitRun::history_csv() const { return st_->history.str(); }
const nlohmann::ordered_json& ExplicitRun::summary() const { return st_->summary; }
std::string ExplicitRun::output_directory() const { return st_->dir.string(); }
int ExplicitRun::exit_code() const { return st_->exit_code; }

int ExplicitRun::finish() {
  State& r = *st_;
  if (r.finished) return r.exit_code;
  r.stopped = true;
  r.finished = true;
  const Config& config = r.config;
  const RunOptions& options = r.options;
  System& s = r.s;
  ExplicitSolver& solver = *r.solver;
  const fs::path& dir = r.dir;
  const std::string& status = r.status;
  const std::string& message = r.message;
  auto& crack = *r.crack;
  if (!options.quiet) r.progress->finish();
  r.sync();
  if ((r.exit_code != 0 && r.exit_code != 5) || status == "stopped") {
    // The last good state (restored by the solver on a non-finite step) as the final frame.
    solver.update_kinetic();
    r.record_history();
    r.write_frame();
  }
  if (options.handle_signals) clear_interrupt();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - r.wall_start).count();
  const double loop_time = r.progress->elapsed();
  const double loop_cpu_time = cpu_seconds() - r.cpu_start;

  // After an output error, history and summary are tried once (they are small) and their
  // failure only reported.
  auto write_result = [&](const std::string& name, const std::string& text) {
    if (!r.lead) return;
    write_result_file((dir / name).string(), text, r.exit_code == 5);
  };
  write_result("history.csv", r.history.str());

  // Summary: final figures and run statistics.
  const Ledger& g = solver.ledger();
  // The crack figures read the cracked particles alone (rank 0's with local particles).
  const System& o = r.cracks();
  nlohmann::ordered_json j = summary_header(config, s, status, message, solver.steps());
  j["time_step"] = solver.dt();
  if (r.adaptive) j["time_step_range"] = {r.dt_min, r.dt_max};
  j["time"] = solver.time();
  j["threads"] = omp_get_max_threads();
  j["ranks"] = r.dd ? r.dd->size : 1;
  j["state_crc32"] = r.local_particles() ? streamed_state_digest(s, *r.dd) : state_digest(s);
  if (r.dd) {
    // Halo traffic per rank and step (docs/benchmarks.md), from every rank.
    const std::vector<HaloStats> hs = gather_halo_stats(*r.dd);
    // The bond rows each rank holds and its peak resident memory.
    const std::vector<uint64_t> held = gather_on_lead(s.bonds.size());
    // The particles each rank integrates and those it holds (with its ghosts).
    const std::vector<uint64_t> owned = gather_on_lead(r.dd->owned.size());
    const std::vector<uint64_t> particles_held = gather_on_lead(s.particles.size());
    // Local particles with short-range contact: the contact ghosts each rank holds
    // outside its system (parallel/decomposition.hpp ContactGhosts), now and at most.
    const std::vector<uint64_t> contact_ghosts = gather_on_lead(r.dd->contact.id.size());
    const std::vector<uint64_t> contact_ghosts_most = gather_on_lead(r.dd->contact.most);
    const std::vector<uint64_t> rss = gather_on_lead(static_cast<uint64_t>(peak_memory_bytes()));
    nlohmann::ordered_json h = nlohmann::ordered_json::array();
    for (std::size_t k = 0; k < hs.size(); ++k) {
      const double steps = static_cast<double>(std::max<uint64_t>(1, hs[k].steps));
      h.push_back({{"rank", k},
                   {"particles", owned[k]},
                   {"particles_held", particles_held[k]},
                   {"contact_ghosts", contact_ghosts[k]},
                   {"contact_ghosts_most", contact_ghosts_most[k]},
                   {"bonds_held", held[k]},
                   {"peak_memory_bytes", rss[k]},
                   {"messages_per_step", static_cast<double>(hs[k].messages) / steps},
                   {"bytes_per_step", static_cast<double>(hs[k].bytes) / steps},
                   {"ghost_rebuilds", hs[k].rebuilds}});
    }
    j["halo"] = h;
    j["bonds_local"] = r.dd->local_rows;
    j["particles_local"] = r.dd->local_particles;
    // With local particles rank 0 holds no copy of the whole system (parallel/lead_view.hpp):
    // the most cracked particles it gathered for the crack figures.
    if (r.local_particles()) j["lead_cracked_particles_most"] = r.cracked_most;
  }
  j["wall_time_s"] = wall;
  j["loop_time_s"] = loop_time;
  j["loop_cpu_time_s"] = loop_cpu_time;
  j["bond_updates_per_second"] =
      loop_time > 0 ? static_cast<double>(checkpoint_bond_count(s)) * static_cast<double>(solver.steps() - r.steps_at_start) / loop_time : 0.0;
  j["peak_memory_bytes"] = peak_memory_bytes();
  if (s.fe) {
    j["fe"] = {{"elements", s.fe->elements()},
               {"element", s.fe->nodes_per_element == 8 ? "hex8" : "tet4"},
               {"nodes", s.fe->nodes()},
               {"shared_nodes", s.fe->shared_nodes()},
               {"coupling_work", s.fe->coupling_work}};
  }
  summary_state(j, s, g, *r.loads, r.max_balance_error);
  if (r.dd && (r.dd->local_particles || r.dd->size > 1)) {
    // Local particles, or a run on several ranks (a model's fields hold its owned
    // particles' values only): the models' dissipation parts (summary_state's sum, in the
    // same global order) from every owner's field values streamed through rank 0.
    std::vector<ModelField> fields;
    for (const auto& m : s.models) m->fields(s, fields);
    nlohmann::ordered_json parts = nlohmann::ordered_json::object();
    std::vector<std::string> done;
    for (const auto& f : fields) {
      if (!f.dissipation_part || std::find(done.begin(), done.end(), f.name) != done.end()) continue;
      done.push_back(f.name);
      double sum = 0.0;
      stream_on_lead(
          s, r.dd.get(), 2,
          [&](uint32_t i, std::vector<double>& v) {
            v.push_back(i < f.values.size() ? f.values[i] : 0.0);
            v.push_back(s.particles.volume[i]);
          },
          [&](std::size_t, const double* v) { sum += v[0] * v[1]; });
      parts[f.name] = sum;
    }
    if (!parts.empty()) j["energy"]["dissipated_parts"] = parts;
  }
  if (!r.loads->projectiles().empty()) {
    nlohmann::ordered_json pj = nlohmann::ordered_json::object();
    for (const auto& p : r.loads->projectiles()) {
      const Vec3 v0 = p.config().velocity;
      pj[p.config().name] = {{"mass", p.mass()},
                             {"position", {p.x.x, p.x.y, p.x.z}},
                             {"velocity", {p.v.x, p.v.y, p.v.z}},
                             {"initial_speed", norm(v0)},
                             {"final_speed", norm(p.v)},
                             {"impulse", {p.impulse.x, p.impulse.y, p.impulse.z}},
                             {"peak_force", p.peak_force},
                             {"peak_acceleration", p.peak_acceleration},
                             {"peak_filtered_acceleration", p.peak_filtered_acceleration},
                             {"filter_cutoff", p.config().filter_cutoff},
                             {"contact_start", p.contact_start},
                             {"contact_end", p.contact_end},
                             {"penalty_energy", p.penalty_energy}};
    }
    j["projectiles"] = pj;
  }
  if (r.heat) {
    j["thermal"] = heat_summary(s, solver.dt() * config.thermal.time_scale, r.heat_stable, r.heat_initial);
    j["energy"]["thermal_work"] = g.thermal_work;
    if (config.dimension == 2 && s.initial_bonds > 0) {
      nlohmann::ordered_json e = edge_cracks(config, s, r.dd.get());  // collective
      if (r.lead) j["thermal"]["edge_cracks"] = std::move(e);
    }
  }
  // The crack path and front at the end, for the crack and fracture figures below.
  const std::vector<uint8_t> on = crack.active ? crack.path(o) : std::vector<uint8_t>{};
  const CrackFront f = crack.active ? crack.front(o, on) : CrackFront{};
  if (crack.active) {
    const auto branch = branch_distance(o.particles, crack.origin, crack.direction, kCrackDamage, config.spacing,
                                        2.0 * config.horizon, &on);
    nlohmann::ordered_json cj;
    cj["origin"] = {crack.origin.x, crack.origin.y, crack.origin.z};
    cj["length"] = f.found ? f.length : 0.0;
    cj["damage_threshold"] = kCrackDamage;
    cj["tip"] = {f.tip.x, f.tip.y, f.tip.z};
    // Speed before branching: fit over the growth from 2 horizons to the branch point.
    const double l_end = branch ? *branch : (f.found ? f.length : 0.0);
    cj["speed_before_branching"] = fitted_speed(crack.history, 2 * config.horizon, l_end);
    if (branch) {
      cj["branch_distance"] = *branch;
      const Vec3 at = crack.origin + crack.direction * *branch;
      cj["branch_point"] = {at.x, at.y, at.z};
      double t_branch = 0;
      for (const auto& [t, l] : crack.history)
        if (l >= *branch) {
          t_branch = t;
          break;
        }
      cj["branch_time"] = t_branch;
    } else {
      cj["branch_distance"] = nullptr;
    }
    j["crack"] = cj;
  }
  if (s.models.owner() || crack.active) {
    // Tupek's fracture figures (thesis Table 6.1 and 6.2), for any model that breaks bonds
    // from a precrack: dissipated energy per unit thickness (2-D), the crack length from
    // the first precrack's tip, their ratio, and the angle each precrack's crack leaves its
    // tip at (damage/crack_angle.hpp: a line fitted to the damage ridge 2 to 8 horizons
    // from the tip).
    nlohmann::ordered_json fj;
    const double per = config.dimension == 2 ? 1.0 / config.thickness : 1.0;
    fj["dissipated_energy"] = g.dissipated;
    fj["dissipated_energy_per_thickness"] = g.dissipated * per;
    if (crack.active) {
      const double len = f.found ? f.length : 0.0;
      fj["crack_length"] = len;
      fj["energy_per_crack_length"] = len > 0 ? g.dissipated * per / len : 0.0;
    }
    // crack_angles_deg: |angle| from the notch direction (Tupek's Table 6.2 figure);
    // crack_angles_signed_deg: counter-clockwise positive, so that the side the crack
    // turns to can be checked (Kalthoff: + for a notch along +x above the struck strip).
    nlohmann::ordered_json angles = nlohmann::ordered_json::array(), signed_angles = angles;
    for (const auto& pc : config.precracks) {
      if (pc.points.size() < 2) continue;
      Vec3 d = pc.points[1] - pc.points[0];
      d.z = 0;
      if (norm(d) == 0) continue;
      const CrackAngle a = crack_angle(o.particles, pc.points[1], d / norm(d), kCrackDamage, 2 * config.horizon,
                                       8 * config.horizon, config.spacing, config.horizon);
      angles.push_back(a.found ? nlohmann::ordered_json(std::abs(a.degrees)) : nlohmann::ordered_json(nullptr));
      signed_angles.push_back(a.found ? nlohmann::ordered_json(a.degrees) : nlohmann::ordered_json(nullptr));
    }
    fj["crack_angles_deg"] = angles;
    fj["crack_angles_signed_deg"] = signed_angles;
    j["fracture"] = fj;
  }
  const std::string energy_warning = energy_balance_warning(config, r.max_balance_error);
  if (!energy_warning.empty()) j["warnings"] = {energy_warning};
  write_result("summary.json", j.dump(2) + "\n");
  r.summary = j;

  if (!energy_warning.empty() && r.lead) fmt::print(stderr, "horizon: warning: {}\n", energy_warning);
  if (!options.quiet) {
    fmt::print(stderr, "{} in {} ({} steps, {:.3g} bond updates/s); output in {}\n", status, format_duration(wall),
               solver.steps(), j["bond_updates_per_second"].get<double>(), dir.string());
  }
  // A run stopped by its caller says so in summary.json; quiet runs leave stderr alone.
  if (!message.empty() && r.lead && !(options.quiet && status == "stopped")) fmt::print(stderr, "horizon: {}\n", message);
  return r.exit_code;
}


int run_deck(Config config, const RunOptions& options) {
  if (options.restart && config.solver.type != SolverType::explicit_dynamic)
    throw Error(fmt::format("{}: --restart continues explicit runs only (solver.type explicit)", config.deck_file));
  if (config.solver.type == SolverType::heat) return run_heat_deck(std::move(config), options);
  if (config.solver.type != SolverType::explicit_dynamic) return run_implicit_deck(std::move(config), options);
  ExplicitRun run(std::move(config), options);
  run.advance(std::numeric_limits<int64_t>::max());
  return run.finish();
}

}  // namespace horizon
