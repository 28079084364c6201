// GCC's -Wpsabi note on the pair form's eight-lane vectors (see "eight lanes" below).
#pragma GCC diagnostic ignored "-Wpsabi"
#include "horizon/material/models/extended_correspondence.hpp"

#include <array>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "horizon/core/error.hpp"
#include "horizon/kernels/extended.hpp"
#include "horizon/kernels/hencky.hpp"
#include "horizon/kernels/strain_laws.hpp"
#include "horizon/kernels/unified.hpp"
#include "horizon/material/nonlocal_gradient.hpp"
#include "horizon/parallel/decomposition.hpp"
#include "horizon/state/system.hpp"

namespace horizon {

// A StrainLawState is numbers and a fixed-size Eigen matrix: it checkpoints as its bytes.
template <>
struct plain_data<classical::StrainLawState> : std::true_type {};
// The kept moment maps: two fixed-size Eigen matrices, as bytes.
template <>
struct plain_data<extended::MomentMap> : std::true_type {};

namespace {

// ---- The pair form's eight lanes (pair_*_lanes below) ----
// Bond k of a row goes to lane (k - row start) mod 8 and each lane keeps its own partial
// sums, added as ((l0 + l1) + (l2 + l3)) + ((l4 + l5) + (l6 + l7)) at the row's end
// (kernels/lanes.hpp, as the fast loops and the affine sweeps add theirs). The lanes are
// GCC's eight-double vectors and nothing target-specific (no FMA contraction in this
// file: a lane computes what one bond's scalar code would). They run in the AVX-512 rows
// only (pair_forces); built for AVX2 or x86-64-v2 the same code gave the same bits 1.8x
// slower than the bond-by-bond rows, which those machines keep (their sums round in bond
// order). A lane whose bond does not act adds +0, which changes no sum (a lane's sum
// starts at +0 and never becomes -0).
// The eight-lane vectors never cross a call (every function that takes one is inlined,
// kernels/extended.hpp's too), so GCC's note that their ABI depends on AVX-512 (-Wpsabi,
// silenced at the top of this file) says nothing here.
using v8d = double __attribute__((vector_size(64)));
using v8l = int64_t __attribute__((vector_size(64)));
using v4d = double __attribute__((vector_size(32)));
#define HORIZON_LANE_INLINE __attribute__((always_inline)) inline

// Eight records of (at least) four doubles, one per lane, transposed into four vectors:
// a[l] = p[l][0], ..., d[l] = p[l][3] (eight 32-byte loads and eight permutations).
HORIZON_LANE_INLINE void transpose8(const double* const* p, v8d& a, v8d& b, v8d& c, v8d& d) {
  v4d r[8];
#pragma GCC unroll 8
  for (int l = 0; l < 8; ++l) std::memcpy(&r[l], p[l], sizeof(v4d));
  const v8d z0 = __builtin_shufflevector(r[0], r[1], 0, 1, 2, 3, 4, 5, 6, 7);
  const v8d z1 = __builtin_shufflevector(r[2], r[3], 0, 1, 2, 3, 4, 5, 6, 7);
  const v8d z2 = __builtin_shufflevector(r[4], r[5], 0, 1, 2, 3, 4, 5, 6, 7);
  const v8d z3 = __builtin_shufflevector(r[6], r[7], 0, 1, 2, 3, 4, 5, 6, 7);
  const v8d u0 = __builtin_shufflevector(z0, z1, 0, 4, 8, 12, 1, 5, 9, 13);
  const v8d u1 = __builtin_shufflevector(z0, z1, 2, 6, 10, 14, 3, 7, 11, 15);
  const v8d w0 = __builtin_shufflevector(z2, z3, 0, 4, 8, 12, 1, 5, 9, 13);
  const v8d w1 = __builtin_shufflevector(z2, z3, 2, 6, 10, 14, 3, 7, 11, 15);
  a = __builtin_shufflevector(u0, w0, 0, 1, 2, 3, 8, 9, 10, 11);
  b = __builtin_shufflevector(u0, w0, 4, 5, 6, 7, 12, 13, 14, 15);
  c = __builtin_shufflevector(u1, w1, 0, 1, 2, 3, 8, 9, 10, 11);
  d = __builtin_shufflevector(u1, w1, 4, 5, 6, 7, 12, 13, 14, 15);
}
HORIZON_LANE_INLINE v8d masked(v8l m, v8d v) { return reinterpret_cast<v8d>(m & reinterpret_cast<v8l>(v)); }
// m ? a : b lane by lane, in bit operations (GCC lowers some of its vector conditionals
// lane by lane).
HORIZON_LANE_INLINE v8d select(v8l m, v8d a, v8d b) {
  return reinterpret_cast<v8d>((m & reinterpret_cast<v8l>(a)) | (~m & reinterpret_cast<v8l>(b)));
}
HORIZON_LANE_INLINE double lanes_total(const v8d& v) {
  alignas(64) double a[8];
  std::memcpy(a, &v, sizeof a);
  return kernels::lane_total(a);
}
HORIZON_LANE_INLINE double lanes_min(const v8d& v) {
  alignas(64) double a[8];
  std::memcpy(a, &v, sizeof a);
  return kernels::lane_min(a);
}
HORIZON_LANE_INLINE v8d lanes_sqrt(v8d x) {
  v8d r;
#pragma GCC unroll 8
  for (int l = 0; l < 8; ++l) r[l] = std::sqrt(x[l]);
  return r;
}
// The byte flags of bonds k .. k + count - 1 as lane masks (-1: the flag is set).
using c8 = uint8_t __attribute__((vector_size(8)));
using c64 = uint8_t __attribute__((vector_size(64)));
// (Flags 0, 1 or 2, as Bonds::intact. GCC 12 lowers a vector comparison lane by lane
// wherever its result is kept as an integer mask, so the lanes make their masks with bit
// operations, keep them in the records as all-ones bit patterns, and compare only inside
// a selection of doubles: gt below.)
HORIZON_LANE_INLINE v8l byte_lanes(const uint8_t* flags, uint64_t k, int count, uint64_t total) {
  uint64_t bits = 0;
  if (k + 8 <= total)
    std::memcpy(&bits, flags + k, 8);
  else
    for (int l = 0; l < count; ++l) bits |= static_cast<uint64_t>(flags[k + static_cast<uint64_t>(l)]) << (8 * l);
  if (count < 8) bits &= (uint64_t{1} << (8 * count)) - 1;
  const v8l shift = {0, 8, 16, 24, 32, 40, 48, 56};
  const v8l b = ((v8l{} + static_cast<int64_t>(bits)) >> shift) & 0xff;
  return -((b | (b >> 1)) & 1);
}
// a > b lane by lane as a mask (through a selection of 1.0 or 0.0: bit 52 is 1.0's).
HORIZON_LANE_INLINE v8l gt(v8d a, v8d b) {
  const v8d t = a > b ? v8d{} + 1.0 : v8d{};
  return -((reinterpret_cast<v8l>(t) >> 52) & 1);
}
// A mask kept in a double's bits (all ones: set).
inline double mask_bits(bool set) {
  const int64_t m = set ? -1 : 0;
  double d;
  std::memcpy(&d, &m, sizeof d);
  return d;
}
HORIZON_LANE_INLINE v8l as_mask(v8d v) { return reinterpret_cast<v8l>(v); }
// Lanes 0 .. count - 1 set.
HORIZON_LANE_INLINE v8l count_lanes(int count) {
  const v8l lane = {0, 1, 2, 3, 4, 5, 6, 7};
  return -(((v8l{} + count) - lane - 1) >> 63) - 1;
}
// Lane masks as eight bytes, 1 where the lane's mask is set (byte l: lane l).
HORIZON_LANE_INLINE uint64_t lane_bytes(v8l m) {
  const c64 b = reinterpret_cast<c64>(m & 1);
  const c8 r = __builtin_shufflevector(b, b, 0, 8, 16, 24, 32, 40, 48, 56);
  uint64_t bits;
  std::memcpy(&bits, &r, 8);
  return bits;
}
HORIZON_LANE_INLINE bool any_lane(v8l m) { return lane_bytes(m) != 0; }
// Lane masks back to the bytes of bonds k .. k + count - 1.
HORIZON_LANE_INLINE void store_bytes(uint8_t* flags, uint64_t k, int count, v8l m) {
  const uint64_t bits = lane_bytes(m);
  if (count == 8)
    std::memcpy(flags + k, &bits, 8);
  else
    for (int l = 0; l < count; ++l) flags[k + static_cast<uint64_t>(l)] = static_cast<uint8_t>(bits >> (8 * l));
}
// Eight doubles of bonds k .. k + count - 1 (lanes past count: 0).
HORIZON_LANE_INLINE v8d load_lanes(const double* v, uint64_t k, int count) {
  v8d r = {};
  if (count == 8)
    std::memcpy(&r, v + k, sizeof r);
  else
    for (int l = 0; l < count; ++l) r[l] = v[k + static_cast<uint64_t>(l)];
  return r;
}
// v[k + l] = x[l] for l < count: every lane, also those whose bond does not act (the
// per-bond scratch eps_, rforce_, pair_q_ is read only where the bond acts).
HORIZON_LANE_INLINE void store_lanes(double* v, uint64_t k, int count, v8d x) {
  if (count == 8)
    std::memcpy(v + k, &x, sizeof x);
  else
    for (int l = 0; l < count; ++l) v[k + static_cast<uint64_t>(l)] = x[l];
}
// The lane record of a particle for the pair sum (lane_rec_): A, k_s, and as masks (all
// ones: set) on, mid, on with k_s != 0; then E.
constexpr int kLaneRecord = 16;
constexpr int kLanePK = 12;  // PK column by column, 0, 0, 0

using classical::StrainLaw;
using classical::StrainLawParams;
using classical::StrainLawState;
using extended::Mat3;
using extended::Vec6;

const ModelTraits& traits() {
  static const ModelTraits t = [] {
    ModelTraits m;
    m.name = "extended_correspondence";
    m.summary =
        "Tupek's extended correspondence on Seth-Hill bond strains (thesis eq. 4.2-4.7) with elastic, J2 or modified "
        "Johnson-Cook viscoplasticity and damage, damage-dependent influence (eq. 7.1-7.2)";
    m.min_dimension = 2;
    m.default_influence = InfluenceKind::gaussian;
    // Split over MPI ranks: a rank computes the rows of its owned particles and of their
    // bond neighbours (the general pass's rule) and receives from the owners what those
    // rows read of particles further out, the committed damage (omega_D), the stabilisation
    // modulus and the midpoint residual's E (force_state, exchange_to_ghosts).
    m.rows_local = true;
    m.adaptive_time_step = true;  // spring_factors: the stable step from the current state
    using R = ParameterSpec::Range;
    m.parameters = {
        {"seth_hill_m", "Seth-Hill parameter m of the bond strains (0: logarithmic, 1/2: engineering)", R::any, 0.0},
        {"stabilization", "bond-level stabilisation G_s: W_s = G_s mu_bar (d/sum w) sum w (eps - n.E n)^2; 0: off",
         R::non_negative, 0.0},
        {"stabilization_yield",
         "j2, johnson_cook: cap of the bond stabilisation stress 2 k_s (r - r_p) as a multiple of the current flow "
         "stress; the excess flows into a per-bond plastic residual r_p (dissipated); 0: no cap",
         R::non_negative, 0.0},
        {"yield_stress", "j2: initial yield stress [Pa]; johnson_cook: sigma_0 [Pa]", R::non_negative, 0.0},
        {"hardening_modulus", "j2: linear isotropic hardening modulus H [Pa]", R::non_negative, 0.0},
        {"hardening_coefficient", "johnson_cook: B [Pa] (eps_p0 = (sigma_0/B)^(1/n))", R::non_negative, 0.0},
        {"hardening_exponent", "johnson_cook: n", R::positive, 1.0},
        {"rate_coefficient", "johnson_cook: C of the asinh rate term", R::non_negative, 0.0},
        {"reference_rate", "johnson_cook: reference plastic strain rate [1/s]", R::positive, 1.0},
        {"failure_d1", "johnson_cook damage: d1 of eps_f = [d1 + d2 exp(-d3 sigma_m/sigma_e)][1 + d4 ln(rate/rate_0)]",
         R::any, 0.0},
        {"failure_d2", "johnson_cook damage: d2", R::any, 0.0},
        {"failure_d3", "johnson_cook damage: d3", R::any, 0.0},
        {"failure_d4", "johnson_cook damage: d4", R::any, 0.0},
        {"failure_reference_rate", "johnson_cook damage: reference rate of eps_f [1/s]", R::positive, 1.0},
        {"critical_damage",
         "D_c of the damage-dependent influence: bonds to a particle with D > D_c stop acting and it carries no "
         "stress; 1: off",
         R::fraction, 0.99},
        {"shape_tolerance",
         "smallest reciprocal condition number of the shape tensor; below it the particle carries no stress",
         R::fraction, 1e-4},
        {"min_acting_fraction",
         "smallest share of the family's influence weight sum w V that may still act (omega_D drops bonds); below it "
         "the particle carries no stress (its stiffness grows as the inverse of the share: the step would not hold); "
         "0: off",
         R::fraction, 0.0},
    };
    m.choices = {
        {"stress_law", "law on the nonlocal strain E_(m): elastic (isotropic quadratic), j2 (linear hardening), "
                       "johnson_cook (Tupek's modified Johnson-Cook with damage)",
         {"elastic", "j2", "johnson_cook"}},
        {"strain_measure",
         "seth_hill: Tupek's E_(m) = sum w eps_(m) H (eq. 4.3); hencky: the logarithm of the nonlocal Cauchy-Green "
         "tensor I + 2 E_(1) (Green bond strains, exact for homogeneous finite strain; seth_hill_m unused)",
         {"seth_hill", "hencky"}},
        {"stabilization_residual",
         "the bond residual the stabilisation acts on: full, r = eps - n.E_i n; midpoint, r = eps - n.(E_i + E_j)/2 n "
         "(E at both ends of the bond: a smooth strain gradient leaves only O(h^2), a zero-energy mode all of it)",
         {"full", "midpoint"}},
        {"stabilization_softening",
         "none: the stabilisation modulus k_s = G_s mu_bar d/sum w stays; secant: k_s x s_f/(s_f + 3 mu eps_p) (s_f the "
         "flow stress at the committed plastic strain eps_p: the secant shear modulus of the flow curve over mu), "
         "updated at each commit, the stabilisation energy it releases booked as plastic work",
         {"none", "secant"}},
        {"volumetric_strain",
         "the trace of the strain the law sees: average (that of the nonlocal strain E) or gradient (ln det F of the "
         "classical nonlocal deformation gradient over the same bonds: no Jensen bias across a deformation gradient)",
         {"average", "gradient"}},
    };
    return m;
  }();
  return t;
}

class ExtendedCorrespondence final : public Model {
 public:
  std::unique_ptr<Model> clone() const override { return std::make_unique<ExtendedCorrespondence>(*this); }
  const ModelTraits& traits() const override { return horizon::traits(); }

