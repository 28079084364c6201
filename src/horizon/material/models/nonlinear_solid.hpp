#pragma once
// Tupek's nonlinear ordinary elastic solid with brittle bond failure (seed
// 000_7a6865da82fe3c94, M. R. Tupek, PhD thesis MIT 2014; digest
// reference/notes/000_tupek.md). Pure per-bond kernels and constants here; the model
// (nonlinear_solid.cpp) owns its force pass, because its energy failure law couples the
// two ends of a bond, and shares a run only with materials of its own model.
//
// One force pass is two sweeps over the rows, each particle summing its own row in bond
// order (bit-identical on any number of threads):
//   1. bond strains eps_ij (stored per bond) and theta_i = sum_j phi omega eps V_j (eq. 6.8);
//   2. for each intact bond in tension, the symmetric pair criterion
//      s_ij + s_ji >= 2 beta/|xi|^2, s_ij = lambda_bar_i eps theta_i + mu_bar_i eps^2
//      (eqs. 6.5, 6.10/6.11 and the symmetrised form of sec. 6.1.3), computed from both
//      ends' theta of sweep 1, so both copies of a bond decide identically; then the force
//      f_i = sum_j (t_ij + t_ji) Y/|Y| V_j, t_ij = (lambda_bar_i theta_i + 2 mu_bar_i eps)
//      phi omega d eps/d|Y| (eq. 6.8).
// A bond that breaks in sweep 2 still carries its force in that pass (the force is then
// the exact gradient of the energy with the flags at the start of the pass) and is off
// from the next pass on; its instantaneous energy omega V_j s_ij (per unit V_i, eq. 6.5)
// goes to dissipated_at, and the strain energy reported for the pass is the one with
// the bond cut, so that elastic + kinetic + dissipated balances.
//
// The stable time step follows the current bond tangent stiffness (digest sec. 13.1):
// min_i sqrt(2 rho_i / sum_j K_ij), K_ij = d(t_ij + t_ji)/d|Y| V_j with the dilatation
// coupling bounded Gershgorin-wise, plus the contact springs.
//
// Notation (digest sec. 0): m is the Seth-Hill parameter, NOT the weighted volume. The
// influence functions are the normalised ones of (6.6)/(6.7): int_H omega = 2 (2-D) or
// 3 (3-D) in the bulk, not renormalised near surfaces (thesis sec. 6.1.3).
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <vector>

#include "horizon/kernels/tupek.hpp"

