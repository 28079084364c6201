#include "horizon/material/models/elastic_plastic.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>
#include <numbers>

#include "horizon/core/error.hpp"
#include "horizon/material/influence.hpp"
#include "horizon/material/models/history_ledger.hpp"
#include "horizon/material/models/ordinary_flat.hpp"
#include "horizon/material/models/ordinary_lanes.hpp"
#include "horizon/material/models/ordinary_rows.hpp"
#include "horizon/material/shear_correction.hpp"
#include "horizon/state/system.hpp"

namespace horizon {

namespace {

const ModelTraits& traits() {
  static const ModelTraits t = [] {
    ModelTraits m;
    m.name = "elastic_plastic";
    m.summary = "LPS with deviatoric plasticity and linear isotropic hardening, ordinary state-based "
                "(Silling et al. 2007, sec. 16; Mitchell, SAND2011-3166)";
    m.min_dimension = 2;
    m.parameters = {
        {"yield_stress", "uniaxial (von Mises) yield stress sigma_y [Pa]", ParameterSpec::Range::positive, std::nullopt},
        {"hardening_modulus",
         "linear isotropic hardening modulus H [Pa]: sigma_y + H eps_p; uniaxial tangent slope E H/(E + H); 0: "
         "perfect plasticity",
         ParameterSpec::Range::non_negative, 0.0},
        {"shear_correction",
         "true: a per-particle factor s_i on the shear modulus (alpha and the return's mu) that gives a truncated "
         "family the continuum's deviatoric energy under shear, averaged over the shear's orientations (Peridigm's "
         "Apply Shear Correction Factor; material/shear_correction.hpp); written as the field "
         "shear_correction_factor",
         ParameterSpec::Range::boolean, 0.0},
    };
    m.choices = {
        {"yield_reference",
         "the weighted volume of the yield function psi_0 = sigma_y^2/(2 c m): particle (each particle's own m, "
         "so a homogeneous test yields at sigma_y on any lattice) or continuum (the full sphere's m = 4 pi "
         "int omega r^4 dr, 3-D only: Mitchell's psi_0 = 25 sigma_y^2/(8 pi delta^5) for omega = 1, Peridigm's "
         "Elastic Plastic)",
         {"particle", "continuum"}},
        {"plasticity",
         "on, or off: the model's elastic part alone (the LPS forces; plastic_multiplier stays 0), Peridigm's "
         "Disable Plasticity",
         {"on", "off"}},
    };
    m.thermal_strain = true;  // force_state subtracts eps_ij |xi| from e (docs/models/heat.md)
    m.rows_local = true;      // row i reads i's family, eps_p_i and e^dp of i's bonds alone
    m.ordinary = true;        // T = t Y/|Y|: the scalar general pass (force_row)
    return m;
  }();
  return t;
}

class ElasticPlastic final : public Model {
 public:
  std::unique_ptr<Model> clone() const override { return std::make_unique<ElasticPlastic>(*this); }
  const ModelTraits& traits() const override { return horizon::traits(); }
  void setup(const ModelSetup& in) override;
  void force_state(ForcePass& pass) override;
  void begin_rows(const RowPass& pass) override {
    size_bonds(pass.system.bonds);
    mode_ = ledger_.begin_rows(pass.system, lanes::wide());
    if (yield_flags_stale_) {  // after a restart: from the restored e^dp
      const auto& B = pass.system.bonds;
      for (uint32_t i : particles_)
        for (uint64_t k = B.begin(i); k < B.end(i); ++k)
          if (ep_.committed()[k] != 0 || ep_.trial()[k] != 0) yielded_[i] = 1;
      yield_flags_stale_ = false;
    }
  }
  void force_row(const RowPass& pass, std::size_t i, double dilatation_sum) override;
  void force_row_scalar(const RowPass& pass, std::size_t i, double dilatation_sum);
  void commit(System& s) override;
  double pending_dissipation(const System& s) const override {
    return ledger_.pending_energy(particles_, s.particles.volume);
  }
  void fields(const System& s, std::vector<ModelField>& out) const override {
    // The equivalent plastic strain, measured like the classical one, and the plastic
    // multiplier lambda (header).
    (void)s;
    out.push_back({"plastic_strain", eps_p_});
    out.push_back({"plastic_multiplier", lambda_});
    // theta of the last force pass: this model's rows compute it themselves, so the
    // general pass's System::model.theta (the Exodus file's Dilatation) stays 0 here.
    out.push_back({"dilatation", theta_});
    if (shear_corrected_) out.push_back({"shear_correction_factor", shear_factor_});
  }

