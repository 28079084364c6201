#include "horizon/contact/short_range.hpp"

#include <algorithm>
#include <cmath>

#include "horizon/core/cell_key.hpp"
#include "horizon/solver/system.hpp"

namespace horizon {


void ShortRangeContact::setup(const ShortRangeContactConfig& config, double spacing, double horizon) {
  enabled_ = config.enabled;
  config_ = config;
  horizon_ = horizon;
  cutoff_ = config.max_distance * spacing;
  // Half a spacing of skin: a particle is updated after it moves a quarter spacing.
  skin_ = 0.5 * spacing;
  y_built_.clear();
  rows_.clear();
  cell_of_.clear();
  cells_.clear();
  rebuilds_ = candidates_ = 0;
}

double ShortRangeContact::distance(double reference_length) const {
  return enabled_ ? std::min(config_.reference_fraction * reference_length, cutoff_) : 0.0;
}

uint64_t ShortRangeContact::cell_key(const Vec3& p) const {
  const double edge = cutoff_ + skin_;
  return pack_cell(cell_coord(p.x, edge), cell_coord(p.y, edge), cell_coord(p.z, edge));
}

void ShortRangeContact::update(const System& s, const Point4* y) {
  const std::size_t n = s.particles.size();
  const auto& B = s.bonds;
  const double edge = cutoff_ + skin_, reach2 = edge * edge;
  const bool first = y_built_.size() != n;
  if (first) {
    y_built_.assign(n, Vec3{});
    rows_.assign(n, {});
    cell_of_.assign(n, 0);
    cells_.clear();
    is_mover_.assign(n, 0);
    movers_.resize(n);
    for (std::size_t i = 0; i < n; ++i) movers_[i] = static_cast<uint32_t>(i);
  }
  for (uint32_t m : movers_) is_mover_[m] = 1;
  // Forget the movers' pairs and move them to their new cells.
  for (uint32_t m : movers_) {
    for (uint32_t j : rows_[m]) {
      if (is_mover_[j]) continue;
      auto& r = rows_[j];
      r.erase(std::lower_bound(r.begin(), r.end(), m));
    }
    rows_[m].clear();
    if (!first) {
      auto& old = cells_[cell_of_[m]];
      old.erase(std::find(old.begin(), old.end(), m));
    }
    y_built_[m] = {y[m].x, y[m].y, y[m].z};
    cell_of_[m] = cell_key(y_built_[m]);
    cells_[cell_of_[m]].push_back(m);
  }
  // Find their pairs again: within cut-off + skin, and not in the mover's family (rows
  // of the bonds are sorted by neighbour). A pair of two movers is found by both.
  std::vector<uint32_t> touched;
  for (uint32_t m : movers_) {
    const Vec3 p = y_built_[m];
    const auto first_bond = B.nbr.begin() + static_cast<std::ptrdiff_t>(B.begin(m));
    const auto last_bond = B.nbr.begin() + static_cast<std::ptrdiff_t>(B.end(m));
    const int64_t c[3] = {cell_coord(p.x, edge), cell_coord(p.y, edge), cell_coord(p.z, edge)};
    for (int64_t a = c[0] - 1; a <= c[0] + 1; ++a)
      for (int64_t b = c[1] - 1; b <= c[1] + 1; ++b)
        for (int64_t d = c[2] - 1; d <= c[2] + 1; ++d) {
          const auto it = cells_.find(pack_cell(a, b, d));
          if (it == cells_.end()) continue;
          for (uint32_t j : it->second) {
            if (j == m || norm2(y_built_[j] - p) > reach2) continue;
            if (std::binary_search(first_bond, last_bond, j)) continue;
            // A row this rank does not hold (a run split over ranks with local rows,
            // parallel/decomposition.hpp) is empty: the family test then reads j's row
            // (families are symmetric; serially an empty row has no family at all).
            if (first_bond == last_bond && B.end(j) > B.begin(j) &&
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
    std::sort(rows_[m].begin(), rows_[m].end());
  }
  for (uint32_t j : touched) std::sort(rows_[j].begin(), rows_[j].end());
  for (uint32_t m : movers_) is_mover_[m] = 0;
  rebuilds_ += movers_.size();
  candidates_ = 0;
  for (const auto& r : rows_) candidates_ += r.size();
}

void ShortRangeContact::add_forces(const System& s, const Point4* y, Vec3* f, double* W) {
  if (!enabled_) return;
  const auto& P = s.particles;
  const auto& M = s.model;
  const std::size_t n = P.size();
  if (y_built_.size() != n) {
    update(s, y);
  } else {
    // The particles that moved more than skin/2 since their last update, in index order.
    const double half2 = 0.25 * skin_ * skin_;
    movers_.clear();
    for (std::size_t i = 0; i < n; ++i) {
      const double dx = y[i].x - y_built_[i].x, dy = y[i].y - y_built_[i].y, dz = y[i].z - y_built_[i].z;
      if (dx * dx + dy * dy + dz * dz > half2) movers_.push_back(static_cast<uint32_t>(i));
    }
    if (!movers_.empty()) update(s, y);
  }
  if (candidates_ == 0) return;
  const double cut2 = cutoff_ * cutoff_;
  const double factor = config_.stiffness_factor / horizon_;
  // A decomposed run adds the contact of its active particles alone (solver/system.hpp).
  const std::vector<uint32_t>* act = s.active_rows.empty() ? nullptr : &s.active_rows;
  const std::size_t count = act ? act->size() : n;
#pragma omp parallel for schedule(static)
  for (std::size_t a = 0; a < count; ++a) {
    const std::size_t i = act ? (*act)[a] : a;
    if (rows_[i].empty()) continue;
    Vec3 fi;
    double wi = 0;
    for (uint32_t j : rows_[i]) {
      const double dx = y[j].x - y[i].x, dy = y[j].y - y[i].y, dz = y[j].z - y[i].z;
      const double r2 = dx * dx + dy * dy + dz * dz;
      if (!(r2 < cut2) || r2 == 0) continue;
      const double d = distance(norm(P.X[j] - P.X[i]));
      const double r = std::sqrt(r2);
      if (!(r < d)) continue;
      const double k = factor * 0.5 * (M.contact_micromodulus[i] + M.contact_micromodulus[j]) * P.volume[j];
      const double a = -k * (d - r) / r;  // pushes i away from j
      fi += Vec3{dx, dy, dz} * a;
      wi += 0.25 * k * (d - r) * (d - r);
    }
    f[i] += fi;
    if (W) W[i] += wi;
  }
}

}  // namespace horizon
