#include "horizon/driver/exodus_output.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <numbers>

#include "horizon/core/error.hpp"
#include "horizon/driver/history_columns.hpp"
#include "horizon/loading/loads.hpp"
#include "horizon/material/model.hpp"
#include "horizon/material/nonlocal_gradient.hpp"

#include "horizon/output/exodus.hpp"
#include "horizon/parallel/decomposition.hpp"
#include "horizon/parallel/lead_view.hpp"
#include "horizon/state/system.hpp"
#include "horizon/thermal/heat.hpp"

namespace horizon {

namespace {

// Per particle: X, u, v, f (3 each), volume, density, damage, theta, m, block, neighbours,
// then the external force density b (3) and the strain energy density W.
constexpr int kWidth = 23;

// Peridigm's block id of a body named block_<id>; otherwise its position + 1.
int block_id(const std::vector<std::string>& names, int index) {
  if (index >= 0 && static_cast<std::size_t>(index) < names.size()) {
    const std::string& n = names[static_cast<std::size_t>(index)];
    if (n.rfind("block_", 0) == 0) {
      char* end = nullptr;
      const long id = std::strtol(n.c_str() + 6, &end, 10);
      if (*end == '\0' && id > 0) return static_cast<int>(id);
    }
  }
  return index + 1;
}

// The nonlocal deformation gradient of particle i over its intact bonds, row by row
// (material/nonlocal_gradient.hpp; the identity where the shape tensor is singular).
std::array<double, 9> deformation_gradient(const System& s, std::size_t i) {
  const Particles& P = s.particles;
  const Bonds& B = s.bonds;
  NonlocalGradient g;
  if (i + 1 < B.offset.size())
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
      if (!B.intact[k]) continue;
      const uint32_t j = B.nbr[k];
      g.add(P.X[j] - P.X[i], (P.X[j] + P.u[j]) - (P.X[i] + P.u[i]), B.weight[k] * B.volume[k]);
    }
  NonlocalGradient::Mat3 Kinv, F;
  g.finish(s.dimension, 1e-12, Kinv, F);
  std::array<double, 9> out{};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) out[static_cast<std::size_t>(3 * r + c)] = F(r, c);
  return out;
}

// Peridigm's variables that are models' fields (exodus_output.hpp): its name, whether it
// is nodal, and the fields' name stem; tensors take 9 components, vectors 3.
struct FieldVariable {
  const char* name;
  bool nodal;
  int components;  // 1, 3 (X Y Z) or 9 (XX XY ... ZZ)
  const char* field;
};
constexpr FieldVariable kFieldVariables[] = {
    {"Hourglass_Force_Density", true, 3, "hourglass_force_density"},
    {"Left_Stretch_Tensor", false, 9, "left_stretch_tensor"},
    {"Rotation_Tensor", false, 9, "rotation_tensor"},
    {"Shape_Tensor_Inverse", false, 9, "shape_tensor_inverse"},
    {"Unrotated_Rate_Of_Deformation", false, 9, "unrotated_rate_of_deformation"},
    {"Cauchy_Stress", false, 9, "cauchy_stress"},
    {"Unrotated_Cauchy_Stress", false, 9, "unrotated_cauchy_stress"},
    {"Von_Mises_Stress", false, 1, "von_mises_stress"},
    {"Equivalent_Plastic_Strain", false, 1, "equivalent_plastic_strain"},
    // bond_associated_correspondence (material/models/bond_associated.hpp)
    {"Velocity_Gradient", false, 9, "velocity_gradient"},
    {"Jacobian_Determinant", false, 1, "jacobian_determinant"},
    // lps and elastic_plastic with shear_correction (material/shear_correction.hpp)
    {"Surface_Correction_Factor", false, 1, "shear_correction_factor"},
    // pals (material/models/pals.hpp)
    {"Dilatation_Normalization", false, 1, "dilatation_normalization"},
    {"Deviatoric_Normalization", false, 1, "deviatoric_normalization"},
    {"Lagrange_Multiplier_Dilatation_1", false, 1, "lagrange_multiplier_dilatation_1"},
    {"Lagrange_Multiplier_Dilatation_2", false, 1, "lagrange_multiplier_dilatation_2"},
    {"Lagrange_Multiplier_Dilatation_3", false, 1, "lagrange_multiplier_dilatation_3"},
    {"Lagrange_Multiplier_Dilatation_4", false, 1, "lagrange_multiplier_dilatation_4"},
    {"Lagrange_Multiplier_Dilatation_5", false, 1, "lagrange_multiplier_dilatation_5"},
    {"Lagrange_Multiplier_Dilatation_6", false, 1, "lagrange_multiplier_dilatation_6"},
    {"Lagrange_Multiplier_Deviatoric_1", false, 1, "lagrange_multiplier_deviatoric_1"},
    {"Lagrange_Multiplier_Deviatoric_2", false, 1, "lagrange_multiplier_deviatoric_2"},
    {"Lagrange_Multiplier_Deviatoric_3", false, 1, "lagrange_multiplier_deviatoric_3"},
    {"Lagrange_Multiplier_Deviatoric_4", false, 1, "lagrange_multiplier_deviatoric_4"},
    {"Lagrange_Multiplier_Deviatoric_5", false, 1, "lagrange_multiplier_deviatoric_5"},
    {"Lagrange_Multiplier_Deviatoric_6", false, 1, "lagrange_multiplier_deviatoric_6"},
};

