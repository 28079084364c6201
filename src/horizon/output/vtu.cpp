#include "horizon/output/vtu.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cstring>
#include <fstream>
#include <functional>
#include <sstream>

#include "horizon/core/error.hpp"
#include "horizon/output/atomic_file.hpp"
#include "horizon/output/xml_tags.hpp"

namespace horizon {

namespace {

// Arrays are copied straight from memory, and the file says LittleEndian.
static_assert(std::endian::native == std::endian::little,
              "write_vtu/read_vtu assume a little-endian host");
static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 must be three packed doubles");

constexpr uint8_t vtk_vertex = 1;  // VTK cell type id of a single-point cell

// One array of the appended block: what the XML says about it and how to stream it.
struct AppendedArray {
  std::string section;  // FieldData, PointData, Points or Cells
  std::string type;     // VTK type name
  size_t value_size;
  std::string name;
  int components;
  uint64_t tuples;
  std::function<void(std::ostream&)> write;

  uint64_t bytes() const { return tuples * uint64_t(components) * value_size; }
};

template <class T>
void put(std::ostream& out, const T* data, size_t count) {
  out.write(reinterpret_cast<const char*>(data), std::streamsize(count * sizeof(T)));
}

// Streams first, first+1, ... (n values) in chunks: connectivity and offsets are
// just counters, and building them whole would double the memory of a large frame.
void put_counting(std::ostream& out, int64_t first, size_t n) {
  std::array<int64_t, 4096> chunk;
  for (size_t done = 0; done < n;) {
    const size_t m = std::min(chunk.size(), n - done);
    for (size_t k = 0; k < m; ++k) chunk[k] = first + int64_t(done + k);
    put(out, chunk.data(), m);
    done += m;
  }
}

void put_vertex_types(std::ostream& out, size_t n) {
  std::array<uint8_t, 4096> chunk;
  chunk.fill(vtk_vertex);
  for (size_t done = 0; done < n; done += chunk.size())
    put(out, chunk.data(), std::min(chunk.size(), n - done));
}

std::vector<AppendedArray> arrays_of(const Frame& f, const std::string& path) {
  const size_t n = f.points.size();
  std::vector<AppendedArray> a;
  a.push_back({"FieldData", "Float64", 8, "TIME", 1, 1, [&f](auto& o) { put(o, &f.time, 1); }});
  a.push_back({"FieldData", "Int64", 8, "CYCLE", 1, 1, [&f](auto& o) { put(o, &f.step, 1); }});
  const int32_t dim = f.dimension;
  a.push_back({"FieldData", "Int32", 4, "dimension", 1, 1, [dim](auto& o) { put(o, &dim, 1); }});
  for (const FrameField& field : f.fields) {
    if (field.components != 1 && field.components != 3)
      throw Error(fmt::format("{}: field '{}' has {} components; frames hold 1 or 3", path,
                              field.name, field.components));
    if (field.data.size() != n * size_t(field.components))
      throw Error(fmt::format("{}: field '{}' has {} values, expected {} ({} points x {})", path,
                              field.name, field.data.size(), n * field.components, n,
                              field.components));
    a.push_back({"PointData", "Float64", 8, field.name, field.components, n,
                 [&field](auto& o) { put(o, field.data.data(), field.data.size()); }});
  }
  a.push_back({"Points", "Float64", 8, "Points", 3, n,
               [&f](auto& o) { put(o, f.points.data(), f.points.size()); }});
  a.push_back({"Cells", "Int64", 8, "connectivity", 1, n, [n](auto& o) { put_counting(o, 0, n); }});
  a.push_back({"Cells", "Int64", 8, "offsets", 1, n, [n](auto& o) { put_counting(o, 1, n); }});
  a.push_back({"Cells", "UInt8", 1, "types", 1, n, [n](auto& o) { put_vertex_types(o, n); }});
  return a;
}

std::string header_of(const Frame& f, const std::vector<AppendedArray>& arrays) {
  auto section = [&](const std::string& name, const std::string& indent) {
    std::string s = indent + "<" + name + ">\n";
    uint64_t offset = 0;  // from the byte after '_', as the VTK format defines it
    for (const AppendedArray& a : arrays) {
      if (a.section == name)
        s += fmt::format(
            "{}  <DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\" "
            "NumberOfTuples=\"{}\" format=\"appended\" offset=\"{}\"/>\n",
            indent, a.type, xml_escape(a.name), a.components, a.tuples, offset);
      offset += sizeof(uint64_t) + a.bytes();
    }
    return s + indent + "</" + name + ">\n";
  };
  const size_t n = f.points.size();
  return "<?xml version=\"1.0\"?>\n"
         "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
         "header_type=\"UInt64\">\n"
         "  <UnstructuredGrid>\n" +
         section("FieldData", "    ") +
         fmt::format("    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", n, n) +
         section("PointData", "      ") + section("Points", "      ") +
         section("Cells", "      ") +
         "    </Piece>\n"
         "  </UnstructuredGrid>\n"
         "  <AppendedData encoding=\"raw\">\n   _";
}

// ---- reading -------------------------------------------------------------------------

std::string read_whole_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open '" + path + "' for reading");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The parsed layout of a VTU file, with every array's bytes bounds-checked.
class VtuReader {
 public:
  explicit VtuReader(const std::string& path) : path_(path), bytes_(read_whole_file(path)) {}

