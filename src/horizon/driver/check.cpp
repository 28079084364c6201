// The check report (`horizon check`, and the set-up of every run): counts, memory, the
// stable step and the step count of a deck's system; the limits of a run split over ranks.
#include <fmt/format.h>

#include <cmath>
#include <sstream>

#include "horizon/driver/explicit_state.hpp"
#include "horizon/driver/model_list.hpp"
#include "horizon/driver/run.hpp"
#include "horizon/fe/fe_region.hpp"
#include "horizon/loading/loads.hpp"
#include "horizon/parallel/decomposition.hpp"
#include "horizon/thermal/heat.hpp"

namespace horizon {

void apply_run_options(Config& c, const RunOptions& o) {
  if (o.output_dir) c.output.directory = *o.output_dir;
  if (o.end_time) c.solver.end_time = *o.end_time;
  if (o.max_memory_gib > 0) c.memory_limit_bytes = o.max_memory_gib * 1024.0 * 1024.0 * 1024.0;
  if (o.backend) {
    if (*o.backend != "cpu" && c.solver.type != SolverType::explicit_dynamic)
      throw Error(fmt::format("{}: --backend {}: the backends take explicit runs only (solver.type explicit)",
                              c.deck_file, *o.backend));
    c.solver.backend = *o.backend;
    c.solver.backend_at = "--backend";
  }
  if (o.coarsen != 1) {
    c.spacing *= o.coarsen;
    c.horizon *= o.coarsen;
    // Bodies' own horizons scale with the deck's (an expression is scaled as a whole).
    for (auto& b : c.bodies)
      if (b.horizon)
        b.horizon = b.horizon->is_constant() ? Expression((*b.horizon)(0) * o.coarsen)
                                             : Expression(fmt::format("({})*{}", b.horizon->text(), o.coarsen));
    if (c.solver.time_step) *c.solver.time_step *= o.coarsen;
  }
}

// The stable step of the whole system: with local rows (parallel/decomposition.hpp) each
// rank sees its rows alone, and a model that owns its force pass its owned rows alone
// (nonlinear_solid); the minimum over ranks is the serial figure, bit for bit (a rank
// that holds every row finds it itself). Collective when decomposed: every rank calls it
// (the set-up's check, each adaptive step).
double whole_stable_step(const System& s) {
  const double dt = stable_time_step(s);
  return s.decomposition ? min_over_ranks(dt) : dt;
}

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
  // A staged run's explicit stage runs from its start_time (0 otherwise).
  const double steps = std::ceil((c.solver.end_time - c.solver.start_time) / dt - 1e-9);
  if (!(steps <= kMaxSteps)) {
    throw Error(fmt::format("{}: the run would take {:.3g} steps of {:.4g} s to end_time {:.4g} s, more than the "
                            "{:g} a run may take; check solver.end_time and solver.time_step (units: seconds)",
                            c.deck_file, steps, dt, c.solver.end_time, kMaxSteps));
  }
  return static_cast<int64_t>(steps);
}

namespace {

// Particles whose family is empty (a model that allows them: material/model.hpp
// fill_state_based_coefficients), over the whole system: a decomposed run counts the
// particles each rank owns. The nodes the finite elements own have no bonds by design.
std::size_t isolated_particles(const System& s) {
  const auto& B = s.bonds;
  const std::vector<uint8_t>* fe = s.fe_coupling ? &s.fe_coupling->owned_particle : nullptr;
  auto alone = [&](std::size_t i) {
    return B.begin(i) == B.end(i) && !(fe && i < fe->size() && (*fe)[i]) ? 1u : 0u;
  };
  uint64_t n = 0;
  if (s.decomposition && !s.owned.empty()) {
    for (uint32_t i : s.owned) n += alone(i);
  } else if (!s.decomposition) {
    for (std::size_t i = 0; i < s.particles.size(); ++i) n += alone(i);
  }
  return static_cast<std::size_t>(s.decomposition ? sum_over_ranks(n) : n);
}

}  // namespace

CheckReport check_system(const Config& c, const System& s) {
  CheckReport r;
  r.isolated = isolated_particles(s);
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
  if (s.heat.active() && s.heat.conduction) r.heat_stable_dt = heat_stable_step(s);
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
  if (r.isolated)
    o << fmt::format("warning         {} particle(s) have no neighbours (the horizon is smaller than their spacing): "
                     "no bond acts on them; loads and contact move them alone\n",
                     r.isolated);
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
    o << fmt::format("load steps      {}{} to pseudo-time {:.4g} (tolerance {:.1e})\n", r.steps,
                     c.solver.load_times.empty() ? "" : " (listed pseudo-times, load_times)", c.solver.end_time,
                     c.solver.tolerance);
    return o.str();
  }
  const bool penalty = !c.contact.indenters.empty() || !c.contact.projectiles.empty();
  if (c.static_stage)  // a staged run (docs/input.md "Solver stages")
    o << fmt::format("stage 1         static, {}, {} load steps to t = {:.4e} s (tolerance {:.1e}); then explicit "
                     "from its state\n",
                     c.static_stage->method == StaticMethod::adr ? "adaptive dynamic relaxation" : "Newton-Raphson",
                     c.static_stage->load_steps, c.static_stage->end_time, c.static_stage->tolerance);
  o << fmt::format("stable step     {:.4e} s ({}{})\n", r.stable_dt,
                   r.fe_elements ? "Silling-Askari bound and the elements'" : "Silling-Askari bound",
                   penalty ? ", with the contact penalty" : "");
  if (c.solver.type == SolverType::implicit_dynamic)
    o << fmt::format("time step       {:.4e} s (implicit Newmark, {:.1f} x the stable step)\n", r.dt,
                     r.dt / r.stable_dt);
  else
    o << fmt::format("time step       {:.4e} s{}\n", r.dt,
                     c.solver.time_step ? " (fixed)" : fmt::format(" (safety factor {})", c.solver.safety_factor));
  if (c.static_stage)
    o << fmt::format("steps           {} from t = {:.4e} s to t = {:.4e} s\n", r.steps, c.solver.start_time,
                     c.solver.end_time);
  else
    o << fmt::format("steps           {} to t = {:.4e} s\n", r.steps, c.solver.end_time);
  return o.str();
}

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

}  // namespace horizon
