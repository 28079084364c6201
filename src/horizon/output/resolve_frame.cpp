#include "horizon/output/resolve_frame.hpp"

#include <algorithm>
#include <filesystem>
#include <vector>

#include "horizon/core/error.hpp"
#include "horizon/output/pvd.hpp"

namespace horizon {

namespace fs = std::filesystem;

namespace {

std::string last_dataset(const std::string& pvd) {
  const auto entries = read_pvd(pvd);
  if (entries.empty()) throw Error("ParaView index '" + pvd + "' lists no frames yet");
  return entries.back().second;
}

}  // namespace

std::string resolve_frame(const std::string& frame_or_dir) {
  const fs::path p(frame_or_dir);
  std::error_code ec;
  if (fs::is_directory(p, ec)) {
    std::vector<std::string> indexes;
    for (const auto& entry : fs::directory_iterator(p, ec))
      if (entry.path().extension() == ".pvd") indexes.push_back(entry.path().string());
    if (indexes.empty())
      throw Error("directory '" + frame_or_dir + "' has no .pvd index; pass a .vtu frame instead");
    if (indexes.size() > 1) {
      std::sort(indexes.begin(), indexes.end());
      std::string list;
      for (const auto& i : indexes) list += "\n  " + i;
      throw Error("directory '" + frame_or_dir + "' has several .pvd indexes; pass one:" + list);
    }
    return last_dataset(indexes.front());
  }
  if (!fs::exists(p, ec)) throw Error("'" + frame_or_dir + "' does not exist");
  if (p.extension() == ".vtu") return frame_or_dir;
  if (p.extension() == ".pvd") return last_dataset(frame_or_dir);
  throw Error("'" + frame_or_dir +
              "' is neither a .vtu frame, a .pvd index nor an output directory");
}

}  // namespace horizon
