#include "horizon/solver/build.hpp"

#include "horizon/contact/rigid_contact.hpp"

#include "horizon/parallel/decomposition.hpp"

#include <fmt/format.h>

#include "horizon/thermal/heat.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "horizon/core/error.hpp"
#include "horizon/fe/fe_region.hpp"
#include "horizon/family/bond_helpers.hpp"
#include "horizon/family/neighbors.hpp"
#include "horizon/family/precrack.hpp"
#include "horizon/geometry/lattice.hpp"
#include "horizon/geometry/region_select.hpp"
#include "horizon/kernels/unified.hpp"
#include "horizon/material/constants.hpp"
#include "horizon/material/influence.hpp"
#include "horizon/solver/forces.hpp"
#include "horizon/solver/forces_general.hpp"
#include "horizon/solver/memory_guard.hpp"

namespace horizon {

namespace {

Dimensioning dimensioning(const Config& c) {
  return {c.dimension, c.plane, c.thickness, c.area, c.horizon};
}

double cell_volume(const Config& c) {
  double v = std::pow(c.spacing, c.dimension);
  if (c.dimension == 2) v *= c.thickness;
  if (c.dimension == 1) v *= c.area;
  return v;
}

std::string point_text(const Vec3& p, int d) {
  std::string s = "(";
  for (int k = 0; k < d; ++k) s += (k ? ", " : "") + fmt::format("{:g}", p[k]);
  return s + ")";
}

// A precrack that crosses no bond (outside every body, or shorter than a bond and between
// two lattice lines) changes nothing: a mistake in the deck, reported as such. Only the
// particles within a horizon of the crack's bounding box are tried.
// `global` (a system with local rows, parallel/decomposition.hpp): a precrack counts as
// cutting when it crosses a bond of any rank's rows. Collective then.
void check_precracks_cut(const System& s, const Config& config, bool global) {
  const auto& X = s.particles.X;
  const int d = config.dimension;
  for (std::size_t c = 0; c < config.precracks.size(); ++c) {
    const PrecrackConfig& pc = config.precracks[c];
    Vec3 lo, hi;
    bounding_box(pc, lo, hi);
    bool cuts = false;
    for (std::size_t i = 0; i < X.size() && !cuts; ++i) {
      bool near = true;
      for (int k = 0; k < d; ++k) near = near && X[i][k] >= lo[k] - config.horizon && X[i][k] <= hi[k] + config.horizon;
      if (!near) continue;
      for (uint64_t k = s.bonds.begin(i); k < s.bonds.end(i) && !cuts; ++k)
        cuts = crosses(X[i], X[s.bonds.nbr[k]], pc, d);
    }
    if (global) cuts = sum_over_ranks(cuts ? 1 : 0) > 0;
    if (!cuts) {
      std::string where;
      if (!pc.facets.empty()) where = fmt::format("(a surface of {} facets)", pc.facets.size());
      else if (pc.radius > 0) where = fmt::format("(a disk of radius {} about {})", pc.radius, point_text(pc.points[0], d));
      else
        for (const Vec3& p : pc.points) where += (where.empty() ? "" : " - ") + point_text(p, d);
      throw Error(fmt::format("{}: precracks[{}] {} crosses no bond: it lies outside the bodies (or between two lattice "
                              "lines); move it into a body, or remove it",
                              config.deck_file, c, where));
    }
  }
}

// Local particles (build_system_split with a Decomposition): keeps the rows flagged in
// `built` and the particles they read, renumbered in ascending global index (so that
// every row keeps its serial order); `built`, `owned` and `owner` follow. The bond
// kinds are kept as they are.
void keep_local_particles(System& s, std::vector<uint8_t>& built, std::vector<uint8_t>& owned,
                          std::vector<int32_t>& owner) {
  const std::size_t n = s.particles.size();
  const Bonds& B = s.bonds;
  std::vector<uint8_t> keep = built;
  for (std::size_t i = 0; i < n; ++i)
    if (built[i])
      for (uint64_t k = B.begin(i); k < B.end(i); ++k) keep[B.nbr[k]] = 1;
  std::vector<uint32_t> local(n, 0);
  uint32_t m = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (keep[i]) local[i] = m++;
  const Particles& P = s.particles;
  Particles Q;
  // The rows are moved down in place (a kept particle's local index is at most its
  // global one, so each bond is written at or before where it is read): no second copy
  // of the bonds, which would double the peak of the build.
  Bonds& L = s.bonds;
  std::vector<uint8_t> built_l, owned_l;
  std::vector<int32_t> owner_l;
  built_l.reserve(m), owned_l.reserve(m), owner_l.reserve(m);
  uint64_t w = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!keep[i]) continue;
    Q.add(P.X[i], P.volume[i], P.density[i], P.block[i], P.material[i]);
    Q.u.back() = P.u[i];
    Q.v.back() = P.v[i];
    Q.id.back() = P.id[i];
    Q.no_fail.back() = P.no_fail[i];
    built_l.push_back(built[i]);
    owned_l.push_back(owned[i]);
    owner_l.push_back(owner[i]);
    const uint64_t a = L.offset[i], b = L.offset[i + 1];
    L.offset[Q.size() - 1] = w;
    for (uint64_t k = a; k < b; ++k, ++w) {
      L.nbr[w] = local[L.nbr[k]];
      L.kind[w] = L.kind[k];
      if (L.length_per_bond) L.lengths[w] = L.lengths[k];
      L.intact[w] = L.intact[k];
    }
  }
  L.offset[Q.size()] = w;
  L.offset.resize(Q.size() + 1);
  L.offset.shrink_to_fit();
  if (w != L.nbr.size()) {  // rows dropped (not built here): release their storage
    L.nbr.resize(w), L.kind.resize(w), L.intact.resize(w);
    L.nbr.shrink_to_fit(), L.kind.shrink_to_fit(), L.intact.shrink_to_fit();
    if (L.length_per_bond) L.lengths.resize(w), L.lengths.shrink_to_fit();
  }
  s.particles = std::move(Q);
  built = std::move(built_l);
  owned = std::move(owned_l);
  owner = std::move(owner_l);
}

