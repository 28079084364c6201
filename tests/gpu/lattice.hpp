#pragma once
// A block of a simple cubic lattice as a flat state (kernels/flat_system.hpp), built without
// the library (the device machine has no yaml-cpp, Cairo, ...: the GPU tests and benchmark
// build with -DHORIZON_GPU_ONLY=ON from the kernel headers alone). Horizon 3 spacings
// (122 neighbours inside), omega = 1, whole volumes; PMB (c = 18 K/(pi delta^4), seed 002
// eq. 22, nu = 1/4) or LPS (a = 3K/m, b = 15 mu/m, seed 003 eq. 112-113); a striker of the
// first `striker` layers moving at (v0, v0/6, 0) into the rest, bonded to it, bonds
// breaking at the critical stretch s0.
#include <cmath>
#include <cstdint>
#include <vector>

#include "horizon/kernels/flat_system.hpp"

namespace horizon::test {

struct Lattice {
  std::vector<uint64_t> offset;
  std::vector<uint32_t> nbr, kind;
  std::vector<uint8_t> intact, no_fail;
  std::vector<kernels::Kind> kinds;
  std::vector<double> r_of, X, u, v, f, b, density, volume, critical_stretch, alpha, min_stretch, min_stretch_next,
      dilatation_coef, Q, R, weighted_volume, theta, P, intact_weight, damage_total, damage, energy, dissipated, y4;
  std::vector<uint64_t> broken;
  // Loads (add_loads): constraints, the tracked particles, the constraints' entries.
  std::vector<uint8_t> fixed, entry_mask;
  std::vector<double> fixed_value, u_before, v_before, entry_reaction, ledger{0.0};
  std::vector<uint32_t> tracked, entry_slot;
  bool has_forces = false;
  // Tupek's nonlinear solid (make_tupek_lattice; empty otherwise).
  std::vector<double> eps, seth_m, lambda_bar, mu_bar, beta, failure_scale, nonlocal_damage, contact_stiffness;
  std::vector<uint8_t> compression_only;
  bool tupek = false;
  // The correspondence model (make_affine_lattice; off otherwise): kernels/flat_affine.hpp.
  bool affine = false;
  kernels::FlatAffine affine_constants;
  std::vector<kernels::FlatAffineLaw> laws;
  std::vector<uint32_t> material;
  std::vector<kernels::FlatPoint> ref, kind_record;
  std::vector<kernels::FlatBondKind> bond_kinds;
  std::vector<double> omega_volume, record, work, von_mises, F_pass;
  std::vector<horizon::Vec3> y_old;
  std::vector<uint8_t> singular;
  std::vector<kernels::J2History> j2_committed, j2_trial;
  // elastic_plastic, viscoelastic or microplastic (make_ordinary_lattice, make_micro_lattice;
  // ord.model 0 otherwise): the
  // arrays kernels::FlatOrdinary points to (view() points ord into them).
  kernels::FlatOrdinary ord;
  std::vector<double> o_omega, o_vj, o_r[2], o_q[2], o_pending_amount, o_stored, o_theta, o_ep, o_eps_p, o_lambda,
      o_shear_factor, o_dissipated, o_back[kernels::kFlatBranches], o_sbar, o_sigma, o_tau;
  std::vector<kernels::FlatPalsKind> o_pals_kinds;
  std::vector<uint64_t> o_rev;
  std::vector<uint8_t> o_booked, o_pending_set, o_flowed, o_yielded, o_current{0};
  uint64_t n = 0;
  bool lps = false;
  double dt = 0;
  // solver.verlet: peridigm (set_peridigm; off otherwise): FlatSystem::peridigm's arrays.
  bool peridigm = false;
  std::vector<double> positions, fixed_v, fixed_rate;

