#pragma once
// A run's frames as one Exodus II file with Peridigm's variable names (output.format:
// exodus; docs/input.md, docs/peridigm.md), so that a Peridigm user's scripts, exodiff and
// ParaView read Horizon's output as they read Peridigm's:
//   nodal    DisplacementX/Y/Z, VelocityX/Y/Z, Force_DensityX/Y/Z, ForceX/Y/Z (= force
//            density x volume, as Peridigm's Force), AccelerationX/Y/Z ((f + b) / rho),
//            External_Force_DensityX/Y/Z (b: body forces and tractions); with a
//            thermal section Temperature and Temperature_Change (T - T_ref);
//   element  Element_Id (the particle's 1-based id), Block_Id, Volume, Damage, Dilatation,
//            Weighted_Volume, Number_Of_Neighbors (its family's bonds),
//            Stored_Elastic_Energy_Density (the strain energy density W, as of the last
//            force pass that computed it: history rows and frames), Stored_Elastic_Energy (W V),
//            Radius (of the sphere of the particle's volume);
//   global   Global_Kinetic_Energy (sum of rho V |v|^2 / 2); static and implicit runs also
//            Nonlinear_Solver_Iterations (Newton's iterations of the step).
// A file with `velocity: verlet` reports at prescribed components v + dt/2 (f + b)/rho
// (Peridigm's Verlet; set_verlet).
// A file's `variables` (output.exodus_files) add (element variables after the fixed set,
// Lambda first; globals in the order given):
//   Lambda                element: the plastic multiplier of elastic_plastic (its field
//                         plastic_multiplier; 0 at particles of other models);
//   Deformation_Gradient  element Deformation_GradientXX, XY, XZ, YX, ..., ZZ: the nonlocal
//                         deformation gradient F_i = (sum_j omega V_j Y (x) xi) K_i^-1 over the
//                         intact bonds (Silling et al. 2007, seed 003 eq. 17 and 134;
//                         material/nonlocal_gradient.hpp), exact for a homogeneous deformation;
//   a history column's name  global: its value (vectors NAMEX, NAMEY, NAMEZ), as in history.csv
//                         but at full precision: Peridigm's compute classes' Output Labels.
//   Flux_Divergence       nodal, after Temperature_Change (runs with a thermal section):
//                         the conduction's sum_j kbar g (T_j - T_i) V_j [W/m^3]
//                         (thermal/heat.hpp heat_conduction), 0 without conduction.
//   Contact_Force_Density nodal Contact_Force_DensityX, Y, Z (after the fixed set): the
//                         short-range contact's force density of the last force pass
//                         (friction included; state/short_range.hpp record_forces), 0
//                         where no pair touches.
// On several MPI ranks every particle is streamed to rank 0 in global order
// (parallel/lead_view.hpp stream_on_lead), which alone writes: the same file, byte for
// byte, as one rank.
#include <cstdint>
#include <limits>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "horizon/core/vec3.hpp"
#include "horizon/deck/config.hpp"

namespace horizon {

struct System;
struct Decomposition;
class ExodusWriter;
class Loads;

// Whether `name` is one of Peridigm's variables written from the models' fields:
// Hourglass_Force_Density (nodal X Y Z: correspondence's Peridigm hourglass force),
// Left_Stretch_Tensor, Rotation_Tensor, Shape_Tensor_Inverse,
// Unrotated_Rate_Of_Deformation, Cauchy_Stress, Unrotated_Cauchy_Stress (element XX ... ZZ:
// correspondence's hypoelastic laws), Von_Mises_Stress, Equivalent_Plastic_Strain
// (element); 0 at particles whose model has no such field.
bool exodus_field_variable(const std::string& name);

class ExodusOutput {
 public:
  // `iterations`: the file also has the global Nonlinear_Solver_Iterations (static and
  // implicit runs: Newton's iterations of the last step, set_iterations; 0 at t = 0).
  explicit ExodusOutput(std::string path, bool iterations = false);
  // With a file's `variables` (above); `config` gives the history columns they name.
  ExodusOutput(std::string path, bool iterations, const std::vector<std::string>& variables, const Config& config,
               bool verlet_velocity = false);
  void set_iterations(int n);
  ~ExodusOutput();
  // Collective: appends the system's state at `time` as the next time step (the file is
  // created with the first). Throws OutputError on the writing rank.
  void write(const System& s, const Decomposition* d, double time);
  const std::string& path() const { return path_; }
  // Whether the file has Contact_Force_Density (the contact keeps its forces for it).
  bool contact_forces() const { return contact_; }
  // Static solves: the velocities the next write reports, (u - u_before) / dt per held
  // particle -- the last load step's displacement increment over its pseudo-time
  // increment, what Peridigm's QuasiStatic solver reports as the velocity.
  void set_step_velocity(const std::vector<Vec3>& u, const std::vector<Vec3>& u_before, double dt);
  // Explicit runs: the constraints and the step of the next write, for `velocity: verlet`
  // files (deck/config.hpp ExodusFile); dt = 0 (the initial state) adds nothing.
  void set_verlet(const Loads* loads, double dt) { loads_ = loads, verlet_dt_ = dt; }

