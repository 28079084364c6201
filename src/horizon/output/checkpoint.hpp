#pragma once
// Checkpoint files: the whole state of a run, so that `horizon run DECK --restart FILE`
// continues bit for bit (docs/input.md, output.checkpoint; the format is documented there
// and below).
//
// Layout (little-endian, as the machine that wrote it; the byte-order mark refuses others):
//   offset  0  8 bytes  magic "HZNCHKPT"
//           8  uint32   format version (kCheckpointVersion)
//          12  uint32   byte-order mark 0x01020304
//          16  uint64   payload size P [bytes]
//          24  uint32   CRC-32 of the payload (zlib's crc32, ISO-HDLC polynomial)
//          28  uint32   0 (reserved)
//          32  P bytes  payload: records, each
//                         uint32 name length L, L bytes of name,
//                         uint32 element size E, uint64 count C, C*E bytes of data.
// The records are whatever the parts of the run list in their checkpoint() functions
// (core/state_archive.hpp), in that order. The file is written under a temporary name and
// renamed (output/atomic_file.hpp), so a run killed while writing leaves the previous one.
#include <cstdint>
#include <fstream>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "horizon/core/state_archive.hpp"

namespace horizon {

inline constexpr uint32_t kCheckpointVersion = 1;

// Collects records in memory; write() puts header, payload and checksum on disk.
class CheckpointWriter : public StateArchive {
 public:
  // What put() keeps of the records: `copy` all their bytes (a file's payload); `list` no
  // bytes, only the records' names, kinds and sizes (what a restart picks by).
  enum class Keep { copy, list };
  explicit CheckpointWriter(Keep keep = Keep::copy) : StateArchive(false), keep_(keep) {}
  // Atomically (temporary file and rename). Throws horizon::OutputError.
  void write(const std::string& path) const;
  const std::string& payload() const { return payload_; }

  // Every record, empty and global ones too, with its Extent (core/state_archive.hpp) and where
  // its bytes lie in the payload: a run split over MPI ranks overwrites the per-particle, per-bond
  // and listed ones with every owner's entries (decomposition.hpp gather_checkpoint) before rank 0 writes.
  struct Spread {
    std::string name;
    Extent extent = Extent::global;
    std::size_t element_size = 0, count = 0, offset = 0;
    const std::vector<uint32_t>* list = nullptr;  // Extent::listed: the particle of each entry group
  };
  const std::vector<Spread>& spread() const { return spread_; }
  char* bytes(const Spread& r) { return payload_.data() + r.offset; }
  // Replaces the data of record spread()[index] by `data` (a whole number of its
  // elements; its count becomes data.size() / element_size), moving the records after it:
  // a run whose ranks hold only their own bond rows puts the global per-bond arrays in
  // place of rank 0's own (gather_checkpoint).
  void replace(std::size_t index, const std::string& data);
  // The names of every per-bond record (Extent::bonds), empty ones included.
  const std::vector<std::string>& bond_records() const { return bond_records_; }

 protected:
  void put(const std::string& name, const void* bytes, std::size_t element_size, std::size_t count,
           Extent extent) override;
  Record get(const std::string&, std::size_t) override { return {}; }
  void expect_count(const std::string&, uint64_t, uint64_t) override {}
  void mismatch(const std::string&) override {}

 private:
  Keep keep_;
  std::string payload_;
  std::vector<Spread> spread_;
  std::vector<std::string> bond_records_;
};

// Checks a file at construction (magic, version, byte order, size, and the checksum of
// the payload, read in chunks of a bounded buffer); then hands out its records in order,
// reading each from the file when it is asked for: what it holds at a time is one record,
// or of a record whose entries it picks (pick, keep_bond_rows) only the picked ones.
// Every error is a horizon::Error that names the file and what is wrong with it.
class CheckpointReader : public StateArchive {
 public:
  explicit CheckpointReader(const std::string& path);
  // After the last io(): every record was read (a longer file is an error too).
  void finish() const;
  const std::string& path() const { return path_; }
  // The entries of one record a rank keeps (parallel/checkpoint_stream.hpp): the record
  // holds `units` groups of entries of the whole system (its particles, its bonds or a
  // list's particles, in global order; each group count / units elements), and reading it
  // hands out only the groups [first, first + n) of each pair of `ranges` (ascending, not
  // overlapping), one after the other.
  struct Pick {
    uint64_t units = 0;
    std::vector<std::pair<uint64_t, uint64_t>> ranges;
  };
  // Picks for the records by their position in the order io() reads them (picks[k] for the
  // k-th record); a record whose pick has no units, or past the end, is read whole.
  void pick(std::vector<Pick> picks) { picks_ = std::move(picks); }
  // A run whose ranks hold only some bond rows (parallel/decomposition.hpp, local rows):
  // each per-bond record named in `records` holds the `global_bonds` bonds of the whole
  // system in serial order; reading it hands out only the bonds [first, first + count) of
  // each pair of `rows`, one after the other (this rank's rows, in its order).
  void keep_bond_rows(std::vector<std::string> records, std::vector<std::pair<uint64_t, uint64_t>> rows,
                      uint64_t global_bonds);
  // "checkpoint 'PATH': " + what.
  [[noreturn]] void fail(const std::string& what) const;

 protected:
  void put(const std::string&, const void*, std::size_t, std::size_t, Extent) override {}
  Record get(const std::string& name, std::size_t element_size) override;
  void expect_count(const std::string& name, uint64_t found, uint64_t expected) override;
  void mismatch(const std::string& what) override { fail(what); }

 private:
  void read(char* to, std::size_t n);  // the next n bytes of the payload
  void skip(uint64_t n);

  std::string path_;
  std::ifstream in_;
  uint64_t size_ = 0;  // of the payload
  uint64_t pos_ = 0;   // next record (bytes into the payload)
  std::size_t index_ = 0;  // of the next record
  std::vector<std::string> bond_records_;  // keep_bond_rows
  std::vector<std::pair<uint64_t, uint64_t>> bond_rows_;
  uint64_t global_bonds_ = 0;
  std::vector<Pick> picks_;
  std::string record_;  // the last record's bytes handed out
};

// Rank 0's end of a checkpoint written record by record (parallel/checkpoint_stream.hpp):
// the same bytes as CheckpointWriter::write, put on `out` as they come, the payload's size
// and checksum written into the header at the end (the stream must be seekable). Without
// a stream (nullptr) it only counts: a rank whose file could not be opened still takes
// part in the collective writing.
class CheckpointStream {
 public:
  explicit CheckpointStream(std::ostream* out);
  void record(const std::string& name, std::size_t element_size, uint64_t count);
  void data(const char* bytes, std::size_t n);
  // Puts the payload's size and checksum into the header.
  void end();
  uint64_t payload_size() const { return size_; }

 private:
  std::ostream* out_;
  uint64_t size_ = 0;
  uint32_t crc_ = 0;
};

}  // namespace horizon
