#include "horizon/loading/loads.hpp"

#include "horizon/core/parallel_select.hpp"
#include "horizon/parallel/decomposition.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <set>

#include <fmt/format.h>

#include "horizon/core/error.hpp"
#include "horizon/material/model.hpp"
#include "horizon/geometry/region_select.hpp"

namespace horizon {

namespace {
const char* kind_name(LoadKind k) {
  switch (k) {
    case LoadKind::traction: return "traction";
    case LoadKind::body_force: return "body_force";
    case LoadKind::displacement: return "displacement";
    case LoadKind::velocity: return "velocity";
    case LoadKind::force: return "force";
    case LoadKind::pressure: return "pressure";
  }
  return "load";
}
bool is_constraint(LoadKind k) { return k == LoadKind::displacement || k == LoadKind::velocity; }

bool same_expression(const Expression& a, const Expression& b) {
  if (a.is_constant() != b.is_constant()) return false;
  return a.is_constant() ? a(0) == b(0) : a.text() == b.text();
}

const char* axis_name(int c) { return c == 0 ? "x" : c == 1 ? "y" : "z"; }

// An expression that is not finite where it is used at the start (1/0, sqrt(-1), log(0))
// is an error here rather than a non-finite state a step later.
void check_finite(const std::string& file, const Expression& e, double t, const Vec3& x, const std::string& what,
                  int c) {
  const double v = e(t, x.x, x.y, x.z);
  if (std::isfinite(v)) return;
  throw Error(fmt::format("{}: {} {}-component '{}' is {} at t = {:g}, (x, y, z) = ({:g}, {:g}, {:g}) (a division "
                          "by zero, or a function outside its domain); an expression must be finite wherever it "
                          "applies",
                          file, what, axis_name(c), e.text(), std::isnan(v) ? "not a number" : "infinite", t, x.x, x.y,
                          x.z));
}
}  // namespace

std::vector<uint32_t> region_particles(const Config& config, const System& s, const std::string& region) {
  std::vector<uint32_t> ids;
  if (region.empty() || region == "all") {
    for (std::size_t i = 0; i < s.particles.size(); ++i) ids.push_back(static_cast<uint32_t>(i));
    return ids;
  }
  const auto it = config.regions.find(region);
  if (it == config.regions.end()) throw Error("unknown region '" + region + "'");
  ids = particles_inside(it->second, s.particles.X);
  // A rank with local particles (parallel/decomposition.hpp) holds part of the bodies: the
  // region is empty when it is on every rank (collective then).
  const bool local = s.decomposition && s.decomposition->local_particles;
  auto empty = [&] { return local ? sum_over_ranks(ids.size()) == 0 : ids.empty(); };
  if (empty() && selects_nearest_layer(it->second)) {
    // A box that holds no particle selects the nearest lattice layer(s) instead
    // (geometry/region_select.hpp; docs/input.md, "Regions"): a strip one spacing thick
    // stays on its boundary at any --coarsen. The gaps are the whole system's.
    const Box3 box = it->second.bounds();
    Vec3 gaps = nearest_layer_gaps(box, s.particles.X, config.dimension, s.spacing);
    if (local)
      for (int k = 0; k < 3; ++k) gaps[k] = min_over_ranks(gaps[k]);
    ids = particles_nearest(box, s.particles.X, config.dimension, s.spacing, gaps);
  }
  if (empty()) {
    const Box3 r = it->second.bounds();
    Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    for (const Vec3& x : s.particles.X)
      for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], x[k]), hi[k] = std::max(hi[k], x[k]);
    auto box = [&](const Vec3& a, const Vec3& b) {
      std::string t;
      for (int k = 0; k < config.dimension; ++k)
        t += fmt::format("{}{}: [{:g}, {:g}]", k ? ", " : "", axis_name(k), a[k], b[k]);
      return t;
    };
    throw Error(fmt::format("{}: region '{}' contains no particle: it spans {}, the particles span {}; is it inside "
                            "a body, or less than one spacing ({:g} m) from one?",
                            config.deck_file, region, box(r.min, r.max), box(lo, hi), s.spacing));
  }
  return ids;
}

