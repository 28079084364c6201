#pragma once
// Classical finite-element regions (linear elastic or J2-plastic 8-node hexahedra with one-point
// integration and hourglass control, or 4-node tetrahedra) advanced by the explicit
// loop together with the peridynamic particles, and their coupling to peridynamic
// bodies (seed 002 digest sec. 7; docs/design.md, "Finite-element regions").
//
// Nodes are particles. An FE body's nodes sit on the lattice of the deck's spacing (the
// cells of the outermost layers stand for the material out to the box faces: their
// volume is scaled, their nodes stay on the lattice), every lattice point
// (element_size 1) or a graded grid (element_size n: every lattice point within a
// horizon of a peridynamic body's index range, grid lines n to 2n - 1 spacings apart
// beyond, so the band is all nodes of unit elements), or they are a mesh's nodes. Where a peridynamic
// body lies inside the FE body its particles are the nodes there. Every degree of
// freedom has one owner:
//   - a particle of a peridynamic body is owned by the peridynamics: its force is the
//     bond sum, over a full family (below);
//   - every other node is owned by the FE: its force is the element assembly, over all
//     the elements around it (elements whose nodes are all particles are left out, so
//     the elements reach to the peridynamic body's outermost particles and carry their
//     displacements).
// The overlap band: the lattice points within a horizon of a peridynamic particle that no
// particle takes complete the particles' families. One at an FE-owned node is that node
// (a "ghost" of the neighbour search); any other one inside an element is an
// interpolated particle, slaved to the element: its displacement and velocity (hence its
// current position) are u = sum_I N_I(X) u_I, v = sum_I N_I(X) v_I at its reference point
// X (trilinear N for hex8, barycentric for tet4), its own bond forces are not integrated
// (force zero, no volume: the elements carry the mass). This is the seed's interpolation
// constraint u_p = N u_h (eq. 46), imposed on the FE side of an overlap of one horizon;
// on the peridynamic side the overlap is the layer of elements that reach the particles
// (their nodes there follow the particles: N = 1 at a node). It is force-based: each
// owner takes its force from its own model only. A linear displacement field gives zero
// force on every owned degree of freedom (the peridynamic family is the complete,
// symmetric lattice family and N reproduces linear fields exactly; an FE-owned node has
// all its elements), so a uniform strain crosses the interface with no spurious force:
// the patch test holds to round-off with coincident, coarser and distorted elements
// (tests/verification/test_fe.cpp, test_fe_interpolation.cpp).
// The price is that the coupling forces derive from no energy: the ledger (each owner's
// energy: the particles' bond energies and the FE-owned nodes' share of the element
// energies) closes only with the coupling's work booked (coupling_work below).
#include <cstdint>
#include <string>
#include <vector>

#include "horizon/core/vec3.hpp"
#include "horizon/state/system.hpp"