namespace horizon {

// The per-bond functions (Seth-Hill strain eps_(m) = (c^m - 1)/(2m) of thesis eq. 4.2, its
// first and second derivatives in |Y|) are device-portable kernels (kernels/tupek.hpp).
using kernels::seth_hill_curvature;
using kernels::seth_hill_slope;
using kernels::seth_hill_strain;

// Normalised influence functions: (6.6) omega_2D = 10/(pi delta^6) (3r + delta)(delta - r)^3,
// int omega dA = 2; (6.7) omega_3D = 315/(16 pi delta^7) (3r + delta)(delta - r)^3,
// int omega dV = 3. Zero at and beyond the horizon.
inline double tupek_influence(double r, double delta, int dimension) {
  if (!(r < delta)) return 0.0;
  const double shape = (3.0 * r + delta) * (delta - r) * (delta - r) * (delta - r);
  if (dimension == 2) return 10.0 / (std::numbers::pi * std::pow(delta, 6)) * shape;
  return 315.0 / (16.0 * std::numbers::pi * std::pow(delta, 7)) * shape;
}

// Peridynamic Lame constants from the classical ones.
// 3-D (thesis sec. 5.1): kappa_bar = kappa, mu_bar = 5/2 mu, lambda_bar = lambda - mu.
// 2-D (digest sec. 4.1, derived with int omega = 2 and <n_i n_j n_k n_l> = (sym)/8):
// mu_bar = 2 mu, lambda_bar = lambda_2D - mu, lambda_2D = E nu/(1 - nu^2) (plane stress)
// or E nu/((1 + nu)(1 - 2 nu)) (plane strain).
struct TupekLame {
  double lambda_bar = 0, mu_bar = 0;
};
inline TupekLame tupek_lame(double E, double nu, int dimension, bool plane_stress) {
  const double mu = E / (2 * (1 + nu));
  if (dimension == 3) return {E * nu / ((1 + nu) * (1 - 2 * nu)) - mu, 2.5 * mu};
  const double lambda2 = plane_stress ? E * nu / (1 - nu * nu) : E * nu / ((1 + nu) * (1 - 2 * nu));
  return {lambda2 - mu, 2.0 * mu};
}

// Critical bond-energy coefficient beta of s_c = beta omega / |xi|^2 (thesis eq. 6.3),
// such that cutting every bond across a plane dissipates G_c (eqs. 6.1/6.2):
//   2-D: beta = pi delta G_c / 16 (thesis sec. 6.1.3);
//   3-D: beta = 16 delta G_c / 63. The thesis prints 16 pi delta G_c/63, but its own
//   integral (6.1) with (6.7) is beta 63/(32 delta) = G_c/2, i.e. no pi (digest sec. 0.3;
//   tests/unit/test_nonlinear_solid.cpp integrates it and recovers G_c only without pi).
//
// With the bond-failure-energy function s_c = beta omega |xi|^-p (p = exponent; the thesis
// calls its form a constitutive choice, sec. 6.1.1), the same integrals (6.2)/(6.1) give
//   2-D: int_0^delta 2 beta omega(r) r^(2-p) dr = G_c/2,
//   3-D: pi int_0^delta beta omega(r) r^(3-p) dr = G_c/2,
// and with omega = C (3r + delta)(delta - r)^3:
//   int_0^delta r^q (3r + delta)(delta - r)^3 dr = delta^(q+5) (3 B(q+2, 4) + B(q+1, 4)),
// B the beta function. p = 2 gives the two closed forms above, which are kept exactly.
inline double tupek_beta(double fracture_energy, double delta, int dimension, double exponent = 2) {
  if (exponent == 2) {
    if (dimension == 2) return std::numbers::pi * delta * fracture_energy / 16.0;
    return 16.0 * delta * fracture_energy / 63.0;
  }
  auto beta_fn = [](double a, double b) { return std::exp(std::lgamma(a) + std::lgamma(b) - std::lgamma(a + b)); };
  const double q = (dimension == 2 ? 2.0 : 3.0) - exponent;
  const double moment = std::pow(delta, q + 5) * (3 * beta_fn(q + 2, 4) + beta_fn(q + 1, 4));  // / C
  if (dimension == 2) {
    const double C = 10.0 / (std::numbers::pi * std::pow(delta, 6));
    return fracture_energy / (4.0 * C * moment);
  }
  const double C = 315.0 / (16.0 * std::numbers::pi * std::pow(delta, 7));
  return fracture_energy / (2.0 * std::numbers::pi * C * moment);
}

// The instantaneous bond energy (thesis eq. 6.5) per unit omega (kernels/tupek.hpp).
using kernels::instantaneous_bond_energy;

// Per-particle state of the model, owned by the model object of the run.
struct NonlinearState {
  bool enabled = false;
  std::vector<double> lambda_bar, mu_bar, m;  // per particle (from its material)
  std::vector<double> beta;                   // per particle; +inf: bonds never break
  std::vector<double> failure_scale;          // per bond kind: |xi|^-p of s_c (used when p != 2)
  bool failure_exponent_two = true;           // p = 2 everywhere: the criterion uses 1/|xi|^2 as written
  std::vector<uint8_t> compression_only;      // 1: broken bonds push in compression (6.9); 0: off for good
  std::vector<double> theta;                  // theta_phi (eq. 6.8), from the last force pass
  std::vector<double> nonlocal_damage;        // D = 1 - (1/d) int omega phi (eq. 6.12), phi from the broken flags
  std::vector<double> bond_strain;            // per bond: eps of the last pass
  std::vector<double> contact_stiffness;      // per particle: family contact springs, for the time step
  double dimension = 3;
  int adaptive_every = 0;                     // >0: the stable step is recomputed every N steps
  double last_stable_dt = 0;
};

struct ModelEntry;
struct System;
ModelEntry nonlinear_solid_model();

// The state of the run's nonlinear solid, or null when the run has none (tests, output;
// the flat backend's copy writes its state back through the second: solver/flat_copy.cpp).
const NonlinearState* nonlinear_state(const System& s);
NonlinearState* nonlinear_state(System& s);

}  // namespace horizon