double layer_depth(const System& s, const std::vector<uint32_t>& ids, int axis) {
  // Layers are counted from the region's lowest coordinate: X / h alone sits on a half
  // integer for a lattice at (k + 1/2) h, where rounding sends neighbouring layers to the
  // same integer (a bar of 100 layers counted 97).
  const bool local = s.decomposition && s.decomposition->local_particles;
  double lo = 1e300;
  for (uint32_t i : ids) lo = std::min(lo, s.particles.X[i][axis]);
  if (local) lo = min_over_ranks(lo);  // collective: every rank calls it
  std::set<int64_t> layers;
  for (uint32_t i : ids) layers.insert(std::llround((s.particles.X[i][axis] - lo) / s.spacing));
  if (local) {
    // Local particles (parallel/decomposition.hpp): the layers of every rank (collective).
    std::vector<double> mine;
    for (int64_t l : layers) mine.push_back(static_cast<double>(l));
    for (double l : allgather_values(mine)) layers.insert(static_cast<int64_t>(l));
  }
  return static_cast<double>(layers.size()) * s.spacing;
}

Loads::Loads(const Config& config, const System& s) : constrained_(s.particles.size(), 0) {
  // The load that constrains each component of each particle (index into loads_), to
  // name both when a second one conflicts.
  std::vector<std::array<int32_t, 3>> owner(s.particles.size(), {-1, -1, -1});
  // A rank with local particles (parallel/decomposition.hpp) holds part of each region:
  // the figures of a whole region come from every rank.
  const bool local = s.decomposition && s.decomposition->local_particles;
  for (const auto& lc : config.loads) {
    AppliedLoad L;
    L.kind = lc.kind;
    L.value = lc.value;
    L.particles = region_particles(config, s, lc.region);
    L.name = (lc.region.empty() ? std::string("all") : lc.region) + ":" + kind_name(lc.kind);
    if (lc.kind == LoadKind::traction) {
      int axis = lc.normal_axis;
      if (axis < 0) {
        // The normal is the axis along which the loaded layer is thinnest.
        double best = 1e300;
        for (int k = 0; k < config.dimension; ++k) {
          double lo = 1e300, hi = -1e300;
          for (uint32_t i : L.particles) {
            lo = std::min(lo, s.particles.X[i][k]);
            hi = std::max(hi, s.particles.X[i][k]);
          }
          if (local) lo = min_over_ranks(lo), hi = -min_over_ranks(-hi);  // the whole region's extent
          if (hi - lo < best) {
            best = hi - lo;
            axis = k;
          }
        }
      }
      // Traction T over the boundary becomes a force density T/d over a layer of depth
      // d, so the total force is T times the loaded area (docs/input.md).
      L.scale = 1.0 / layer_depth(s, L.particles, axis);
    }
    for (int c = 0; c < 3; ++c)
      if (lc.value[c])
        for (uint32_t i : L.particles) check_finite(config.deck_file, *lc.value[c], 0, s.particles.X[i], "load " + L.name, c);
    if (lc.kind == LoadKind::force) {
      // A total force spread evenly over the region: the density F / sum V (seed 001
      // digest sec. 4.7: a point load over the nodes of a patch about one horizon wide).
      double volume = 0;
      if (local) {
        // Local particles: every owner's (global id, volume), summed in global order as
        // serially (collective).
        std::vector<double> mine;
        for (uint32_t i : L.particles)
          if (s.decomposition->owns(i)) mine.insert(mine.end(), {static_cast<double>(s.particles.id[i]), s.particles.volume[i]});
        const std::vector<double> all = allgather_values(mine);
        std::vector<std::pair<double, double>> by_id;
        for (std::size_t k = 0; k + 1 < all.size(); k += 2) by_id.emplace_back(all[k], all[k + 1]);
        std::sort(by_id.begin(), by_id.end());
        for (const auto& [g, v] : by_id) volume += v;
      } else {
        for (uint32_t i : L.particles) volume += s.particles.volume[i];
      }
      L.scale = 1.0 / volume;
    }
    if (lc.kind == LoadKind::pressure) {
      // Per unit mid-surface area of a plate or shell (the density p / thickness), per
      // unit length of a beam (q / area): the nodal force is p times the node's area or
      // length (seed 001 digest sec. 4.7, "treated normally").
      L.scale = 1.0 / (config.dimension == 1 ? config.area : config.thickness);
    }
    if (is_constraint(lc.kind)) {
      L.reaction_old.assign(L.particles.size(), Vec3{});
      for (uint32_t i : L.particles)
        for (int c = 0; c < 3; ++c) {
          if (!lc.value[c]) continue;
          if (owner[i][c] >= 0) {
            // Two constraints on one component of one particle: the later would silently
            // override the earlier. The same prescription twice (corners shared by two
            // clamped edges) is harmless and allowed.
            const AppliedLoad& prior = loads_[static_cast<std::size_t>(owner[i][c])];
            if (prior.kind != lc.kind || !same_expression(*prior.value[c], *lc.value[c])) {
              const Vec3& x = s.particles.X[i];
              throw Error(fmt::format("{}: loads '{}' and '{}' both prescribe the {}-component of particle {} at ({:g}, "
                                      "{:g}, {:g}) differently; a component takes one displacement or velocity: "
                                      "make the regions disjoint or give the component once",
                                      config.deck_file, prior.name, L.name, axis_name(c), i, x.x, x.y, x.z));
            }
          }
          constrained_[i] |= static_cast<uint8_t>(1u << c);
          owner[i][c] = static_cast<int32_t>(loads_.size());
        }
    }
    loads_.push_back(std::move(L));
  }
  // Supports of a thin structure (deck structure.supports): the nodes on the support line
  // are held at w = 0; the model mirrors the body across it with ghost nodes (seed 001
  // digest sec. 4.7).
  for (std::size_t q = 0; q < config.structure.supports.size(); ++q) {
    const SupportConfig& sup = config.structure.supports[q];
    AppliedLoad L;
    L.kind = LoadKind::displacement;
    L.value[2] = Expression(0.0);
    L.name = "support" + std::to_string(q + 1) + ":displacement";
    for (std::size_t i = 0; i < s.particles.size(); ++i)
      if (std::abs(s.particles.X[i][sup.axis] - sup.at) < 1e-6 * s.spacing) L.particles.push_back(static_cast<uint32_t>(i));
    L.reaction_old.assign(L.particles.size(), Vec3{});
    L.support = static_cast<int>(q);
    for (uint32_t i : L.particles) constrained_[i] |= 4u;
    loads_.push_back(std::move(L));
  }
  // A node on two support lines (a corner) gives half its reaction to each.
  {
    std::vector<uint8_t> lines(s.particles.size(), 0);
    for (const auto& L : loads_)
      if (L.support >= 0)
        for (uint32_t i : L.particles) ++lines[i];
    for (auto& L : loads_)
      if (L.support >= 0) {
        L.share.resize(L.particles.size());
        for (std::size_t n = 0; n < L.particles.size(); ++n) L.share[n] = 1.0 / lines[L.particles[n]];
      }
  }
  for (const auto& ic : config.contact.indenters) {
    // A body force whose density the sphere computes from the current positions.
    AppliedLoad L;
    L.kind = LoadKind::body_force;
    L.name = ic.name;
    L.indenter = Indenter(ic);
    loads_.push_back(std::move(L));
  }
  for (const auto& pc : config.contact.projectiles) projectiles_.emplace_back(pc);
}

