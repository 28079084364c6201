#include "horizon/output/checkpoint.hpp"

#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "horizon/core/error.hpp"
#include "horizon/output/atomic_file.hpp"

namespace horizon {

namespace {

constexpr char kMagic[8] = {'H', 'Z', 'N', 'C', 'H', 'K', 'P', 'T'};
constexpr uint32_t kByteOrder = 0x01020304u;
constexpr std::size_t kHeader = 32;

// zlib's crc32 takes at most UINT_MAX bytes at a time.
uint32_t crc_of(const std::string& s) {
  uLong crc = crc32(0L, Z_NULL, 0);
  std::size_t done = 0;
  while (done < s.size()) {
    const std::size_t n = std::min<std::size_t>(s.size() - done, 1u << 30);
    crc = crc32(crc, reinterpret_cast<const Bytef*>(s.data() + done), static_cast<uInt>(n));
    done += n;
  }
  return static_cast<uint32_t>(crc);
}

template <class T>
void append(std::string& s, const T& x) {
  s.append(reinterpret_cast<const char*>(&x), sizeof(T));
}

template <class T>
T read_at(const std::string& s, std::size_t at) {
  T x;
  std::memcpy(&x, s.data() + at, sizeof(T));
  return x;
}

}  // namespace

void CheckpointWriter::put(const std::string& name, const void* bytes, std::size_t element_size, std::size_t count,
                           Extent extent) {
  const std::string full = full_name(name);
  append(payload_, static_cast<uint32_t>(full.size()));
  payload_ += full;
  append(payload_, static_cast<uint32_t>(element_size));
  append(payload_, static_cast<uint64_t>(count));
  // Every record, global and empty ones too: with local particles (parallel/
  // decomposition.hpp) an array may be empty on one rank and not on another, and the
  // gather walks the same list on every rank.
  spread_.push_back({full, extent, element_size, count, payload_.size(), list()});
  if (extent == Extent::bonds) bond_records_.push_back(full);
  if (count) payload_.append(static_cast<const char*>(bytes), element_size * count);
}

void CheckpointWriter::replace(std::size_t index, const std::string& data) {
  Spread& r = spread_.at(index);
  if (data.size() % r.element_size != 0)
    throw Error("checkpoint: record '" + r.name + "' replaced by a partial element");
  const std::size_t old_bytes = r.count * r.element_size;
  payload_.replace(r.offset, old_bytes, data);
  const uint64_t count = data.size() / r.element_size;
  std::memcpy(payload_.data() + r.offset - sizeof(uint64_t), &count, sizeof(count));  // the record's count field
  r.count = count;
  for (std::size_t q = index + 1; q < spread_.size(); ++q) spread_[q].offset = spread_[q].offset + data.size() - old_bytes;
}

void CheckpointWriter::write(const std::string& path) const {
  std::string head(kMagic, sizeof(kMagic));
  append(head, kCheckpointVersion);
  append(head, kByteOrder);
  append(head, static_cast<uint64_t>(payload_.size()));
  append(head, crc_of(payload_));
  append(head, uint32_t{0});
  write_file_atomic(path, [&](std::ostream& out) {
    out.write(head.data(), static_cast<std::streamsize>(head.size()));
    out.write(payload_.data(), static_cast<std::streamsize>(payload_.size()));
  });
}

CheckpointReader::CheckpointReader(const std::string& path) : StateArchive(true), path_(path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("checkpoint '" + path + "': cannot open it: " + std::strerror(errno));
  std::ostringstream all;
  all << in.rdbuf();
  const std::string file = all.str();
  if (file.size() < kHeader) {
    if (file.size() >= sizeof(kMagic) && std::memcmp(file.data(), kMagic, sizeof(kMagic)) != 0)
      fail("not a Horizon checkpoint (it does not start with \"HZNCHKPT\")");
    fail("truncated: " + std::to_string(file.size()) + " bytes, shorter than the 32-byte header");
  }
  if (std::memcmp(file.data(), kMagic, sizeof(kMagic)) != 0)
    fail("not a Horizon checkpoint (it does not start with \"HZNCHKPT\")");
  const auto version = read_at<uint32_t>(file, 8);
  if (version != kCheckpointVersion)
    fail("format version " + std::to_string(version) + "; this Horizon reads version " +
         std::to_string(kCheckpointVersion));
  if (read_at<uint32_t>(file, 12) != kByteOrder)
    fail("written on a machine of the other byte order, or a corrupt header");
  const auto size = read_at<uint64_t>(file, 16);
  if (file.size() - kHeader < size)
    fail("truncated: the header announces " + std::to_string(size) + " bytes of state, the file holds " +
         std::to_string(file.size() - kHeader));
  if (file.size() - kHeader > size)
    fail(std::to_string(file.size() - kHeader - size) + " bytes after the announced end of the state");
  data_ = file.substr(kHeader);
  const uint32_t stored = read_at<uint32_t>(file, 24), computed = crc_of(data_);
  if (stored != computed) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "checksum mismatch (CRC-32 stored %08x, computed %08x): the file is corrupt",
                  stored, computed);
    fail(buf);
  }
}

