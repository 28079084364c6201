#include "horizon/state/short_range.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>

#include "horizon/core/cell_key.hpp"
#include "horizon/core/error.hpp"
#include "horizon/parallel/decomposition.hpp"
#include "horizon/state/system.hpp"

namespace horizon {


void ShortRangeContact::setup(const ShortRangeContactConfig& config, double spacing, double horizon) {
  enabled_ = config.enabled;
  config_ = config;
  horizon_ = horizon;
  cutoff_ = config.law == ShortRangeLaw::peridigm ? config.contact_radius : config.max_distance * spacing;
  // Peridigm's c = 9k/(pi delta^4) (half the PMB micromodulus, users' guide SAND2012-7800),
  // which each particle of a pair receives twice: once from its own contact list and once
  // from its partner's, both lists holding the pair. Contact_2x1x1's gold fixes the sum:
  // two free particles oscillate at omega^2 = 36 k V/(pi delta^5 rho), omega = 75,695 rad/s
  // (peak u = 1/omega = 1.32111e-5 there), i.e. 2 c per pair; Horizon visits each pair once
  // per particle, so its one coefficient is 18k/(pi delta^4). Over delta once more for the
  // force density's (d - r)/delta.
  peridigm_k_ = 18.0 * config.spring_constant / (3.14159265358979323846 * std::pow(horizon, 4)) / horizon;
  touch_.clear();
  touch_bodies_ = 0;
  // Half a spacing of skin: a particle is updated after it moves a quarter spacing.
  skin_ = 0.5 * spacing;
  y_built_.clear();
  rows_.clear();
  cell_of_.clear();
  cells_.clear();
  rebuilds_ = candidates_ = 0;
  energy_.clear();
  y_last_.clear();
  y_start_.clear();
  last_time_ = 0;
  step_ = -1;
}

double ShortRangeContact::distance(double reference_length) const {
  if (!enabled_) return 0.0;
  if (config_.law == ShortRangeLaw::peridigm) return cutoff_;
  return std::min(config_.reference_fraction * reference_length, cutoff_);
}

uint64_t ShortRangeContact::cell_key(const Vec3& p) const {
  const double edge = cutoff_ + skin_;
  return pack_cell(cell_coord(p.x, edge), cell_coord(p.y, edge), cell_coord(p.z, edge));
}

void ShortRangeContact::update(const System& s, const Point4* y, bool first) {
  const std::size_t n = s.particles.size();
  const std::size_t total = n + ghost_y_.size();  // with the contact ghosts (local particles)
  const auto& B = s.bonds;
  const double edge = cutoff_ + skin_, reach2 = edge * edge;
  // Local particles: a row lists only pairs with a computed row (the rows of the others
  // may not be held, so their families are unknown here), sorted by global id.
  const bool local = s.decomposition && s.decomposition->local_particles;
  const bool keyed = !key_.empty();
  auto less = [&](uint32_t a, uint32_t b) { return keyed ? key_[a] < key_[b] : a < b; };
  auto pos = [&](uint32_t j) -> const Point4& { return j < n ? y[j] : ghost_y_[j - n]; };
  auto computed = [&](uint32_t j) { return j < n && s.computes_row(j); };
  // Only the listed bodies touch (ShortRangeContactConfig::pairs).
  if (!config_.pairs.empty() && touch_.empty()) {
    touch_bodies_ = s.block_names.size();
    touch_.assign(touch_bodies_ * touch_bodies_, 0);
    auto index = [&](const std::string& name) {
      const auto it = std::find(s.block_names.begin(), s.block_names.end(), name);
      if (it == s.block_names.end()) throw Error("contact.short_range.pairs: no body named '" + name + "'");
      return static_cast<std::size_t>(it - s.block_names.begin());
    };
    for (const auto& [a, b] : config_.pairs) {
      const std::size_t ia = index(a), ib = index(b);
      touch_[ia * touch_bodies_ + ib] = touch_[ib * touch_bodies_ + ia] = 1;
    }
  }
  if (!touch_.empty() && !ghost_y_.empty())
    throw Error("contact.short_range.pairs is not supported yet on several ranks with local particles");
  const bool filter = !touch_.empty();
  const bool screen = local || filter;
  auto touches = [&](uint32_t a, uint32_t b) {
    const auto ba = static_cast<std::size_t>(s.particles.block[a]), bb = static_cast<std::size_t>(s.particles.block[b]);
    return ba < touch_bodies_ && bb < touch_bodies_ && touch_[ba * touch_bodies_ + bb];
  };
  if (first) {
    y_built_.assign(total, Vec3{});
    rows_.assign(total, {});
    cell_of_.assign(total, 0);
    cells_.clear();
    is_mover_.assign(total, 0);
    movers_.resize(total);
    for (std::size_t i = 0; i < total; ++i) movers_[i] = static_cast<uint32_t>(i);
  }
  for (uint32_t m : movers_) is_mover_[m] = 1;
  // Forget the movers' pairs and move them to their new cells.
  for (uint32_t m : movers_) {
    for (uint32_t j : rows_[m]) {
      if (is_mover_[j]) continue;
      auto& r = rows_[j];
      r.erase(std::lower_bound(r.begin(), r.end(), m, less));
    }
    rows_[m].clear();
    if (!first) {
      auto& old = cells_[cell_of_[m]];
      old.erase(std::find(old.begin(), old.end(), m));
    }
    const Point4& p = pos(m);
    y_built_[m] = {p.x, p.y, p.z};
    cell_of_[m] = cell_key(y_built_[m]);
    cells_[cell_of_[m]].push_back(m);
  }
  // Find their pairs again: within cut-off + skin, and not in the mover's family (rows
  // of the bonds are sorted by neighbour). A pair of two movers is found by both.
  std::vector<uint32_t> touched;
  for (uint32_t m : movers_) {
    const Vec3 p = y_built_[m];
    const bool held = m < n;  // a contact ghost has no row here (and no family with a held row)
    const auto first_bond = B.nbr.begin() + static_cast<std::ptrdiff_t>(held ? B.begin(m) : 0);
    const auto last_bond = B.nbr.begin() + static_cast<std::ptrdiff_t>(held ? B.end(m) : 0);
    const bool m_computed = computed(m);
    const int64_t c[3] = {cell_coord(p.x, edge), cell_coord(p.y, edge), cell_coord(p.z, edge)};
    for (int64_t a = c[0] - 1; a <= c[0] + 1; ++a)
      for (int64_t b = c[1] - 1; b <= c[1] + 1; ++b)
        for (int64_t d = c[2] - 1; d <= c[2] + 1; ++d) {
          const auto it = cells_.find(pack_cell(a, b, d));
          if (it == cells_.end()) continue;
          for (uint32_t j : it->second) {
            if (j == m || norm2(y_built_[j] - p) > reach2) continue;
            // One test for both screens, so that a serial run without `pairs` pays no more
            // per candidate than before `pairs` existed.
            if (screen && ((local && !m_computed && !computed(j)) || (filter && !touches(m, j)))) continue;
            if (std::binary_search(first_bond, last_bond, j)) continue;
            // A row this rank does not hold (a run split over ranks with local rows,
            // parallel/decomposition.hpp) is empty: the family test then reads j's row
            // (families are symmetric; serially an empty row has no family at all).
            if (first_bond == last_bond && j < n && B.end(j) > B.begin(j) &&
                std::binary_search(B.nbr.begin() + static_cast<std::ptrdiff_t>(B.begin(j)),
                                   B.nbr.begin() + static_cast<std::ptrdiff_t>(B.end(j)), m))
              continue;
            rows_[m].push_back(j);
            if (!is_mover_[j]) {
              rows_[j].push_back(m);
              touched.push_back(j);
            }
          }
        }
    std::sort(rows_[m].begin(), rows_[m].end(), less);
  }
  for (uint32_t j : touched) std::sort(rows_[j].begin(), rows_[j].end(), less);
  for (uint32_t m : movers_) is_mover_[m] = 0;
  rebuilds_ += movers_.size();
  candidates_ = 0;
  for (const auto& r : rows_) candidates_ += r.size();
}

void ShortRangeContact::peridigm_search(const System& s, const Point4* y) {
  const std::size_t n = s.particles.size();
  // A new step is a pass at another time than the last: the positions it starts from are
  // that last pass's. The first pass (t = 0) searches at its own positions.
  if (step_ < 0 || y_last_.size() != n) {
    step_ = 0;
    y_start_.resize(n);
    for (std::size_t i = 0; i < n; ++i) y_start_[i] = {y[i].x, y[i].y, y[i].z};
  } else if (s.time != last_time_) {
    ++step_;
    // Between searches only the positions of the last pass are kept; at a search those
    // of the step's start become the searched ones.
    if (step_ % config_.search_every == 0) y_start_.swap(y_last_);
  }
  y_last_.resize(n);
  for (std::size_t i = 0; i < n; ++i) y_last_[i] = {y[i].x, y[i].y, y[i].z};
  last_time_ = s.time;
}

void ShortRangeContact::add_forces(const System& s, const Point4* y, Vec3* f, double* W) {
  if (!enabled_) return;
  const auto& P = s.particles;
  const auto& M = s.model;
  const std::size_t n = P.size();
  if (record_) recorded_.assign(n, Vec3{});  // zero where no pair touches
  if (config_.law == ShortRangeLaw::peridigm && W) energy_.assign(n, 0.0);  // own_energy
  // Local particles on ranks: the contact ghosts' current positions (the same sum as the
  // owner's packed position), and the lists built again for a new ghost set.
  const Decomposition* dec = s.decomposition;
  const ContactGhosts* g = dec && dec->local_particles ? &dec->contact : nullptr;
  bool first = false;
  if (g) {
    const std::size_t ng = g->id.size();
    ghost_y_.resize(ng);
    for (std::size_t k = 0; k < ng; ++k) {
      const Vec3 p = g->X[k] + g->u[k];
      ghost_y_[k] = {p.x, p.y, p.z, 0.0};
    }
    if (generation_ != g->generation || y_built_.size() != n + ng) {
      first = true;
      generation_ = g->generation;
      key_.clear();
      if (ng > 0) {
        key_.assign(P.id.begin(), P.id.end());
        key_.insert(key_.end(), g->id.begin(), g->id.end());
      }
    }
  }
  const std::size_t total = n + ghost_y_.size();
  // Peridigm's search: the positions of the last search (y_start_); the pass below keeps
  // the pairs of Horizon's lists that were within the search radius there. Horizon's lists
  // hold every pair closer than R_c, so these are the pairs of Peridigm's list closer than
  // R_c, without a list of every pair within the (larger) search radius.
  const bool searched = config_.law == ShortRangeLaw::peridigm && config_.search_radius > 0;
  if (searched) {
    if (!ghost_y_.empty())
      throw Error("contact.short_range.search_radius is not supported yet on several ranks with local particles");
    peridigm_search(s, y);
  }
  if (first || y_built_.size() != total) {
    update(s, y, true);
  } else {
    // The particles that moved more than skin/2 since their last update, in index order.
    const double half2 = 0.25 * skin_ * skin_;
    movers_.clear();
    for (std::size_t i = 0; i < total; ++i) {
      const Point4& p = i < n ? y[i] : ghost_y_[i - n];
      const double dx = p.x - y_built_[i].x, dy = p.y - y_built_[i].y, dz = p.z - y_built_[i].z;
      if (dx * dx + dy * dy + dz * dz > half2) movers_.push_back(static_cast<uint32_t>(i));
    }
    if (!movers_.empty()) update(s, y, false);
  }
  if (candidates_ == 0) return;
  const double cut2 = cutoff_ * cutoff_;
  const double factor = config_.stiffness_factor / horizon_;
  // A decomposed run adds the contact of its active particles alone (state/system.hpp).
  const std::vector<uint32_t>* act = s.active_rows.empty() ? nullptr : &s.active_rows;
  const std::size_t count = act ? act->size() : n;
  // One pair sum; with contact ghosts (local particles on ranks: index n + k is ghost k)
  // partner j's data come from the ghost arrays, term for term the same arithmetic. The
  // flag is a compile-time constant so the serial loop reads the particle arrays alone.
  const bool peridigm = config_.law == ShortRangeLaw::peridigm;
  if (peridigm && (config_.friction > 0 || config_.friction_in_time) && !ghost_y_.empty())
    throw Error("contact.short_range.friction is not supported yet on several ranks with local particles");
  const Vec3* v = P.v.data();
  // A coefficient that varies in time: mu at the time of the state the pass sees.
  const double mu = config_.friction_in_time ? (*config_.friction_in_time)(s.time) : config_.friction;
  if (!(mu >= 0))
    throw Error("contact.short_range.friction is " + std::to_string(mu) + " at t = " + std::to_string(s.time) +
                "; a friction coefficient must be >= 0");
  Vec3* kept = record_ ? recorded_.data() : nullptr;
  const Vec3* ys = searched ? y_start_.data() : nullptr;
  const double rs2 = config_.search_radius * config_.search_radius;
  // Law peridigm's energy goes to energy_ (own_energy), not to the material's W.
  double* own = peridigm && W ? energy_.data() : nullptr;
  auto pass = [&](auto with_ghosts, auto peridigm_law) {
    constexpr bool ghosts = decltype(with_ghosts)::value;
    constexpr bool pd = decltype(peridigm_law)::value;
#pragma omp parallel for schedule(static)
    for (std::size_t a = 0; a < count; ++a) {
      const std::size_t i = act ? (*act)[a] : a;
      if (rows_[i].empty()) continue;
      Vec3 fi;
      double wi = 0;
      for (uint32_t j : rows_[i]) {
        const bool held = !ghosts || j < n;
        const Point4& yj = held ? y[j] : ghost_y_[j - n];
        const double dx = yj.x - y[i].x, dy = yj.y - y[i].y, dz = yj.z - y[i].z;
        const double r2 = dx * dx + dy * dy + dz * dz;
        if (!(r2 < cut2) || r2 == 0) continue;
        if constexpr (pd) {
          // Peridigm's search: only pairs within its radius at the last search touch.
          if (ys && norm2(ys[j] - ys[i]) > rs2) continue;
          // Peridigm's law: d = R_c (= the cut-off) and one k for every pair.
          const double r = std::sqrt(r2), d = cutoff_;
          const double k = peridigm_k_ * (held ? P.volume[j] : g->volume[j - n]);
          const double a = -k * (d - r) / r;  // pushes i away from j
          fi += Vec3{dx, dy, dz} * a;
          wi += 0.25 * k * (d - r) * (d - r);
          if (mu > 0) {
            // Coulomb friction mu |f_n| along the relative tangential velocity of j
            // with respect to i (friction on several ranks is refused above).
            const Vec3 e = Vec3{dx, dy, dz} * (1.0 / r);
            const Vec3 rel = v[j] - v[i];
            const Vec3 tangential = rel - e * dot(rel, e);
            const double vt = norm(tangential);
            if (vt > 0) fi += tangential * (mu * k * (d - r) / vt);
          }
        } else {
          const Vec3& Xj = held ? P.X[j] : g->X[j - n];
          // distance() of the LAMMPS law, inlined (contact is on here).
          const double d = std::min(config_.reference_fraction * norm(Xj - P.X[i]), cutoff_);
          const double r = std::sqrt(r2);
          if (!(r < d)) continue;
          const double cj = held ? M.contact_micromodulus[j] : g->micromodulus[j - n];
          const double Vj = held ? P.volume[j] : g->volume[j - n];
          const double k = factor * 0.5 * (M.contact_micromodulus[i] + cj) * Vj;
          const double a = -k * (d - r) / r;  // pushes i away from j
          fi += Vec3{dx, dy, dz} * a;
          wi += 0.25 * k * (d - r) * (d - r);
        }
      }
      f[i] += fi;
      if constexpr (pd) {
        if (own) own[i] = wi;
      } else if (W) {
        W[i] += wi;
      }
      if (kept) kept[i] = fi;
    }
  };
  if (peridigm) {
    if (ghost_y_.empty())
      pass(std::false_type{}, std::true_type{});
    else
      pass(std::true_type{}, std::true_type{});
  } else if (ghost_y_.empty()) {
    pass(std::false_type{}, std::false_type{});
  } else {
    pass(std::true_type{}, std::false_type{});
  }
}

}  // namespace horizon
