#pragma once
// A material model as one unit (docs/design.md, "Adding a material model").
//
// A model is a header and a source file under material/models/, and one line of
// material/registry.cpp. It declares what the deck may say about it (ModelTraits: its
// parameters with their ranges and defaults, the damage laws and influence functions it
// accepts), and it computes, for the particles of its material:
//   - setup: per-particle constants into the shared arrays of ModelCoefficients (the
//     bond-based spring of the stable time step, the contact micromodulus, the critical
//     stretch of the damage law) and its own state, sized;
//   - force_state: the force state T[x_i]<xi_ij> of every bond of its particles (and the
//     strain energy density W_i when asked), from the current positions and its
//     *committed* history; the trial history goes to its own scratch;
//   - commit: the trial history becomes the history (explicit dynamics: every step;
//     static and implicit solvers: every converged step; never while a tangent is
//     probed), and the energy it dissipated goes to the ledger;
//   - fields: what it adds to the output frames (plastic strain, damage of its own...).
// The general force pass (solver/forces_general.cpp) breaks bonds by the critical-stretch
// law, calls force_state of every model, and sums f_i = sum_j (T_ij - T_ji) V_j
// (seed 003 eq. 33 in its discrete form, digest sec. 9) with the contact: it never names
// a model.
//
// Two capabilities keep the old fast paths behind the same interface:
//   - unified(): the model writes its forces in the form t = omega (P_i |xi| + Q_i e +
//     R_i e/|xi|) of state/system.hpp (PMB, LPS). When every material of a run is
//     unified, compute_forces runs the vectorised loops of solver/forces.cpp and the
//     static solvers have an analytic tangent.
//   - owns_force_pass(): the model computes the whole force pass itself and shares a run
//     only with materials of its own model (Tupek's nonlinear solid, whose energy failure
//     law couples the two ends of a bond).
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "horizon/core/point4.hpp"
#include "horizon/core/state_archive.hpp"
#include "horizon/core/vec3.hpp"
#include "horizon/deck/config.hpp"
#include "horizon/material/constants.hpp"

