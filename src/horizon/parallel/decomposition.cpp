#include "horizon/parallel/decomposition.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstring>
#include <numeric>
#include <unordered_map>

#include "horizon/core/cell_key.hpp"
#include "horizon/core/error.hpp"
#include "horizon/fe/fe_region.hpp"
#include "horizon/output/checkpoint.hpp"
#include "horizon/parallel/checkpoint_stream.hpp"
#include "horizon/parallel/lead_view.hpp"
#include "horizon/material/model.hpp"
#include "horizon/state/system.hpp"

#if defined(HORIZON_MPI)
#include <mpi.h>
#endif

namespace horizon {

namespace {

void rcb(const std::vector<Vec3>& x, std::vector<uint32_t>& ids, std::size_t begin, std::size_t end, int first,
         int ranks, std::vector<int32_t>& owner) {
  if (ranks == 1 || end - begin == 0) {
    for (std::size_t k = begin; k < end; ++k) owner[ids[k]] = first;
    return;
  }
  Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  for (std::size_t k = begin; k < end; ++k)
    for (int c = 0; c < 3; ++c) {
      lo[c] = std::min(lo[c], x[ids[k]][c]);
      hi[c] = std::max(hi[c], x[ids[k]][c]);
    }
  int axis = 0;
  for (int c = 1; c < 3; ++c)
    if (hi[c] - lo[c] > hi[axis] - lo[axis]) axis = c;
  std::sort(ids.begin() + static_cast<std::ptrdiff_t>(begin), ids.begin() + static_cast<std::ptrdiff_t>(end),
            [&](uint32_t a, uint32_t b) { return x[a][axis] < x[b][axis] || (x[a][axis] == x[b][axis] && a < b); });
  const int left = ranks / 2;
  const std::size_t cut = begin + (end - begin) * static_cast<std::size_t>(left) / static_cast<std::size_t>(ranks);
  rcb(x, ids, begin, cut, first, left, owner);
  rcb(x, ids, cut, end, first + left, ranks - left, owner);
}

Vec3 position(const System& s, std::size_t i) { return s.particles.X[i] + s.particles.u[i]; }

#if defined(HORIZON_MPI)
// Every rank's owned entries of `per` (k doubles per particle, packed by `pack`) onto
// every rank, unpacked by `unpack` in each owner's index order.
template <class Pack, class Unpack>
void allgather_owned(const System& s, const Decomposition& d, int k, Pack pack, Unpack unpack) {
  std::vector<double> mine;
  mine.reserve(d.owned.size() * static_cast<std::size_t>(k));
  for (uint32_t i : d.owned) pack(i, mine);
  std::vector<int> counts(static_cast<std::size_t>(d.size)), displs(static_cast<std::size_t>(d.size));
  std::vector<int> owned_count(static_cast<std::size_t>(d.size), 0);
  for (int32_t r : d.owner) ++owned_count[static_cast<std::size_t>(r)];
  int at = 0;
  for (int r = 0; r < d.size; ++r) {
    counts[static_cast<std::size_t>(r)] = owned_count[static_cast<std::size_t>(r)] * k;
    displs[static_cast<std::size_t>(r)] = at;
    at += counts[static_cast<std::size_t>(r)];
  }
  std::vector<double> all(static_cast<std::size_t>(at));
  MPI_Allgatherv(mine.data(), static_cast<int>(mine.size()), MPI_DOUBLE, all.data(), counts.data(), displs.data(),
                 MPI_DOUBLE, MPI_COMM_WORLD);
  std::vector<std::size_t> next(displs.begin(), displs.end());
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    std::size_t& p = next[static_cast<std::size_t>(d.owner[i])];
    unpack(i, all.data() + p);
    p += static_cast<std::size_t>(k);
  }
}
#endif

// Each rank r receives the entries send[r] of `from` into the entries recv[r] of `to`.
void exchange_values(Decomposition& d, const std::vector<std::vector<uint32_t>>& send, const std::vector<Vec3>& from,
                     const std::vector<std::vector<uint32_t>>& recv, std::vector<Vec3>& to) {
  if (d.size == 1) return;
#if defined(HORIZON_MPI)
  std::vector<std::vector<double>> out(static_cast<std::size_t>(d.size)), in(static_cast<std::size_t>(d.size));
  std::vector<MPI_Request> req;
  for (int r = 0; r < d.size; ++r) {
    const auto& rl = recv[static_cast<std::size_t>(r)];
    if (r == d.rank || rl.empty()) continue;
    in[static_cast<std::size_t>(r)].resize(3 * rl.size());
    req.emplace_back();
    MPI_Irecv(in[static_cast<std::size_t>(r)].data(), static_cast<int>(3 * rl.size()), MPI_DOUBLE, r, 7, MPI_COMM_WORLD,
              &req.back());
  }
  for (int r = 0; r < d.size; ++r) {
    const auto& sl = send[static_cast<std::size_t>(r)];
    if (r == d.rank || sl.empty()) continue;
    auto& o = out[static_cast<std::size_t>(r)];
    for (uint32_t i : sl) o.insert(o.end(), {from[i].x, from[i].y, from[i].z});
    req.emplace_back();
    MPI_Isend(o.data(), static_cast<int>(o.size()), MPI_DOUBLE, r, 7, MPI_COMM_WORLD, &req.back());
    ++d.stats.messages;
    d.stats.bytes += o.size() * sizeof(double);
  }
  MPI_Waitall(static_cast<int>(req.size()), req.data(), MPI_STATUSES_IGNORE);
  for (int r = 0; r < d.size; ++r) {
    const auto& rl = recv[static_cast<std::size_t>(r)];
    if (r == d.rank || rl.empty()) continue;
    const double* p = in[static_cast<std::size_t>(r)].data();
    for (std::size_t k = 0; k < rl.size(); ++k) to[rl[k]] = {p[3 * k], p[3 * k + 1], p[3 * k + 2]};
  }
#else
  (void)send, (void)from, (void)recv, (void)to;
#endif
}

// Local particles with short-range contact: the contact ghosts (decomposition.hpp)
// chosen from the current positions without gathering them. Each rank's box around its
// owned particles, widened by the contact reach plus the skin, goes to every rank; each
// rank sends the owned particles inside another rank's box (global id, X, u, V, c); the
// receiver keeps those it does not hold that lie within reach + skin of one of its owned
// particles and tells the sender which, whose displacements it then sends every step.
// Collective.
void choose_contact_ghosts(System& s, Decomposition& d) {
  ContactGhosts& g = d.contact;
  // The same set as before (the same ids in the same order: the candidates come in each
  // owner's index order) keeps its generation, so the contact lists are kept.
  const std::vector<int64_t> before = std::move(g.id);
  const bool first = g.generation == 0;
  g.id.clear(), g.X.clear(), g.u.clear(), g.volume.clear(), g.micromodulus.clear();
  const std::size_t ranks = static_cast<std::size_t>(d.size);
  d.contact_send.assign(ranks, {});
  d.contact_recv.assign(ranks, {});
#if defined(HORIZON_MPI)
  const auto& P = s.particles;
  const auto& M = s.model;
  const double reach = d.contact_reach + d.skin, reach2 = reach * reach;
  double box[6] = {1e300, 1e300, 1e300, -1e300, -1e300, -1e300};
  for (uint32_t i : d.owned) {
    const Vec3 y = position(s, i);
    for (int c = 0; c < 3; ++c) box[c] = std::min(box[c], y[c] - reach), box[3 + c] = std::max(box[3 + c], y[c] + reach);
  }
  std::vector<double> boxes(6 * ranks);
  MPI_Allgather(box, 6, MPI_DOUBLE, boxes.data(), 6, MPI_DOUBLE, MPI_COMM_WORLD);
  // The candidates for each rank: 9 doubles each (id exact below 2^53).
  constexpr int per = 9;
  std::vector<std::vector<uint32_t>> candidates(ranks);
  std::vector<double> out;
  std::vector<int> send_count(ranks, 0), send_at(ranks, 0), recv_count(ranks, 0), recv_at(ranks, 0);
  for (std::size_t r = 0; r < ranks; ++r) {
    send_at[r] = static_cast<int>(out.size());
    if (static_cast<int>(r) == d.rank) continue;
    const double* b = boxes.data() + 6 * r;
    for (uint32_t i : d.owned) {
      const Vec3 y = position(s, i);
      if (y.x < b[0] || y.y < b[1] || y.z < b[2] || y.x > b[3] || y.y > b[4] || y.z > b[5]) continue;
      candidates[r].push_back(i);
      out.insert(out.end(), {static_cast<double>(P.id[i]), P.X[i].x, P.X[i].y, P.X[i].z, P.u[i].x, P.u[i].y, P.u[i].z,
                             P.volume[i], M.contact_micromodulus[i]});
    }
    send_count[r] = static_cast<int>(out.size()) - send_at[r];
  }
  MPI_Alltoall(send_count.data(), 1, MPI_INT, recv_count.data(), 1, MPI_INT, MPI_COMM_WORLD);
  std::size_t at = 0;
  for (std::size_t r = 0; r < ranks; ++r) {
    if (at > static_cast<std::size_t>(INT_MAX)) throw Error("contact ghosts: too many candidates to exchange");
    recv_at[r] = static_cast<int>(at);
    at += static_cast<std::size_t>(recv_count[r]);
  }
  std::vector<double> in(at);
  MPI_Alltoallv(out.data(), send_count.data(), send_at.data(), MPI_DOUBLE, in.data(), recv_count.data(),
                recv_at.data(), MPI_DOUBLE, MPI_COMM_WORLD);
  out = {};
  // This rank's owned particles on a grid of cell reach + skin.
  std::unordered_map<uint64_t, std::vector<uint32_t>> grid;
  auto key = [&](const Vec3& p, int dx, int dy, int dz) {
    return pack_cell(cell_coord(p.x, reach) + dx, cell_coord(p.y, reach) + dy, cell_coord(p.z, reach) + dz);
  };
  for (uint32_t i : d.owned) grid[key(position(s, i), 0, 0, 0)].push_back(i);
  auto near = [&](const Vec3& y) {
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = grid.find(key(y, dx, dy, dz));
          if (it == grid.end()) continue;
          for (uint32_t i : it->second)
            if (norm2(position(s, i) - y) < reach2) return true;
        }
    return false;
  };
  // Keep those not held here and near an owned particle; tell each sender which.
  std::vector<uint32_t> kept;
  std::vector<int> keep_count(ranks, 0), keep_at(ranks, 0), give_count(ranks, 0), give_at(ranks, 0);
  for (std::size_t r = 0; r < ranks; ++r) {
    keep_at[r] = static_cast<int>(kept.size());
    const std::size_t count = static_cast<std::size_t>(recv_count[r]) / per;
    for (std::size_t k = 0; k < count; ++k) {
      const double* p = in.data() + recv_at[r] + k * per;
      const auto id = static_cast<int64_t>(p[0]);
      if (std::binary_search(P.id.begin(), P.id.end(), id)) continue;
      const Vec3 X{p[1], p[2], p[3]}, u{p[4], p[5], p[6]};
      if (!near(X + u)) continue;
      kept.push_back(static_cast<uint32_t>(k));
      d.contact_recv[r].push_back(static_cast<uint32_t>(g.id.size()));
      g.id.push_back(id);
      g.X.push_back(X);
      g.u.push_back(u);
      g.volume.push_back(p[7]);
      g.micromodulus.push_back(p[8]);
    }
    keep_count[r] = static_cast<int>(kept.size()) - keep_at[r];
  }
  MPI_Alltoall(keep_count.data(), 1, MPI_INT, give_count.data(), 1, MPI_INT, MPI_COMM_WORLD);
  at = 0;
  for (std::size_t r = 0; r < ranks; ++r) give_at[r] = static_cast<int>(at), at += static_cast<std::size_t>(give_count[r]);
  std::vector<uint32_t> give(at);
  MPI_Alltoallv(kept.data(), keep_count.data(), keep_at.data(), MPI_UINT32_T, give.data(), give_count.data(),
                give_at.data(), MPI_UINT32_T, MPI_COMM_WORLD);
  for (std::size_t r = 0; r < ranks; ++r)
    for (int k = 0; k < give_count[r]; ++k) d.contact_send[r].push_back(candidates[r][give[static_cast<std::size_t>(give_at[r] + k)]]);
  g.most = std::max(g.most, g.id.size());
#else
  (void)s;
#endif
  if (first || g.id != before) ++g.generation;
}

