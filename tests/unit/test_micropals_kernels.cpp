// The portable kernels of microplastic, PALS, the linearised LPS and the bond-pair model
// (kernels/microplastic.hpp, pals.hpp, linear_lps.hpp, bond_pair.hpp; issue 30): against closed forms, and bit for
// bit against the host forms they replaced (the models' loops as they were before the
// kernels, copied here as the reference) on random rows.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

#include "horizon/core/point4.hpp"
#include "horizon/core/vec3.hpp"
#include "horizon/family/bonds.hpp"
#include "horizon/kernels/bond_pair.hpp"
#include "horizon/kernels/linear_lps.hpp"
#include "horizon/kernels/microplastic.hpp"
#include "horizon/kernels/pals.hpp"
#include "kernel_bits.hpp"

namespace horizon {
namespace {

using test::same_bits;

// A random row of n bonds over `kinds` kinds: |xi| in [1, 1.7] mm, V_j, fraction, omega.
struct RandomRow {
  std::vector<BondKind> kinds;
  std::vector<uint32_t> kind;
  std::vector<uint8_t> intact;
};
RandomRow random_row(std::mt19937_64& g, std::size_t n, std::size_t kinds) {
  std::uniform_real_distribution<double> u(0, 1);
  RandomRow r;
  for (std::size_t c = 0; c < kinds; ++c) {
    BondKind b;
    b.length = 1e-3 * (1 + 0.7 * u(g));
    b.volume = 1e-9 * (0.5 + u(g));
    b.fraction = u(g) < 0.7 ? 1.0 : 0.2 + 0.8 * u(g);
    b.weight = 0.3 + u(g);
    r.kinds.push_back(b);
  }
  for (std::size_t k = 0; k < n; ++k) {
    r.kind.push_back(static_cast<uint32_t>(g() % kinds));
    r.intact.push_back(u(g) < 0.85 ? 1 : 0);
  }
  return r;
}

// --- microplastic ---

TEST(MicropalsKernels, MicroplasticBondIsElasticBelowYieldAndPerfectlyPlasticAbove) {
  const double c = 3e19, sy = 1e-3, L = 2e-3, V = 1e-9, omega = 0.8;
  // Below yield: sbar stays, t = omega c s/2, W share = (t/2) s L V (seed 002 eq. 19).
  const double s = 0.5 * sy;
  kernels::MicroplasticBond b = kernels::microplastic_bond(s * L, L, omega, V, c, sy, 0.0, 0.0, 0.0);
  EXPECT_EQ(b.sbar, 0.0);
  EXPECT_FALSE(b.yielded);
  EXPECT_NEAR(b.t / (omega * c * s / 2), 1.0, 1e-15);
  EXPECT_NEAR(b.energy / (omega * c * s * s * L * V / 4), 1.0, 1e-15);
  EXPECT_NEAR(b.work / (0.5 * b.t * s * L * V), 1.0, 1e-15);  // from rest: (0 + t)/2 e V
  // Above yield in tension and compression: |s - sbar| = s_Y, |t| = omega c s_Y/2.
  b = kernels::microplastic_bond(3 * sy * L, L, omega, V, c, sy, 0.0, 0.0, 0.0);
  EXPECT_TRUE(b.yielded);
  EXPECT_NEAR(b.sbar / (2 * sy), 1.0, 1e-15);
  EXPECT_NEAR(b.t / (omega * c * sy / 2), 1.0, 1e-12);
  b = kernels::microplastic_bond(-3 * sy * L, L, omega, V, c, sy, 0.0, 0.0, 0.0);
  EXPECT_NEAR(b.t / (-omega * c * sy / 2), 1.0, 1e-12);
  // Unloading from sbar = 2 s_Y to s = 1.5 s_Y: elastic, sbar kept.
  b = kernels::microplastic_bond(1.5 * sy * L, L, omega, V, c, sy, 2 * sy, 0.0, 0.0);
  EXPECT_FALSE(b.yielded);
  EXPECT_EQ(b.sbar, 2 * sy);
  // The critical stretch of equal work: s0 = (s_e^2 + s_Y^2)/(2 s_Y) above s_Y.
  EXPECT_DOUBLE_EQ(kernels::microplastic_critical_stretch(3 * sy, sy), 5 * sy);
  EXPECT_EQ(kernels::microplastic_critical_stretch(0.5 * sy, sy), 0.5 * sy);
}

// The ledger's arrays of one row and its opening of a bond, as HistoryLedger::Row::open_bond
// had them (history_ledger.hpp), copied so that the reference does not move with it.
struct LedgerArrays {
  std::vector<double> extension_trial, pending_amount;
  std::vector<uint8_t> booked_committed, booked_trial, pending_set;
  LedgerArrays(std::mt19937_64& g, std::size_t n) : extension_trial(n), pending_amount(n), booked_trial(n) {
    for (std::size_t k = 0; k < n; ++k) {
      booked_committed.push_back(g() % 3 == 0 ? 1 : 0);
      pending_set.push_back(g() % 5 == 0 ? 1 : 0);
      pending_amount[k] = pending_set[k] ? 1e-3 * static_cast<double>(g() % 100) : 0.0;
    }
  }
  bool open_bond(uint64_t k, uint8_t intact, double t_old, double length, double e, double volume,
                 double& booked_sum) {
    extension_trial[k] = e;
    const uint8_t was = booked_committed[k];
    booked_trial[k] = was;
    if (!was && intact != 1) {  // bond_booked_now
      if (!pending_set[k]) {
        pending_amount[k] = length > 0 ? 0.5 * t_old * e * volume : 0.0;  // broken_bond_booking
        pending_set[k] = 1;
      }
      booked_sum += pending_amount[k];
      booked_trial[k] = 1;
      return true;
    }
    if (pending_set[k]) pending_set[k] = 0;
    return false;
  }
};

// Microplastic::force_row_scalar as it was before the kernel (its loop; the ledger's
// opening below).
struct MicroOld {
  double W = 0, work = 0, booked = 0;
  bool inelastic = false;
};
MicroOld micro_old(const RandomRow& row, LedgerArrays& ledger, const double* r, double* q,
                   const double* sbar_old, double* sbar_trial, const double* old_force, const double* old_extension,
                   double* force_trial, double c_, double yield_) {
  const BondKind* kinds = row.kinds.data();
  const uint32_t* kind = row.kind.data();
  const uint8_t* intact = row.intact.data();
  double W = 0, work = 0, booked = 0;
  bool inelastic = false;
  for (uint64_t k = 0; k < row.kind.size(); ++k) {
    const BondKind& bk = kinds[kind[k]];
    const double vj = bk.volume * bk.fraction;
    const double e = r[k] - bk.length;
    inelastic = ledger.open_bond(k, intact[k], q[k], r[k], e, vj, booked) || inelastic;
    if (!intact[k]) {
      q[k] = 0;
      sbar_trial[k] = sbar_old[k];
      force_trial[k] = 0;
      if (old_force[k] != 0) {
        work += 0.5 * old_force[k] * (e - old_extension[k]) * vj;
        inelastic = true;
      }
      continue;
    }
    const double stretch = e / bk.length;
    const double sbar = kernels::microplastic_return(stretch, sbar_old[k], yield_);  // (moved unchanged)
    sbar_trial[k] = sbar;
    if (sbar != sbar_old[k]) inelastic = true;
    const double t = bk.weight * 0.5 * c_ * (stretch - sbar);
    W += 0.5 * t * (stretch - sbar) * bk.length * vj;
    force_trial[k] = t;
    work += 0.5 * (old_force[k] + t) * (e - old_extension[k]) * vj;
  }
  return {W, work, booked, inelastic};
}

TEST(MicropalsKernels, MicroplasticRowKeepsTheHostRowsBits) {
  std::mt19937_64 g(30);
  std::uniform_real_distribution<double> u(-1, 1);
  const double c = 3e19, sy = 5e-4;
  int rows = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const std::size_t n = 1 + g() % 60;
    const RandomRow row = random_row(g, n, 1 + g() % 5);
    std::vector<double> r(n), q(n), sbar_old(n), old_force(n), old_extension(n);
    for (std::size_t k = 0; k < n; ++k) {
      const double L = row.kinds[row.kind[k]].length;
      r[k] = L * (1 + 3 * sy * u(g));  // stretches within +-3 s_Y: elastic and yielding bonds
      q[k] = u(g) * 1e12;
      sbar_old[k] = g() % 2 ? 0.0 : 2 * sy * u(g);
      old_force[k] = g() % 4 ? u(g) * 1e16 : 0.0;
      old_extension[k] = (r[k] - L) * (1 + 0.1 * u(g));
    }
    LedgerArrays la(g, n), lb = la;
    std::vector<double> sbar_a(n), sbar_b(n), force_a(n), force_b(n), q_a = q, q_b = q;
    const MicroOld want = micro_old(row, la, r.data(), q_a.data(), sbar_old.data(), sbar_a.data(),
                                    old_force.data(), old_extension.data(), force_a.data(), c, sy);
    kernels::MicroplasticRow<BondKind> a;
    a.kinds = row.kinds.data(), a.kind = row.kind.data(), a.intact = row.intact.data(), a.r = r.data();
    a.sbar_old = sbar_old.data(), a.sbar_trial = sbar_b.data();
    a.old_force = old_force.data(), a.old_extension = old_extension.data(), a.force_trial = force_b.data();
    a.c = c, a.yield = sy;
    const kernels::MicroplasticSums got =
        kernels::microplastic_row(a, 0, n, [&](uint64_t k, double e, double vj, double& booked) {
          return lb.open_bond(k, row.intact[k], q_b[k], r[k], e, vj, booked);
        });
    ASSERT_TRUE(same_bits(want.W, got.W));
    ASSERT_TRUE(same_bits(want.work, got.work));
    ASSERT_TRUE(same_bits(want.booked, got.booked));
    ASSERT_EQ(want.inelastic, got.inelastic);
    for (std::size_t k = 0; k < n; ++k) {
      ASSERT_TRUE(same_bits(sbar_a[k], sbar_b[k]));
      ASSERT_TRUE(same_bits(force_a[k], force_b[k]));
      ASSERT_TRUE(same_bits(la.extension_trial[k], lb.extension_trial[k]));
      ASSERT_TRUE(same_bits(la.pending_amount[k], lb.pending_amount[k]));
      ASSERT_EQ(la.booked_trial[k], lb.booked_trial[k]);
    }
    rows += want.inelastic ? 1 : 0;
  }
  EXPECT_GT(rows, 1000);  // most rows yield or release a bond
}

// --- PALS ---

// The 6 x 6 solve and the multipliers' assembly as material/models/pals.cpp had them.
bool solve6_old(double a[6][6], double b[6], double x[6]) {
  double scale = 0;
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c) scale = std::max(scale, std::abs(a[r][c]));
  if (!(scale > 0)) return false;
  for (int c = 0; c < 6; ++c) {
    int p = c;
    for (int r = c + 1; r < 6; ++r)
      if (std::abs(a[r][c]) > std::abs(a[p][c])) p = r;
    if (!(std::abs(a[p][c]) > 1e-13 * scale)) return false;
    if (p != c) {
      for (int k = 0; k < 6; ++k) std::swap(a[p][k], a[c][k]);
      std::swap(b[p], b[c]);
    }
    for (int r = c + 1; r < 6; ++r) {
      const double f = a[r][c] / a[c][c];
      for (int k = c; k < 6; ++k) a[r][k] -= f * a[c][k];
      b[r] -= f * b[c];
    }
  }
  for (int r = 5; r >= 0; --r) {
    double s = b[r];
    for (int k = r + 1; k < 6; ++k) s -= a[r][k] * x[k];
    x[r] = s / a[r][r];
  }
  return true;
}
void quadratic_old(const Vec3& x, double q[6]) {
  q[0] = x.x * x.x, q[1] = x.y * x.y, q[2] = x.z * x.z;
  q[3] = x.x * x.y, q[4] = x.x * x.z, q[5] = x.y * x.z;
}
void modes_old(const Vec3& x, double g[6]) {
  const double r2 = dot(x, x);
  const double s[6] = {x.x * x.x - r2 / 3, x.y * x.y - r2 / 3, x.z * x.z - r2 / 3,
                       2 * x.x * x.y,      2 * x.x * x.z,      2 * x.y * x.z};
  for (int k = 0; k < 6; ++k) g[k] = s[k] * s[k] / r2;
}
constexpr double kModeNormOld[6] = {2.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0, 2.0, 2.0, 2.0};
bool dilatation_old(const std::vector<Vec3>& xi, const std::vector<double>& wv, double out[6]) {
  double a[6][6] = {}, b[6] = {1, 1, 1, 0, 0, 0};
  for (std::size_t j = 0; j < xi.size(); ++j) {
    double q[6];
    quadratic_old(xi[j], q);
    for (int r = 0; r < 6; ++r) {
      b[r] -= wv[j] * q[r];
      for (int c = 0; c < 6; ++c) a[r][c] += wv[j] * q[r] * q[c] * (c < 3 ? 1.0 : 2.0);
    }
  }
  return solve6_old(a, b, out);
}
bool deviatoric_old(const std::vector<Vec3>& xi, const std::vector<double>& wv, double out[6]) {
  double a[6][6] = {}, b[6];
  for (int k = 0; k < 6; ++k) b[k] = kModeNormOld[k];
  for (std::size_t j = 0; j < xi.size(); ++j) {
    double g[6];
    modes_old(xi[j], g);
    for (int r = 0; r < 6; ++r) {
      b[r] -= wv[j] * g[r];
      for (int c = 0; c < 6; ++c) a[r][c] += wv[j] * g[r] * g[c];
    }
  }
  return solve6_old(a, b, out);
}
double dilatation_factor_old(const double lambda[6], const Vec3& x) {
  double q[6];
  quadratic_old(x, q);
  return 1 + lambda[0] * q[0] + lambda[1] * q[1] + lambda[2] * q[2] +
         2 * (lambda[3] * q[3] + lambda[4] * q[4] + lambda[5] * q[5]);
}
double deviatoric_factor_old(const double mu[6], const Vec3& x) {
  double g[6];
  modes_old(x, g);
  double s = 1;
  for (int k = 0; k < 6; ++k) s += mu[k] * g[k];
  return s;
}

