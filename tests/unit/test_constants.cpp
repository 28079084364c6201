// Model constants (material/constants.hpp, material/influence.hpp) against their closed
// forms: PMB micromodulus and critical stretch (seed 002 eq. 17-18, 26-29 and the 2-D/1-D
// table of the digest, sec. 2.1), LPS bulk modulus and deviatoric factor (seed 003
// eq. 112 and digest sec. 8), influence moments, and the Poisson's ratio a bond-based
// material is forced to. docs/models.md collects the formulas.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "horizon/material/constants.hpp"
#include "horizon/material/influence.hpp"

namespace horizon {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kRel = 1e-12;

// Relative closeness, the check every closed form below uses.
void expect_rel(double got, double want, double tol = kRel) {
  EXPECT_NEAR(got / want, 1.0, tol) << "got " << got << ", want " << want;
}

const double kE = 72.0e9, kDelta = 1.0e-3, kT = 2.0e-3, kA = 3.0e-6, kG0 = 3.8;

Dimensioning dims3() { return {3, PlaneMode::none, 1, 1, kDelta}; }
Dimensioning dims_stress() { return {2, PlaneMode::stress, kT, 1, kDelta}; }
Dimensioning dims_strain() { return {2, PlaneMode::strain, kT, 1, kDelta}; }
Dimensioning dims1() { return {1, PlaneMode::none, 1, kA, kDelta}; }

TEST(Constants, BondBasedPoissonRatio) {
  EXPECT_DOUBLE_EQ(bond_based_poisson_ratio(3, PlaneMode::none), 0.25);
  EXPECT_DOUBLE_EQ(bond_based_poisson_ratio(2, PlaneMode::stress), 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(bond_based_poisson_ratio(2, PlaneMode::strain), 0.25);
  EXPECT_DOUBLE_EQ(bond_based_poisson_ratio(1, PlaneMode::none), 0.25);
}

TEST(Constants, PmbMicromodulusClosedForms) {
  const double k = kE / (3 * (1 - 2 * 0.25));
  expect_rel(pmb_micromodulus(kE, InfluenceKind::constant, dims3()), 18 * k / (kPi * std::pow(kDelta, 4)));
  expect_rel(pmb_micromodulus(kE, InfluenceKind::constant, dims_stress()), 9 * kE / (kPi * kT * std::pow(kDelta, 3)));
  expect_rel(pmb_micromodulus(kE, InfluenceKind::constant, dims_strain()),
             48 * kE / (5 * kPi * kT * std::pow(kDelta, 3)));
  expect_rel(pmb_micromodulus(kE, InfluenceKind::constant, dims1()), 2 * kE / (kA * kDelta * kDelta));
}

TEST(Constants, PmbCriticalStretchClosedForms) {
  const double k = kE / (3 * (1 - 2 * 0.25));
  struct Case {
    Dimensioning d;
    double want;
  };
  const Case cases[] = {
      {dims3(), std::sqrt(5 * kG0 / (9 * k * kDelta))},
      {dims_stress(), std::sqrt(4 * kPi * kG0 / (9 * kE * kDelta))},
      {dims_strain(), std::sqrt(5 * kPi * kG0 / (12 * kE * kDelta))},
      {dims1(), std::sqrt(3 * kG0 / (kE * kDelta))},
  };
  for (const auto& c : cases) {
    const double cc = pmb_micromodulus(kE, InfluenceKind::constant, c.d);
    expect_rel(pmb_critical_stretch(kG0, cc, InfluenceKind::constant, c.d), c.want);
  }
}

// With any influence function the micromodulus satisfies its defining calibration,
// (1/4) c int_H omega |xi| dV = classical energy per s^2 (seed 002 eq. 17), here with
// the moments int_0^delta omega r^d dr in closed form.
TEST(Constants, PmbMicromodulusCalibrationForEveryInfluence) {
  const double k = kE / (3 * (1 - 2 * 0.25));
  const double d = kDelta;
  // int_0^delta omega r^p dr / delta^(p+1) for p = 1, 2, 3 (rows: constant, inverse, linear).
  const double mom[3][4] = {
      {0, 1.0 / 2, 1.0 / 3, 1.0 / 4}, {0, 1.0, 1.0 / 2, 1.0 / 3}, {0, 1.0 / 6, 1.0 / 12, 1.0 / 20}};
  const InfluenceKind kinds[3] = {InfluenceKind::constant, InfluenceKind::inverse, InfluenceKind::linear};
  for (int w = 0; w < 3; ++w) {
    const double c3 = pmb_micromodulus(kE, kinds[w], dims3());
    expect_rel(0.25 * c3 * 4 * kPi * mom[w][3] * std::pow(d, 4), 4.5 * k);
    const double cs = pmb_micromodulus(kE, kinds[w], dims_stress());
    expect_rel(0.25 * cs * 2 * kPi * kT * mom[w][2] * std::pow(d, 3), kE / (1 - 1.0 / 3));
    const double cp = pmb_micromodulus(kE, kinds[w], dims_strain());
    expect_rel(0.25 * cp * 2 * kPi * kT * mom[w][2] * std::pow(d, 3), kE / (1.25 * 0.5));
    const double c1 = pmb_micromodulus(kE, kinds[w], dims1());
    expect_rel(0.25 * c1 * 2 * kA * mom[w][1] * d * d, 0.5 * kE);
  }
}

TEST(Constants, LpsBulkModulusAndDeviatoricFactor) {
  const double E = 2.0e11, nu = 0.3;
  const double k = E / (3 * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
  const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
  expect_rel(lps_bulk_modulus(k, mu, dims3()), k);
  expect_rel(lps_bulk_modulus(k, mu, dims_stress()), E / (2 * (1 - nu)));
  expect_rel(lps_bulk_modulus(k, mu, dims_strain()), lambda + mu);
  EXPECT_EQ(lps_deviatoric_factor(3), 15.0);
  EXPECT_EQ(lps_deviatoric_factor(2), 8.0);
}

// The LPS critical stretch (Madenci and Oterkus 2014) reduces to the PMB one when the
// Poisson's ratio is the one a bond-based material has (both count the same bonds).
TEST(Constants, LpsCriticalStretchReducesToPmbAtBondBasedPoissonRatio) {
  for (const Dimensioning& d : {dims3(), dims_stress(), dims_strain()}) {
    const double nu = bond_based_poisson_ratio(d.dimension, d.plane);
    const double k = kE / (3 * (1 - 2 * nu)), mu = kE / (2 * (1 + nu));
    const double c = pmb_micromodulus(kE, InfluenceKind::constant, d);
    expect_rel(lps_critical_stretch(kG0, k, mu, d), pmb_critical_stretch(kG0, c, InfluenceKind::constant, d));
  }
  // And the printed closed forms at another Poisson's ratio.
  const double nu = 0.2, k = kE / (3 * (1 - 2 * nu)), mu = kE / (2 * (1 + nu));
  expect_rel(lps_critical_stretch(kG0, k, mu, dims3()),
             std::sqrt(kG0 / ((3 * mu + std::pow(0.75, 4) * (k - 5 * mu / 3)) * kDelta)));
  const double kk = kE / (2 * (1 - nu));
  expect_rel(lps_critical_stretch(kG0, k, mu, dims_stress()),
             std::sqrt(kG0 / ((6 * mu / kPi + 16 / (9 * kPi * kPi) * (kk - 2 * mu)) * kDelta)));
}

// The equivalent micromodulus used for the stable time step is the PMB one when the
// material is bond-based.
TEST(Constants, EquivalentMicromodulusMatchesPmbForBondBasedMaterial) {
  for (const Dimensioning& d : {dims3(), dims_stress(), dims_strain()}) {
    const double nu = bond_based_poisson_ratio(d.dimension, d.plane);
    const double k = kE / (3 * (1 - 2 * nu)), mu = kE / (2 * (1 + nu));
    for (InfluenceKind w : {InfluenceKind::constant, InfluenceKind::linear})
      expect_rel(equivalent_micromodulus(k, mu, w, d), pmb_micromodulus(kE, w, d), 1e-11);
  }
}

TEST(Constants, InfluenceFunctionValues) {
  EXPECT_EQ(influence(InfluenceKind::constant, 0.3, 1.0), 1.0);
  EXPECT_DOUBLE_EQ(influence(InfluenceKind::inverse, 0.25, 1.0), 4.0);
  EXPECT_DOUBLE_EQ(influence(InfluenceKind::linear, 0.25, 1.0), 0.75);
  EXPECT_DOUBLE_EQ(influence(InfluenceKind::gaussian, 0.5, 1.0), std::exp(-0.25));
}

// int_0^delta omega(r) r^p dr in closed form for each influence function.
TEST(Constants, InfluenceMomentClosedForms) {
  const double d = 2.5e-3;
  // Gaussian: I_p = int_0^1 exp(-x^2) x^p dx, I_p = (p-1)/2 I_{p-2} - e^{-1}/2.
  double I[6];
  I[0] = std::sqrt(kPi) / 2 * std::erf(1.0);
  I[1] = (1 - std::exp(-1.0)) / 2;
  for (int p = 2; p < 6; ++p) I[p] = (p - 1) / 2.0 * I[p - 2] - std::exp(-1.0) / 2;
  for (int p = 1; p <= 5; ++p) {
    const double s = std::pow(d, p + 1);
    expect_rel(influence_moment(InfluenceKind::constant, d, p), s / (p + 1));
    expect_rel(influence_moment(InfluenceKind::inverse, d, p), s / p);
    expect_rel(influence_moment(InfluenceKind::linear, d, p), s / ((p + 1.0) * (p + 2.0)));
    expect_rel(influence_moment(InfluenceKind::gaussian, d, p), s * I[p]);
  }
}

// Calibration identities of the LPS (seed 003 eq. 109-110 and digest sec. 8):
// m = 4 pi delta^5/5 (3-D) and pi delta^4/2 (2-D, per unit thickness) with omega = 1.
TEST(Constants, WeightedVolumeClosedForms) {
  expect_rel(4 * kPi * influence_moment(InfluenceKind::constant, kDelta, 4), 4 * kPi * std::pow(kDelta, 5) / 5);
  expect_rel(2 * kPi * influence_moment(InfluenceKind::constant, kDelta, 3), kPi * std::pow(kDelta, 4) / 2);
}

TEST(Constants, IsotropicEnergyPerStretchSquared) {
  const double k = kE / 1.5;
  expect_rel(isotropic_energy_per_s2(kE, dims3()), 4.5 * k);
  expect_rel(isotropic_energy_per_s2(kE, dims_stress()), 1.5 * kE);
  expect_rel(isotropic_energy_per_s2(kE, dims_strain()), kE / (1.25 * 0.5));
  expect_rel(isotropic_energy_per_s2(kE, dims1()), 0.5 * kE);
}

}  // namespace
}  // namespace horizon