// The components of a field variable: (Exodus name, field name) pairs.
std::vector<std::pair<std::string, std::string>> field_components(const FieldVariable& v) {
  static const char* up[3] = {"X", "Y", "Z"};
  static const char* low[3] = {"x", "y", "z"};
  std::vector<std::pair<std::string, std::string>> out;
  const std::string n = v.name, f = v.field;
  if (v.components == 1) out.push_back({n, f});
  if (v.components == 3)
    for (int c = 0; c < 3; ++c) out.push_back({n + up[c], f + "_" + low[c]});
  if (v.components == 9)
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) out.push_back({n + up[r] + up[c], f + "_" + low[r] + low[c]});
  return out;
}

}  // namespace

bool exodus_field_variable(const std::string& name) {
  for (const auto& v : kFieldVariables)
    if (name == v.name) return true;
  return false;
}

ExodusOutput::ExodusOutput(std::string path, bool iterations)
    : path_(std::move(path)), iterations_(iterations ? std::optional<int>(0) : std::nullopt) {}

ExodusOutput::ExodusOutput(std::string path, bool iterations, const std::vector<std::string>& variables,
                           const Config& config, bool verlet_velocity)
    : ExodusOutput(std::move(path), iterations) {
  verlet_ = verlet_velocity;
  columns_.deck_file = config.deck_file;
  columns_.regions = config.regions;
  for (const auto& v : variables) {
    if (v == "Lambda") {
      lambda_ = true;
    } else if (v == "Deformation_Gradient") {
      gradient_ = true;
    } else if (v == "Horizon") {
      horizon_ = true;
      deck_horizon_ = config.horizon;
      for (const auto& b : config.bodies) body_horizon_.push_back(b.horizon);
    } else if (exodus_field_variable(v)) {
      for (const auto& fv : kFieldVariables)
        if (v == fv.name)
          for (const auto& [exo, field] : field_components(fv))
            (fv.nodal ? nodal_fields_ : element_fields_).push_back({exo, field});
    } else if (v == "Contact_Force_Density") {
      contact_ = true;
    } else if (v == "Flux_Divergence") {
      flux_divergence_ = true;
    } else {
      // The deck reader has checked that a history column of this name exists.
      for (const auto& c : config.output.history_columns)
        if (c.name == v) columns_.output.history_columns.push_back(c);
    }
  }
}

void ExodusOutput::set_iterations(int n) {
  if (iterations_) iterations_ = n;
}
ExodusOutput::~ExodusOutput() = default;

void ExodusOutput::set_step_velocity(const std::vector<Vec3>& u, const std::vector<Vec3>& u_before, double dt) {
  velocity_.assign(u.size(), Vec3{});
  if (u_before.size() != u.size() || !(dt > 0)) return;
  for (std::size_t i = 0; i < u.size(); ++i) velocity_[i] = (u[i] - u_before[i]) / dt;
}