TEST(MicropalsKernels, PalsSolveSixIsExactOnATriangularSystemAndRefusesASingularOne) {
  // An upper triangular system with powers of two: the elimination and the back
  // substitution are exact. x = (1, 2, 3, 4, 5, 6).
  double a[6][6] = {}, b[6], x[6];
  const double want[6] = {1, 2, 3, 4, 5, 6};
  for (int r = 0; r < 6; ++r) {
    b[r] = 0;
    for (int c = r; c < 6; ++c) a[r][c] = c == r ? 4.0 : 0.5, b[r] += a[r][c] * want[c];
  }
  ASSERT_TRUE(kernels::pals_solve6(a, b, x));
  for (int r = 0; r < 6; ++r) EXPECT_EQ(x[r], want[r]);
  // Row 5 twice row 4: singular.
  double s[6][6] = {}, t[6] = {1, 1, 1, 1, 1, 1};
  for (int r = 0; r < 5; ++r) s[r][r] = 1 + r;
  for (int c = 0; c < 6; ++c) s[5][c] = 2 * s[4][c];
  EXPECT_FALSE(kernels::pals_solve6(s, t, x));
  double z[6][6] = {}, w[6] = {};
  EXPECT_FALSE(kernels::pals_solve6(z, w, x));
}

TEST(MicropalsKernels, PalsMultipliersAndInfluenceKeepTheHostBits) {
  std::mt19937_64 g(31);
  std::uniform_real_distribution<double> u(-1, 1);
  int solved = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    // A random family: the bonds of a lattice cube of 2..3 spacings around a point,
    // randomly perturbed (so no symmetry makes entries vanish), or a few random bonds.
    std::vector<Vec3> xi;
    std::vector<double> wv;
    const double h = 1e-3 * (0.5 + 0.5 * (u(g) + 1));
    const int reach = trial % 7 == 0 ? 1 : 2 + static_cast<int>(g() % 2);
    for (int a = -reach; a <= reach; ++a)
      for (int b = -reach; b <= reach; ++b)
        for (int c = -reach; c <= reach; ++c) {
          if ((a == 0 && b == 0 && c == 0) || g() % 4 == 0) continue;
          xi.push_back({h * (a + 0.1 * u(g)), h * (b + 0.1 * u(g)), h * (c + 0.1 * u(g))});
          wv.push_back(h * h * h * (0.5 + 0.5 * (u(g) + 1)));
        }
    double la[6] = {}, lb[6] = {}, ma[6] = {}, mb[6] = {};
    const bool da = dilatation_old(xi, wv, la), db = kernels::pals_dilatation_multipliers(xi.data(), wv.data(), xi.size(), lb);
    const bool va = deviatoric_old(xi, wv, ma), vb = kernels::pals_deviatoric_multipliers(xi.data(), wv.data(), xi.size(), mb);
    ASSERT_EQ(da, db);
    ASSERT_EQ(va, vb);
    for (int k = 0; k < 6; ++k) {
      ASSERT_TRUE(same_bits(la[k], lb[k])) << trial << " " << k;
      ASSERT_TRUE(same_bits(ma[k], mb[k])) << trial << " " << k;
    }
    for (const Vec3& x : xi) {
      ASSERT_TRUE(same_bits(dilatation_factor_old(la, x), kernels::pals_dilatation_factor(lb, x.x, x.y, x.z)));
      ASSERT_TRUE(same_bits(deviatoric_factor_old(ma, x), kernels::pals_deviatoric_factor(mb, x.x, x.y, x.z)));
    }
    solved += da && va ? 1 : 0;
  }
  EXPECT_GT(solved, 2500);
}