// The ghosts of this rank from the current positions of every particle (which must be
// up to date on this rank), and the lists of what to send where.
void choose_ghosts(System& s, Decomposition& d) {
  const std::size_t n = s.particles.size();
  const auto& B = s.bonds;
  // The bond ghosts never change (bonds only break): found once.
  if (d.bond_ghosts.size() != n) {
    d.bond_ghosts.assign(n, 0);
    for (uint32_t i : s.active_rows) {
      if (!d.owns(i)) d.bond_ghosts[i] = 1;
      for (uint64_t k = B.begin(i); k < B.end(i); ++k) d.bond_ghosts[B.nbr[k]] = 1;
    }
    // Finite-element regions: the nodes of the elements and interpolated particles this
    // rank updates (fe/fe_region.hpp FeRegion::split).
    if (s.fe) s.fe->split(d.is_owned, d.bond_ghosts);
  }
  std::vector<uint8_t> need = d.bond_ghosts;
  // Local particles: every particle held is kept current, also those only a bond cut by
  // a precrack brought in (the build keeps the rows' neighbours from before the cut):
  // the contact pass reads every held particle (choose_contact_ghosts sends none of them).
  if (d.local_particles) need.assign(n, 1);
  if (d.contact_reach > 0 && !d.local_particles) {
    // Every particle within reach + skin of an owned one (a hash grid of that cell size).
    const double cell = d.contact_reach + d.skin, cut2 = cell * cell;
    std::unordered_map<uint64_t, std::vector<uint32_t>> grid;
    auto key = [&](const Vec3& p, int dx, int dy, int dz) {
      return pack_cell(cell_coord(p.x, cell) + dx, cell_coord(p.y, cell) + dy, cell_coord(p.z, cell) + dz);
    };
    for (std::size_t j = 0; j < n; ++j) grid[key(position(s, j), 0, 0, 0)].push_back(static_cast<uint32_t>(j));
    for (uint32_t i : d.owned) {
      const Vec3 yi = position(s, i);
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dz = -1; dz <= 1; ++dz) {
            const auto it = grid.find(key(yi, dx, dy, dz));
            if (it == grid.end()) continue;
            for (uint32_t j : it->second)
              if (norm2(position(s, j) - yi) < cut2) need[j] = 1;
          }
    }
  }
  d.recv.assign(static_cast<std::size_t>(d.size), {});
  for (std::size_t j = 0; j < n; ++j)
    if (need[j] && !d.owns(j)) d.recv[static_cast<std::size_t>(d.owner[j])].push_back(static_cast<uint32_t>(j));
  // Local particles: the owners are asked by global id (Particles::id) and answer with
  // their local index.
  [[maybe_unused]] const auto& id = s.particles.id;
  d.send.assign(static_cast<std::size_t>(d.size), {});
