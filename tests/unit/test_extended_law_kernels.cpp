// Extended correspondence's law row as portable kernels (kernels/extended_law.hpp, issue 30)
// against the Eigen host forms they replaced in material/models/extended_correspondence.*
// (written out here as they were: MomentMap's outer products, FullPivLU, its inverse, solve
// and dual; Fbar = N K^-1, P K^-1, the von Mises stress; the volumetric gradient's bond
// terms), bit for bit on random bond families: full 3-D and 2-D families, thinned ones
// (few bonds: near-singular maps), degenerate ones (every bond on one line: singular).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstring>
#include <random>

#include "horizon/kernels/extended_law.hpp"
#include "horizon/kernels/hencky.hpp"
#include "horizon/kernels/strain_laws.hpp"
#include "horizon/material/models/extended_correspondence.hpp"
#include "horizon/material/nonlocal_gradient.hpp"
#include "kernel_bits.hpp"

namespace horizon {
namespace {

using test::Mat3;
using test::same_bits;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Vec3d = Eigen::Vector3d;

// The host's Eigen forms before the kernels (extended_correspondence.hpp's MomentMap).
Vec6 eigen_shape_state(const Vec3d& xi, int dimension) {
  const double L2 = xi.x() * xi.x() + xi.y() * xi.y() + xi.z() * xi.z();
  const double a = dimension == 3 ? 2.5 : 2.0;
  Vec6 h;
  h << a * xi.x() * xi.x() / L2 - 0.5, a * xi.y() * xi.y() / L2 - 0.5,
      dimension == 3 ? a * xi.z() * xi.z() / L2 - 0.5 : 0.0, a * xi.y() * xi.z() / L2, a * xi.x() * xi.z() / L2,
      a * xi.x() * xi.y() / L2;
  return h;
}
Vec6 eigen_normal_projector(const Vec3d& xi) {
  const double L2 = xi.x() * xi.x() + xi.y() * xi.y() + xi.z() * xi.z();
  Vec6 p;
  p << xi.x() * xi.x() / L2, xi.y() * xi.y() / L2, xi.z() * xi.z() / L2, 2 * xi.y() * xi.z() / L2,
      2 * xi.x() * xi.z() / L2, 2 * xi.x() * xi.y() / L2;
  return p;
}
Vec6 to_vec6(const Mat3& A) { return (Vec6() << A(0, 0), A(1, 1), A(2, 2), A(1, 2), A(0, 2), A(0, 1)).finished(); }

int differing(const double* a, const double* b, int n) {
  int d = 0;
  for (int k = 0; k < n; ++k) d += same_bits(a[k], b[k]) ? 0 : 1;
  return d;
}

// A random family of bonds: kind 0 a full lattice-like family, 1 a thinned one (few bonds),
// 2 every bond along one line (singular map), 3 two lines (singular in 3-D).
std::vector<Vec3d> random_family(std::mt19937_64& g, int kind, int dimension) {
  std::uniform_real_distribution<double> u(-1, 1);
  const int n = kind == 0 ? 20 + static_cast<int>(40 * std::abs(u(g))) : 4 + static_cast<int>(6 * std::abs(u(g)));
  std::vector<Vec3d> xi;
  const Vec3d d1(u(g), u(g), dimension == 3 ? u(g) : 0.0), d2(u(g), u(g), dimension == 3 ? u(g) : 0.0);
  for (int b = 0; b < n; ++b) {
    Vec3d x(u(g), u(g), dimension == 3 ? u(g) : 0.0);
    if (kind == 2) x = u(g) * d1;
    if (kind == 3) x = (b % 2 ? d1 : d2) * u(g);
    if (x.norm() < 1e-3) x = Vec3d(0.5, 0.25, dimension == 3 ? 0.125 : 0.0);
    xi.push_back(1e-3 * x);
  }
  return xi;
}

TEST(ExtendedLawKernels, MomentMapInverseSolveAndDualKeepEigensBits) {
  std::mt19937_64 g(23);
  std::uniform_real_distribution<double> u(-1, 1);
  int bad = 0, singular = 0, regular = 0;
  for (int t = 0; t < 6000; ++t) {
    const int dim = t % 3 == 0 ? 2 : 3, kind = t % 11 == 0 ? 2 : (t % 13 == 0 ? 3 : (t % 4 == 1 ? 1 : 0));
    const std::vector<Vec3d> fam = random_family(g, kind, dim);
    Mat6 M = Mat6::Zero();
    if (dim == 2) M(2, 2) = M(3, 3) = M(4, 4) = 1.0;
    double Mk[36];
    kernels::moment_map_reset(Mk, dim);
    for (const Vec3d& xi : fam) {
      const double w = (t % 5 == 0 ? 1.0 : 1e-9) * (0.5 + std::abs(u(g)));
      M.noalias() += w * eigen_shape_state(xi, dim) * eigen_normal_projector(xi).transpose();
      const double x[3] = {xi.x(), xi.y(), xi.z()};
      kernels::moment_map_add(Mk, x, w, dim);
    }
    bad += differing(M.data(), Mk, 36);
    // MomentMap::finish
    Mat6 inverse = Mat6::Zero();
    const Eigen::FullPivLU<Mat6> lu(M);
    bool ok = lu.isInvertible();
    if (ok) {
      inverse = lu.inverse();
      ok = inverse.allFinite();
    }
    double inv[36] = {};
    const bool kok = kernels::moment_map_inverse(Mk, inv);
    ASSERT_EQ(ok, kok) << t;
    bad += differing(inverse.data(), inv, 36);
    (ok ? regular : singular) += 1;
    // solve, dual and dual_weighted
    Vec6 S;
    for (int k = 0; k < 6; ++k) S[k] = u(g) * (k % 3 ? 1e-3 : 1.0);
    const Vec6 E = inverse * S;
    double e[6];
    kernels::moment_solve(inv, S.data(), e);
    bad += differing(E.data(), e, 6);
    Mat3 T;
    for (int k = 0; k < 9; ++k) T(k / 3, k % 3) = 1e8 * u(g);
    const Vec6 a = inverse.transpose() * (Vec6() << 1, 1, 1, 2, 2, 2).finished().cwiseProduct(to_vec6(T));
    double Tr[9], ak[6];
    test::to_rows(T, Tr);
    kernels::moment_dual(inv, Tr, ak);
    bad += differing(a.data(), ak, 6);
    const Vec6 b = inverse.transpose() * S;
    kernels::moment_dual_weighted(inv, S.data(), ak);
    bad += differing(b.data(), ak, 6);
  }
  EXPECT_EQ(bad, 0);
  EXPECT_GT(singular, 500);  // the refusals ran
  EXPECT_GT(regular, 3000);
}

// rebuild_map's row as it was: MomentMap (Eigen) and NonlocalGradient over the acting bonds,
// the acting-weight guard, K's guard, M's FullPivLU, against moment_map_row.
TEST(ExtendedLawKernels, MomentMapRowKeepsTheHostsBits) {
  std::mt19937_64 g(37);
  std::uniform_real_distribution<double> u(-1, 1);
  int bad = 0, outcomes[2] = {0, 0};
  for (int t = 0; t < 4000; ++t) {
    const int dim = t % 3 == 0 ? 2 : 3, kind = t % 11 == 0 ? 2 : (t % 4 == 1 ? 1 : 0);
    const std::vector<Vec3d> fam = random_family(g, kind, dim);
    std::vector<double> w(fam.size());
    std::vector<uint8_t> acts(fam.size());
    for (std::size_t b = 0; b < fam.size(); ++b) w[b] = 1e-9 * (0.5 + std::abs(u(g))), acts[b] = u(g) > -0.6;
    const double min_weight = t % 5 == 0 ? 1e-9 * 8 : 0.0, tolerance = 1e-4;
    Mat6 M = Mat6::Zero();
    if (dim == 2) M(2, 2) = M(3, 3) = M(4, 4) = 1.0;
    NonlocalGradient K;
    double acting = 0;
    for (std::size_t b = 0; b < fam.size(); ++b) {
      if (!acts[b]) continue;
      M.noalias() += w[b] * eigen_shape_state(fam[b], dim) * eigen_normal_projector(fam[b]).transpose();
      const Vec3 x{fam[b].x(), fam[b].y(), fam[b].z()};
      K.add(x, x, w[b]);
      acting += w[b];
    }
    Mat3 Kinv = Mat3::Zero(), F;
    Mat6 inverse = Mat6::Zero();
    bool ok = acting >= min_weight && K.finish(dim, tolerance, Kinv, F);
    if (ok) {
      const Eigen::FullPivLU<Mat6> lu(M);
      ok = lu.isInvertible();
      if (ok) {
        inverse = lu.inverse();
        ok = inverse.allFinite();
      }
    }
    auto bond = [&](uint64_t k, double* xi, double& wk) {
      if (!acts[k]) return false;
      xi[0] = fam[k].x(), xi[1] = fam[k].y(), xi[2] = fam[k].z();
      wk = w[k];
      return true;
    };
    double Mk[36], inv[36], Ki[9], aw = -1;
    const bool kok = kernels::moment_map_row(0, fam.size(), bond, dim, tolerance, min_weight, Mk, inv, Ki, aw);
    ASSERT_EQ(ok, kok) << t;
    outcomes[ok ? 1 : 0] += 1;
    bad += differing(M.data(), Mk, 36) + differing(inverse.data(), inv, 36) + differing(&acting, &aw, 1);
    if (acting >= min_weight) bad += differing(Kinv.data(), Ki, 9);
  }
  EXPECT_EQ(bad, 0);
  EXPECT_GT(outcomes[0], 300);
  EXPECT_GT(outcomes[1], 2000);
}

// pair_law_row's stabilisation loop and record as they were (Eigen 6-vectors), against
// pair_stabilisation_row and pair_record.
TEST(ExtendedLawKernels, PairStabilisationAndRecordKeepTheHostsBits) {
  std::mt19937_64 g(41);
  std::uniform_real_distribution<double> u(-1, 1);
  int bad = 0;
  for (int t = 0; t < 4000; ++t) {
    const int n = 10 + t % 30;
    Vec6 Ei, a;
    for (int q = 0; q < 6; ++q) Ei[q] = 0.01 * u(g), a[q] = 1e9 * u(g);
    Mat6 inv;
    for (int k = 0; k < 36; ++k) inv.data()[k] = (k % 7 == 0 ? 1.0 : 0.0) + 0.1 * u(g);
    const double ks = t % 9 == 0 ? 0.0 : 1e10 * (0.5 + std::abs(u(g)));
    std::vector<kernels::StabilisationBond> bonds(n);
    std::vector<Vec6> Ej(n);
    std::vector<uint8_t> acts(n);
    for (int k = 0; k < n; ++k) {
      const Vec3d x(u(g), u(g), u(g));
      const Vec3d nv = x / x.norm();
      kernels::StabilisationBond& b = bonds[k];
      b.n[0] = nv.x(), b.n[1] = nv.y(), b.n[2] = nv.z();
      b.eps = 0.01 * u(g), b.w = 1e-9 * std::abs(u(g));
      for (int q = 0; q < 6; ++q) Ej[k][q] = 0.01 * u(g);
      b.mid = t % 2 == 0 && u(g) > -0.5;
      b.Ej = b.mid ? Ej[k].data() : nullptr;
      b.ksj = b.mid ? 1e10 * std::abs(u(g)) : 0.0;
      acts[k] = u(g) > -0.7;
    }
    // The host's loop.
    std::vector<double> r_host(n, 0.0), r_k(n, 0.0);
    Vec6 Rp = Vec6::Zero();
    double Ws = 0;
    Vec6 A = a;
    if (ks != 0) {
      const double inv_ks = 1.0 / ks;
      for (int k = 0; k < n; ++k) {
        if (!acts[k]) continue;
        const kernels::StabilisationBond& b = bonds[k];
        const Vec6 p = extended::unit_normal_projector(Vec3{b.n[0], b.n[1], b.n[2]});
        double r, coef = ks;
        if (b.mid) {
          r = b.eps - p.dot(0.5 * (Ei + Ej[k]));
          coef = 0.5 * (ks + b.ksj);
        } else {
          r = b.eps - p.dot(Ei);
        }
        r_host[k] = r;
        const double wr = b.w * r;
        Rp.noalias() += (wr * (coef * inv_ks)) * p;
        Ws += coef * wr * r;
      }
      A -= (2.0 * ks) * (inv.transpose() * Rp);
    }
    auto bond = [&](uint64_t k, kernels::StabilisationBond& b) {
      b = bonds[k];
      return acts[k] != 0;
    };
    double Rk[6] = {0, 0, 0, 0, 0, 0}, Wk = 0, Ak[6];
    if (ks != 0) kernels::pair_stabilisation_row(0, n, bond, Ei.data(), ks, r_k.data(), Rk, Wk);
    kernels::pair_record(a.data(), ks, inv.data(), Rk, Ak);
    bad += differing(Rp.data(), Rk, 6) + differing(&Ws, &Wk, 1) + differing(A.data(), Ak, 6);
    bad += differing(r_host.data(), r_k.data(), n);
  }
  EXPECT_EQ(bad, 0);
}

// The vector form's stabilisation() loop as it was (Eigen), capped and not, midpoint and
// full residuals, against vector_stabilisation_row.
TEST(ExtendedLawKernels, VectorStabilisationKeepsTheHostsBits) {
  std::mt19937_64 g(43);
  std::uniform_real_distribution<double> u(-1, 1);
  int bad = 0, returned = 0;
  for (int t = 0; t < 4000; ++t) {
    const int n = 10 + t % 30;
    Vec6 Ei;
    for (int q = 0; q < 6; ++q) Ei[q] = 0.01 * u(g);
    const double ks = 1e10 * (0.5 + std::abs(u(g)));
    const bool capped = t % 2 == 0;
    const double r_c = capped ? 0.003 * std::abs(u(g)) : 0.0;
    std::vector<kernels::VectorStabilisationBond> bonds(n);
    std::vector<Vec6> Ej(n);
    std::vector<uint8_t> acts(n);
    std::vector<double> rpc(n), rpt_host(n, -1.0), rpt_k(n, -1.0), rf_host(n, 0.0), rf_k(n, 0.0);
    for (int k = 0; k < n; ++k) {
      kernels::VectorStabilisationBond& b = bonds[k];
      for (int a = 0; a < 3; ++a) b.xi[a] = 1e-3 * u(g);
      if (t % 7 == 0) b.xi[2] = 0.0;
      b.eps = 0.01 * u(g), b.w = 1e-9 * std::abs(u(g));
      for (int q = 0; q < 6; ++q) Ej[k][q] = 0.01 * u(g);
      b.mid = t % 3 == 0 && u(g) > -0.5;
      b.Ej = b.mid ? Ej[k].data() : nullptr;
      b.ksj = b.mid ? 1e10 * std::abs(u(g)) : 0.0;
      acts[k] = u(g) > -0.7;
      rpc[k] = 0.002 * u(g);
    }
    // The host's loop.
    Mat3 R = Mat3::Zero();
    double W = 0, work = 0;
    for (int k = 0; k < n; ++k) {
      if (!acts[k]) continue;
      const kernels::VectorStabilisationBond& b = bonds[k];
      const Vec3d xi(b.xi[0], b.xi[1], b.xi[2]);
      double r0, coef = ks;
      if (b.mid) {
        r0 = b.eps - eigen_normal_projector(xi).dot(0.5 * (Ei + Ej[k]));
        coef = 0.5 * (ks + b.ksj);
      } else {
        r0 = b.eps - eigen_normal_projector(xi).dot(Ei);
      }
      double rp = 0;
      if (capped) {
        const double rc = rpc[k];
        rp = std::abs(r0 - rc) > r_c ? r0 - std::copysign(r_c, r0 - rc) : rc;
        work += 2.0 * coef * r_c * std::abs(rp - rc) * b.w;
        rpt_host[k] = rp;
        returned += rp != rc ? 1 : 0;
      }
      const double r = r0 - rp;
      rf_host[k] = r * coef / ks;
      const Eigen::Vector3d nv = xi.normalized();
      R.noalias() += (b.w * rf_host[k]) * nv * nv.transpose();
      W += coef * b.w * r * r;
    }
    auto bond = [&](uint64_t k, kernels::VectorStabilisationBond& b) {
      b = bonds[k];
      return acts[k] != 0;
    };
    kernels::VectorStabilisation st;
    kernels::vector_stabilisation_row(0, n, bond, Ei.data(), ks, capped, r_c, rpc.data(), rpt_k.data(), rf_k.data(),
                                      st);
    bad += test::differing(R, st.R) + differing(&W, &st.W, 1) + differing(&work, &st.work, 1);
    bad += differing(rf_host.data(), rf_k.data(), n);
    if (capped) bad += differing(rpt_host.data(), rpt_k.data(), n);
  }
  EXPECT_EQ(bad, 0);
  EXPECT_GT(returned, 5000);  // the capped return ran
}

// The vector form's bond terms as they were (NonlocalStrain::add_strain, residual and
// bond_force_state with Eigen 6-vectors), against vector_strain_add, dot6 and vector_bond_force.
TEST(ExtendedLawKernels, VectorFormBondTermsKeepEigensBits) {
  std::mt19937_64 g(47);
  std::uniform_real_distribution<double> u(-1, 1);
  int bad = 0;
  for (int t = 0; t < 20000; ++t) {
    const int dim = t % 3 == 0 ? 2 : 3;
    const double m = t % 4 == 0 ? 0.0 : (t % 4 == 1 ? 1.0 : (t % 4 == 2 ? 0.5 : -1.0));
    const Vec3d xi(1e-3 * u(g), 1e-3 * u(g), dim == 3 ? 1e-3 * u(g) : 0.0);
    const Vec3d Y = xi * (1.0 + 0.1 * u(g)) + Vec3d(1e-4 * u(g), 1e-4 * u(g), dim == 3 ? 1e-4 * u(g) : 0.0);
    const double w = 1e-9 * std::abs(u(g)), x[3] = {xi.x(), xi.y(), xi.z()}, y[3] = {Y.x(), Y.y(), Y.z()};
    Vec6 S, a, b, E;
    for (int q = 0; q < 6; ++q) S[q] = 1e-9 * u(g), a[q] = 1e9 * u(g), b[q] = 0.01 * u(g), E[q] = 0.01 * u(g);
    // add_strain
    const double c = (Y.x() * Y.x() + Y.y() * Y.y() + Y.z() * Y.z()) / (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    const double eps = kernels::seth_hill_strain(c, m);
    Vec6 Sk = S;
    S.noalias() += (w * eps) * eigen_shape_state(xi, dim);
    const double ek = kernels::vector_strain_add(Sk.data(), x, y, w, m, dim);
    bad += differing(S.data(), Sk.data(), 6) + differing(&eps, &ek, 1);
    // residual
    const double r_host = eps - eigen_normal_projector(xi).dot(E);
    double p[6];
    kernels::normal_projector_of(x, p);
    const double r_k = eps - kernels::dot6(p, E.data());
    bad += differing(&r_host, &r_k, 1);
    // bond_force_state
    const double ks = t % 5 == 0 ? 0.0 : 1e10 * std::abs(u(g)), omega = std::abs(u(g)), r = 0.01 * u(g);
    const double xi2 = x[0] * x[0] + x[1] * x[1] + x[2] * x[2], cc = (y[0] * y[0] + y[1] * y[1] + y[2] * y[2]) / xi2;
    const Vec6 h = eigen_shape_state(xi, dim);
    const double s = a.dot(h) + 2.0 * ks * (r - b.dot(h));
    const double gf = (m == 0.0 ? 1.0 / cc : m == 1.0 ? 1.0 : std::pow(cc, m - 1.0)) / xi2;
    const double f = omega * s * gf;
    const double T[3] = {f * y[0], f * y[1], f * y[2]};
    double Tk[3];
    kernels::vector_bond_force(a.data(), b.data(), ks, omega, m, dim, x, y, r, Tk);
    bad += differing(T, Tk, 3);
  }
  EXPECT_EQ(bad, 0);
}

TEST(ExtendedLawKernels, VolumetricGradientBondTermsKeepEigensBits) {
  std::mt19937_64 g(29);
  std::uniform_real_distribution<double> u(-1, 1);
  int bad = 0;
  for (int t = 0; t < 20000; ++t) {
    Mat3 N = Mat3::Zero(), P;
    double Nk[9] = {}, Pc[9];
    for (int b = 0; b < 8; ++b) {
      const Vec3d Y(u(g), u(g), u(g)), xi(u(g), u(g), t % 4 ? u(g) : 0.0);
      const double w = std::abs(u(g)) * 1e-9, y[3] = {Y.x(), Y.y(), Y.z()}, x[3] = {xi.x(), xi.y(), xi.z()};
      N.noalias() += w * Eigen::Vector3d(Y.x(), Y.y(), Y.z()) * Eigen::RowVector3d(xi.x(), xi.y(), xi.z());
      kernels::gradient_outer_add(Nk, w, y, x);
    }
    bad += differing(N.data(), Nk, 9);
    for (int k = 0; k < 9; ++k) P(k / 3, k % 3) = 1e8 * u(g);
    std::memcpy(Pc, P.data(), sizeof Pc);
    const Vec3d xi(u(g), u(g), t % 4 ? u(g) : 0.0);
    const double w = std::abs(u(g)), x[3] = {xi.x(), xi.y(), xi.z()};
    const Eigen::Vector3d tw = w * (P * Eigen::Vector3d(xi.x(), xi.y(), xi.z()));
    const Eigen::Vector3d t1 = P * Eigen::Vector3d(xi.x(), xi.y(), xi.z());
    double tk[3];
    kernels::pressure_bond_term(Pc, w, x, tk);
    bad += differing(tw.data(), tk, 3);
    kernels::mat3c_vec(Pc, x, tk);
    bad += differing(t1.data(), tk, 3);
  }
  EXPECT_EQ(bad, 0);
}

// The host's law row before the kernel: Fbar = N K^-1 (Eigen), run_law's kernel calls,
// P K^-1 (Eigen), a = dual(S) (Eigen), and row_end's von Mises stress (Eigen).
TEST(ExtendedLawKernels, LawRowKeepsTheHostsBits) {
  std::mt19937_64 g(31);
  std::uniform_real_distribution<double> u(-1, 1);
  classical::StrainLawParams p;
  p.kappa = 160e9, p.mu = 80e9, p.yield_stress = p.sigma0 = 1e9, p.hardening_modulus = 2e9;
  p.B = 5e8, p.n = 0.3, p.C = 0.02, p.rate0 = 1.0;
  p.d1 = 0.05, p.d2 = 3.4, p.d3 = -1.5, p.d4 = 0.01, p.damage_rate0 = 1.0;
  int bad = 0, yielded = 0, failed = 0;
  for (int t = 0; t < 12000; ++t) {
    const int law = t % 3, dim = t % 5 == 0 ? 2 : 3;
    p.law = law == 0 ? classical::StrainLaw::elastic : law == 1 ? classical::StrainLaw::j2 : classical::StrainLaw::johnson_cook;
    p.damage = law == 2 && t % 2 == 0;
    kernels::ExtendedLawConstants c;
    c.law = extended::strain_law_constants(p);
    c.dimension = dim;
    c.hencky = (t / 3) % 2 == 0;
    c.vol_gradient = (t / 6) % 2 == 0;
    c.floor = extended::kHenckyFloor;
    const double amp = t % 7 == 0 ? 0.3 : 0.01;
    Vec6 E;
    for (int k = 0; k < 6; ++k) E[k] = amp * u(g);
    if (dim == 2) E[2] = E[3] = E[4] = 0.0;
    Mat3 N, Kinv;
    for (int k = 0; k < 9; ++k) {
      N(k / 3, k % 3) = (k % 4 == 0 ? 1.0 : 0.0) + amp * u(g);
      Kinv(k / 3, k % 3) = (k % 4 == 0 ? 1.0 : 0.0) + 0.1 * u(g);
    }
    Mat6 inv;
    for (int k = 0; k < 36; ++k) inv.data()[k] = (k % 7 == 0 ? 1.0 : 0.0) + 0.1 * u(g);
    kernels::ExtendedLawHistory committed{};
    if (t % 4 < 2) {
      double P3[9];
      for (int k = 0; k < 9; ++k) P3[k] = 0.02 * u(g);
      const double tr = (P3[0] + P3[4] + P3[8]) / 3.0;
      for (int k = 0; k < 9; ++k) committed.Ep[k] = P3[k] - (k % 4 == 0 ? tr : 0.0);
      committed.alpha = 0.05 * std::abs(u(g));
      committed.damage = t % 97 == 0 ? 1.0 : 0.5 * std::abs(u(g));
    }
    const double dt = t % 7 == 0 ? 0.0 : 1e-8;
    // The host form.
    Mat3 Fbar = Mat3::Identity();
    if (c.vol_gradient) {
      Fbar = N * Kinv;
      if (dim == 2) Fbar(2, 2) = 1.0;
    }
    const Mat3 Em = extended::to_mat3(E);
    double hN[9] = {}, hl[3] = {}, strain[9], F[9] = {}, T[9], S[9] = {}, pm[9] = {};
    for (int k = 0; k < 9; ++k) strain[k] = Em(k / 3, k % 3), F[k] = Fbar(k / 3, k % 3);
    if (c.hencky) {
      double e[9];
      for (int k = 0; k < 9; ++k) e[k] = strain[k];
      kernels::hencky_of_green3(e, c.floor, hN, hl, strain);
    }
    if (c.vol_gradient) kernels::volumetric_gradient_strain(F, dim, strain);
    kernels::ExtendedLawHistory trial = committed;
    kernels::StrainLawPoint pt{};
    const bool host_ok = committed.damage < 1.0;
    Mat3 law_stress = Mat3::Zero(), pressure = Mat3::Zero();
    if (host_ok) {
      kernels::strain_law_point(c.law, committed.Ep, committed.alpha, committed.damage, strain, dt, trial.Ep,
                                trial.alpha, trial.damage, pt);
      for (int k = 0; k < 9; ++k) T[k] = pt.S[k], law_stress(k / 3, k % 3) = pt.S[k];
      if (c.vol_gradient) kernels::volumetric_pressure_split(F, dim, T, pm);
      for (int k = 0; k < 9; ++k) pressure(k / 3, k % 3) = pm[k];
      if (c.hencky) {
        kernels::green_stress_of_hencky3(hN, hl, T, S);
      } else {
        for (int k = 0; k < 9; ++k) S[k] = T[k];
      }
    }
    const Mat3 PK = pressure * Kinv;
    Mat3 Sm;
    for (int k = 0; k < 9; ++k) Sm(k / 3, k % 3) = S[k];
    const Vec6 a = inv.transpose() * (Vec6() << 1, 1, 1, 2, 2, 2).finished().cwiseProduct(to_vec6(Sm));
    const Mat3 dev = law_stress - (law_stress.trace() / 3.0) * Mat3::Identity();
    const double vm = std::sqrt(1.5 * (dev.array() * dev.array()).sum());
    // The kernel.
    kernels::ExtendedLawHistory ktrial{};
    kernels::ExtendedLawRow row;
    kernels::extended_law_row(c, inv.data(), E.data(), N.data(), Kinv.data(), committed, dt, ktrial, row);
    ASSERT_EQ(row.ok, host_ok);
    failed += host_ok ? 0 : 1;
    yielded += pt.plastic_work > 0 ? 1 : 0;
    bad += differing(PK.data(), row.PK, 9);
    bad += differing(trial.Ep, ktrial.Ep, 9) + differing(&trial.alpha, &ktrial.alpha, 1);
    bad += differing(&trial.damage, &ktrial.damage, 1);
    if (!host_ok) continue;
    bad += differing(S, row.S, 9) + differing(pt.S, row.law_stress, 9) + differing(a.data(), row.a, 6);
    bad += differing(&pt.W, &row.W, 1) + differing(&pt.plastic_work, &row.plastic_work, 1);
    bad += differing(&pt.rate, &row.rate, 1) + differing(&vm, &row.von_mises, 1);
  }
  EXPECT_EQ(bad, 0);
  EXPECT_GT(yielded, 1000);
  EXPECT_GT(failed, 20);
}

}  // namespace
}  // namespace horizon