// Pals::force_row as it was before the kernel.
std::pair<double, double> pals_row_old(const RandomRow& B, const double* r, const double* sigma_, const double* tau_,
                                       double kappa_, double mu_, double* q) {
  const uint64_t first = 0, last = B.kind.size();
  double theta = 0;
  for (uint64_t k = first; k < last; ++k) {
    const BondKind& b = B.kinds[B.kind[k]];
    const double e = r[k] - b.length;
    if (B.intact[k]) theta += sigma_[k] * b.length * e * b.volume * b.fraction;
  }
  double S = 0, dev = 0;
  for (uint64_t k = first; k < last; ++k) {
    if (!B.intact[k]) continue;
    const BondKind& b = B.kinds[B.kind[k]];
    const double ed = (r[k] - b.length) - theta * b.length / 3;
    const double v = b.volume * b.fraction;
    S += tau_[k] * ed * b.length * v;
    dev += tau_[k] * ed * ed * v;
  }
  for (uint64_t k = first; k < last; ++k) {
    if (!B.intact[k]) {
      q[k] = 0;
      continue;
    }
    const BondKind& b = B.kinds[B.kind[k]];
    const double ed = (r[k] - b.length) - theta * b.length / 3;
    const double t = kappa_ * theta * sigma_[k] * b.length + 2 * mu_ * tau_[k] * ed -
                     (2 * mu_ / 3) * S * sigma_[k] * b.length;
    q[k] = r[k] > 0 ? t / r[k] : 0.0;
  }
  return {theta, 0.5 * kappa_ * theta * theta + mu_ * dev};
}

