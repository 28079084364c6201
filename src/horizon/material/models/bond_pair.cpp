#include "horizon/material/models/bond_pair.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "horizon/core/error.hpp"
#include "horizon/family/precrack.hpp"
#include "horizon/parallel/decomposition.hpp"
#include "horizon/state/system.hpp"

namespace horizon {

namespace {

constexpr double kPiValue = 3.14159265358979323846;

// Vec3 to the kernels' three doubles and back (kernels/bond_pair.hpp; no arithmetic).
kernels::BpVec bp(const Vec3& v) { return {v.x, v.y, v.z}; }
Vec3 vec(const kernels::BpVec& v) { return {v.x, v.y, v.z}; }

const ModelTraits& traits() {
  static const ModelTraits t = [] {
    ModelTraits m;
    m.name = "bond_pair";
    m.aliases = {"ogrady"};
    m.summary = "O'Grady's bond-pair beams, plates and flat shells: rotational springs between opposite bonds "
                "(seed 001, dissertation ch. 4-5)";
    m.critical_stretch_law = false;
    m.exclusive = true;
    m.structural = true;
    // Split over MPI ranks by its own pass (force_pass, split()): each rank evaluates the
    // pairs and bonds that reach its owned nodes (and the ghost nodes whose support force
    // it sums), in the serial order, from the positions of the particles they read.
    m.rows_local = true;
    m.influences = {InfluenceKind::constant};
    m.parameters = {
        {"depth", "beam: depth t of the rectangular section [m], I = area t^2/12; 0: a square section",
         ParameterSpec::Range::non_negative, 0.0},
        {"membrane", "in-plane (beam: axial) extension springs, eq. 4.13 (a shell needs them)",
         ParameterSpec::Range::boolean, 1.0},
        {"yield_strain", "elastic-perfectly-plastic pairs: surface yield strain (eq. 4.8); 0: elastic",
         ParameterSpec::Range::non_negative, 0.0},
        {"critical_strain", "brittle pairs: surface strain at which a pair fails for good (eq. 4.9); 0: never",
         ParameterSpec::Range::non_negative, 0.0},
    };
    m.choices = {
        {"pair_weight", "weight omega of the bending pairs: uniform (omega = 1) or length (omega = |xi|), sec. 4.2.3",
         {"uniform", "length"}},
    };
    return m;
  }();
  return t;
}

// One unordered pair of opposite bonds (j, j') through its centre k.
struct Pair {
  uint32_t k, j, jp;
  double coef;        // 2 omega alpha Vk Vj [N m]: e = coef (1 + cos theta)
  double iso;         // (4 C/m0) omega_iso Vk Vj / |xi|^2 (bond-multiple correction, sec. 4.4)
  double inv_length;  // 1/|xi|
  // Curved shells: the pair's reference angle theta0 (cos, sin); straight pairs have
  // cos = -1, sin = 0, and e = coef (1 - cos(theta - theta0)) is then coef (1 + cos theta).
  double c0 = -1, s0 = 0;
};

// One unordered bond (k, j) of the extension springs.
struct Bond {
  uint32_t k, j;
  double length;
  double coef;  // beta omega Vk Vj: e = coef (|Y| - |xi|)^2
  double dil;   // 2 omega |xi| / m_b (the 2-D dilatation, sec. 3.9) times V (of the other end)
};

// A ghost node: its displacement is an affine image of real nodes' displacements,
// u_g = sum_t coeff_t (componentwise) u_{node_t} (mirror across a support, digest sec. 4.7).
struct GhostTerm {
  uint32_t node;
  Vec3 coeff;
};

class BondPair final : public Model {
 public:
  std::unique_ptr<Model> clone() const override { return std::make_unique<BondPair>(*this); }
  const ModelTraits& traits() const override { return horizon::traits(); }
  bool owns_force_pass() const override { return true; }
  void setup(const ModelSetup& in) override;
  uint64_t force_pass(System& s, bool energy) override;
  // The failed pairs this rank keeps (their keeper's owner; every pair without a split).
  uint64_t failures_kept(const System& s) const override {
    uint64_t n = 0;
    for (std::size_t q = 0; q < failed_.size(); ++q)
      n += failed_[q] && (!part_ || s.decomposition->owns(keeper_[q])) ? 1 : 0;
    return n;
  }
  void commit(System& s) override;
  double pending_dissipation(const System& s) const override;
  bool support_reactions(const System& s, std::vector<Vec3>& out) const override;
  void hold_bonds(bool hold) override { held_ = hold; }
  double stable_time_step(const System& s) const override;
  bool stiffness(const System& s, StiffnessSink& out) const override;
  void fields(const System& s, std::vector<ModelField>& out) const override;

  // The per-pair history belongs to the pair's keeper (keeper_: a rank that evaluates the
  // pair owns it), so a checkpoint of a decomposed run takes each pair's entries from there.
  void checkpoint(StateArchive& a) override {
    a.io_listed("theta_p", theta_p_, keeper_);
    a.io_listed("theta_p_trial", theta_p_trial_, keeper_);
    a.io_listed("failed", failed_, keeper_);
    a.io("held", held_);
  }
 private:
  // Run split over ranks (s.decomposition with more than one rank): chooses, once per
  // decomposition, the pairs and bonds this rank evaluates and makes their particles its
  // ghosts (split()). `part_` false: every pair and bond (serially, and on one rank).
  void split(System& s);
  bool part_ = false;
  const Decomposition* split_for_ = nullptr;
  std::vector<uint32_t> my_pairs_, my_bonds_;  // ascending: the serial order of every sum
  std::vector<int32_t> ghost_rank_;            // per ghost node: the rank that sums its force
  std::vector<double> ghost_force_;            // exchange buffer of the ghosts' forces
  // Per pair: the real particle whose owner keeps its history (checkpoint) and counts its
  // failure: the centre, or a ghost centre's first master.
  std::vector<uint32_t> keeper_;
  uint32_t master(uint32_t node) const {
    return node < n_real_ ? node : ghost_terms_[ghost_offset_[node - n_real_]].node;
  }
  void positions(const System& s);
  void current_positions(const System& s, std::vector<Vec3>& y) const;
  Kink shell_kink(const std::vector<Vec3>& y, const Pair& p) const;
  double plastic_increment(std::size_t q) const;

