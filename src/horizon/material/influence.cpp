#include "horizon/material/influence.hpp"

namespace horizon {

double influence_moment(InfluenceKind kind, double horizon, int p) {
  static const double node[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                                 0.9061798459386640};
  static const double wt[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889, 0.4786286704993665,
                               0.2369268850561891};
  constexpr int kPanels = 64;
  const double h = horizon / kPanels;
  double sum = 0;
  for (int k = 0; k < kPanels; ++k) {
    const double mid = (k + 0.5) * h;
    for (int q = 0; q < 5; ++q) {
      const double r = mid + 0.5 * h * node[q];
      sum += wt[q] * influence(kind, r, horizon) * std::pow(r, p);
    }
  }
  return 0.5 * h * sum;
}

}  // namespace horizon