TEST(MicropalsKernels, PalsRowKeepsTheHostRowsBits) {
  std::mt19937_64 g(32);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 3000; ++trial) {
    const std::size_t n = 1 + g() % 80;
    const RandomRow row = random_row(g, n, 1 + g() % 6);
    std::vector<double> r(n), sigma(n), tau(n), qa(n, 7.0), qb(n, 7.0);
    for (std::size_t k = 0; k < n; ++k) {
      r[k] = row.kinds[row.kind[k]].length * (1 + 0.01 * u(g));
      if (g() % 50 == 0) r[k] = 0;  // a bond of zero deformed length: q = 0
      sigma[k] = 1 + 0.3 * u(g);
      tau[k] = 1 + 0.3 * u(g);
    }
    const double kappa = 1.6e11 * (1 + 0.1 * u(g)), mu = 8e10 * (1 + 0.1 * u(g));
    const auto want = pals_row_old(row, r.data(), sigma.data(), tau.data(), kappa, mu, qa.data());
    kernels::PalsRow<BondKind> a;
    a.kinds = row.kinds.data(), a.kind = row.kind.data(), a.intact = row.intact.data(), a.r = r.data();
    a.sigma = sigma.data(), a.tau = tau.data(), a.q = qb.data(), a.kappa = kappa, a.mu = mu;
    const kernels::PalsSums got = kernels::pals_row(a, 0, n);
    ASSERT_TRUE(same_bits(want.first, got.theta));
    ASSERT_TRUE(same_bits(want.second, got.W));
    for (std::size_t k = 0; k < n; ++k) ASSERT_TRUE(same_bits(qa[k], qb[k])) << k;
  }
}

