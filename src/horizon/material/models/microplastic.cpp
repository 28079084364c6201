#include "horizon/material/models/microplastic.hpp"

#include <cmath>
#include <limits>

#include "horizon/kernels/microplastic.hpp"
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
    m.name = "microplastic";
    m.summary = "proportional microplastic bonds, bond-based elastic-perfectly plastic (Macek and Silling, seed 002 "
                "eq. 19-21)";
    m.elastic = ElasticInput::one_modulus;
    m.parameters = {
        {"yield_stretch",
         "bond yield stretch s_Y [-], the same in tension and compression; the seed's estimate is "
         "sigma_ut/(2 E) (eq. 50)",
         ParameterSpec::Range::positive, std::nullopt},
    };
    m.rows_local = true;  // row i reads i's family and the plastic stretch of i's bonds alone
    m.ordinary = true;    // T = t Y/|Y|: the scalar general pass (force_row)
    return m;
  }();
  return t;
}

class Microplastic final : public Model {
 public:
  std::unique_ptr<Model> clone() const override { return std::make_unique<Microplastic>(*this); }
  const ModelTraits& traits() const override { return horizon::traits(); }

  void setup(const ModelSetup& in) override {
    const MaterialConfig& mat = in.material;
    auto& M = in.system.model;
    c_ = mat.micromodulus ? *mat.micromodulus : pmb_micromodulus(mat.youngs_modulus, mat.influence, in.dims);
    yield_ = Model::parameter(mat, "yield_stretch");
    double s0 = std::numeric_limits<double>::infinity();
    if (mat.damage.enabled) {
      s0 = mat.damage.critical_stretch
               ? *mat.damage.critical_stretch
               : microplastic_critical_stretch(
                     pmb_critical_stretch(*mat.damage.fracture_energy, c_, mat.influence, in.dims), yield_);
    }
    particles_ = in.particles;
    for (uint32_t i : particles_) {
      M.spring[i] = 0.5 * c_;  // the elastic stiffness bounds the tangent: PMB's stable step
      M.contact_micromodulus[i] = c_;
      M.critical_stretch[i] = s0;
      M.alpha[i] = mat.damage.enabled ? mat.damage.alpha : 0.0;
    }
    const std::size_t n = in.system.particles.size();
    ledger_.size_particles(n);
    sbar_.assign(0, 0);
    size_bonds(in.system.bonds);
  }