 private:
  void append(const System& s, const std::vector<std::vector<double>>& rows, const std::vector<double>& globals,
              double time);
  std::string path_;
  std::unique_ptr<ExodusWriter> writer_;
  std::vector<Vec3> velocity_;  // set_step_velocity's, else empty (the particles' own)
  std::optional<int> iterations_;  // Nonlinear_Solver_Iterations, when the file has it
  bool lambda_ = false, gradient_ = false, horizon_ = false;  // the element variables asked for
  // Models' fields asked for (exodus_field_variable): (Exodus name, field name) per column.
  std::vector<std::pair<std::string, std::string>> nodal_fields_, element_fields_;
  bool contact_ = false;                     // Contact_Force_Density (nodal)
  bool flux_divergence_ = false;             // Flux_Divergence (nodal, after Temperature_Change)
  // Horizon: each particle's (its body's own, BodyConfig::horizon, else the deck's).
  std::vector<std::optional<Expression>> body_horizon_;
  double deck_horizon_ = 0;
  bool verlet_ = false;                      // velocity: verlet
  const Loads* loads_ = nullptr;
  double verlet_dt_ = 0;
  Config columns_;  // the history columns written as globals (with the regions they read)
};

// output.exodus_files: Exodus files on their own schedules, each written at step 0 (the
// initial state) and at every step that its `every` divides, within its first_step and
// last_step -- Peridigm's rule for each of its Output lists (Output Frequency, Initial and
// Final Output Step). Static runs count load steps; a staged run counts on across its
// stages (driver/static_stage.cpp).
class ExodusSchedule {
 public:
  ExodusSchedule(const std::vector<OutputConfig::ExodusFile>& files, const std::filesystem::path& dir,
                 bool iterations, const Config& config);
  void set_iterations(int n);
  bool empty() const { return files_.empty(); }
  bool due(int64_t step) const;
  // Before the first force pass: the contact keeps its per-particle forces where a file
  // writes Contact_Force_Density (ShortRangeContact::record_forces).
  void prepare(System& s) const;
  // Collective: the files due at `step` get the state at `time`.
  void write(const System& s, const Decomposition* d, double time, int64_t step);
  // Static solves: as ExodusOutput::set_step_velocity, for every file.
  void set_step_velocity(const std::vector<Vec3>& u, const std::vector<Vec3>& u_before, double dt);
  // As ExodusOutput::set_verlet, for every file.
  void set_verlet(const Loads* loads, double dt);
  // A staged run's explicit stage starts at this step: from it on a file's explicit_every
  // (deck/config.hpp ExodusFile) replaces its every.
  void set_explicit_from(int64_t step) { explicit_from_ = step; }

 private:
  bool due_file(std::size_t k, int64_t step) const;
  std::vector<std::unique_ptr<ExodusOutput>> files_;
  std::vector<int64_t> every_;
  std::vector<std::pair<int64_t, int64_t>> range_;  // first_step, last_step
  std::vector<int64_t> explicit_every_;             // 0: every_
  int64_t explicit_from_ = std::numeric_limits<int64_t>::max();
};

}  // namespace horizon
