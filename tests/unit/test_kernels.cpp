// The device-portable kernels (src/horizon/kernels/, issue 30) against closed forms:
// PMB's pair force (seed 002 eq. 22), LPS's dilatation of a uniform stretch (seed 003
// eq. 113), the critical stretch with alpha and no_fail, velocity Verlet under a constant
// force, the family contact, finite(). The host's passes and the CUDA backend call these.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "horizon/kernels/flat_system.hpp"
#include "horizon/kernels/ordinary.hpp"
#include "horizon/material/models/history_ledger.hpp"

namespace horizon::kernels {
namespace {

TEST(Kernels, PmbForceIsHalfTheMicromodulusTimesTheStretchAlongTheBond) {
  const double c = 3.0e19, L = 2e-3, V = 1e-9, e = 4e-6, s = e / L;
  // t_ij = omega R e/L with R = c/2: c s / 2 (seed 002 eq. 22).
  EXPECT_NEAR(unified_force_scalar(1.0, 0, 0, c / 2, L, 1 / L, e) / (c * s / 2), 1.0, 1e-15);
  // The pair form, pair = omega V (R_i + R_j)/L: (t_ij + t_ji) V / |Y| along Y.
  const double r = L + e;
  EXPECT_NEAR(pair_bond_coefficient(V * c / L, e, r) * r / (c * s * V), 1.0, 1e-15);
  EXPECT_NEAR(pair_force_coefficient(V, V * c / L, 0, 0, 0, 0, L, e, r) * r / (c * s * V), 1.0, 1e-15);
  // W share (1/2) t e V_j = c s^2 L V / 4, intact or broken.
  EXPECT_NEAR(pmb_bond_energy(V, c / 2, 1 / L, e) / (c * s * s * L * V / 4), 1.0, 1e-15);
  EXPECT_NEAR(pmb_broken_energy(V, c / 2, 1 / L, e) / (c * s * s * L * V / 4), 1.0, 1e-15);
  EXPECT_NEAR(bond_work(c * s / 2, e, V) / (c * s * s * L * V / 4), 1.0, 1e-15);
}

TEST(Kernels, LpsDilatationOfAUniformStretchIsDTimesTheStretch) {
  // Every bond stretched by s: theta = (d/m) sum omega |xi| (s |xi|) V = d s.
  const double s = 1e-3, V = 1e-9, lengths[3] = {1e-3, std::sqrt(2.0) * 1e-3, std::sqrt(3.0) * 1e-3};
  double sum = 0, m = 0;
  for (double L : lengths) {
    sum += dilatation_term(V, L, extension(L * (1 + s), L, 0));
    m += weighted_volume_term(1.0, L, V);
  }
  EXPECT_NEAR(dilatation(3, sum, m) / (3 * s), 1.0, 1e-12);
  // P = theta (a - b/d): t = omega (P L + Q e) is the LPS force state (seed 003 eq. 112).
  const double theta = 3 * s, a = 2.0, b = 3.0;
  EXPECT_DOUBLE_EQ(dilatation_pressure(theta, a, b, 3), theta * (a - 1.0));
  // The deviatoric extension of a uniform stretch vanishes (seed 003 sec. 15).
  EXPECT_NEAR(deviatoric_extension(s * 2e-3, theta, 2e-3, 3), 0.0, 1e-18);
}

TEST(Kernels, CriticalStretchTakesAlphaAndNoFail) {
  EXPECT_DOUBLE_EQ(critical_stretch_now(0.01, 0.25, -0.004, false), 0.011);
  EXPECT_DOUBLE_EQ(critical_stretch_now(0.01, 0.25, INFINITY, false), 0.01);  // no intact bond yet
  EXPECT_TRUE(std::isinf(critical_stretch_now(0.01, 0.25, -0.004, true)));
  EXPECT_TRUE(breaks(0.02, 0.03, 0.01));   // the smaller s0 of the two ends
  EXPECT_FALSE(breaks(0.02, 0.03, 0.025));
  EXPECT_FALSE(breaks(std::numeric_limits<double>::quiet_NaN(), 0.01, 0.01));
  EXPECT_TRUE(finite(1.0));
  EXPECT_FALSE(finite(INFINITY));
  EXPECT_FALSE(finite(std::numeric_limits<double>::quiet_NaN()));
}

TEST(Kernels, VerletUnderAConstantForceIsExact) {
  // u(t) = v0 t + a t^2/2, v(t) = v0 + a t under f/rho = a (no damping).
  const double rho = 7850, f = 7850 * 3.0, v0 = 2.0, dt = 1e-3;
  double u = 0, v = v0;
  for (int n = 0; n < 10; ++n) {
    v = half_kick(v, f, 0, 1.0 / rho, 0, dt / 2);
    u = drift(u, v, dt);
    v = second_half_kick(v, f, 0, (dt / 2) / rho, 1.0);
  }
  const double t = 10 * dt;
  EXPECT_NEAR(u, v0 * t + 1.5 * t * t, 1e-15);
  EXPECT_NEAR(v, v0 + 3.0 * t, 1e-13);
  EXPECT_DOUBLE_EQ(kinetic(2.0, 0.5, 1.0, 2.0, 2.0), 4.5);
}

TEST(Kernels, FamilyContactPushesApartInsideItsDistance) {
  double a = 0, w = 0;
  const double d = 1e-3, k = 5e15;
  EXPECT_FALSE(contact_coefficient(d * d, d, k, 4 * d * d, a, w));  // apart
  EXPECT_FALSE(contact_coefficient(d * d, d, k, 0, a, w));          // coincident: no direction
  ASSERT_TRUE(contact_coefficient(d * d, d, k, 0.25 * d * d, a, w));
  EXPECT_DOUBLE_EQ(a, -k * (d - 0.5 * d) / (0.5 * d));  // a Y: away from j
  EXPECT_DOUBLE_EQ(w, 0.25 * k * 0.25 * d * d);
  EXPECT_DOUBLE_EQ(damage_fraction(3.0, 4.0), 0.25);
  EXPECT_DOUBLE_EQ(damage_fraction(0.0, 0.0), 0.0);
}

}  // namespace
// The ledger's booking as a portable kernel (kernels::ledger_open_bond, which
// HistoryLedger::Row and the flat rows call) against the host ledger's own member path
// (HistoryLedger::open_bond, scalar form: open() with the booking as a callback), on
// random bonds: intact 0, 1 or 2, booked or not, a pending booking or not. The same trial
// extensions, flags, pending amounts and booked sums, bit for bit; and with the flags in
// place (the trial flags the committed ones), the same as the host ledger's copies.
TEST(Kernels, LedgerBookingIsTheHostLedgersBitForBit) {
  std::mt19937_64 rng(30);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const std::size_t nb = 4000;
  HistoryLedger host;
  host.booked.assign(nb, 0);
  host.extension.assign(nb, 0.0);
  host.pending_amount.assign(nb, 0.0);
  host.pending_set.assign(nb, 0);
  std::vector<uint8_t> intact(nb);
  for (std::size_t k = 0; k < nb; ++k) {
    intact[k] = static_cast<uint8_t>(rng() % 3);
    host.booked.committed()[k] = static_cast<uint8_t>(rng() % 2);
    host.pending_set[k] = static_cast<uint8_t>(rng() % 2);
    host.pending_amount[k] = u(rng);
  }
  std::vector<double> ext(nb, 0.0), amount = host.pending_amount;
  std::vector<uint8_t> committed(host.booked.committed(), host.booked.committed() + nb), trial(nb, 0),
      pending = host.pending_set, in_place = committed, pending_in_place = pending;
  std::vector<double> amount_in_place = amount;
  const kernels::LedgerBonds L{ext.data(), committed.data(), trial.data(), pending.data(), amount.data()};
  const kernels::LedgerBonds P{ext.data(), in_place.data(), in_place.data(), pending_in_place.data(),
                               amount_in_place.data()};
  double sum_host = 0, sum_kernel = 0, sum_in_place = 0;
  int booked = 0;
  for (std::size_t k = 0; k < nb; ++k) {
    const double t = 1e3 * u(rng), length = k % 17 == 0 ? 0.0 : 1e-3 * (1.5 + u(rng)), e = 1e-5 * u(rng),
                 V = 1e-9 * (1.2 + u(rng));
    const bool h = host.open_bond(k, intact[k], t, length, e, V, sum_host);
    const bool a = kernels::ledger_open_bond(L, k, intact[k], t, length, e, V, sum_kernel);
    const bool b = kernels::ledger_open_bond(P, k, intact[k], t, length, e, V, sum_in_place);
    EXPECT_EQ(h, a);
    EXPECT_EQ(h, b);
    booked += h;
  }
  EXPECT_GT(booked, 100);
  auto same = [](double x, double y) { return std::memcmp(&x, &y, sizeof x) == 0; };
  EXPECT_TRUE(same(sum_host, sum_kernel));
  EXPECT_TRUE(same(sum_host, sum_in_place));
  int bad = 0;
  for (std::size_t k = 0; k < nb; ++k)
    bad += !same(host.extension.trial()[k], ext[k]) || host.booked.trial()[k] != trial[k] ||
           host.booked.trial()[k] != in_place[k] || host.pending_set[k] != pending[k] ||
           host.pending_set[k] != pending_in_place[k] || !same(host.pending_amount[k], amount[k]) ||
           !same(host.pending_amount[k], amount_in_place[k]);
  EXPECT_EQ(bad, 0);
}

}  // namespace horizon::kernels