void CheckpointReader::fail(const std::string& what) const { throw Error("checkpoint '" + path_ + "': " + what); }

StateArchive::Record CheckpointReader::get(const std::string& name, std::size_t element_size) {
  const std::string full = full_name(name);
  auto need = [&](std::size_t n) {
    if (data_.size() - pos_ < n) fail("the state ends inside record '" + full + "'");
  };
  if (pos_ == data_.size()) fail("the state ends before record '" + full + "' (written by another Horizon?)");
  need(4);
  const auto len = read_at<uint32_t>(data_, pos_);
  need(4 + static_cast<std::size_t>(len) + 12);
  const std::string found = data_.substr(pos_ + 4, len);
  if (found != full)
    fail("record '" + found + "' where '" + full +
         "' was expected: the checkpoint was written for another deck or by another Horizon");
  const auto esize = read_at<uint32_t>(data_, pos_ + 4 + len);
  const auto count = read_at<uint64_t>(data_, pos_ + 8 + len);
  if (esize != element_size)
    fail("record '" + full + "' has elements of " + std::to_string(esize) + " bytes, expected " +
         std::to_string(element_size));
  pos_ += 16 + len;
  if (count > (data_.size() - pos_) / std::max<std::size_t>(1, esize)) fail("the state ends inside record '" + full + "'");
  Record r{data_.data() + pos_, count};
  pos_ += static_cast<std::size_t>(count) * esize;
  if (count && !bond_records_.empty() &&
      std::find(bond_records_.begin(), bond_records_.end(), full) != bond_records_.end()) {
    // The whole system's bonds in serial order: keep this rank's rows.
    if (global_bonds_ == 0 || count % global_bonds_ != 0)
      fail("record '" + full + "' holds " + std::to_string(count) + " values, not a multiple of the " +
           std::to_string(global_bonds_) + " bonds: the checkpoint does not belong to this deck");
    const std::size_t per = static_cast<std::size_t>(count / global_bonds_) * esize;  // bytes per bond
    kept_.clear();
    for (const auto& [first, n] : bond_rows_) {
      if (first + n > global_bonds_) fail("record '" + full + "': a bond row reaches past its end");
      kept_.append(static_cast<const char*>(r.bytes) + first * per, n * per);
    }
    r = Record{kept_.data(), kept_.size() / esize};
  }
  return r;
}

void CheckpointReader::keep_bond_rows(std::vector<std::string> records, std::vector<std::pair<uint64_t, uint64_t>> rows,
                                      uint64_t global_bonds) {
  bond_records_ = std::move(records);
  bond_rows_ = std::move(rows);
  global_bonds_ = global_bonds;
}

void CheckpointReader::expect_count(const std::string& name, uint64_t found, uint64_t expected) {
  if (found != expected)
    fail("record '" + full_name(name) + "' holds " + std::to_string(found) + " values where the deck has " +
         std::to_string(expected) + ": the checkpoint does not belong to this deck");
}

void CheckpointReader::finish() const {
  if (pos_ != data_.size())
    fail(std::to_string(data_.size() - pos_) + " bytes of state left unread (written for another deck?)");
}

}  // namespace horizon
