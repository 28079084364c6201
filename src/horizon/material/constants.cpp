#include "horizon/material/constants.hpp"

#include <cmath>
#include <numbers>

#include "horizon/material/influence.hpp"

namespace horizon {

namespace {
constexpr double kPi = std::numbers::pi;

// int_H omega(|xi|) |xi| dV = S_d * int_0^delta omega r^d dr, with the shell measure
// S_3 = 4 pi r^2, S_2 = 2 pi r t, S_1 = 2 A.
double first_moment_volume(InfluenceKind omega, const Dimensioning& d) {
  switch (d.dimension) {
    case 3: return 4 * kPi * influence_moment(omega, d.horizon, 3);
    case 2: return 2 * kPi * d.thickness * influence_moment(omega, d.horizon, 2);
    default: return 2 * d.area * influence_moment(omega, d.horizon, 1);
  }
}
}  // namespace

double bond_based_poisson_ratio(int dimension, PlaneMode plane) {
  return (dimension == 2 && plane == PlaneMode::stress) ? 1.0 / 3.0 : 0.25;
}

double isotropic_energy_per_s2(double E, const Dimensioning& d) {
  const double nu = bond_based_poisson_ratio(d.dimension, d.plane);
  switch (d.dimension) {
    case 3: return 4.5 * E / (3 * (1 - 2 * nu));
    case 2: return d.plane == PlaneMode::stress ? E / (1 - nu) : E / ((1 + nu) * (1 - 2 * nu));
    default: return 0.5 * E;
  }
}

double pmb_micromodulus(double E, InfluenceKind omega, const Dimensioning& d) {
  return 4 * isotropic_energy_per_s2(E, d) / first_moment_volume(omega, d);
}

double pmb_critical_stretch(double G0, double c, InfluenceKind omega, const Dimensioning& d) {
  double h_factor = 0;  // h(r) = h_factor * r^(d)
  switch (d.dimension) {
    case 3: h_factor = kPi; break;
    case 2: h_factor = 2 * d.thickness; break;
    default: h_factor = d.area; break;
  }
  const double integral = 0.5 * c * h_factor * influence_moment(omega, d.horizon, d.dimension + 1);
  return std::sqrt(G0 / integral);
}

double lps_bulk_modulus(double k, double mu, const Dimensioning& d) {
  if (d.dimension != 2) return k;
  if (d.plane == PlaneMode::strain) return k + mu / 3;  // lambda + mu
  return 9 * k * mu / (3 * k + 4 * mu);
}

double lps_deviatoric_factor(int dimension) { return dimension == 2 ? 8.0 : 15.0; }

double lps_critical_stretch(double G0, double k, double mu, const Dimensioning& d) {
  const double kk = lps_bulk_modulus(k, mu, d);
  const double denom = d.dimension == 2 ? (6 * mu / kPi + 16 / (9 * kPi * kPi) * (kk - 2 * mu))
                                        : (3 * mu + std::pow(0.75, 4) * (kk - 5 * mu / 3));
  return std::sqrt(G0 / (denom * d.horizon));
}

double equivalent_micromodulus(double k, double mu, InfluenceKind omega, const Dimensioning& d) {
  // A bond-based material with the model's dilatational stiffness: in each dimension
  // the PMB micromodulus for the Young's modulus that gives the same bulk modulus.
  const double kk = lps_bulk_modulus(k, mu, d);
  const double nu = bond_based_poisson_ratio(d.dimension, d.plane);
  double E = 0;
  switch (d.dimension) {
    case 3: E = 3 * kk * (1 - 2 * nu); break;
    case 2: E = d.plane == PlaneMode::stress ? 2 * kk * (1 - nu) : 2 * kk * (1 + nu) * (1 - 2 * nu); break;
    default: E = kk; break;
  }
  return pmb_micromodulus(E, omega, d);
}

}  // namespace horizon
