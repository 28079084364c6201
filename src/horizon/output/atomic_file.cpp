#include "horizon/output/atomic_file.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <system_error>

#include "horizon/core/error.hpp"

namespace horizon {

namespace fs = std::filesystem;

void write_file_atomic(const std::string& path, const std::string& bytes) {
  write_file_atomic(path, [&](std::ostream& out) {
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  });
}

void write_file_atomic(const std::string& path,
                       const std::function<void(std::ostream&)>& write) {
  const fs::path target(path);
  const fs::path tmp(path + ".tmp");
  std::error_code ec;
  if (target.has_parent_path()) {
    fs::create_directories(target.parent_path(), ec);
    if (ec)
      throw Error("cannot create directory '" + target.parent_path().string() +
                  "' for output file '" + path + "': " + ec.message());
  }
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out)
      throw Error("cannot open '" + tmp.string() + "' for writing: " + std::strerror(errno));
    try {
      write(out);
    } catch (...) {
      out.close();
      fs::remove(tmp, ec);  // leave no debris behind a failed writer
      throw;
    }
    out.flush();
    if (!out) {
      out.close();
      fs::remove(tmp, ec);
      throw Error("failed while writing '" + tmp.string() + "' (disk full?)");
    }
  }
  fs::rename(tmp, target, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw Error("cannot rename '" + tmp.string() + "' to '" + path + "': " + ec.message());
  }
}

}  // namespace horizon
