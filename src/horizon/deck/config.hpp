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
#include "horizon/family/precrack.hpp"
#include "horizon/geometry/shape.hpp"

namespace horizon {

enum class PlaneMode { none, stress, strain };
enum class ModelKind { pmb, lps };
enum class InfluenceKind { constant, inverse, linear, gaussian };

struct DamageConfig {
  bool enabled = false;
  // Exactly one of the two is set when enabled; fracture_energy is converted to a
  // critical stretch per model and dimension (docs/models.md).
  std::optional<double> critical_stretch;
  std::optional<double> fracture_energy;
};

struct MaterialConfig {
  std::string name;
  ModelKind model = ModelKind::pmb;
  double density = 0;
  // Elastic constants, all filled in from any two given (PMB needs only one).
  double youngs_modulus = 0;
  double poissons_ratio = 0;
  double bulk_modulus = 0;
  double shear_modulus = 0;
  InfluenceKind influence = InfluenceKind::constant;
  DamageConfig damage;
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

enum class LoadKind { traction, body_force, displacement, velocity };

struct LoadConfig {
  LoadKind kind = LoadKind::traction;
  std::string region;  // empty: every particle (body force only)
  Vec3Expr value;      // traction [Pa], body force [N/m^3], displacement [m] or velocity [m/s]
  int normal_axis = -1;  // traction only: 0,1,2 for x,y,z; -1 = detect from the region
};

struct SolverConfig {
  double end_time = 0;
  std::optional<double> time_step;  // fixed step; else the stable step times safety_factor
  double safety_factor = 0.8;
  double damping = 0;               // mass-proportional damping rate [1/s], for runs to rest
};

struct OutputConfig {
  std::string directory = "out";
  int frames = 10;
  int history_every = 10;
  int progress_every = 0;  // plain progress line every N steps when not a terminal; 0 = auto
};

struct Config {
  std::string deck_file;
  int dimension = 3;
  PlaneMode plane = PlaneMode::none;
  double thickness = 1;    // 2-D only [m]
  double area = 1;         // 1-D only: cross-section [m^2]
  double spacing = 0;
  double horizon = 0;
  std::optional<Vec3> lattice_origin;  // a lattice point; default: cell centres from each body's box
  bool partial_volume = false;
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