  void setup(const ModelSetup& in) override;
  void force_state(ForcePass& pass) override;
  bool takes_pair_pass(const System& s) const override;
  uint64_t pair_forces(System& s, bool energy) override;
  void commit(System& s) override;

 private:
  // What the pair form's rows read of the pass (pair_forces).
  struct PairPass {
    System& system;
    const Point4* y;
    const Vec3* X;
    const KindCoefficients* kcs;
    const BondKind* kinds;
    bool after;          // break_after_force
    const double* soft;  // the critical-stretch factors, or null
    const ForcePass* pass;
    bool energy;
    bool keep_q;  // some bond may break in the next pass: pair_q_ is written (pair_forces)
    // The rows in the eight lanes (pair_forces: kinds with their lengths, no temperature-
    // dependent critical stretch, the material holding every particle in order):
    bool lanes;
    bool contact;             // the family contact acts (per lane, scalar)
    const Point4* ref;        // per particle {X, 1: D > D_c (omega_D)}
    const Point4* kind4;      // per kind {L, 1/L, omega, V_j (partial-volume scaled)}
    const Point4* contact4;   // per kind {d^2, d, k, 0} of the family contact (KindCoefficients)
  };
  uint64_t pair_break_lanes(const PairPass& c, std::size_t l, uint32_t& count, Vec6& S, Mat3& N, double& smin,
                            double& lost);
  void pair_stabilisation_lanes(const PairPass& c, std::size_t l, const Vec6& Ei, double ks, Vec6& Rp, double& Ws);
  bool pair_sum_lanes(const PairPass& c, std::size_t i);
  void book_break(const PairPass& c, std::size_t i, uint64_t k, double r, double e, double& lost);
  void lane_record(std::size_t l);
  uint64_t pair_break_row(const PairPass& c, std::size_t l);
  void pair_law_row(const PairPass& c, std::size_t l);
  void pair_sum_row(const PairPass& c, std::size_t i);
  uint64_t pair_break_base(const PairPass& c, std::size_t l);
  void pair_law_base(const PairPass& c, std::size_t l);
  void pair_sum_base(const PairPass& c, std::size_t i);
  uint64_t pair_break_avx512(const PairPass& c, std::size_t l);
  void pair_law_avx512(const PairPass& c, std::size_t l);
  void pair_sum_avx512(const PairPass& c, std::size_t i);

 public:
  double pending_dissipation(const System& s) const override {
    double sum = 0;
    for (std::size_t l = 0; l < particles_.size(); ++l)
      sum += (work_[l] + released(l) + switched_[l] + thinned_[l]) * s.particles.volume[particles_[l]];
    return sum;
  }
  void fields(const System& s, std::vector<ModelField>& out) const override;
  bool spring_factors(const System& s, std::vector<double>& g) const override;

  // Every per-particle array is indexed by the material's particle list (io_listed: a
  // checkpoint of a decomposed run takes each entry from the particle's owner, the bonds'
  // from their row's owner). The moment maps are kept with the acting-set size they were
  // built for and the bonds that acted at the last pass: a change of the acting set in
  // the first step after a restart then prices the old set as the uninterrupted run does.
  void checkpoint(StateArchive& a) override {
    a.io_listed("committed", committed_, particles_);
    a.io_listed("trial", trial_, particles_);
    a.io_listed("work", work_, particles_);
    a.io_listed("energy", energy_, particles_);
    a.io_listed("von_mises", von_mises_, particles_);
    a.io_listed("inactive", inactive_, particles_);
    a.io_listed("map_ok", map_ok_, particles_);
    a.io_listed("plastic_total", plastic_total_, particles_);
    a.io_listed("failure_total", failure_total_, particles_);
    a.io_listed("acting_set_total", thinned_total_, particles_);
    a.io_listed("stabilization_modulus", ks_, particles_);
    a.io_listed("acting_count", acting_, particles_);
    a.io_listed("acting_share", acting_share_, particles_);
    a.io_listed("moment_map", maps_, particles_);
    std::vector<std::array<double, 9>> kinv(kinv_.size());
    for (std::size_t l = 0; l < kinv_.size(); ++l) std::copy(kinv_[l].data(), kinv_[l].data() + 9, kinv[l].begin());
    a.io_listed("shape_inverse", kinv, particles_);
    if (a.loading()) {
      kinv_.resize(kinv.size());
      for (std::size_t l = 0; l < kinv.size(); ++l) std::copy(kinv[l].begin(), kinv[l].end(), kinv_[l].data());
    }
    a.io_bonds("acted", acted_);
    // The pair form's booking of a bond broken in the next pass: its force state of the
    // last pass, rebuilt from these (pair_forces).
    std::vector<std::array<double, 9>> pk(pair_pk_.size());
    for (std::size_t l = 0; l < pair_pk_.size(); ++l) std::copy(pair_pk_[l].data(), pair_pk_[l].data() + 9, pk[l].begin());
    a.io_listed("pair_pressure_map", pk, particles_);
    if (a.loading()) {
      pair_pk_.resize(pk.size());
      for (std::size_t l = 0; l < pk.size(); ++l) std::copy(pk[l].begin(), pk[l].end(), pair_pk_[l].data());
    }
    a.io_bonds("pair_force_scalar", pair_q_);
    a.io_particles("pair_position", pair_y_);
    if (stab_yield_ > 0) {
      a.io_bonds("plastic_residual", rp_committed_);
      if (a.loading()) rp_trial_ = rp_committed_;
    }
  }
 private:
  // A decomposed run on more than one rank: `width` (<= 9) numbers per particle of this
  // material, packed by pack(l, v) on every rank, go from each owner to the ranks that hold
  // the particle as a ghost (parallel/decomposition.hpp exchange_ghost_values, three
  // numbers a message entry), where unpack(l, v) takes them for every particle this rank
  // does not own. Collective: every rank calls it at the same point of every pass (its
  // model exists on every rank, with or without particles). Nothing serially.
  template <class Pack, class Unpack>
  void exchange_to_ghosts(const System& s, int width, Pack pack, Unpack unpack) {
    Decomposition* d = s.decomposition;
    if (!d || d->size == 1) return;
    const std::size_t n = particles_.size(), groups = static_cast<std::size_t>((width + 2) / 3);
    exchange_.resize(groups);
    double v[9] = {};
    for (auto& g : exchange_) g.assign(s.particles.size(), Vec3{});
    for (std::size_t l = 0; l < n; ++l) {
      pack(l, v);
      for (std::size_t g = 0; g < groups; ++g)
        exchange_[g][particles_[l]] = {v[3 * g], v[3 * g + 1], v[3 * g + 2]};
    }
    for (auto& g : exchange_) exchange_ghost_values(*d, g);
    for (std::size_t l = 0; l < n; ++l) {
      const uint32_t i = particles_[l];
      if (d->owns(i)) continue;
      for (std::size_t g = 0; g < groups; ++g) {
        const Vec3& e = exchange_[g][i];
        v[3 * g] = e.x, v[3 * g + 1] = e.y, v[3 * g + 2] = e.z;
      }
      unpack(l, v);
    }
  }
  std::vector<std::vector<Vec3>> exchange_;  // exchange_to_ghosts' buffers
  // Once per pass, both forms: the per-bond scratch sized, the ghosts' committed damage and
  // stabilisation modulus from their owners, omega_D's flag of every particle.
  void begin_pass(const System& s);
  void rebuild_map(const Bonds& B, const std::vector<Vec3>& X, std::size_t l, uint32_t i, uint32_t count);
  void exchange_midpoint(const System& s);

  // Elastic energy released by a particle that fails in this step [J/m^3]: its damage
  // passes D_c (omega_D drops its bonds) or reaches 1 (the law stops carrying stress,
  // the only failure when D_c = 1).
  bool failed_state(const StrainLawState& st) const { return st.damage > critical_ || st.damage >= 1.0; }
  double released(std::size_t l) const {
    return !failed_state(committed_[l]) && failed_state(trial_[l]) ? energy_[l] : 0.0;
  }
  // The law at the nonlocal strain E of particle l from its committed state. strain
  // (hencky: E_log = ln(I + 2E)/2; seth_hill: E itself) is what the law sees, except with
  // volumetric_strain gradient (Fbar set): its trace is replaced by ln det Fbar, Fbar the
  // classical nonlocal deformation gradient over the same bonds (material/nonlocal_gradient.hpp),
  //   E' = E_log + ((ln J - I_d : E_log)/d) I_d   (I_d the identity of the d in-plane axes),
  // which is E_log for every homogeneous deformation. Why: E averages the Green bond
  // strains, and across a deformation gradient the average of C is more than C of the
  // average deformation (the variance of F adds to it: Jensen), a positive trace that
  // the bulk modulus prices elastically and that never yields; ln det Fbar is linear in
  // the bonds (no such bias). The law's stress T splits accordingly:
  //   T : dE' = (T - p I_d) : dE_log + p d(ln J),  p = (I_d : T)/d,
  // the first part through the central force (4.7), the second as the classical
  // correspondence force of p Fbar^-T (d ln J = Fbar^-T : dFbar): T_k += omega p Fbar^-T K^-1 xi.
  // The law row in the portable kernel (kernels/extended_law.hpp extended_law_row: Fbar =
  // N K^-1, the Hencky map, the volumetric gradient's corrections, the strain law, the
  // pressure map P K^-1, a = dual(S) when `inv` (M^-1) is given, the von Mises stress; the
  // host's former Eigen forms' bits), the history copied row-major in and out.
  bool law_row(std::size_t l, const Vec6& E, const Mat3& N, const Mat3& Kinv, const double* inv, double dt,
               StrainLawState& trial, kernels::ExtendedLawRow& out) const {
    kernels::ExtendedLawHistory ht;
    kernels::extended_law_row(kext_, inv, E.data(), N.data(), Kinv.data(), history_in(l), dt, ht, out);
    history_out(ht, trial);
    return out.ok;
  }
  kernels::ExtendedLawHistory history_in(std::size_t l) const {
    const StrainLawState& c = committed_[l];
    kernels::ExtendedLawHistory h;
    for (int k = 0; k < 9; ++k) h.Ep[k] = c.plastic_strain(k / 3, k % 3);
    h.alpha = c.alpha, h.damage = c.damage;
    return h;
  }
  static void history_out(const kernels::ExtendedLawHistory& h, StrainLawState& trial) {
    for (int k = 0; k < 9; ++k) trial.plastic_strain(k / 3, k % 3) = h.Ep[k];
    trial.alpha = h.alpha, trial.damage = h.damage;
  }