#if defined(HORIZON_MPI)
  std::vector<int> want(static_cast<std::size_t>(d.size)), give(static_cast<std::size_t>(d.size));
  for (int r = 0; r < d.size; ++r) want[static_cast<std::size_t>(r)] = static_cast<int>(d.recv[static_cast<std::size_t>(r)].size());
  MPI_Alltoall(want.data(), 1, MPI_INT, give.data(), 1, MPI_INT, MPI_COMM_WORLD);
  std::vector<int> sd(static_cast<std::size_t>(d.size)), rd(static_cast<std::size_t>(d.size));
  std::vector<uint32_t> asked, flat;
  int a = 0, b = 0;
  for (int r = 0; r < d.size; ++r) {
    rd[static_cast<std::size_t>(r)] = a;
    a += want[static_cast<std::size_t>(r)];
    for (uint32_t j : d.recv[static_cast<std::size_t>(r)]) flat.push_back(d.local_particles ? static_cast<uint32_t>(id[j]) : j);
    sd[static_cast<std::size_t>(r)] = b;
    b += give[static_cast<std::size_t>(r)];
  }
  asked.resize(static_cast<std::size_t>(b));
  MPI_Alltoallv(flat.data(), want.data(), rd.data(), MPI_UINT32_T, asked.data(), give.data(), sd.data(), MPI_UINT32_T,
                MPI_COMM_WORLD);
  if (d.local_particles)
    for (uint32_t& g : asked) {
      const auto it = std::lower_bound(id.begin(), id.end(), static_cast<int64_t>(g));
      if (it == id.end() || *it != static_cast<int64_t>(g) || !d.owns(static_cast<std::size_t>(it - id.begin())))
        throw Error("internal error: a rank asks for particle " + std::to_string(g) + ", which this rank does not own");
      g = static_cast<uint32_t>(it - id.begin());
    }
  for (int r = 0; r < d.size; ++r)
    d.send[static_cast<std::size_t>(r)].assign(asked.begin() + sd[static_cast<std::size_t>(r)],
                                              asked.begin() + sd[static_cast<std::size_t>(r)] + give[static_cast<std::size_t>(r)]);
#endif
  if (d.local_particles && d.contact_reach > 0) choose_contact_ghosts(s, d);
  d.y_built.resize(n);
  for (uint32_t i : d.owned) d.y_built[i] = position(s, i);
  ++d.stats.rebuilds;
}

