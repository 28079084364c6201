#pragma once
// The ParaView collection (.pvd) that lists a run's frames with their times, so that
// ParaView opens the whole run as one time series.
#include <string>
#include <utility>
#include <vector>

namespace horizon {

class PvdIndex {
 public:
  // Nothing is written until the first add() or write().
  explicit PvdIndex(std::string path);

  // Appends a frame (its path relative to the .pvd's folder) and rewrites the index at
  // once, so that a run stopped at any moment still leaves a valid, complete index.
  void add(double time, const std::string& relative_file);

  // Writes the index atomically: readers see the previous version or this one.
  void write() const;

  // Replaces the entries (a restart continues the index of its checkpoint).
  void set_entries(std::vector<std::pair<double, std::string>> entries) { entries_ = std::move(entries); }

  const std::string& path() const { return path_; }
  const std::vector<std::pair<double, std::string>>& entries() const { return entries_; }

 private:
  std::string path_;
  std::vector<std::pair<double, std::string>> entries_;
};

// The (time, file) entries of a .pvd in file order, each file resolved against the
// .pvd's folder. Throws horizon::Error naming the path on a missing or malformed index.
std::vector<std::pair<double, std::string>> read_pvd(const std::string& path);

}  // namespace horizon
