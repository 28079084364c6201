#include "horizon/damage/crack_tracking.hpp"

#include <algorithm>
#include <cmath>

#include "horizon/parallel/decomposition.hpp"
#include "horizon/parallel/lead_view.hpp"

namespace horizon {

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

// Edge cracks of a thermal shock (crack_tracking.hpp): two streams through rank 0.
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

}  // namespace horizon
