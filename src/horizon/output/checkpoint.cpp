#include "horizon/output/checkpoint.hpp"

#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>

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
  if (count && keep_ == Keep::copy) payload_.append(static_cast<const char*>(bytes), element_size * count);
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
  in_.open(path, std::ios::binary);
  if (!in_) throw Error("checkpoint '" + path + "': cannot open it: " + std::strerror(errno));
  in_.seekg(0, std::ios::end);
  const auto end = in_.tellg();
  if (end < 0) fail("cannot read it: " + std::string(std::strerror(errno)));
  const uint64_t file_size = static_cast<uint64_t>(end);
  in_.seekg(0);
  std::string head(static_cast<std::size_t>(std::min<uint64_t>(file_size, kHeader)), '\0');
  in_.read(head.data(), static_cast<std::streamsize>(head.size()));
  if (!in_) fail("cannot read its header");
  if (file_size < kHeader) {
    if (file_size >= sizeof(kMagic) && std::memcmp(head.data(), kMagic, sizeof(kMagic)) != 0)
      fail("not a Horizon checkpoint (it does not start with \"HZNCHKPT\")");
    fail("truncated: " + std::to_string(file_size) + " bytes, shorter than the 32-byte header");
  }
  if (std::memcmp(head.data(), kMagic, sizeof(kMagic)) != 0)
    fail("not a Horizon checkpoint (it does not start with \"HZNCHKPT\")");
  const auto version = read_at<uint32_t>(head, 8);
  if (version != kCheckpointVersion)
    fail("format version " + std::to_string(version) + "; this Horizon reads version " +
         std::to_string(kCheckpointVersion));
  if (read_at<uint32_t>(head, 12) != kByteOrder)
    fail("written on a machine of the other byte order, or a corrupt header");
  size_ = read_at<uint64_t>(head, 16);
  if (file_size - kHeader < size_)
    fail("truncated: the header announces " + std::to_string(size_) + " bytes of state, the file holds " +
         std::to_string(file_size - kHeader));
  if (file_size - kHeader > size_)
    fail(std::to_string(file_size - kHeader - size_) + " bytes after the announced end of the state");
  // The checksum, read through a bounded buffer (the records are read again as they are
  // asked for: a file of any size costs this reader one record at a time).
  std::string chunk(std::min<uint64_t>(size_, uint64_t{1} << 22), '\0');
  uLong crc = crc32(0L, Z_NULL, 0);
  for (uint64_t done = 0; done < size_;) {
    const std::size_t n = static_cast<std::size_t>(std::min<uint64_t>(size_ - done, chunk.size()));
    in_.read(chunk.data(), static_cast<std::streamsize>(n));
    if (!in_) fail("cannot read it: the file ended or changed while it was read");
    crc = crc32(crc, reinterpret_cast<const Bytef*>(chunk.data()), static_cast<uInt>(n));
    done += n;
  }
  const uint32_t stored = read_at<uint32_t>(head, 24), computed = static_cast<uint32_t>(crc);
  if (stored != computed) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "checksum mismatch (CRC-32 stored %08x, computed %08x): the file is corrupt",
                  stored, computed);
    fail(buf);
  }
  in_.seekg(static_cast<std::streamoff>(kHeader));
}

void CheckpointReader::fail(const std::string& what) const { throw Error("checkpoint '" + path_ + "': " + what); }

void CheckpointReader::read(char* to, std::size_t n) {
  if (n == 0) return;
  in_.read(to, static_cast<std::streamsize>(n));
  if (!in_) fail("cannot read it: the file ended or changed while it was read");
  pos_ += n;
}

void CheckpointReader::skip(uint64_t n) {
  if (n == 0) return;
  in_.seekg(static_cast<std::streamoff>(n), std::ios::cur);
  if (!in_) fail("cannot read it: the file ended or changed while it was read");
  pos_ += n;
}