  std::size_t n_real_ = 0;
  std::vector<Vec3> X_;                 // reference positions, real nodes then ghosts
  std::vector<double> V_;               // node length (beam) or area (plate) [m or m^2]
  std::vector<uint64_t> ghost_offset_;  // per ghost, into ghost_terms_
  std::vector<GhostTerm> ghost_terms_;
  // The supports a ghost's force goes to (its reaction, Model::support_reactions): the
  // support it mirrors across, or each of the two (weight 1/2) for a ghost of a ghost
  // beyond a corner. Per ghost, into ghost_share_.
  struct GhostShare {
    uint32_t support;
    double weight;
  };
  std::vector<uint64_t> share_offset_;
  std::vector<GhostShare> ghost_share_;
  std::vector<Vec3> support_force_;  // per support, at the last force pass [N]
  std::vector<Pair> pairs_;
  std::vector<Bond> bonds_;
  std::vector<double> section_;  // per real node: particle volume / V (area of a beam, thickness of a plate)
  std::vector<Vec3> y_;          // current positions of all nodes
  std::vector<Vec3> F_;          // nodal forces of all nodes [N]
  std::vector<Vec3> kbar_;       // isotropic curvature vector per node (sec. 4.4)
  std::vector<double> theta_;    // 2-D dilatation per node (sec. 3.9)
  std::vector<double> m0_inv_;   // per node: 1/m0 of its own complete pairs (curvature output)
  // Per pair history.
  // Plastic offset (committed, trial): kink_dims_ per pair, the signed kink of a beam or a
  // plate (1) or the kink vector (n, t) of a flat shell (2).
  std::vector<double> theta_p_, theta_p_trial_;
  std::vector<uint8_t> failed_;                  // brittle failure (permanent)
  std::vector<uint8_t> no_fail_;                 // a node of the pair lies in a no_fail region
  std::vector<double> pairs_at_;                 // pairs centred at each real node
  std::vector<double> failed_at_;                // failed pairs centred at each real node (damage; scratch)
  // Energy weight of a real node: 1/2 per support line it lies on. The forces on the real
  // nodes are -dE/du of E = sum_k weight_k e_k (e_k the energy of the pairs and half
  // bonds centred at k, ghosts following their masters): a ghost centre's terms are the
  // mirror images of a real centre's, and a centre on the line is its own image.
  std::vector<double> energy_weight_;
  bool held_ = false;
  bool transverse_ = true;  // beam / plate: z only
  bool signed_mode_ = false;
  int kink_dims_ = 1;
  double theta_yield_ = 0, theta_fail_ = 0;
  double iso_C_ = 0, dil_coef_ = 0;  // C of sec. 4.4; G h (3 nu - 1)/(1 - nu) of sec. 3.9
  double moment_factor_ = 0;         // moment per unit curvature: EI (beam), D (1 + nu) (plate)
  double bending_bound_ = 0, membrane_bound_ = 0, iso_bound_ = 0;  // time-step bounds
  int dim_ = 2;
};

// Integer lattice key of a position.
struct LatticeKey {
  int64_t a, b;
  bool operator==(const LatticeKey& o) const { return a == o.a && b == o.b; }
};
struct LatticeHash {
  std::size_t operator()(const LatticeKey& k) const {
    return std::hash<int64_t>()(k.a * 1000003 + k.b);
  }
};

void BondPair::setup(const ModelSetup& in) {
  System& s = in.system;
  const Config& config = in.config;
  const MaterialConfig& mat = in.material;
  for (const auto& m : config.materials)
    if (!find_model(m.model) || find_model(m.model)->traits.name != "bond_pair")
      throw Error("material '" + m.name + "' (model " + m.model + ") cannot share a run with model bond_pair");
  if (config.structure.kind == StructureKind::none)
    throw Error("model bond_pair models beams, plates and shells: give structure: {type: ...}");
  for (const auto& m : config.materials)
    if (m.youngs_modulus != mat.youngs_modulus || m.poissons_ratio != mat.poissons_ratio ||
        Model::parameter(m, "depth") != Model::parameter(mat, "depth"))
      throw Error("materials '" + mat.name + "' and '" + m.name +
                  "': a structure is one section of one material (one bond_pair material per run)");
  auto& P = s.particles;
  const std::size_t n = P.size();
  dim_ = config.dimension;
  const double dx = config.spacing, delta = config.horizon;
  transverse_ = config.structure.kind != StructureKind::shell;

  // The generic model arrays, neutral (other code reads their sizes); the forces reach
  // two horizons (the partner of a neighbour's partner), for the tangent's probing.
  auto& M = s.model;
  M.dim = dim_;
  M.weighted_volume.assign(n, 0);
  reset_model_arrays(M, n);
  M.state_based = true;
  s.dissipated_at.assign(n, 0);

  // Section: the beam's area A and depth t (I = A t^2/12), the plate's thickness h.
  const double E = mat.youngs_modulus, nu = mat.poissons_ratio, G = mat.shear_modulus;
  const double A = config.area, h = config.thickness;
  double depth = Model::parameter(mat, "depth");
  if (dim_ == 1 && depth == 0) depth = std::sqrt(A);
  if (dim_ == 2) depth = h;
  const double cellV = dim_ == 1 ? dx : dx * dx;  // node length or area

  // The lattice: every real node must be a lattice point (the pairs need exact opposites,
  // dissertation sec. 5.2: "the discretization must be absolutely regular").
  const Vec3 origin = n ? P.X[0] : Vec3{};
  // A cylindrical shell (StructureConfig::cylinder_radius): the lattice is that of (x, arc
  // length), periodic around with `around` nodes.
  const double R = config.structure.cylinder_radius;
  int64_t around = 0;
  if (R > 0) {
    const double f = 2 * kPiValue * R / dx;
    around = static_cast<int64_t>(std::llround(f));
    if (std::abs(f - static_cast<double>(around)) > 1e-6 * f || around < 3)
      throw Error("structure.cylinder_radius: the circumference 2 pi R = " + std::to_string(2 * kPiValue * R) +
                  " m must be a whole number of spacings (" + std::to_string(f) + ")");
  }
  auto wrap = [around](int64_t b) { return around > 0 ? ((b % around) + around) % around : b; };
  auto key_of = [&](const Vec3& x, bool& exact) {
    double fa = (x.x - origin.x) / dx, fb = dim_ == 2 ? (x.y - origin.y) / dx : 0.0;
    if (R > 0) {
      double arc = R * std::atan2(x.y, x.z);
      if (arc < 0) arc += 2 * kPiValue * R;
      fb = arc / dx;
    }
    const double ra = std::round(fa), rb = std::round(fb);
    exact = std::abs(fa - ra) < 1e-6 && std::abs(fb - rb) < 1e-6;
    return LatticeKey{static_cast<int64_t>(ra), wrap(static_cast<int64_t>(rb))};
  };
  std::unordered_map<LatticeKey, uint32_t, LatticeHash> where;
  n_real_ = n;
  X_.assign(P.X.begin(), P.X.end());
  V_.assign(n, cellV);
  section_.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    bool exact = false;
    const LatticeKey key = key_of(P.X[i], exact);
    const bool off = R > 0 ? std::abs(std::hypot(P.X[i].y, P.X[i].z) - R) > 1e-9 * dx : std::abs(P.X[i].z) > 1e-9 * dx;
    if (!exact || off || (dim_ == 1 && std::abs(P.X[i].y) > 1e-9 * dx))
      throw Error("model bond_pair needs a regular lattice of nodes (one spacing, one body lattice)");
    if (!where.emplace(key, static_cast<uint32_t>(i)).second)
      throw Error("model bond_pair: two nodes at one lattice point (a cylinder's lattice must not repeat the "
                  "first row at arc length 2 pi R)");
    section_[i] = P.volume[i] / cellV;
  }