// Each particle's own horizon (BodyConfig::horizon: its body's, else the deck's), or
// empty when no body gives one. The options that read one horizon for every bond are
// refused with per-body horizons.
std::vector<double> particle_horizons(const System& s, const Config& config) {
  bool any = false;
  for (const auto& b : config.bodies) any = any || b.horizon.has_value();
  if (!any) return {};
  auto refuse = [&](const std::string& what) {
    throw Error(config.deck_file + ": bodies with their own horizon: " + what +
                " reads one horizon for every bond; not supported with bodies.horizon");
  };
  if (config.partial_volume) refuse("partial_volume");
  if (config.family_box) refuse("family_box");
  if (s.fe) refuse("a finite-element body's coupling");
  if (config.thermal.enabled) refuse("heat conduction (its moments)");
  for (const auto& mat : config.materials) {
    if (mat.influence != InfluenceKind::constant && mat.influence != InfluenceKind::inverse_length)
      refuse("material '" + mat.name + "': an influence function of |xi|/delta (only constant and inverse_length)");
    if (const auto sc = mat.parameters.find("surface_correction"); sc != mat.parameters.end() && sc->second != 0)
      refuse("material '" + mat.name + "': surface_correction");
  }
  const auto& P = s.particles;
  std::vector<double> h(P.size(), config.horizon);
  for (std::size_t i = 0; i < P.size(); ++i) {
    const BodyConfig& body = config.bodies[static_cast<std::size_t>(P.block[i])];
    if (!body.horizon) continue;
    const Vec3& X = P.X[i];
    const double v = (*body.horizon)(0, X.x, X.y, X.z);
    if (!(v > 0) || !(v <= config.horizon * (1 + 1e-12)))
      throw Error(fmt::format("{}: bodies.{}.horizon: {} at the particle ({}, {}, {}); expected a value in (0, {}] (the "
                              "deck's horizon bounds every body's: the families are searched within it)",
                              config.deck_file, body.name, v, X.x, X.y, X.z, config.horizon));
    h[i] = v;
  }
  return h;
}

// The horizon material m's constants take (ModelSetup::config.horizon and dims.horizon):
// the one horizon of its bodies, or, where its particles have several (bodies of
// different horizons, or one that varies in space), the deck's, for the models whose
// forces do not scale with it (ModelTraits::any_horizon). Decided from the deck alone, so
// every rank agrees.
double material_horizon(const Config& config, const MaterialConfig& mat) {
  std::optional<double> one;
  bool several = false;
  for (const auto& body : config.bodies) {
    if (body.material != mat.name || body.discretization == Discretization::fe) continue;
    const double v = !body.horizon ? config.horizon : body.horizon->is_constant() ? (*body.horizon)(0) : -1;
    if (v < 0 || (one && *one != v)) several = true;
    one = v;
  }
  if (!several) return one ? *one : config.horizon;
  const ModelEntry* model = find_model(mat.model);
  if (!model || !model->traits.any_horizon || mat.damage.fracture_energy)
    throw Error(config.deck_file + ": material '" + mat.name + "' (model " + mat.model +
                "): its particles have different horizons (bodies of different horizons, or one that varies in space), "
                "and its constants" + (mat.damage.fracture_energy ? " (the critical stretch from fracture_energy)" : "") +
                " depend on the horizon; give each horizon its own material");
  return config.horizon;
}