  // Sweep 1's end, both forms: particle l's E over its acting bonds (and N = sum w Y (x) xi
  // for Fbar), kept for sweep 2; with the midpoint residual also sent to the other ends.
  void keep_strain(std::size_t l, const Vec6& E, const Mat3& N) {
    e_fin_[l] = 1;
    e_full_[l] = E;
    if (vol_gradient_) n_sum_[l] = N;
    if (midpoint_ && committed_[l].damage < 1.0) {
      e_vec_[l] = E;
      e_ok_[l] = 1;
    }
  }
  // Sweep 2's per-particle part, both forms: the pricing of a changed acting set (its
  // energy and plastic work over the old set at these positions, energy_with), the law at
  // sweep 1's E (e_full_; Fbar from n_sum_: the same sums over the same acting set as a
  // second summation would give, bit for bit), and the state of a particle that carries
  // no stress in this pass (false; its force states are the caller's to clear). `pair`:
  // energy_with overwrote the strains of the old set's bonds, and the acting ones are
  // written again with the pair pass's pair_strain instead of the vector form's.
  struct RowLaw {
    kernels::ExtendedLawRow out{};  // S, the law's stress, PK = p Fbar^-T K^-1, a = dual(S), W, ...
    double before = 0;               // a changed set: energy + plastic work over the old set
    bool changed = false;            // the acting set of an active particle changed in this pass
  };
  bool row_law(const ForcePass& pass, std::size_t l, uint32_t i, bool pair, RowLaw& r) {
    return row_law(pass, l, i, pair, r, [&](kernels::ExtendedLawRow& out) {
      return law_row(l, e_full_[l], n_sum_[l], kinv_[l], maps_[l].inverse(), pass.dt, trial_[l], out);
    });
  }
  // The same with the law row computed by law(out) (the pair form: the whole row in one kernel).
  template <class Law>
  bool row_law(const ForcePass& pass, std::size_t l, uint32_t i, bool pair, RowLaw& r, Law law) {
    const System& s = pass.system;
    const Bonds& B = s.bonds;
    const std::vector<Vec3>& X = s.particles.X;
    bool ok = !(committed_[l].damage > critical_) && map_ok_[l] != 0;
    r.changed = changed_[l] != 0;
    if (r.changed && pair) {
      r.before = pair_energy_with(pass, l);  // leaves eps_ as sweep 1 wrote it
    } else if (r.changed) {
      r.before = energy_with(pass, l, old_maps_[l], old_kinv_[l], [&](uint64_t k) { return acted_[k] != 0; });
      const Point4 yi = pass.y[i];
      for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
        if (!acts_[k]) continue;
        const uint32_t j = B.nbr[k];
        const Vec3 xi = X[j] - X[i], Y{pass.y[j].x - yi.x, pass.y[j].y - yi.y, pass.y[j].z - yi.z};
        const double c = dot(Y, Y) / dot(xi, xi);
        eps_[k] = pair ? extended::pair_strain(dot(Y, Y) * pair_inv2(s, k), m_) : seth_hill_strain(c, m_);
      }
    }
    ok = ok && e_fin_[l] != 0;
    if (ok) {
      ok = law(r.out);
    } else {
      trial_[l] = committed_[l];
    }
    inactive_[l] = ok ? 0 : 1;
    work_[l] = ok ? r.out.plastic_work : 0.0;
    if (ok) return true;
    if (!rp_trial_.empty())
      for (uint64_t k = B.begin(i); k < B.end(i); ++k) rp_trial_[k] = rp_committed_[k];
    energy_[l] = von_mises_[l] = 0;
    if (pass.energy) pass.energy[i] = 0;
    if (r.changed) switched_[l] += r.before;
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) acted_[k] = 0;
    return false;
  }
  // Sweep 2's end for a particle that carries stress, both forms: W its energy density.
  void row_end(const ForcePass& pass, std::size_t l, uint32_t i, const RowLaw& r, double W) {
    const Bonds& B = pass.system.bonds;
    energy_[l] = W;
    if (r.changed) thinned_[l] += r.before - (W + work_[l]);
    // acted_ = acts_ over the row (a copy: the byte loop does not vectorise through the members).
    if (B.end(i) > B.begin(i)) std::memcpy(&acted_[B.begin(i)], &acts_[B.begin(i)], B.end(i) - B.begin(i));
    von_mises_[l] = r.out.von_mises;
    if (pass.energy) pass.energy[i] = W;
  }
  // The volumetric gradient's bond terms (kernels/extended_law.hpp, Eigen's bits): N += w Y (x) xi,
  // the force term w P xi of a column-major P (PK), and P v.
  static void gradient_add(Mat3& N, double w, const Vec3& Y, const Vec3& xi) {
    const double y[3] = {Y.x, Y.y, Y.z}, x[3] = {xi.x, xi.y, xi.z};
    kernels::gradient_outer_add(N.data(), w, y, x);
  }
  static Vec3 pressure_term(const double* PK, double w, const Vec3& xi) {
    const double x[3] = {xi.x, xi.y, xi.z};
    double t[3];
    kernels::pressure_bond_term(PK, w, x, t);
    return {t[0], t[1], t[2]};
  }
  static Vec3 pressure_sum(const double* PK, const Vec3& v) {
    const double x[3] = {v.x, v.y, v.z};
    double t[3];
    kernels::mat3c_vec(PK, x, t);
    return {t[0], t[1], t[2]};
  }
  // 1/|xi|^2 of bond k from its kind's 1/|xi| (the same bits from either end).
  static double pair_inv2(const System& s, uint64_t k) {
    const double v = s.model.kind[s.bonds.kind[k]].inv_length;
    return v * v;
  }

  // The energy density plus the step's plastic work [J/m^3] of particle l at the pass's
  // positions over the bonds `acts` selects, with the moment map `map`, from the committed
  // state (the trial state is discarded): the same sums as force_state. It prices a change
  // of the acting set (below, switched_).
  template <class Acts>
  double energy_with(const ForcePass& pass, std::size_t l, const extended::MomentMap& map, const Mat3& Kinv,
                     Acts acts) {
    const Bonds& B = pass.system.bonds;
    const std::vector<Vec3>& X = pass.system.particles.X;
    const uint32_t i = particles_[l];
    const Point4 yi = pass.y[i];
    auto deformed = [&](uint32_t j) { return Vec3{pass.y[j].x - yi.x, pass.y[j].y - yi.y, pass.y[j].z - yi.z}; };
    extended::NonlocalStrain E(dim_, m_);
    E.use(map);
    Mat3 N = Mat3::Zero();
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
      if (!acts(k)) continue;
      const Vec3 xi = X[B.nbr[k]] - X[i], Y = deformed(B.nbr[k]);
      const double w = B.weight[k] * B.volume[k];
      eps_[k] = E.add_strain(xi, Y, w);
      if (vol_gradient_) gradient_add(N, w, Y, xi);
    }
    if (!E.finish(false)) return 0.0;
    StrainLawState scratch;
    kernels::ExtendedLawRow out;
    if (!law_row(l, E.strain_vector(), N, Kinv, nullptr, pass.dt, scratch, out)) return 0.0;
    if (ks_[l] == 0) return out.W + out.plastic_work;
    const Stabilisation st = stabilisation(B, X, i, l, E, acts, scratch.alpha, out.rate, false);
    return out.W + out.plastic_work + st.W + st.work;
  }

  // energy_with for the pair form: the old set's energy and plastic work over the bonds
  // that acted at the last pass (acted_), with the old map and K^-1 (old_maps_, old_kinv_),
  // in the pair form's geometry (n from the kind's 1/|xi|, its bond strain pair_strain: the
  // strain of a bond that still acts is sweep 1's, eps_, left as it is) and its
  // stabilisation energy (the uncapped one of pair_law_row). Only the ledger reads it
  // (the pricing of a changed set), so the forces keep their bits.
  double pair_energy_with(const ForcePass& pass, std::size_t l) {
    const System& s = pass.system;
    const Bonds& B = s.bonds;
    const std::vector<Vec3>& X = s.particles.X;
    const KindCoefficients* kcs = s.model.kind.data();
    const uint32_t i = particles_[l];
    const Point4 yi = pass.y[i];
    const uint64_t begin = B.begin(i), end = B.end(i);
    static thread_local std::vector<double> eps_old;  // the old set's strains (no allocation once grown)
    if (eps_old.size() < end - begin) eps_old.resize(end - begin);
    Vec6 S = Vec6::Zero();
    Mat3 N = Mat3::Zero();
    for (uint64_t k = begin; k < end; ++k) {
      if (!acted_[k]) continue;
      const uint32_t j = B.nbr[k];
      const Vec3 Y{pass.y[j].x - yi.x, pass.y[j].y - yi.y, pass.y[j].z - yi.z}, xi = X[j] - X[i];
      const double inv = kcs[B.kind[k]].inv_length;
      const double eps = acts_[k] ? eps_[k] : kernels::pair_strain(dot(Y, Y) * (inv * inv), m_);
      eps_old[k - begin] = eps;
      const Vec3 nv = inv * xi;
      const double n[3] = {nv.x, nv.y, nv.z};
      double h[6];
      kernels::unit_shape_state(n, dim_, h);
      const BondKind& bk = B.kinds[B.kind[k]];
      const double w = bk.weight * (bk.volume * bk.fraction);
      kernels::strain_sum_add(S.data(), w * eps, h);
      if (vol_gradient_) gradient_add(N, w, Y, xi);
    }
    const Vec6 E = old_maps_[l].solve(S);
    if (!E.allFinite()) return 0.0;
    StrainLawState scratch;
    kernels::ExtendedLawRow lp;
    if (!law_row(l, E, N, old_kinv_[l], nullptr, pass.dt, scratch, lp)) return 0.0;
    const double ks = ks_[l];
    if (ks == 0) return lp.W + lp.plastic_work;
    double Ws = 0;
    for (uint64_t k = begin; k < end; ++k) {
      if (!acted_[k]) continue;
      const uint32_t j = B.nbr[k];
      const Vec3 nv = kcs[B.kind[k]].inv_length * (X[j] - X[i]);
      const double n[3] = {nv.x, nv.y, nv.z};
      double p[6];
      kernels::unit_normal_projector(n, p);
      const int32_t lj = midpoint_ ? local_[j] : -1;
      const double eps = eps_old[k - begin];
      double r, coef = ks;
      if (lj >= 0 && e_ok_[lj]) {
        r = eps - kernels::dot6_mid(p, E.data(), e_vec_[lj].data());
        coef = 0.5 * (ks + ks_[lj]);
      } else {
        r = eps - kernels::dot6(p, E.data());
      }
      const BondKind& bk = B.kinds[B.kind[k]];
      const double w = bk.weight * (bk.volume * bk.fraction);
      Ws += coef * w * r * r;
    }
    return lp.W + lp.plastic_work + Ws;
  }

  // The bond-level stabilisation of particle i (local index l) at the strain E (eps_ holds
  // the acting bonds' strains): W_s,i = sum_k k_k w_k r_k^2 with
  //   stabilization_residual full: r_k = eps_k - n_k . E_i n_k - r_p,k, k_k = k_s,i;
  //   midpoint: r_k = eps_k - n_k . (E_i + E_j)/2 n_k - r_p,k, k_k = (k_s,i + k_s,j)/2, E_j
  //     the strain of the bond's other end in this pass (Ej_; an end that carries no stress,
  //     or of another model: the full residual with k_s,i),
  // r_p the capped stabilisation's plastic residual (stabilization_yield). The midpoint
  // residual appears in both ends' W_s with the same value (symmetric families, w_ij =
  // w_ji); summed over both, dW_s = sum_i 2 sum_k k_k w_k r_k (d eps_k - n_k . dE_i n_k),
  // the form (**) with r -> r_force = k_k r / k_s,i (written to rforce_) and R = sum w
  // r_force n n. write: the trial r_p is written (a force pass) or not (energy_with).
  struct Stabilisation {
    Mat3 R = Mat3::Zero();  // sum_k w_k r_force_k n n
    double W = 0, work = 0;  // W_s [J/m^3] and the capped part's dissipation in the step
  };
  template <class Acts>
  Stabilisation stabilisation(const Bonds& B, const std::vector<Vec3>& X, uint32_t i, std::size_t l,
                              const extended::NonlocalStrain& E, Acts acts, double alpha, double rate, bool write) {
    // The bond loop is a portable kernel (kernels/extended_law.hpp vector_stabilisation_row:
    // this loop's Eigen form, the same bits).
    Stabilisation out;
    const double ks = ks_[l];
    const bool capped = stab_yield_ > 0 && !rp_committed_.empty();
    const double r_c = capped ? stab_yield_ * kernels::strain_flow(kext_.law, alpha, rate) / (2.0 * gs_mu_bar_) : 0.0;
    auto bond = [&](uint64_t k, kernels::VectorStabilisationBond& b) {
      if (!acts(k)) return false;
      const uint32_t j = B.nbr[k];
      const Vec3 xi = X[j] - X[i];
      b.xi[0] = xi.x, b.xi[1] = xi.y, b.xi[2] = xi.z;
      b.eps = eps_[k];
      b.w = B.weight[k] * B.volume[k];
      const int32_t lj = midpoint_ ? local_[j] : -1;
      b.mid = lj >= 0 && e_ok_[lj];
      b.Ej = b.mid ? e_vec_[lj].data() : nullptr;
      b.ksj = b.mid ? ks_[lj] : 0.0;
      return true;
    };
    kernels::VectorStabilisation st;
    kernels::vector_stabilisation_row(B.begin(i), B.end(i), bond, E.strain_vector().data(), ks, capped, r_c,
                                      capped ? rp_committed_.data() : nullptr,
                                      capped && write ? rp_trial_.data() : nullptr, rforce_.data(), st);
    for (int k = 0; k < 9; ++k) out.R(k / 3, k % 3) = st.R[k];
    out.W = st.W, out.work = st.work;
    return out;
  }
  bool failed_committed(uint32_t i) const {
    const int32_t l = local_[i];
    return l >= 0 && committed_[l].damage > critical_;
  }
  // omega_D (thesis eq. 7.2): bond k of particle l acts while it is intact and neither end
  // has D > D_c.
  bool bond_acts(const Bonds& B, std::size_t l, uint64_t k) const {
    return B.intact[k] && !(committed_[l].damage > critical_) && !failed_committed(B.nbr[k]);
  }

  StrainLawParams law_;
  kernels::ExtendedLawConstants kext_;  // law_ and the measures for the portable law row (law_row)
  int dim_ = 3;
  double m_ = 0, critical_ = 0.99, tolerance_ = 1e-4, min_acting_ = 0;
  std::vector<double> family_weight_;  // per particle: sum of w V over its reference family
  std::vector<double> acting_share_;   // per particle: the acting set's share of it (output field)
  bool hencky_ = false;  // strain_measure hencky (extended_correspondence.hpp, HenckyMap)
  double stab_yield_ = 0;  // stabilization_yield (0: elastic stabilisation)
  double gs_mu_bar_ = 0;   // G_s mu_bar [Pa]
  std::vector<double> rp_committed_, rp_trial_;  // per bond: the plastic residual r_p
  std::vector<uint32_t> particles_;
  std::vector<int32_t> local_;   // particle index -> index in particles_ (-1: not ours)
  std::vector<double> ks_;       // stabilisation modulus per particle [Pa] (softened: stabilization_softening)
  std::vector<double> ks0_;      // its unsoftened value
  std::vector<double> ws_;       // per particle: the stabilisation energy W_s of the last pass [J/m^3]
  bool secant_ = false;          // stabilization_softening secant
  bool adaptive_ = false;        // solver.adaptive_time_step: spring_factors from the current state
  std::vector<StrainLawState> committed_, trial_;
  std::vector<double> work_, energy_, von_mises_;
  // Per particle, the energy [J/m^3] a change of its acting set in this step released
  // (> 0) or added (< 0) at fixed positions: (W + plastic work) over the old set minus
  // over the new one. omega_D drops the bonds to a failed neighbour and M^-1 renormalises
  // the family; without this the jump leaves the strain energy and enters no account of
  // the ledger. switched_: a particle the guards (min_acting_fraction, shape tensor)
  // switch off, its whole energy (booked with the failure energy); thinned_: a particle
  // that keeps acting on fewer bonds, signed (output field acting_set_energy).
  std::vector<double> switched_, thinned_;
  std::vector<double> thinned_total_;  // accumulated thinned_ [J/m^3]
  std::vector<uint8_t> acted_;  // per bond: 1 when it acted at the last pass
  // The dissipation booked so far [J/m^3], split: plastic work (the law's and the capped
  // stabilisation's) and the elastic energy of particles that failed (output fields
  // plastic_work and failure_energy; summary.json energy.dissipated_parts).
  std::vector<double> plastic_total_, failure_total_;
  std::vector<uint8_t> inactive_;  // 1: carried no stress at the last pass (failed or singular)
  std::vector<double> eps_;        // per bond: the bond strain of the pass (scratch)
  std::vector<double> rforce_;  // per bond: the force's r (scratch, stabilisation())
  bool midpoint_ = false;       // stabilization_residual midpoint
  std::vector<Vec6> e_vec_;     // per particle: E of this pass (midpoint; first sweep)
  std::vector<uint8_t> e_ok_;   // 1: it carries stress in this pass
  std::vector<uint8_t> changed_;  // 1: its acting set changed in this pass (first sweep)
  std::vector<extended::MomentMap> old_maps_;  // the map and K^-1 before the change
  std::vector<Mat3> old_kinv_;
  std::vector<extended::MomentMap> maps_;  // per particle: the kept moment map
  std::vector<Mat3> kinv_;                 // per particle: K^-1 of the acting set (volumetric_strain gradient)
  bool vol_gradient_ = false;              // volumetric_strain gradient
  std::vector<uint32_t> acting_;           // its acting-set size (UINT32_MAX: not built)
  std::vector<uint8_t> map_ok_;            // 1: the map and the shape tensor passed the guard
  // Scratch of one pass (issue 31: each bond's acting flag and strain computed once, in
  // sweep 1, and read by sweep 2): per particle of the system, 1 when it is ours and its
  // committed damage passes D_c (omega_D); per bond, 1 when it acts in this pass; per
  // particle of this material, E of sweep 1 (e_full_, valid when e_fin_) and
  // sum w Y (x) xi (n_sum_, volumetric_strain gradient).
  std::vector<uint8_t> failed_at_, acts_, e_fin_;
  // The pair form (pair_forces): per particle of this material, what the pair sum reads of
  // both ends of a bond; T_ij = omega g (A_i . h + 2 coef r_i) Y + omega PK_i xi
  // (ExtendedCorrespondence::pair_forces).
  // Two cache lines (PK is pair_pk_'s: the volumetric gradient's only); the first holds what
  // the pair sum reads of a neighbour when both ends take the midpoint residual (its value
  // kept per bond by the row's stabilisation sum, rforce_), the second E, which the other
  // residuals read.
  struct alignas(64) PairRecord {
    Vec6 A = Vec6::Zero();   // a - 2 k_s b (a = dual(S), b = dual(R): bond_force_state's)
    double ks = 0;           // k_s (0: no stabilisation)
    uint8_t on = 0;          // carries stress in this pass
    uint8_t mid = 0;         // the other end's residual takes the midpoint with this E (e_ok_)
    alignas(64) Vec6 E = Vec6::Zero();  // the strain its residuals read (e_vec_ when it sends it, else e_full_)
  };
  std::vector<PairRecord> pair_;
  std::vector<Mat3> pair_pk_;   // per particle: PK of the pass (0: no stress); the last pass's while the
                                // breaking sweep books the broken bonds
  std::vector<double> pair_q_;  // per bond: omega g (A_i . h + 2 coef r_i) of the last pass, i's side
  std::vector<Vec3> pair_y_;    // per particle of the system: the positions of the last pass
  std::vector<Vec6> e_full_;
  std::vector<Mat3> n_sum_;
  // The lanes' copies (PairPass::lanes): per particle of the system, packed; per kind.
  bool identity_ = false;          // particles_[l] == l for every particle of the system
  std::vector<Point4> lane_ref_;   // {X, omega_D's flag}
  std::vector<Point4> lane_kind_;  // {L, 1/L, omega, V_j}
  std::vector<Point4> lane_contact_;  // {d^2, d, k, 0}
  std::vector<double> lane_mid_;   // the midpoint's neighbour data {E, k_s, e_ok_} (8 a particle)
  std::vector<double> lane_rec_;   // kLaneRecord a particle (the pair sum's record)
  std::vector<double> lane_pk_;    // kLanePK a particle (PK, volumetric_strain gradient)
};