  // Ghost nodes across each support (digest sec. 4.7 and 6): mirror every node within two
  // horizons of the support line (the stencil's reach) to the far side, transverse
  // displacement even (clamped) or odd (simply supported); the in-plane normal component
  // mirrors about the support line's own motion, the tangential one is even.
  energy_weight_.assign(n, 1.0);
  for (const auto& sup : config.structure.supports)
    for (std::size_t i = 0; i < n; ++i)
      if (std::abs(P.X[i][sup.axis] - sup.at) < 1e-6 * dx) energy_weight_[i] *= 0.5;
  std::vector<std::vector<GhostTerm>> terms(n);
  std::vector<std::vector<uint32_t>> across(n);  // the supports a node is the mirror image across (none: real)
  for (std::size_t i = 0; i < n; ++i) terms[i] = {GhostTerm{static_cast<uint32_t>(i), Vec3{1, 1, 1}}};
  for (std::size_t si = 0; si < config.structure.supports.size(); ++si) {
    const SupportConfig& sup = config.structure.supports[si];
    const int a = sup.axis;
    double mean = 0;
    for (std::size_t i = 0; i < n; ++i) mean += P.X[i][a] - sup.at;
    const double side = mean >= 0 ? 1.0 : -1.0;
    bool on_line = false;
    for (std::size_t i = 0; i < n; ++i) on_line = on_line || std::abs(P.X[i][a] - sup.at) < 1e-6 * dx;
    if (!on_line)
      throw Error("support at " + std::string(a == 0 ? "x" : "y") + " = " + std::to_string(sup.at) +
                  ": no node lies on it; place the lattice so that nodes lie on the supports (lattice_origin)");
    const std::size_t existing = X_.size();
    for (std::size_t i = 0; i < existing; ++i) {
      const double d = (X_[i][a] - sup.at) * side;
      if (!(d > 1e-6 * dx && d <= 2 * delta * (1 + 1e-9))) continue;
      Vec3 xg = X_[i];
      xg[a] = 2 * sup.at - X_[i][a];
      bool exact = false;
      const LatticeKey key = key_of(xg, exact);
      if (where.count(key)) continue;  // the body itself is there
      Vec3 foot_x = X_[i];
      foot_x[a] = sup.at;
      const auto foot = where.find(key_of(foot_x, exact));
      std::vector<GhostTerm> t;
      Vec3 mirror{1, 1, 1};
      mirror[a] = -1;
      mirror.z = sup.kind == SupportKind::clamped ? 1.0 : -1.0;
      for (const auto& term : terms[i]) t.push_back({term.node, Vec3{term.coeff.x * mirror.x, term.coeff.y * mirror.y,
                                                                     term.coeff.z * mirror.z}});
      if (foot != where.end())
        for (const auto& term : terms[foot->second]) {
          Vec3 c{};
          c[a] = 2 * term.coeff[a];
          t.push_back({term.node, c});
        }
      where.emplace(key, static_cast<uint32_t>(X_.size()));
      X_.push_back(xg);
      V_.push_back(V_[i]);
      terms.push_back(std::move(t));
      std::vector<uint32_t> sides = across[i];
      if (std::find(sides.begin(), sides.end(), static_cast<uint32_t>(si)) == sides.end())
        sides.push_back(static_cast<uint32_t>(si));
      across.push_back(std::move(sides));
    }
  }
  ghost_offset_.assign(1, 0);
  ghost_terms_.clear();
  share_offset_.assign(1, 0);
  ghost_share_.clear();
  for (std::size_t g = n; g < X_.size(); ++g) {
    for (const auto& t : terms[g]) ghost_terms_.push_back(t);
    ghost_offset_.push_back(ghost_terms_.size());
    for (uint32_t q : across[g]) ghost_share_.push_back({q, 1.0 / static_cast<double>(across[g].size())});
    share_offset_.push_back(ghost_share_.size());
  }
  support_force_.assign(config.structure.supports.size(), Vec3{});
  const std::size_t N = X_.size();

  // Lattice offsets of a full family, |xi| <= delta, and the bulk normalisations
  // (digest sec. 4.2: m over a full family, also near edges).
  const bool by_length = Model::choice(mat, "pair_weight") == "length";
  struct Offset {
    int64_t a, b;
    double length;
  };
  std::vector<Offset> half;  // one of each opposite pair
  double m_bend = 0, m_memb = 0, m0 = 0, s_bend = 0, s_iso = 0, s_memb = 0;
  const int64_t reach = static_cast<int64_t>(std::floor(delta / dx + 1e-9));
  for (int64_t a = -reach; a <= reach; ++a)
    for (int64_t b = (dim_ == 2 ? -reach : 0); b <= (dim_ == 2 ? reach : 0); ++b) {
      if (a == 0 && b == 0) continue;
      const double L = dx * std::sqrt(static_cast<double>(a * a + b * b));
      if (L > delta * (1 + 1e-9)) continue;
      const double w = by_length ? L : 1.0;
      m_bend += w * L * L * cellV;  // m = sum omega |xi|^2 V (eqs. 4.4, 4.12)
      m_memb += L * L * cellV;      // m = sum |xi|^2 V (eq. 4.13, omega = 1)
      m0 += L * cellV;              // m0 = sum omega_iso V, omega_iso = |xi| (sec. 4.4)
      s_bend += w * cellV / (L * L);
      s_iso += L * cellV / (L * L);
      s_memb += cellV;
      if (a > 0 || (a == 0 && b > 0)) half.push_back({a, b, L});
    }
  // alpha: beam EI/m (eq. 4.4); plate 2 G h^3 / (3 m) (eq. 4.12, D = G h^3/4 at nu = 1/3).
  const double I = A * depth * depth / 12;
  const double alpha = dim_ == 1 ? E * I / m_bend : 2 * G * h * h * h / (3 * m_bend);
  // Extension springs: beam EA/m (a 1-D bar, digest sec. 2.1); plate beta = 8 G h / m (eq. 4.13).
  const bool membrane = Model::parameter(mat, "membrane") != 0;
  const double beta = !membrane ? 0.0 : dim_ == 1 ? E * A / m_memb : 8 * G * h / m_memb;
  if (!membrane && !transverse_)
    throw Error("material '" + mat.name + "': a shell needs membrane: true (the bending pairs alone do not resist "
                "in-plane stretch or shear, dissertation sec. 4.3.2)");
  // Any Poisson ratio (sec. 3.9): the bond-multiple correction of the bending energy,
  // C = 2 G h^3/12 (3 nu - 1)/(1 - nu) (sec. 4.4), and the 2-D LPS dilatation term of the
  // membrane, G h (3 nu - 1)/(1 - nu).
  iso_C_ = dim_ == 2 ? 2 * G * h * h * h / 12 * (3 * nu - 1) / (1 - nu) : 0.0;
  if (std::abs(3 * nu - 1) < 1e-12) iso_C_ = 0;
  dil_coef_ = (dim_ == 2 && membrane && iso_C_ != 0) ? G * h * (3 * nu - 1) / (1 - nu) : 0.0;
  moment_factor_ = dim_ == 1 ? E * I : (E * h * h * h / (12 * (1 - nu * nu))) * (1 + nu);

  if (R > 0 && iso_C_ != 0)
    throw Error("material '" + mat.name + "': a curved shell takes nu = 1/3 only (the isotropic-curvature "
                "correction of sec. 4.4 is not defined about a curved reference)");
  // Failure and plasticity: one critical kink for every pair (digest sec. 3.5).
  const double ey = Model::parameter(mat, "yield_strain"), ec = Model::parameter(mat, "critical_strain");
  theta_yield_ = ey > 0 ? critical_kink(delta, ey, depth) : 0.0;
  theta_fail_ = ec > 0 ? critical_kink(delta, ec, depth) : 0.0;
  signed_mode_ = theta_yield_ > 0;
  kink_dims_ = transverse_ ? 1 : 2;
  if (signed_mode_ && R > 0)
    throw Error("material '" + mat.name + "': yield_strain needs a beam, a plate or a flat shell (the kink vector "
                "of a plastic pair is measured from a straight reference pair; a curved shell's pairs are not "
                "straight at rest)");

