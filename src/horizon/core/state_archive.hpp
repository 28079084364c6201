#pragma once
// One function for both directions of a checkpoint (output/checkpoint.hpp): a part of the
// state lists its arrays and numbers once, in `checkpoint(StateArchive& a)`, as
//   a.io("name", array);
// When the archive saves, the value is appended as a named record; when it loads, the next
// record must carry that name, element size and (for fixed-size data) count, and its bytes
// replace the value. Saving and loading therefore walk the same list in the same order,
// and a mismatch is an error naming the record, not a silently shifted state.
//
// Only trivially copyable values go in (numbers, Vec3, plain structs of numbers): their
// bytes are the state, so a restart continues bit for bit.
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

namespace horizon {

// Values a checkpoint may hold as their bytes: the trivially copyable ones, and those a
// unit declares plain (a struct of numbers and Eigen fixed-size matrices, which copy as
// bytes but declare their own copy constructors): template <> struct plain_data<T> : std::true_type {};
template <class T>
struct plain_data : std::is_trivially_copyable<T> {};

// What the entries of an array belong to. A run split over MPI ranks (parallel/
// decomposition.hpp) keeps each particle's entries current on the rank that owns it, and
// each bond's on the rank that owns the bond's row (its first particle): before rank 0
// writes the checkpoint, gather_checkpoint takes every entry of a per-particle or
// per-bond array from its owner. `global` values are the same on every rank (or rank 0's
// are the ones to keep). A per-particle array holds k entries per particle (k = its size
// over the particle count; 0 when empty), and likewise per bond. A `listed` array holds k
// entries per particle of a list the model keeps (its material's particles, in order):
// entry l belongs to particle list[l].
enum class Extent : uint8_t { global, particles, bonds, listed };

class StateArchive {
 public:
  virtual ~StateArchive() = default;
  bool loading() const { return loading_; }

  template <class T>
  void io(const std::string& name, std::vector<T>& v, Extent extent = Extent::global) {
    static_assert(plain_data<T>::value, "a checkpoint holds plain data only");
    if (!loading_) {
      put(name, v.data(), sizeof(T), v.size(), extent);
      return;
    }
    const Record r = get(name, sizeof(T));
    v.resize(r.count);
    if (r.count) std::memcpy(static_cast<void*>(v.data()), r.bytes, r.count * sizeof(T));
  }
  // std::vector<bool> has no bytes of its own: not allowed.
  void io(const std::string& name, std::vector<bool>& v) = delete;

  template <class T>
  void io(const std::string& name, T& x) {
    static_assert(plain_data<T>::value, "a checkpoint holds plain data only");
    if (!loading_) {
      put(name, &x, sizeof(T), 1, Extent::global);
      return;
    }
    const Record r = get(name, sizeof(T));
    expect_count(name, r.count, 1);
    std::memcpy(static_cast<void*>(&x), r.bytes, sizeof(T));
  }

  void io(const std::string& name, std::string& s) {
    if (!loading_) {
      put(name, s.data(), 1, s.size(), Extent::global);
      return;
    }
    const Record r = get(name, 1);
    s.assign(static_cast<const char*>(r.bytes), r.count);
  }

  // A vector whose length the run fixes (per particle, per bond): loading checks it.
  template <class T>
  void io_sized(const std::string& name, std::vector<T>& v, std::size_t expected, Extent extent = Extent::global) {
    if (loading_) {
      std::vector<T> tmp;
      io(name, tmp);
      expect_count(name, tmp.size(), expected);
      v = std::move(tmp);
    } else {
      io(name, v, extent);
    }
  }
  // Per-particle and per-bond arrays (Extent above).
  template <class T>
  void io_particles(const std::string& name, std::vector<T>& v) {
    io(name, v, Extent::particles);
  }
  template <class T>
  void io_bonds(const std::string& name, std::vector<T>& v) {
    io(name, v, Extent::bonds);
  }
  // An array indexed by the position in `list` (particle indices): entry l belongs to
  // particle list[l] (Extent::listed). `list` must outlive the archive.
  template <class T>
  void io_listed(const std::string& name, std::vector<T>& v, const std::vector<uint32_t>& list) {
    list_ = &list;
    io(name, v, Extent::listed);
    list_ = nullptr;
  }

  // Saves x; on load, reads the saved value and, when it differs from x (what the deck
  // built), fails with "the checkpoint has <what> <saved>, the deck <x>".
  void check(const std::string& name, uint64_t x, const std::string& what) {
    uint64_t saved = x;
    io(name, saved);
    if (saved != x)
      mismatch("it holds " + std::to_string(saved) + " " + what + ", the deck builds " + std::to_string(x) +
               ": the checkpoint does not belong to this deck");
  }
  void check(const std::string& name, const std::string& x, const std::string& what) {
    std::string saved = x;
    io(name, saved);
    if (saved != x)
      mismatch("it holds " + what + " '" + saved + "', the deck has '" + x +
               "': the checkpoint does not belong to this deck");
  }

  // The particle list of the record being saved with Extent::listed (io_listed).
  const std::vector<uint32_t>* list() const { return list_; }

  // Names of nested parts ("model 2/plastic_strain"): push a prefix, pop it after.
  void push(const std::string& prefix) { prefix_.push_back(prefix); }
  void pop() { prefix_.pop_back(); }

 protected:
  explicit StateArchive(bool loading) : loading_(loading) {}
  struct Record {
    const void* bytes = nullptr;
    uint64_t count = 0;
  };
  std::string full_name(const std::string& name) const {
    std::string s;
    for (const auto& p : prefix_) s += p + "/";
    return s + name;
  }
  virtual void put(const std::string& name, const void* bytes, std::size_t element_size, std::size_t count,
                   Extent extent) = 0;
  virtual Record get(const std::string& name, std::size_t element_size) = 0;
  // Throws horizon::Error naming the record and both counts.
  virtual void expect_count(const std::string& name, uint64_t found, uint64_t expected) = 0;
  // Throws horizon::Error naming the checkpoint and what does not match.
  virtual void mismatch(const std::string& what) = 0;

 private:
  bool loading_;
  const std::vector<uint32_t>* list_ = nullptr;
  std::vector<std::string> prefix_;
};

}  // namespace horizon