// Local rows: drops the rows this rank does not compute (a bond-based run holds only
// its owned rows; a state-based one keeps its neighbours' rows as built), then finds
// where each row lies in the serial CSR and the whole system's bond count.
void keep_computed_rows(System& s, Decomposition& d) {
  auto& B = s.bonds;
  const std::size_t n = s.particles.size();
  if (!d.state_based) {
    // Before any force pass: no per-bond array exists yet beside the rows themselves (a
    // bond-based run has only unified models, which keep no per-bond state).
    const auto& M = s.model;
    if (!M.deformed_length.empty() || !M.force_state.empty() || !M.reverse.empty() || !M.reverse32.empty())
      throw Error("internal error: per-bond arrays exist before the rows another rank computes are dropped");
    rewrite_bonds(B, [&](std::size_t i, uint64_t) { return s.row_active[i] ? BondAction::keep : BondAction::drop; });
    B.nbr.shrink_to_fit();
    B.kind.shrink_to_fit();
    B.intact.shrink_to_fit();
    B.lengths.shrink_to_fit();
  }
  if (d.local_particles) {
    // No per-particle offsets of the whole system here (they would be O(N)): the bond
    // count alone. Checkpoints, which need them, are built the old way.
    uint64_t mine = 0;
    for (uint32_t i : d.owned) mine += B.end(i) - B.begin(i);
    d.global_offset.clear();
    d.global_bonds = sum_over_ranks(mine);
    s.initial_bonds = d.global_bonds;
    return;
  }
  d.global_offset.assign(n + 1, 0);
  for (uint32_t i : d.owned) d.global_offset[i + 1] = B.end(i) - B.begin(i);
#if defined(HORIZON_MPI)
  if (d.size > 1)
    allgather_owned(
        s, d, 1, [&](uint32_t i, std::vector<double>& o) { o.push_back(static_cast<double>(d.global_offset[i + 1])); },
        [&](std::size_t i, const double* p) { d.global_offset[i + 1] = static_cast<uint64_t>(p[0]); });
#endif
  for (std::size_t i = 0; i < n; ++i) d.global_offset[i + 1] += d.global_offset[i];
  d.global_bonds = d.global_offset[n];
  s.initial_bonds = d.global_bonds;  // the bonds after the precracks, of the whole system
}

}  // namespace

std::vector<int32_t> rcb_owners(const std::vector<Vec3>& x, int ranks) {
  std::vector<int32_t> owner(x.size(), 0);
  std::vector<uint32_t> ids(x.size());
  std::iota(ids.begin(), ids.end(), 0u);
  rcb(x, ids, 0, ids.size(), 0, std::max(1, ranks), owner);
  return owner;
}

bool mpi_built() {
#if defined(HORIZON_MPI)
  return true;
#else
  return false;
#endif
}

int world_rank() {
#if defined(HORIZON_MPI)
  int r = 0, on = 0;
  MPI_Initialized(&on);
  if (on) MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
#else
  return 0;
#endif
}

int world_size() {
#if defined(HORIZON_MPI)
  int n = 1, on = 0;
  MPI_Initialized(&on);
  if (on) MPI_Comm_size(MPI_COMM_WORLD, &n);
  return n;
#else
  return 1;
#endif
}

void decompose(System& s, Decomposition& d, double skin) {
  d.rank = world_rank();
  d.size = world_size();
  d.skin = skin;
  d.contact_reach = s.contact.reach();
  // The rows of a particle read values its neighbours computed in the same pass: the
  // dilatation (state-based models) and the critical stretch lowered by the neighbour's
  // smallest stretch of the previous pass (the compression factor alpha). Then the
  // neighbours' rows are computed here too, from the positions one horizon further out.
  bool alpha = false;
  for (double a : s.model.alpha) alpha = alpha || a != 0;
  // The general force pass (models that are not unified, ModelTraits::rows_local) sums
  // T_ij - T_ji: the neighbours' rows are computed here too.
  // A thermal strain or a temperature-dependent critical stretch takes the general pass
  // for every model (solver/forces.cpp compute_forces): the neighbours' rows too.
  const bool thermal = !s.thermal_strain.empty() || !s.critical_stretch_factor.empty();
  d.state_based = s.model.state_based || alpha || !s.models.all_unified() || thermal;
  d.alpha = any_rank(d, alpha);  // the same on every rank: share_min_stretch is collective
  const std::size_t n = s.particles.size();
  // Local particles: the owners were decided on the whole lattice by the build.
  if (!d.local_particles) d.owner = rcb_owners(s.particles.X, d.size);
  if (d.local_particles && d.owner.size() != n) throw Error("internal error: local particles without their owners");
  d.owned.clear();
  d.is_owned.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i)
    if (d.owner[i] == d.rank) d.owned.push_back(static_cast<uint32_t>(i)), d.is_owned[i] = 1;
  s.owned = d.owned;
  if (d.state_based) {
    std::vector<uint8_t> act(d.is_owned);
    for (uint32_t i : d.owned)
      for (uint64_t k = s.bonds.begin(i); k < s.bonds.end(i); ++k) act[s.bonds.nbr[k]] = 1;
    s.active_rows.clear();
    for (std::size_t i = 0; i < n; ++i)
      if (act[i]) s.active_rows.push_back(static_cast<uint32_t>(i));
  } else {
    s.active_rows = d.owned;
  }
  s.row_active.assign(n, 0);
  for (uint32_t i : s.active_rows) s.row_active[i] = 1;
  {
    // The precracks' broken bonds (a restart loads its state after this).
    uint64_t mine = 0;
    for (uint32_t i : d.owned)
      for (uint64_t k = s.bonds.begin(i); k < s.bonds.end(i); ++k) mine += s.bonds.intact[k] != 1 ? 1 : 0;
    const uint64_t all = sum_over_ranks(mine);
    d.broken_at_start = all - std::min(all, s.broken);
  }
  if (d.local_rows) keep_computed_rows(s, d);
  s.decomposition = &d;
  choose_ghosts(s, d);
}