  Error fail(const std::string& why) const {
    return Error("'" + path_ + "' is not a readable Horizon VTU file: " + why);
  }

  uint64_t number(const XmlTag& tag, const std::string& key, uint64_t fallback) const {
    const std::string* s = tag.find(key);
    if (!s) return fallback;
    uint64_t v = 0;
    auto [end, ec] = std::from_chars(s->data(), s->data() + s->size(), v);
    if (ec != std::errc() || end != s->data() + s->size())
      throw fail("attribute " + key + "=\"" + *s + "\" of <" + tag.name + "> is not a count");
    return v;
  }

  const std::string& attribute(const XmlTag& tag, const std::string& key) const {
    const std::string* s = tag.find(key);
    if (!s) throw fail("<" + tag.name + "> has no " + key + " attribute");
    return *s;
  }

  // The payload of one appended array, checked against the size the XML implies.
  std::string_view payload(const XmlTag& tag, const std::string& type, uint64_t tuples,
                           uint64_t components = 1) {
    const std::string& name = attribute(tag, "Name");
    // Counts from a damaged header could overflow the size arithmetic below.
    const uint64_t offset = number(tag, "offset", 0);
    if (tuples > bytes_.size() || offset > bytes_.size())
      throw fail("array '" + name + "' lies past the end of the file (truncated?)");
    if (attribute(tag, "type") != type)
      throw fail("array '" + name + "' has type " + attribute(tag, "type") + ", expected " + type);
    if (attribute(tag, "format") != "appended")
      throw fail("array '" + name + "' is not in the appended block");
    const uint64_t size = type == "Float64" || type == "Int64" ? 8 : type == "Int32" ? 4 : 1;
    const uint64_t expected = tuples * components * size;
    const uint64_t at = data_start_ + offset;
    if (at + sizeof(uint64_t) > bytes_.size())
      throw fail("array '" + name + "' lies past the end of the file (truncated?)");
    uint64_t count = 0;
    std::memcpy(&count, bytes_.data() + at, sizeof count);
    if (count != expected)
      throw fail(fmt::format("array '{}' holds {} bytes, expected {}", name, count, expected));
    if (at + sizeof(uint64_t) + count > bytes_.size())
      throw fail("array '" + name + "' is cut off (file truncated?)");
    data_end_ = std::max(data_end_, at + sizeof(uint64_t) + count);
    return std::string_view(bytes_).substr(at + sizeof(uint64_t), count);
  }

  Frame read();

