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
#include <string>
#include <utility>
#include <vector>

#include "horizon/core/state_archive.hpp"

namespace horizon {

inline constexpr uint32_t kCheckpointVersion = 1;

// Collects records in memory; write() puts header, payload and checksum on disk.
class CheckpointWriter : public StateArchive {
 public:
  CheckpointWriter() : StateArchive(false) {}
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
  std::string payload_;
  std::vector<Spread> spread_;
  std::vector<std::string> bond_records_;
};

// Reads and checks a whole file at construction (magic, version, byte order, size,
// checksum); then hands out its records in order. Every error is a horizon::Error that
// names the file and what is wrong with it.
class CheckpointReader : public StateArchive {
 public:
  explicit CheckpointReader(const std::string& path);
  // After the last io(): every record was read (a longer file is an error too).
  void finish() const;
  const std::string& path() const { return path_; }
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
  std::string path_;
  std::string data_;     // the payload
  std::size_t pos_ = 0;  // next record
  std::vector<std::string> bond_records_;                // keep_bond_rows
  std::vector<std::pair<uint64_t, uint64_t>> bond_rows_;
  uint64_t global_bonds_ = 0;
  std::string kept_;  // the last per-bond record's kept entries
};

}  // namespace horizon