  // Pairs and bonds: every centre (real or ghost) whose pair touches a real node.
  pairs_.clear();
  bonds_.clear();
  pairs_at_.assign(n, 0);
  // A bond that crosses a precrack does not exist, nor does a pair with such a bond.
  auto cut = [&](std::size_t a, std::size_t b) {
    for (const auto& c : config.precracks)
      if (crosses(X_[a], X_[b], c, dim_)) return true;
    return false;
  };
  for (std::size_t k = 0; k < N; ++k) {
    bool exact = false;
    const LatticeKey kk = key_of(X_[k], exact);
    for (const auto& o : half) {
      auto j = where.find({kk.a + o.a, wrap(kk.b + o.b)});
      auto jp = where.find({kk.a - o.a, wrap(kk.b - o.b)});
      if (j != where.end() && cut(k, j->second)) j = where.end();
      if (jp != where.end() && cut(k, jp->second)) jp = where.end();
      // Bonds of ghosts alone move no real node, but complete the 2-D dilatation of a ghost
      // node (sec. 3.9), whose term does (as the ghost pairs complete kbar below).
      if (j != where.end() && (k < n || j->second < n || dil_coef_ != 0)) {
        const double coef = beta * V_[k] * V_[j->second];
        // The reference chord (= |xi| on a flat lattice).
        bonds_.push_back({static_cast<uint32_t>(k), j->second, norm(X_[j->second] - X_[k]), coef, 2 * o.length / m_memb});
      }
      if (j == where.end() || jp == where.end()) continue;
      // Pairs of ghosts alone move no real node, but complete the isotropic curvature of a
      // ghost centre (sec. 4.4), which does.
      if (k >= n && j->second >= n && jp->second >= n && iso_C_ == 0) continue;
      const double w = by_length ? o.length : 1.0;
      Pair p{static_cast<uint32_t>(k), j->second, jp->second, 2 * w * alpha * V_[k] * V_[j->second],
             4 * iso_C_ / m0 * o.length * V_[k] * V_[j->second] / (o.length * o.length), 1 / o.length};
      if (R > 0) {
        // The reference angle of a pair on the curved surface (the dissertation's ch. 6
        // proposal: the pairs not collinear at rest start with their own angle).
        const Vec3 e = X_[p.j] - X_[k], ep = X_[p.jp] - X_[k];
        p.c0 = std::clamp(dot(e, ep) / (norm(e) * norm(ep)), -1.0, 1.0);
        p.s0 = std::sqrt(std::max(0.0, 1 - p.c0 * p.c0));
        if (p.s0 < 1e-12) p.c0 = -1, p.s0 = 0;
      }
      pairs_.push_back(p);
      if (k < n) pairs_at_[k] += 1;
    }
  }
  m0_inv_.assign(N, 1 / m0);
  keeper_.resize(pairs_.size());
  for (std::size_t q = 0; q < pairs_.size(); ++q) keeper_[q] = master(pairs_[q].k);
  split_for_ = nullptr;
  part_ = false;
  theta_p_.assign(pairs_.size() * static_cast<std::size_t>(kink_dims_), 0);
  theta_p_trial_.assign(theta_p_.size(), 0);
  failed_.assign(pairs_.size(), 0);
  // no_fail_regions: a pair with a node in one never fails (loading points, supports).
  no_fail_.assign(pairs_.size(), 0);
  for (std::size_t q = 0; q < pairs_.size(); ++q)
    for (uint32_t node : {pairs_[q].k, pairs_[q].j, pairs_[q].jp})
      if (node < n && P.no_fail[node]) no_fail_[q] = 1;
  y_.assign(N, Vec3{});
  F_.assign(N, Vec3{});
  kbar_.assign(N, Vec3{});
  theta_.assign(N, 0);