TEST(MicropalsKernels, PalsRowOfAUniformStretchHasTheDilatationAndNoDeviatoricEnergy) {
  // sigma = tau = 1 on six bonds with sum |xi|^2 V_j = 3 (PALS's normalisation, sum sigma
  // xi_a xi_b V = delta_ab, traced): a uniform stretch s gives theta = 3 s and e^d = 0.
  const double s = 1e-4, L = 1e-3;
  std::vector<BondKind> kinds(1);
  kinds[0].length = L, kinds[0].volume = 1.0 / (2 * L * L), kinds[0].fraction = 1;
  std::vector<uint32_t> kind(6, 0);
  std::vector<uint8_t> intact(6, 1);
  std::vector<double> r(6, L * (1 + s)), one(6, 1.0), q(6);
  kernels::PalsRow<BondKind> a;
  a.kinds = kinds.data(), a.kind = kind.data(), a.intact = intact.data(), a.r = r.data();
  a.sigma = one.data(), a.tau = one.data(), a.q = q.data(), a.kappa = 2.0, a.mu = 1.0;
  const kernels::PalsSums got = kernels::pals_row(a, 0, 6);
  EXPECT_NEAR(got.theta / (3 * s), 1.0, 1e-12);
  EXPECT_NEAR(got.W / (0.5 * 2.0 * 9 * s * s), 1.0, 1e-9);  // kappa theta^2/2, no deviatoric part
  for (double x : q) EXPECT_NEAR(x * r[0] / (2.0 * 3 * s * L), 1.0, 1e-9);  // t = kappa theta |xi|
}

// --- the linearised LPS ---

// LinearLps::force_state's row as it was before the kernel.
std::pair<double, double> linear_lps_old(const RandomRow& B, const std::vector<uint32_t>& nbr, const Point4* y,
                                         const std::vector<Vec3>& X, Vec3* T, uint32_t i, double m, int dim_,
                                         double bulk_, double alpha_m_) {
  const double d = dim_;
  const uint64_t first = 0, last = B.kind.size();
  auto extension = [&](uint64_t k, const Vec3& xi, double length) {
    const Point4 pi = y[i], pj = y[nbr[k]];
    const Vec3 Y{pj.x - pi.x, pj.y - pi.y, pj.z - pi.z};
    return dot(Y - xi, xi) / length;
  };
  double sum = 0;
  for (uint64_t k = first; k < last; ++k) {
    if (!B.intact[k]) continue;
    const BondKind& b = B.kinds[B.kind[k]];
    sum += b.weight * b.volume * b.fraction * b.length * extension(k, X[nbr[k]] - X[i], b.length);
  }
  const double theta = m > 0 ? d * sum / m : 0.0;
  const double alpha = m > 0 ? alpha_m_ / m : 0.0;
  const double p = m > 0 ? d * bulk_ * theta / m : 0.0;
  double dev = 0;
  for (uint64_t k = first; k < last; ++k) {
    if (!B.intact[k]) {
      T[k] = {};
      continue;
    }
    const BondKind& b = B.kinds[B.kind[k]];
    const Vec3 xi = X[nbr[k]] - X[i];
    const double ed = extension(k, xi, b.length) - theta * b.length / d;
    dev += b.weight * b.volume * b.fraction * ed * ed;
    const double t = p * b.weight * b.length + alpha * b.weight * ed;
    T[k] = (t / b.length) * xi;
  }
  return {theta, 0.5 * bulk_ * theta * theta + 0.5 * alpha * dev};
}