  void checkpoint(StateArchive& a) override {
    a.io_particles("eps_p", eps_p_);
    a.io_particles("eps_p_trial", eps_p_trial_);
    a.io_particles("lambda", lambda_);
    a.io_particles("lambda_trial", lambda_trial_);
    ep_.checkpoint(a, "ep", "ep_trial", ledger_.fresh);
    ledger_.checkpoint(a);
    if (a.loading()) std::fill(yielded_.begin(), yielded_.end(), 0), yield_flags_stale_ = true;
  }
  // The flat backend's view of the state (material/models/ordinary_flat.hpp).
  void flat_state(OrdinaryModelState& o) {
    o.kind = OrdinaryModelState::elastic_plastic;
    o.dim = dim_, o.ledger = &ledger_, o.mu = mu_;
    o.bulk = bulk_, o.yield = yield_, o.hardening = hardening_, o.yield_volume = yield_volume_, o.plastic = plastic_;
    o.eps_p = &eps_p_, o.eps_p_trial = &eps_p_trial_, o.lambda = &lambda_, o.lambda_trial = &lambda_trial_;
    o.theta = &theta_, o.shear_factor = &shear_factor_, o.flowed = &flowed_, o.yielded = &yielded_;
    o.yield_flags_stale = &yield_flags_stale_, o.ep = &ep_;
  }

 private:
  void size_bonds(const Bonds& B) {
    const std::size_t nb = B.size();
    if (ep_.size() == nb) return;
    ep_.assign(nb, 0);
    std::fill(yielded_.begin(), yielded_.end(), 0);
    ledger_.size_bonds(B);
  }