  void force_state(ForcePass& pass) override {
    const System& s = pass.system;
    const auto& B = s.bonds;
    size_bonds(B);
    const Point4* y = pass.y;
    Vec3* T = pass.T;
    const std::size_t count = particles_.size();
    ledger_.begin_pass();
    const double* sbar_old = sbar_.committed();
    double* sbar_trial = sbar_.trial();
#pragma omp parallel for schedule(static)
    for (std::size_t q = 0; q < count; ++q) {
      const uint32_t i = particles_[q];
      if (!s.computes_row(i)) continue;  // another rank's row (ModelTraits::rows_local)
      const Point4 pi = y[i];
      double W = 0, work = 0, booked = 0;
      bool inelastic = false;
      for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
        const BondKind& bk = B.kind_of(k);
        const double vj = bk.volume * bk.fraction;
        const Point4 pj = y[B.nbr[k]];
        const Vec3 Y{pj.x - pi.x, pj.y - pi.y, pj.z - pi.z};
        const double r = norm(Y);
        const double e = r - bk.length;
        const bool booked_now = ledger_.open_bond(k, B.intact[k], T[k], Y, r, e, vj, booked);
        const double old_force = ledger_.force.committed()[k], old_extension = ledger_.extension.committed()[k];
        inelastic = inelastic || booked_now;
        if (!B.intact[k]) {
          T[k] = {};
          sbar_trial[k] = sbar_old[k];
          ledger_.force.trial()[k] = 0;
          if (old_force != 0) {
            work += kernels::released_work(old_force, e, old_extension, vj);
            inelastic = true;
          }
          continue;
        }
        // t = omega (c/2) (s - sbar): half the pair force (eq. 19); W_i = sum_j (t/2)(s - sbar) |xi| v_j
        // (kernels/microplastic.hpp microplastic_bond).
        const kernels::MicroplasticBond mb = kernels::microplastic_bond(
            e, bk.length, bk.weight, vj, c_, yield_, sbar_old[k], old_force, old_extension);
        sbar_trial[k] = mb.sbar;
        if (mb.yielded) inelastic = true;
        const double t = mb.t;
        W += mb.energy;
        ledger_.force.trial()[k] = t;
        work += mb.work;
        T[k] = (r > 0 ? t / r : 0.0) * Y;
      }
      ledger_.stored_trial[i] = W;
      // Plastic flow or a broken bond: the trapezoidal work of the step less the change of
      // W, less what the force pass booked (history_ledger.hpp); an elastic step books 0.
      ledger_.loss_trial[i] = inelastic ? inelastic_loss(work, W - ledger_.stored[i], booked) : 0.0;
      if (pass.energy) pass.energy[i] = W;
    }
  }

  void begin_rows(const RowPass& pass) override {
    size_bonds(pass.system.bonds);
    mode_ = ledger_.begin_rows(pass.system, lanes::wide());
  }

  // The scalar pass's row (ModelTraits::ordinary) in eight lanes (ordinary_lanes.hpp):
  // force_state's sums in the lanes' order, on the |Y| of the pass's breaking sweep, from
  // flat bond arrays.
  void force_row(const RowPass& pass, std::size_t i, double dilatation_sum) override {
    if (!lanes::wide()) return force_row_scalar(pass, i, dilatation_sum);
    lanes::RowBonds b = lanes::row_bonds(pass, ledger_, mode_, i, false);
    // (in place: over the committed copy, each bond's read before it is written; LedgerRows)
    const lanes::RowSums sums =
        lanes::micro_row(b, {sbar_.committed(), mode_.in_place ? sbar_.committed() : sbar_.trial(), c_, yield_});
    const double W = sums.dev;
    ledger_.stored_trial[i] = W;
    ledger_.loss_trial[i] = sums.inelastic ? inelastic_loss(sums.work, W - ledger_.stored[i], sums.booked) : 0.0;
    if (pass.energy) pass.energy[i] = W;
  }

  // The row in bond order, without the lanes (ordinary_lanes.hpp wide()).
  void force_row_scalar(const RowPass& pass, std::size_t i, double dilatation_sum) {
    (void)dilatation_sum;  // bond-based
    const auto& B = pass.system.bonds;
    const double* r = pass.deformed;
    double* q = pass.t;
    kernels::MicroplasticRow<BondKind> a;
    a.kinds = B.kinds.data(), a.kind = B.kind.data(), a.intact = B.intact.data(), a.r = r;
    a.sbar_old = sbar_.committed(), a.sbar_trial = sbar_.trial();
    a.old_force = ledger_.force.committed(), a.old_extension = ledger_.extension.committed();
    a.force_trial = ledger_.force.trial();
    a.c = c_, a.yield = yield_;
    const HistoryLedger::Row ledger = ledger_.row();
    const kernels::MicroplasticSums sums =
        kernels::microplastic_row(a, B.begin(i), B.end(i), [&](uint64_t k, double e, double vj, double& booked) {
          return ledger.open_bond(k, B.intact[k], q[k], r[k], e, vj, booked);
        });
    const double W = sums.W;
    // q = t/|Y| (0 where the bond does not act), vectorised apart from the sums (ordinary_rows.hpp).
    rows::force_scalars(a.force_trial, r, a.intact, true, B.begin(i), B.end(i), q);
    ledger_.stored_trial[i] = W;
    ledger_.loss_trial[i] = sums.inelastic ? inelastic_loss(sums.work, W - ledger_.stored[i], sums.booked) : 0.0;
    if (pass.energy) pass.energy[i] = W;
  }

  void commit(System& s) override {
    const std::size_t count = particles_.size();
#pragma omp parallel for schedule(static)
    for (std::size_t q = 0; q < count; ++q) {
      const uint32_t i = particles_[q];
      if (!s.computes_row(i)) continue;
      const double loss = ledger_.commit_particle(i);
      if (loss != 0) s.dissipated_at[i] += loss * s.particles.volume[i];
    }
    if (ledger_.commit_bonds(s)) sbar_.flip();  // the trial bond records become the committed ones
  }

  double pending_dissipation(const System& s) const override {
    return ledger_.pending_energy(particles_, s.particles.volume);
  }

  void fields(const System& s, std::vector<ModelField>& out) const override {
    // The largest |plastic stretch| among a particle's bonds.
    std::vector<double> v(s.particles.size(), 0);
    const auto& B = s.bonds;
    if (sbar_.size() == B.size())
      for (uint32_t i : particles_)
        for (uint64_t k = B.begin(i); k < B.end(i); ++k) v[i] = std::max(v[i], std::abs(sbar_.committed()[k]));
    out.push_back({"plastic_stretch", std::move(v)});
  }

  void checkpoint(StateArchive& a) override {
    sbar_.checkpoint(a, "sbar", "sbar_trial", ledger_.fresh);
    ledger_.checkpoint(a);
  }

  // The flat backend's view of the state (material/models/ordinary_flat.hpp).
  void flat_state(OrdinaryModelState& o) {
    o.kind = OrdinaryModelState::microplastic;
    o.dim = 3, o.ledger = &ledger_;
    o.micro_c = c_, o.yield_stretch = yield_, o.sbar = &sbar_;
  }

 private:
  void size_bonds(const Bonds& B) {
    if (sbar_.size() == B.size()) return;
    sbar_.assign(B.size(), 0);
    ledger_.size_bonds(B);
  }

  double c_ = 0, yield_ = 0;
  std::vector<uint32_t> particles_;
  BondHistory<double> sbar_;  // plastic stretch per directed bond, committed and trial
  HistoryLedger ledger_;
  LedgerRows mode_;  // how this pass's rows read and write the ledger's t and e
};

}  // namespace

bool microplastic_state(Model& m, OrdinaryModelState& out) {
  auto* p = dynamic_cast<Microplastic*>(&m);
  if (p) p->flat_state(out);
  return p != nullptr;
}

ModelEntry microplastic_model() {
  return {traits(), [] { return std::unique_ptr<Model>(std::make_unique<Microplastic>()); }};
}

}  // namespace horizon