// `split`: the rows of this rank alone (build_system_split, parallel/decomposition.hpp).
// `local` (with split): the particles those rows read alone (local particles), and the
// neighbours' rows only with `neighbour_rows`; d.owner and the rest filled.
System build(const Config& config, bool split, Decomposition* local = nullptr, bool neighbour_rows = true) {
  check_memory(config, config.memory_limit_bytes, split ? world_size() : 1);  // before anything is allocated
  System s;
  s.dimension = config.dimension;
  switch (config.structure.kind) {
    case StructureKind::none: s.active_components = 0; break;
    case StructureKind::beam:
    case StructureKind::plate: s.active_components = 4; break;
    case StructureKind::shell: s.active_components = 7; break;
  }
  s.horizon = config.horizon;
  s.spacing = config.spacing;
  for (const auto& p : config.contact.projectiles)
    s.contact_stiffness = std::max(
        s.contact_stiffness,
        penalty_stiffness(p.law, p.stiffness, p.max_penetration > 0 ? p.max_penetration : config.spacing));
  // The indenters push with the same quadratic penalty (contact/indenter.hpp): a particle
  // pressed into one has the spring 2 K d too, and the explicit step must know it (a stiff
  // wall with a step from the bonds alone gains energy once a particle is deep in it).
  // As for a projectile without max_penetration, the stiffness is taken at a depth of one
  // spacing (contact/rigid_contact.hpp penalty_stiffness).
  for (const auto& p : config.contact.indenters)
    s.contact_stiffness =
        std::max(s.contact_stiffness, penalty_stiffness(ContactLaw::quadratic, p.stiffness, config.spacing));

  LatticeSpec spec{config.dimension, config.spacing, cell_volume(config), config.lattice_origin};
  for (std::size_t b = 0; b < config.bodies.size(); ++b) {
    const auto& body = config.bodies[b];
    int mat = -1;
    for (std::size_t m = 0; m < config.materials.size(); ++m)
      if (config.materials[m].name == body.material) mat = static_cast<int>(m);
    if (mat < 0) throw Error("body '" + body.name + "' names unknown material '" + body.material + "'");
    if (body.discretization == Discretization::fe) {  // built below, after the particles
      s.block_names.push_back(body.name);
      continue;
    }
    const std::size_t added = fill_shape(s.particles, body.shape, spec, config.materials[mat].density,
                                         static_cast<int32_t>(b), mat);
    if (added == 0)
      throw Error("body '" + body.name + "' contains no lattice point: its shape is smaller than the spacing " +
                  std::to_string(config.spacing) + " m or lies outside the lattice");
    s.block_names.push_back(body.name);
  }

  // A cylindrical shell: the lattice's (x, y) wrapped around the x axis, y the arc length
  // (StructureConfig::cylinder_radius).
  if (const double R = config.structure.cylinder_radius; R > 0)
    for (auto& X : s.particles.X) X = Vec3{X.x, R * std::sin(X.y / R), R * std::cos(X.y / R)};

  for (const auto& name : config.no_fail_regions) {
    // As a load's region (geometry/region_select.hpp): what it holds, else the nearest layer.
    for (uint32_t i : select_region(config.regions.at(name), s.particles.X, config.dimension, config.spacing))
      s.particles.no_fail[i] = 1;
  }

  // A box family (family_box) is searched within the box's half-diagonal, then trimmed.
  const double radius = config.family_box ? norm(*config.family_box)
                                          : family_radius(config.horizon, config.spacing, config.partial_volume.rule);
  std::vector<uint8_t> ghost;
  build_fe_regions(s, config, radius, ghost);  // fe/fe_region.hpp: no-op without FE bodies
  std::vector<uint8_t> owned, built;  // split: the rows this rank owns, and those it builds
  if (split) {
    if (s.fe) throw Error("internal error: finite-element regions are built whole on every rank");
    const auto& P = s.particles;
    std::vector<int32_t> owner = rcb_owners(P.X, world_size());
    const int rank = world_rank();
    owned.assign(P.size(), 0);
    for (std::size_t i = 0; i < P.size(); ++i) owned[i] = owner[i] == rank ? 1 : 0;
    // The owned rows and the rows of their bond neighbours: state-based models and the
    // general force pass compute those too (decompose drops them for a bond-based run).
    built = owned;
    {
      Bonds own = find_neighbors(P.X, P.volume, radius, &P.material, &owned);
      if (local && !neighbour_rows) {
        s.bonds = std::move(own);  // a bond-based run with local particles: its owned rows alone
      } else {
        for (std::size_t i = 0; i < P.size(); ++i)
          for (uint64_t k = own.begin(i); k < own.end(i); ++k) built[own.nbr[k]] = 1;
      }
    }
    if (!local || neighbour_rows) s.bonds = find_neighbors(P.X, P.volume, radius, &P.material, &built);
    if (local) {
      local->global_particles = P.size();
      keep_local_particles(s, built, owned, owner);
      local->owner = std::move(owner);
      local->local_particles = true;
      local->local_rows = true;
    }
  } else if (!s.fe) {
    s.bonds = find_neighbors(s.particles.X, s.particles.volume, radius, &s.particles.material);
  } else {
    // Families of the peridynamic particles and of the FE nodes within a horizon of them
    // (ghosts, with the lattice cell's volume as a neighbour); bonds between two FE-owned
    // nodes are dropped, so the FE nodes carry only the bonds that complete the
    // particles' families (fe/fe_region.hpp).
    const auto& P = s.particles;
    std::vector<uint32_t> subset;
    std::vector<Vec3> pts;
    std::vector<double> vol;
    std::vector<int32_t> mats;
    for (std::size_t i = 0; i < P.size(); ++i)
      if (!s.fe->owned_particle[i] || ghost[i]) {
        subset.push_back(static_cast<uint32_t>(i));
        pts.push_back(P.X[i]);
        vol.push_back(s.fe->owned_particle[i] ? cell_volume(config) : P.volume[i]);
        mats.push_back(P.material[i]);
      }
    Bonds sub = find_neighbors(pts, vol, radius, &mats);
    expand_kinds(sub);  // the FE coupling reads kinds with their lengths
    Bonds& b = s.bonds;
    b.kinds = std::move(sub.kinds);
    b.offset.assign(P.size() + 1, 0);
    for (std::size_t q = 0; q < subset.size(); ++q) {
      const std::size_t i = subset[q];
      for (uint64_t k = sub.begin(q); k < sub.end(q); ++k) {
        const uint32_t j = subset[sub.nbr[k]];
        if (s.fe->owned_particle[i] && s.fe->owned_particle[j]) continue;
        b.nbr.push_back(j);
        b.kind.push_back(sub.kind[k]);
        ++b.offset[i + 1];
      }
    }
    for (std::size_t i = 0; i < P.size(); ++i) b.offset[i + 1] += b.offset[i];
    b.intact.assign(b.nbr.size(), 1);
  }
  if (config.partial_volume) apply_partial_volume(s.bonds, config.horizon, config.spacing);
  // bonds_between_bodies: false: each body keeps its bonds to itself (Peridigm's Omit
  // Bonds Between Blocks: All); such pairs are never bonded, so contact sees them.
  if (!config.bonds_between_bodies)
    rewrite_bonds(s.bonds, [&](std::size_t i, uint64_t k) {
      return s.particles.block[i] == s.particles.block[s.bonds.nbr[k]] ? BondAction::keep : BondAction::drop;
    });
  if (const auto& h = config.family_box) {
    // Peridigm's PdQuickGrid box: j is in i's family when |X_j - X_i| <= h on every axis
    // (survey sec. 1.7); a relative 1e-10 of the box's size keeps lattice points on its faces.
    const double tol = 1e-10 * norm(*h);
    rewrite_bonds(s.bonds, [&](std::size_t i, uint64_t k) {
      const Vec3 d = s.particles.X[s.bonds.nbr[k]] - s.particles.X[i];
      for (int a = 0; a < 3; ++a)
        if (std::abs(d[a]) > (*h)[a] + tol) return BondAction::drop;
      return BondAction::keep;
    });
  }
  // Bodies of their own horizons: each particle's family within its own horizon.
  if (const std::vector<double> own = particle_horizons(s, config); !own.empty()) {
    const uint64_t one_way = restrict_to_horizons(s.bonds, own);
    s.one_way_bonds = (split ? sum_over_ranks(one_way) : one_way) > 0;
  }
  check_precracks_cut(s, config, split);
  // The owned rows' intact bonds: cut_bonds drops a bond or keeps it broken (keep_broken).
  auto owned_intact = [&] {
    uint64_t intact = 0;
    for (std::size_t i = 0; i < owned.size(); ++i)
      if (owned[i])
        for (uint64_t k = s.bonds.begin(i); k < s.bonds.end(i); ++k) intact += s.bonds.intact[k] ? 1 : 0;
    return intact;
  };
  const uint64_t owned_before = split ? owned_intact() : 0;
  s.precrack_bonds = cut_bonds(s.bonds, s.particles.X, config.precracks, config.dimension);
  if (split) s.precrack_bonds = sum_over_ranks(owned_before - owned_intact());  // each bond cut once, by its row's owner
  s.initial_bonds = s.bonds.size();  // split: the whole system's count is set by decompose
  // Split: the models' set-up checks the rows built here alone (the rest are empty).
  if (split) s.row_active = built;
  setup_model(s, config.materials, config);
  // Critical stretches that vary in time: the explicit solver sets them each step.
  for (std::size_t m = 0; m < config.materials.size(); ++m) {
    const auto& e = config.materials[m].damage.critical_stretch_in_time;
    if (!e || !config.materials[m].damage.enabled) continue;
    if (config.solver.type != SolverType::explicit_dynamic)
      throw Error(config.deck_file + ": materials." + config.materials[m].name +
                  ".damage.critical_stretch: an expression in t needs solver type explicit");
    System::CriticalStretchSchedule schedule{*e, {}};
    for (std::size_t i = 0; i < s.particles.size(); ++i)
      if (s.particles.material[i] == static_cast<int32_t>(m)) schedule.particles.push_back(static_cast<uint32_t>(i));
    s.critical_stretch_schedules.push_back(std::move(schedule));
  }
  if (s.fe && (s.model.state_based || s.models.owner()))
    throw Error("finite-element bodies couple to bond-based peridynamic models only (a state-based model's force on a "
                "particle needs its neighbours' full families, which the FE nodes do not have)");
  if (config.thermal.enabled) {
    // Split: the calibration's bulk moment is the whole system's (a maximum over ranks), and
    // with local particles the boundary regions and layers are the whole body's (the
    // decomposition named for that while the heat is set up: region_particles, layer_depth).
    if (local) s.decomposition = local;
    setup_heat(s, config.materials, config, split);  // thermal/heat.hpp; collective when split
    s.decomposition = nullptr;
    // The temperature-dependent critical stretch acts in the general force pass's
    // critical-stretch test: not for a model that owns the force pass.
    for (std::size_t m = 0; m < config.materials.size(); ++m)
      if (config.materials[m].thermal.critical_stretch_slope != 0 && s.models[m].owns_force_pass())
        throw Error("material '" + config.materials[m].name + "' (model " + config.materials[m].model +
                    "): thermal.critical_stretch_slope scales the critical-stretch law of the general force pass, "
                    "which this model does not use");
    // The thermal strain reaches the models that declare it (ModelTraits::thermal_strain):
    // refuse it for the others.
    for (std::size_t m = 0; m < config.materials.size(); ++m)
      if (config.materials[m].thermal.expansion != 0 && !s.models[m].traits().thermal_strain) {
        std::string takers;
        for (const auto& e : model_registry())
          if (e.traits.thermal_strain) takers += (takers.empty() ? "" : ", ") + e.traits.name;
        throw Error("material '" + config.materials[m].name + "' (model " + config.materials[m].model +
                    "): thermal expansion acts on models " + takers +
                    " only; set thermal.expansion: 0 for this material");
      }
  }
  return s;
}

}  // namespace

