#include "horizon/driver/exodus_output.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numbers>

#include "horizon/core/error.hpp"

#include "horizon/output/exodus.hpp"
#include "horizon/parallel/decomposition.hpp"
#include "horizon/parallel/lead_view.hpp"
#include "horizon/state/system.hpp"

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

}  // namespace

ExodusOutput::ExodusOutput(std::string path, bool iterations)
    : path_(std::move(path)), iterations_(iterations ? std::optional<int>(0) : std::nullopt) {}

void ExodusOutput::set_iterations(int n) {
  if (iterations_) iterations_ = n;
}
ExodusOutput::~ExodusOutput() = default;

void ExodusOutput::set_step_velocity(const std::vector<Vec3>& u, const std::vector<Vec3>& u_before, double dt) {
  velocity_.assign(u.size(), Vec3{});
  if (u_before.size() != u.size() || !(dt > 0)) return;
  for (std::size_t i = 0; i < u.size(); ++i) velocity_[i] = (u[i] - u_before[i]) / dt;
}

void ExodusOutput::write(const System& s, const Decomposition* d, double time) {
  const Particles& P = s.particles;
  const ModelCoefficients& M = s.model;
  std::vector<std::vector<double>> rows;  // on the writing process: [particle][value]
  const std::vector<Vec3>& velocity = velocity_.size() == P.size() ? velocity_ : P.v;
  auto pack = [&](uint32_t i, std::vector<double>& out) {
    for (const Vec3* v : {&P.X[i], &P.u[i], &velocity[i], &P.f[i]}) out.insert(out.end(), {v->x, v->y, v->z});
    out.push_back(P.volume[i]);
    out.push_back(i < P.density.size() ? P.density[i] : 0.0);
    out.push_back(P.damage[i]);
    out.push_back(i < M.theta.size() ? M.theta[i] : 0.0);
    out.push_back(i < M.weighted_volume.size() ? M.weighted_volume[i] : 0.0);
    out.push_back(static_cast<double>(P.block[i]));
    out.push_back(i + 1 < s.bonds.offset.size() ? static_cast<double>(s.bonds.offset[i + 1] - s.bonds.offset[i]) : 0.0);
    const Vec3 b = i < P.b.size() ? P.b[i] : Vec3{};
    out.insert(out.end(), {b.x, b.y, b.z});
    out.push_back(i < P.energy.size() ? P.energy[i] : 0.0);
  };
  auto take = [&](std::size_t g, const double* v) {
    if (rows.size() <= g) rows.resize(g + 1);
    rows[g].assign(v, v + kWidth);
  };
  stream_on_lead(s, d, kWidth, pack, take);
  const bool lead = !d || d->rank == 0;
  std::string failure;
  if (lead) {
    try {
      append(s, rows, time);
    } catch (const OutputError& e) {
      failure = e.what();
    }
  }
  // Every rank stops on rank 0's output error (the run's collectives stay matched).
  if (d ? any_rank(*d, !failure.empty()) : !failure.empty())
    throw OutputError(lead ? failure : "rank 0 could not write the Exodus file '" + path_ + "'");
}

void ExodusOutput::append(const System& s, const std::vector<std::vector<double>>& rows, double time) {

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
    layout.element = {"Element_Id", "Block_Id", "Volume", "Damage", "Dilatation", "Weighted_Volume",
                      "Number_Of_Neighbors", "Stored_Elastic_Energy_Density", "Stored_Elastic_Energy", "Radius"};
    layout.global = {"Global_Kinetic_Energy"};
    if (iterations_) layout.global.push_back("Nonlinear_Solver_Iterations");
    writer_ = std::make_unique<ExodusWriter>(path_, layout);
  }
  ExodusStep step;
  step.time = time;
  step.nodal.assign(18, std::vector<double>(n));
  step.element.assign(10, std::vector<double>(n));
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
    kinetic += 0.5 * r[13] * r[12] * (r[6] * r[6] + r[7] * r[7] + r[8] * r[8]);
  }
  step.global = {kinetic};
  if (iterations_) step.global.push_back(static_cast<double>(*iterations_));
  writer_->append(step);
}

ExodusSchedule::ExodusSchedule(const std::vector<OutputConfig::ExodusFile>& files, const std::filesystem::path& dir,
                               bool iterations) {
  for (const auto& f : files) {
    files_.push_back(std::make_unique<ExodusOutput>((dir / f.file).string(), iterations));
    every_.push_back(std::max(1, f.every));
  }
}

bool ExodusSchedule::due(int64_t step) const {
  for (int64_t e : every_)
    if (step % e == 0) return true;
  return false;
}

void ExodusSchedule::write(const System& s, const Decomposition* d, double time, int64_t step) {
  for (std::size_t k = 0; k < files_.size(); ++k)
    if (step % every_[k] == 0) files_[k]->write(s, d, time);
}

void ExodusSchedule::set_iterations(int n) {
  for (auto& f : files_) f->set_iterations(n);
}

void ExodusSchedule::set_step_velocity(const std::vector<Vec3>& u, const std::vector<Vec3>& u_before, double dt) {
  for (auto& f : files_) f->set_step_velocity(u, u_before, dt);
}

}  // namespace horizon
