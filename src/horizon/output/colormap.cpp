#include "horizon/output/colormap.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace horizon {

Rgb viridis(double t) {
  // Ten equally spaced samples of the published viridis map (as tabulated by
  // matplotlib and R's viridisLite, hex #440154 ... #FDE725), interpolated linearly:
  // close to the full 256-entry table, and t = 1 gives the top colour exactly.
  static constexpr std::array<std::array<double, 3>, 10> stops{{
      {68, 1, 84},    {72, 40, 120},  {62, 74, 137},  {49, 104, 142}, {38, 130, 142},
      {31, 158, 137}, {53, 183, 121}, {109, 205, 89}, {180, 222, 44}, {253, 231, 37},
  }};
  if (!(t > 0)) t = 0;  // also maps NaN to the bottom
  t = std::min(t, 1.0);
  const double u = t * double(stops.size() - 1);
  const size_t i = std::min(size_t(u), stops.size() - 2);
  const double w = u - double(i);
  auto mix = [&](int c) {
    return uint8_t(std::lround(stops[i][c] + (stops[i + 1][c] - stops[i][c]) * w));
  };
  return {mix(0), mix(1), mix(2)};
}

}  // namespace horizon