System build_system(const Config& config) { return build(config, false); }

System build_system_split(const Config& config) { return build(config, true); }

System build_system_split(const Config& config, Decomposition& d) {
  // Whether the rows read their neighbours' rows of the same pass (decompose's rule):
  // the general force pass and the compression factor tell from the deck; a unified
  // model tells whether it is state-based once set up, so a deck of unified models
  // without alpha is built with the owned rows first, and again with the neighbours'
  // rows when any rank's models turn out state-based.
  bool neighbour_rows = false;
  // Bodies of their own horizons may give one-way bonds: the general pass, which reads
  // t_ji from j's row.
  for (const auto& body : config.bodies) neighbour_rows = neighbour_rows || body.horizon.has_value();
  for (const auto& mat : config.materials) {
    const ModelEntry* e = find_model(mat.model);
    neighbour_rows = neighbour_rows || !e || !e->traits.unified || (mat.damage.enabled && mat.damage.alpha != 0);
    // A thermal strain or a temperature-dependent critical stretch takes the general pass.
    neighbour_rows = neighbour_rows || (config.thermal.enabled && (mat.thermal.expansion != 0 ||
                                                                   mat.thermal.critical_stretch_slope != 0));
  }
  if (!neighbour_rows) {
    Decomposition first;
    System s = build(config, true, &first, false);
    const bool state_based = s.model.state_based || !s.models.all_unified();
    if (sum_over_ranks(state_based ? 1 : 0) == 0) {
      d.owner = std::move(first.owner);
      d.local_particles = true;
      d.local_rows = true;
      d.global_particles = first.global_particles;
      return s;
    }
  }
  return build(config, true, &d, true);
}