uint64_t sum_over_ranks(uint64_t x) {
#if defined(HORIZON_MPI)
  if (world_size() > 1) {
    uint64_t all = 0;
    MPI_Allreduce(&x, &all, 1, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
    return all;
  }
#endif
  return x;
}

double min_over_ranks(double x) {
#if defined(HORIZON_MPI)
  if (world_size() > 1) {
    double all = 0;
    MPI_Allreduce(&x, &all, 1, MPI_DOUBLE, MPI_MIN, MPI_COMM_WORLD);
    return all;
  }
#endif
  return x;
}

std::vector<uint64_t> gather_on_lead(uint64_t mine) {
#if defined(HORIZON_MPI)
  if (world_size() > 1) {
    std::vector<uint64_t> all(static_cast<std::size_t>(world_size()));
    MPI_Gather(&mine, 1, MPI_UINT64_T, all.data(), 1, MPI_UINT64_T, 0, MPI_COMM_WORLD);
    if (world_rank() != 0) all.clear();
    return all;
  }
#endif
  return {mine};
}

std::vector<double> allgather_values(const std::vector<double>& mine) {
#if defined(HORIZON_MPI)
  if (world_size() > 1) {
    const int size = world_size();
    const int count = static_cast<int>(mine.size());
    std::vector<int> counts(static_cast<std::size_t>(size)), displs(static_cast<std::size_t>(size));
    MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
    int at = 0;
    for (int r = 0; r < size; ++r) displs[static_cast<std::size_t>(r)] = at, at += counts[static_cast<std::size_t>(r)];
    std::vector<double> all(static_cast<std::size_t>(at));
    MPI_Allgatherv(mine.data(), count, MPI_DOUBLE, all.data(), counts.data(), displs.data(), MPI_DOUBLE, MPI_COMM_WORLD);
    return all;
  }
#endif
  return mine;
}

uint64_t checkpoint_bond_count(const System& s) {
  return s.decomposition && s.decomposition->local_rows ? s.decomposition->global_bonds : s.bonds.size();
}

void keep_local_bonds(const System& s, const Decomposition& d, const std::vector<std::string>& records,
                      CheckpointReader& in) {
  if (!d.local_rows) return;
  if (d.local_particles) throw Error("internal error: a restart of local particles picks its rows by global id");
  const auto& B = s.bonds;
  std::vector<std::pair<uint64_t, uint64_t>> rows;
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    const uint64_t held = B.end(i) - B.begin(i);
    if (held == 0) continue;
    if (held != d.global_offset[i + 1] - d.global_offset[i])
      throw Error("internal error: bond row " + std::to_string(i) + " holds " + std::to_string(held) +
                  " bonds here and " + std::to_string(d.global_offset[i + 1] - d.global_offset[i]) + " in the whole system");
    rows.emplace_back(d.global_offset[i], held);
  }
  in.keep_bond_rows(records, std::move(rows), d.global_bonds);
}

void refresh_ghosts(System& s, Decomposition& d) { choose_ghosts(s, d); }

void gather_checkpoint(const System& s, const Decomposition& d, CheckpointWriter& w) {
  if (d.size == 1) return;
  // Local particles: rank 0 writes the records as they come (parallel/checkpoint_stream.hpp).
  if (d.local_particles) throw Error("internal error: a checkpoint of local particles is gathered whole");
  const std::size_t n = s.particles.size(), nb = s.bonds.size();
  const auto& B = s.bonds;
  for (std::size_t index = 0; index < w.spread().size(); ++index) {
    const CheckpointWriter::Spread& r = w.spread()[index];
    if (r.extent == Extent::global || r.count == 0) continue;  // the same on every rank here
    const bool bonds = r.extent == Extent::bonds;
    // Extent::listed: entry group l belongs to particle (*list)[l].
    const std::vector<uint32_t>* list = r.extent == Extent::listed ? r.list : nullptr;
    if (r.extent == Extent::listed && !list) throw Error("checkpoint: record '" + r.name + "' has no particle list");
    const std::size_t units = bonds ? nb : list ? list->size() : n;  // entries of the array's first index
    if (units == 0 || r.count % units != 0)
      throw Error("checkpoint: record '" + r.name + "' has " + std::to_string(r.count) + " entries, not a multiple of the " +
                  std::to_string(units) + (bonds ? " bonds" : list ? " listed particles" : " particles"));
    const std::size_t per = r.element_size * (r.count / units);  // bytes per particle or bond
    char* data = w.bytes(r);
    // This rank's entries in index order: its particles, or the bonds of their rows.
    std::string mine;
    if (list) {
      for (std::size_t l = 0; l < list->size(); ++l)
        if (d.owns((*list)[l])) mine.append(data + l * per, per);
    } else {
      for (uint32_t i : d.owned) {
        const std::size_t a = bonds ? B.begin(i) : i, b = bonds ? B.end(i) : i + 1;
        mine.append(data + a * per, (b - a) * per);
      }
    }
#if defined(HORIZON_MPI)
    // Counted in entries of `per` bytes (a contiguous type), so that int counts reach far.
    MPI_Datatype entry;
    MPI_Type_contiguous(static_cast<int>(per), MPI_BYTE, &entry);
    MPI_Type_commit(&entry);
    const int count = static_cast<int>(mine.size() / per);
    std::vector<int> counts(static_cast<std::size_t>(d.size)), displs(static_cast<std::size_t>(d.size));
    MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
    std::string all;
    if (d.rank == 0) {
      std::size_t at = 0;
      for (int q = 0; q < d.size; ++q) {
        if (at > static_cast<std::size_t>(INT_MAX)) throw Error("checkpoint: record '" + r.name + "' is too large to gather");
        displs[static_cast<std::size_t>(q)] = static_cast<int>(at);
        at += static_cast<std::size_t>(counts[static_cast<std::size_t>(q)]);
      }
      all.resize(at * per);
    }
    MPI_Gatherv(mine.data(), count, entry, all.data(), counts.data(), displs.data(), entry, 0, MPI_COMM_WORLD);
    MPI_Type_free(&entry);
    if (d.rank != 0) continue;
    // Each owner's entries come in its index order: walk the particles in index order.
    std::vector<std::size_t> next(static_cast<std::size_t>(d.size));
    for (int q = 0; q < d.size; ++q)
      next[static_cast<std::size_t>(q)] = static_cast<std::size_t>(displs[static_cast<std::size_t>(q)]) * per;
    if (list) {
      for (std::size_t l = 0; l < list->size(); ++l) {
        std::size_t& at = next[static_cast<std::size_t>(d.owner[(*list)[l]])];
        std::memcpy(data + l * per, all.data() + at, per);
        at += per;
      }
    } else if (bonds && d.local_rows) {
      // Rank 0 holds some rows only: the whole system's array, row i from its owner at
      // its place in the serial order, replaces rank 0's own.
      std::string whole(static_cast<std::size_t>(d.global_bonds) * per, '\0');
      for (std::size_t i = 0; i < n; ++i) {
        const std::size_t bytes = static_cast<std::size_t>(d.global_offset[i + 1] - d.global_offset[i]) * per;
        std::size_t& at = next[static_cast<std::size_t>(d.owner[i])];
        std::memcpy(whole.data() + static_cast<std::size_t>(d.global_offset[i]) * per, all.data() + at, bytes);
        at += bytes;
      }
      w.replace(index, whole);
    } else {
      for (std::size_t i = 0; i < n; ++i) {
        const std::size_t a = bonds ? B.begin(i) : i, b = bonds ? B.end(i) : i + 1;
        std::size_t& at = next[static_cast<std::size_t>(d.owner[i])];
        std::memcpy(data + a * per, all.data() + at, (b - a) * per);
        at += (b - a) * per;
      }
    }
#else
    (void)data;
#endif
  }
}

