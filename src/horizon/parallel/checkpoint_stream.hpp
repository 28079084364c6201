#pragma once
// Checkpoints of a run with local particles (parallel/decomposition.hpp) without the whole
// file on any rank (docs/design.md, "Running on several ranks"):
//  - writing: rank 0 puts the records on disk one after the other as a serial run lists
//    them, each as soon as the run lists it (CheckpointSender: no copy of the state), each
//    per-particle, per-bond and listed record taken from the owners in windows
//    of global ids (Particles::id) whose entries fit a bounded buffer (16 MiB;
//    HORIZON_CHECKPOINT_CHUNK=BYTES sets it, for the tests), merged by global id as they
//    come; the checksum is computed on the way (output/checkpoint.hpp CheckpointStream).
//    The bytes are those of gather_checkpoint + CheckpointWriter::write.
//  - reading (a restart): each rank reads of every per-particle record the entries of the
//    particles it holds (by global id), of every per-bond record those of the rows it
//    holds (where a row lies in the serial order: the row lengths summed over windows of
//    global ids, a bounded buffer), of every listed record those of its list's particles
//    (their place in the whole list: its members counted over windows of global ids),
//    and the global records whole (CheckpointReader::pick).
// Every rank takes part in both (collective); the records are the same on every rank
// (their names and order; their sizes differ).
#include <cstdint>
#include <string>

#include "horizon/core/state_archive.hpp"

namespace horizon {

struct System;
struct Decomposition;
class CheckpointWriter;
class CheckpointReader;
class CheckpointStream;

// Before a restart with local particles reads `in`: for each record of `mine` (this
// rank's state listed by a CheckpointWriter, the records the load will read in the same
// order) the entries this rank keeps. Collective.
void pick_local_entries(const System& s, const Decomposition& d, const CheckpointWriter& mine, CheckpointReader& in);
// Writes a checkpoint with local particles: the run lists its state into this archive
// (checkpoint(StateArchive&)) on every rank at once, and each record goes to rank 0's
// `out` as it is listed (the temporaries a part lists stay valid while it is sent), its
// per-particle, per-bond and listed entries from their owners; then end() on every rank.
// `records`, the same state listed by a CheckpointWriter (Keep::list), checks first that
// every rank lists as many records. Rank 0's `out` may be a stream that only counts (its
// file could not be opened: it still takes part); the other ranks' is ignored. Collective.
class CheckpointSender : public StateArchive {
 public:
  CheckpointSender(const System& s, const Decomposition& d, const CheckpointWriter& records, CheckpointStream* out);
  void end();

 protected:
  void put(const std::string& name, const void* bytes, std::size_t element_size, std::size_t count,
           Extent extent) override;
  Record get(const std::string&, std::size_t) override { return {}; }
  void expect_count(const std::string&, uint64_t, uint64_t) override {}
  void mismatch(const std::string&) override {}

 private:
  const System& s_;
  const Decomposition& d_;
  CheckpointStream* out_;
};
// The broken bonds of the whole system as the serial program counts them: each counted in
// its owner's rows, plus the failures a model keeps outside the rows (Model::failures_kept),
// less the precracks' broken bonds (Decomposition::broken_at_start). gather_state sets
// System::broken from it. Collective.
uint64_t global_broken_bonds(const System& s, const Decomposition& d);

}  // namespace horizon