  kernels::FlatSystem view() {
    kernels::FlatSystem s;
    s.n = n, s.nb = nbr.size(), s.nkinds = kinds.size(), s.state_based = lps, s.dim = 3, s.dt = dt, s.damping = 0;
    s.offset = offset.data(), s.nbr = nbr.data(), s.kind = kind.data(), s.intact = intact.data();
    s.kinds = kinds.data(), s.r_of = r_of.data();
    s.X = X.data(), s.u = u.data(), s.v = v.data(), s.f = f.data(), s.b = b.data();
    s.density = density.data(), s.volume = volume.data(), s.critical_stretch = critical_stretch.data();
    s.alpha = alpha.data(), s.no_fail = no_fail.data(), s.min_stretch = min_stretch.data();
    s.min_stretch_next = min_stretch_next.data(), s.dilatation_coef = dilatation_coef.data(), s.Q = Q.data();
    s.R = R.data(), s.weighted_volume = weighted_volume.data(), s.theta = theta.data(), s.P = P.data();
    s.intact_weight = intact_weight.data(), s.damage_total = damage_total.data(), s.damage = damage.data();
    s.energy = energy.data(), s.dissipated = dissipated.data(), s.y4 = y4.data(), s.broken = broken.data();
    s.fixed = fixed.empty() ? nullptr : fixed.data(), s.fixed_value = fixed.empty() ? nullptr : fixed_value.data();
    s.ntracked = tracked.size(), s.tracked = tracked.data(), s.u_before = u_before.data(), s.v_before = v_before.data();
    s.has_forces = has_forces, s.nentries = entry_slot.size(), s.entry_slot = entry_slot.data();
    s.entry_mask = entry_mask.data(), s.entry_reaction = entry_reaction.data(), s.ledger = ledger.data();
    if (peridigm) {
      s.peridigm = true, s.positions = positions.data();
      if (!fixed.empty()) s.fixed_v = fixed_v.data(), s.fixed_rate = fixed_rate.data();
    }
    if (tupek) {
      s.tupek = true, s.eps = eps.data(), s.seth_m = seth_m.data(), s.lambda_bar = lambda_bar.data();
      s.mu_bar = mu_bar.data(), s.beta = beta.data(), s.compression_only = compression_only.data();
      s.failure_scale = failure_scale.data(), s.nonlocal_damage = nonlocal_damage.data();
      s.contact_stiffness = contact_stiffness.data();
    }
    if (affine) {
      s.correspondence = true;
      kernels::FlatAffine& a = s.affine;
      a = affine_constants;
      a.nlaws = laws.size(), a.laws = laws.data(), a.material = material.data();
      a.ref = ref.data(), a.kind_record = kind_record.data(), a.bond_kinds = bond_kinds.data();
      a.omega_volume = omega_volume.data(), a.record = record.data(), a.y_old = y_old.data(), a.work = work.data();
      a.von_mises = von_mises.data(), a.singular = singular.data(), a.F_pass = F_pass.data();
      a.j2_committed = j2_committed.data(), a.j2_trial = j2_trial.data();
    }
    if (ord.model) {
      auto p = [](auto& a) { return a.empty() ? nullptr : a.data(); };
      ord.omega = p(o_omega), ord.vj = p(o_vj), ord.current = p(o_current);
      for (int b = 0; b < 2; ++b) ord.r[b] = p(o_r[b]), ord.q[b] = p(o_q[b]);
      ord.rev = p(o_rev), ord.booked = p(o_booked), ord.pending_set = p(o_pending_set);
      ord.pending_amount = p(o_pending_amount), ord.stored = p(o_stored), ord.theta = p(o_theta), ord.ep = p(o_ep);
      ord.eps_p = p(o_eps_p), ord.lambda = p(o_lambda), ord.shear_factor = p(o_shear_factor);
      ord.flowed = p(o_flowed), ord.yielded = p(o_yielded), ord.dissipated_density = p(o_dissipated);
      for (int b = 0; b < kernels::kFlatBranches; ++b) ord.back[b] = p(o_back[b]);
      ord.sbar = p(o_sbar), ord.sigma = p(o_sigma), ord.tau = p(o_tau), ord.pals_kinds = p(o_pals_kinds);
      s.ordinary = &ord;
    }
    return s;
  }
};

inline Lattice make_lattice(int nx, int ny, int nz, bool lps, double s0 = 0.002, int striker = 6, double v0 = 40) {
  const double h = 1e-3, delta = 3 * h, E = 200e9, nu = 0.25, rho = 7850, V = h * h * h;
  const double K = E / (3 * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
  const double pi = 3.14159265358979323846, c = 18 * K / (pi * std::pow(delta, 4));
  Lattice L;
  L.lps = lps;
  const uint64_t n = static_cast<uint64_t>(nx) * ny * nz;
  L.n = n;
  // Kinds by r^2 = a^2 + b^2 + c^2 of the offset (1..9; 7 is never a sum of three squares).
  L.kinds.resize(9);
  double stiffness = 0;  // sum_j V c/|xi| of an interior particle: the stable step below
  struct Off {
    int a, b, c;
    uint32_t kind;
  };
  std::vector<Off> offs;
  for (int a = -3; a <= 3; ++a)
    for (int b2 = -3; b2 <= 3; ++b2)
      for (int c2 = -3; c2 <= 3; ++c2) {
        const int r2 = a * a + b2 * b2 + c2 * c2;
        if (r2 == 0 || r2 > 9) continue;
        offs.push_back({a, b2, c2, static_cast<uint32_t>(r2 - 1)});
        stiffness += V * c / (h * std::sqrt(static_cast<double>(r2)));
      }
  for (int r2 = 1; r2 <= 9; ++r2) {
    const double len = h * std::sqrt(static_cast<double>(r2));
    L.kinds[r2 - 1] = {len, 1.0 / len, lps ? 0.0 : V * c / len, 0.0, 1.0, V, 0.0, 0.0};
  }
  L.dt = 0.5 * std::sqrt(2 * rho / stiffness);
  L.offset.assign(n + 1, 0);
  L.nbr.reserve(n * offs.size());
  L.kind.reserve(n * offs.size());
  L.X.resize(3 * n);
  L.v.assign(3 * n, 0.0);
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) {
        const uint64_t i = (static_cast<uint64_t>(z) * ny + y) * nx + x;
        L.X[3 * i] = x * h, L.X[3 * i + 1] = y * h, L.X[3 * i + 2] = z * h;
        if (x < striker) L.v[3 * i] = v0, L.v[3 * i + 1] = v0 / 6;
        for (const Off& o : offs) {
          const int X2 = x + o.a, Y2 = y + o.b, Z2 = z + o.c;
          if (X2 < 0 || Y2 < 0 || Z2 < 0 || X2 >= nx || Y2 >= ny || Z2 >= nz) continue;
          L.nbr.push_back(static_cast<uint32_t>((static_cast<uint64_t>(Z2) * ny + Y2) * nx + X2));
          L.kind.push_back(o.kind);
        }
        L.offset[i + 1] = L.nbr.size();
      }
  const uint64_t nb = L.nbr.size();
  L.intact.assign(nb, 1);
  L.r_of.assign(nb, 0.0);
  L.u.assign(3 * n, 0.0), L.f.assign(3 * n, 0.0), L.b.assign(3 * n, 0.0);
  L.density.assign(n, rho), L.volume.assign(n, V), L.critical_stretch.assign(n, s0), L.alpha.assign(n, 0.0);
  L.no_fail.assign(n, 0), L.min_stretch.assign(n, 0.0), L.min_stretch_next.assign(n, 0.0);
  L.dilatation_coef.assign(n, 0.0), L.Q.assign(n, 0.0), L.R.assign(n, lps ? 0.0 : c / 2);
  L.weighted_volume.assign(n, 0.0), L.theta.assign(n, 0.0), L.P.assign(n, 0.0);
  L.intact_weight.resize(n), L.damage_total.resize(n), L.damage.assign(n, 0.0);
  L.energy.assign(n, 0.0), L.dissipated.assign(n, 0.0), L.y4.assign(4 * n, 0.0), L.broken.assign(n, 0);
  for (uint64_t i = 0; i < n; ++i) {
    double m = 0;
    for (uint64_t k = L.offset[i]; k < L.offset[i + 1]; ++k) {
      const double len = L.kinds[L.kind[k]].length;
      m += kernels::weighted_volume_term(1.0, len, V);  // m_i = sum omega |xi|^2 V_j
    }
    L.weighted_volume[i] = m;
    if (lps && m > 0) L.dilatation_coef[i] = 3 * K / m, L.Q[i] = 15 * mu / m;
    L.intact_weight[i] = L.damage_total[i] = static_cast<double>(L.offset[i + 1] - L.offset[i]);
  }
  return L;
}

// The same lattice as Tupek's nonlinear solid (material/models/nonlinear_solid.hpp, seed 000,
// Tupek's thesis; its formulas written again here, so that the GPU-only build needs the
// kernel headers alone): the normalised 3-D influence of eq. 6.7, omega = 315/(16 pi
// delta^7) (3r + delta)(delta - r)^3 (omega V_j of each kind), the peridynamic Lame
// constants of sec. 5.1 (lambda_bar = lambda - mu, mu_bar = 5/2 mu; E = 200 GPa, nu = 0.3),
// beta = 16 delta gc/63 of s_c = beta omega/|xi|^2 (eq. 6.3 with p = 2, 3-D:
// nonlinear_solid.hpp tupek_beta), Seth-Hill parameter m, broken bonds pushing in
// compression; no contact springs. The step: half the stable step of the rest state
// (kernels::flat_tupek_stable_step). The striker (the first `striker` layers at (v0, v0/6,
// 0)) stays bonded to the bar: the energy law breaks the bonds at the interface.
inline Lattice make_tupek_lattice(int nx, int ny, int nz, double m = 0, double gc = 3000, int striker = 6,
                                  double v0 = 40) {
  Lattice L = make_lattice(nx, ny, nz, false, 0.002, striker, v0);
  const double h = 1e-3, delta = 3 * h, V = h * h * h, E = 200e9, nu = 0.3, pi = 3.14159265358979323846;
  L.tupek = true;
  for (kernels::Kind& k : L.kinds) {
    const double r = k.length, gap = delta - r;
    const double w = 315.0 / (16.0 * pi * std::pow(delta, 7)) * (3.0 * r + delta) * gap * gap * gap * V;
    k = {k.length, k.inv_length, 0.0, 0.0, w, w, 0.0, 0.0};
    L.failure_scale.push_back(k.inv_length * k.inv_length);
  }
  const uint64_t n = L.n;
  const double mu = E / (2 * (1 + nu)), lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
  L.seth_m.assign(n, m), L.lambda_bar.assign(n, lambda - mu), L.mu_bar.assign(n, 2.5 * mu);
  L.beta.assign(n, 16.0 * delta * gc / 63.0), L.compression_only.assign(n, 1);
  L.nonlocal_damage.assign(n, 0.0), L.contact_stiffness.assign(n, 0.0), L.eps.assign(L.nbr.size(), 0.0);
  for (uint64_t i = 0; i < n; ++i) {
    double w = 0;
    for (uint64_t k = L.offset[i]; k < L.offset[i + 1]; ++k) w += L.kinds[L.kind[k]].wv;
    L.intact_weight[i] = L.damage_total[i] = w;
  }
  std::vector<double> S(n);
  L.dt = 0.5 * kernels::flat_tupek_stable_step(L.view(), S.data());
  return L;
}

// The same lattice as the correspondence model (material/models/correspondence.hpp; its
// constants written again here for the GPU-only build): the J2 law (Simo and Hughes' return
// on the Hencky strain, kernels/laws.hpp) with the lattice's K and mu, sigma_y = 400 MPa,
// H = 2 GPa, Silling 2017's stabilisation G = 0.5 c/delta (c = 18 K/(pi delta^4), as the
// model's stabilization_modulus), omega = 1, bonds breaking at the critical stretch s0;
// the records start at 0, the last pass's positions at X (as after a first pass at rest).
inline Lattice make_affine_lattice(int nx, int ny, int nz, double s0 = 0.002) {
  Lattice L = make_lattice(nx, ny, nz, false, s0);
  const double h = 1e-3, delta = 3 * h, V = h * h * h, E = 200e9, nu = 0.25, pi = 3.14159265358979323846;
  const double K = E / (3 * (1 - 2 * nu)), mu = E / (2 * (1 + nu)), c = 18 * K / (pi * std::pow(delta, 4));
  const uint64_t n = L.n;
  L.affine = true;
  L.affine_constants.contact = false;
  kernels::FlatAffineLaw a;
  a.dim = 3, a.tolerance = 1e-4, a.G = 0.5 * c / delta, a.rate = false;
  a.law.law = kernels::kJ2Law, a.law.lambda = K - 2.0 * mu / 3.0, a.law.mu = mu, a.law.kappa = K;
  a.law.yield_stress = 4.0e8, a.law.hardening = 2.0e9;
  L.laws = {a};
  L.material.assign(n, 0);
  for (const kernels::Kind& k : L.kinds) {
    L.kind_record.push_back({k.length, k.inv_length, V, 0.0});
    L.bond_kinds.push_back({V, 1.0, 1.0});
    L.omega_volume.push_back(V);
  }
  L.ref.resize(n), L.y_old.resize(n);
  for (uint64_t i = 0; i < n; ++i) {
    L.ref[i] = {L.X[3 * i], L.X[3 * i + 1], L.X[3 * i + 2], 0.0};
    L.y_old[i] = {L.X[3 * i], L.X[3 * i + 1], L.X[3 * i + 2]};
  }
  L.record.assign(kernels::kAffineRecord * n, 0.0), L.work.assign(n, 0.0), L.von_mises.assign(n, 0.0);
  L.F_pass.assign(9 * n, 0.0);
  L.singular.assign(n, 0), L.j2_committed.assign(n, kernels::J2History{}), L.j2_trial.assign(n, kernels::J2History{});
  // The stable step: the bond-based spring stiffened by the stabilisation (1 + G_s).
  L.dt /= std::sqrt(1.5);
  return L;
}

// The same lattice as an ordinary history model (kernels/flat_ordinary.hpp; material/models/
// elastic_plastic.hpp and viscoelastic.hpp, their constants written again here): omega = 1,
// E = 200 GPa, nu = 1/4 (k' = K in 3-D, alpha m = 15 mu); elastic_plastic with yield stress
// 150 MPa and hardening 2 GPa, viscoelastic with two Maxwell branches (lambda 0.4, tau 0.2 us;
// lambda 0.3, tau 1 us: the exact SLS step of viscoelastic.hpp sls_step, h >= 0.05 here).
// At rest as after the initial pass: |Y| = |xi|, q = 0.
inline Lattice make_ordinary_lattice(int nx, int ny, int nz, bool plastic, double s0 = 0.004, double v0 = 60) {
  Lattice L = make_lattice(nx, ny, nz, false, s0, 6, v0);
  const double E = 200e9, nu = 0.25, V = 1e-9;
  const double K = E / (3 * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
  kernels::FlatOrdinary& o = L.ord;
  o.model = plastic ? 1 : 2;
  o.dim = 3;
  o.dev_factor = 15.0;
  o.mu = mu;
  const uint64_t n = L.n, nb = L.nbr.size();
  for (kernels::Kind& k : L.kinds) {
    k.pair = 0.0, k.wv = V;  // omega V_j
    L.o_omega.push_back(1.0), L.o_vj.push_back(V);
  }
  for (uint64_t k = 0; k < nb; ++k) L.o_r[0].push_back(L.kinds[L.kind[k]].length);
  L.o_r[1].assign(nb, 0.0), L.o_q[0].assign(nb, 0.0), L.o_q[1].assign(nb, 0.0);
  L.o_booked.assign(nb, 0), L.o_pending_set.assign(nb, 0);
  L.o_pending_amount.assign(nb, 0.0), L.o_stored.assign(n, 0.0), L.o_theta.assign(n, 0.0);
  L.o_rev.resize(nb);
  for (uint64_t i = 0; i < n; ++i)
    for (uint64_t k = L.offset[i]; k < L.offset[i + 1]; ++k) {
      const uint32_t j = L.nbr[k];
      for (uint64_t q = L.offset[j]; q < L.offset[j + 1]; ++q)
        if (L.nbr[q] == i) L.o_rev[k] = q;
    }
  if (plastic) {
    o.bulk = K, o.yield = 150e6, o.hardening = 2e9;
    L.o_ep.assign(nb, 0.0), L.o_eps_p.assign(n, 0.0), L.o_lambda.assign(n, 0.0), L.o_shear_factor.assign(n, 1.0);
    L.o_flowed.assign(n, 0), L.o_yielded.assign(n, 0);
  } else {
    o.bulk_elastic = K, o.lambda_inf = 0.3, o.branches = 2;
    const double lambda[2] = {0.4, 0.3}, tau[2] = {2e-7, 1e-6};
    for (int b = 0; b < 2; ++b) {
      const double h = L.dt / tau[b], ratio = -std::expm1(-h) / h;  // sls_step (h >= 0.05)
      o.branch_lambda[b] = lambda[b], o.decay[b] = std::exp(-h), o.from_old[b] = ratio - o.decay[b];
      o.from_new[b] = 1.0 - ratio;
      L.o_back[b].assign(nb, 0.0);
    }
    L.o_dissipated.assign(n, 0.0);
  }
  return L;
}

// The same lattice as microplastic (kernels/flat_ordinary.hpp micro_flat_row; material/models/
// microplastic.hpp): PMB's c = 18 K/(pi delta^4) (E = 200 GPa, nu = 1/4), yield stretch
// 0.0005, omega = 1. At rest as after the initial pass.
inline Lattice make_micro_lattice(int nx, int ny, int nz, double s0 = 0.004, double v0 = 60) {
  Lattice L = make_ordinary_lattice(nx, ny, nz, false, s0, v0);
  const double delta = 3e-3, E = 200e9, nu = 0.25, pi = 3.14159265358979323846;
  const double K = E / (3 * (1 - 2 * nu));
  kernels::FlatOrdinary& o = L.ord;
  o.model = 3, o.branches = 0;
  o.micro_c = 18 * K / (pi * std::pow(delta, 4)), o.yield_stretch = 0.0005;
  for (int b = 0; b < kernels::kFlatBranches; ++b) L.o_back[b].clear();
  L.o_sbar.assign(L.nbr.size(), 0.0);
  return L;
}

// The same lattice as PALS (kernels/flat_ordinary.hpp pals_flat_row, kernels/pals.hpp):
// kappa = K, mu of E = 200 GPa, nu = 1/4; sigma and tau of row i the LPS-like 3/m_i and
// 7.5/m_i (m_i = sum |xi|^2 V_j: t = kappa theta sigma |xi| + 2 mu tau e^d - ... is then
// LPS's force state; not PALS's Lagrange multipliers, which the device test does not need:
// it compares the device with the host on the same arrays). At rest as after the initial pass.
inline Lattice make_pals_lattice(int nx, int ny, int nz, double s0 = 0.004, double v0 = 60) {
  Lattice L = make_ordinary_lattice(nx, ny, nz, false, s0, v0);
  const double E = 200e9, nu = 0.25, V = 1e-9;
  kernels::FlatOrdinary& o = L.ord;
  o.model = 4, o.branches = 0;
  o.kappa = E / (3 * (1 - 2 * nu)), o.mu = E / (2 * (1 + nu));
  for (int b = 0; b < kernels::kFlatBranches; ++b) L.o_back[b].clear();
  for (const kernels::Kind& k : L.kinds) L.o_pals_kinds.push_back({k.length, V, 1.0});
  L.o_sigma.assign(L.nbr.size(), 0.0), L.o_tau.assign(L.nbr.size(), 0.0);
  for (uint64_t i = 0; i < L.n; ++i) {
    double m = 0;
    for (uint64_t k = L.offset[i]; k < L.offset[i + 1]; ++k) m += L.kinds[L.kind[k]].length * L.kinds[L.kind[k]].length * V;
    for (uint64_t k = L.offset[i]; k < L.offset[i + 1]; ++k) L.o_sigma[k] = 3.0 / m, L.o_tau[k] = 7.5 / m;
  }
  return L;
}

// The loads of solver/flat_copy.cpp on the lattice: the far end (the last layer in x)
// clamped in x (displacement 0), the striker's first layer held at its y-velocity
// (velocity), a body force in y on the far end; their work goes to ledger[0].
inline void add_loads(Lattice& L, int nx, double b) {
  const double h = 1e-3;
  L.fixed.assign(L.n, 0), L.fixed_value.assign(3 * L.n, 0.0);
  std::vector<uint32_t> ends, firsts;
  for (uint64_t i = 0; i < L.n; ++i) {
    const int x = static_cast<int>(std::lround(L.X[3 * i] / h));
    if (x == nx - 1) ends.push_back(static_cast<uint32_t>(i)), L.fixed[i] |= 1u << 3, L.b[3 * i + 1] = b;
    if (x == 0) firsts.push_back(static_cast<uint32_t>(i)), L.fixed[i] |= 1u << 1, L.fixed_value[3 * i + 1] = L.v[3 * i + 1];
  }
  L.has_forces = true;
  std::vector<uint32_t> slot(L.n, 0);
  for (uint64_t i = 0; i < L.n; ++i)
    if (L.fixed[i]) slot[i] = static_cast<uint32_t>(L.tracked.size()), L.tracked.push_back(static_cast<uint32_t>(i));
  for (uint32_t i : ends) L.entry_slot.push_back(slot[i]), L.entry_mask.push_back(1u);
  for (uint32_t i : firsts) L.entry_slot.push_back(slot[i]), L.entry_mask.push_back(2u);
  L.entry_reaction.assign(3 * L.entry_slot.size(), 0.0);
  L.u_before.assign(3 * L.tracked.size(), 0.0), L.v_before.assign(3 * L.tracked.size(), 0.0);
}

// Peridigm's step (FlatSystem::peridigm) after add_loads or without loads: the clamp's
// increment 0 every step, so its velocity is (0 - u)/dt (Loads::prescribe_increments with
// t1 - t0 = dt: the values need no stepper).
inline void set_peridigm(Lattice& L) {
  L.peridigm = true;
  L.positions.assign(3 * L.n, 0.0);
  if (!L.fixed.empty()) L.fixed_v.assign(3 * L.n, 0.0), L.fixed_rate.assign(3 * L.n, 1.0 / L.dt);
}

}  // namespace horizon::test