void ExtendedCorrespondence::setup(const ModelSetup& in) {
  const MaterialConfig& mat = in.material;
  dim_ = in.config.dimension;
  if (dim_ < 2) throw Error("material '" + mat.name + "': the extended_correspondence model needs dimension 2 or 3");
  if (dim_ == 2 && in.dims.plane == PlaneMode::stress)
    throw Error("material '" + mat.name + "': the extended_correspondence model supports plane strain only in 2-D");
  const std::string& law = choice(mat, "stress_law");
  law_.law = law == "j2" ? StrainLaw::j2 : law == "johnson_cook" ? StrainLaw::johnson_cook : StrainLaw::elastic;
  law_.kappa = mat.bulk_modulus;
  law_.mu = mat.shear_modulus;
  law_.yield_stress = law_.sigma0 = parameter(mat, "yield_stress");
  law_.hardening_modulus = parameter(mat, "hardening_modulus");
  law_.B = parameter(mat, "hardening_coefficient");
  law_.n = parameter(mat, "hardening_exponent");
  law_.C = parameter(mat, "rate_coefficient");
  law_.rate0 = parameter(mat, "reference_rate");
  law_.d1 = parameter(mat, "failure_d1");
  law_.d2 = parameter(mat, "failure_d2");
  law_.d3 = parameter(mat, "failure_d3");
  law_.d4 = parameter(mat, "failure_d4");
  law_.damage_rate0 = parameter(mat, "failure_reference_rate");
  law_.damage = law_.law == StrainLaw::johnson_cook && (law_.d1 != 0 || law_.d2 != 0);
  kext_.law = extended::strain_law_constants(law_);
  if (law_.law != StrainLaw::elastic && !(law_.yield_stress > 0))
    throw Error("material '" + mat.name + "': stress_law " + law + " needs a positive yield_stress [Pa]");
  if (law_.law == StrainLaw::johnson_cook && !(law_.B > 0))
    throw Error("material '" + mat.name + "': stress_law johnson_cook needs a positive hardening_coefficient [Pa]");
  m_ = parameter(mat, "seth_hill_m");
  hencky_ = choice(mat, "strain_measure") == "hencky";
  if (hencky_) m_ = 1.0;  // Green bond strains; the logarithm is taken of their average
  critical_ = parameter(mat, "critical_damage");
  tolerance_ = parameter(mat, "shape_tolerance");
  min_acting_ = parameter(mat, "min_acting_fraction");
  const double Gs = parameter(mat, "stabilization");
  stab_yield_ = law_.law == StrainLaw::elastic ? 0.0 : parameter(mat, "stabilization_yield");
  // mu_bar of the nonlinear solid's bond-based term (digest sec. 13.2).
  const double mu_bar = (dim_ == 3 ? 2.5 : 2.0) * mat.shear_modulus;
  gs_mu_bar_ = Gs * mu_bar;

  const System& s = in.system;
  const Bonds& B = s.bonds;
  particles_ = in.particles;
  identity_ = particles_.size() == s.particles.size();
  for (std::size_t l = 0; l < particles_.size() && identity_; ++l) identity_ = particles_[l] == l;
  local_.assign(s.particles.size(), -1);
  ks_.assign(particles_.size(), 0.0);
  family_weight_.assign(particles_.size(), 0.0);
  acting_share_.assign(particles_.size(), 1.0);
  for (std::size_t l = 0; l < particles_.size(); ++l) {
    const uint32_t i = particles_[l];
    local_[i] = static_cast<int32_t>(l);
    double w = 0;
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) w += B.weight[k] * B.volume[k];
    family_weight_[l] = w;
    ks_[l] = w > 0 ? Gs * mu_bar * dim_ / w : 0.0;
  }
  fill_state_based_coefficients(in, 1.0 + Gs);
  midpoint_ = choice(mat, "stabilization_residual") == "midpoint";
  secant_ = choice(mat, "stabilization_softening") == "secant" && law_.law != StrainLaw::elastic;
  ks0_ = ks_;
  ws_.assign(particles_.size(), 0.0);
  const std::size_t n = particles_.size();
  committed_.assign(n, StrainLawState{});
  trial_.assign(n, StrainLawState{});
  work_.assign(n, 0.0);
  plastic_total_.assign(n, 0.0);
  failure_total_.assign(n, 0.0);
  energy_.assign(n, 0.0);
  switched_.assign(n, 0.0);
  thinned_.assign(n, 0.0);
  thinned_total_.assign(n, 0.0);
  von_mises_.assign(n, 0.0);
  inactive_.assign(n, 0);
  maps_.assign(n, extended::MomentMap{});
  kinv_.assign(n, Mat3::Zero());
  e_vec_.assign(n, Vec6::Zero());
  e_ok_.assign(n, 0);
  changed_.assign(n, 0);
  old_maps_.assign(n, extended::MomentMap{});
  old_kinv_.assign(n, Mat3::Zero());
  vol_gradient_ = choice(mat, "volumetric_strain") == "gradient";
  kext_.dimension = dim_;
  kext_.hencky = hencky_;
  kext_.vol_gradient = vol_gradient_;
  kext_.floor = extended::kHenckyFloor;
  adaptive_ = in.config.solver.adaptive_time_step;
  acting_.assign(n, UINT32_MAX);
  map_ok_.assign(n, 0);
  failed_at_.assign(s.particles.size(), 0);
  e_fin_.assign(n, 0);
  e_full_.assign(n, Vec6::Zero());
  n_sum_.assign(n, Mat3::Zero());
  pair_pk_.assign(n, Mat3::Zero());
  pair_q_.assign(B.size(), 0.0);
  pair_y_.assign(s.particles.size(), Vec3{});
}

void ExtendedCorrespondence::begin_pass(const System& s) {
  const Bonds& B = s.bonds;
  if (eps_.size() != B.size()) eps_.assign(B.size(), 0.0);
  if (rforce_.size() != B.size()) rforce_.assign(B.size(), 0.0);
  if (acted_.size() != B.size()) acted_.assign(B.size(), 0);
  if (acts_.size() != B.size()) acts_.assign(B.size(), 0);
  if (stab_yield_ > 0 && rp_committed_.size() != B.size()) {
    rp_committed_.assign(B.size(), 0.0);
    rp_trial_.assign(B.size(), 0.0);
  }
  const std::size_t n = particles_.size();
  // A decomposed run: the ghosts' committed damage (which bonds act, omega_D) and
  // stabilisation modulus from their owners (rows_local in traits()).
  exchange_to_ghosts(s, 2, [&](std::size_t l, double* v) { v[0] = committed_[l].damage, v[1] = ks_[l]; },
                     [&](std::size_t l, const double* v) { committed_[l].damage = v[0], ks_[l] = v[1]; });
  // omega_D's flag of every particle once (bond_acts reads it at both ends).
  for (std::size_t l = 0; l < n; ++l) failed_at_[particles_[l]] = committed_[l].damage > critical_ ? 1 : 0;
}