  // Gerschgorin bounds of the linearised operator per unit V (digest sec. 4.8):
  // bending 16 alpha sum omega V/xi^2, extension 4 beta sum V, correction 2 |C| g^2.
  bending_bound_ = 16 * alpha * s_bend;
  membrane_bound_ = 4 * beta * s_memb;
  const double g = 4 / m0 * s_iso;
  iso_bound_ = 2 * std::abs(iso_C_) * g * g;
}

// Current positions of the real nodes and the ghosts, into y (resized; the force pass
// reuses its own buffer, so an explicit step allocates nothing).
void BondPair::current_positions(const System& s, std::vector<Vec3>& y) const {
  const auto& P = s.particles;
  y.resize(X_.size());
  for (std::size_t i = 0; i < n_real_; ++i) y[i] = P.X[i] + P.u[i];
  for (std::size_t g = 0; g + n_real_ < X_.size(); ++g) {
    kernels::BpVec u{};
    for (uint64_t t = ghost_offset_[g]; t < ghost_offset_[g + 1]; ++t)
      u = kernels::bp_ghost_term(u, bp(ghost_terms_[t].coeff), bp(P.u[ghost_terms_[t].node]));
    y[n_real_ + g] = vec(kernels::bp_add(bp(X_[n_real_ + g]), u));
  }
}

void BondPair::positions(const System& s) { current_positions(s, y_); }

// The kink vector of a pair of a flat shell (Kink, bond_pair.hpp): d = (u_j + u_j' -
// 2 u_k)/|xi| in the pair's reference frame, n along z, t along z x xi/|xi|.
Kink BondPair::shell_kink(const std::vector<Vec3>& y, const Pair& p) const {
  return kernels::bp_shell_kink(bp(y[p.j]), bp(y[p.jp]), bp(y[p.k]), bp(X_[p.j]), bp(X_[p.jp]), bp(X_[p.k]),
                                p.inv_length);
}

// |trial - committed| plastic offset of pair q (the length of the kink vector's increment).
double BondPair::plastic_increment(std::size_t q) const {
  double sum = 0;
  for (int c = 0; c < kink_dims_; ++c) {
    const double d = theta_p_trial_[q * kink_dims_ + c] - theta_p_[q * kink_dims_ + c];
    sum += d * d;
  }
  return std::sqrt(sum);
}

// The pairs and bonds this rank evaluates in a decomposed run. Its targets: its owned
// nodes and the ghost nodes it sums the support force of (those whose first master it
// owns). A target's force sums the pairs that touch it, the isotropic-curvature terms of
// their centres (each needs every pair of its centre) and the bonds that touch it (each
// needs the 2-D dilatation of both ends: every bond of a node bonded to a target). Every
// such sum runs over the same terms in the same order as serially, so the target's force
// has the serial bits. The particles these terms read (a ghost node: its masters) become
// the rank's ghosts (parallel/decomposition.hpp refresh_ghosts): two horizons and more
// from its own, beyond what the bond rows reach near a support. Collective.
void BondPair::split(System& s) {
  Decomposition& d = *s.decomposition;
  split_for_ = &d;
  part_ = d.size > 1;
  my_pairs_.clear();
  my_bonds_.clear();
  if (!part_) return;
  if (d.local_particles) throw Error("internal error: model bond_pair with local particles");
  const std::size_t n = n_real_, N = X_.size();
  std::vector<uint8_t> target(N, 0);
  for (std::size_t i = 0; i < n; ++i) target[i] = d.owns(i) ? 1 : 0;
  ghost_rank_.assign(N - n, 0);
  for (std::size_t g = 0; g + n < N; ++g) {
    ghost_rank_[g] = d.owner[master(static_cast<uint32_t>(n + g))];
    target[n + g] = ghost_rank_[g] == d.rank ? 1 : 0;
  }
  std::vector<uint8_t> centre(N, 0);
  for (const Pair& p : pairs_)
    if (target[p.k] || target[p.j] || target[p.jp]) centre[p.k] = 1;
  for (std::size_t q = 0; q < pairs_.size(); ++q)
    if (centre[pairs_[q].k]) my_pairs_.push_back(static_cast<uint32_t>(q));
  std::vector<uint8_t> near(target);
  for (const Bond& b : bonds_) {
    if (target[b.k]) near[b.j] = 1;
    if (target[b.j]) near[b.k] = 1;
  }
  for (std::size_t b = 0; b < bonds_.size(); ++b)
    if (near[bonds_[b].k] || near[bonds_[b].j]) my_bonds_.push_back(static_cast<uint32_t>(b));
  auto read = [&](uint32_t node) {
    auto mark = [&](uint32_t i) {
      if (!d.owns(i)) d.bond_ghosts[i] = 1;
    };
    if (node < n) return mark(node);
    for (uint64_t t = ghost_offset_[node - n]; t < ghost_offset_[node - n + 1]; ++t) mark(ghost_terms_[t].node);
  };
  for (uint32_t q : my_pairs_) read(pairs_[q].k), read(pairs_[q].j), read(pairs_[q].jp);
  for (uint32_t b : my_bonds_) read(bonds_[b].k), read(bonds_[b].j);
  refresh_ghosts(s, d);
  exchange_ghost_values(d, s.particles.u);  // the new ghosts' displacements for this pass
}

uint64_t BondPair::force_pass(System& s, bool energy) {
  auto& P = s.particles;
  if (s.decomposition && s.decomposition != split_for_) split(s);
  const std::size_t pair_count = part_ ? my_pairs_.size() : pairs_.size();
  const std::size_t bond_count = part_ ? my_bonds_.size() : bonds_.size();
  auto pair_at = [&](std::size_t a) { return part_ ? static_cast<std::size_t>(my_pairs_[a]) : a; };
  auto bond_at = [&](std::size_t a) -> const Bond& { return bonds_[part_ ? my_bonds_[a] : a]; };
  positions(s);
  const std::size_t N = X_.size();
  std::fill(F_.begin(), F_.end(), Vec3{});
  if (energy) std::fill(P.energy.begin(), P.energy.end(), 0.0);
  auto add_energy = [&](uint32_t node, double e) {
    if (energy && node < n_real_) P.energy[node] += e;
  };
  uint64_t newly_failed = 0;

  // A pair that fails is counted by its keeper's owner alone (summed over ranks).
  auto counts = [&](std::size_t q) { return !part_ || s.decomposition->owns(keeper_[q]) ? 1 : 0; };
  // Bending pairs (eqs. 3.1, 4.1 x 2; digest sec. 4.2), elastic-plastic (4.8) or brittle (4.9).
  for (std::size_t a = 0; a < pair_count; ++a) {
    const std::size_t q = pair_at(a);
    const Pair& p = pairs_[q];
    if (failed_[q]) continue;
    const Vec3 Y = y_[p.j] - y_[p.k], Yp = y_[p.jp] - y_[p.k];
    if (signed_mode_ && !transverse_) {
      // Flat shell with plastic offsets: e = coef (1 - cos |d - p|), d the kink vector, p its
      // plastic offset (plastic_offset of a Kink, a circular yield surface).
      const Kink d = shell_kink(y_, p);
      if (kernels::bp_fails(theta_fail_, no_fail_[q], kernels::bp_hypot(d.n, d.t), theta_fail_)) {
        if (!held_) {
          failed_[q] = 1;
          newly_failed += counts(q);
          continue;
        }
      }
      // de/dd = coef sin(r) (en, et)/r; the node's share of dd/dy is (1, 1, -2)/|xi| along n and t.
      const kernels::BpShellPair sp = kernels::bp_shell_pair(d, {theta_p_[2 * q], theta_p_[2 * q + 1]}, theta_yield_,
                                                              p.coef, p.inv_length, bp(X_[p.j]), bp(X_[p.k]));
      theta_p_trial_[2 * q] = sp.offset.n;
      theta_p_trial_[2 * q + 1] = sp.offset.t;
      const Vec3 G = vec(sp.G);
      F_[p.j] -= G;
      F_[p.jp] -= G;
      F_[p.k] += G * 2.0;
      add_energy(p.k, sp.energy);
      continue;
    }
    if (signed_mode_) {
      // Transverse mode with plastic offsets: e = coef (1 - cos(s - theta_p)).
      const double sk =
          kernels::bp_transverse_kink(y_[p.j].z, y_[p.jp].z, y_[p.k].z, X_[p.j].z, X_[p.jp].z, X_[p.k].z, p.inv_length);
      if (kernels::bp_fails(theta_fail_, no_fail_[q], kernels::bp_abs(sk), theta_fail_)) {
        if (!held_) {
          failed_[q] = 1;
          newly_failed += counts(q);
          continue;
        }
      }
      const kernels::BpSignedPair sp = kernels::bp_signed_pair(sk, theta_p_[q], theta_yield_, p.coef, p.inv_length);
      theta_p_trial_[q] = sp.offset;
      F_[p.j].z -= sp.g;
      F_[p.jp].z -= sp.g;
      F_[p.k].z += 2 * sp.g;
      add_energy(p.k, sp.energy);
      continue;
    }
    const kernels::BpElasticPair ep = kernels::bp_elastic_pair(bp(Y), bp(Yp), p.coef, p.c0, p.s0);
    if (kernels::bp_fails(theta_fail_, no_fail_[q], ep.f, 1 - kernels::bp_cos(theta_fail_))) {
      if (!held_) {
        failed_[q] = 1;
        newly_failed += counts(q);
        continue;
      }
    }
    const Vec3 Fj = vec(ep.Fj), Fjp = vec(ep.Fjp);
    F_[p.j] += Fj;
    F_[p.jp] += Fjp;
    F_[p.k] -= Fj + Fjp;
    add_energy(p.k, p.coef * ep.f);
  }

  // Isotropic-curvature (bond-multiple) correction for nu != 1/3 (eq. 4.14, digest sec. 4.4):
  // kbar_k = (1/m0) sum_j omega (Y_kj + Y_kj')/|xi|^2 V_j, E' = sum_k C kbar.kbar V_k.
  if (iso_C_ != 0) {
    std::fill(kbar_.begin(), kbar_.end(), Vec3{});
    for (std::size_t a = 0; a < pair_count; ++a) {
      const std::size_t q = pair_at(a);
      const Pair& p = pairs_[q];
      if (failed_[q]) continue;
      const Vec3 Y = y_[p.j] - y_[p.k], Yp = y_[p.jp] - y_[p.k];
      // Both orientations of the pair: 2 omega V_j (Y + Y')/|xi|^2, omega_iso = |xi|.
      kbar_[p.k] += vec(kernels::bp_curvature_term(bp(Y), bp(Yp), p.inv_length, V_[p.j], m0_inv_[p.k]));
    }
    for (std::size_t a = 0; a < pair_count; ++a) {
      const std::size_t q = pair_at(a);
      const Pair& p = pairs_[q];
      if (failed_[q]) continue;
      const Vec3 g = vec(kernels::bp_scale(bp(kbar_[p.k]), p.iso));  // dE'/dy_j = dE'/dy_j' = (4C/m0) omega Vk Vj kbar_k/|xi|^2
      F_[p.j] -= g;
      F_[p.jp] -= g;
      F_[p.k] += g * 2.0;
    }
    if (energy)
      for (std::size_t k = 0; k < n_real_; ++k) P.energy[k] += kernels::bp_curvature_energy(iso_C_, bp(kbar_[k]), V_[k]);
  }

  // Extension springs (eq. 4.13): e = beta omega Vk Vj (|Y| - |xi|)^2 per bond, and for
  // nu != 1/3 the 2-D dilatation term (sec. 3.9): E' = sum_k (G h/2)(3nu-1)/(1-nu) theta_k^2 V_k,
  // theta_k = (2/m) sum_j omega |xi| (|Y| - |xi|) V_j.
  if (!bonds_.empty() && bonds_[0].coef != 0) {
    if (dil_coef_ != 0) {
      std::fill(theta_.begin(), theta_.end(), 0.0);
      for (std::size_t a = 0; a < bond_count; ++a) {
        const Bond& b = bond_at(a);
        const double e = kernels::bp_bond_extension(bp(y_[b.j] - y_[b.k]), b.length);
        theta_[b.k] += kernels::bp_dilatation_term(b.dil, e, V_[b.j]);
        theta_[b.j] += kernels::bp_dilatation_term(b.dil, e, V_[b.k]);
      }
    }
    for (std::size_t a = 0; a < bond_count; ++a) {
      const Bond& b = bond_at(a);
      const kernels::BpVec Y = bp(y_[b.j] - y_[b.k]);
      const double L = kernels::bp_bond_length(Y), e = L - b.length;
      // dE/d|Y| = 2 coef e (+ the dilatation term) along Y.
      const Vec3 f = vec(kernels::bp_spring_force(Y, L, e, b.coef, dil_coef_, b.dil, theta_[b.k], theta_[b.j], V_[b.k],
                                                  V_[b.j]));
      F_[b.k] += f;
      F_[b.j] -= f;
      add_energy(b.k, kernels::bp_spring_energy(b.coef, e));
      add_energy(b.j, kernels::bp_spring_energy(b.coef, e));
    }
    if (energy && dil_coef_ != 0)
      for (std::size_t k = 0; k < n_real_; ++k) P.energy[k] += kernels::bp_dilatation_energy(dil_coef_, theta_[k], V_[k]);
  }

  // The ghosts' forces act on no particle: the supports take them (their reactions,
  // support_reactions). The forces of every pair and bond sum to zero, so the reactions
  // of the support nodes plus these balance the load at equilibrium.
  // Split over ranks: each ghost's force from the rank that sums it (every rank then adds
  // them up in the serial order).
  if (part_) {
    ghost_force_.clear();
    for (std::size_t g = 0; g + n_real_ < N; ++g)
      if (ghost_rank_[g] == s.decomposition->rank)
        ghost_force_.insert(ghost_force_.end(), {F_[n_real_ + g].x, F_[n_real_ + g].y, F_[n_real_ + g].z});
    const std::vector<double> all = allgather_values(ghost_force_);
    // Rank r's entries start after those of the ranks before it.
    std::vector<std::size_t> at(static_cast<std::size_t>(s.decomposition->size) + 1, 0);
    for (int32_t r : ghost_rank_) at[static_cast<std::size_t>(r) + 1] += 3;
    for (std::size_t r = 1; r < at.size(); ++r) at[r] += at[r - 1];
    for (std::size_t g = 0; g + n_real_ < N; ++g) {
      std::size_t& k = at[static_cast<std::size_t>(ghost_rank_[g])];
      F_[n_real_ + g] = {all[k], all[k + 1], all[k + 2]};
      k += 3;
    }
  }
  std::fill(support_force_.begin(), support_force_.end(), Vec3{});
  for (std::size_t g = 0; g + n_real_ < N; ++g)
    for (uint64_t t = share_offset_[g]; t < share_offset_[g + 1]; ++t)
      support_force_[ghost_share_[t].support] -= F_[n_real_ + g] * ghost_share_[t].weight;
  // Force densities of the real nodes (ghost forces are dropped: the ghosts only complete
  // the stencils near the supports); beams and plates move in z only.
  // A node on a support line is its own mirror image: F_ is the derivative of the whole
  // mirrored energy (body and ghosts), 1/w_k times that of the booked energy E = sum_k
  // w_k e_k for such a node (1 elsewhere: there the ghost image adds as much again). A
  // shell's line nodes move in plane, so their in-plane forces take the weight w_k and are
  // then -dE/du of the booked energy (without it the ledger of a shell pushed along a
  // support drifted). The held w keeps the whole force: it is the support's reaction.
  for (std::size_t i = 0; i < n_real_; ++i) {
    P.f[i] = vec(kernels::bp_node_force(bp(F_[i]), P.volume[i], transverse_, energy_weight_[i]));
    if (energy) P.energy[i] = kernels::bp_node_energy(P.energy[i], energy_weight_[i], P.volume[i]);
  }
  // Damage: the fraction of failed pairs about each node (dissertation Fig. 5.16).
  if (theta_fail_ > 0) {
    failed_at_.assign(n_real_, 0.0);
    for (std::size_t q = 0; q < pairs_.size(); ++q)
      if (failed_[q] && pairs_[q].k < n_real_) failed_at_[pairs_[q].k] += 1;
    for (std::size_t i = 0; i < n_real_; ++i) P.damage[i] = kernels::bp_damage(failed_at_[i], pairs_at_[i]);
  }
  (void)N;
  return newly_failed;
}

void BondPair::commit(System& s) {
  if (!signed_mode_) return;
  // Plastic work: the yield force times the plastic kink increment, pair by pair, with the
  // centre's energy weight (1/2 on a support line, as its stored energy).
  for (std::size_t q = 0; q < pairs_.size(); ++q) {
    const double d = plastic_increment(q);
    if (d != 0 && pairs_[q].k < n_real_)
      s.dissipated_at[pairs_[q].k] += energy_weight_[pairs_[q].k] * pairs_[q].coef * std::sin(theta_yield_) * d;
  }
  theta_p_ = theta_p_trial_;
}

double BondPair::pending_dissipation(const System& s) const {
  (void)s;
  if (!signed_mode_) return 0;
  double sum = 0;
  for (std::size_t q = 0; q < pairs_.size(); ++q)
    if (pairs_[q].k < n_real_)
      sum += energy_weight_[pairs_[q].k] * pairs_[q].coef * std::sin(theta_yield_) * plastic_increment(q);
  return sum;
}

bool BondPair::support_reactions(const System& s, std::vector<Vec3>& out) const {
  (void)s;
  out = support_force_;
  return true;
}

double BondPair::stable_time_step(const System& s) const {
  // Central differences are stable for dt <= 2/sqrt(lambda_max), lambda_max <= (row sum
  // of the linearised operator per unit V)/(mass per unit V) (digest sec. 4.8).
  const auto& P = s.particles;
  double dt = std::numeric_limits<double>::infinity();
  const double bound = bending_bound_ + membrane_bound_ + iso_bound_;
  for (std::size_t i = 0; i < n_real_; ++i) dt = std::min(dt, kernels::bp_stable_step(bound, P.density[i], section_[i]));
  return dt;
}

namespace {
// A 3x3 block of the stiffness.
struct Block {
  double a[3][3] = {};
  static Block outer(const Vec3& u, const Vec3& v, double s = 1) {
    Block b;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) b.a[r][c] = s * u[r] * v[c];
    return b;
  }
  static Block identity(double s) {
    Block b;
    for (int r = 0; r < 3; ++r) b.a[r][r] = s;
    return b;
  }
  Block& operator+=(const Block& o) {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) a[r][c] += o.a[r][c];
    return *this;
  }
  Block operator+(const Block& o) const { return Block(*this) += o; }
  Block operator-() const {
    Block b;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) b.a[r][c] = -a[r][c];
    return b;
  }
  Block transpose() const {
    Block b;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) b.a[r][c] = a[c][r];
    return b;
  }
  Block scaled(double s) const {
    Block b;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) b.a[r][c] = s * a[r][c];
    return b;
  }
};
}  // namespace

