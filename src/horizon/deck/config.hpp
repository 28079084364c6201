#pragma once
// The typed deck: what `horizon run` needs, already validated. Physics code sees only
// these structs, never YAML. Every field is documented in docs/input.md.
#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "horizon/core/expression.hpp"
#include "horizon/core/vec3.hpp"
#include "horizon/family/bonds.hpp"
#include "horizon/family/precrack.hpp"
#include "horizon/geometry/shape.hpp"

namespace horizon {

enum class PlaneMode { none, stress, strain };
// tupek: the normalised (6.6)/(6.7) functions (nonlinear_solid only).
enum class InfluenceKind { constant, inverse, linear, gaussian, tupek };

struct DamageConfig {
  bool enabled = false;
  // Exactly one of the two is set when enabled; fracture_energy is converted to a
  // critical stretch per model and dimension (docs/models.md).
  std::optional<double> critical_stretch;
  std::optional<double> fracture_energy;
  // Compression raises the critical stretch: s0_i = s00 - alpha * (the smallest stretch
  // among i's bonds at the previous force pass), s00 the value above (Silling and Askari
  // 2005, eq. 25; LAMMPS peri/pmb and peri/lps). 0: the plain critical-stretch law.
  double alpha = 0;
  // When a bond whose stretch exceeds s0 stops carrying force: before the forces of
  // that step (false, the default, as Peridigm) or after them (true, as LAMMPS PERI:
  // the bond still acts in the step it breaks). All materials with damage must agree.
  bool break_after_force = false;
  // law: energy (nonlinear_solid only): a pair of bonds breaks when its instantaneous
  // bond energies reach 2 s_c = 2 beta omega/|xi|^2 (thesis eqs. 6.5-6.11), beta from
  // fracture_energy. Broken bonds still push in compression (6.9) unless
  // broken_bonds_compression is false (the Kalthoff variant: off for good).
  bool energy_law = false;
  bool broken_bonds_compression = true;
  // The bond-failure-energy function s_c = beta omega |xi|^-p of the energy law (thesis
  // sec. 6.1.1 calls its form a constitutive choice; eq. 6.3 takes p = 2, a critical bond
  // elongation the same for every bond). p = 0: one critical strain for every bond, as
  // the PMB. beta keeps G_c for any p in [0, 2] (material/models/nonlinear_solid.hpp).
  double failure_length_exponent = 2;
};

struct MaterialConfig {
  std::string name;
  // The registry name of its model (material/registry.cpp; docs/models.md lists them).
  std::string model = "pmb";
  double density = 0;
  // Elastic constants, all filled in from any two given (PMB needs only one).
  double youngs_modulus = 0;
  double poissons_ratio = 0;
  double bulk_modulus = 0;
  double shear_modulus = 0;
  InfluenceKind influence = InfluenceKind::constant;
  DamageConfig damage;
  std::optional<double> micromodulus;  // bond-based models: c given directly [N/m^6]; the moduli follow from it
  // The model's own parameters (ModelTraits::parameters and ::choices, material/model.hpp),
  // every one present: the deck fills in the defaults.
  std::map<std::string, double> parameters;
  std::map<std::string, std::string> choices;
};

struct BodyConfig {
  std::string name;
  std::string material;
  Shape shape;
};

// A polygon (3-D) or a segment (2-D: two points, extruded through the thickness).
using PrecrackConfig = Precrack;

using Vec3Expr = std::array<std::optional<Expression>, 3>;  // unset component = free

struct InitialConditionConfig {
  std::string region;  // empty: every particle
  Vec3Expr velocity;
  Vec3Expr displacement;
};

// force: a total force [N] spread evenly over the region's particles (a point load over a
// patch about one horizon wide, seed 001 digest sec. 4.7); pressure: structures only, a
// load per unit mid-surface area (plates, shells) or per unit length (beams).
enum class LoadKind { traction, body_force, displacement, velocity, force, pressure };

struct LoadConfig {
  LoadKind kind = LoadKind::traction;
  std::string region;  // empty: every particle (body force only)
  Vec3Expr value;      // traction [Pa], body force [N/m^3], displacement [m] or velocity [m/s]
  int normal_axis = -1;  // traction only: 0,1,2 for x,y,z; -1 = detect from the region
};

// explicit: velocity Verlet; static: equilibrium at each load step (Newton or ADR);
// implicit_dynamic: Newmark average acceleration (docs/input.md, solver).
enum class SolverType { explicit_dynamic, static_equilibrium, implicit_dynamic };
enum class StaticMethod { newton, adr };
enum class LinearSolverKind { cg, cholesky, matrix_free };
enum class TangentKind { analytic, finite_difference };

struct SolverConfig {
  double end_time = 0;              // static: the pseudo-time of the last load step (default 1)
  std::optional<double> time_step;  // fixed step; else the stable step times safety_factor
  double safety_factor = 0.8;
  double damping = 0;               // mass-proportional damping rate [1/s], for runs to rest
  // Static and implicit solvers (solver/static_driver.hpp).
  SolverType type = SolverType::explicit_dynamic;
  StaticMethod method = StaticMethod::newton;
  LinearSolverKind linear_solver = LinearSolverKind::cg;
  TangentKind tangent = TangentKind::analytic;
  double tolerance = 1e-6;              // residual norm / applied-load norm at convergence
  std::optional<int> max_iterations;    // per solve; default 30 (Newton) or 100000 (ADR)
  int load_steps = 1;                   // static: equal increments of the pseudo-time
  int max_step_cuts = 6;                // halvings of one increment before giving up
  int max_break_rounds = 100;           // break-and-re-equilibrate rounds per load step
  bool condition_number = false;        // estimate the tangent's condition number
  // Explicit, models with ModelTraits::adaptive_time_step (nonlinear_solid): recompute the
  // stable step from the current bond tangent stiffness every adaptive_every steps.
  bool adaptive_time_step = false;
  int adaptive_every = 5;
};

// How the damage field weighs the bonds: phi_i = 1 - sum(intact) w / sum(all) w with
// w = omega V_j (partial-volume scaled; the default) or w = V_j (whole volumes, as
// LAMMPS's compute damage/atom).
enum class DamageMeasure { weighted, volume };

struct OutputConfig {
  DamageMeasure damage_measure = DamageMeasure::weighted;
  std::string directory = "out";
  int frames = 10;
  int history_every = 10;
  int progress_every = 0;  // plain progress line every N steps when not a terminal; 0 = auto
};

// The partial-volume rule, readable as a boolean (true: any rule but none) so that
// `partial_volume = true` keeps meaning the linear rule.
struct PartialVolume {
  PartialVolumeRule rule = PartialVolumeRule::none;
  PartialVolume() = default;
  PartialVolume(bool on) : rule(on ? PartialVolumeRule::linear : PartialVolumeRule::none) {}  // NOLINT
  PartialVolume(PartialVolumeRule r) : rule(r) {}                                               // NOLINT
  explicit operator bool() const { return rule != PartialVolumeRule::none; }
  bool operator==(const PartialVolume&) const = default;
};

// Short-range repulsion between any two particles closer than
// d_ij = min(reference_fraction |X_j - X_i|, max_distance * spacing): force density on i
// stiffness_factor * c_ij V_j (d_ij - |Y|)/horizon along Y_ji (Silling's EMU manual via
// LAMMPS PERI; c_ij the mean of the two ends' bond-based micromoduli). contact/short_range.hpp.
struct ShortRangeContactConfig {
  bool enabled = false;
  double stiffness_factor = 15;
  double reference_fraction = 0.9;
  double max_distance = 1.35;  // in lattice spacings
};

// A rigid sphere whose centre moves as given: every particle inside it feels the force
// density stiffness (R - r)^2 pointing away from the centre (LAMMPS fix indent).
struct IndenterConfig {
  std::string name;
  Vec3Expr center;  // expressions in t (all three set)
  double radius = 0;
  double stiffness = 0;  // [N/m^5]: force density per m^2 of penetration
};

struct ContactConfig {
  ShortRangeContactConfig short_range;
  std::vector<IndenterConfig> indenters;
};

// Thin structures (seed 001, O'Grady 2014; docs/models/bond_pair.md): a beam is a 1-D line
// of nodes along x, a plate or shell a 2-D lattice in the x-y plane, living in 3-D space.
// beam and plate: only the transverse displacement w = u_z is free (the in-plane
// components follow their constraints, 0 by default; the dissertation's z-only mode);
// shell: all three components.
enum class StructureKind { none, beam, plate, shell };
enum class SupportKind { clamped, simply_supported };

// An edge support (a point of a beam, a line of a plate) at X[axis] = at: the nodes on it
// are held (w = 0), and ghost nodes mirror the body across it over two horizons, with
// the transverse displacement even (clamped) or odd (simply supported) (seed 001 digest
// sec. 4.7 and 6).
struct SupportConfig {
  int axis = 0;
  double at = 0;
  SupportKind kind = SupportKind::clamped;
};

struct StructureConfig {
  StructureKind kind = StructureKind::none;
  std::vector<SupportConfig> supports;
};

struct Config {
  std::string deck_file;
  StructureConfig structure;
  int dimension = 3;
  PlaneMode plane = PlaneMode::none;
  double thickness = 1;    // 2-D only [m]
  double area = 1;         // 1-D only: cross-section [m^2]
  double spacing = 0;
  double horizon = 0;
  std::optional<Vec3> lattice_origin;  // a lattice point; default: cell centres from each body's box
  PartialVolume partial_volume;  // none, linear (true) or lammps; docs/models.md sec. 4
  ContactConfig contact;
  std::vector<MaterialConfig> materials;
  std::vector<BodyConfig> bodies;
  std::vector<PrecrackConfig> precracks;
  std::map<std::string, Shape> regions;
  std::vector<std::string> no_fail_regions;
  std::vector<InitialConditionConfig> initial_conditions;
  std::vector<LoadConfig> loads;
  SolverConfig solver;
  OutputConfig output;
  // Legal but dubious choices found while reading the deck, one line each in the form
  // "file:line:column: warning: ...", for the run to print.
  std::vector<std::string> warnings;
};

}  // namespace horizon