// The moment map and the shape-tensor guard of particle l (system index i) over the bonds
// acts_ marks, `count` of them: they depend on the acting set only, which only shrinks
// (bonds break, neighbours fail), so its size identifies it; the old map is kept for the
// pricing of the change (energy_with).
void ExtendedCorrespondence::rebuild_map(const Bonds& B, const std::vector<Vec3>& X, std::size_t l, uint32_t i,
                                         uint32_t count) {
  if (acting_[l] != UINT32_MAX && map_ok_[l]) {
    changed_[l] = 1;
    old_maps_[l] = maps_[l];
    old_kinv_[l] = kinv_[l];
  }
  // The map, K and their factorisations in one portable kernel (kernels/extended_law.hpp
  // moment_map_row: MomentMap::add, NonlocalGradient::add and their finish, the same bits).
  // The moment map M = sum w H (x) n n of a family that omega_D has thinned to a
  // share s of its weight is ~ s M_full: E = M^-1 sum w eps H and the force of
  // (4.7) both scale as 1/s, so the particle's stiffness grows as 1/s while the
  // stable step was taken from the full family. min_acting_fraction bounds 1/s.
  auto bond = [&](uint64_t k, double* xi, double& w) {
    if (!acts_[k]) return false;
    const Vec3 d = X[B.nbr[k]] - X[i];
    xi[0] = d.x, xi[1] = d.y, xi[2] = d.z;
    w = B.weight[k] * B.volume[k];
    return true;
  };
  double acting_weight = 0;
  map_ok_[l] = kernels::moment_map_row(B.begin(i), B.end(i), bond, dim_, tolerance_, min_acting_ * family_weight_[l],
                                       maps_[l].matrix_data(), maps_[l].inverse_data(), kinv_[l].data(), acting_weight)
                   ? 1
                   : 0;
  acting_share_[l] = family_weight_[l] > 0 ? acting_weight / family_weight_[l] : 0.0;
  acting_[l] = count;
}

// The midpoint residual reads E of both ends: the ghosts' from their owners.
void ExtendedCorrespondence::exchange_midpoint(const System& s) {
  if (midpoint_)
    exchange_to_ghosts(
        s, 7,
        [&](std::size_t l, double* v) {
          for (int c = 0; c < 6; ++c) v[c] = e_vec_[l][c];
          v[6] = e_ok_[l];
        },
        [&](std::size_t l, const double* v) {
          for (int c = 0; c < 6; ++c) e_vec_[l][c] = v[c];
          e_ok_[l] = v[6] != 0 ? 1 : 0;
        });
}

void ExtendedCorrespondence::force_state(ForcePass& pass) {
  const System& s = pass.system;
  const Bonds& B = s.bonds;
  const std::vector<Vec3>& X = s.particles.X;
  const Point4* y = pass.y;
  Vec3* T = pass.T;
  begin_pass(s);
  const std::size_t n = particles_.size();
  // Sweep 1: the acting sets and moment maps, and (midpoint residual) every particle's E,
  // which sweep 2's stabilisation reads at both ends of a bond.
#pragma omp parallel for schedule(static) if (n > 512)
  for (std::size_t l = 0; l < n; ++l) {
    const uint32_t i = particles_[l];
    if (!s.computes_row(i)) continue;  // another rank's row (its state comes from its owner)
    const Point4 yi = y[i];
    auto deformed = [&](uint32_t j) { return Vec3{y[j].x - yi.x, y[j].y - yi.y, y[j].z - yi.z}; };
    const bool self_failed = committed_[l].damage > critical_;
    auto acts = [&](uint64_t k) { return acts_[k] != 0; };
    changed_[l] = 0;
    e_ok_[l] = 0;
    e_fin_[l] = 0;
    if (self_failed) {
      for (uint64_t k = B.begin(i); k < B.end(i); ++k) acts_[k] = 0;
      continue;
    }
    {
      // The moment map and the shape-tensor guard depend on the acting set only, which
      // only shrinks (bonds break, neighbours fail): its size identifies it.
      uint32_t count = 0;
      for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
        acts_[k] = B.intact[k] && !failed_at_[B.nbr[k]] ? 1 : 0;  // bond_acts (self_failed is false here)
        count += acts_[k];
      }
      if (count != acting_[l]) rebuild_map(B, X, l, i, count);
    }
    if (!map_ok_[l]) continue;
    // E over the acting bonds (and sum w Y (x) xi for Fbar), each bond's strain kept in
    // eps_: sweep 2 reads them instead of summing again (the same sums, the same bits).
    extended::NonlocalStrain E(dim_, m_);
    E.use(maps_[l]);
    Mat3 N = Mat3::Zero();
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
      if (!acts(k)) continue;
      const uint32_t j = B.nbr[k];
      const Vec3 xi = X[j] - X[i], Y = deformed(j);
      const double w = B.weight[k] * B.volume[k];
      eps_[k] = E.add_strain(xi, Y, w);
      if (vol_gradient_) gradient_add(N, w, Y, xi);
    }
    if (E.finish(false)) keep_strain(l, E.strain_vector(), N);
  }
  exchange_midpoint(s);
  // Sweep 2: the law, the stabilisation and the force states.
#pragma omp parallel for schedule(static) if (n > 512)
  for (std::size_t l = 0; l < n; ++l) {
    const uint32_t i = particles_[l];
    if (!s.computes_row(i)) continue;
    const Point4 yi = y[i];
    auto deformed = [&](uint32_t j) { return Vec3{y[j].x - yi.x, y[j].y - yi.y, y[j].z - yi.z}; };
    auto acts = [&](uint64_t k) { return acts_[k] != 0; };
    RowLaw law;
    if (!row_law(pass, l, i, false, law)) {
      for (uint64_t k = B.begin(i); k < B.end(i); ++k) T[k] = {};
      continue;
    }
    const kernels::ExtendedLawRow& out = law.out;
    extended::NonlocalStrain E(dim_, m_);
    E.use(maps_[l]);
    E.set_strain(e_full_[l]);
    const Vec6 a = Eigen::Map<const Vec6>(out.a);  // dual(S)
    Vec6 b = Vec6::Zero();
    double W = out.W;
    const double ks = ks_[l];
    if (ks != 0) {
      const Stabilisation st = stabilisation(B, X, i, l, E, acts, trial_[l].alpha, out.rate, true);
      work_[l] += st.work;
      b = E.dual(st.R);
      W += st.W;
      ws_[l] = st.W;
    }
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
      if (!acts(k)) {
        T[k] = {};
        continue;
      }
      const uint32_t j = B.nbr[k];
      const Vec3 xi = X[j] - X[i], Y = deformed(j);
      const double r = ks != 0 ? rforce_[k] : 0.0;
      T[k] = extended::bond_force_state(a, b, ks, B.weight[k], m_, dim_, xi, Y, r);
      if (vol_gradient_) T[k] = T[k] + pressure_term(out.PK, B.weight[k], xi);
    }
    row_end(pass, l, i, law, W);
  }
}

// The pair form of the general pass (Model::takes_pair_pass; issue 31 scope 2). The force
// state (4.7) with the volumetric gradient's term,
//   T_ij = omega g_ij (a_i . h_ij + 2 k_s,i (r_force,ij - b_i . h_ij)) Y + omega PK_i xi,
// g = c^(m-1)/|xi|^2, is omega g (A_i . h + 2 coef_ij r_ij) Y + omega PK_i xi with
// A_i = a_i - 2 k_s,i b_i and coef r = k_s r_force (stabilisation()): a per-particle record
// and the bond's geometry, strain and residual, all of them even in xi (h, g, the strain)
// or computable from either end (the residuals read E of both ends). So the pass keeps no
// force state per bond and no reverse-bond index, and visits each bond three times:
//   1. per row: breaking (forces_general.cpp break_row, the same stretch bits), the acting
//      flags, the sums of E and of Fbar's N over the acting bonds, each bond's strain kept;
//   2. per row (after the midpoint's exchange): the law, the stabilisation's R and W, the
//      record;
//   3. per row: f_i = sum_j V_j (T_ij - T_ji) = sum_j omega V_j (g (s_i + s_j) Y + (PK_i +
//      PK_j) xi), s_i the scalar of i's side, with the family contact.
// The geometry takes n = xi/|xi| from the kind's 1/|xi| and the m = 1 strain as (c - 1)/2:
// the forces agree with the vector form to round-off (tests/verification/
// test_general_pass.cpp). The capped stabilisation (stabilization_yield: a per-bond plastic
// residual of each side) keeps the vector form, as do mixed runs and runs with one-way
// bonds (bodies of different horizons).
constexpr uint64_t kPairAhead = 8;  // bonds ahead the pair sum asks for a neighbour's record

bool ExtendedCorrespondence::takes_pair_pass(const System& s) const {
  // One-way bonds (bodies of different horizons) have omega_ij != omega_ji: no pair form.
  return stab_yield_ == 0 && particles_.size() == s.particles.size() && s.thermal_strain.empty() && !s.fe_coupling &&
         !s.one_way_bonds;
}

// 1. Row l's breaking and strain sums (pair_forces); returns the bonds it broke.
__attribute__((always_inline)) inline uint64_t ExtendedCorrespondence::pair_break_row(const PairPass& c, std::size_t l) {
  System& s = c.system;
  Particles& P = s.particles;
  Bonds& B = s.bonds;
  ModelCoefficients& M = s.model;
  const Point4* y = c.y;
  const Vec3* X = c.X;
  const KindCoefficients* kcs = c.kcs;
  const BondKind* kinds = c.kinds;
  const bool after = c.after;
  const double* soft = c.soft;
  auto scaled = [](double w, double f) { return std::isinf(w) ? w : w * f; };
  const uint32_t i = particles_[l];
  if (!s.computes_row(i)) return 0;  // another rank's row
  const Point4 pi = y[i];
  const Vec3 xi_i = X[i];
  const double wi = soft ? scaled(pi.w, soft[i]) : pi.w;
  const bool self_failed = committed_[l].damage > critical_;
  const Mat3& pk_old = pair_pk_[l];
  double smin = std::numeric_limits<double>::infinity(), lost = 0;
  uint64_t row_broken = 0;
  uint32_t count = 0;
  Vec6 S = Vec6::Zero();
  Mat3 N = Mat3::Zero();
  if (c.lanes) row_broken = pair_break_lanes(c, l, count, S, N, smin, lost);
  for (uint64_t k = c.lanes ? B.end(i) : B.begin(i); k < B.end(i); ++k) {
    acts_[k] = 0;
    if (!B.intact[k]) continue;
    const uint32_t j = B.nbr[k];
    const KindCoefficients& kc = kcs[B.kind[k]];
    const Point4 pj = y[j];
    const Vec3 Y{pj.x - pi.x, pj.y - pi.y, pj.z - pi.z};
    const double r = kernels::bond_length(Y.x, Y.y, Y.z), e = kernels::extension(r, kc.length, 0.0),
                 stretch = e * kc.inv_length;
    smin = stretch < smin ? stretch : smin;
    const BondKind& bk = kinds[B.kind[k]];
    const Vec3 xi = X[j] - xi_i;
    if (kernels::breaks(stretch, wi, soft ? scaled(pj.w, soft[j]) : pj.w)) {
      B.intact[k] = after ? 2 : 0;
      ++row_broken;
      if (r > 0 && acted_[k]) {
        // (1/2) (T_old . Y/|Y|) e V_j with T_old the bond's force state of the last pass
        // (forces_general.cpp break_row), rebuilt from its scalar, PK_i and the positions.
        const Vec3 Yo = pair_y_[j] - pair_y_[i];
        const Vec3 T_old = pair_q_[k] * Yo + pressure_term(pk_old.data(), bk.weight, xi);
        lost += 0.5 * dot(T_old, Y) / r * e * (bk.volume * bk.fraction);
      }
      M.intact_weight[i] -= kc.damage;
      if (!after) continue;
    }
    if (self_failed || failed_at_[j]) continue;  // omega_D (bond_acts)
    acts_[k] = 1;
    ++count;
    const double w = bk.weight * (bk.volume * bk.fraction);
    const double inv = kc.inv_length, eps = kernels::pair_strain(dot(Y, Y) * (inv * inv), m_);
    eps_[k] = eps;
    const Vec3 nv = inv * xi;
    const double n[3] = {nv.x, nv.y, nv.z};
    double h[6];
    kernels::unit_shape_state(n, dim_, h);
    kernels::strain_sum_add(S.data(), w * eps, h);
    if (vol_gradient_) gradient_add(N, w, Y, xi);
  }
  if (lost != 0) s.dissipated_at[i] += lost * P.volume[i];
  if (row_broken) M.intact_weight[i] = intact_damage_weight(s, i);  // afresh (state/system.hpp)
  P.damage[i] = damage_of(M.intact_weight[i], M.damage_total[i]);
  M.min_stretch_next[i] = smin;
  changed_[l] = e_ok_[l] = e_fin_[l] = 0;
  if (self_failed) return row_broken;
  if (count != acting_[l]) rebuild_map(B, P.X, l, i, count);
  if (!map_ok_[l]) return row_broken;
  const Vec6 E = maps_[l].solve(S);  // NonlocalStrain::finish(false)
  if (E.allFinite()) keep_strain(l, E, N);
  return row_broken;
}