// The tangent K = -dF/du of the force pass above, term by term (each term's energy e has
// nodal forces -de/dy, so its blocks are the Hessian d2e/dy_a dy_b), rows of the real
// nodes only (ghost forces are dropped by the force pass), columns of a ghost mapped to
// its masters by its mirror coefficients (u_g = sum coeff o u_master):
//   - bending pair, e = coef f(c), f = 1 + c (or 1 - cos(theta - theta0) on a curved
//     shell), c = e.e', e = Y/a, e' = Y'/b (eq. 4.1 x 2): f'(c) d2c + f''(c) dc dc^T, with
//     w = e' - c e, w' = e - c e', P = I - e e^T, P' = I - e' e'^T (differentiating
//     bond_pair_gradient once more),
//       d2c/dY2 = -(e w^T + w e^T + c P)/a^2,  d2c/dY'2 = -(e' w'^T + w' e'^T + c P')/b^2,
//       d2c/dY dY' = (P' - e w'^T)/(a b),
//     and Y = y_j - y_k, Y' = y_j' - y_k;
//   - signed (plastic) pair, e = coef (1 - cos(s - theta_p)), s = (w_j + w_j' - 2 w_k)/|xi|:
//     coef cos(s - theta_p) b b^T/|xi|^2, b = (1, 1, -2), while elastic, and 0 while the
//     pair flows plastically (perfect plasticity, sec. 3.5: the force is capped);
//   - plastic pair of a flat shell, e = coef (1 - cos |d - p|), d the kink vector (Kink):
//     b b^T/|xi|^2 (x) T H T^T, T = [z, z x xi/|xi|], H = coef (cos r h h^T + sin r/r
//     (I - h h^T)) while elastic, coef sin theta_c (I - h h^T)/r while flowing (the
//     consistent tangent of the radial return), h = (d - p)/r, r = |d - p|;
//   - isotropic-curvature correction (sec. 4.4), linear in y: per centre k,
//     K += (sum_q iso_q b_q)(sum_q c_q b_q)^T I, c_q = 2 V_j/(|xi| m0);
//   - extension springs, e = coef (|Y| - |xi|)^2 (+ dilatation): (t/|Y|)(I - n n^T) +
//     2 coef n n^T per bond (t = dE/d|Y| as in the force pass), and for nu != 1/3 the
//     dilatation term sum_c dil_coef V_c grad(theta_c) grad(theta_c)^T.
bool BondPair::stiffness(const System& s, StiffnessSink& out) const {
  std::vector<Vec3> y;
  current_positions(s, y);
  const int c0 = transverse_ ? 2 : 0;  // beams and plates: the z rows and columns only
  const Vec3 one{1, 1, 1};
  // K(a, b) += H, b real or a ghost.
  auto add_block = [&](uint32_t a, uint32_t b, const Block& H) {
    if (a >= n_real_) return;
    // A shell's support-line node: its in-plane rows with its energy weight (force_pass).
    const double wa = energy_weight_[a];
    auto put = [&](uint32_t node, const Vec3& coeff) {
      for (int r = c0; r < 3; ++r)
        for (int c = c0; c < 3; ++c) out.add(a, r, node, c, H.a[r][c] * coeff[c] * (r < 2 ? wa : 1.0));
    };
    if (b < n_real_) {
      put(b, one);
      return;
    }
    const std::size_t g = b - n_real_;
    for (uint64_t t = ghost_offset_[g]; t < ghost_offset_[g + 1]; ++t) put(ghost_terms_[t].node, ghost_terms_[t].coeff);
  };
  // K(a, b) += v for the z component alone.
  auto add_zz = [&](uint32_t a, uint32_t b, double v) {
    if (a >= n_real_) return;
    if (b < n_real_) {
      out.add(a, 2, b, 2, v);
      return;
    }
    const std::size_t g = b - n_real_;
    for (uint64_t t = ghost_offset_[g]; t < ghost_offset_[g + 1]; ++t)
      out.add(a, 2, ghost_terms_[t].node, 2, v * ghost_terms_[t].coeff.z);
  };

  // Bending pairs.
  for (std::size_t q = 0; q < pairs_.size(); ++q) {
    if (failed_[q]) continue;
    const Pair& p = pairs_[q];
    if (p.k >= n_real_ && p.j >= n_real_ && p.jp >= n_real_) continue;  // moves no real row
    const uint32_t nodes[3] = {p.j, p.jp, p.k};
    if (signed_mode_ && !transverse_) {
      // e = coef (1 - cos r), r = |d - p|: d2e/dd2 = coef (cos r h h^T + sin r/r (I - h h^T)),
      // h = (d - p)/r, while elastic; while flowing the force is coef sin theta_c h, whose
      // derivative is coef sin theta_c (I - h h^T)/r (radial return, r the trial kink).
      const Kink d = shell_kink(y, p);
      const double en = d.n - theta_p_[2 * q], et = d.t - theta_p_[2 * q + 1], r = std::hypot(en, et);
      double a_hh = p.coef, a_perp = p.coef;  // coefficients of h h^T and of I - h h^T
      if (r > theta_yield_) {
        a_hh = 0;
        a_perp = p.coef * std::sin(theta_yield_) / r;
      } else if (r > 0) {
        a_hh = p.coef * std::cos(r);
        a_perp = p.coef * std::sin(r) / r;
      }
      const double hn = r > 0 ? en / r : 1.0, ht = r > 0 ? et / r : 0.0;
      const Vec3 e0 = (X_[p.j] - X_[p.k]) * p.inv_length;
      const Vec3 nv{0, 0, 1}, tv{-e0.y, e0.x, 0};
      const Vec3 hv = nv * hn + tv * ht, pv = nv * (-ht) + tv * hn;  // h and its normal in (n, t)
      const Block Hd = (Block::outer(hv, hv, a_hh) + Block::outer(pv, pv, a_perp)).scaled(p.inv_length * p.inv_length);
      const double b[3] = {1, 1, -2};
      for (int rr = 0; rr < 3; ++rr)
        for (int cc = 0; cc < 3; ++cc) add_block(nodes[rr], nodes[cc], Hd.scaled(b[rr] * b[cc]));
      continue;
    }
    if (signed_mode_) {
      const double sk = signed_kink(y[p.j].z, y[p.jp].z, y[p.k].z, 1 / p.inv_length) -
                        (X_[p.j].z + X_[p.jp].z - 2 * X_[p.k].z) * p.inv_length;
      const double trial = sk - theta_p_[q];
      if (std::abs(trial) > theta_yield_) continue;  // flowing: the force is capped
      const double k = p.coef * std::cos(trial) * p.inv_length * p.inv_length;
      const double b[3] = {1, 1, -2};
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) add_zz(nodes[r], nodes[c], k * b[r] * b[c]);
      continue;
    }
    const Vec3 Y = y[p.j] - y[p.k], Yp = y[p.jp] - y[p.k];
    const double a = norm(Y), b = norm(Yp);
    const Vec3 e = Y / a, ep = Yp / b;
    const double c = dot(e, ep);
    const Vec3 w = ep - c * e, wp = e - c * ep;
    // e_pair = coef f(c): coef f'(c) d2c + coef f''(c) dc dc^T (referenced_pair).
    const ReferencedPair rp = referenced_pair(c, p.c0, p.s0);
    const double k1 = p.coef * rp.dc;
    const Block P = Block::identity(1) + -Block::outer(e, e), Pp = Block::identity(1) + -Block::outer(ep, ep);
    Block hYY = (Block::outer(e, w) + Block::outer(w, e) + P.scaled(c)).scaled(-k1 / (a * a));
    Block hPP = (Block::outer(ep, wp) + Block::outer(wp, ep) + Pp.scaled(c)).scaled(-k1 / (b * b));
    Block hYP = (Pp + -Block::outer(e, wp)).scaled(k1 / (a * b));
    if (rp.dcc != 0) {
      const Vec3 gY = w / a, gP = wp / b;  // dc/dY, dc/dY'
      const double k2 = p.coef * rp.dcc;
      hYY += Block::outer(gY, gY, k2);
      hPP += Block::outer(gP, gP, k2);
      hYP += Block::outer(gY, gP, k2);
    }
    const Block hPY = hYP.transpose();
    const Block H[3][3] = {
        {hYY, hYP, -(hYY + hYP)},
        {hPY, hPP, -(hPY + hPP)},
        {-(hYY + hPY), -(hYP + hPP), hYY + hYP + hPY + hPP},
    };
    for (int r = 0; r < 3; ++r)
      for (int cc = 0; cc < 3; ++cc) add_block(nodes[r], nodes[cc], H[r][cc]);
  }

  // Isotropic-curvature correction, centre by centre (the pairs are stored by centre).
  if (iso_C_ != 0) {
    std::vector<std::pair<uint32_t, double>> A, C;
    auto accumulate = [](std::vector<std::pair<uint32_t, double>>& v, uint32_t node, double x) {
      for (auto& e : v)
        if (e.first == node) {
          e.second += x;
          return;
        }
      v.emplace_back(node, x);
    };
    for (std::size_t q0 = 0; q0 < pairs_.size();) {
      std::size_t q1 = q0;
      while (q1 < pairs_.size() && pairs_[q1].k == pairs_[q0].k) ++q1;
      A.clear();
      C.clear();
      for (std::size_t q = q0; q < q1; ++q) {
        if (failed_[q]) continue;
        const Pair& p = pairs_[q];
        const double cq = 2 * p.inv_length * V_[p.j] * m0_inv_[p.k];
        accumulate(A, p.j, p.iso);
        accumulate(A, p.jp, p.iso);
        accumulate(A, p.k, -2 * p.iso);
        accumulate(C, p.j, cq);
        accumulate(C, p.jp, cq);
        accumulate(C, p.k, -2 * cq);
      }
      for (const auto& [ra, va] : A)
        for (const auto& [cb, vc] : C) add_block(ra, cb, Block::identity(va * vc));
      q0 = q1;
    }
  }

  // Extension springs and the dilatation term.
  if (!bonds_.empty() && bonds_[0].coef != 0) {
    std::vector<double> theta(X_.size(), 0.0);
    if (dil_coef_ != 0)
      for (const Bond& b : bonds_) {
        const double e = norm(y[b.j] - y[b.k]) - b.length;
        theta[b.k] += b.dil * e * V_[b.j];
        theta[b.j] += b.dil * e * V_[b.k];
      }
    // grad(theta_c) per centre c: (node, vector) terms.
    std::vector<std::vector<std::pair<uint32_t, Vec3>>> grad(dil_coef_ != 0 ? X_.size() : 0);
    for (const Bond& b : bonds_) {
      const Vec3 Y = y[b.j] - y[b.k];
      const double L = norm(Y), e = L - b.length;
      double t = 2 * b.coef * e;
      if (dil_coef_ != 0) t += dil_coef_ * (theta[b.k] * V_[b.k] * b.dil * V_[b.j] + theta[b.j] * V_[b.j] * b.dil * V_[b.k]);
      const Vec3 n = Y / L;
      const Block H = (Block::identity(t / L) + Block::outer(n, n, 2 * b.coef - t / L));
      add_block(b.j, b.j, H);
      add_block(b.k, b.k, H);
      add_block(b.j, b.k, -H);
      add_block(b.k, b.j, -H);
      if (dil_coef_ != 0) {
        auto accumulate = [](std::vector<std::pair<uint32_t, Vec3>>& v, uint32_t node, const Vec3& x) {
          for (auto& term : v)
            if (term.first == node) {
              term.second += x;
              return;
            }
          v.emplace_back(node, x);
        };
        accumulate(grad[b.k], b.j, n * (b.dil * V_[b.j]));
        accumulate(grad[b.k], b.k, n * (-b.dil * V_[b.j]));
        accumulate(grad[b.j], b.j, n * (b.dil * V_[b.k]));
        accumulate(grad[b.j], b.k, n * (-b.dil * V_[b.k]));
      }
    }
    for (std::size_t c = 0; c < grad.size(); ++c) {
      const double f = dil_coef_ * V_[c];
      for (const auto& [ra, ga] : grad[c])
        for (const auto& [cb, gb] : grad[c]) add_block(ra, cb, Block::outer(ga, gb, f));
    }
  }
  return true;
}