StateArchive::Record CheckpointReader::get(const std::string& name, std::size_t element_size) {
  const std::string full = full_name(name);
  const std::size_t index = index_++;
  auto need = [&](uint64_t n) {
    if (size_ - pos_ < n) fail("the state ends inside record '" + full + "'");
  };
  if (pos_ == size_) fail("the state ends before record '" + full + "' (written by another Horizon?)");
  need(4);
  uint32_t len = 0;
  read(reinterpret_cast<char*>(&len), sizeof len);
  need(static_cast<uint64_t>(len) + 12);
  std::string found(len, '\0');
  read(found.data(), len);
  if (found != full)
    fail("record '" + found + "' where '" + full +
         "' was expected: the checkpoint was written for another deck or by another Horizon");
  uint32_t esize = 0;
  uint64_t count = 0;
  read(reinterpret_cast<char*>(&esize), sizeof esize);
  read(reinterpret_cast<char*>(&count), sizeof count);
  if (esize != element_size)
    fail("record '" + full + "' has elements of " + std::to_string(esize) + " bytes, expected " +
         std::to_string(element_size));
  if (count > (size_ - pos_) / std::max<uint64_t>(1, esize)) fail("the state ends inside record '" + full + "'");
  const uint64_t bytes = count * esize;
  // Which entries to keep: a pick by position (local particles), the bond rows by name
  // (local rows), or all.
  const Pick* pick = index < picks_.size() && picks_[index].units > 0 ? &picks_[index] : nullptr;
  Pick rows;
  if (!pick && count && !bond_records_.empty() &&
      std::find(bond_records_.begin(), bond_records_.end(), full) != bond_records_.end()) {
    // The whole system's bonds in serial order: keep this rank's rows.
    if (global_bonds_ == 0) fail("record '" + full + "' holds bonds, the deck none: the checkpoint does not belong to this deck");
    rows.units = global_bonds_;
    rows.ranges = bond_rows_;
    pick = &rows;
  }
  record_.clear();
  if (!pick || count == 0) {
    record_.resize(static_cast<std::size_t>(bytes));
    read(record_.data(), record_.size());
    return Record{record_.data(), count};
  }
  if (count % pick->units != 0)
    fail("record '" + full + "' holds " + std::to_string(count) + " values, not a multiple of the " +
         std::to_string(pick->units) + " particles or bonds it is for: the checkpoint does not belong to this deck");
  const uint64_t per = count / pick->units * esize;  // bytes per particle or bond
  const uint64_t start = pos_;
  uint64_t at = 0;  // units passed
  std::size_t kept = 0;
  for (const auto& [first, n] : pick->ranges) kept += static_cast<std::size_t>(n * per);
  record_.resize(kept);
  kept = 0;
  for (const auto& [first, n] : pick->ranges) {
    if (first < at || first + n > pick->units) fail("record '" + full + "': a picked range lies outside it");
    skip((first - at) * per);
    read(record_.data() + kept, static_cast<std::size_t>(n * per));
    kept += static_cast<std::size_t>(n * per);
    at = first + n;
  }
  skip(start + bytes - pos_);
  return Record{record_.data(), kept / esize};
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
  if (pos_ != size_) fail(std::to_string(size_ - pos_) + " bytes of state left unread (written for another deck?)");
}

CheckpointStream::CheckpointStream(std::ostream* out) : out_(out), crc_(static_cast<uint32_t>(crc32(0L, Z_NULL, 0))) {
  if (!out_) return;
  std::string head(kMagic, sizeof(kMagic));
  append(head, kCheckpointVersion);
  append(head, kByteOrder);
  append(head, uint64_t{0});  // size and checksum: end()
  append(head, uint32_t{0});
  append(head, uint32_t{0});
  out_->write(head.data(), static_cast<std::streamsize>(head.size()));
}

void CheckpointStream::record(const std::string& name, std::size_t element_size, uint64_t count) {
  std::string head;
  append(head, static_cast<uint32_t>(name.size()));
  head += name;
  append(head, static_cast<uint32_t>(element_size));
  append(head, count);
  data(head.data(), head.size());
}

void CheckpointStream::data(const char* bytes, std::size_t n) {
  size_ += n;
  if (!out_) return;  // nothing is written: no checksum either
  for (std::size_t done = 0; done < n;) {
    const std::size_t k = std::min<std::size_t>(n - done, 1u << 30);
    crc_ = static_cast<uint32_t>(crc32(crc_, reinterpret_cast<const Bytef*>(bytes + done), static_cast<uInt>(k)));
    done += k;
  }
  if (n) out_->write(bytes, static_cast<std::streamsize>(n));
}

void CheckpointStream::end() {
  if (!out_) return;
  std::string tail;
  append(tail, size_);
  append(tail, crc_);
  out_->seekp(16);
  out_->write(tail.data(), static_cast<std::streamsize>(tail.size()));
  out_->seekp(0, std::ios::end);
}

}  // namespace horizon
