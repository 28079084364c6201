#pragma once
// The typed deck: what `horizon run` needs, already validated. Physics code sees only
// these structs, never YAML. Every field is documented in docs/input.md.
#include <array>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "horizon/core/expression.hpp"
#include "horizon/core/vec3.hpp"
#include "horizon/family/bonds.hpp"
#include "horizon/family/precrack.hpp"
#include "horizon/geometry/shape.hpp"

namespace horizon {

struct Mesh;  // geometry/mesh.hpp

enum class PlaneMode { none, stress, strain };
// tupek: the normalised (6.6)/(6.7) functions (nonlinear_solid only).
// inverse: delta/|xi| (dimensionless); inverse_length: 1/|xi| [1/m], Peridigm's "1.0/zeta",
// whose weighted volume m is delta times smaller (the forces of the state-based models
// do not change: omega enters them as omega/m).
enum class InfluenceKind { constant, inverse, linear, gaussian, tupek, inverse_length };

struct DamageConfig {
  bool enabled = false;
  // Exactly one of the two is set when enabled; fracture_energy is converted to a
  // critical stretch per model and dimension (docs/models.md).
  std::optional<double> critical_stretch;
  std::optional<double> fracture_energy;
  // critical_stretch written as an expression in t (explicit runs): s0(t), evaluated at
  // each step's new time; critical_stretch holds s0(0).
  std::optional<Expression> critical_stretch_in_time;
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

// A material's thermal properties (docs/input.md, materials.NAME.thermal;
// docs/models/heat.md): present for every material of a run with a thermal section.
struct ThermalMaterialConfig {
  bool enabled = false;
  double conductivity = 0;           // classical conductivity k [W/(m K)]
  double specific_heat = 0;          // c [J/(kg K)]: heat capacity per volume rho c
  double expansion = 0;              // linear thermal expansion coefficient alpha [1/K]
  double reference_temperature = 0;  // T_ref [K]: no thermal strain at T = T_ref
  // reference_temperature: initial -- T_ref,i is particle i's own temperature at t = 0
  // (Peridigm's Temperature_Change = T - T(0), docs/peridigm.md).
  bool reference_initial = false;
  double plastic_heat_fraction = 0;  // Taylor-Quinney beta: share of the dissipated plastic work turned to heat
  // Temperature-dependent critical stretch: s0(T) = s0 max(0, 1 + slope (T - T_ref)) [1/K].
  double critical_stretch_slope = 0;
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
  ThermalMaterialConfig thermal;
  // false: a material of heat alone (materials.NAME without `model`: solver.type heat
  // only; docs/input.md "Materials of heat alone"). Its mechanics are never computed:
  // the model is a placeholder (pmb, E = 1) that the run's set-up wants.
  bool mechanics = true;
};

// How a body is discretised: peridynamic particles on the lattice, or classical finite
// elements on the same lattice's grid (fe/fe_region.hpp; docs/input.md, "Finite-element bodies").
enum class Discretization { peridynamic, fe };
enum class FeElement { hex8, tet4 };

struct BodyConfig {
  std::string name;
  std::string material;
  Shape shape;
  Discretization discretization = Discretization::peridynamic;
  // The body's own horizon delta (a number, or an expression in x, y, z of the reference
  // position): unset, the deck's `horizon`, which bounds it from above (the search
  // radius). Particles of different horizons bond as Peridigm's directed families do
  // (family/neighbors.hpp restrict_to_horizons; docs/input.md "Bodies of different horizons").
  std::optional<Expression> horizon{};
  FeElement element = FeElement::hex8;  // fe only
  double hourglass = 0.1;               // fe hex8 only: hourglass stiffness coefficient kappa
  // fe box bodies only: elements of about this many spacings (nodes on every n-th lattice
  // point; 1: every lattice point). Particles of the overlap band off the nodes follow
  // the element interpolation (fe/fe_region.hpp).
  int fe_element_size = 1;
  // fe only: J2 plasticity of the elements (fe/fe_region.hpp); yield_stress 0: elastic.
  double fe_yield_stress = 0;      // sigma_y [Pa]
  double fe_hardening_modulus = 0; // H [Pa]: sigma_y + H eps_p
  // fe only, a body whose shape is a mesh (shape: {mesh: ...}): the mesh, the cells it
  // takes (all hex8 or all tet4) and the coordinate scale; the mesh's nodes are the FE
  // nodes (fe/fe_region.hpp). Null for a box FE body.
  std::shared_ptr<const Mesh> fe_mesh{};
  std::vector<uint32_t> fe_cells{};
  double fe_mesh_scale = 1;
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
// heat: heat conduction alone (no mechanics; thermal section required).
enum class SolverType { explicit_dynamic, static_equilibrium, implicit_dynamic, heat };
enum class StaticMethod { newton, adr };
enum class LinearSolverKind { cg, cholesky, matrix_free };
enum class TangentKind { analytic, finite_difference };

struct SolverConfig {
  double end_time = 0;              // static: the pseudo-time of the last load step (default 1)
  // Explicit stage of a staged deck (Config::static_stage): the time it starts at, the
  // static stage's end_time; its steps run from there to end_time. 0 otherwise.
  double start_time = 0;
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
  // static: the pseudo-times of the load steps when they are not equal (solver.load_times:
  // 0 = t_0 < t_1 < ... < t_N; then load_steps = N and end_time = t_N). Empty: equal steps.
  std::vector<double> load_times;
  // static: pseudo-times (ends of load steps, inside the path) where a Peridigm deck's next
  // solver list starts (Solver2 after Solver1): the Exodus files write the state there
  // again as that solver's initial output, one more output step (driver/run_implicit.cpp).
  std::vector<double> solver_starts;
  int max_step_cuts = 6;                // halvings of one increment before giving up
  // The static stage of a staged run: on_failure: explicit starts the explicit stage from
  // the last converged state when an increment fails after its cuts (Peridigm's Switch to
  // Verlet), instead of stopping the run.
  bool switch_on_failure = false;
  int max_break_rounds = 100;           // break-and-re-equilibrate rounds per load step
  // implicit_dynamic: initial_acceleration: zero starts Newmark with a_0 = 0 (Peridigm's
  // Implicit solver: Body_Force_Implicit's gold) instead of the equilibrium (f + b)/rho.
  bool zero_initial_acceleration = false;
  // explicit: verlet: peridigm rounds the step as Peridigm's Verlet (ExplicitSolver::
  // set_peridigm_verlet): the importer's choice, so that its decks' golds match bit for bit.
  bool peridigm_verlet = false;
  // static: positions: peridigm forms the force pass's current positions as Peridigm's
  // quasi-static solvers do, y = (X + u_n) + (u - u_n) with u_n the load step's start
  // (System::step_start_u): the importer's choice (Pals_Simple_Shear's gold to the bit).
  bool peridigm_positions = false;
  bool condition_number = false;        // estimate the tangent's condition number
  // Explicit, models with ModelTraits::adaptive_time_step (nonlinear_solid): recompute the
  // stable step from the current bond tangent stiffness every adaptive_every steps.
  bool adaptive_time_step = false;
  int adaptive_every = 5;
  // Explicit and implicit dynamics: a run whose |energy balance error| (relative to the
  // largest energy of the ledger) exceeds this warns in the log and in summary.json.
  double energy_balance_warning = 0.05;
  // Explicit: what takes the steps (solver/backend.hpp, docs/input.md solver.backend): cpu
  // (the solver's own passes), flat (the portable kernels over flat arrays, on the host) or
  // cuda (the same kernels on a GPU, builds with -DHORIZON_CUDA=ON). --backend overrides it.
  std::string backend = "cpu";
  std::string backend_at;  // where it was chosen, for messages: "deck:line:column", "--backend" or ""
};

// How the damage field weighs the bonds: phi_i = 1 - sum(intact) w / sum(all) w with
// w = omega V_j (partial-volume scaled; the default) or w = V_j (whole volumes, as
// LAMMPS's compute damage/atom).
enum class DamageMeasure { weighted, volume };

// One probe of output.history_columns (driver/history_columns.hpp): a quantity of each
// particle, reduced over a body, a region or the whole system (sum, min, max), or read
// at the particle nearest a reference point. Vector quantities give three columns,
// NAMEX, NAMEY, NAMEZ (Peridigm's names for its compute classes' globals).
enum class HistoryQuantity {
  displacement, velocity, force, force_density, position, reference_position, volume, damage,
  kinetic_energy, strain_energy, linear_momentum, angular_momentum
};
enum class HistoryReduce { sum, min, max, nearest };
struct HistoryColumnConfig {
  std::string name;
  HistoryQuantity quantity = HistoryQuantity::displacement;
  std::string field;   // instead of quantity: a scalar output field of the models (von_mises_stress, ...)
  HistoryReduce reduce = HistoryReduce::sum;
  std::string body;    // "" : every body
  std::string region;  // "" : no region filter
  Vec3 at;             // nearest
};

struct OutputConfig {
  std::vector<HistoryColumnConfig> history_columns;
  DamageMeasure damage_measure = DamageMeasure::weighted;
  std::string directory = "out";
  int frames = 10;
  int history_every = 10;
  int progress_every = 0;  // plain progress line every N steps when not a terminal; 0 = auto
  int64_t checkpoint_every = 0;  // output.checkpoint.every: steps between checkpoints; 0 = none
  // output.format: the frames as VTU files (frames/ and frames.pvd), as one Exodus II file
  // with Peridigm's variable names (driver/exodus_output.hpp), `exodus_file` inside the
  // directory, or both.
  enum class Format { vtu, exodus, both } format = Format::vtu;
  bool writes_vtu() const { return format != Format::exodus; }
  bool writes_exodus() const { return format != Format::vtu; }
  std::string exodus_file = "frames.e";
  // output.exodus_files: more Exodus files (the same layout), each with its own schedule:
  // the initial state and every `every` steps (explicit and implicit dynamics: time steps;
  // static: load steps), as Peridigm writes each of its Output lists (docs/input.md).
  struct ExodusFile {
    std::string file;
    int every = 1;
    // More variables than the fixed set (driver/exodus_output.hpp): `Lambda` (element: the
    // plastic multiplier of elastic_plastic), `Deformation_Gradient` (element: XX ... ZZ),
    // or the name of an output.history_columns column (global: its value, vectors X Y Z).
    std::vector<std::string> variables;
    // velocity: verlet (explicit runs): at a prescribed component the file reports the
    // prescribed rate plus dt/2 (f + b)/rho of the step's new forces, the velocity
    // Peridigm's Verlet integrator reports there (its second half-kick is not masked);
    // default (false): the particle's own velocity, the prescribed rate.
    bool verlet_velocity = false;
    // first_step, last_step: the file is written at the steps in [first_step, last_step]
    // that `every` divides (Peridigm's Initial Output Step, Final Output Step); the steps
    // of a staged run count on across its stages (docs/input.md "Solver stages").
    int64_t first_step = 0;
    int64_t last_step = std::numeric_limits<int64_t>::max();
    // explicit_every: the frequency from a staged run's explicit stage on (0: `every`;
    // Peridigm's Switch to Verlet's own Output Frequency).
    int explicit_every = 0;
  };
  std::vector<ExodusFile> exodus_files;
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
// LAMMPS PERI; c_ij the mean of the two ends' bond-based micromoduli). state/short_range.hpp.
//
// law peridigm: Peridigm's "Short Range Force" (its users' guide SAND2012-7800; survey
// sec. 1.4): pairs that were not bonded at the start and are closer than contact_radius
// R_c repel with c V_j (R_c - |Y|)/horizon, c = 9 spring_constant/(pi horizon^4), plus
// the Coulomb friction mu |f_n| against their relative tangential velocity.
// pairs: the bodies that touch (name pairs, either order; a body with itself is its
// self-contact); empty: every pair of particles (Peridigm's General Contact).
// search_radius > 0 (law peridigm; Peridigm's `Search Radius`, `Search Frequency`): the
// candidate pairs are found every search_every steps, within search_radius of each other
// at the positions the step starts from (before its drift), and only they touch until the
// next search (Contact_Ring's gold). 0: Horizon's own lists, which hold every pair.
enum class ShortRangeLaw { lammps, peridigm };
struct ShortRangeContactConfig {
  bool enabled = false;
  ShortRangeLaw law = ShortRangeLaw::lammps;
  double stiffness_factor = 15;
  double reference_fraction = 0.9;
  double max_distance = 1.35;  // in lattice spacings
  double contact_radius = 0;   // peridigm: R_c [m]
  double spring_constant = 0;  // peridigm: k [Pa]
  double friction = 0;         // peridigm: mu
  // peridigm: mu(t) where `friction` is an expression in t (Peridigm's Time Dependent
  // Short Range Force), evaluated at each force pass's time; `friction` is then mu(0).
  std::optional<Expression> friction_in_time;
  std::vector<std::pair<std::string, std::string>> pairs;
  double search_radius = 0;  // peridigm: the candidates' search radius [m]; 0: Horizon's lists
  int search_every = 1;      // peridigm: steps between searches (with search_radius)
};

// A rigid sphere whose centre moves as given: every particle inside it feels the force
// density stiffness (R - r)^2 pointing away from the centre (LAMMPS fix indent).
struct IndenterConfig {
  std::string name;
  Vec3Expr center;  // expressions in t (all three set)
  double radius = 0;
  double stiffness = 0;  // [N/m^5]: force density per m^2 of penetration
};

// The penalty law of a rigid body's contact (contact/rigid_contact.hpp): the force density
// on a particle at penetration depth d is K d (linear, K in N/m^4) or K d^2 (quadratic, the
// indenter's law, K in N/m^5), along the body's outward normal.
enum class ContactLaw { linear, quadratic };

// A rigid shape in its own frame (contact/rigid_contact.hpp): a sphere of `radius` about
// its reference point, or a cylinder of `radius` with a tangent-ogive nose whose tip is the
// reference point, the nose pointing along `axis` (a unit vector), the ogive's arc radius
// crh x 2 radius (the caliber-radius-head), the cylindrical shank `length` long behind it.
enum class RigidShapeKind { sphere, ogive };
struct RigidShapeConfig {
  RigidShapeKind kind = RigidShapeKind::sphere;
  double radius = 0;
  double length = 0;  // ogive: the shank behind the nose [m]
  double crh = 0;     // ogive: arc radius / caliber
  Vec3 axis{0, 0, -1};
};

// A rigid projectile (contact/projectile.hpp): translation only (3 degrees of freedom, no
// spin), integrated by the explicit loop's velocity Verlet; penalty contact with every
// particle (peridynamic particles and finite-element nodes alike).
struct ProjectileConfig {
  std::string name;
  RigidShapeConfig shape;
  double mass = 0;                 // [kg] (from the deck's mass, or density x the shape's volume)
  Vec3 position, velocity;         // initial reference point (sphere centre, ogive tip) and velocity
  ContactLaw law = ContactLaw::linear;
  double stiffness = 0;            // K of the law
  double max_penetration = 0;      // quadratic law: the depth whose stiffness 2 K d the stable step takes (0: spacing)
  double filter_cutoff = 0;        // [Hz] Butterworth low-pass of the acceleration; 0: none
};

struct ContactConfig {
  ShortRangeContactConfig short_range;
  std::vector<IndenterConfig> indenters;
  std::vector<ProjectileConfig> projectiles;
};

// Nonlocal heat conduction (thermal/heat.hpp, docs/models/heat.md).
// kernel: the micro-conductivity's dependence on the bond length, kappa g(|xi|) with
//   inverse  g = 1/|xi| (Bobaru and Duangpanya 2010, Oterkus et al. 2014),
//   constant g = 1       (the kernel of digest 004 sec. 8, C = 3k/delta^3 in 1-D).
// calibration: how kappa is fixed from the classical conductivity k,
//   continuum:  the horizon integral, kappa = 2k / int_H g xi_1^2 dV (piecewise-constant
//               quadrature: not asymptotically compatible, digest 004 sec. 8);
//   discrete:   the same moment summed over the lattice family with its partial volumes,
//               so that the discrete operator is exact on quadratics (asymptotically
//               compatible, Trask, You, Yu and Parks 2019).
enum class HeatKernel { inverse, constant };
enum class HeatCalibration { continuum, discrete };
// steady: each step (solver.type heat) solves the steady state at its end time, the
// conduction, sources and films in balance with the prescribed temperatures (Peridigm's
// ImplicitDiffusion solver, one solve per load step; docs/models/heat.md "Steady solve").
enum class HeatIntegration { explicit_euler, implicit_euler, steady };
// How the bond sum integrates over the horizon (docs/models/heat.md "Improved quadrature"):
//   one_point: each neighbour's volume (partial-volume scaled), the one-point rule;
//   improved:  per-particle weights omega_ij, the smallest change of the one-point weights
//              that makes the sum exact on the polynomials of degree 1 and 2 over the whole
//              ball (the optimisation-based quadrature of Trask, You, Yu and Parks 2019,
//              Comput. Methods Appl. Mech. Engrg. 343:151): a linear field has no flux
//              divergence at any particle, surface ones included.
enum class HeatQuadrature { one_point, improved };
enum class ThermalBoundaryKind { temperature, flux, convection };

struct ThermalBoundaryConfig {
  ThermalBoundaryKind kind = ThermalBoundaryKind::temperature;
  std::string region;   // empty: every particle
  Expression value;     // temperature [K] or flux into the body [W/m^2] (expressions in t, x, y, z)
  double coefficient = 0;  // convection: film coefficient h [W/(m^2 K)]
  Expression ambient;      // convection: ambient temperature [K]
  int normal_axis = -1;    // flux and convection: 0,1,2; -1 = the axis the region is thinnest along
};

struct ThermalConfig {
  bool enabled = false;
  Expression initial_temperature;  // [K], in x, y, z
  HeatKernel kernel = HeatKernel::inverse;
  HeatCalibration calibration = HeatCalibration::continuum;
  HeatIntegration integration = HeatIntegration::explicit_euler;
  HeatQuadrature quadrature = HeatQuadrature::one_point;
  // solver.type heat: the heat step is solver.time_step (default: the explicit stable
  // step times solver.safety_factor; required for implicit). Coupled runs: the heat
  // advances time_scale times the mechanical step per step (1: real time; > 1 accelerates
  // a slow heat transfer for a mechanical response that stays quasi-static).
  double time_scale = 1;
  // false: no conduction; the temperature is a prescribed field (initial_temperature and
  // the boundary's temperature conditions, which may cover the whole body) that strains the
  // mechanics with any solver, static included (docs/input.md, "thermal").
  bool conduction = true;
  std::vector<ThermalBoundaryConfig> boundary;
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
  // Shells: > 0 wraps the 2-D lattice around a cylinder of this radius about the x axis,
  // (x, y) -> (x, R sin(y/R), R cos(y/R)): y is the arc length, and a lattice of
  // 2 pi R / spacing nodes around closes the tube (docs/input.md, structure).
  double cylinder_radius = 0;
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
  // false: no bond joins particles of two bodies (Peridigm's Omit Bonds Between Blocks:
  // All); the bodies meet through contact only.
  bool bonds_between_bodies = true;
  // Set: each family is the box |X_j - X_i| <= family_box per axis (half-widths) instead
  // of the sphere |xi| <= horizon (Peridigm's PdQuickGrid default neighbourhood).
  std::optional<Vec3> family_box;
  std::map<std::string, Shape> regions;
  std::vector<std::string> no_fail_regions;
  std::vector<InitialConditionConfig> initial_conditions;
  std::vector<LoadConfig> loads;
  SolverConfig solver;
  // A staged deck (`solver:` a list of two stages, docs/input.md "Solver stages"): the
  // static solve run first; `solver` is then the explicit run that starts from its last
  // equilibrium at solver.start_time, with the velocity of its last load step.
  std::optional<SolverConfig> static_stage;
  ThermalConfig thermal;
  OutputConfig output;
  // Not a deck key: the memory a run may need [bytes] before build_system refuses it
  // (solver/memory_guard.hpp); 0 means the machine's physical memory. --max-memory sets it.
  double memory_limit_bytes = 0;
  // Legal but dubious choices found while reading the deck, one line each in the form
  // "file:line:column: warning: ...", for the run to print.
  std::vector<std::string> warnings;
};

}  // namespace horizon