namespace {
// Peridigm's fields of two states (N, N+1) that Horizon writes, as their Exodus names
// start: at a QuasiStatic solver's start its output holds them as of the load step
// before the last (PredictorFromPreviousSolver's golds: 0 after one load step, where the
// displacements, forces, Deformation_Gradient and Shape_Tensor_Inverse are the last
// step's), which the writer takes as Peridigm's N+1 state after its update swapped it
// with N (docs/peridigm.md "Solvers in sequence").
bool two_state(const std::string& exodus_name) {
  for (const char* stem : {"Unrotated_Cauchy_Stress", "Cauchy_Stress", "Equivalent_Plastic_Strain"})
    if (exodus_name.rfind(stem, 0) == 0) return true;
  return false;
}
}  // namespace

void ExodusOutput::hold_fields(const System& s) {
  held_.assign(element_fields_.size(), {});
  std::vector<ModelField> fields;
  for (const auto& m : s.models) m->fields(s, fields);
  for (std::size_t c = 0; c < element_fields_.size(); ++c) {
    if (!two_state(element_fields_[c].first)) continue;
    held_[c].assign(s.particles.size(), 0.0);  // 0 where no model has the field
    for (const auto& f : fields)
      if (f.name == element_fields_[c].second && f.values.size() == s.particles.size()) held_[c] = f.values;
  }
}