namespace horizon {

struct Config;
struct System;
struct Particles;
class StateArchive;

// The force pass, the models and commit_history reach it through FeCoupling
// (state/system.hpp), which holds owned_particle; the rooms above fe/ use it whole.
struct FeRegion : FeCoupling {
  int nodes_per_element = 8;  // 8: hex8, 4: tet4 (one kind per run's FE bodies)
  // Per FE node: its particle, its position (its particle's lattice point), and whether
  // the FE owns it.
  std::vector<uint32_t> node_particle;
  std::vector<Vec3> node_X;
  std::vector<uint8_t> node_owned;
  // Per element: its nodes (nodes_per_element each, FE node ids), volume, Lame constants,
  // shape-function gradients at the centre b_I = dN_I/dx (3 per node), hourglass
  // vectors gamma (hex8: 4 x 8) and hourglass stiffness.
  std::vector<uint32_t> conn;
  std::vector<double> volume, lambda, mu, density, hourglass_k;
  // Per element: the factor on its geometric volume (outermost cells stand for the
  // material out to the box faces; 1 elsewhere).
  std::vector<double> volume_scale;
  std::vector<double> grad;
  std::vector<double> gamma;
  // FeCoupling::owned_particle, per particle: 1 where the FE owns it: an FE-owned node
  // (its force and energy come from the elements) or an interpolated particle (below).
  // Interpolated particles of the overlap band (lattice points within a horizon of a
  // peridynamic particle that lie inside an element but at none of its nodes): per
  // interpolated particle its index, and nodes_per_element (FE node, weight N_I(X)) pairs
  // of the element that holds it. Their displacement and velocity are sum_I N_I u_I,
  // sum_I N_I v_I (interpolate); they have no volume (no mass: the elements carry it)
  // and no force (apply zeroes it); they are the peridynamic particles' neighbours there.
  std::vector<uint32_t> slave_particle;
  std::vector<uint32_t> slave_node;
  std::vector<double> slave_weight;
  // Interface damping (a stabiliser of the force-based coupling): the elements that touch
  // the overlap (a node at a peridynamic particle or within a horizon of one) add a
  // stiffness-proportional (Rayleigh) viscous stress beta_e C : sym(grad v) and hourglass
  // force beta_e k gamma.v, beta_e = 2 interface_damping / omega_e (omega_e the element's
  // largest frequency, stable_time_step): a damping ratio of interface_damping at the
  // element's highest mode, proportionally less below (a pulse of many elements' length
  // is hardly touched). Why: the coupled operator is not symmetric and has complex
  // eigenvalue pairs, slowly growing modes at the interface (tests: FeInterpolation.
  // CoupledOperatorSpectrum); a small viscosity there turns them into decaying ones.
  // Its work is part of coupling_work. Per element: 1 where damped.
  std::vector<uint8_t> damped;
  std::vector<double> damping_beta;  // per element: beta_e [s] (0: undamped)
  double interface_damping = 0.1;
  // Node -> (element, local node) lists, for a race-free assembly.
  std::vector<uint64_t> node_offset;
  std::vector<uint32_t> node_elem;  // element * nodes_per_element + local
  // J2 plasticity (the classical small-strain law of classical/strain_laws.hpp, the one
  // the extended correspondence model uses, with the element's strain eps = sym H as its
  // strain: Simo and Hughes 1998, "Computational Inelasticity", box 3.1-3.2): per element
  // the yield stress (0: linear elastic) and the hardening modulus H of
  // sigma_y + H eps_p. History per element (one integration point: hex8's centre, tet4's
  // only one), kHistory numbers: the plastic strain E_p (3 x 3, column-major) and the
  // equivalent plastic strain eps_p; committed after each step (commit), the trial one
  // written by apply. Empty without plastic elements.
  static constexpr int kHistory = 10;
  std::vector<double> yield_stress, hardening;
  std::vector<double> history, history_trial;
  // Plastic work of the element in the last apply [J] (elements without plasticity: 0).
  std::vector<double> elem_work;
  // Scratch: element nodal forces and energies.
  std::vector<Vec3> elem_force;
  std::vector<double> elem_energy;

  // The coupling's energy account. Force-based coupling derives from no potential: a
  // peridynamic particle's bond to a point on the FE side pushes the particle but not the
  // point, and an element with a node a particle holds pushes its FE-owned nodes but not
  // that one, while the ledger books each owner's energy only. `coupling_work` is the work
  // these interface forces put in since the first force pass with energies, the
  // work-energy account of the parts of the model that hold an interface force:
  //   W_c = W_int + (U + D) - (U + D)_start  over the interface set:
  //   - every peridynamic particle (owned_particle 0): its whole force F = f V (bonds,
  //     contact), its energy W V and its dissipated energy;
  //   - every FE-owned node, with the force, energy share and plastic-work share of its
  //     interface elements only (interface_element: an element with a node a particle
  //     holds, or with interface damping, whose work is the coupling's too);
  //   W_int = sum over steps of 1/2 (F_n + F_n+1) . (u_n+1 - u_n) (the trapezoid, exact for
  //   a quadratic energy).
  // The elements away from the interface derive from their energy and are left out, so
  // their energy and plastic work are checked by the ledger itself, not absorbed here; a
  // run without peridynamic particles (elements alone) has no interface and W_c = 0.
  // U + D is read after the step's commit (close_account, at the end of commit), when the
  // step's plastic work is in D, as the ledger reads it: the plastic dissipation of an
  // element is counted once, in D, and enters W_c only as the change of D that balances
  // the interface elements' force work. Written to history.csv (fe_coupling_work) and
  // summary.json; the ledger counts it (Ledger::coupling_work); checkpointed
  // (checkpoint_account).
  double internal_work = 0;
  double coupling_work = 0;
  double stored_at_start = 0;
  uint8_t account_started = 0;
  std::vector<Vec3> account_F, account_u;
  // Per element: 1 for an interface element (above); per particle: an FE-owned node's
  // force and energy from its interface elements (this pass) and its share of their
  // plastic work (summed since the start). Empty without peridynamic particles.
  std::vector<uint8_t> interface_element;
  std::vector<Vec3> interface_force;
  std::vector<double> interface_energy, interface_dissipated;
  // Whether the run has peridynamic particles (the FE regions have an interface), and a
  // force pass with energies whose account waits for the commit (1: to be closed, 2: the
  // account's start).
  bool coupled() const { return has_peridynamics; }
  bool has_peridynamics = false, interface_marked = false;
  uint8_t account_pending = 0;

