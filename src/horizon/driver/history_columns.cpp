#include "horizon/driver/history_columns.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <vector>

#include "horizon/core/error.hpp"
#include "horizon/driver/summary.hpp"
#include "horizon/material/model.hpp"
#include "horizon/parallel/decomposition.hpp"
#include "horizon/state/system.hpp"

namespace horizon {

namespace {

bool is_vector(HistoryQuantity q) {
  switch (q) {
    case HistoryQuantity::volume:
    case HistoryQuantity::damage:
    case HistoryQuantity::kinetic_energy:
    case HistoryQuantity::strain_energy:
      return false;
    default:
      return true;
  }
}

// The quantity of particle i (3 components; scalars in the first). Peridigm's Force is
// the force density times the volume; its energies and momenta are per particle.
Vec3 value_of(const System& s, std::size_t i, HistoryQuantity q) {
  const Particles& p = s.particles;
  const double m = p.density[i] * p.volume[i];
  switch (q) {
    case HistoryQuantity::displacement: return p.u[i];
    case HistoryQuantity::velocity: return p.v[i];
    case HistoryQuantity::force: return p.f[i] * p.volume[i];
    case HistoryQuantity::force_density: return p.f[i];
    case HistoryQuantity::position: return p.X[i] + p.u[i];
    case HistoryQuantity::reference_position: return p.X[i];
    case HistoryQuantity::volume: return {p.volume[i], 0, 0};
    case HistoryQuantity::damage: return {p.damage[i], 0, 0};
    case HistoryQuantity::kinetic_energy: return {0.5 * m * dot(p.v[i], p.v[i]), 0, 0};
    case HistoryQuantity::strain_energy: return {p.energy[i] * p.volume[i], 0, 0};
    case HistoryQuantity::linear_momentum: return p.v[i] * m;
    case HistoryQuantity::angular_momentum: return cross(p.X[i] + p.u[i], p.v[i] * m);
  }
  return {};
}

}  // namespace

std::vector<std::string> history_columns_names(const Config& config) {
  std::vector<std::string> names;
  for (const auto& c : config.output.history_columns) {
    if (c.field.empty() && is_vector(c.quantity))
      for (const char* x : {"X", "Y", "Z"}) names.push_back(c.name + x);
    else
      names.push_back(c.name);
  }
  return names;
}

std::string history_columns_header(const Config& config) {
  std::string h;
  for (const auto& c : config.output.history_columns) {
    if (c.field.empty() && is_vector(c.quantity))
      h += "," + c.name + "X," + c.name + "Y," + c.name + "Z";
    else
      h += "," + c.name;
  }
  return h;
}

std::string history_columns_row(const Config& config, const System& s) {
  std::string row;
  for (double v : history_columns_values(config, s)) row += fmt::format(",{:.9e}", v);
  return row;
}

std::vector<double> history_columns_values(const Config& config, const System& s) {
  std::vector<double> row;
  const auto& columns = config.output.history_columns;
  if (columns.empty()) return row;
  const Particles& p = s.particles;
  // The models' output fields, gathered once a row when a column reads one.
  std::vector<ModelField> fields;
  bool gathered = false;
  for (const auto& c : columns) {
    const std::vector<double>* field = nullptr;
    if (!c.field.empty()) {
      if (!gathered)
        for (const auto& m : s.models) m->fields(s, fields);
      gathered = true;
      std::string names;
      for (const auto& f : fields) {
        if (f.name == c.field && !field) field = &f.values;
        names += (names.empty() ? "; fields: " : ", ") + f.name;
      }
      if (!field)
        throw Error(fmt::format("{}: output.history_columns: column '{}': no model of this run writes the field "
                                "'{}'{}",
                                config.deck_file, c.name, c.field, names));
    }
    // The value of particle i: the field's, or the quantity's.
    auto value = [&](std::size_t i) {
      return field ? Vec3{i < field->size() ? (*field)[i] : 0.0, 0, 0} : value_of(s, i, c.quantity);
    };
    const int body = [&] {
      if (c.body.empty()) return -1;
      for (std::size_t b = 0; b < s.block_names.size(); ++b)
        if (s.block_names[b] == c.body) return static_cast<int>(b);
      throw Error("output.history_columns: no body named '" + c.body + "'");
    }();
    const Shape* region = nullptr;
    if (!c.region.empty()) {
      const auto it = config.regions.find(c.region);
      if (it == config.regions.end()) throw Error("output.history_columns: no region named '" + c.region + "'");
      region = &it->second;
    }
    auto selected = [&](std::size_t i) {
      return (body < 0 || p.block[i] == body) && (!region || region->contains(p.X[i]));
    };
    const int n = field || !is_vector(c.quantity) ? 1 : 3;
    Vec3 out;
    if (c.reduce == HistoryReduce::nearest) {
      // The particle nearest the point in the reference configuration; of equals, the
      // smallest global id (the same particle on any number of ranks).
      double best = std::numeric_limits<double>::infinity(), best_id = best;
      for_each_summed(s, [&](std::size_t i) {
        const double d = norm2(p.X[i] - c.at);
        const auto id = static_cast<double>(p.id[i]);
        if (d < best || (d == best && id < best_id)) best = d, best_id = id;
      });
      if (s.decomposition) {
        const double d = min_over_ranks(best);
        best_id = min_over_ranks(best == d ? best_id : std::numeric_limits<double>::infinity());
      }
      GridSum sum = GridSum::exact(s, 3);
      for_each_summed(s, [&](std::size_t i) {
        if (static_cast<double>(p.id[i]) == best_id) sum.add(0, value(i));
      });
      const auto t = sum.totals();
      out = {t[0], t[1], t[2]};
    } else if (c.reduce == HistoryReduce::sum) {
      GridSum sum = GridSum::exact(s, 3);
      for_each_summed(s, [&](std::size_t i) {
        if (selected(i)) sum.add(0, value(i));
      });
      const auto t = sum.totals();
      out = {t[0], t[1], t[2]};
    } else {
      // Minimum or maximum of each component; the maximum as minus the minimum of minus.
      const double sign = c.reduce == HistoryReduce::min ? 1.0 : -1.0;
      Vec3 low{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
               std::numeric_limits<double>::infinity()};
      for_each_summed(s, [&](std::size_t i) {
        if (!selected(i)) return;
        const Vec3 v = value(i) * sign;
        for (int k = 0; k < 3; ++k) low[k] = std::min(low[k], v[k]);
      });
      for (int k = 0; k < 3; ++k) out[k] = sign * (s.decomposition ? min_over_ranks(low[k]) : low[k]);
    }
    for (int k = 0; k < n; ++k) row.push_back(out[k]);
  }
  return row;
}

}  // namespace horizon