// A bond of row i that breaks in the lanes (bond order, as pair_break_row books it): r
// and e as the lanes computed them.
void ExtendedCorrespondence::book_break(const PairPass& c, std::size_t i, uint64_t k, double r, double e,
                                        double& lost) {
  System& s = c.system;
  Bonds& B = s.bonds;
  const uint32_t j = B.nbr[k];
  const BondKind& bk = c.kinds[B.kind[k]];
  B.intact[k] = c.after ? 2 : 0;
  if (r > 0 && acted_[k]) {
    const Point4 pi = c.y[i], pj = c.y[j];
    const Vec3 Y{pj.x - pi.x, pj.y - pi.y, pj.z - pi.z}, xi = c.X[j] - c.X[i];
    const Vec3 Yo = pair_y_[j] - pair_y_[i];
    const Vec3 T_old = pair_q_[k] * Yo + pressure_term(pair_pk_[local_[i]].data(), bk.weight, xi);
    lost += 0.5 * dot(T_old, Y) / r * e * (bk.volume * bk.fraction);
  }
  s.model.intact_weight[i] -= c.kcs[B.kind[k]].damage;
}

// Row l's bond loop of pair_break_row in the eight lanes: breaking (the same stretch bits;
// the broken bonds booked in bond order), the acting flags and strains, S = sum w eps H and
// N = sum w Y (x) xi (volumetric_strain gradient) lane by lane. Returns the bonds it broke.
__attribute__((always_inline)) inline uint64_t ExtendedCorrespondence::pair_break_lanes(
    const PairPass& c, std::size_t l, uint32_t& count, Vec6& S6, Mat3& N9, double& smin, double& lost) {
  Bonds& B = c.system.bonds;
  const uint32_t i = particles_[l];
  const Point4 pi = c.y[i], xr = c.ref[i];
  const bool self_failed = committed_[l].damage > critical_, after = c.after, m1 = m_ == 1.0;
  const uint64_t begin = B.begin(i), end = B.end(i), total = B.size();
  const v8d zero = {};
  v8d S[6], N[9];
  for (auto& v : S) v = zero;
  for (auto& v : N) v = zero;
  v8d sm = zero + std::numeric_limits<double>::infinity();
  uint64_t broken = 0;
  for (uint64_t k = begin; k < end; k += 8) {
    const int cnt = end - k < 8 ? static_cast<int>(end - k) : 8;
    const v8l live = byte_lanes(B.intact.data(), k, cnt, total);
    if (!any_lane(live)) {
      for (int q = 0; q < cnt; ++q) acts_[k + static_cast<uint64_t>(q)] = 0;
      continue;
    }
    const double *pp[8], *pr[8], *pk[8];
    for (int q = 0; q < 8; ++q) {
      const uint64_t kk = q < cnt ? k + static_cast<uint64_t>(q) : k;
      const uint32_t j = q < cnt ? B.nbr[kk] : i;
      pp[q] = &c.y[j].x;
      pr[q] = &c.ref[j].x;
      pk[q] = &c.kind4[B.kind[kk]].x;
    }
    v8d Yx, Yy, Yz, wj, xx, xy, xz, fj, L, iL, om, V;
    transpose8(pp, Yx, Yy, Yz, wj);
    transpose8(pr, xx, xy, xz, fj);
    transpose8(pk, L, iL, om, V);
    Yx -= pi.x, Yy -= pi.y, Yz -= pi.z;
    const v8d r2 = kernels::squared_length(Yx, Yy, Yz), r = lanes_sqrt(r2), e = r - L, stretch = e * iL;
    const v8d sl = select(live, stretch, zero + std::numeric_limits<double>::infinity());
    sm = sl < sm ? sl : sm;
    const v8d s0i = zero + pi.w, s0 = s0i < wj ? s0i : wj;  // kernels::breaks
    const v8l breaks = live & gt(stretch, s0);
    v8l acts = after ? live : live & ~breaks;
    acts = (self_failed ? v8l{} : acts) & ~as_mask(fj);  // omega_D (bond_acts)
    if (const uint64_t b = lane_bytes(breaks))
      for (int q = 0; q < cnt; ++q)
        if ((b >> (8 * q)) & 1) {
          ++broken;
          book_break(c, i, k + static_cast<uint64_t>(q), r[q], e[q], lost);
        }
    store_bytes(acts_.data(), k, cnt, acts);
    const uint64_t acting = lane_bytes(acts);
    if (!acting) continue;
    count += static_cast<uint32_t>(__builtin_popcountll(acting));
    const v8d cc = r2 * (iL * iL);
    v8d eps;
    if (m1) {
      eps = kernels::green_bond_strain(cc);
    } else {
      eps = zero;
      for (int q = 0; q < cnt; ++q)
        if ((acting >> (8 * q)) & 1) eps[q] = kernels::pair_strain(cc[q], m_);
    }
    store_lanes(eps_.data(), k, cnt, eps);
    const v8d xi[3] = {xx - xr.x, xy - xr.y, xz - xr.z};
    const v8d n[3] = {iL * xi[0], iL * xi[1], iL * xi[2]};
    v8d h[6];
    kernels::unit_shape_state(n, dim_, h);
    const v8d w = om * V, we = w * eps;
    for (int q = 0; q < 6; ++q) S[q] += masked(acts, we * h[q]);
    if (vol_gradient_) {
      const v8d Y[3] = {Yx, Yy, Yz};
      for (int a = 0; a < 3; ++a) {
        const v8d wy = w * Y[a];
        for (int b = 0; b < 3; ++b) N[3 * a + b] += masked(acts, wy * xi[b]);
      }
    }
  }
  for (int q = 0; q < 6; ++q) S6[q] = lanes_total(S[q]);
  if (vol_gradient_)
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) N9(a, b) = lanes_total(N[3 * a + b]);
  smin = lanes_min(sm);
  return broken;
}

// 2. Row l's law, stabilisation and record (pair_forces).
__attribute__((always_inline)) inline void ExtendedCorrespondence::pair_law_row(const PairPass& c, std::size_t l) {
  System& s = c.system;
  const Bonds& B = s.bonds;
  const Vec3* X = c.X;
  const KindCoefficients* kcs = c.kcs;
  const BondKind* kinds = c.kinds;
  const ForcePass& pass = *c.pass;
  const uint32_t i = particles_[l];
  if (!s.computes_row(i)) return;
  PairRecord& rec = pair_[l];
  rec.mid = midpoint_ && e_ok_[l];
  rec.E = rec.mid ? e_vec_[l] : e_full_[l];
  // The law row: the law (kernels/extended_law.hpp extended_law_row), the stabilisation
  // (stabilisation() without the cap, takes_pair_pass; n from the kind's 1/|xi|; R summed as
  // its weighted 6-vector sum w r_force p, the dual's argument, instead of sum w r_force
  // n (x) n) and the record A = dual(S) - 2 k_s dual_weighted(Rp): one portable kernel
  // (extended_pair_law_row) bond by bond, or the law, the lanes' stabilisation sums and the
  // record (pair_record).
  const double ks = ks_[l];
  const Vec6& Ei = e_full_[l];
  const double* inv = maps_[l].inverse();
  double Ws = 0;
  auto whole_row = [&](kernels::ExtendedLawRow& out) {
    auto bond = [&](uint64_t k, kernels::StabilisationBond& b) {
      if (!acts_[k]) return false;
      const uint32_t j = B.nbr[k];
      const Vec3 nv = kcs[B.kind[k]].inv_length * (X[j] - X[i]);
      b.n[0] = nv.x, b.n[1] = nv.y, b.n[2] = nv.z;
      b.eps = eps_[k];
      const BondKind& bk = kinds[B.kind[k]];
      b.w = bk.weight * (bk.volume * bk.fraction);
      const int32_t lj = midpoint_ ? local_[j] : -1;
      b.mid = lj >= 0 && e_ok_[lj];
      b.Ej = b.mid ? e_vec_[lj].data() : nullptr;
      b.ksj = b.mid ? ks_[lj] : 0.0;
      return true;
    };
    kernels::ExtendedLawHistory ht;
    const bool ok = kernels::extended_pair_law_row(kext_, inv, Ei.data(), n_sum_[l].data(), kinv_[l].data(),
                                                   history_in(l), pass.dt, ks, B.begin(i), B.end(i), bond,
                                                   rforce_.data(), ht, out, rec.A.data(), Ws);
    history_out(ht, trial_[l]);
    return ok;
  };
  RowLaw law;
  // (The lanes' sums run here, in the row itself, not in a lambda: a lambda does not take
  // the AVX-512 target of pair_law_avx512, and its eight-lane code then runs 1.3x slower.)
  const bool on = c.lanes ? row_law(pass, l, i, true, law) : row_law(pass, l, i, true, law, whole_row);
  if (on && c.lanes) {
    Vec6 Rp = Vec6::Zero();
    if (ks != 0) pair_stabilisation_lanes(c, l, Ei, ks, Rp, Ws);
    kernels::pair_record(law.out.a, ks, inv, Rp.data(), rec.A.data());
  }
  if (!on) {
    rec.on = 0;
    rec.A.setZero();
    rec.ks = 0;
    pair_pk_[l].setZero();
    if (c.lanes) lane_record(l);
    return;
  }
  double W = law.out.W;
  if (ks != 0) {
    W += Ws;
    ws_[l] = Ws;
  }
  pair_pk_[l] = Eigen::Map<const Mat3>(law.out.PK);
  rec.ks = ks;
  rec.on = 1;
  if (c.lanes) lane_record(l);
  row_end(pass, l, i, law, W);
}

// Row l's stabilisation loop of pair_law_row in the eight lanes: each acting bond's
// residual r (kept in rforce_ for the sum), Rp = sum w r_force p and W_s = sum coef w r^2.
__attribute__((always_inline)) inline void ExtendedCorrespondence::pair_stabilisation_lanes(
    const PairPass& c, std::size_t l, const Vec6& Ei, double ks, Vec6& Rp6, double& Ws1) {
  const Bonds& B = c.system.bonds;
  const uint32_t i = particles_[l];
  const Point4 xr = c.ref[i];
  const uint64_t begin = B.begin(i), end = B.end(i), total = B.size();
  const double inv_ks = 1.0 / ks;
  const v8d zero = {};
  v8d E[6];
  for (int q = 0; q < 6; ++q) E[q] = zero + Ei[q];
  v8d Rp[6], Ws = zero;
  for (auto& v : Rp) v = zero;
  for (uint64_t k = begin; k < end; k += 8) {
    const int cnt = end - k < 8 ? static_cast<int>(end - k) : 8;
    const v8l acts = byte_lanes(acts_.data(), k, cnt, total);
    if (!any_lane(acts)) continue;
    const double *pr[8], *pk[8], *pm[8];
    for (int q = 0; q < 8; ++q) {
      const uint64_t kk = q < cnt ? k + static_cast<uint64_t>(q) : k;
      const uint32_t j = q < cnt ? B.nbr[kk] : i;
      pr[q] = &c.ref[j].x;
      pk[q] = &c.kind4[B.kind[kk]].x;
      pm[q] = lane_mid_.data() + 8 * static_cast<std::size_t>(j);
    }
    v8d xx, xy, xz, fj, L, iL, om, V;
    transpose8(pr, xx, xy, xz, fj);
    transpose8(pk, L, iL, om, V);
    const v8d n[3] = {iL * (xx - xr.x), iL * (xy - xr.y), iL * (xz - xr.z)};
    v8d p[6];
    kernels::unit_normal_projector(n, p);
    const v8d eps = load_lanes(eps_.data(), k, cnt);
    v8d r = eps - kernels::dot6(p, E), coef = zero + ks;
    if (midpoint_) {
      v8d Ej[6], ksj, okj;
      const double* pm4[8];
      transpose8(pm, Ej[0], Ej[1], Ej[2], Ej[3]);
      for (int q = 0; q < 8; ++q) pm4[q] = pm[q] + 4;
      transpose8(pm4, Ej[4], Ej[5], ksj, okj);
      const v8l ok = as_mask(okj);
      r = select(ok, eps - kernels::dot6_mid(p, E, Ej), r);
      coef = select(ok, 0.5 * (ks + ksj), coef);
    }
    store_lanes(rforce_.data(), k, cnt, r);  // the pair sum's i side
    const v8d w = om * V, wr = w * r, f = wr * (coef * inv_ks);
    for (int q = 0; q < 6; ++q) Rp[q] += masked(acts, f * p[q]);
    Ws += masked(acts, coef * wr * r);
  }
  for (int q = 0; q < 6; ++q) Rp6[q] = lanes_total(Rp[q]);
  Ws1 = lanes_total(Ws);
}

// The pair sum's lane record of particle l (lane_rec_, lane_pk_) from pair_[l], pair_pk_[l].
void ExtendedCorrespondence::lane_record(std::size_t l) {
  const PairRecord& rec = pair_[l];
  double* v = lane_rec_.data() + kLaneRecord * l;
  for (int q = 0; q < 6; ++q) v[q] = rec.A[q], v[10 + q] = rec.E[q];
  v[6] = rec.ks;
  v[7] = mask_bits(rec.on != 0);
  v[8] = mask_bits(rec.mid != 0);
  v[9] = mask_bits(rec.on != 0 && rec.ks != 0);
  if (vol_gradient_) {
    double* pk = lane_pk_.data() + kLanePK * l;
    for (int q = 0; q < 9; ++q) pk[q] = pair_pk_[l].data()[q];
    pk[9] = pk[10] = pk[11] = 0.0;
  }
}

