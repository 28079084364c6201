#include "horizon/output/pvd.hpp"

#include <fmt/format.h>

#include <charconv>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "horizon/core/error.hpp"
#include "horizon/output/atomic_file.hpp"
#include "horizon/output/xml_tags.hpp"

namespace horizon {

PvdIndex::PvdIndex(std::string path) : path_(std::move(path)) {}

void PvdIndex::add(double time, const std::string& relative_file) {
  entries_.emplace_back(time, relative_file);
  try {
    write();
  } catch (...) {
    entries_.pop_back();  // the index on disk is the previous one: keep saying so
    throw;
  }
}

void PvdIndex::write() const {
  std::string xml =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      "  <Collection>\n";
  // "{}" prints the shortest text that reads back to the same double.
  for (const auto& [time, file] : entries_)
    xml += fmt::format("    <DataSet timestep=\"{}\" group=\"\" part=\"0\" file=\"{}\"/>\n", time,
                       xml_escape(file));
  xml += "  </Collection>\n</VTKFile>\n";
  write_file_atomic(path_, xml);
}

std::vector<std::pair<double, std::string>> read_pvd(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open ParaView index '" + path + "' for reading");
  std::ostringstream text;
  text << in.rdbuf();
  const auto tags = scan_xml_tags(text.str(), path);

  bool collection = false, closed = false;
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  std::vector<std::pair<double, std::string>> entries;
  for (const XmlTag& t : tags) {
    if (t.name == "VTKFile" && t.closing) closed = true;
    if (t.name == "VTKFile" && !t.closing) {
      const std::string* type = t.find("type");
      collection = type && *type == "Collection";
    }
    if (t.name != "DataSet") continue;
    const std::string* time = t.find("timestep");
    const std::string* file = t.find("file");
    if (!file) throw Error(path + ": a <DataSet> has no file attribute");
    double value = 0;
    if (time) {
      auto [end, ec] = std::from_chars(time->data(), time->data() + time->size(), value);
      if (ec != std::errc() || end != time->data() + time->size())
        throw Error(path + ": timestep \"" + *time + "\" is not a number");
    }
    entries.emplace_back(value, (folder / *file).string());
  }
  if (!collection) throw Error("'" + path + "' is not a ParaView collection (.pvd) file");
  if (!closed) throw Error("'" + path + "' ends before </VTKFile> (file truncated?)");
  return entries;
}

}  // namespace horizon