TEST(MicropalsKernels, LinearLpsRowKeepsTheHostRowsBits) {
  std::mt19937_64 g(33);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 3000; ++trial) {
    const std::size_t n = 1 + g() % 60, particles = n + 1;
    RandomRow row = random_row(g, n, 1 + g() % 4);
    std::vector<Vec3> X(particles);
    std::vector<Point4> y(particles);
    std::vector<uint32_t> nbr(n);
    for (std::size_t p = 0; p < particles; ++p) {
      X[p] = {1e-3 * u(g), 1e-3 * u(g), 1e-3 * u(g)};
      y[p].x = X[p].x + 1e-5 * u(g), y[p].y = X[p].y + 1e-5 * u(g), y[p].z = X[p].z + 1e-5 * u(g);
    }
    const uint32_t i = 0;
    for (std::size_t k = 0; k < n; ++k) nbr[k] = static_cast<uint32_t>(1 + k);
    // One kind per bond, so that |xi| is the bond's.
    std::vector<BondKind> kinds(n);
    for (std::size_t k = 0; k < n; ++k) {
      kinds[k] = row.kinds[row.kind[k]];
      const Vec3 xi = X[nbr[k]] - X[i];
      kinds[k].length = std::sqrt(dot(xi, xi));
      row.kind[k] = static_cast<uint32_t>(k);
    }
    row.kinds = kinds;
    const int dim = g() % 2 ? 3 : 2;
    const double m = g() % 20 == 0 ? 0.0 : 1e-12 * (1 + u(g) * 0.5), bulk = 1.6e11, alpha_m = 15 * 8e10;
    std::vector<Vec3> Ta(n), Tb(n, Vec3{1, 1, 1});
    const auto want = linear_lps_old(row, nbr, y.data(), X, Ta.data(), i, m, dim, bulk, alpha_m);
    kernels::LinearLpsRow<BondKind, Point4, Vec3> a;
    a.kinds = row.kinds.data(), a.kind = row.kind.data(), a.nbr = nbr.data(), a.intact = row.intact.data();
    a.y = y.data(), a.X = X.data(), a.T = Tb.data(), a.bulk = bulk, a.alpha_m = alpha_m, a.dim = dim;
    const kernels::LinearLpsSums got = kernels::linear_lps_row(a, i, 0, n, m);
    ASSERT_TRUE(same_bits(want.first, got.theta));
    ASSERT_TRUE(same_bits(want.second, got.W));
    for (std::size_t k = 0; k < n; ++k) {
      ASSERT_TRUE(same_bits(Ta[k].x, Tb[k].x));
      ASSERT_TRUE(same_bits(Ta[k].y, Tb[k].y));
      ASSERT_TRUE(same_bits(Ta[k].z, Tb[k].z));
    }
  }
}

TEST(MicropalsKernels, LinearExtensionIsTheProjectedDisplacement) {
  // eta = Y - xi = (1, 2, 3) 1e-6 on xi = (1, 0, 0) 1e-3: eta . xi/|xi| = 1e-6.
  EXPECT_NEAR(kernels::linear_extension(1e-3 + 1e-6, 2e-6, 3e-6, 1e-3, 0, 0, 1e-3) / 1e-6, 1.0, 1e-9);
  // A displacement normal to the bond (a rigid rotation's, to first order): no extension.
  EXPECT_EQ(kernels::linear_extension(0, 1e-3, 1e-6, 0, 1e-3, 0, 1e-3), 0.0);
  // t = p omega |xi| + alpha omega e^d; W = k theta^2/2 + alpha/2 ||e^d||^2.
  EXPECT_DOUBLE_EQ(kernels::linear_lps_force_scalar(2.0, 0.5, 3.0, 4.0, 5.0), 13.0);
  EXPECT_DOUBLE_EQ(kernels::linear_lps_energy(2.0, 3.0, 4.0, 5.0), 19.0);
}

// --- bond pairs ---