bool local_particles_allowed(const Config& c) {
  // Static and implicit solves hold local rows but every particle (their distributed
  // vectors are indexed by the global DofMap; driver/run_implicit.cpp).
  return c.solver.type == SolverType::explicit_dynamic && local_rows_allowed(c);
}

bool local_rows_allowed(const Config& c) {
  // Static and implicit solves: local rows when the solve is split over ranks
  // (driver/run_implicit.cpp implicit_distributed_limits): unified models, a matrix-free
  // tangent or ADR, no condition number (those assemble the whole tangent on one rank).
  if (c.solver.type == SolverType::heat) return false;
  if (c.solver.type != SolverType::explicit_dynamic) {
    const bool newton = c.solver.type == SolverType::implicit_dynamic || c.solver.method == StaticMethod::newton;
    if (newton && c.solver.linear_solver != LinearSolverKind::matrix_free) return false;
    if (c.solver.condition_number || c.solver.tangent != TangentKind::analytic) return false;
    if (c.thermal.enabled || !c.contact.projectiles.empty()) return false;  // explicit runs only
    for (const auto& mat : c.materials)
      if (const ModelEntry* e = find_model(mat.model); !e || !e->traits.unified) return false;
  }
  // Heat conduction and rigid projectiles split on local rows and local particles too
  // (thermal/heat.cpp: owned rows, ghosts' temperatures exchanged, boundary layers over
  // ranks; contact/rigid_contact.cpp: each rank pushes its owned particles).
  if (c.structure.kind != StructureKind::none) return false;
  // Finite-element regions split on the whole system (fe/fe_region.hpp FeRegion::split:
  // the element and node arrays are indexed by the serial particle numbers).
  for (const auto& body : c.bodies)
    if (body.discretization == Discretization::fe) return false;
  for (const auto& mat : c.materials) {
    const ModelEntry* e = find_model(mat.model);
    // An exclusive model owns its force pass: split when it computes the owned rows alone
    // (rows_local), whole on every rank otherwise. Structures keep
    // every particle (above): their pass reads the ghost nodes' masters near the supports.
    if (!e || !(e->traits.unified || e->traits.rows_local)) return false;
    // The surface correction of a bond reads both ends' factors, each from the families
    // up to kSurfacePasses horizons out: the split build exchanges them after each pass
    // (material/surface_correction.cpp share_held_factors), for the unified models.
    if (const auto it = mat.parameters.find("surface_correction");
        it != mat.parameters.end() && it->second != 0 && !e->traits.unified)
      return false;
  }
  return true;
}