namespace horizon {

struct System;

// One number (or yes/no) a model reads from its material's map in the deck.
struct ParameterSpec {
  enum class Range { any, positive, non_negative, fraction, boolean };  // fraction: [0, 1]
  std::string key;
  std::string meaning;  // "yield stress [Pa]": for messages and docs/models.md
  Range range = Range::positive;
  std::optional<double> default_value;  // none: the key is required
};

// One word a model reads (e.g. the classical stress law of the correspondence model).
struct ChoiceSpec {
  std::string key;
  std::string meaning;
  std::vector<std::string> choices;  // the first is the default
};

enum class ElasticInput {
  one_modulus,   // bond-based: one modulus (or micromodulus); Poisson's ratio fixed by the dimension
  two_constants  // any two of E, nu, K, G
};

struct ModelTraits {
  std::string name;                  // the word after `model:` in the deck
  std::vector<std::string> aliases;  // other words accepted for it
  std::string summary;               // one line: what it is and its source
  ElasticInput elastic = ElasticInput::two_constants;
  int min_dimension = 1;             // 2: 2-D and 3-D only
  bool critical_stretch_law = true;  // damage: {law: critical_stretch, ...} (critical_stretch or fracture_energy)
  bool energy_law = false;           // damage: {law: energy, ...} (Tupek's nonlinear solid)
  bool exclusive = false;            // shares a run only with materials of the same model
  bool adaptive_time_step = false;   // solver.adaptive_time_step applies (stable_time_step from the current state)
  // The model subtracts System::thermal_strain from its bond extensions (thermal expansion,
  // docs/models/heat.md): materials.NAME.thermal.expansion is allowed. The unified models
  // take it in the general force pass; a model with its own force_state takes it there.
  bool thermal_strain = false;
  // The material's constants do not scale with its horizon (lps: m_i is each particle's
  // own; correspondence: only its stabilisation modulus reads it), so its particles may
  // have several (bodies of different horizons; solver/build.cpp material_horizon).
  bool any_horizon = false;
  bool structural = false;           // models the nodes of a beam, plate or shell (deck structure: ...), not a solid
  // The force state of particle i's bonds reads only the current positions of i's family,
  // i's own history and the shared per-particle constants (no other particle's state of
  // the same pass), and force_state and commit skip the rows with !System::computes_row(i).
  // Then a run split over MPI ranks computes the rows of its particles' bond neighbours
  // too (their T_ji enter f_i), from the positions one horizon further out, and each rank
  // keeps their history itself: no model state crosses ranks (parallel/decomposition.hpp).
  // A model that owns the force pass (exclusive) sets it to say that its pass splits
  // itself over ranks (docs/design.md, "A model that owns its force pass").
  bool rows_local = false;
  // The model writes its forces in the unified form t = omega (P_i |xi| + Q_i e + R_i e/|xi|)
  // of state/system.hpp (Model::unified, above): the fast loops, the analytic tangent, and
  // a run split over MPI ranks without any model code.
  bool unified = false;
  // The model's force states lie along their bonds, T = t Y/|Y| (ordinary state-based and
  // bond-based models), it sets rows_local, and it implements begin_rows and force_row
  // (below): the general pass then runs in its scalar form (solver/forces_ordinary.cpp),
  // with the breaking, the model's row and the sum of the forces fused per row.
  bool ordinary = false;
  // The model's force states are affine in the bond, T_ij = omega_ij (M_i xi_ij + g_i Y_ij)
  // with a 3 x 3 M_i and a scalar g_i per particle (the correspondence model with its
  // stabilisation, kernels/affine.hpp), it sets rows_local, and it
  // implements affine_row (below): when every model of a run is such, the general pass
  // keeps one record per particle instead of a force state per bond and sums the pair form
  // f_i = sum_j omega V_j ((M_i + M_j) xi + (g_i + g_j) Y) (solver/forces_affine.cpp).
  bool affine = false;
  std::vector<InfluenceKind> influences{InfluenceKind::constant, InfluenceKind::inverse, InfluenceKind::linear,
                                        InfluenceKind::gaussian, InfluenceKind::inverse_length};
  InfluenceKind default_influence = InfluenceKind::constant;
  std::vector<ParameterSpec> parameters;
  std::vector<ChoiceSpec> choices;
};

// What a model's setup is given.
struct ModelSetup {
  System& system;
  const Config& config;
  const MaterialConfig& material;
  int material_index = 0;
  std::vector<uint32_t> particles;  // the particles of this material, in index order
  Dimensioning dims;
};

// One evaluation of the general force pass, as a model sees it.
struct ForcePass {
  const System& system;
  const Point4* y = nullptr;   // current positions (w: scratch of the pass, not for models)
  Vec3* T = nullptr;           // per bond k (i -> j): the force state T[x_i]<xi_ij> [N/m^6]; write
                               // it for every bond of your particles (zero for broken bonds)
  double* energy = nullptr;    // per particle: W_i [J/m^3]; null when not asked
  double time = 0;             // the time of this deformation
  double dt = 0;               // time since the committed state (viscous and rate laws)
};

// One evaluation of the scalar general pass (ModelTraits::ordinary), as a model sees it.
// The pass visits each row once: it breaks the row's bonds, then asks the row's model for
// its scalar force states (force_row), then sums the forces of the row's bonds once every
// row has its force states.
struct RowPass {
  const System& system;
  const Point4* y = nullptr;         // current positions (w: scratch of the pass, not for models)
  const double* deformed = nullptr;  // per bond k: |Y_k| (every bond, acting or not)
  double* t = nullptr;               // per bond k: q = t/|Y| (T = q Y); write this pass's for every
                                     // bond of the row (0 for a bond that does not act). On entry
                                     // the previous pass's q, except for a bond that this pass's
                                     // breaking sweep broke: there the previous pass's t (what the
                                     // sweep booked as dissipated, history_ledger.hpp)
  double* energy = nullptr;          // per particle: W_i [J/m^3]; null when not asked
  double time = 0;                   // the time of this deformation
  double dt = 0;                     // time since the committed state
  const Point4* kinds = nullptr;     // per bond kind {|xi|, omega, omega V_j, V_j} (System::model.kind_rows)
  // Per bond k of the row (valid for the row's bonds only): |Y| of the previous pass, as the
  // breaking sweep found it before writing this pass's; null when the pass does not keep it
  // (history_ledger.hpp LedgerMode: the ledger's committed t and e rebuilt from it).
  const double* r_old = nullptr;
};

// One evaluation of the affine general pass (ModelTraits::affine), as a model sees it: for
// each row i the pass breaks i's bonds, then asks i's model for i's record.
struct AffineRowPass {
  const System& system;
  const Point4* y = nullptr;  // current positions (w: scratch of the pass, not for models)
  double* record = nullptr;   // per particle, kernels::kAffineRecord numbers {M_i row by row, g_i}
  double* energy = nullptr;   // per particle: W_i [J/m^3]; null when not asked
  double time = 0;            // the time of this deformation
  double dt = 0;              // time since the committed state
};

// A per-particle output field (a model's history variable in the frames).
struct ModelField {
  std::string name;
  std::vector<double> values;  // one per particle; models fill their own, others stay 0
  // A density of dissipated energy [J/m^3] (plastic work, failure energy, ...): the summary
  // integrates it over the volume into energy.dissipated_parts.
  bool dissipation_part = false;
};

// Where a model that owns its force pass writes its tangent stiffness K = -dF/du (F the
// nodal forces [N], u the displacements [m]) on a solver's unknowns (Model::stiffness).
// Entries of one (row, column) may repeat: they are summed.
struct StiffnessEntry {
  int32_t row, col;
  double value;
};
struct StiffnessSink {
  const int32_t* dof = nullptr;  // 3 per particle: the unknown of component c, or -1 (prescribed, inactive)
  std::vector<StiffnessEntry> entries;
  // K(particle i component ci, particle j component cj) += v, when both are unknowns.
  void add(uint32_t i, int ci, uint32_t j, int cj, double v) {
    const int32_t r = dof[3 * static_cast<std::size_t>(i) + static_cast<std::size_t>(ci)];
    const int32_t c = dof[3 * static_cast<std::size_t>(j) + static_cast<std::size_t>(cj)];
    if (r >= 0 && c >= 0 && v != 0) entries.push_back({r, c, v});
  }
};

class Model {
 public:
  virtual ~Model() = default;
  virtual std::unique_ptr<Model> clone() const = 0;
  virtual const ModelTraits& traits() const = 0;

