#pragma once
// Nonlocal (bond-based peridynamic) heat conduction on the bonds of the mechanics
// (docs/models/heat.md). Per unit volume of particle i:
//   rho c dT_i/dt = sum_j kbar_ij g(|xi_ij|) (T_j - T_i) V_j + q_i + h_i (T_amb - T_i),
// kbar_ij = (kappa_i + kappa_j)/2 (the symmetric kernel of digest 004 sec. 8), over the
// intact bonds (a crack stops the heat). It is the nonlocal Laplacian of digest 004
// sec. 9, L[u] = 2 int (u(y) - u(x)) mu(x,y) dy, with 2 mu = kbar g; in the discrete form
// heat leaves i exactly as it reaches j, so conduction conserves sum rho c T V to round-off.
//
// Calibration (kappa from the classical conductivity k): a quadratic T = x_1^2 gives
// L T = kappa M2 with M2 = int_H g xi_1^2 dV, and the local equation gives 2k; hence
//   kappa = 2k / M2,
//   inverse kernel:  1-D 2k/(A delta^2), 2-D 6k/(pi h delta^3), 3-D 6k/(pi delta^4)
//                    (Bobaru and Duangpanya 2010, Int. J. Heat Mass Transfer 53:4047;
//                    Oterkus, Madenci and Agwai 2014, J. Comput. Phys. 265:71);
//   constant kernel: 1-D 3k/(A delta^3) (digest 004 sec. 8, C = (3/delta^3) k),
//                    2-D 8k/(pi h delta^4), 3-D 15k/(2 pi delta^5) [derived the same way].
// calibration: continuum takes M2 as the integral above; discrete takes M2 summed over the
// lattice family, sum_j g |xi|^2 V_j / d (its bulk value per material), which makes the
// discrete operator exact on quadratics: the asymptotically compatible choice
// (docs/models/heat.md, "Quadrature").
//
// thermal.quadrature: improved replaces V_j by per-particle weights omega_ij exact on the
// quadratics over the whole ball (heat.cpp improved_weights; Trask, You, Yu and Parks
// 2019): no longer symmetric, so heat is conserved to the quadrature's error only.
//
// Heat flux (output): q_i = -(1/2) sum_j kbar g (T_j - T_i) xi_ij V_j, which is -k grad T
// for a linear field wherever sum_j g xi xi V_j = M2 I (the calibration above) [derived].
//
// On MPI ranks (parallel/decomposition.hpp) each rank computes the rows of its owned
// particles and HeatSolver::step sends the new temperatures to the ghosts (the backward
// Euler step also each conjugate-gradient search direction); the sums below are grid sums
// over owned particles then, and collective.
#include <memory>
#include <vector>

#include "horizon/state/system.hpp"

namespace horizon {

// M2 = int_H g(|xi|) xi_1^2 dV of the continuum calibration; `measure` is the cross-
// section area (1-D) or the thickness (2-D), unused in 3-D.
double heat_moment_continuum(HeatKernel kernel, int dimension, double horizon, double measure);

// Fills s.heat from the materials' thermal properties and the thermal section: capacity,
// micro-conductivity, initial temperature, boundary conditions (regions of `config`).
// Bonds and particles must exist. build_system calls it when the deck has a thermal section.
// `split` (build_system_split, collective then): the system holds only this rank's rows, so
// the discrete calibration's bulk moment is the largest over ranks; with local particles
// (s.decomposition set with local_particles during the call) the boundary regions' normal
// axes and layer depths are the whole region's.
void setup_heat(System& s, const std::vector<MaterialConfig>& materials, const Config& config, bool split = false);

// out_i = sum_j kbar g (T_j - T_i) V_j over the intact bonds [W/m^3].
void heat_conduction(const System& s, const std::vector<double>& T, std::vector<double>& out);

// The largest stable forward-Euler step: min_i rho c_i / (sum_j kbar g V_j + h_i/d)
// (Gershgorin: the conduction matrix's eigenvalues lie within twice the diagonal).
double heat_stable_step(const System& s);

// Sum of rho c (T - T_ref) V over the body [J].
double heat_content(const System& s);

// s.heat.flux from the current temperature.
void update_heat_flux(System& s);

// The mechanics' thermal strain alpha_i (T_i - T_ref,i) (System::thermal_strain), when some
// material expands; leaves it empty otherwise.
void update_thermal_strain(System& s);

// The rate of the stored energy with the thermal strain, applied to a change `delta`
// (per particle) at the positions and force states of the last force pass (general pass:
// model.force_state): -sum_i V_i sum_j t_ij (delta_ij |xi|) V_j [J], t_ij the scalar force
// state, the gradient of W_i in e_ij for the unified models. The explicit driver books a
// change of the thermal strain as thermal_work by the trapezoidal rule: half at the force
// states before it, half at those after it (exact for their quadratic energies).
double thermal_strain_work(const System& s, const std::vector<double>& delta);

// Heat deposited at particle i [J] (plastic work times beta): raises T_i by E/(rho c V).
void deposit_heat(System& s, std::size_t i, double energy);

// commit_history (state/system.hpp), and with a temperature field the energy the history
// models dissipate in it (Model::commit adds plastic work and viscous loss to
// dissipated_at) raises the temperature: beta_i times it is deposited at particle i
// (Taylor and Quinney's fraction, materials.NAME.thermal.plastic_heat_fraction). The
// heat reaches the mechanics back only through the thermal strain of the unified models
// (docs/models/heat.md, "Coupling").
void commit_history_with_heat(System& s);

// Advances s.heat.T by dt: forward Euler, backward Euler or the steady state at the new
// time (the SPD system solved by a matrix-free Jacobi-preconditioned conjugate gradient
// with exact grid-sum inner products, BiCGSTAB with the improved quadrature's
// non-symmetric rows; the same algorithm and bits serially and on any number of MPI
// ranks: heat.cpp).
// Prescribed temperatures take their value at the new time; the heat each boundary brings
// in is added to its HeatBoundary::heat (temperature conditions: what the conduction
// carries out of their particles plus the change of their own content).
class HeatSolver {
 public:
  HeatSolver(System& s, HeatIntegration integration);
  ~HeatSolver();
  HeatSolver(const HeatSolver&) = delete;
  HeatSolver& operator=(const HeatSolver&) = delete;

  void step(double dt);
  HeatIntegration integration() const { return integration_; }
  // Conjugate-gradient iterations of the last backward-Euler step (0 for forward Euler).
  int iterations() const;
  // The heat the boundaries moved so far, particle by particle in absolute value [J]: the
  // scale of the heat balance where their net is small (a steady solve's inflow and
  // outflow through one boundary).
  double moved() const { return moved_; }

 private:
  struct Implicit;
  void implicit_step(double dt, const std::vector<double>& source, const std::vector<double>& film,
                     const std::vector<double>& film_t);
  System& s_;
  HeatIntegration integration_;
  std::unique_ptr<Implicit> implicit_;
  std::vector<double> rate_, old_;
  double moved_ = 0;
};

// Prescribed temperatures at time t (the run's start, and after each step).
void apply_temperature_conditions(System& s, double t);

// The temperature field at time t without conduction (thermal.conduction: false; the
// static and implicit drivers' load steps): the prescribed temperatures, the ghosts' copies
// and the thermal strain. Collective when decomposed.
void set_temperature_field(System& s, double t);

}  // namespace horizon