bool kinds_need_lengths(const std::vector<MaterialConfig>& materials, const Config& config) {
  if (config.thermal.enabled || config.structure.kind != StructureKind::none) return true;  // heat, output/truss
  for (const auto& body : config.bodies)
    if (body.discretization == Discretization::fe) return true;  // fe/fe_region.hpp
  for (const auto& mat : materials) {
    const ModelEntry* entry = find_model(mat.model);
    if (!entry || !entry->traits.unified) return true;  // the general force pass and the models' own loops
    if (mat.influence != InfluenceKind::constant) return true;  // omega(|xi|) per kind
    const auto sc = mat.parameters.find("surface_correction");
    if (sc != mat.parameters.end() && sc->second != 0) return true;  // per-bond weights
  }
  return false;
}

void setup_model(System& s, const std::vector<MaterialConfig>& given, const Config& config) {
  // The materials with every declared parameter present (a material built in code may
  // leave the defaults out; the deck fills them in).
  Config cfg = config;
  cfg.materials = given;
  for (auto& mat : cfg.materials) fill_model_defaults(mat);
  const std::vector<MaterialConfig>& materials = cfg.materials;
  s.models.clear();
  for (const auto& mat : materials) {
    const ModelEntry* entry = find_model(mat.model);
    if (!entry) {
      std::string known;
      for (const auto& name : model_names()) known += (known.empty() ? "" : ", ") + name;
      throw Error("material '" + mat.name + "': unknown model '" + mat.model + "' (known: " + known + ")");
    }
    s.models.add(entry->make());
  }
  // Bonds with their own lengths (family/bonds.hpp) serve the fast loops; a deck that
  // gives the kinds values of |xi| or reads a kind's length gets kinds with lengths.
  if (s.bonds.length_per_bond && kinds_need_lengths(materials, cfg)) expand_kinds(s.bonds);
  const Dimensioning dims = dimensioning(cfg);
  const std::size_t n = s.particles.size();
  std::vector<uint32_t> all(n);
  for (std::size_t i = 0; i < n; ++i) all[i] = static_cast<uint32_t>(i);
  // A model that owns the force pass sets up the whole run (it is exclusive).
  if (Model* owner = s.models.owner()) {
    owner->setup(ModelSetup{s, cfg, materials[0], 0, all, dims});
    return;
  }
  auto& P = s.particles;
  auto& B = s.bonds;
  auto& M = s.model;
  M.dim = cfg.dimension;

  // Influence weights, per bond kind (kinds carry the materials of both ends): the
  // average of the two ends' functions keeps omega_ij = omega_ji.
  split_kinds_by_material(B, P.material);
  for (auto& c : B.kinds) {
    c.weight = 0.5 * (influence(materials[c.material_i].influence, c.length, cfg.horizon) +
                      influence(materials[c.material_j].influence, c.length, cfg.horizon));
    if (c.one_way) c.weight = 0;  // beyond i's own horizon: in j's family alone (restrict_to_horizons)
  }

  M.weighted_volume.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i)
    for (uint64_t k = B.begin(i); k < B.end(i); ++k)
      M.weighted_volume[i] += kernels::weighted_volume_term(B.weight[k], B.length[k], B.volume[k]);

  reset_model_arrays(M, n);
  s.dissipated_at.assign(n, 0);
  s.time = 0;
  s.dt = 0;

  std::vector<std::vector<uint32_t>> members(materials.size());
  for (std::size_t i = 0; i < n; ++i) members[P.material[i]].push_back(static_cast<uint32_t>(i));
  bool own_horizons = false;
  for (const auto& body : cfg.bodies) own_horizons = own_horizons || body.horizon.has_value();
  for (std::size_t m = 0; m < materials.size(); ++m) {
    if (!own_horizons) {
      s.models[m].setup(ModelSetup{s, cfg, materials[m], static_cast<int>(m), std::move(members[m]), dims});
      continue;
    }
    // Bodies of their own horizons: each material's constants with its bodies' horizon.
    Config own = cfg;
    own.horizon = material_horizon(cfg, materials[m]);
    s.models[m].setup(ModelSetup{s, own, materials[m], static_cast<int>(m), std::move(members[m]), dimensioning(own)});
  }
  M.break_after_force = false;
  for (const auto& mat : materials)
    if (mat.damage.enabled) M.break_after_force = M.break_after_force || mat.damage.break_after_force;
  s.contact.setup(cfg.contact.short_range, cfg.spacing, cfg.horizon);
  build_kind_coefficients(s, cfg.output.damage_measure);
}