  // Once, after the bonds, the influence weights and the weighted volumes exist.
  virtual void setup(const ModelSetup& setup) = 0;

  // The fast path (see above; ModelTraits::unified). A unified model's setup fills
  // pair_coef, dilatation_coef, deviatoric_coef (and sets state_based when it uses the
  // dilatation).
  bool unified() const { return traits().unified; }

  // General path: T of every bond of this model's particles; W_i when pass.energy is set.
  virtual void force_state(ForcePass& pass) { (void)pass; }

  // Scalar general pass (ModelTraits::ordinary): once per pass before any row (one thread;
  // sizing, per-pass constants), then for each row i of the model's particles that this
  // process computes, on the thread that broke the row's bonds just before: the scalar
  // force states t of i's bonds (RowPass::t) and W_i. `dilatation_sum` is
  // sum_j omega V_j |xi| e over i's acting bonds, e the mechanical extension
  // |Y| - |xi| - eps_ij |xi| (theta_i = d sum / m_i, seed 003 eq. 113), computed as the
  // general pass's force_state models compute it, bit for bit.
  virtual void begin_rows(const RowPass& pass) { (void)pass; }
  virtual void force_row(const RowPass& pass, std::size_t i, double dilatation_sum) {
    (void)pass, (void)i, (void)dilatation_sum;
  }

  // Affine general pass (ModelTraits::affine): for each row i of the model's particles that
  // this process computes, on the thread that broke i's bonds just before, i's record (and
  // W_i when pass.energy is set) from `sums`, what the breaking sweep summed over i's acting
  // bonds: K_i = sum_j omega V_j xi (x) xi, then sum_j omega V_j Y (x) xi, row-major
  // (kernels/affine.hpp GradientSums). Rows run in any order.
  virtual void affine_row(const AffineRowPass& pass, std::size_t i, const double* sums) {
    (void)pass, (void)i, (void)sums;
  }

  // The pair form of the general pass (issue 31 scope 2; the extended correspondence
  // model): when the run's only model says yes here (its particles are all of the run's,
  // and its settings have a pair form), general_forces hands it the whole material pass:
  // the critical-stretch breaking of its rows with their damage bookkeeping, its force
  // states, and f_i = sum_j (T_ij - T_ji) V_j with the family contact, over the rows of
  // System::active_rows (all rows when empty) as the general pass does; the solver adds
  // the other contact. It returns the directed bonds broken. The vector form
  // (force_state) stays the reference (set_general_reference(true)).
  virtual bool takes_pair_pass(const System& s) const {
    (void)s;
    return false;
  }
  virtual uint64_t pair_forces(System& s, bool energy) {
    (void)s, (void)energy;
    return 0;
  }

  // The trial history of the last force pass becomes the history. Energy the model
  // dissipated since the last commit (plastic work, viscous loss) is added to
  // system.dissipated_at [J] of its particles.
  virtual void commit(System& system) { (void)system; }

  // The energy commit() would add to the ledger now [J]: what the model dissipated since
  // the last commit, at the state of the last force pass (a static solver subtracts its
  // change between re-equilibration rounds, so that the work is not also counted as
  // released energy).
  virtual double pending_dissipation(const System& system) const {
    (void)system;
    return 0;
  }

  // Hold (true) or release the model's own bond breaking while a solver iterates
  // (the critical-stretch law is held by the solvers themselves).
  virtual void hold_bonds(bool hold) { (void)hold; }

