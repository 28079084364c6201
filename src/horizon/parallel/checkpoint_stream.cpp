// Checkpoints with local particles, streamed (parallel/checkpoint_stream.hpp). Compiled
// twice, as decomposition.cpp: into the library without MPI (where no run has local
// particles on several ranks) and into horizon-mpi with HORIZON_MPI.
#include "horizon/parallel/checkpoint_stream.hpp"

#include <algorithm>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "horizon/core/error.hpp"
#include "horizon/output/checkpoint.hpp"
#include "horizon/parallel/decomposition.hpp"
#include "horizon/material/model.hpp"
#include "horizon/state/system.hpp"

#if defined(HORIZON_MPI)
#include <mpi.h>
#endif

namespace horizon {

uint64_t global_broken_bonds(const System& s, const Decomposition& d) {
  uint64_t broken = 0;
  for (uint32_t i : d.owned)
    for (uint64_t k = s.bonds.begin(i); k < s.bonds.end(i); ++k) broken += s.bonds.intact[k] != 1 ? 1 : 0;
  for (const auto& m : s.models) broken += m->failures_kept(s);  // a structure's failed pairs
  const uint64_t all = sum_over_ranks(broken);
  // The precracks' broken bonds are no breaks (the serial count): left out of the total.
  return all - std::min(all, d.broken_at_start);
}

#if defined(HORIZON_MPI)
namespace {

// The bytes a window of global ids may hold on rank 0 (entries and their ids).
std::size_t window_budget() {
  const char* env = std::getenv("HORIZON_CHECKPOINT_CHUNK");
  if (env && *env) {
    const long long v = std::atoll(env);
    if (v > 0) return static_cast<std::size_t>(v);
  }
  return std::size_t{16} << 20;
}

uint64_t max_over_ranks(uint64_t x) {
  uint64_t all = 0;
  MPI_Allreduce(&x, &all, 1, MPI_UINT64_T, MPI_MAX, MPI_COMM_WORLD);
  return all;
}

// The kind of record r on every rank: the same everywhere, except a record that some
// ranks list by particle and others as a global record with no entries (a load with no
// particle on that rank: loading/loads.hpp), which is listed (as gather_checkpoint).
Extent agreed_extent(const CheckpointWriter::Spread& r) {
  int kind[2] = {static_cast<int>(r.extent), -static_cast<int>(r.extent)}, all[2] = {0, 0};
  MPI_Allreduce(kind, all, 2, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  const int most = all[0], least = -all[1];
  if (most == least) return r.extent;
  if (most == static_cast<int>(Extent::listed) && least == static_cast<int>(Extent::global) &&
      (r.extent == Extent::listed || r.count == 0))
    return Extent::listed;
  throw Error("checkpoint: record '" + r.name + "' is of different kinds on different ranks");
}

void same_records(const CheckpointWriter& w) {
  uint64_t records[2] = {w.spread().size(), ~static_cast<uint64_t>(w.spread().size())}, extreme[2] = {0, 0};
  MPI_Allreduce(records, extreme, 2, MPI_UINT64_T, MPI_MAX, MPI_COMM_WORLD);
  if (extreme[0] != ~extreme[1]) throw Error("internal error: the ranks list different checkpoint records");
}

// The particles of record r's list on this rank (local indices, ascending), or none.
const std::vector<uint32_t>* listed_particles(const CheckpointWriter::Spread& r) {
  if (r.extent != Extent::listed) return nullptr;
  if (!r.list) throw Error("checkpoint: record '" + r.name + "' has no particle list");
  if (!std::is_sorted(r.list->begin(), r.list->end()))
    throw Error("internal error: the particle list of checkpoint record '" + r.name + "' is not in ascending order");
  return r.list;
}

// Walks the global ids 0..N-1 in windows of `window` ids; per window, `fill(lo, hi, buf)`
// sets this rank's entries of its owned particles (buf[id - lo]), the buffers of all
// ranks are summed, and `use(lo, hi, sum)` reads the whole system's. Collective.
template <class T, class Fill, class Use>
void over_windows(uint64_t n, std::size_t window, MPI_Datatype type, Fill fill, Use use) {
  std::vector<T> mine, sum;
  for (uint64_t lo = 0; lo < n; lo += window) {
    const uint64_t hi = std::min<uint64_t>(n, lo + window);
    mine.assign(static_cast<std::size_t>(hi - lo), T{0});
    sum.assign(mine.size(), T{0});
    fill(lo, hi, mine);
    MPI_Allreduce(mine.data(), sum.data(), static_cast<int>(mine.size()), type, MPI_SUM, MPI_COMM_WORLD);
    use(lo, hi, sum);
  }
}

// Global ids per window of the restart's sums (a row length of 4 bytes each, summed into
// a second buffer).
std::size_t id_window() { return std::max<std::size_t>(1, window_budget() / 8); }

// Where each held row lies in the serial order: (first bond, bonds) per local particle
// with a row held, in local order (ascending global id).
std::vector<std::pair<uint64_t, uint64_t>> held_rows(const System& s, const Decomposition& d) {
  const auto& P = s.particles;
  const auto& B = s.bonds;
  const std::size_t n = P.size();
  std::vector<std::pair<uint64_t, uint64_t>> rows;
  std::size_t owned_at = 0, held_at = 0;  // cursors into d.owned and the local particles
  uint64_t offset = 0;
  over_windows<uint32_t>(
      d.global_particles, id_window(), MPI_UINT32_T,
      [&](uint64_t lo, uint64_t hi, std::vector<uint32_t>& len) {
        for (; owned_at < d.owned.size() && static_cast<uint64_t>(P.id[d.owned[owned_at]]) < hi; ++owned_at) {
          const uint32_t i = d.owned[owned_at];
          len[static_cast<std::size_t>(static_cast<uint64_t>(P.id[i]) - lo)] = static_cast<uint32_t>(B.end(i) - B.begin(i));
        }
      },
      [&](uint64_t lo, uint64_t hi, const std::vector<uint32_t>& len) {
        uint64_t at = offset;  // the row of global id lo
        uint64_t g = lo;
        for (; held_at < n && static_cast<uint64_t>(P.id[held_at]) < hi; ++held_at) {
          const uint64_t id = static_cast<uint64_t>(P.id[held_at]);
          for (; g < id; ++g) at += len[static_cast<std::size_t>(g - lo)];
          const uint64_t held = B.end(held_at) - B.begin(held_at);
          if (held == 0) continue;
          if (held != len[static_cast<std::size_t>(id - lo)])
            throw Error("internal error: bond row " + std::to_string(id) + " holds " + std::to_string(held) +
                        " bonds here and " + std::to_string(len[static_cast<std::size_t>(id - lo)]) +
                        " in the whole system");
          rows.emplace_back(at, held);
        }
        for (; g < hi; ++g) at += len[static_cast<std::size_t>(g - lo)];
        offset = at;
      });
  if (offset != d.global_bonds)
    throw Error("internal error: the rows hold " + std::to_string(offset) + " bonds, the whole system " +
                std::to_string(d.global_bonds));
  return rows;
}

// The place of each particle of `list` (local indices, ascending; may be null: none) in
// the whole system's list (the owned members of every rank, by global id), and the whole
// list's length. Collective.
std::pair<std::vector<uint64_t>, uint64_t> list_places(const System& s, const Decomposition& d,
                                                       const std::vector<uint32_t>* list) {
  const auto& id = s.particles.id;
  static const std::vector<uint32_t> none;
  const std::vector<uint32_t>& L = list ? *list : none;
  std::vector<uint64_t> places;
  places.reserve(L.size());
  std::size_t fill_at = 0, use_at = 0;
  uint64_t count = 0;
  over_windows<uint8_t>(
      d.global_particles, id_window(), MPI_UINT8_T,
      [&](uint64_t lo, uint64_t hi, std::vector<uint8_t>& member) {
        for (; fill_at < L.size() && static_cast<uint64_t>(id[L[fill_at]]) < hi; ++fill_at)
          if (d.owns(L[fill_at])) member[static_cast<std::size_t>(static_cast<uint64_t>(id[L[fill_at]]) - lo)] = 1;
      },
      [&](uint64_t lo, uint64_t hi, const std::vector<uint8_t>& member) {
        uint64_t g = lo;
        for (; use_at < L.size() && static_cast<uint64_t>(id[L[use_at]]) < hi; ++use_at) {
          const uint64_t mine = static_cast<uint64_t>(id[L[use_at]]);
          for (; g < mine; ++g) count += member[static_cast<std::size_t>(g - lo)];
          if (member[static_cast<std::size_t>(mine - lo)] != 1)
            throw Error("internal error: particle " + std::to_string(mine) +
                        " is on a list here and not on its owner's (or on several owners')");
          places.push_back(count);
        }
        for (; g < hi; ++g) count += member[static_cast<std::size_t>(g - lo)];
      });
  return {std::move(places), count};
}

// Consecutive units as ranges.
void add_unit(std::vector<std::pair<uint64_t, uint64_t>>& ranges, uint64_t first, uint64_t n) {
  if (n == 0) return;
  if (!ranges.empty() && ranges.back().first + ranges.back().second == first) ranges.back().second += n;
  else ranges.emplace_back(first, n);
}

}  // namespace

void pick_local_entries(const System& s, const Decomposition& d, const CheckpointWriter& mine, CheckpointReader& in) {
  if (!d.local_particles) throw Error("internal error: picking a checkpoint's entries without local particles");
  same_records(mine);
  const auto& id = s.particles.id;
  std::vector<CheckpointReader::Pick> picks(mine.spread().size());
  bool have_rows = false;
  std::vector<std::pair<uint64_t, uint64_t>> rows;
  for (std::size_t index = 0; index < mine.spread().size(); ++index) {
    const CheckpointWriter::Spread& r = mine.spread()[index];
    const Extent extent = agreed_extent(r);
    CheckpointReader::Pick& p = picks[index];
    if (extent == Extent::particles) {
      p.units = d.global_particles;
      for (std::size_t i = 0; i < id.size(); ++i) add_unit(p.ranges, static_cast<uint64_t>(id[i]), 1);
    } else if (extent == Extent::bonds) {
      if (!have_rows) rows = held_rows(s, d), have_rows = true;
      p.units = d.global_bonds;
      for (const auto& [first, n] : rows) add_unit(p.ranges, first, n);
    } else if (extent == Extent::listed) {
      const auto [places, whole] = list_places(s, d, listed_particles(r));
      p.units = whole;
      for (uint64_t l : places) add_unit(p.ranges, l, 1);
    }
    // A record of no units (an empty list) is read whole: it must be empty then.
  }
  in.pick(std::move(picks));
}

namespace {

// One record of the checkpoint (`r`, its bytes `data` on this rank) onto rank 0's stream.
void stream_record(const System& s, const Decomposition& d, const CheckpointWriter::Spread& r, const char* data,
                   CheckpointStream* out) {
  const auto& P = s.particles;
  const auto& B = s.bonds;
  const bool lead = d.rank == 0;
  const Extent extent = agreed_extent(r);
  if (extent == Extent::global) {  // rank 0's values
    if (lead) out->record(r.name, r.element_size, r.count), out->data(data, r.count * r.element_size);
    return;
  }
  const std::vector<uint32_t>* list = r.extent == Extent::listed ? listed_particles(r) : nullptr;
  const std::size_t units = extent == Extent::bonds ? B.size() : extent == Extent::particles ? P.size() : list ? list->size() : 0;
  if (units > 0 && r.count % units != 0)
    throw Error("checkpoint: record '" + r.name + "' holds " + std::to_string(r.count) + " entries for " +
                std::to_string(units) + " particles or bonds");
  const uint64_t mine_per = units > 0 ? r.element_size * (r.count / units) : 0;  // bytes per particle or bond
  // Every rank with entries has the same number per particle (bond).
  const uint64_t per = max_over_ranks(mine_per);
  const uint64_t least = ~max_over_ranks(units > 0 ? ~mine_per : 0);
  if (per != least && !(least == ~uint64_t{0} && per == 0))
    throw Error("internal error: checkpoint record '" + r.name + "' has " + std::to_string(least) + " and " +
                std::to_string(per) + " bytes per particle or bond on different ranks");
  // The owned entries in ascending global id: (global id, bytes, byte count).
  struct Entry {
    int64_t id;
    const char* bytes;
    uint64_t n;
  };
  std::vector<Entry> entries;
  uint64_t longest = per;  // bytes of the largest entry (a bond row: per * its length)
  if (per > 0 && units > 0) {
    if (extent == Extent::listed) {
      for (std::size_t l = 0; l < list->size(); ++l)
        if (d.owns((*list)[l])) entries.push_back({P.id[(*list)[l]], data + l * per, per});
    } else if (extent == Extent::bonds) {
      for (uint32_t i : d.owned)
        if (B.end(i) > B.begin(i)) entries.push_back({P.id[i], data + B.begin(i) * per, (B.end(i) - B.begin(i)) * per});
    } else {
      for (uint32_t i : d.owned) entries.push_back({P.id[i], data + i * per, per});
    }
  }
  for (const Entry& e : entries) longest = std::max(longest, e.n);
  const uint64_t global_units = extent == Extent::particles ? d.global_particles
                                : extent == Extent::bonds   ? d.global_bonds
                                                            : sum_over_ranks(extent == Extent::listed ? entries.size() : 0);
  const uint64_t count = per > 0 ? global_units * (per / r.element_size) : 0;
  if (lead) out->record(r.name, r.element_size, count);
  if (count == 0) return;
  longest = max_over_ranks(longest);
  // Windows of global ids whose entries, with their ids and sizes, fit the budget.
  const uint64_t window = std::max<uint64_t>(1, window_budget() / (longest + 2 * sizeof(uint64_t)));
  std::size_t at = 0;
  uint64_t written = 0;
  std::vector<uint64_t> meta;  // id, byte count per entry
  std::string bytes, all_bytes;
  std::vector<uint64_t> all_meta;
  std::vector<int> counts(2 * static_cast<std::size_t>(d.size)), meta_counts(static_cast<std::size_t>(d.size)),
      meta_displs(static_cast<std::size_t>(d.size)), byte_counts(static_cast<std::size_t>(d.size)),
      byte_displs(static_cast<std::size_t>(d.size));
  for (uint64_t lo = 0; lo < d.global_particles; lo += window) {
    const uint64_t hi = std::min<uint64_t>(d.global_particles, lo + window);
    meta.clear(), bytes.clear();
    for (; at < entries.size() && static_cast<uint64_t>(entries[at].id) < hi; ++at) {
      meta.push_back(static_cast<uint64_t>(entries[at].id));
      meta.push_back(entries[at].n);
      bytes.append(entries[at].bytes, entries[at].n);
    }
    if (bytes.size() > static_cast<std::size_t>(INT_MAX) || meta.size() > static_cast<std::size_t>(INT_MAX))
      throw Error("checkpoint: record '" + r.name + "' has a window too large to gather");
    const int mine_counts[2] = {static_cast<int>(meta.size()), static_cast<int>(bytes.size())};
    MPI_Gather(mine_counts, 2, MPI_INT, counts.data(), 2, MPI_INT, 0, MPI_COMM_WORLD);
    if (lead) {
      std::size_t m = 0, b = 0;
      for (int q = 0; q < d.size; ++q) {
        const std::size_t k = static_cast<std::size_t>(q);
        meta_counts[k] = counts[2 * k], byte_counts[k] = counts[2 * k + 1];
        meta_displs[k] = static_cast<int>(m), byte_displs[k] = static_cast<int>(b);
        m += static_cast<std::size_t>(meta_counts[k]), b += static_cast<std::size_t>(byte_counts[k]);
        if (m > static_cast<std::size_t>(INT_MAX) || b > static_cast<std::size_t>(INT_MAX))
          throw Error("checkpoint: record '" + r.name + "' has a window too large to gather");
      }
      all_meta.resize(m), all_bytes.resize(b);
    }
    MPI_Gatherv(meta.data(), mine_counts[0], MPI_UINT64_T, all_meta.data(), meta_counts.data(), meta_displs.data(),
                MPI_UINT64_T, 0, MPI_COMM_WORLD);
    MPI_Gatherv(bytes.data(), mine_counts[1], MPI_BYTE, all_bytes.data(), byte_counts.data(), byte_displs.data(),
                MPI_BYTE, 0, MPI_COMM_WORLD);
    if (!lead) continue;
    // Each rank's entries come in ascending id: merged by id (the serial order; a bond
    // row's bonds keep their serial order in the local numbering).
    struct Got {
      uint64_t id, at, n;
    };
    std::vector<Got> got;
    got.reserve(all_meta.size() / 2);
    for (int q = 0; q < d.size; ++q) {
      const std::size_t k = static_cast<std::size_t>(q);
      uint64_t b = static_cast<uint64_t>(byte_displs[k]);
      for (std::size_t e = static_cast<std::size_t>(meta_displs[k]);
           e < static_cast<std::size_t>(meta_displs[k] + meta_counts[k]); e += 2) {
        got.push_back({all_meta[e], b, all_meta[e + 1]});
        b += all_meta[e + 1];
      }
    }
    std::sort(got.begin(), got.end(), [](const Got& a, const Got& b) { return a.id < b.id; });
    for (const Got& g : got) out->data(all_bytes.data() + g.at, static_cast<std::size_t>(g.n));
    for (const Got& g : got) written += g.n;
  }
  if (lead && written != count * r.element_size)
    throw Error("internal error: checkpoint record '" + r.name + "' gathered " + std::to_string(written) +
                " bytes, the whole system has " + std::to_string(count * r.element_size));
}

}  // namespace

CheckpointSender::CheckpointSender(const System& s, const Decomposition& d, const CheckpointWriter& records,
                                   CheckpointStream* out)
    : StateArchive(false), s_(s), d_(d), out_(out) {
  if (!d.local_particles) throw Error("internal error: streaming a checkpoint without local particles");
  if (d.rank == 0 && !out) throw Error("internal error: rank 0 streams a checkpoint to nowhere");
  same_records(records);
}

void CheckpointSender::put(const std::string& name, const void* bytes, std::size_t element_size, std::size_t count,
                           Extent extent) {
  CheckpointWriter::Spread r;
  r.name = full_name(name);
  r.extent = extent;
  r.element_size = element_size;
  r.count = count;
  r.list = list();
  stream_record(s_, d_, r, static_cast<const char*>(bytes), d_.rank == 0 ? out_ : nullptr);
}

void CheckpointSender::end() {
  if (d_.rank == 0) out_->end();
}

#else

void pick_local_entries(const System&, const Decomposition&, const CheckpointWriter&, CheckpointReader&) {
  throw Error("internal error: local particles without MPI");
}
CheckpointSender::CheckpointSender(const System& s, const Decomposition& d, const CheckpointWriter&, CheckpointStream* out)
    : StateArchive(false), s_(s), d_(d), out_(out) {
  throw Error("internal error: local particles without MPI");
}
void CheckpointSender::put(const std::string&, const void*, std::size_t, std::size_t, Extent) {}
void CheckpointSender::end() {}

#endif

}  // namespace horizon