bool any_rank(const Decomposition& d, bool flag) {
  (void)d;
#if defined(HORIZON_MPI)
  int in = flag ? 1 : 0, out = 0;
  MPI_Allreduce(&in, &out, 1, MPI_INT, MPI_LOR, MPI_COMM_WORLD);
  return out != 0;
#else
  return flag;
#endif
}

void halo_exchange(System& s, Decomposition& d) {
  [[maybe_unused]] auto& u = s.particles.u;
  if (d.size == 1) {  // one rank: no ghosts, nothing to send or to choose again
    ++d.stats.steps;
    return;
  }
  // Local particles: the bond ghosts (the bond neighbours of the rows computed here)
  // never change; the contact ghosts are chosen again when any particle has moved more
  // than half the skin since they were chosen (choose_contact_ghosts).
  if (d.local_particles) {
    if (d.contact_reach > 0) {
      const double half2 = 0.25 * d.skin * d.skin;
      bool moved = false;
      for (uint32_t i : d.owned) moved = moved || norm2(position(s, i) - d.y_built[i]) > half2;
      if (any_rank(d, moved)) {
        choose_contact_ghosts(s, d);
        for (uint32_t i : d.owned) d.y_built[i] = position(s, i);
        ++d.stats.rebuilds;
      }
    }
    ++d.stats.steps;
    exchange_ghost_values(d, u);
    if (d.contact_reach > 0) exchange_values(d, d.contact_send, u, d.contact_recv, d.contact.u);
    return;
  }
  const double half2 = 0.25 * d.skin * d.skin;
  bool moved = false;
  for (uint32_t i : d.owned) moved = moved || norm2(position(s, i) - d.y_built[i]) > half2;
  if (any_rank(d, moved)) {
#if defined(HORIZON_MPI)
    allgather_owned(
        s, d, 3, [&](uint32_t i, std::vector<double>& out) { out.insert(out.end(), {u[i].x, u[i].y, u[i].z}); },
        [&](std::size_t i, const double* p) { u[i] = {p[0], p[1], p[2]}; });
#endif
    choose_ghosts(s, d);
  }
  ++d.stats.steps;
  exchange_ghost_values(d, u);
}

void exchange_ghost_values(Decomposition& d, std::vector<Vec3>& a) { exchange_values(d, d.send, a, d.recv, a); }

void exchange_ghost_scalars(Decomposition& d, std::vector<double>& a) {
  if (d.size == 1) return;
#if defined(HORIZON_MPI)
  // exchange_ghost_values with one double a particle (tag 8).
  std::vector<std::vector<double>> out(static_cast<std::size_t>(d.size)), in(static_cast<std::size_t>(d.size));
  std::vector<MPI_Request> req;
  for (int r = 0; r < d.size; ++r) {
    const auto& rl = d.recv[static_cast<std::size_t>(r)];
    if (r == d.rank || rl.empty()) continue;
    in[static_cast<std::size_t>(r)].resize(rl.size());
    req.emplace_back();
    MPI_Irecv(in[static_cast<std::size_t>(r)].data(), static_cast<int>(rl.size()), MPI_DOUBLE, r, 8, MPI_COMM_WORLD,
              &req.back());
  }
  for (int r = 0; r < d.size; ++r) {
    const auto& sl = d.send[static_cast<std::size_t>(r)];
    if (r == d.rank || sl.empty()) continue;
    auto& o = out[static_cast<std::size_t>(r)];
    for (uint32_t i : sl) o.push_back(a[i]);
    req.emplace_back();
    MPI_Isend(o.data(), static_cast<int>(o.size()), MPI_DOUBLE, r, 8, MPI_COMM_WORLD, &req.back());
    ++d.stats.messages;
    d.stats.bytes += o.size() * sizeof(double);
  }
  MPI_Waitall(static_cast<int>(req.size()), req.data(), MPI_STATUSES_IGNORE);
  for (int r = 0; r < d.size; ++r) {
    const auto& rl = d.recv[static_cast<std::size_t>(r)];
    if (r == d.rank || rl.empty()) continue;
    const double* p = in[static_cast<std::size_t>(r)].data();
    for (std::size_t k = 0; k < rl.size(); ++k) a[rl[k]] = p[k];
  }
#else
  (void)a;
#endif
}

#if defined(HORIZON_MPI)
namespace {
// Local particles: each rank's owned entries (k doubles each, packed by `pack`) onto rank
// 0, where `unpack` gets each with its global id. Collective.
template <class Pack, class Unpack>
void gather_owned_on_lead(const System& s, const Decomposition& d, int k, Pack pack, Unpack unpack) {
  std::vector<double> mine;
  mine.reserve(d.owned.size() * static_cast<std::size_t>(k + 1));
  for (uint32_t i : d.owned) {
    mine.push_back(static_cast<double>(s.particles.id[i]));  // exact below 2^53
    pack(i, mine);
  }
  const int count = static_cast<int>(mine.size());
  std::vector<int> counts(static_cast<std::size_t>(d.size)), displs(static_cast<std::size_t>(d.size));
  MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  std::vector<double> all;
  if (d.rank == 0) {
    std::size_t at = 0;
    for (int r = 0; r < d.size; ++r) {
      if (at > static_cast<std::size_t>(INT_MAX)) throw Error("gather: the whole state is too large to gather on rank 0");
      displs[static_cast<std::size_t>(r)] = static_cast<int>(at);
      at += static_cast<std::size_t>(counts[static_cast<std::size_t>(r)]);
    }
    all.resize(at);
  }
  MPI_Gatherv(mine.data(), count, MPI_DOUBLE, all.data(), counts.data(), displs.data(), MPI_DOUBLE, 0, MPI_COMM_WORLD);
  if (d.rank != 0) return;
  const std::size_t per = static_cast<std::size_t>(k + 1);
  for (std::size_t at = 0; at + per <= all.size(); at += per)
    unpack(static_cast<std::size_t>(all[at]), all.data() + at + 1);
}
}  // namespace
#endif