bool Loads::is_constrained(std::size_t i, int component) const {
  return !constrained_.empty() && (constrained_[i] >> component) & 1u;
}

void Loads::apply_initial_conditions(const Config& config, System& s) const {
  auto& P = s.particles;
  for (const auto& ic : config.initial_conditions)
    for (uint32_t i : region_particles(config, s, ic.region)) {
      const Vec3& x = P.X[i];
      for (int c = 0; c < 3; ++c) {
        if (ic.velocity[c]) {
          check_finite(config.deck_file, *ic.velocity[c], 0, x, "initial velocity", c);
          P.v[i][c] = (*ic.velocity[c])(0, x.x, x.y, x.z);
        }
        if (ic.displacement[c]) {
          check_finite(config.deck_file, *ic.displacement[c], 0, x, "initial displacement", c);
          P.u[i][c] = (*ic.displacement[c])(0, x.x, x.y, x.z);
        }
      }
    }
}

void Loads::apply_constraints(System& s, double t, double dt) const {
  auto& P = s.particles;
  for (const auto& L : loads_) {
    if (!is_constraint(L.kind)) continue;
    for (uint32_t i : L.particles) {
      const Vec3& x = P.X[i];
      for (int c = 0; c < 3; ++c) {
        if (!L.value[c]) continue;
        const Expression& g = *L.value[c];
        if (L.kind == LoadKind::displacement) {
          const double now = g(t, x.x, x.y, x.z);
          P.v[i][c] = dt > 0 ? (now - g(t - dt, x.x, x.y, x.z)) / dt : 0.0;
          P.u[i][c] = now;
        } else {
          P.v[i][c] = g(t, x.x, x.y, x.z);  // u was advanced with the mid-step velocity
        }
      }
    }
  }
}