 private:
  std::string path_;
  std::string bytes_;
  uint64_t data_start_ = 0;
  uint64_t data_end_ = 0;
};

template <class T>
T scalar(std::string_view bytes) {
  T v;
  std::memcpy(&v, bytes.data(), sizeof v);
  return v;
}

Frame VtuReader::read() {
  if (!bytes_.starts_with("<?xml") && !bytes_.starts_with("<VTKFile"))
    throw fail("it does not start with an XML header");
  const size_t appended = bytes_.find("<AppendedData");
  if (appended == std::string::npos)
    throw fail("no <AppendedData> block (truncated, or written by another program)");
  const size_t tag_end = bytes_.find('>', appended);
  const size_t marker = bytes_.find('_', tag_end == std::string::npos ? appended : tag_end);
  if (tag_end == std::string::npos || marker == std::string::npos)
    throw fail("the <AppendedData> block is cut off (file truncated?)");
  data_start_ = marker + 1;
  const auto tags = scan_xml_tags(std::string_view(bytes_).substr(0, tag_end + 1), path_);

  bool is_vtk = false;
  uint64_t n = 0;
  std::string section;
  std::vector<std::pair<std::string, const XmlTag*>> arrays;
  for (const XmlTag& t : tags) {
    if (t.name == "VTKFile" && !t.closing) {
      is_vtk = true;
      if (attribute(t, "type") != "UnstructuredGrid") throw fail("it is not an UnstructuredGrid");
      if (attribute(t, "byte_order") != "LittleEndian") throw fail("it is not LittleEndian");
      if (attribute(t, "header_type") != "UInt64") throw fail("its header_type is not UInt64");
    } else if (t.name == "AppendedData" && attribute(t, "encoding") != "raw") {
      throw fail("its appended data is not raw (compressed or base64)");
    } else if (t.name == "Piece" && !t.closing) {
      if (n != 0) throw fail("it has more than one Piece");
      n = number(t, "NumberOfPoints", 0);
    } else if (t.name == "DataArray") {
      arrays.emplace_back(section, &t);
    } else if (!t.self_closing) {
      section = t.closing ? "" : t.name;
    }
  }
  if (!is_vtk) throw fail("it has no <VTKFile> element");

  Frame f;
  bool has_points = false;
  for (const auto& [where, tag] : arrays) {
    const std::string& name = attribute(*tag, "Name");
    const uint64_t components = number(*tag, "NumberOfComponents", 1);
    if (where == "FieldData" && name == "TIME") {
      f.time = scalar<double>(payload(*tag, "Float64", 1));
    } else if (where == "FieldData" && name == "CYCLE") {
      f.step = scalar<int64_t>(payload(*tag, "Int64", 1));
    } else if (where == "FieldData" && name == "dimension") {
      f.dimension = scalar<int32_t>(payload(*tag, "Int32", 1));
    } else if (where == "Points") {
      if (components != 3) throw fail("Points do not have 3 components");
      const auto data = payload(*tag, "Float64", n, 3);
      f.points.resize(n);
      if (n > 0) std::memcpy(static_cast<void*>(f.points.data()), data.data(), data.size());
      has_points = true;
    } else if (where == "PointData") {
      if (components != 1 && components != 3)
        throw fail("field '" + name + "' has neither 1 nor 3 components");
      const auto data = payload(*tag, "Float64", n, components);
      FrameField field{name, int(components), std::vector<double>(components * n)};
      if (n > 0) std::memcpy(field.data.data(), data.data(), data.size());
      f.fields.push_back(std::move(field));
    } else if (where == "Cells") {
      const std::string type = name == "types" ? "UInt8" : "Int64";
      payload(*tag, type, n);  // not needed, but its bytes must all be there
    }
  }
  if (!has_points) throw fail("it has no Points array");
  if (bytes_.find("</VTKFile>", data_end_) == std::string::npos)
    throw fail("it does not end with </VTKFile> (file truncated?)");
  return f;
}

}  // namespace

void write_vtu(const std::string& path, const Frame& frame) {
  const auto arrays = arrays_of(frame, path);
  const std::string header = header_of(frame, arrays);
  write_file_atomic(path, [&](std::ostream& out) {
    out << header;
    for (const AppendedArray& a : arrays) {
      const uint64_t count = a.bytes();
      put(out, &count, 1);
      a.write(out);
    }
    out << "\n  </AppendedData>\n</VTKFile>\n";
  });
}

Frame read_vtu(const std::string& path) { return VtuReader(path).read(); }

Frame frame_subset(const Frame& frame, const std::vector<uint32_t>& which) {
  Frame f;
  f.time = frame.time;
  f.step = frame.step;
  f.dimension = frame.dimension;
  f.points.reserve(which.size());
  for (uint32_t i : which) f.points.push_back(frame.points[i]);
  for (const auto& ff : frame.fields) {
    FrameField g{ff.name, ff.components, {}};
    const auto c = static_cast<std::size_t>(ff.components);
    g.data.reserve(which.size() * c);
    for (uint32_t i : which)
      for (std::size_t k = 0; k < c; ++k) g.data.push_back(ff.data[i * c + k]);
    f.fields.push_back(std::move(g));
  }
  return f;
}

void write_pvtu(const std::string& path, const Frame& like, const std::vector<std::string>& pieces) {
  std::string x =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
      "  <PUnstructuredGrid GhostLevel=\"0\">\n    <PPointData>\n";
  for (const auto& ff : like.fields)
    x += fmt::format("      <PDataArray type=\"Float64\" Name=\"{}\" NumberOfComponents=\"{}\"/>\n",
                     xml_escape(ff.name), ff.components);
  x += "    </PPointData>\n    <PPoints>\n      <PDataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"/>\n"
       "    </PPoints>\n";
  for (const auto& p : pieces) x += fmt::format("    <Piece Source=\"{}\"/>\n", xml_escape(p));
  x += "  </PUnstructuredGrid>\n</VTKFile>\n";
  write_file_atomic(path, x);
}

}  // namespace horizon