// 3. Row i's pair sum with the family contact (pair_forces).
__attribute__((always_inline)) inline void ExtendedCorrespondence::pair_sum_row(const PairPass& c, std::size_t i) {
  System& s = c.system;
  Particles& P = s.particles;
  Bonds& B = s.bonds;
  const Point4* y = c.y;
  const Vec3* X = c.X;
  const KindCoefficients* kcs = c.kcs;
  const BondKind* kinds = c.kinds;
  const bool energy = c.energy;
  const double m = m_;
  if (c.lanes && pair_sum_lanes(c, i)) return;
  const Point4 pi = y[i];
  const Vec3 xi_i = X[i];
  const int32_t li = local_[i];
  Vec3 f, xw;
  double wc_sum = 0;
  const uint64_t last = B.end(i);
  for (uint64_t k = B.begin(i); k < last; ++k) {
    // The neighbour's record lies up to a horizon of rows away (one or two lines): asked for a
    // few bonds ahead.
    if (k + kPairAhead < last) {
      const std::size_t la = local_[B.nbr[k + kPairAhead]];
      const char* ahead = reinterpret_cast<const char*>(&pair_[la]);
      __builtin_prefetch(ahead);
      if (!midpoint_) __builtin_prefetch(ahead + 64);  // E: the full residual's j side
      if (vol_gradient_) __builtin_prefetch(&pair_pk_[la]);
    }
    const uint32_t j = B.nbr[k];
    const Point4 pj = y[j];
    const Vec3 Y{pj.x - pi.x, pj.y - pi.y, pj.z - pi.z};
    const KindCoefficients& kc = kcs[B.kind[k]];
    if (acts_[k]) {
      const PairRecord& ri = pair_[li];
      const int32_t lj = local_[j];
      const PairRecord& rj = pair_[lj];
      const BondKind& bk = kinds[B.kind[k]];
      const Vec3 xi = X[j] - xi_i, nv = kc.inv_length * xi;
      const double n[3] = {nv.x, nv.y, nv.z};
      // The bond's term, a device-portable kernel (kernels/extended.hpp pair_bond).
      const kernels::PairEnd ei{ri.A.data(), ri.E.data(), ri.ks, ri.on != 0, ri.mid != 0};
      const kernels::PairEnd ej{rj.A.data(), rj.E.data(), rj.ks, rj.on != 0, rj.mid != 0};
      const double V = bk.volume * bk.fraction, wv = bk.weight * V;
      const kernels::PairBond pb =
          kernels::pair_bond_kept(ei, ej, n, dim_, kc.inv_length, dot(Y, Y), &eps_[k], rforce_[k], m, bk.weight, V);
      if (c.keep_q) pair_q_[k] = pb.q;
      f += pb.scale * Y;
      if (vol_gradient_) {
        f += pressure_term(pair_pk_[lj].data(), wv, xi);
        xw += wv * xi;  // omega V_j PK_i xi summed as PK_i (sum omega V_j xi), after the row
      }
    }
    Vec3 fc;
    double wc = 0;
    if (family_contact(kc, Y, fc, wc)) {
      f += fc;
      wc_sum += wc;
    }
  }
  if (vol_gradient_) f += pressure_sum(pair_pk_[li].data(), xw);
  P.f[i] = f;
  if (energy) P.energy[i] += wc_sum;
}

// Row i's pair sum (pair_sum_row) in the eight lanes, for a row that carries stress with
// k_s != 0 (its residual kept: kernels::pair_bond_kept, the same terms lane by lane);
// false for another row (pair_sum_row sums it bond by bond).
__attribute__((always_inline)) inline bool ExtendedCorrespondence::pair_sum_lanes(const PairPass& c, std::size_t i) {
  const PairRecord& rec = pair_[i];
  const double* reci = lane_rec_.data() + kLaneRecord * i;
  const double ksi = rec.ks;
  if (!rec.on || ksi == 0) return false;  // carries no stress, or no stabilisation
  System& s = c.system;
  const Bonds& B = s.bonds;
  const bool mid_i = rec.mid != 0, m1 = m_ == 1.0, m0 = m_ == 0.0;
  const Point4 pi = c.y[i], xr = c.ref[i];
  const uint64_t begin = B.begin(i), end = B.end(i), total = B.size();
  const v8d zero = {};
  v8d Ai[6];
  for (int q = 0; q < 6; ++q) Ai[q] = zero + reci[q];
  v8d f[3] = {zero, zero, zero}, xw[3] = {zero, zero, zero}, wc = zero;
  for (uint64_t k = begin; k < end; k += 8) {
    const int cnt = end - k < 8 ? static_cast<int>(end - k) : 8;
    const v8l acts = byte_lanes(acts_.data(), k, cnt, total);
    const bool any = any_lane(acts);
    if (!any && !c.contact) continue;
    const v8l live_row = count_lanes(cnt);  // the row's bonds (the contact acts on every one)
    // The next block's neighbour records, asked for one block ahead (a large body's
    // records do not stay in cache from row to row).
    for (uint64_t kk = k + 8; kk < k + 16 && kk < end; ++kk) {
      const std::size_t j = B.nbr[kk];
      const char* rec = reinterpret_cast<const char*>(lane_rec_.data() + kLaneRecord * j);
      __builtin_prefetch(rec);
      __builtin_prefetch(rec + 64);
      if (vol_gradient_) __builtin_prefetch(lane_pk_.data() + kLanePK * j);
    }
    const double *pp[8], *pr[8], *pk[8], *pa[8], *pb[8], *pc[8];
    for (int q = 0; q < 8; ++q) {
      const uint64_t kk = q < cnt ? k + static_cast<uint64_t>(q) : k;
      const uint32_t j = q < cnt ? B.nbr[kk] : static_cast<uint32_t>(i);
      pp[q] = &c.y[j].x;
      pr[q] = &c.ref[j].x;
      pk[q] = &c.kind4[B.kind[kk]].x;
      pa[q] = lane_rec_.data() + kLaneRecord * static_cast<std::size_t>(j);
      pb[q] = pa[q] + 4;
      pc[q] = pa[q] + 8;
    }
    v8d Yx, Yy, Yz, unused;
    transpose8(pp, Yx, Yy, Yz, unused);
    Yx -= pi.x, Yy -= pi.y, Yz -= pi.z;
    if (any) {
      v8d xx, xy, xz, L, iL, om, V, Aj[6], ksj, onv, midv, stabv, Ej[6];
      transpose8(pr, xx, xy, xz, unused);
      transpose8(pk, L, iL, om, V);
      transpose8(pa, Aj[0], Aj[1], Aj[2], Aj[3]);
      transpose8(pb, Aj[4], Aj[5], ksj, onv);
      transpose8(pc, midv, stabv, Ej[0], Ej[1]);
      const v8d xi[3] = {xx - xr.x, xy - xr.y, xz - xr.z};
      const v8d n[3] = {iL * xi[0], iL * xi[1], iL * xi[2]};
      v8d h[6];
      kernels::unit_shape_state(n, dim_, h);
      const v8l onj = as_mask(onv), midj = as_mask(midv), stab_j = as_mask(stabv);
      const v8d r_i = load_lanes(rforce_.data(), k, cnt);
      // i's residual term (kernels::pair_bond_kept): (k_i + k_j) r_i when j sends its E, else 2 k_i r_i.
      const v8d si = kernels::dot6(Ai, h) + select(midj, (ksi + ksj) * r_i, (2.0 * ksi) * r_i);
      // j's residual: the midpoint one i kept when both ends send their E, else j's own.
      v8d res = (ksi + ksj) * r_i;
      const v8l own = mid_i ? stab_j & ~midj : stab_j;
      if (const uint64_t own_bits = lane_bytes(own)) {
        v8d p[6];
        kernels::unit_normal_projector(n, p);
        const v8d eps = load_lanes(eps_.data(), k, cnt);
        if (!midpoint_) {
          const double* pe[8];
          for (int q = 0; q < 8; ++q) pe[q] = pa[q] + 12;
          transpose8(pe, Ej[2], Ej[3], Ej[4], Ej[5]);
          res = (2.0 * ksj) * (eps - kernels::dot6(p, Ej));  // pair_side_residual without the midpoint
        } else {
          for (int q = 0; q < cnt; ++q) {
            if (!((own_bits >> (8 * q)) & 1)) continue;
            const double* rj = pa[q];
            const double pq[6] = {p[0][q], p[1][q], p[2][q], p[3][q], p[4][q], p[5][q]};
            const kernels::PairEnd ej{rj, rj + 10, rj[6], true, pair_[B.nbr[k + static_cast<uint64_t>(q)]].mid != 0};
            const kernels::PairEnd ei{reci, reci + 10, ksi, true, mid_i};
            res[q] = kernels::pair_side_residual(ej, ei, pq, eps[q]);
          }
        }
      }
      const v8d aj = kernels::dot6(Aj, h);
      const v8d sj = masked(onj, select(stab_j, aj + res, aj));
      const v8d inv2 = iL * iL;
      v8d g = inv2;
      if (!m1) {
        const v8d cc = kernels::squared_length(Yx, Yy, Yz) * inv2;
        if (m0) {
          g = (1.0 / cc) * inv2;
        } else {
          for (int q = 0; q < 8; ++q) g[q] = kernels::power(cc[q], m_ - 1.0) * inv2[q];
        }
      }
      const v8d wg = om * g, qi = wg * si, scale = V * (qi + wg * sj);
      if (c.keep_q) store_lanes(pair_q_.data(), k, cnt, qi);
      f[0] += masked(acts, scale * Yx);
      f[1] += masked(acts, scale * Yy);
      f[2] += masked(acts, scale * Yz);
      if (vol_gradient_) {
        const double *p0[8], *p1[8], *p2[8];
        for (int q = 0; q < 8; ++q) {
          const uint32_t j = q < cnt ? B.nbr[k + static_cast<uint64_t>(q)] : static_cast<uint32_t>(i);
          p0[q] = lane_pk_.data() + kLanePK * static_cast<std::size_t>(j);
          p1[q] = p0[q] + 4, p2[q] = p0[q] + 8;
        }
        v8d P[12];  // column by column
        transpose8(p0, P[0], P[1], P[2], P[3]);
        transpose8(p1, P[4], P[5], P[6], P[7]);
        transpose8(p2, P[8], P[9], P[10], P[11]);
        const v8d w = om * V;
        for (int a = 0; a < 3; ++a) {
          const v8d t = w * ((P[a] * xi[0] + P[3 + a] * xi[1]) + P[6 + a] * xi[2]);
          f[a] += masked(acts, t);
          xw[a] += masked(acts, w * xi[a]);
        }
      }
    }
    if (c.contact) {
      // family_contact (state/system.hpp) lane by lane: the pair closer than d_ij pushes
      // i away from j with k_ij V_j/delta per unit overlap; energy share k overlap^2/4.
      const double* pq[8];
      for (int q = 0; q < 8; ++q) pq[q] = &c.contact4[B.kind[q < cnt ? k + static_cast<uint64_t>(q) : k]].x;
      v8d d2, d, kc;
      transpose8(pq, d2, d, kc, unused);
      const v8d r2 = kernels::squared_length(Yx, Yy, Yz);
      const v8l near = gt(d2, r2) & gt(r2, zero) & live_row;
      const v8d r = lanes_sqrt(r2), overlap = d - r, fc = -kc * overlap / r;
      f[0] += masked(near, fc * Yx);
      f[1] += masked(near, fc * Yy);
      f[2] += masked(near, fc * Yz);
      wc += masked(near, 0.25 * kc * overlap * overlap);
    }
  }
  Vec3 fi{lanes_total(f[0]), lanes_total(f[1]), lanes_total(f[2])};
  if (vol_gradient_) {
    fi += pressure_sum(pair_pk_[i].data(), Vec3{lanes_total(xw[0]), lanes_total(xw[1]), lanes_total(xw[2])});
  }
  s.particles.f[i] = fi;
  if (c.energy) s.particles.energy[i] += lanes_total(wc);
  return true;
}

// The rows built for AVX-512 as well as for the build's own target, chosen once per pass
// (as ordinary_lanes.hpp and solver/forces.cpp choose theirs): the same body, the same
// operations in the same order (no FMA contraction in this file, CMakeLists.txt; Eigen's
// packets are the build's own in both), so the same bits on every machine, in fewer
// instructions: AVX-512's 32 vector registers spare the rows' spills (1.2x on the bench
// deck; an AVX2 build of the rows, 16 registers, measured no gain and is not kept).
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define HORIZON_PAIR_AVX512 1
#define HORIZON_PAIR_TARGET \
  __attribute__((target("avx2,fma,bmi,bmi2,lzcnt,movbe,avx512f,avx512vl,avx512bw,avx512dq,avx512cd")))