double stable_time_step(const System& s) {
  // A particle in contact with a rigid projectile or an indenter also has the penalty spring k = K_c V
  // (contact/rigid_contact.hpp): its stiffness joins the bond sum of the Silling-Askari
  // bound, dt = sqrt(2 rho / (sum c V_j/|xi| + K_c)) (Silling and Askari 2005, eq. 17 with
  // the contact spring as one more term). Models that set their own step and the elements
  // take it in the same way through 1/dt^2 = 1/dt_own^2 + K_c/(2 rho).
  const double kc = s.contact_stiffness;
  const auto& P = s.particles;
  auto with_contact = [&](double dt) {
    if (!(kc > 0) || P.size() == 0) return dt;
    double rho_min = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < P.size(); ++i) rho_min = std::min(rho_min, P.density[i]);
    const double inv = (std::isfinite(dt) ? 1 / (dt * dt) : 0.0) + kc / (2 * rho_min);
    return 1 / std::sqrt(inv);
  };
  if (const Model* owner = s.models.owner()) return with_contact(owner->stable_time_step(s));
  const auto& B = s.bonds;
  // Models whose stiffness grows with the deformation scale their particles' springs by
  // the current state (Model::spring_factors; the correspondence model under
  // solver.adaptive_time_step): each half spring of a bond carries its particle's factor.
  std::vector<double> g(P.size(), 1.0);
  bool scaled = false;
  for (const auto& m : s.models) scaled = m->spring_factors(s, g) || scaled;
  const double* gp = scaled ? g.data() : nullptr;
  double dt = std::numeric_limits<double>::infinity();
  // A decomposed run takes its own particles (the caller takes the minimum over the
  // ranks): a neighbour's row held here may read a ghost whose state (its factor) this
  // rank does not compute.
  const std::vector<uint32_t>* own = s.decomposition && !s.owned.empty() ? &s.owned : nullptr;
  const std::size_t n = own ? own->size() : P.size();
  std::vector<uint64_t> reverse;
  if (s.one_way_bonds) reverse = reverse_bonds(B, s.decomposition && s.decomposition->local_rows);
  const std::vector<uint64_t>* rev = s.one_way_bonds ? &reverse : nullptr;
#pragma omp parallel for schedule(static) reduction(min : dt)
  for (std::size_t a = 0; a < n; ++a) {
    const std::size_t i = own ? (*own)[a] : a;
    double sum = 0;
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
      const uint32_t j = B.nbr[k];
      if (rev) {
        // One-way bonds: each direction's spring with its own weight, omega_ij and omega_ji
        // (the sum below when they are equal).
        const double si = gp ? s.model.spring[i] * gp[i] : s.model.spring[i];
        const double sj = gp ? s.model.spring[j] * gp[j] : s.model.spring[j];
        sum += B.volume[k] * (B.weight[k] * si + B.weight[(*rev)[k]] * sj) / B.length[k];
        continue;
      }
      const double spring = gp ? s.model.spring[i] * gp[i] + s.model.spring[j] * gp[j]
                               : s.model.spring[i] + s.model.spring[j];
      sum += B.volume[k] * B.weight[k] * spring / B.length[k];
    }
    if (sum > 0) dt = std::min(dt, std::sqrt(2 * P.density[i] / (sum + kc)));
  }
  if (s.fe) dt = std::min(dt, with_contact(s.fe->stable_time_step()));
  return dt;
}