// BondPair::force_pass's per-pair and per-bond expressions (and bond_pair.hpp's helpers)
// as they were before the kernels, over Vec3.
struct OldElastic {
  Vec3 Fj, Fjp;
  double f;
};
OldElastic old_elastic_pair(const Vec3& Y, const Vec3& Yp, double coef, double c0, double s0) {
  const double ia2 = 1 / dot(Y, Y), ib2 = 1 / dot(Yp, Yp), d = dot(Y, Yp);
  const double r = std::sqrt(ia2 * ib2);
  const Vec3 dY = (Yp - Y * (d * ia2)) * r, dYp = (Y - Yp * (d * ib2)) * r;
  const double c = (1 + d * r) - 1;
  double energy, dc;
  if (s0 == 0) {
    energy = 1 + c, dc = -c0;
  } else {
    const double s = std::max(std::sqrt(std::max(0.0, 1 - c * c)), 1e-9);
    energy = 1 - c * c0 - s * s0, dc = -c0 + s0 * c / s;
  }
  return {dY * (-coef * dc), dYp * (-coef * dc), energy};
}
struct OldShell {
  double n, t;  // the trial offset
  Vec3 G;
  double energy;
};
OldShell old_shell_pair(const Vec3& yj, const Vec3& yjp, const Vec3& yk, const Vec3& Xj, const Vec3& Xjp,
                        const Vec3& Xk, double inv_length, double pn, double pt, double theta_yield, double coef,
                        double& kink_n, double& kink_t) {
  const Vec3 dv = (yj - Xj + (yjp - Xjp) - (yk - Xk) * 2.0) * inv_length;
  const Vec3 e0 = (Xj - Xk) * inv_length;
  const double dn = dv.z, dt = e0.x * dv.y - e0.y * dv.x;
  kink_n = dn, kink_t = dt;
  double tn = pn, tt = pt;
  {
    const double en = dn - pn, et = dt - pt, r = std::hypot(en, et);
    if (r > theta_yield) {
      const double f = (r - theta_yield) / r;
      tn = pn + f * en, tt = pt + f * et;
    }
  }
  const double en = dn - tn, et = dt - tt, r = std::hypot(en, et);
  const double g = coef * (r > 0 ? std::sin(r) / r : 1.0) * inv_length;
  return {tn, tt, Vec3{-e0.y * et * g, e0.x * et * g, en * g}, coef * (1 - std::cos(r))};
}

kernels::BpVec bpv(const Vec3& v) { return {v.x, v.y, v.z}; }
bool same_vec(const Vec3& a, const kernels::BpVec& b) {
  return same_bits(a.x, b.x) && same_bits(a.y, b.y) && same_bits(a.z, b.z);
}

