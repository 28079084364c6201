#include "horizon/material/models/viscoelastic.hpp"

#include <array>
#include <cmath>
#include <limits>
#include <string>

#include "horizon/core/error.hpp"
#include "horizon/material/models/history_ledger.hpp"
#include "horizon/material/models/ordinary_flat.hpp"
#include "horizon/material/models/ordinary_lanes.hpp"
#include "horizon/material/models/ordinary_rows.hpp"
#include "horizon/state/system.hpp"

namespace horizon {

namespace {

const ModelTraits& traits() {
  static const ModelTraits t = [] {
    ModelTraits m;
    m.name = "viscoelastic";
    m.summary = "LPS with a standard linear solid on the deviatoric extension, ordinary state-based "
                "(Mitchell, SAND2011-8064)";
    m.min_dimension = 2;
    m.parameters = {
        {"lambda_1", "weight of Maxwell branch 1 in the deviatoric response (lambda_inf = 1 - sum lambda_b)",
         ParameterSpec::Range::fraction, std::nullopt},
        {"tau_1", "decay time of Maxwell branch 1 [s]", ParameterSpec::Range::positive, std::nullopt},
        {"lambda_2", "weight of Maxwell branch 2 (0: none)", ParameterSpec::Range::fraction, 0.0},
        {"tau_2", "decay time of Maxwell branch 2 [s]", ParameterSpec::Range::non_negative, 0.0},
        {"lambda_3", "weight of Maxwell branch 3 (0: none)", ParameterSpec::Range::fraction, 0.0},
        {"tau_3", "decay time of Maxwell branch 3 [s]", ParameterSpec::Range::non_negative, 0.0},
    };
    m.thermal_strain = true;  // force_state subtracts eps_ij |xi| from e (docs/models/heat.md)
    m.rows_local = true;      // row i reads i's family, i's theta/back dilatations and its bonds' e^d, back extensions
    m.ordinary = true;        // T = t Y/|Y|: the scalar general pass (force_row)
    return m;
  }();
  return t;
}

class Viscoelastic final : public Model {
 public:
  std::unique_ptr<Model> clone() const override { return std::make_unique<Viscoelastic>(*this); }
  const ModelTraits& traits() const override { return horizon::traits(); }
  void setup(const ModelSetup& in) override;
  void force_state(ForcePass& pass) override;
  void begin_rows(const RowPass& pass) override;
  void force_row(const RowPass& pass, std::size_t i, double dilatation_sum) override;
  void force_row_scalar(const RowPass& pass, std::size_t i, double dilatation_sum);
  void commit(System& s) override;
  double pending_dissipation(const System& s) const override {
    return ledger_.pending_energy(particles_, s.particles.volume);
  }
  void fields(const System& s, std::vector<ModelField>& out) const override {
    (void)s;
    out.push_back({"viscous_dissipation", dissipated_});  // cumulative, per unit volume [J/m^3]
  }

  void checkpoint(StateArchive& a) override {
    a.io_particles("theta", theta_);
    a.io_particles("theta_trial", theta_trial_);
    a.io_particles("theta_row", theta_row_);
    a.io_particles("theta_row_trial", theta_row_trial_);
    a.io_particles("dissipated", dissipated_);
    ed_.checkpoint(a, "ed", "ed_trial", ledger_.fresh);
    for (std::size_t b = 0; b < kMaxViscousBranches; ++b) {
      a.io_particles("theta_back_" + std::to_string(b), theta_back_[b]);
      a.io_particles("theta_back_trial_" + std::to_string(b), theta_back_trial_[b]);
      back_[b].checkpoint(a, "back_" + std::to_string(b), "back_trial_" + std::to_string(b), ledger_.fresh);
    }
    ledger_.checkpoint(a);
  }
  // The flat backend's view of the state (material/models/ordinary_flat.hpp).
  void flat_state(OrdinaryModelState& o) {
    static_assert(kMaxViscousBranches <= kOrdinaryFlatBranches);
    o.kind = OrdinaryModelState::viscoelastic;
    o.dim = dim_, o.ledger = &ledger_, o.mu = mu_;
    o.bulk_elastic = bulk_elastic_, o.dilatation_shear = dilatation_shear_, o.lambda_inf = lambda_inf_;
    o.branches = branches_;
    for (int b = 0; b < kMaxViscousBranches; ++b) {
      o.branch_lambda[b] = lambda_[b], o.tau[b] = tau_[b];
      o.theta_back[b] = &theta_back_[b], o.theta_back_trial[b] = &theta_back_trial_[b], o.back[b] = &back_[b];
    }
    o.theta_row = &theta_row_, o.theta_row_trial = &theta_row_trial_, o.theta_strain = &theta_;
    o.theta_strain_trial = &theta_trial_, o.dissipated = &dissipated_;
  }