HORIZON_PAIR_TARGET uint64_t ExtendedCorrespondence::pair_break_avx512(const PairPass& c, std::size_t l) {
  return pair_break_row(c, l);
}
HORIZON_PAIR_TARGET void ExtendedCorrespondence::pair_law_avx512(const PairPass& c, std::size_t l) {
  pair_law_row(c, l);
}
HORIZON_PAIR_TARGET void ExtendedCorrespondence::pair_sum_avx512(const PairPass& c, std::size_t i) {
  pair_sum_row(c, i);
}
#undef HORIZON_PAIR_TARGET
#endif
uint64_t ExtendedCorrespondence::pair_break_base(const PairPass& c, std::size_t l) { return pair_break_row(c, l); }
void ExtendedCorrespondence::pair_law_base(const PairPass& c, std::size_t l) { pair_law_row(c, l); }
void ExtendedCorrespondence::pair_sum_base(const PairPass& c, std::size_t i) { pair_sum_row(c, i); }

uint64_t ExtendedCorrespondence::pair_forces(System& s, bool energy) {
  Particles& P = s.particles;
  Bonds& B = s.bonds;
  ModelCoefficients& M = s.model;
  const std::size_t np = P.size(), nb = B.size(), n = particles_.size();
  begin_pass(s);
  if (pair_q_.size() != nb) pair_q_.assign(nb, 0.0);
  if (pair_y_.size() != np) pair_y_.assign(np, Vec3{});
  if (pair_pk_.size() != n) pair_pk_.assign(n, Mat3::Zero());
  if (pair_.size() != n) pair_.assign(n, PairRecord{});
  if (energy)
    for (std::size_t i = 0; i < np; ++i) P.energy[i] = 0;
  const ForcePass pass{s, M.packed.data(), nullptr, energy ? P.energy.data() : nullptr, s.time, s.dt};
  // pair_q_ books the energy of a bond that breaks in the next pass: none can where every
  // particle's critical stretch is infinite (no damage law; inf stays inf under alpha and the
  // temperature's factor) and none is scheduled, and the sum then skips its 8 bytes a bond.
  bool keep_q = !s.critical_stretch_schedules.empty();
  for (std::size_t i = 0; i < M.critical_stretch.size() && !keep_q; ++i) keep_q = !std::isinf(M.critical_stretch[i]);
  // A temperature-dependent critical stretch scales each end's s0 (forces_general.cpp).
  // The rows for this machine (pair_break_row and its versions below).
  auto break_row = &ExtendedCorrespondence::pair_break_base;
  auto law_row = &ExtendedCorrespondence::pair_law_base;
  auto sum_row = &ExtendedCorrespondence::pair_sum_base;
  bool avx512 = false;
#if defined(HORIZON_PAIR_AVX512)
  static const bool has_avx512 = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
                                 __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq") &&
                                 __builtin_cpu_supports("avx512cd") && __builtin_cpu_supports("bmi2") &&
                                 __builtin_cpu_supports("fma");
  avx512 = has_avx512;
  if (avx512) {
    break_row = &ExtendedCorrespondence::pair_break_avx512;
    law_row = &ExtendedCorrespondence::pair_law_avx512;
    sum_row = &ExtendedCorrespondence::pair_sum_avx512;
  }
#endif
  // The rows in the eight lanes on a machine with AVX-512 (GCC 12 builds the eight-lane
  // vectors for AVX2 or SSE 1.8x slower than the bond-by-bond rows: there those run, whose
  // sums round otherwise, docs/benchmarks.md), where the kinds hold the lengths (a per-bond
  // length has no lane record), no temperature scales the critical stretch, and particle l
  // is particle l.
  const bool lanes = avx512 && extended::pair_lanes() && identity_ && !B.length_per_bond &&
                     s.critical_stretch_factor.empty();
  if (lanes) {
    lane_ref_.resize(np);
    for (std::size_t i = 0; i < np; ++i) lane_ref_[i] = {P.X[i].x, P.X[i].y, P.X[i].z, mask_bits(failed_at_[i] != 0)};
    lane_kind_.resize(B.kinds.size());
    lane_contact_.resize(B.kinds.size());
    for (std::size_t q = 0; q < B.kinds.size(); ++q) {
      const BondKind& bk = B.kinds[q];
      const KindCoefficients& kc = M.kind[q];
      lane_kind_[q] = {kc.length, kc.inv_length, bk.weight, bk.volume * bk.fraction};
      lane_contact_[q] = {kc.contact_d2, kc.contact_d, kc.contact_k, 0.0};
    }
    lane_rec_.resize(kLaneRecord * n);
    if (vol_gradient_) lane_pk_.resize(kLanePK * n);
  }
  const PairPass c{s,
                   M.packed.data(),
                   P.X.data(),
                   M.kind.data(),
                   B.kinds.data(),
                   M.break_after_force,
                   s.critical_stretch_factor.empty() ? nullptr : s.critical_stretch_factor.data(),
                   &pass,
                   energy,
                   keep_q,
                   lanes,
                   s.contact.acts_on_family(),
                   lane_ref_.data(),
                   lane_kind_.data(),
                   lane_contact_.data()};

  // 1. Breaking and the strain sums, row by row.
  uint64_t broken = 0;
#pragma omp parallel for schedule(static) reduction(+ : broken) if (n > 512)
  for (std::size_t l = 0; l < n; ++l) broken += (this->*break_row)(c, l);
  exchange_midpoint(s);
  if (lanes && midpoint_) {
    lane_mid_.resize(8 * n);
    for (std::size_t l = 0; l < n; ++l) {
      double* v = lane_mid_.data() + 8 * l;
      for (int q = 0; q < 6; ++q) v[q] = e_vec_[l][q];
      v[6] = ks_[l];
      v[7] = mask_bits(e_ok_[l] != 0);
    }
  }

  // 2. The law, the stabilisation and the record, row by row.
#pragma omp parallel for schedule(static) if (n > 512)
  for (std::size_t l = 0; l < n; ++l) (this->*law_row)(c, l);

  // 3. The pair sum with the family contact, over the rows the general pass sums.
  const std::vector<uint32_t>* act = s.active_rows.empty() ? nullptr : &s.active_rows;
  const std::size_t rows = act ? act->size() : np;
#pragma omp parallel for schedule(static) if (rows > 512)
  for (std::size_t row = 0; row < rows; ++row) (this->*sum_row)(c, act ? (*act)[row] : row);
  const Point4* y = M.packed.data();
  for (std::size_t i = 0; i < np; ++i) pair_y_[i] = {y[i].x, y[i].y, y[i].z};
  if (M.break_after_force)
    for (std::size_t k = 0; k < nb; ++k)
      if (B.intact[k] == 2) B.intact[k] = 0;
  return broken;
}

void ExtendedCorrespondence::commit(System& s) {
  for (std::size_t l = 0; l < particles_.size(); ++l) {
    if (!s.computes_row(particles_[l])) continue;  // another rank's row
    // stabilization_softening secant: k_s follows the committed plastic strain (thesis
    // sec. 8 suggests the plastic part of the bond strain state, after Mitchell; this is
    // the scalar version): k_s = k_s0 s_f/(s_f + 3 mu eps_p), the secant of the flow curve
    // sigma = s_f, total shear strain s_f/(3 mu) + eps_p, over mu. It only falls; the
    // energy W_s (k_old - k_new)/k_old it releases at fixed positions is booked as plastic
    // work (exact for the full residual; the midpoint one shares k between the ends).
    if (secant_ && ks0_[l] > 0 && !inactive_[l]) {
      const double sf = classical::flow_stress(law_, trial_[l].alpha, 0.0);
      const double k_new = ks0_[l] * sf / (sf + 3.0 * law_.mu * trial_[l].alpha);
      if (k_new < ks_[l]) {
        work_[l] += ws_[l] * (ks_[l] - k_new) / ks_[l];
        ks_[l] = k_new;
      }
    }
    const double lost = released(l) + switched_[l];
    const double d = work_[l] + lost + thinned_[l];
    if (d != 0) s.dissipated_at[particles_[l]] += d * s.particles.volume[particles_[l]];
    plastic_total_[l] += work_[l];
    failure_total_[l] += lost;
    thinned_total_[l] += thinned_[l];
    switched_[l] = thinned_[l] = 0;
    committed_[l] = trial_[l];
    work_[l] = 0;
  }
  if (stab_yield_ > 0 && !rp_trial_.empty()) {
    const Bonds& B = s.bonds;
    for (uint32_t i : particles_)
      if (s.computes_row(i))
        for (uint64_t k = B.begin(i); k < B.end(i); ++k) rp_committed_[k] = rp_trial_[k];
  }
}

// The stable step from the current state (solver.adaptive_time_step), as the classical
// correspondence model's (correspondence.cpp spring_factors): the law's Kirchhoff stress
// on a logarithmic strain (the Hencky measure, or E_(0)) gives a reference tangent that a
// bond of direction n sees |F^-T n|^2 times stiffer than undeformed (a compression to the
// stretch lambda along n: 1/lambda^2; digest 000 sec. 10, pitfall 14), while the
// Silling-Askari bound of the shared spring (Silling and Askari 2005, eq. 17) is taken from
// the reference state. F is the classical nonlocal deformation gradient over the bonds
// that acted at the last force pass, with their shape tensor's inverse kept by that pass
// (kinv_; material/nonlocal_gradient.hpp), so every rank that computes the row finds the
// same factor (the acting set reads the neighbours' damage as the pass had it). The factor
// of particle i is the mean of |F^-T n|^2 over its bonds with the bound's weights
// omega V/|xi|: 1 in the reference state. A particle that carried no stress at the last
// pass, or with det F <= 0, keeps 1; before the first pass every particle keeps 1.
bool ExtendedCorrespondence::spring_factors(const System& s, std::vector<double>& g) const {
  if (!adaptive_) return false;
  const Bonds& B = s.bonds;
  const Particles& P = s.particles;
  if (acted_.size() != B.size()) return true;
  const std::size_t n = particles_.size();
#pragma omp parallel for schedule(static) if (n > 512)
  for (std::size_t l = 0; l < n; ++l) {
    const uint32_t i = particles_[l];
    if (!s.computes_row(i) || inactive_[l] || B.begin(i) == B.end(i)) continue;  // another rank's row
    const Vec3 yi = P.position(i);
    Mat3 N = Mat3::Zero();
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
      if (!acted_[k]) continue;
      const Vec3 xi = P.X[B.nbr[k]] - P.X[i], Y = P.position(B.nbr[k]) - yi;
      N.noalias() += (B.weight[k] * B.volume[k]) * Eigen::Vector3d(Y.x, Y.y, Y.z) * Eigen::RowVector3d(xi.x, xi.y, xi.z);
    }
    Mat3 F = N * kinv_[l];
    if (dim_ == 2) F(2, 2) = 1.0;
    if (!(F.determinant() > 0)) continue;
    const Mat3 FinvT = F.inverse().transpose();
    double num = 0, den = 0;
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
      const Vec3 xi = P.X[B.nbr[k]] - P.X[i];
      const double L = B.length[k];
      const double w = B.weight[k] * B.volume[k] / L;
      num += w * (FinvT * Eigen::Vector3d(xi.x / L, xi.y / L, xi.z / L)).squaredNorm();
      den += w;
    }
    if (den > 0 && std::isfinite(num)) g[i] = num / den;
  }
  return true;
}

void ExtendedCorrespondence::fields(const System& s, std::vector<ModelField>& out) const {
  const std::size_t n = s.particles.size();
  ModelField vm{"von_mises_stress", std::vector<double>(n, 0.0)};
  ModelField ep{"equivalent_plastic_strain", std::vector<double>(n, 0.0)};
  ModelField dm{"ductile_damage", std::vector<double>(n, 0.0)};
  ModelField in{"carries_no_stress", std::vector<double>(n, 0.0)};
  ModelField pw{"plastic_work", std::vector<double>(n, 0.0), true};  // a dissipation part
  ModelField fe{"failure_energy", std::vector<double>(n, 0.0), true};  // a dissipation part
  ModelField as{"acting_share", std::vector<double>(n, 0.0)};
  ModelField ae{"acting_set_energy", std::vector<double>(n, 0.0), true};  // a dissipation part
  for (const auto& model : s.models) {
    const auto* c = dynamic_cast<const ExtendedCorrespondence*>(model.get());
    if (!c) continue;
    for (std::size_t l = 0; l < c->particles_.size(); ++l) {
      const uint32_t i = c->particles_[l];
      vm.values[i] = c->von_mises_[l];
      ep.values[i] = c->committed_[l].alpha;
      dm.values[i] = c->committed_[l].damage;
      in.values[i] = c->inactive_[l];
      pw.values[i] = c->plastic_total_[l];
      fe.values[i] = c->failure_total_[l];
      as.values[i] = c->acting_share_[l];
      ae.values[i] = c->thinned_total_[l];
    }
  }
  out.push_back(std::move(vm));
  out.push_back(std::move(ep));
  out.push_back(std::move(dm));
  out.push_back(std::move(in));
  out.push_back(std::move(pw));
  out.push_back(std::move(fe));
  out.push_back(std::move(as));
  out.push_back(std::move(ae));
}

}  // namespace

namespace extended {
namespace {
bool g_pair_lanes = true;
}
void set_pair_lanes(bool on) { g_pair_lanes = on; }
bool pair_lanes() { return g_pair_lanes; }
}  // namespace extended

ModelEntry extended_correspondence_model() {
  return {traits(), [] { return std::unique_ptr<Model>(std::make_unique<ExtendedCorrespondence>()); }};
}

}  // namespace horizon