  // On MPI ranks (the whole system on every rank, decompose(): parallel/decomposition.hpp)
  // the owner computes: a rank evaluates every element with an FE-owned node it owns
  // (redundantly at the rank boundary, each with the same inputs, so the same bits and the
  // same trial history on every rank that evaluates it), sums each owned node's force over
  // its elements in node_elem order as serially, and interpolates the interpolated
  // particles it owns or its rows read; their elements' nodes are its ghosts (split),
  // and before a force pass their velocities come with the displacements (interpolate:
  // the interface damping reads them). Set by split; empty and false on one process.
  bool split_done = false;
  std::vector<uint32_t> work_elements;  // elements evaluated here, ascending
  std::vector<uint32_t> work_slaves;    // interpolated particles (index into slave_particle) updated here
  // Per element: the particle of its first FE-owned node (conn order), whose owner writes
  // the element's plastic history to a checkpoint (StateArchive::io_listed).
  std::vector<uint32_t> element_keeper;

  std::size_t elements() const { return volume.size(); }
  std::size_t nodes() const { return node_particle.size(); }
  std::size_t owned_nodes() const;
  std::size_t shared_nodes() const { return nodes() - owned_nodes(); }
  std::size_t interpolated() const { return slave_particle.size(); }

  // Sets the interpolated particles' displacement and velocity from the element
  // interpolation u = N u_h (seed 002 digest eq. 46). Called by compute_forces before
  // the bond loops, so their current positions X + u enter the bonds.
  // Decomposed: the ghosts' velocities are received first (collective).
  void interpolate(System& s) override;
  // The elements and interpolated particles this rank updates (above), from its owned
  // particles and the particles its rows read (`ghosts`, one per particle); marks the
  // nodes they read in `ghosts` (those not in `is_owned`). Called once by the ghost choice.
  void split(const std::vector<uint8_t>& is_owned, std::vector<uint8_t>& ghosts);
  // Overwrites the force density and the energy density of every FE-owned particle
  // with the element assembly (F_I / V_I, the FE-owned share of element energies / V_I);
  // an interpolated particle's are set to zero.
  void apply(System& s, bool energy) override;
  // Adds this pass's internal work to the coupling account (above); called by apply.
  void update_coupling_account(System& s, bool energy);
  // After the step's commit: W_c from the interface set's U + D (above), when the last
  // force pass had energies. Collective on ranks (every rank commits).
  void close_account(System& s);
  // Marks the interface elements and whether there are peridynamic particles (once).
  void mark_interface(const System& s);
  // Accepts the trial history of the last apply and adds its plastic work to the ledger
  // (System::dissipated_at): each FE-owned node takes 1/n of its elements' work, as it
  // takes their energy (a node a peridynamic particle holds takes none, as for the energy).
  // Then closes the coupling account (close_account).
  void commit(System& s) override;
  bool plastic() const { return !history.empty(); }
  // The plastic history for checkpoints (per element, from the owner of its keeper
  // particle on ranks: element_keeper).
  void checkpoint(StateArchive& a);
  // The coupling's energy account (above), for checkpoints of every deck with elements.
  void checkpoint_account(StateArchive& a);
  // Equivalent plastic strain per element (0 for elastic elements).
  double plastic_strain(std::size_t e) const { return plastic() ? history[e * kHistory + 9] : 0.0; }
  // Strain energy of all the elements (not only the FE-owned share) [J].
  double element_energy(const System& s) const;
  // Stable step of the elements with lumped mass (Flanagan and Belytschko 1981, sec. 7:
  // omega_max^2 <= 8 (lambda + 2 mu) b_iI b_iI / (rho V^2) for the one-point hexahedron,
  // here with b = V dN/dx; the hourglass stiffness added; the same bound for tet4 with
  // 4 nodes). Returns +inf without elements.
  double stable_time_step() const;
  // The element's largest frequency without hourglass control (the bound of
  // stable_time_step's linear part), for the interface damping [rad/s].
  double element_omega(std::size_t e) const;
  // Precomputes gradients, volumes and hourglass vectors from node_X and conn.
  void setup_geometry();
};

// Builds the FE regions of the deck's FE bodies into s (after the peridynamic bodies'
// particles exist): nodes on the lattice, carved where peridynamic particles are; new
// particles for the FE-owned nodes with their lumped volume. Sets block names.
// `ghost` (out, one per particle) marks the FE-owned nodes within `radius` of a
// peridynamic particle: the ones the neighbour search must see.
void build_fe_regions(System& s, const Config& config, double radius, std::vector<uint8_t>& ghost);

}  // namespace horizon