 private:
  // p_i = k theta + (mu/3) [lambda_inf theta + sum_b lambda_b (theta - theta^b_b)] in plane
  // strain (header); stores the branches' trial back dilatations and theta's trial value, and
  // returns p_i with the dilatation springs' sum (lambda_inf theta^2 + sum_b lambda_b
  // (theta - theta^b_b)^2) in `springs`. Shared by force_state and force_row.
  double pressure(std::size_t i, double theta, const SlsStep* step, double& springs) {
    double p = bulk_elastic_ * theta;
    springs = 0;
    if (dilatation_shear_ == 0) return p;
    double relaxing = lambda_inf_ * theta;
    springs = lambda_inf_ * theta * theta;
    for (int b = 0; b < branches_; ++b) {
      const double back = sls_back_extension(step[b], theta_back_[b][i], theta_[i], theta);
      theta_back_trial_[b][i] = back;
      relaxing += lambda_[b] * (theta - back);
      springs += lambda_[b] * (theta - back) * (theta - back);
    }
    theta_trial_[i] = theta;
    return p + dilatation_shear_ * relaxing;
  }
  void size_bonds(const Bonds& B) {
    const std::size_t nb = B.size();
    if (ed_.size() == nb) return;
    ed_.assign(nb, 0);
    for (int b = 0; b < branches_; ++b) back_[b].assign(nb, 0);
    ledger_.size_bonds(B);
  }