namespace {
// Bytes a bond costs (memory_estimate).
std::size_t bytes_per_bond(const System& s) {
  // Neighbour, kind, intact flag; reference data per kind (family/bonds.hpp).
  // State-based models keep each bond's |Y| between their two passes (8 bytes more).
  std::size_t per_bond = 2 * sizeof(uint32_t) + sizeof(uint8_t) + (s.model.state_based ? sizeof(double) : 0);
  if (s.bonds.length_per_bond) per_bond += sizeof(double);  // its own |xi| (an irregular cloud)
  // The general force pass keeps each bond's force state and its reverse bond
  // (solver/forces_general.hpp); models keep their own history on top.
  // Its scalar form (solver/forces_ordinary.cpp) keeps a scalar instead, and every bond's |Y|.
  if (!s.models.all_unified() && !s.models.owner()) {
    if (affine_general_pass(s)) {
      // a record per particle (solver/forces_affine.cpp), nothing per bond
    } else if (scalar_general_pass(s)) {
      per_bond += sizeof(double) + sizeof(uint64_t) + (s.model.state_based ? 0 : sizeof(double));
    } else {
      per_bond += sizeof(Vec3) + sizeof(uint64_t);
    }
  }
  return per_bond;
}
// The kinds: their reference data (family/bonds.hpp) and the force loops' tables
// (ModelCoefficients: KindCoefficients, the two records of the state-based passes and the
// ordinary rows' record, kind_rows).
std::size_t kind_bytes(const System& s) {
  return s.bonds.kinds.size() * (sizeof(BondKind) + sizeof(KindCoefficients) + 3 * sizeof(Point4));
}
}  // namespace

RankShare largest_rank_share(const System& s, int ranks, bool local_particles) {
  const std::size_t n = s.particles.size();
  const auto& B = s.bonds;
  const std::vector<int32_t> owner = rcb_owners(s.particles.X, ranks);
  // The rule of decompose(): the neighbours' rows are computed (and held) too when a row
  // reads what its neighbours compute in the same pass.
  bool alpha = false;
  for (double a : s.model.alpha) alpha = alpha || a != 0;
  const bool neighbours = s.model.state_based || alpha || !s.models.all_unified();
  std::vector<std::vector<uint32_t>> owned(static_cast<std::size_t>(std::max(1, ranks)));
  for (std::size_t i = 0; i < n; ++i) owned[static_cast<std::size_t>(owner[i])].push_back(static_cast<uint32_t>(i));
  std::vector<int32_t> counted(n, -1);  // the last rank that counted the row
  std::vector<int32_t> read(n, -1);     // the last rank that counted the particle (local particles)
  RankShare best;
  for (std::size_t r = 0; r < owned.size(); ++r) {
    uint64_t held = 0, particles = 0;
    std::vector<uint32_t> rows;
    auto add = [&](uint32_t i) {
      if (counted[i] == static_cast<int32_t>(r)) return;
      counted[i] = static_cast<int32_t>(r);
      held += B.end(i) - B.begin(i);
      rows.push_back(i);
    };
    for (uint32_t i : owned[r]) {
      add(i);
      if (neighbours)
        for (uint64_t k = B.begin(i); k < B.end(i); ++k) add(B.nbr[k]);
    }
    // Local particles: the rows held and the particles they read.
    auto mark = [&](uint32_t i) {
      if (read[i] == static_cast<int32_t>(r)) return;
      read[i] = static_cast<int32_t>(r);
      ++particles;
    };
    for (uint32_t i : rows) {
      mark(i);
      for (uint64_t k = B.begin(i); k < B.end(i); ++k) mark(B.nbr[k]);
    }
    best.bonds = std::max(best.bonds, held);
    best.particles = std::max(best.particles, local_particles ? particles : static_cast<uint64_t>(n));
  }
  const std::size_t kinds = kind_bytes(s);
  const std::size_t particle_bytes = memory_estimate(s) - kProgramBytes - B.size() * bytes_per_bond(s) - kinds;
  best.bytes =
      kProgramBytes + (n ? particle_bytes / n : 0) * best.particles + best.bonds * bytes_per_bond(s) + kinds;
  return best;
}

// An output frame's copy of the positions and fields (output/frame.hpp), up to 32 doubles
// a particle: measured, the peak of a run of the jittered cylinder (bench/clouds) lies
// 162 bytes a particle above the arrays counted here, that of its regular rings 214.
constexpr std::size_t kFrameBytes = 32 * sizeof(double);

std::size_t memory_estimate(const System& s) {
  const std::size_t n = s.particles.size(), nb = s.bonds.size();
  // Particles (geometry/particles.hpp), the model arrays (13 doubles), the force pass's
  // scratch (a Point4 and a double), the dissipated energy, the explicit solver's copies of
  // u, v and b (solver/explicit.hpp) and the constraint flags (loading/loads.hpp): what an
  // explicit run of the unified models holds a particle (tests/unit/test_clouds.cpp).
  const std::size_t per_particle = 5 * sizeof(Vec3) + 4 * sizeof(double) + 2 * sizeof(int32_t) + sizeof(int64_t) + 1 +
                                   13 * sizeof(double) + sizeof(Point4) + sizeof(double) + sizeof(double) +
                                   3 * sizeof(Vec3) + 1 + sizeof(uint64_t) +  // + the row's bond offset
                                   kFrameBytes;
  const std::size_t per_bond = bytes_per_bond(s);
  const std::size_t kinds = kind_bytes(s);
  return kProgramBytes + n * per_particle + nb * per_bond + kinds;
}

}  // namespace horizon
