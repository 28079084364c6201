#include "horizon/material/shear_correction.hpp"

namespace horizon {

double shear_correction_factor(const FamilyView& family, int dimension) {
  // S = sum_j omega V_j xi (x) xi over the in-plane components (header).
  const int d = dimension == 2 ? 2 : 3;
  double S[3][3] = {};
  for (std::size_t k = 0; k < family.xi.size(); ++k) {
    const double x[3] = {family.xi[k].x, family.xi[k].y, family.xi[k].z};
    for (int a = 0; a < d; ++a)
      for (int b = 0; b < d; ++b) S[a][b] += family.wv[k] * x[a] * x[b];
  }
  double m = 0;
  for (int a = 0; a < d; ++a) m += S[a][a];
  if (!(m > 0)) return 1.0;
  // |dev S|^2 = |S|^2 - (tr S)^2/d.
  double norm2 = 0;
  for (int a = 0; a < d; ++a)
    for (int b = 0; b < d; ++b) norm2 += S[a][b] * S[a][b];
  const double full = (1.0 - 1.0 / d) * m * m;  // (1 - 1/d) m^2: the isotropic family's
  const double dev2 = norm2 - m * m / d;
  // The deviatoric stiffness left, as a fraction of the isotropic family's: in [0, 1].
  const double left = 1.0 - dev2 / full;
  if (!(left > kShearCorrectionFloor)) return 1.0;
  return 1.0 / left;
}

}  // namespace horizon