std::vector<double> gather_on_lead(const System& s, const Decomposition& d, const std::vector<double>& local) {
  std::vector<double> whole;
#if defined(HORIZON_MPI)
  // Without local particles the indices are the global ids (Particles::id).
  if (d.rank == 0) whole.assign(d.local_particles ? d.global_particles : s.particles.size(), 0.0);
  gather_owned_on_lead(
      s, d, 1, [&](uint32_t i, std::vector<double>& o) { o.push_back(i < local.size() ? local[i] : 0.0); },
      [&](std::size_t g, const double* p) { whole[g] = p[0]; });
#else
  (void)s, (void)d;
  whole = local;
#endif
  return whole;
}

void gather_state(System& s, Decomposition& d) {
  [[maybe_unused]] auto& P = s.particles;
  const uint64_t broken = global_broken_bonds(s, d);  // collective
#if defined(HORIZON_MPI)
  if (d.local_particles && d.size > 1) {
    // The particles stay with their owners (rank 0 gathers what it reads: parallel/lead_view.hpp).
    s.broken = broken;
    return;
  }
  if (d.size == 1) {  // one rank owns every particle: nothing to gather
    s.broken = broken;
    return;
  }
  allgather_owned(
      s, d, 15,
      [&](uint32_t i, std::vector<double>& o) {
        o.insert(o.end(), {P.u[i].x, P.u[i].y, P.u[i].z, P.v[i].x, P.v[i].y, P.v[i].z, P.f[i].x, P.f[i].y, P.f[i].z,
                           P.b[i].x, P.b[i].y, P.b[i].z, P.damage[i], P.energy[i], s.dissipated_at[i]});
      },
      [&](std::size_t i, const double* p) {
        P.u[i] = {p[0], p[1], p[2]};
        P.v[i] = {p[3], p[4], p[5]};
        P.f[i] = {p[6], p[7], p[8]};
        P.b[i] = {p[9], p[10], p[11]};
        P.damage[i] = p[12];
        P.energy[i] = p[13];
        s.dissipated_at[i] = p[14];
      });
#endif
  s.broken = broken;
}

std::vector<HaloStats> gather_halo_stats(const Decomposition& d) {
  std::vector<HaloStats> all;
#if defined(HORIZON_MPI)
  uint64_t mine[4] = {d.stats.steps, d.stats.messages, d.stats.bytes, d.stats.rebuilds};
  std::vector<uint64_t> buf(4 * static_cast<std::size_t>(d.size));
  MPI_Gather(mine, 4, MPI_UINT64_T, buf.data(), 4, MPI_UINT64_T, 0, MPI_COMM_WORLD);
  if (d.rank == 0)
    for (int r = 0; r < d.size; ++r) {
      const uint64_t* b = buf.data() + 4 * r;
      all.push_back({b[0], b[1], b[2], b[3]});
    }
#else
  all.push_back(d.stats);
#endif
  return all;
}

GridSum::GridSum(const System& s, int quantities)
    : grid_(s.decomposition), plain_(static_cast<std::size_t>(quantities), 0.0) {
  if (grid_) terms_.resize(static_cast<std::size_t>(quantities));
}