void Loads::prescribe_velocity(System& s, double t) const {
  auto& P = s.particles;
  for (const auto& L : loads_) {
    if (L.kind != LoadKind::velocity) continue;
    for (uint32_t i : L.particles)
      for (int c = 0; c < 3; ++c)
        if (L.value[c]) P.v[i][c] = (*L.value[c])(t, P.X[i].x, P.X[i].y, P.X[i].z);
  }
}

void Loads::apply_forces(System& s, double t) const {
  auto& P = s.particles;
  parallel_fill(P.b, Vec3{});
  for (const auto& L : loads_) {
    if (is_constraint(L.kind)) continue;
    if (L.indenter) {
      L.applied = L.indenter->apply(s, t);
      continue;
    }
    for (uint32_t i : L.particles) {
      const Vec3& x = P.X[i];
      for (int c = 0; c < 3; ++c)
        if (L.value[c]) P.b[i][c] += L.scale * (*L.value[c])(t, x.x, x.y, x.z);
    }
  }
  for (auto& p : projectiles_) p.contact(s);
}

double Loads::update_reactions(System& s, const std::vector<Vec3>& u_before, const std::vector<Vec3>* v_before,
                               double dt) {
  auto& P = s.particles;
  // Quantity 0: the work; 1 + 3l: the reaction of load l. In a decomposed run each rank
  // adds its own particles and GridSum makes the totals independent of the split.
  const Decomposition* dd = s.decomposition;
  GridSum sums(s, 1 + 3 * static_cast<int>(loads_.size()));
  // A structure's supports also take the forces of the model's ghost nodes beyond them
  // (Model::support_reactions: the whole support's, the same on every rank of a
  // decomposed run, where rank 0 adds them).
  std::vector<Vec3> beyond;
  if (const Model* m = s.models.owner(); m && (!dd || dd->rank == 0)) m->support_reactions(s, beyond);
  for (std::size_t l = 0; l < loads_.size(); ++l) {
    auto& L = loads_[l];
    const int q = 1 + 3 * static_cast<int>(l);
    if (L.indenter) continue;
    if (!is_constraint(L.kind)) {
      for (uint32_t i : L.particles)
        if (!dd || dd->owns(i)) sums.add(q, P.b[i] * P.volume[i]);
      continue;
    }
    for (std::size_t n = 0; n < L.particles.size(); ++n) {
      const uint32_t i = L.particles[n];
      if (dd && !dd->owns(i)) continue;
      // The constraint supplies what the prescribed motion needs beyond the internal
      // force: rho V a - (f + b) V; for slow loading that is -(f + b) V. The static part
      // does work by the trapezoidal rule; the inertial part does exactly the change of
      // the constrained components' kinetic energy, 1/2 rho V (v^2 - v_before^2).
      Vec3 r = -(P.f[i] + P.b[i]) * P.volume[i];
      for (int c = 0; c < 3; ++c)
        if (!L.value[c]) r[c] = 0;
      const double share = L.share.empty() ? 1.0 : L.share[n];  // a node on two supports: half each
      r = r * share;
      const Vec3 du = P.u[i] - u_before[i];
      sums.add(0, 0.5 * dot(L.reaction_old[n] + r, du));
      L.reaction_old[n] = r;
      if (v_before && dt > 0) {
        const double mass = share * P.density[i] * P.volume[i];
        const Vec3& v0 = (*v_before)[i];
        for (int c = 0; c < 3; ++c)
          if (L.value[c]) {
            r[c] += mass * (P.v[i][c] - v0[c]) / dt;
            sums.add(0, 0.5 * mass * (P.v[i][c] * P.v[i][c] - v0[c] * v0[c]));
          }
      }
      sums.add(q, r);
    }
    if (L.support >= 0 && static_cast<std::size_t>(L.support) < beyond.size()) {
      Vec3 r = beyond[static_cast<std::size_t>(L.support)];
      for (int c = 0; c < 3; ++c)
        if (!L.value[c]) r[c] = 0;
      sums.add(q, r);
    }
  }
  const std::vector<double> t = sums.totals();
  for (std::size_t l = 0; l < loads_.size(); ++l) {
    const std::size_t q = 1 + 3 * l;
    loads_[l].reaction = loads_[l].indenter ? loads_[l].applied : Vec3{t[q], t[q + 1], t[q + 2]};
  }
  return t[0];
}

}  // namespace horizon