TEST(MicropalsKernels, BondPairKernelsKeepTheForcePasssBits) {
  std::mt19937_64 g(34);
  std::uniform_real_distribution<double> u(-1, 1);
  auto near = [&](const Vec3& x, double h) { return Vec3{x.x + h * u(g), x.y + h * u(g), x.z + h * u(g)}; };
  for (int trial = 0; trial < 20000; ++trial) {
    const double h = 1e-2 * (1 + u(g) * 0.5), inv = 1 / h, coef = 1e3 * (1 + u(g) * 0.5);
    const Vec3 Xk{u(g), u(g), 0}, Xj = Xk + Vec3{h, 0.3 * h * u(g), 0}, Xjp = Xk - (Xj - Xk);
    const double amp = trial % 3 == 0 ? 1e-3 * h : 0.05 * h;
    const Vec3 yk = near(Xk, amp), yj = near(Xj, amp), yjp = near(Xjp, amp);
    const Vec3 Y = yj - yk, Yp = yjp - yk;
    // Elastic pairs, straight and with a reference angle.
    const double theta0 = trial % 2 ? 0.0 : 0.3 * u(g);
    const double c0 = trial % 2 ? -1.0 : -std::cos(theta0), s0 = trial % 2 ? 0.0 : std::sin(theta0);
    const OldElastic want = old_elastic_pair(Y, Yp, coef, c0, s0);
    const kernels::BpElasticPair got = kernels::bp_elastic_pair(bpv(Y), bpv(Yp), coef, c0, s0);
    ASSERT_TRUE(same_vec(want.Fj, got.Fj) && same_vec(want.Fjp, got.Fjp) && same_bits(want.f, got.f)) << trial;
    // Shell pairs with a plastic offset, yielding or not.
    const double pn = 1e-3 * u(g), pt = 1e-3 * u(g), ty = trial % 4 ? 1e-3 : 1.0;
    double kn, kt;
    const OldShell ws = old_shell_pair(yj, yjp, yk, Xj, Xjp, Xk, inv, pn, pt, ty, coef, kn, kt);
    const kernels::BpKink d = kernels::bp_shell_kink(bpv(yj), bpv(yjp), bpv(yk), bpv(Xj), bpv(Xjp), bpv(Xk), inv);
    ASSERT_TRUE(same_bits(kn, d.n) && same_bits(kt, d.t));
    const kernels::BpShellPair gs = kernels::bp_shell_pair(d, {pn, pt}, ty, coef, inv, bpv(Xj), bpv(Xk));
    ASSERT_TRUE(same_bits(ws.n, gs.offset.n) && same_bits(ws.t, gs.offset.t));
    ASSERT_TRUE(same_vec(ws.G, gs.G) && same_bits(ws.energy, gs.energy)) << trial;
    // Signed (transverse) pairs.
    const double sk_want = (yj.z + yjp.z - 2 * yk.z) / (1 / inv) - (Xj.z + Xjp.z - 2 * Xk.z) * inv;
    const double sk = kernels::bp_transverse_kink(yj.z, yjp.z, yk.z, Xj.z, Xjp.z, Xk.z, inv);
    ASSERT_TRUE(same_bits(sk_want, sk));
    const double tp_old = 1e-3 * u(g);
    double tp = tp_old;
    if (std::abs(sk - tp_old) > ty) tp = tp_old + (sk - tp_old > 0 ? sk - tp_old - ty : sk - tp_old + ty);
    const kernels::BpSignedPair sp = kernels::bp_signed_pair(sk, tp_old, ty, coef, inv);
    ASSERT_TRUE(same_bits(tp, sp.offset));
    ASSERT_TRUE(same_bits(coef * std::sin(sk - tp) * inv, sp.g));
    ASSERT_TRUE(same_bits(coef * (1 - std::cos(sk - tp)), sp.energy));
    // The isotropic-curvature term and the extension spring with the dilatation term.
    const double Vj = h * h * (1 + 0.1 * u(g)), Vk = h * h, m0 = 0.7 + 0.1 * u(g);
    ASSERT_TRUE(same_vec((Y + Yp) * (2 * inv * Vj * m0), kernels::bp_curvature_term(bpv(Y), bpv(Yp), inv, Vj, m0)));
    const double length = std::sqrt(dot(Xj - Xk, Xj - Xk)), dil = 0.3 + 0.1 * u(g), dil_coef = trial % 2 ? 0.0 : 5.0;
    const double th_k = 1e-3 * u(g), th_j = 1e-3 * u(g);
    const double L = norm(Y), e = L - length;
    double t = 2 * coef * e;
    if (dil_coef != 0) t += dil_coef * (th_k * Vk * dil * Vj + th_j * Vj * dil * Vk);
    ASSERT_TRUE(same_bits(e, kernels::bp_bond_extension(bpv(Y), length)));
    ASSERT_TRUE(same_bits(L, kernels::bp_bond_length(bpv(Y))));
    ASSERT_TRUE(same_vec(Y * (t / L), kernels::bp_spring_force(bpv(Y), kernels::bp_bond_length(bpv(Y)), e, coef,
                                                               dil_coef, dil, th_k, th_j, Vk, Vj)));
    ASSERT_TRUE(same_bits(0.5 * coef * e * e, kernels::bp_spring_energy(coef, e)));
    // A node's force density: F / V, z only (transverse) or the energy weight in plane.
    const Vec3 F = Y * (1e6 * u(g));
    const double Vn = 1e-6 * (1 + 0.5 * u(g)), w = trial % 3 == 0 ? 0.5 : 1.0;
    const bool transverse = trial % 2 == 0;
    Vec3 f = F / Vn;
    if (transverse) f = Vec3{0, 0, 1} * f.z;
    else if (w != 1) f = Vec3{f.x * w, f.y * w, f.z};
    ASSERT_TRUE(same_vec(f, kernels::bp_node_force(bpv(F), Vn, transverse, w)));
    const double en = 1e3 * u(g);
    double booked = en;
    booked *= w / Vn;
    ASSERT_TRUE(same_bits(booked, kernels::bp_node_energy(en, w, Vn)));
  }
}

TEST(MicropalsKernels, BondPairStraightPairHasNoForceAndItsKinkCostsTheSpringEnergy) {
  // A straight pair at rest: f = 1 + cos(pi) = 0, no force.
  const kernels::BpElasticPair rest = kernels::bp_elastic_pair({1e-2, 0, 0}, {-1e-2, 0, 0}, 5.0, -1, 0);
  EXPECT_EQ(rest.f, 0.0);
  EXPECT_EQ(rest.Fj.x, 0.0);
  EXPECT_EQ(rest.Fj.z, 0.0);
  // Kinked by a small angle a: f = 1 - cos(a) ~ a^2/2; the force on j is normal to Y.
  const double a = 1e-3;
  const kernels::BpElasticPair k =
      kernels::bp_elastic_pair({1e-2, 0, 0}, {-1e-2 * std::cos(a), 0, 1e-2 * std::sin(a)}, 5.0, -1, 0);
  EXPECT_NEAR(k.f / (a * a / 2), 1.0, 1e-6);
  EXPECT_NEAR(k.Fj.x, 0.0, 1e-15);
  // A signed pair below yield is elastic (offset kept), above it the force is capped.
  EXPECT_EQ(kernels::bp_signed_pair(1e-4, 0, 1e-3, 2.0, 10.0).offset, 0.0);
  EXPECT_NEAR(kernels::bp_signed_pair(5e-3, 0, 1e-3, 2.0, 10.0).g / (2.0 * std::sin(1e-3) * 10.0), 1.0, 1e-12);
}

}  // namespace
}  // namespace horizon