void BondPair::fields(const System& s, std::vector<ModelField>& out) const {
  const auto& P = s.particles;
  const std::size_t n = n_real_;
  ModelField w{"deflection", std::vector<double>(n)};
  ModelField kappa{"curvature", std::vector<double>(n)};
  ModelField moment{"moment", std::vector<double>(n)};
  // The mean curvature (kappa_1 + kappa_2)/2 of a plate, kappa of a beam:
  // (1/m0) sum_j omega (w_j + w_j' - 2 w_k)/|xi|^2 V_j over complete pairs, omega = |xi|
  // (the isotropic curvature of sec. 4.4, z component).
  std::vector<double> m0(n, 0), sum(n, 0);
  for (std::size_t q = 0; q < pairs_.size(); ++q) {
    const Pair& p = pairs_[q];
    if (p.k >= n) continue;
    auto wz = [&](uint32_t node) {
      if (node < n) return P.u[node].z;
      double u = 0;
      const std::size_t g = node - n;
      for (uint64_t t = ghost_offset_[g]; t < ghost_offset_[g + 1]; ++t)
        u += ghost_terms_[t].coeff.z * P.u[ghost_terms_[t].node].z;
      return u;
    };
    const double L = 1 / p.inv_length;
    sum[p.k] += 2 * L * V_[p.j] * (wz(p.j) + wz(p.jp) - 2 * wz(p.k)) / (L * L);
    m0[p.k] += 2 * L * V_[p.j];
  }
  for (std::size_t i = 0; i < n; ++i) {
    w.values[i] = P.u[i].z;
    kappa.values[i] = m0[i] > 0 ? sum[i] / m0[i] : 0.0;
    moment.values[i] = -moment_factor_ * kappa.values[i];
  }
  out.push_back(std::move(w));
  out.push_back(std::move(kappa));
  out.push_back(std::move(moment));
  if (signed_mode_) {
    ModelField plastic{"plastic_pairs", std::vector<double>(n, 0)};
    for (std::size_t q = 0; q < pairs_.size(); ++q)
      if (pairs_[q].k < n && std::any_of(theta_p_.begin() + static_cast<std::ptrdiff_t>(q * kink_dims_),
                                         theta_p_.begin() + static_cast<std::ptrdiff_t>((q + 1) * kink_dims_),
                                         [](double v) { return v != 0; }))
        plastic.values[pairs_[q].k] += 1 / pairs_at_[pairs_[q].k];
    out.push_back(std::move(plastic));
  }
  (void)kPiValue;
}

}  // namespace

ModelEntry bond_pair_model() {
  return {traits(), [] { return std::unique_ptr<Model>(std::make_unique<BondPair>()); }};
}

}  // namespace horizon