void ExodusOutput::write(const System& s, const Decomposition* d, double time) {
  const Particles& P = s.particles;
  // A new solver's start frame (set_solver_start): velocities 0, the two-state fields held.
  const bool start = solver_start_;
  solver_start_ = false;
  if (start) velocity_.assign(P.size(), Vec3{});
  const ModelCoefficients& M = s.model;
  std::vector<std::vector<double>> rows;  // on the writing process: [particle][value]
  std::vector<Vec3> kicked;  // velocity: verlet (set_verlet)
  if (verlet_ && loads_ && verlet_dt_ > 0) {
    kicked = P.v;
    for (std::size_t i = 0; i < P.size(); ++i) {
      const double rho = i < P.density.size() ? P.density[i] : 0.0;
      if (!(rho > 0)) continue;
      const Vec3 b = i < P.b.size() ? P.b[i] : Vec3{};
      for (int c = 0; c < 3; ++c)
        if (loads_->is_constrained(i, c)) kicked[i][c] += 0.5 * verlet_dt_ * (P.f[i][c] + b[c]) / rho;
    }
  }
  const std::vector<Vec3>& velocity = velocity_.size() == P.size() ? velocity_ : kicked.size() ? kicked : P.v;
  // The file's own variables (header): the plastic multiplier field of the models, and
  // the globals, computed on every rank (the history columns are collective).
  // Lambda is NaN (undefined) at the particles of models without it: Peridigm leaves the
  // variable out of those blocks (Bar_TwoBlocks_TwoDifferentMaterial_QS's gold), which
  // exodiff and netCDF readers see as missing values.
  std::vector<double> lambda, dilatation;
  std::vector<ModelField> fields;
  {
    for (const auto& m : s.models) m->fields(s, fields);
    std::vector<uint8_t> plastic(P.size(), 0);
    for (std::size_t m = 0; m < s.models.size(); ++m)  // s.models[m]: material m's model
      if (s.models[m].traits().name == "elastic_plastic")
        for (std::size_t i = 0; i < P.size(); ++i)
          if (P.material[i] == static_cast<int32_t>(m)) plastic[i] = 1;
    if (lambda_) lambda.assign(P.size(), std::numeric_limits<double>::quiet_NaN());
    for (const auto& f : fields) {
      if (f.values.size() != P.size()) continue;
      if (f.name == "plastic_multiplier" && lambda_)
        for (std::size_t i = 0; i < P.size(); ++i)
          if (plastic[i]) lambda[i] = f.values[i];
      // Models whose rows compute theta themselves publish it as a field (elastic_plastic).
      // Models whose rows compute theta themselves publish it as a field (elastic_plastic,
      // pals, linear_lps), 0 at other particles: the fields of several such materials add.
      if (f.name == "dilatation") {
        if (dilatation.empty()) dilatation.assign(P.size(), 0.0);
        for (std::size_t i = 0; i < P.size(); ++i) dilatation[i] += f.values[i];
      }
    }
  }
  const std::vector<double> globals = history_columns_values(columns_, s);
  // The field variables' columns (0 where no model has the field).
  std::vector<const std::vector<double>*> extra_columns;
  for (const auto* list : {&nodal_fields_, &element_fields_})
    for (const auto& [exo, field] : *list) {
      const std::vector<double>* col = nullptr;
      for (const auto& f : fields)
        if (!col && f.name == field && f.values.size() == P.size()) col = &f.values;
      const std::size_t e = extra_columns.size() - (list == &element_fields_ ? nodal_fields_.size() : 0);
      if (start && list == &element_fields_ && e < held_.size() && held_[e].size() == P.size()) col = &held_[e];
      extra_columns.push_back(col);
    }
  // A run with a temperature field (thermal section) adds the nodal Temperature and
  // Temperature_Change (T - T_ref, the change that strains the mechanics; Peridigm's
  // names, its T - T(0) with reference_temperature: initial), after the contact force.
  const bool heat = s.heat.active();
  // Flux_Divergence: the conduction's sum_j kbar g (T_j - T_i) V_j [W/m^3] (thermal/heat.hpp
  // heat_conduction; Peridigm's name for it, docs/peridigm.md), 0 without conduction.
  const bool divergence = heat && flux_divergence_;
  std::vector<double> flux_divergence;
  if (divergence) {
    if (s.heat.conduction) heat_conduction(s, s.heat.T, flux_divergence);
    flux_divergence.resize(P.size(), 0.0);
  }
  const int width = kWidth + (lambda_ ? 1 : 0) + (gradient_ ? 9 : 0) + (horizon_ ? 1 : 0) + (contact_ ? 3 : 0) +
                    (heat ? 2 : 0) + (divergence ? 1 : 0) + static_cast<int>(extra_columns.size());
  const std::vector<Vec3>& contact = s.contact.recorded_forces();
  // Number_Of_Neighbors: i's family, without the bonds in the neighbour's family alone
  // (BondKind::one_way: bodies of different horizons).
  auto neighbours = [&](uint32_t i) {
    if (i + 1 >= s.bonds.offset.size()) return 0.0;
    uint64_t count = s.bonds.end(i) - s.bonds.begin(i);
    if (s.one_way_bonds)
      for (uint64_t k = s.bonds.begin(i); k < s.bonds.end(i); ++k) count -= s.bonds.kinds[s.bonds.kind[k]].one_way ? 1 : 0;
    return static_cast<double>(count);
  };
  auto pack = [&](uint32_t i, std::vector<double>& out) {
    for (const Vec3* v : {&P.X[i], &P.u[i], &velocity[i], &P.f[i]}) out.insert(out.end(), {v->x, v->y, v->z});
    out.push_back(P.volume[i]);
    out.push_back(i < P.density.size() ? P.density[i] : 0.0);
    out.push_back(P.damage[i]);
    out.push_back((i < M.theta.size() ? M.theta[i] : 0.0) + (i < dilatation.size() ? dilatation[i] : 0.0));
    out.push_back(i < M.weighted_volume.size() ? M.weighted_volume[i] : 0.0);
    out.push_back(static_cast<double>(P.block[i]));
    out.push_back(neighbours(i));
    const Vec3 b = i < P.b.size() ? P.b[i] : Vec3{};
    out.insert(out.end(), {b.x, b.y, b.z});
    out.push_back(i < P.energy.size() ? P.energy[i] : 0.0);
    if (lambda_) out.push_back(lambda[i]);
    if (gradient_) {
      const auto F = deformation_gradient(s, i);
      out.insert(out.end(), F.begin(), F.end());
    }
    if (horizon_) {
      const auto b = static_cast<std::size_t>(P.block[i]);
      const auto& h = b < body_horizon_.size() ? body_horizon_[b] : std::nullopt;
      out.push_back(h ? (*h)(0, P.X[i].x, P.X[i].y, P.X[i].z) : deck_horizon_);
    }
    if (contact_) {
      const Vec3 fc = i < contact.size() ? contact[i] : Vec3{};
      out.insert(out.end(), {fc.x, fc.y, fc.z});
    }
    if (heat) out.insert(out.end(), {s.heat.T[i], s.heat.T[i] - s.heat.reference[i]});
    if (divergence) out.push_back(flux_divergence[i]);
    for (const auto* col : extra_columns) out.push_back(col ? (*col)[i] : 0.0);
  };
  auto take = [&](std::size_t g, const double* v) {
    if (rows.size() <= g) rows.resize(g + 1);
    rows[g].assign(v, v + width);
  };
  stream_on_lead(s, d, width, pack, take);
  const bool lead = !d || d->rank == 0;
  std::string failure;
  if (lead) {
    try {
      append(s, rows, globals, time);
    } catch (const OutputError& e) {
      failure = e.what();
    }
  }
  // Every rank stops on rank 0's output error (the run's collectives stay matched).
  if (d ? any_rank(*d, !failure.empty()) : !failure.empty())
    throw OutputError(lead ? failure : "rank 0 could not write the Exodus file '" + path_ + "'");
}

