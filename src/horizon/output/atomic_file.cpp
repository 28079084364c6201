#include "horizon/output/atomic_file.hpp"

#include <cerrno>
#include <cstdio>
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
      throw OutputError("cannot create directory '" + target.parent_path().string() + "' for output file '" + path +
                        "': " + ec.message());
  }
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out)
      throw OutputError("cannot open '" + tmp.string() + "' for writing: " + std::strerror(errno));
    errno = 0;
    try {
      write(out);
    } catch (...) {
      out.close();
      fs::remove(tmp, ec);  // leave no debris behind a failed writer
      throw;
    }
    out.flush();
    // The failed write(2) leaves its errno (ENOSPC: disk full, EFBIG: file-size limit;
    // `horizon` ignores SIGXFSZ so that the limit is an error, not a kill).
    int e = errno;
    if (out) {
      out.close();  // the last buffered bytes reach the disk here
      e = errno;
    }
    if (!out) {
      out.close();
      fs::remove(tmp, ec);
      throw OutputError("cannot write '" + tmp.string() + "': " + (e ? std::strerror(e) : "write failed") +
                        "; '" + path + "' keeps its previous content");
    }
  }
  fs::rename(tmp, target, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw OutputError("cannot rename '" + tmp.string() + "' to '" + path + "': " + ec.message());
  }
}

void write_result_file(const std::string& path, const std::string& bytes, bool after_output_error) {
  try {
    write_file_atomic(path, bytes);
  } catch (const OutputError& e) {
    if (!after_output_error) throw;
    std::fprintf(stderr, "horizon: %s\n", e.what());
  }
}

void prepare_output_directory(const std::string& dir, const std::string& sub) {
  std::error_code ec;
  const fs::path d(dir);
  fs::create_directories(d / sub, ec);
  if (ec) throw OutputError("cannot create the output directory '" + (d / sub).string() + "': " + ec.message());
  const fs::path probe = d / sub / ".horizon-write-probe";
  {
    std::ofstream out(probe, std::ios::binary | std::ios::trunc);
    if (!out) throw OutputError("the output directory '" + (d / sub).string() + "' is not writable: " + std::strerror(errno));
  }
  fs::remove(probe, ec);
}

}  // namespace horizon