  // Models that own the force pass (see above).
  virtual bool owns_force_pass() const { return false; }
  // Failures a model records outside the bond rows (a structure's failed pairs), those
  // this process keeps (on MPI ranks each failure is kept by one rank): the whole
  // system's broken count on ranks is the bond rows' breaks plus these, summed over the
  // ranks (parallel/decomposition.cpp gather_state).
  virtual uint64_t failures_kept(const System& system) const {
    (void)system;
    return 0;
  }
  virtual uint64_t force_pass(System& system, bool energy) {
    (void)system, (void)energy;
    return 0;
  }
  // The analytic tangent stiffness of a model that owns the force pass, or of a general-pass
  // model that holds every particle (correspondence; solver/tangent.hpp model_tangent), at
  // the current displacements with the bonds held as they are: true when written to `out`,
  // false when the model has none (the static solvers then take finite differences).
  virtual bool stiffness(const System& system, StiffnessSink& out) const {
    (void)system, (void)out;
    return false;
  }
  // A thin structure's supports (deck structure.supports, in order): the part of each
  // support's reaction [N] that the model's own off-body nodes carry at the state of the
  // last force pass (the ghost nodes that mirror the body across a support: their forces
  // act on no particle, so the support takes them). Loads adds it to the reactions of
  // the nodes on the support line. False (and `out` untouched) for a model without.
  virtual bool support_reactions(const System& system, std::vector<Vec3>& out) const {
    (void)system, (void)out;
    return false;
  }
  // A stable time step from the current state, or 0 to use the Silling-Askari bound of
  // the shared spring coefficients.
  virtual double stable_time_step(const System& system) const {
    (void)system;
    return 0;
  }
  // The current state's stiffening of a model that shares the Silling-Askari bound
  // (solver/build.cpp stable_time_step, with solver.adaptive_time_step): for each of the
  // model's particles i, the factor g_i on its shared spring (ModelCoefficients::spring)
  // in the bound's bond sum; `g` holds one entry per particle of the system, 1 on entry.
  // False (g untouched) for a model whose stiffness the reference spring holds.
  virtual bool spring_factors(const System& system, std::vector<double>& g) const {
    (void)system, (void)g;
    return false;
  }

  // Checkpoint and restart (output/checkpoint.hpp): the model lists, with a.io(name, x),
  // every array and number of its state that a run changes (committed and trial history,
  // its ledger, caches whose content decides later results), in a fixed order; the same
  // call saves and loads. Constants that setup computes from the deck are left out: a
  // restart builds them again. A model without such state keeps the default.
  virtual void checkpoint(StateArchive& a) { (void)a; }

  // Output fields (names stable: users post-process them).
  virtual void fields(const System& system, std::vector<ModelField>& out) const { (void)system, (void)out; }

  // Values of the deck (MaterialConfig::parameters, with defaults filled in by the deck).
  static double parameter(const MaterialConfig& m, const std::string& key);
  static const std::string& choice(const MaterialConfig& m, const std::string& key);
};

// The shared coefficients of a state-based model calibrated like the LPS, for the
// particles of `in`: the spring of the stable time step (the bond-based equivalent of the
// same bulk modulus, times spring_factor for models stiffer than that), the contact
// micromodulus (omega = 1, as LAMMPS peri/lps), the critical stretch (given, or from
// fracture_energy by the LPS formula of material/constants.hpp) and its compression
// factor; it refuses a particle without neighbours (unless `isolated_allowed`: a model
// whose row of no bonds has no force and dilatation 0, the LPS) and marks the run
// state-based (the tangent probes two horizons out).
void fill_state_based_coefficients(const ModelSetup& in, double spring_factor = 1.0, bool isolated_allowed = false);

// The registry: one entry per model (material/registry.cpp).
struct ModelEntry {
  ModelTraits traits;
  std::unique_ptr<Model> (*make)();
};
const std::vector<ModelEntry>& model_registry();
// The entry whose name or alias is `name`, or null.
const ModelEntry* find_model(const std::string& name);
// The registered names, in registry order (for messages).
std::vector<std::string> model_names();
// The registry as text for `horizon models`: each model, its summary, what it accepts
// and its own deck parameters with their meaning and default.
std::string describe_models();
// Fills in the defaults of every declared parameter and choice the material lacks (a
// material built in code, as the tests do; the deck does it while reading).
void fill_model_defaults(MaterialConfig& m);

// The models' trial history of the last force pass becomes their history, and so does
// the finite-element regions' (System::fe_coupling): explicit solvers after every step,
// static ones after each converged step.
void commit_history(System& s);

}  // namespace horizon