std::vector<double> GridSum::totals() const {
  if (!grid_ && !exact_) return plain_;
  // Rounding every term to the grid 2^(E - 100), |term| < 2^E for the largest term over
  // all ranks, and adding the integers exactly: the total is the same however the terms
  // are split and ordered. 2^27 terms of at most 2^100 fit in 128 bits.
  const std::size_t nq = terms_.size();
  std::vector<int> e(nq, INT_MIN / 2), emax(nq);
  for (std::size_t q = 0; q < nq; ++q)
    for (double t : terms_[q])
      if (t != 0) {
        int x = 0;
        std::frexp(t, &x);
        e[q] = std::max(e[q], x);
      }
#if defined(HORIZON_MPI)
  if (grid_) MPI_Allreduce(e.data(), emax.data(), static_cast<int>(nq), MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  else emax = e;  // GridSum::exact without a decomposition: this process's terms alone
#else
  emax = e;
#endif
  std::vector<int64_t> parts(2 * nq);
  for (std::size_t q = 0; q < nq; ++q) {
    __int128 sum = 0;
    if (emax[q] > INT_MIN / 2) {
      // x = t 2^(100 - E) by one multiplication by an exact power of two (the same bits as
      // ldexp while the factor is a normal number, and a few times faster per term).
      const int shift = 100 - emax[q];
      const bool exact_scale = shift > -1000 && shift < 1000;
      const double scale = exact_scale ? std::ldexp(1.0, shift) : 0.0;
      for (double t : terms_[q]) {
        const double x = exact_scale ? t * scale : std::ldexp(t, shift);
        const double hi = std::trunc(x * 0x1p-50);
        const double rem = x - hi * 0x1p50;
        sum += static_cast<__int128>(static_cast<int64_t>(hi)) * (static_cast<__int128>(1) << 50) +
               static_cast<__int128>(std::llround(rem));
      }
    }
    const auto bits = static_cast<unsigned __int128>(sum);
    parts[2 * q] = static_cast<int64_t>(static_cast<uint64_t>(bits >> 64));
    parts[2 * q + 1] = static_cast<int64_t>(static_cast<uint64_t>(bits));
  }
  std::vector<int64_t> all = parts;
#if defined(HORIZON_MPI)
  if (grid_) {
    all.resize(parts.size() * static_cast<std::size_t>(grid_->size));
    MPI_Allgather(parts.data(), static_cast<int>(parts.size()), MPI_INT64_T, all.data(),
                  static_cast<int>(parts.size()), MPI_INT64_T, MPI_COMM_WORLD);
  }
#endif
  std::vector<double> out(nq, 0.0);
  const std::size_t ranks = all.size() / std::max<std::size_t>(1, parts.size());
  for (std::size_t q = 0; q < nq; ++q) {
    if (emax[q] <= INT_MIN / 2) continue;
    __int128 total = 0;
    for (std::size_t r = 0; r < ranks; ++r) {
      const unsigned __int128 bits = (static_cast<unsigned __int128>(static_cast<uint64_t>(all[r * parts.size() + 2 * q])) << 64) |
                                     static_cast<uint64_t>(all[r * parts.size() + 2 * q + 1]);
      total += static_cast<__int128>(bits);
    }
    out[q] = std::ldexp(static_cast<double>(total), emax[q] - 100);
  }
  return out;
}


// parallel/lead_view.hpp: what rank 0 reads of a run with local particles.
void gather_cracked(const System& s, const Decomposition* d, double threshold, Particles& out) {
  out = Particles();
  const Particles& P = s.particles;
  auto keep = [&](int64_t id, const Vec3& x, double damage) {
    out.add(x, 0, 0, 0, 0);
    out.id.back() = id;
    out.damage.back() = damage;
  };
#if defined(HORIZON_MPI)
  if (d && d->local_particles && d->size > 1) {
    // (global id, X, damage) of each owned cracked particle; rank 0 sorts them by id (each
    // rank's list is in ascending id already: the local numbering follows the global one).
    std::vector<double> mine;
    for (uint32_t i : d->owned)
      if (P.damage[i] >= threshold)
        mine.insert(mine.end(), {static_cast<double>(P.id[i]), P.X[i].x, P.X[i].y, P.X[i].z, P.damage[i]});
    const int count = static_cast<int>(mine.size());
    std::vector<int> counts(static_cast<std::size_t>(d->size)), displs(static_cast<std::size_t>(d->size));
    MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
    std::vector<double> all;
    if (d->rank == 0) {
      std::size_t at = 0;
      for (int r = 0; r < d->size; ++r) {
        if (at > static_cast<std::size_t>(INT_MAX)) throw Error("gather: too many cracked particles to gather on rank 0");
        displs[static_cast<std::size_t>(r)] = static_cast<int>(at);
        at += static_cast<std::size_t>(counts[static_cast<std::size_t>(r)]);
      }
      all.resize(at);
    }
    MPI_Gatherv(mine.data(), count, MPI_DOUBLE, all.data(), counts.data(), displs.data(), MPI_DOUBLE, 0,
                MPI_COMM_WORLD);
    if (d->rank != 0) return;
    std::vector<std::size_t> order(all.size() / 5);
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return all[5 * a] < all[5 * b]; });
    for (std::size_t k : order) {
      const double* q = all.data() + 5 * k;
      keep(static_cast<int64_t>(q[0]), {q[1], q[2], q[3]}, q[4]);
    }
    return;
  }
#else
  (void)d;
#endif
  for (std::size_t i = 0; i < P.size(); ++i)
    if (P.damage[i] >= threshold) keep(P.id[i], P.X[i], P.damage[i]);
}

void stream_on_lead(const System& s, const Decomposition* d, int width,
                    const std::function<void(uint32_t, std::vector<double>&)>& pack,
                    const std::function<void(std::size_t, const double*)>& take) {
  std::vector<double> buffer;
#if defined(HORIZON_MPI)
  if (d && d->size > 1) {
    // Every rank holds every particle without local particles, but only the owners' values
    // of some fields are current (the models' fields): from the owners too.
    const std::size_t n = d->local_particles ? d->global_particles : s.particles.size();
    const auto w = static_cast<std::size_t>(width);
    const auto ranks = static_cast<std::size_t>(d->size);
    const std::size_t slice = std::max<std::size_t>(1, (n + ranks - 1) / ranks);
    std::size_t next = 0;  // the first owned particle not sent yet (d->owned ascends in global id)
    std::vector<double> mine, all;
    std::vector<int> counts(static_cast<std::size_t>(d->size)), displs(static_cast<std::size_t>(d->size));
    for (std::size_t first = 0; first < n; first += slice) {
      const std::size_t end = std::min(n, first + slice);
      mine.clear();
      for (; next < d->owned.size() && static_cast<std::size_t>(s.particles.id[d->owned[next]]) < end; ++next) {
        const uint32_t i = d->owned[next];
        mine.push_back(static_cast<double>(s.particles.id[i]));  // exact below 2^53
        const std::size_t before = mine.size();
        pack(i, mine);
        if (mine.size() != before + w) throw Error("internal error: stream_on_lead: pack gave the wrong count of values");
      }
      const int count = static_cast<int>(mine.size());
      MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
      if (d->rank == 0) {
        std::size_t at = 0;
        for (int r = 0; r < d->size; ++r) {
          displs[static_cast<std::size_t>(r)] = static_cast<int>(at);
          at += static_cast<std::size_t>(counts[static_cast<std::size_t>(r)]);
        }
        all.resize(at);
      }
      MPI_Gatherv(mine.data(), count, MPI_DOUBLE, all.data(), counts.data(), displs.data(), MPI_DOUBLE, 0,
                  MPI_COMM_WORLD);
      if (d->rank != 0) continue;
      // Each of the slice's particles once, from its owner: put in global order, then taken.
      buffer.assign((end - first) * w, 0.0);
      std::size_t got = 0;
      for (std::size_t at = 0; at + w + 1 <= all.size(); at += w + 1, ++got) {
        const auto g = static_cast<std::size_t>(all[at]);
        if (g < first || g >= end) throw Error("internal error: stream_on_lead: a particle outside its slice");
        std::copy(all.begin() + static_cast<std::ptrdiff_t>(at + 1), all.begin() + static_cast<std::ptrdiff_t>(at + 1 + w),
                  buffer.begin() + static_cast<std::ptrdiff_t>((g - first) * w));
      }
      if (got != end - first) throw Error("internal error: stream_on_lead: a slice's particles are not all owned once");
      for (std::size_t g = first; g < end; ++g) take(g, buffer.data() + (g - first) * w);
    }
    return;
  }
#else
  (void)d, (void)width;
#endif
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    buffer.clear();
    pack(static_cast<uint32_t>(i), buffer);
    take(i, buffer.data());
  }
}

}  // namespace horizon