void ExodusOutput::append(const System& s, const std::vector<std::vector<double>>& rows,
                          const std::vector<double>& globals, double time) {

  const std::size_t n = rows.size();
  if (!writer_) {
    ExodusLayout layout;
    layout.title = "Horizon";
    for (const auto& r : rows) {
      layout.points.push_back({r[0], r[1], r[2]});
      layout.block.push_back(static_cast<int>(r[17]));
    }
    layout.block_names = s.block_names;
    int most = 0;
    for (int b : layout.block) most = std::max(most, b + 1);
    for (int b = static_cast<int>(layout.block_names.size()); b < most; ++b)
      layout.block_names.push_back("block_" + std::to_string(b + 1));
    layout.nodal = {"DisplacementX", "DisplacementY", "DisplacementZ", "VelocityX", "VelocityY", "VelocityZ",
                    "Force_DensityX", "Force_DensityY", "Force_DensityZ", "ForceX", "ForceY", "ForceZ",
                    "AccelerationX", "AccelerationY", "AccelerationZ", "External_Force_DensityX",
                    "External_Force_DensityY", "External_Force_DensityZ"};
    if (contact_)
      for (const char* a : {"X", "Y", "Z"}) layout.nodal.push_back(std::string("Contact_Force_Density") + a);
    if (s.heat.active()) layout.nodal.insert(layout.nodal.end(), {"Temperature", "Temperature_Change"});
    if (s.heat.active() && flux_divergence_) layout.nodal.push_back("Flux_Divergence");
    layout.element = {"Element_Id", "Block_Id", "Volume", "Damage", "Dilatation", "Weighted_Volume",
                      "Number_Of_Neighbors", "Stored_Elastic_Energy_Density", "Stored_Elastic_Energy", "Radius"};
    if (lambda_) layout.element.push_back("Lambda");
    if (gradient_)
      for (const char* r : {"X", "Y", "Z"})
        for (const char* c : {"X", "Y", "Z"}) layout.element.push_back(std::string("Deformation_Gradient") + r + c);
    if (horizon_) layout.element.push_back("Horizon");
    for (const auto& f : nodal_fields_) layout.nodal.push_back(f.first);
    for (const auto& f : element_fields_) layout.element.push_back(f.first);
    layout.global = {"Global_Kinetic_Energy"};
    if (iterations_) layout.global.push_back("Nonlinear_Solver_Iterations");
    for (const auto& name : history_columns_names(columns_)) layout.global.push_back(name);
    writer_ = std::make_unique<ExodusWriter>(path_, layout);
  }
  ExodusStep step;
  step.time = time;
  const bool heat = s.heat.active();
  const std::size_t contact_columns = contact_ ? 3 : 0, heat_columns = heat ? (flux_divergence_ ? 3 : 2) : 0,
                    nodal_extra = nodal_fields_.size();
  step.nodal.assign(18 + contact_columns + heat_columns + nodal_extra, std::vector<double>(n));
  const std::size_t extra = (lambda_ ? 1 : 0) + (gradient_ ? 9 : 0) + (horizon_ ? 1 : 0);
  const std::size_t element_extra = extra + element_fields_.size();
  step.element.assign(10 + element_extra, std::vector<double>(n));
  double kinetic = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto& r = rows[i];
    for (int c = 0; c < 9; ++c) step.nodal[static_cast<std::size_t>(c)][i] = r[static_cast<std::size_t>(3 + c)];
    for (int c = 0; c < 3; ++c) {
      const auto k = static_cast<std::size_t>(c);
      step.nodal[9 + k][i] = r[9 + k] * r[12];
      // (f + b) / rho: the acceleration of the equation of motion (0 without a density).
      step.nodal[12 + k][i] = r[13] > 0 ? (r[9 + k] + r[19 + k]) / r[13] : 0.0;
      step.nodal[15 + k][i] = r[19 + k];
    }
    step.element[0][i] = static_cast<double>(i + 1);
    step.element[1][i] = block_id(s.block_names, static_cast<int>(r[17]));
    step.element[2][i] = r[12];
    step.element[3][i] = r[14];
    step.element[4][i] = r[15];
    step.element[5][i] = r[16];
    step.element[6][i] = r[18];
    step.element[7][i] = r[22];
    step.element[8][i] = r[22] * r[12];
    // Peridigm's sphere radius: the sphere of the particle's volume, (3V / 4 pi)^(1/3).
    step.element[9][i] = std::cbrt(3 * r[12] / (4 * std::numbers::pi));
    // Row layout past kWidth: Lambda, F, Horizon (extra), contact, the nodal fields, the element fields.
    for (std::size_t c = 0; c < extra; ++c) step.element[10 + c][i] = r[kWidth + c];
    if (contact_)
      for (std::size_t c = 0; c < 3; ++c) step.nodal[18 + c][i] = r[kWidth + extra + c];
    if (heat)
      for (std::size_t c = 0; c < heat_columns; ++c)
        step.nodal[18 + contact_columns + c][i] = r[kWidth + extra + contact_columns + c];
    const std::size_t base = kWidth + extra + contact_columns + heat_columns;
    for (std::size_t c = 0; c < nodal_extra; ++c)
      step.nodal[18 + contact_columns + heat_columns + c][i] = r[base + c];
    for (std::size_t c = 0; c < element_fields_.size(); ++c)
      step.element[10 + extra + c][i] = r[base + nodal_extra + c];
    kinetic += 0.5 * r[13] * r[12] * (r[6] * r[6] + r[7] * r[7] + r[8] * r[8]);
  }
  step.global = {kinetic};
  if (iterations_) step.global.push_back(static_cast<double>(*iterations_));
  step.global.insert(step.global.end(), globals.begin(), globals.end());
  writer_->append(step);
}