  std::vector<uint32_t> particles_;
  int dim_ = 3;
  double bulk_ = 0, mu_ = 0;
  // Plane strain: the elastic part k of k' = k + mu/3 and the relaxing part mu/3 (header);
  // 3-D and plane stress: bulk_elastic_ = k', dilatation_shear_ = 0.
  double bulk_elastic_ = 0, dilatation_shear_ = 0;
  double lambda_inf_ = 1;
  int branches_ = 0;
  std::array<double, kMaxViscousBranches> lambda_{}, tau_{};
  // Per particle, plane strain only: theta and the back dilatation of each branch,
  // committed and trial (the relaxing mu/3 of k', header).
  std::vector<double> theta_, theta_trial_;
  // Per particle: theta of the last pass, committed and trial. The scalar pass's rows
  // rebuild a bond's committed e^d_n from it and the ledger's committed extension e_n,
  // e^d_n = e_n - theta_n |xi| / d, the same operations on the same numbers as the pass
  // that computed it: the same bits as the stored ed_, without streaming ed_ (16 bytes a
  // bond and step; ed_ stays the vector form's, force_state).
  std::vector<double> theta_row_, theta_row_trial_;
  std::array<std::vector<double>, kMaxViscousBranches> theta_back_, theta_back_trial_;
  // Per particle: the stored energy density W, committed and trial; the dissipation
  // density of the trial step (material/models/history_ledger.hpp) and its running total.
  std::vector<double> dissipated_;
  // Per directed bond: e^d and the back extension of each branch, committed and trial,
  // and what the ledger needs of the step.
  BondHistory<double> ed_;
  std::array<BondHistory<double>, kMaxViscousBranches> back_;
  std::array<SlsStep, kMaxViscousBranches> step_{};  // the branches' update over the pass's dt (begin_rows)
  HistoryLedger ledger_;  // the step's energy bookkeeping (history_ledger.hpp)
  LedgerRows mode_;       // how this pass's rows read and write the ledger's t and e
};

void Viscoelastic::setup(const ModelSetup& in) {
  const MaterialConfig& mat = in.material;
  System& s = in.system;
  dim_ = in.config.dimension;
  if (dim_ == 1) throw Error("material '" + mat.name + "': model viscoelastic needs dimension 2 or 3");
  particles_ = in.particles;
  bulk_ = lps_bulk_modulus(mat.bulk_modulus, mat.shear_modulus, in.dims);
  const bool plane_strain = dim_ == 2 && in.config.plane == PlaneMode::strain;
  bulk_elastic_ = plane_strain ? mat.bulk_modulus : bulk_;
  dilatation_shear_ = plane_strain ? mat.shear_modulus / 3 : 0.0;
  mu_ = mat.shear_modulus;
  branches_ = 0;
  double sum = 0;
  for (int b = 0; b < kMaxViscousBranches; ++b) {
    const std::string n = std::to_string(b + 1);
    const double lambda = Model::parameter(mat, "lambda_" + n), tau = Model::parameter(mat, "tau_" + n);
    if (lambda == 0) continue;
    if (!(tau > 0))
      throw Error("material '" + mat.name + "': Maxwell branch " + n + " has lambda_" + n + " = " +
                  std::to_string(lambda) + " but no decay time: give tau_" + n + " > 0 [s]");
    lambda_[branches_] = lambda;
    tau_[branches_] = tau;
    ++branches_;
    sum += lambda;
  }
  if (sum > 1 + 1e-12)
    throw Error("material '" + mat.name + "': the branch weights lambda_1 + lambda_2 + lambda_3 = " +
                std::to_string(sum) + " exceed 1 (lambda_inf = 1 - their sum is the long-term share of mu)");
  lambda_inf_ = std::max(0.0, 1.0 - sum);
  const std::size_t n = s.particles.size();
  ledger_.size_particles(n);
  dissipated_.assign(n, 0);
  const std::size_t nd = dilatation_shear_ != 0 ? n : 0;
  theta_.assign(nd, 0);
  theta_trial_.assign(nd, 0);
  theta_row_.assign(n, 0);
  theta_row_trial_.assign(n, 0);
  for (int b = 0; b < kMaxViscousBranches; ++b) {
    theta_back_[b].assign(b < branches_ ? nd : 0, 0);
    theta_back_trial_[b].assign(b < branches_ ? nd : 0, 0);
  }
  ed_.assign(0, 0);
  size_bonds(s.bonds);

  // As the LPS (material/models/lps.cpp): spring, contact, critical stretch.
  fill_state_based_coefficients(in);
}

void Viscoelastic::force_state(ForcePass& pass) {
  const System& s = pass.system;
  const auto& B = s.bonds;
  const auto& M = s.model;
  size_bonds(B);
  const Point4* y = pass.y;
  Vec3* T = pass.T;
  double* energy = pass.energy;
  const KindCoefficients* kc = M.kind.data();
  const int dim = dim_, nbranch = branches_;
  std::array<SlsStep, kMaxViscousBranches> step{};
  for (int b = 0; b < nbranch; ++b) step[b] = sls_step(pass.dt, tau_[b]);
  const double factor = lps_deviatoric_factor(dim) * mu_;  // alpha m
  const double linf = lambda_inf_;
  const std::size_t count = particles_.size();
  ledger_.begin_pass();
  const double* ed_old_all = ed_.committed();
  double* ed_trial = ed_.trial();
  // The thermal extension eps_ij |xi| of a bond (System::thermal_strain; none without a
  // temperature field).
  const double* eps = s.thermal_strain.empty() ? nullptr : s.thermal_strain.data();
  auto thermal = [eps](std::size_t i, std::size_t j, double length) {
    return eps ? 0.5 * (eps[i] + eps[j]) * length : 0.0;
  };
#pragma omp parallel for schedule(static)
  for (std::size_t q = 0; q < count; ++q) {
    const uint32_t i = particles_[q];
    if (!s.computes_row(i)) continue;  // another rank's row (ModelTraits::rows_local)
    const Point4 pi = y[i];
    const uint64_t first = B.begin(i), last = B.end(i);
    const double m = M.weighted_volume[i];
    const double alpha = factor / m;
    // theta = (d/m) sum omega |xi| e V_j over the intact bonds (seed 003 eq. 113, digest sec. 9),
    // e the mechanical extension (less the thermal extension eps_ij |xi|, docs/models/heat.md).
    double sum = 0;
    for (uint64_t k = first; k < last; ++k) {
      if (!B.intact[k]) continue;
      const Point4 pj = y[B.nbr[k]];
      const double dx = pj.x - pi.x, dy = pj.y - pi.y, dz = pj.z - pi.z;
      const KindCoefficients& c = kc[B.kind[k]];
      sum += c.wv * c.length * (std::sqrt(dx * dx + dy * dy + dz * dz) - c.length - thermal(i, B.nbr[k], c.length));
    }
    const double theta = dim * sum / m;
    theta_row_trial_[i] = theta;
    // t^i = (d/m) omega |xi| p_i, p_i = k' theta; in plane strain
    // p_i = k theta + (mu/3) [lambda_inf theta + sum_b lambda_b (theta - theta^b_b)] (header).
    double dil_springs;
    const double pressure = this->pressure(i, theta, step.data(), dil_springs);
    const double p_coef = dim * pressure / m;
    double work = 0, booked = 0, stored = 0;
    for (uint64_t k = first; k < last; ++k) {
      const KindCoefficients& c = kc[B.kind[k]];
      const BondKind& bk = B.kinds[B.kind[k]];
      const double vj = bk.volume * bk.fraction;
      const Point4 pj = y[B.nbr[k]];
      const Vec3 Y{pj.x - pi.x, pj.y - pi.y, pj.z - pi.z};
      const double r = std::sqrt(dot(Y, Y));
      const double e = r - c.length - thermal(i, B.nbr[k], c.length);
      ledger_.open_bond(k, B.intact[k], T[k], Y, r, e, vj, booked);
      const double old_force = ledger_.force.committed()[k], old_extension = ledger_.extension.committed()[k];
      if (!B.intact[k]) {
        T[k] = {};
        ed_trial[k] = ed_old_all[k];
        for (int b = 0; b < nbranch; ++b) back_[b].trial()[k] = back_[b].committed()[k];
        ledger_.force.trial()[k] = 0;
        work += 0.5 * old_force * (e - old_extension) * vj;  // it acted at the start of the step (or 0)
        continue;
      }
      const double omega = bk.weight;
      const double ed = e - theta * c.length / dim;  // e^d (seed 003 sec. 15; digest sec. 8)
      const double ed_old = ed_old_all[k];
      ed_trial[k] = ed;
      double dev = linf * ed;  // lambda_inf e^d + sum_b lambda_b (e^d - e^b)
      double springs = linf * ed * ed;
      for (int b = 0; b < nbranch; ++b) {
        const double back = sls_back_extension(step[b], back_[b].committed()[k], ed_old, ed);
        back_[b].trial()[k] = back;
        const double q = ed - back;
        dev += lambda_[b] * q;
        springs += lambda_[b] * q * q;
      }
      stored += c.wv * springs;
      const double t = p_coef * omega * c.length + alpha * omega * dev;
      ledger_.force.trial()[k] = t;
      work += 0.5 * (old_force + t) * (e - old_extension) * vj;
      T[k] = (t / r) * Y;
    }
    const double W = 0.5 * bulk_elastic_ * theta * theta + 0.5 * dilatation_shear_ * dil_springs + 0.5 * alpha * stored;
    ledger_.stored_trial[i] = W;
    // The dashpots' work in the step (material/models/history_ledger.hpp).
    ledger_.loss_trial[i] = inelastic_loss(work, W - ledger_.stored[i], booked);
    if (energy) energy[i] = W;
  }
}

void Viscoelastic::begin_rows(const RowPass& pass) {
  size_bonds(pass.system.bonds);
  mode_ = ledger_.begin_rows(pass.system, lanes::wide());
  for (int b = 0; b < branches_; ++b) step_[b] = sls_step(pass.dt, tau_[b]);
}

// The scalar pass's row (ModelTraits::ordinary) in eight lanes (ordinary_lanes.hpp):
// force_state's sums in the lanes' order, on the |Y| and the dilatation sum of the pass's
// breaking sweep, from flat bond arrays.
void Viscoelastic::force_row(const RowPass& pass, std::size_t i, double dilatation_sum) {
  if (!lanes::wide()) return force_row_scalar(pass, i, dilatation_sum);
  static_assert(kMaxViscousBranches <= lanes::kMaxBranches);
  const System& s = pass.system;
  const auto& M = s.model;
  const int dim = dim_;
  const double m = M.weighted_volume[i];
  const double alpha = lps_deviatoric_factor(dim) * mu_ / m;
  const double theta = dim * dilatation_sum / m;
  double dil_springs;
  const double pressure = this->pressure(i, theta, step_.data(), dil_springs);
  lanes::RowBonds b = lanes::row_bonds(pass, ledger_, mode_, i, true);
  lanes::VesRow row;
  row.theta_old = theta_row_[i];
  theta_row_trial_[i] = theta;
  row.branches = branches_;
  for (int br = 0; br < branches_; ++br) {
    // (in place: over the committed copy, each bond's read before it is written; LedgerRows)
    row.back_old[br] = back_[br].committed(), row.back_trial[br] = mode_.in_place ? back_[br].committed() : back_[br].trial();
    row.decay[br] = step_[br].decay, row.from_old[br] = step_[br].from_old, row.from_new[br] = step_[br].from_new;
    row.lambda[br] = lambda_[br];
  }
  row.lambda_inf = lambda_inf_, row.theta = theta, row.alpha = alpha, row.p_coef = dim * pressure / m, row.dim = dim;
  const lanes::RowSums sums = lanes::ves_row(b, row);
  const double W = 0.5 * bulk_elastic_ * theta * theta + 0.5 * dilatation_shear_ * dil_springs + 0.5 * alpha * sums.dev;
  ledger_.stored_trial[i] = W;
  ledger_.loss_trial[i] = inelastic_loss(sums.work, W - ledger_.stored[i], sums.booked);
  if (pass.energy) pass.energy[i] = W;
}

// The row in bond order, without the lanes (ordinary_lanes.hpp wide()): force_state's
// sums in the same order, e^d_n read from ed_ (which this path keeps).
void Viscoelastic::force_row_scalar(const RowPass& pass, std::size_t i, double dilatation_sum) {
  const System& s = pass.system;
  const auto& B = s.bonds;
  const auto& M = s.model;
  const KindCoefficients* kc = M.kind.data();
  const BondKind* kinds = B.kinds.data();
  const uint32_t* kind = B.kind.data();
  const uint8_t* intact = B.intact.data();
  const double* r = pass.deformed;
  double* q = pass.t;
  const double* ed_old_all = ed_.committed();
  double* ed_trial = ed_.trial();
  const double* old_force = ledger_.force.committed();
  const double* old_extension = ledger_.extension.committed();
  double* force_trial = ledger_.force.trial();
  const int dim = dim_, nbranch = branches_;
  const double linf = lambda_inf_;
  const double* eps = s.thermal_strain.empty() ? nullptr : s.thermal_strain.data();
  const uint64_t first = B.begin(i), last = B.end(i);
  const double m = M.weighted_volume[i];
  const double alpha = lps_deviatoric_factor(dim) * mu_ / m;
  const double theta = dim * dilatation_sum / m;
  double dil_springs;
  const double pressure = this->pressure(i, theta, step_.data(), dil_springs);
  const double p_coef = dim * pressure / m;
  theta_row_trial_[i] = theta;
  double work = 0, booked = 0, stored = 0;
  const HistoryLedger::Row ledger = ledger_.row();
  // The branches' back extensions, committed and trial, as plain pointers (taken once: see
  // HistoryLedger::Row).
  const double* back_old[kMaxViscousBranches];
  double* back_trial[kMaxViscousBranches];
  for (int b = 0; b < nbranch; ++b) {
    back_old[b] = back_[b].committed();
    back_trial[b] = back_[b].trial();
  }
  for (uint64_t k = first; k < last; ++k) {
    const KindCoefficients& c = kc[kind[k]];
    const BondKind& bk = kinds[kind[k]];
    const double vj = bk.volume * bk.fraction;
    const double e = r[k] - c.length - (eps ? 0.5 * (eps[i] + eps[B.nbr[k]]) * c.length : 0.0);
    ledger.open_bond(k, intact[k], q[k], r[k], e, vj, booked);
    if (!intact[k]) {
      q[k] = 0;
      ed_trial[k] = ed_old_all[k];
      for (int b = 0; b < nbranch; ++b) back_trial[b][k] = back_old[b][k];
      force_trial[k] = 0;
      work += kernels::released_work(old_force[k], e, old_extension[k], vj);  // it acted at the start of the step (or 0)
      continue;
    }
    const double omega = bk.weight;
    const double ed = kernels::deviatoric_extension(e, theta, c.length, dim);  // e^d (seed 003 sec. 15; digest sec. 8)
    const double ed_old = ed_old_all[k];
    ed_trial[k] = ed;
    double dev = linf * ed;  // lambda_inf e^d + sum_b lambda_b (e^d - e^b)
    double springs = kernels::weighted_square(linf, ed);
    for (int b = 0; b < nbranch; ++b) {
      const double back = sls_back_extension(step_[b], back_old[b][k], ed_old, ed);
      back_trial[b][k] = back;
      const double qb = ed - back;
      dev += lambda_[b] * qb;
      springs += kernels::weighted_square(lambda_[b], qb);
    }
    stored += c.wv * springs;
    const double t = kernels::ordinary_force_scalar(p_coef, omega, c.length, alpha, dev);
    force_trial[k] = t;
    work += kernels::trapezoid_work(old_force[k], t, e, old_extension[k], vj);
  }
  // q = t/|Y| (0 where the bond does not act), vectorised apart from the sums (ordinary_rows.hpp).
  rows::force_scalars(force_trial, r, intact, false, first, last, q);
  const double W = 0.5 * bulk_elastic_ * theta * theta + 0.5 * dilatation_shear_ * dil_springs + 0.5 * alpha * stored;
  ledger_.stored_trial[i] = W;
  ledger_.loss_trial[i] = inelastic_loss(work, W - ledger_.stored[i], booked);
  if (pass.energy) pass.energy[i] = W;
}

void Viscoelastic::commit(System& s) {
  const auto& P = s.particles;
  const std::size_t count = particles_.size();
  const int nbranch = branches_;
#pragma omp parallel for schedule(static)
  for (std::size_t q = 0; q < count; ++q) {
    const uint32_t i = particles_[q];
    if (!s.computes_row(i)) continue;
    theta_row_[i] = theta_row_trial_[i];
    if (dilatation_shear_ != 0) {
      theta_[i] = theta_trial_[i];
      for (int b = 0; b < nbranch; ++b) theta_back_[b][i] = theta_back_trial_[b][i];
    }
    const double loss = ledger_.commit_particle(i);
    if (loss != 0) {
      s.dissipated_at[i] += loss * P.volume[i];
      dissipated_[i] += loss;
    }
  }
  if (ledger_.commit_bonds(s)) {  // the trial bond records become the committed ones
    ed_.flip();
    for (int b = 0; b < nbranch; ++b) back_[b].flip();
  }
}

}  // namespace

bool viscoelastic_state(Model& m, OrdinaryModelState& out) {
  auto* p = dynamic_cast<Viscoelastic*>(&m);
  if (p) p->flat_state(out);
  return p != nullptr;
}

ModelEntry viscoelastic_model() {
  return {traits(), [] { return std::unique_ptr<Model>(std::make_unique<Viscoelastic>()); }};
}

}  // namespace horizon