  std::vector<uint32_t> particles_;
  int dim_ = 3;
  double bulk_ = 0;  // k' (lps_bulk_modulus)
  double mu_ = 0, yield_ = 0, hardening_ = 0;
  // The weighted volume of the yield function: 0 for each particle's own m, else the
  // continuum's (yield_reference).
  double yield_volume_ = 0;
  bool plastic_ = true;  // plasticity: off leaves every step elastic (beta = 1)
  // Per particle: the shear correction factor s_i (1 without shear_correction), which
  // scales alpha and the return's shear modulus of i's row.
  std::vector<double> shear_factor_;
  bool shear_corrected_ = false;
  double yield_m(double m) const { return yield_volume_ > 0 ? yield_volume_ : m; }
  // Per particle (indexed by particle, only this material's filled): the equivalent
  // plastic strain and the stored energy density W, committed and trial, and the energy
  // density dissipated in the trial step [J/m^3].
  std::vector<double> eps_p_, eps_p_trial_;
  // Per particle: it flowed in its last pass of the scalar form (force_row's guess; not
  // state: whatever it holds, the row computes the same bits).
  std::vector<uint8_t> flowed_;
  // Per particle: its row has flowed in some pass (beta != 1). A row that never did has
  // e^dp = 0 on every bond in both copies, which its lanes neither read nor write
  // (ordinary_lanes.hpp EpRow): 24 bytes a bond and step less where most rows stay elastic.
  // Recomputed from e^dp after a restart (yield_flags_stale_).
  std::vector<uint8_t> yielded_;
  bool yield_flags_stale_ = false;
  // The plastic multiplier, committed and trial: the sum of the steps' d lambda (header).
  std::vector<double> lambda_, lambda_trial_;
  std::vector<double> theta_;  // the dilatation of the last force pass (an output)
  // Per directed bond: the plastic deviatoric extension (history), committed and trial,
  // and what the ledger needs of the step (below).
  BondHistory<double> ep_;
  HistoryLedger ledger_;  // the step's energy bookkeeping (history_ledger.hpp)
  LedgerRows mode_;       // how this pass's rows read and write the ledger's t and e
};

void ElasticPlastic::setup(const ModelSetup& in) {
  const MaterialConfig& mat = in.material;
  System& s = in.system;
  dim_ = in.config.dimension;
  if (dim_ == 1) throw Error("material '" + mat.name + "': model elastic_plastic needs dimension 2 or 3");
  if (dim_ == 2 && in.config.plane == PlaneMode::stress)
    throw Error("material '" + mat.name +
                "': model elastic_plastic refuses plane: stress. Its plastic extension is deviatoric in the plane "
                "(no dilatation, Silling et al. 2007 eq. 127), but J2 flow with sigma_33 = 0 changes the in-plane "
                "area, and its in-plane yield criterion would put uniaxial yield at 2 sigma_y/sqrt(3). Use plane: "
                "strain or dimension: 3 (docs/models/elastic_plastic.md)");
  particles_ = in.particles;
  bulk_ = lps_bulk_modulus(mat.bulk_modulus, mat.shear_modulus, in.dims);
  mu_ = mat.shear_modulus;
  yield_ = Model::parameter(mat, "yield_stress");
  hardening_ = Model::parameter(mat, "hardening_modulus");
  const std::size_t n = s.particles.size();
  eps_p_.assign(n, 0);
  eps_p_trial_.assign(n, 0);
  flowed_.assign(n, 0);
  yielded_.assign(n, 0);
  lambda_.assign(n, 0);
  lambda_trial_.assign(n, 0);
  theta_.assign(n, 0);
  ledger_.size_particles(n);
  plastic_ = Model::choice(mat, "plasticity") == "on";
  yield_volume_ = 0;
  if (Model::choice(mat, "yield_reference") == "continuum") {
    if (dim_ != 3)
      throw Error("material '" + mat.name + "': yield_reference: continuum is defined in 3-D only (m = 4 pi int omega "
                  "r^4 dr over the sphere)");
    // m of the full sphere: 4 pi int_0^delta omega(r) r^4 dr (= 4 pi delta^5/5 for omega = 1).
    yield_volume_ = 4.0 * std::numbers::pi * influence_moment(mat.influence, in.config.horizon, 4);
  }
  ep_.assign(0, 0);
  size_bonds(s.bonds);
  shear_corrected_ = Model::parameter(mat, "shear_correction") != 0;
  shear_factor_.assign(n, 1.0);
  if (shear_corrected_)
    for (uint32_t i : particles_) shear_factor_[i] = shear_correction_factor(family_of(s, i), dim_);

  // As the LPS (material/models/lps.cpp): spring, contact, critical stretch.
  fill_state_based_coefficients(in);
}

void ElasticPlastic::force_state(ForcePass& pass) {
  const System& s = pass.system;
  const auto& B = s.bonds;
  const auto& M = s.model;
  size_bonds(B);
  const Point4* y = pass.y;
  Vec3* T = pass.T;
  double* energy = pass.energy;
  const KindCoefficients* kc = M.kind.data();
  const int dim = dim_;
  const double factor = lps_deviatoric_factor(dim) * mu_;  // alpha m
  const std::size_t count = particles_.size();
  ledger_.begin_pass();
  const double* ep = ep_.committed();
  double* ep_trial = ep_.trial();
  // The thermal extension eps_ij |xi| of a bond, eps_ij the mean of its ends' thermal
  // strains (System::thermal_strain; none without a temperature field).
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
    const double alpha = shear_factor_[i] * factor / m;
    const double mu = shear_factor_[i] * mu_;
    // |Y| of each bond of the row, computed once and read by the three sweeps below.
    thread_local std::vector<double> deformed;
    deformed.resize(last - first);
    for (uint64_t k = first; k < last; ++k) {
      const Point4 pj = y[B.nbr[k]];
      const double dx = pj.x - pi.x, dy = pj.y - pi.y, dz = pj.z - pi.z;
      deformed[k - first] = std::sqrt(dx * dx + dy * dy + dz * dz);
    }
    // The mechanical extension: e less the bond's thermal extension.
    auto extension = [&](uint64_t k) {
      return deformed[k - first] - kc[B.kind[k]].length - thermal(i, B.nbr[k], kc[B.kind[k]].length);
    };
    // theta = (d/m) sum omega |xi| e V_j over the intact bonds (seed 003 eq. 113, digest sec. 9).
    double sum = 0;
    for (uint64_t k = first; k < last; ++k)
      if (B.intact[k]) sum += kc[B.kind[k]].wv * kc[B.kind[k]].length * extension(k);
    const double theta = dim * sum / m;
    theta_[i] = theta;
    // Trial: t^d_tr = alpha omega (e^d - e^dp_n); its weighted norm^2 (header).
    double n2 = 0;
    for (uint64_t k = first; k < last; ++k) {
      if (!B.intact[k]) continue;
      const KindCoefficients& c = kc[B.kind[k]];
      const double ede = deviatoric_extension(extension(k), theta, c.length, dim) - ep[k];
      n2 += c.wv * ede * ede;
    }
    n2 *= alpha * alpha;
    const ReturnMap r = plastic_ ? ep_return_map(n2, yield_m(m), dim, mu, yield_, hardening_, eps_p_[i]) : ReturnMap{};
    eps_p_trial_[i] = eps_p_[i] + r.plastic_strain;
    const double beta = r.scale;
    if (beta != 1.0) yielded_[i] = 1;
    lambda_trial_[i] = lambda_[i] + plastic_multiplier_step(beta, alpha);
    const double p_coef = dim * bulk_ * theta / m;  // t^i = (d k' theta/m) omega |xi|
    double work = 0, dev = 0, booked = 0;
    bool inelastic = r.plastic_strain > 0;
    for (uint64_t k = first; k < last; ++k) {
      const KindCoefficients& c = kc[B.kind[k]];
      const BondKind& bk = B.kinds[B.kind[k]];
      const double vj = bk.volume * bk.fraction;
      const Point4 pj = y[B.nbr[k]];
      const Vec3 Y{pj.x - pi.x, pj.y - pi.y, pj.z - pi.z};
      const double r_len = deformed[k - first];
      const double e = extension(k);
      const bool booked_now = ledger_.open_bond(k, B.intact[k], T[k], Y, r_len, e, vj, booked);
      const double old_force = ledger_.force.committed()[k], old_extension = ledger_.extension.committed()[k];
      if (booked_now) inelastic = true;
      if (!B.intact[k]) {
        T[k] = {};
        ep_trial[k] = ep[k];
        ledger_.force.trial()[k] = 0;
        if (old_force != 0) {  // it acted at the start of the step
          work += 0.5 * old_force * (e - old_extension) * vj;
          inelastic = true;
        }
        continue;
      }
      const double omega = bk.weight;
      const double ede_trial = deviatoric_extension(e, theta, c.length, dim) - ep[k];
      const double ede = beta * ede_trial;
      ep_trial[k] = ep[k] + (1.0 - beta) * ede_trial;
      dev += c.wv * ede * ede;
      const double t = p_coef * omega * c.length + alpha * omega * ede;
      ledger_.force.trial()[k] = t;
      work += 0.5 * (old_force + t) * (e - old_extension) * vj;
      T[k] = (t / r_len) * Y;
    }
    const double W = 0.5 * bulk_ * theta * theta + 0.5 * alpha * dev;
    ledger_.stored_trial[i] = W;
    // Dissipated in the step: the trapezoidal work of the step less the change of W, less
    // what the force pass booked for the bonds it broke (header and inelastic_loss). Only
    // steps with plastic flow or a broken bond dissipate; an elastic step books exactly 0.
    ledger_.loss_trial[i] = inelastic ? inelastic_loss(work, W - ledger_.stored[i], booked) : 0.0;
    if (energy) energy[i] = W;
  }
}

// The scalar pass's row (ModelTraits::ordinary) in eight lanes (ordinary_lanes.hpp): the
// sums of force_state in the lanes' order, on the |Y| and the dilatation sum of the pass's
// breaking sweep, the row's bonds read from flat arrays: two visits of the row (the yield
// norm needs theta, the forces need the return), the second on what the first brought
// into cache.
void ElasticPlastic::force_row(const RowPass& pass, std::size_t i, double dilatation_sum) {
  if (!lanes::wide()) return force_row_scalar(pass, i, dilatation_sum);
  const System& s = pass.system;
  const auto& B = s.bonds;
  const auto& M = s.model;
  const int dim = dim_;
  const uint64_t first = B.begin(i), last = B.end(i);
  const double m = M.weighted_volume[i];
  const double alpha = shear_factor_[i] * lps_deviatoric_factor(dim) * mu_ / m;
  const double mu = shear_factor_[i] * mu_;
  const double theta = dim * dilatation_sum / m;
  theta_[i] = theta;
  lanes::RowBonds b = lanes::row_bonds(pass, ledger_, mode_, i, true);
  // The trial deviatoric extension e^d - e^dp_n of each bond (kernels::ep_bond's trial),
  // kept from the visit that computes it for a visit that scales it; likewise a rebuilt t_n
  // (ordinary_lanes.hpp RowBonds::t_old).
  thread_local std::vector<double> trial_row, t_old_row;
  if (trial_row.size() < last - first) trial_row.resize(last - first);
  if (b.r_old) {
    if (t_old_row.size() < last - first) t_old_row.resize(last - first);
    b.t_old = t_old_row.data() - first;
  }
  lanes::EpRow row;
  const bool never_yielded = !yielded_[i];
  // Written in place (LedgerRows::in_place), e^dp changes only where the return scales the
  // row (beta != 1): a visit with beta = 1 writes nothing then (ep + 0 * e^de = ep).
  double* const ep_out = mode_.in_place ? ep_.committed() : ep_.trial();
  if (!never_yielded) row.ep = ep_.committed(), row.ep_trial = mode_.in_place ? nullptr : ep_out;
  row.ede = trial_row.data() - first;
  row.theta = theta, row.alpha = alpha, row.p_coef = dim * bulk_ * theta / m, row.dim = dim;
  // The yield norm needs theta, the forces need the return: two visits of the row. A
  // particle that did not flow in its last pass is taken to stay elastic (beta = 1): one
  // visit computes the norm and the elastic forces, and only if the return then scales
  // them (beta != 1) does a second visit write them again. Either way every written value
  // is the two-visit one, bit for bit; a particle that flowed takes the two visits at once.
  const bool guess_elastic = !flowed_[i];
  lanes::RowSums sums = lanes::ep_row(b, row, 1.0, true, guess_elastic);
  const double n2 = sums.norm * (alpha * alpha);
  const ReturnMap rm = plastic_ ? ep_return_map(n2, yield_m(m), dim, mu, yield_, hardening_, eps_p_[i]) : ReturnMap{};
  eps_p_trial_[i] = eps_p_[i] + rm.plastic_strain;
  flowed_[i] = rm.plastic_strain > 0;
  lambda_trial_[i] = lambda_[i] + plastic_multiplier_step(rm.scale, alpha);
  if (rm.scale != 1.0 && !row.ep_trial) {  // e^dp written (a first flow: e^dp_n = 0, not read)
    if (never_yielded) yielded_[i] = 1;
    row.ep_trial = ep_out;
  }
  if (!guess_elastic || rm.scale != 1.0) {
    const lanes::RowSums first = sums;
    b.revisit = guess_elastic;  // the first visit wrote q
    sums = lanes::ep_row(b, row, rm.scale, false, true);
    sums.norm = first.norm;
    // A first visit that opened the bonds with the flags in place booked the bonds broken
    // since the commit and set their flags: the second one finds them booked.
    if (b.revisit && b.booked_in_place) sums.booked = first.booked, sums.inelastic = sums.inelastic || first.inelastic;
  }
  const bool inelastic = rm.plastic_strain > 0 || sums.inelastic;
  const double W = 0.5 * bulk_ * theta * theta + 0.5 * alpha * sums.dev;
  ledger_.stored_trial[i] = W;
  ledger_.loss_trial[i] = inelastic ? inelastic_loss(sums.work, W - ledger_.stored[i], sums.booked) : 0.0;
  if (pass.energy) pass.energy[i] = W;
}

// The row in bond order, without the lanes (ordinary_lanes.hpp wide(): machines without
// AVX-512, where the lanes' eight-wide vectors cost more than they save): the same sums
// in the same order as force_state, three visits of the row at most.
void ElasticPlastic::force_row_scalar(const RowPass& pass, std::size_t i, double dilatation_sum) {
  const System& s = pass.system;
  const auto& B = s.bonds;
  const auto& M = s.model;
  const KindCoefficients* kc = M.kind.data();
  const BondKind* kinds = B.kinds.data();
  const uint32_t* kind = B.kind.data();
  const uint8_t* intact = B.intact.data();
  const double* r = pass.deformed;
  double* q = pass.t;
  const double* ep = ep_.committed();
  double* ep_trial = ep_.trial();
  const double* old_force = ledger_.force.committed();
  const double* old_extension = ledger_.extension.committed();
  double* force_trial = ledger_.force.trial();
  const int dim = dim_;
  const double* eps = s.thermal_strain.empty() ? nullptr : s.thermal_strain.data();
  auto extension = [&](uint64_t k, double length) {
    return r[k] - length - (eps ? 0.5 * (eps[i] + eps[B.nbr[k]]) * length : 0.0);
  };
  const uint64_t first = B.begin(i), last = B.end(i);
  const double m = M.weighted_volume[i];
  const double alpha = shear_factor_[i] * lps_deviatoric_factor(dim) * mu_ / m;
  const double mu = shear_factor_[i] * mu_;
  const double theta = dim * dilatation_sum / m;
  const double p_coef = dim * bulk_ * theta / m;
  const HistoryLedger::Row ledger = ledger_.row();
  // The trial deviatoric extension e^d - e^dp_n of each acting bond (kernels::ep_bond's
  // trial), kept from the visit that computes it for a visit that scales it.
  thread_local std::vector<double> trial_row;
  if (trial_row.size() < last - first) trial_row.resize(last - first);
  double* ede_trial = trial_row.data() - first;
  theta_[i] = theta;
  double n2 = 0;
  auto trial_norm = [&] {  // ||t^d_tr||^2 / alpha^2, in bond order
    for (uint64_t k = first; k < last; ++k) {
      if (!intact[k]) continue;
      const KindCoefficients& c = kc[kind[k]];
      const double ede = deviatoric_extension(extension(k, c.length), theta, c.length, dim) - ep[k];
      ede_trial[k] = ede;
      n2 += kernels::weighted_square(c.wv, ede);
    }
  };
  // One visit of the row with the return's scaling beta: the force states and trial
  // records, and the sums of dev and the step's work. With `norm`, the visit also computes
  // the trial extensions and their norm (trial_norm's operations, in its order).
  double work = 0, dev = 0, booked = 0;
  bool inelastic_bonds = false;
  auto visit = [&](double beta, auto norm) {
    work = 0, dev = 0, booked = 0;
    inelastic_bonds = false;
    for (uint64_t k = first; k < last; ++k) {
      const KindCoefficients& c = kc[kind[k]];
      const BondKind& bk = kinds[kind[k]];
      const double vj = bk.volume * bk.fraction;
      const double e = extension(k, c.length);
      if (ledger.open_bond(k, intact[k], q[k], r[k], e, vj, booked)) inelastic_bonds = true;
      if (!intact[k]) {
        q[k] = 0;
        ep_trial[k] = ep[k];
        force_trial[k] = 0;
        if (old_force[k] != 0) {  // it acted at the start of the step
          work += kernels::released_work(old_force[k], e, old_extension[k], vj);
          inelastic_bonds = true;
        }
        continue;
      }
      if constexpr (decltype(norm)::value) {
        const double ede = deviatoric_extension(e, theta, c.length, dim) - ep[k];
        ede_trial[k] = ede;
        n2 += kernels::weighted_square(c.wv, ede);
      }
      const double omega = bk.weight;
      // kernels/ordinary.hpp: the return's scaling of the bond, its force state and work.
      const kernels::EpBond b{beta * ede_trial[k], ep[k] + (1.0 - beta) * ede_trial[k]};  // kernels::ep_bond
      ep_trial[k] = b.plastic;
      dev += kernels::weighted_square(c.wv, b.elastic);
      const double t = kernels::ordinary_force_scalar(p_coef, omega, c.length, alpha, b.elastic);
      force_trial[k] = t;
      work += kernels::trapezoid_work(old_force[k], t, e, old_extension[k], vj);
    }
  };
  // The yield norm needs theta, the forces need the return: two visits of the row. A
  // particle that did not flow in its last pass is taken to stay elastic (beta = 1): one
  // visit computes the norm and the elastic forces, and only if the return then scales
  // them (beta != 1) does a second visit write them again. Either way every written value
  // is the two-visit one, bit for bit; a particle that flowed takes the two visits at once.
  const bool guess_elastic = !flowed_[i];
  if (guess_elastic)
    visit(1.0, std::true_type{});
  else
    trial_norm();
  n2 *= alpha * alpha;
  const ReturnMap rm = plastic_ ? ep_return_map(n2, yield_m(m), dim, mu, yield_, hardening_, eps_p_[i]) : ReturnMap{};
  eps_p_trial_[i] = eps_p_[i] + rm.plastic_strain;
  flowed_[i] = rm.plastic_strain > 0;
  if (rm.scale != 1.0) yielded_[i] = 1;
  lambda_trial_[i] = lambda_[i] + plastic_multiplier_step(rm.scale, alpha);
  if (!guess_elastic || rm.scale != 1.0) visit(rm.scale, std::false_type{});
  const bool inelastic = rm.plastic_strain > 0 || inelastic_bonds;
  // q = t/|Y| (0 where the bond does not act), vectorised apart from the sums (ordinary_rows.hpp).
  rows::force_scalars(force_trial, r, intact, false, first, last, q);
  const double W = 0.5 * bulk_ * theta * theta + 0.5 * alpha * dev;
  ledger_.stored_trial[i] = W;
  ledger_.loss_trial[i] = inelastic ? inelastic_loss(work, W - ledger_.stored[i], booked) : 0.0;
  if (pass.energy) pass.energy[i] = W;
}

void ElasticPlastic::commit(System& s) {
  const auto& P = s.particles;
  const std::size_t count = particles_.size();
#pragma omp parallel for schedule(static)
  for (std::size_t q = 0; q < count; ++q) {
    const uint32_t i = particles_[q];
    if (!s.computes_row(i)) continue;
    eps_p_[i] = eps_p_trial_[i];
    lambda_[i] = lambda_trial_[i];
    const double loss = ledger_.commit_particle(i);
    if (loss != 0) s.dissipated_at[i] += loss * P.volume[i];
  }
  if (ledger_.commit_bonds(s)) ep_.flip();  // the trial bond records become the committed ones (unless in place)
}

}  // namespace

bool elastic_plastic_state(Model& m, OrdinaryModelState& out) {
  auto* p = dynamic_cast<ElasticPlastic*>(&m);
  if (p) p->flat_state(out);
  return p != nullptr;
}

ModelEntry elastic_plastic_model() {
  return {traits(), [] { return std::unique_ptr<Model>(std::make_unique<ElasticPlastic>()); }};
}

}  // namespace horizon