ExodusSchedule::ExodusSchedule(const std::vector<OutputConfig::ExodusFile>& files, const std::filesystem::path& dir,
                               bool iterations, const Config& config) {
  for (const auto& f : files) {
    files_.push_back(
        std::make_unique<ExodusOutput>((dir / f.file).string(), iterations, f.variables, config, f.verlet_velocity));
    every_.push_back(std::max(1, f.every));
    range_.emplace_back(f.first_step, f.last_step);
    explicit_every_.push_back(f.explicit_every);
  }
}

// Peridigm's rule: a list writes at the steps its Output Frequency divides, within its
// Initial and Final Output Step (Compression_QS_Explicit_MultiFreqOutput's gold: every 100
// from step 21 writes steps 100, ..., 500, not 21, 121, ...).
bool ExodusSchedule::due_file(std::size_t k, int64_t step) const {
  const int64_t every = step >= explicit_from_ && explicit_every_[k] > 0 ? explicit_every_[k] : every_[k];
  return step % every == 0 && step >= range_[k].first && step <= range_[k].second;
}

void ExodusSchedule::prepare(System& s) const {
  for (const auto& f : files_)
    if (f->contact_forces()) s.contact.record_forces(true);
}

bool ExodusSchedule::due(int64_t step) const {
  for (std::size_t k = 0; k < files_.size(); ++k)
    if (due_file(k, step)) return true;
  return false;
}

void ExodusSchedule::write(const System& s, const Decomposition* d, double time, int64_t step) {
  for (std::size_t k = 0; k < files_.size(); ++k)
    if (due_file(k, step)) files_[k]->write(s, d, time);
}

void ExodusSchedule::hold_fields(const System& s) {
  for (auto& f : files_) f->hold_fields(s);
}

void ExodusSchedule::write_solver_start(const System& s, const Decomposition* d, double time, int64_t step) {
  for (std::size_t k = 0; k < files_.size(); ++k)
    if (due_file(k, step)) {
      files_[k]->set_solver_start();
      files_[k]->write(s, d, time);
    }
}

void ExodusSchedule::set_verlet(const Loads* loads, double dt) {
  for (auto& f : files_) f->set_verlet(loads, dt);
}

void ExodusSchedule::set_iterations(int n) {
  for (auto& f : files_) f->set_iterations(n);
}

void ExodusSchedule::set_step_velocity(const std::vector<Vec3>& u, const std::vector<Vec3>& u_before, double dt) {
  for (auto& f : files_) f->set_step_velocity(u, u_before, dt);
}

}  // namespace horizon
