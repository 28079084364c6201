// Output stage: VTU/PVD round trips, atomic writes, and the PNG renderer.
#include <gtest/gtest.h>
#include <png.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "horizon/core/error.hpp"
#include "horizon/output/atomic_file.hpp"
#include "horizon/output/colormap.hpp"
#include "horizon/output/pvd.hpp"
#include "horizon/output/render.hpp"
#include "horizon/output/vtu.hpp"

namespace fs = std::filesystem;
using namespace horizon;

namespace {

// A fresh, empty folder per test, removed afterwards.
class OutputTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           (std::string("horizon_output_") + info->name() + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  fs::path dir_;
};

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Values chosen to catch any loss of precision: not representable in short decimals.
Frame sample_frame() {
  Frame f;
  f.time = 1.0 / 3.0 * 1e-6;
  f.step = 1234567890123;
  f.dimension = 2;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 4; ++i) f.points.push_back({0.1 * i + 1e-17, std::sqrt(2.0) * j, 0});
  const size_t n = f.points.size();
  FrameField damage{"damage", 1, {}}, u{"displacement", 3, {}};
  for (size_t i = 0; i < n; ++i) {
    damage.data.push_back(std::nextafter(double(i) / n, 1.0));
    for (int c = 0; c < 3; ++c) u.data.push_back(std::sin(double(i * 3 + c)) * 1e-5);
  }
  f.fields = {damage, u, FrameField{"a \"quoted\" <name> & more", 1, std::vector<double>(n, -0.0)}};
  return f;
}

struct Png {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;
  Rgb at(int x, int y) const {
    const size_t i = (size_t(y) * width + x) * 3;
    return {rgb[i], rgb[i + 1], rgb[i + 2]};
  }
  size_t count(Rgb c) const {
    size_t k = 0;
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) k += at(x, y) == c;
    return k;
  }
};

Png read_png(const std::string& path) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, path.c_str()))
    throw std::runtime_error(std::string("libpng: ") + image.message);
  image.format = PNG_FORMAT_RGB;
  Png png{int(image.width), int(image.height), std::vector<uint8_t>(PNG_IMAGE_SIZE(image))};
  if (!png_image_finish_read(&image, nullptr, png.rgb.data(), 0, nullptr))
    throw std::runtime_error(std::string("libpng: ") + image.message);
  return png;
}

}  // namespace

TEST_F(OutputTest, VtuRoundTripIsBitExact) {
  const Frame f = sample_frame();
  write_vtu(path("frame.vtu"), f);
  const Frame g = read_vtu(path("frame.vtu"));

  EXPECT_EQ(std::memcmp(&g.time, &f.time, sizeof f.time), 0);
  EXPECT_EQ(g.step, f.step);
  EXPECT_EQ(g.dimension, f.dimension);
  ASSERT_EQ(g.points.size(), f.points.size());
  EXPECT_EQ(std::memcmp(g.points.data(), f.points.data(), f.points.size() * sizeof(Vec3)), 0);
  ASSERT_EQ(g.fields.size(), f.fields.size());
  for (size_t k = 0; k < f.fields.size(); ++k) {
    EXPECT_EQ(g.fields[k].name, f.fields[k].name);
    EXPECT_EQ(g.fields[k].components, f.fields[k].components);
    ASSERT_EQ(g.fields[k].data.size(), f.fields[k].data.size());
    EXPECT_EQ(std::memcmp(g.fields[k].data.data(), f.fields[k].data.data(),
                          f.fields[k].data.size() * sizeof(double)),
              0)
        << f.fields[k].name;
  }
}

TEST_F(OutputTest, VtuRoundTripOfAnEmptyFrame) {
  Frame f;
  f.time = 2.5;
  f.fields = {FrameField{"damage", 1, {}}};
  write_vtu(path("empty.vtu"), f);
  const Frame g = read_vtu(path("empty.vtu"));
  EXPECT_EQ(g.time, 2.5);
  EXPECT_TRUE(g.points.empty());
  ASSERT_EQ(g.fields.size(), 1u);
  EXPECT_TRUE(g.fields[0].data.empty());
}

TEST_F(OutputTest, VtuHeaderAndByteCountsMatchTheFileSize) {
  const Frame f = sample_frame();
  write_vtu(path("frame.vtu"), f);
  const std::string bytes = slurp(path("frame.vtu"));
  ASSERT_TRUE(bytes.starts_with("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\""));
  EXPECT_NE(bytes.find("header_type=\"UInt64\""), std::string::npos);
  EXPECT_NE(bytes.find("byte_order=\"LittleEndian\""), std::string::npos);

  const std::string open = "<AppendedData encoding=\"raw\">";
  const size_t tag = bytes.find(open);
  ASSERT_NE(tag, std::string::npos);
  size_t at = bytes.find('_', tag + open.size()) + 1;

  // Walk the blocks: 3 field-data values, the fields, points, then 3 cell arrays.
  const size_t n = f.points.size();
  const std::vector<uint64_t> expected = {8, 8, 4, n * 8, n * 24, n * 8, n * 24, n * 8, n * 8, n};
  for (uint64_t want : expected) {
    ASSERT_LE(at + 8, bytes.size());
    uint64_t count = 0;
    std::memcpy(&count, bytes.data() + at, 8);
    EXPECT_EQ(count, want);
    at += 8 + count;
  }
  EXPECT_EQ(bytes.substr(at), "\n  </AppendedData>\n</VTKFile>\n");
  EXPECT_EQ(at + bytes.substr(at).size(), fs::file_size(path("frame.vtu")));
}

TEST_F(OutputTest, ReadVtuRejectsTruncatedAndForeignFiles) {
  write_vtu(path("frame.vtu"), sample_frame());
  const std::string bytes = slurp(path("frame.vtu"));
  // Cut inside the header, inside the data, and just before the closing tags.
  for (size_t keep : {size_t(100), bytes.size() / 2, bytes.size() - 200, bytes.size() - 12}) {
    std::ofstream(path("cut.vtu"), std::ios::binary).write(bytes.data(), std::streamsize(keep));
    EXPECT_THROW(read_vtu(path("cut.vtu")), Error) << "kept " << keep << " bytes";
  }
  std::ofstream(path("other.vtu")) << "hello, not a frame\n";
  try {
    read_vtu(path("other.vtu"));
    FAIL() << "expected horizon::Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("other.vtu"), std::string::npos) << e.what();
  }
  EXPECT_THROW(read_vtu(path("missing.vtu")), Error);
}

TEST_F(OutputTest, WriteVtuRejectsFieldOfWrongSize) {
  Frame f = sample_frame();
  f.fields[0].data.pop_back();
  EXPECT_THROW(write_vtu(path("bad.vtu"), f), Error);
  EXPECT_FALSE(fs::exists(path("bad.vtu")));
}

TEST_F(OutputTest, PvdIsValidAfterEveryAdd) {
  PvdIndex pvd(path("run/run.pvd"));
  const std::vector<double> times = {0.0, 1.0 / 3.0, 2e-6, 1e300};
  for (size_t k = 0; k < times.size(); ++k) {
    pvd.add(times[k], "frames/frame_" + std::to_string(k) + ".vtu");
    const auto read = read_pvd(path("run/run.pvd"));
    ASSERT_EQ(read.size(), k + 1);
    for (size_t j = 0; j <= k; ++j) {
      EXPECT_EQ(read[j].first, times[j]);
      EXPECT_EQ(fs::path(read[j].second),
                fs::path(path("run")) / ("frames/frame_" + std::to_string(j) + ".vtu"));
    }
  }
  EXPECT_EQ(pvd.entries().size(), times.size());
  EXPECT_FALSE(fs::exists(path("run/run.pvd.tmp")));
}

TEST_F(OutputTest, ReadPvdRejectsTruncatedIndex) {
  PvdIndex pvd(path("run.pvd"));
  pvd.add(1.0, "a.vtu");
  const std::string text = slurp(path("run.pvd"));
  std::ofstream(path("cut.pvd")) << text.substr(0, text.size() - 20);
  EXPECT_THROW(read_pvd(path("cut.pvd")), Error);
}

TEST_F(OutputTest, AtomicWriteCreatesFoldersAndLeavesNoTemporary) {
  const std::string target = path("a/b/c/file.txt");
  write_file_atomic(target, "first");
  write_file_atomic(target, [](std::ostream& out) { out << "second"; });
  EXPECT_EQ(slurp(target), "second");
  EXPECT_FALSE(fs::exists(target + ".tmp"));
  EXPECT_EQ(std::distance(fs::directory_iterator(path("a/b/c")), fs::directory_iterator()), 1);
}

TEST_F(OutputTest, AtomicWriteKeepsOldFileWhenWriterFails) {
  const std::string target = path("file.txt");
  write_file_atomic(target, "old");
  EXPECT_THROW(write_file_atomic(target, [](std::ostream&) { throw Error("boom"); }), Error);
  EXPECT_EQ(slurp(target), "old");
  EXPECT_FALSE(fs::exists(target + ".tmp"));
}

TEST_F(OutputTest, AtomicWriteNamesThePathOnFailure) {
  write_file_atomic(path("plain"), "x");
  try {
    write_file_atomic(path("plain/inside.txt"), "y");  // parent is a file
    FAIL() << "expected horizon::Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("plain/inside.txt"), std::string::npos) << e.what();
  }
}

TEST_F(OutputTest, RenderColoursTheMaximumWithTheTopColour) {
  Frame f;
  f.dimension = 2;
  f.points = {{0, 0, 0}, {1e-3, 0, 0}};
  f.fields = {FrameField{"damage", 1, {0.0, 1.0}}};
  RenderOptions o;
  o.width = 400;
  render_png(f, o, path("pic/damage.png"));
  EXPECT_FALSE(fs::exists(path("pic/damage.png.tmp")));

  const Png png = read_png(path("pic/damage.png"));
  EXPECT_EQ(png.width, 400);
  EXPECT_GT(png.height, 0);
  // Each particle is a disc about half the plot wide.
  const Rgb top = viridis(1.0), bottom = viridis(0.0);
  EXPECT_EQ(top, (Rgb{253, 231, 37}));
  EXPECT_GT(png.count(top), 80u * 80u);
  EXPECT_GT(png.count(bottom), 80u * 80u);
  // The maximum sits on the right: the middle row's right quarter is the top colour.
  bool found_right = false;
  for (int y = 0; y < png.height && !found_right; ++y)
    found_right = png.at(3 * png.width / 4, y) == top && png.at(png.width / 4, y) == bottom;
  EXPECT_TRUE(found_right);
  EXPECT_EQ(png.at(0, 0), (Rgb{255, 255, 255}));
}

// The colour bar runs from the field's minimum (left, viridis' bottom colour) to its
// maximum (right, the top colour), and its title names the field and its scaled unit.
TEST_F(OutputTest, RenderColourBarSpansTheFieldsRange) {
  Frame f;
  f.dimension = 2;
  for (int j = 0; j < 10; ++j)
    for (int i = 0; i < 20; ++i) f.points.push_back({1e-4 * i, 1e-4 * j, 0});
  FrameField u{"displacement", 3, {}};
  for (const Vec3& p : f.points) u.data.insert(u.data.end(), {-2e-6 + 0.35 * p.x, 0.0, 0.0});
  f.fields = {u};
  RenderOptions o;
  o.field = "displacement_x";
  o.width = 600;
  const RenderResult r = render_png(f, o, path("u.png"));
  EXPECT_DOUBLE_EQ(r.lo, -2e-6);
  EXPECT_DOUBLE_EQ(r.hi, -2e-6 + 0.35 * 19e-4);
  EXPECT_EQ(r.field_title, "Displacement x (µm)");
  EXPECT_EQ(r.drawn, 200u);
  const Png png = read_png(path("u.png"));
  auto close = [](Rgb a, Rgb b) { return std::abs(a.r - b.r) + std::abs(a.g - b.g) + std::abs(a.b - b.b) <= 12; };
  const int y = int((r.bar_top + r.bar_bottom) / 2);
  EXPECT_TRUE(close(png.at(int(r.bar_left) + 3, y), viridis(0.0)));
  EXPECT_TRUE(close(png.at(int(r.bar_right) - 3, y), viridis(1.0)));
  EXPECT_TRUE(close(png.at(int((r.bar_left + r.bar_right) / 2), y), viridis(0.5)));
  // Outside the bar, the background.
  EXPECT_EQ(png.at(int(r.bar_left) - 4, y), (Rgb{255, 255, 255}));
  EXPECT_EQ(png.at(int(r.bar_right) + 4, y), (Rgb{255, 255, 255}));

  // A fixed range is what the bar shows; SVG carries the title as text.
  o.vmin = -1e-3;
  o.vmax = 1e-3;
  const RenderResult s = render_png(f, o, path("u.svg"));
  EXPECT_EQ(s.lo, -1e-3);
  EXPECT_EQ(s.field_title, "Displacement x (mm)");
  const std::string svg = slurp(path("u.svg"));
  EXPECT_NE(svg.find("<title>Displacement x (mm), t = 0 s</title>"), std::string::npos) << svg.substr(0, 600);
}

// A 3-D block: a slice shows one layer of particles, a projection all of them; a slice
// outside the body says where the body is.
TEST_F(OutputTest, RenderSlicesAndProjectsThreeDimensionalBodies) {
  Frame f;
  f.dimension = 3;
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 5; ++i) f.points.push_back({1e-3 * i, 1e-3 * j, 1e-3 * k});
  FrameField d{"damage", 1, {}};
  for (const Vec3& p : f.points) d.data.push_back(p.z * 100);
  f.fields = {d};
  RenderOptions o;
  o.width = 300;
  o.slice = "z=0.0021";
  RenderResult r = render_png(f, o, path("slice.png"));
  EXPECT_EQ(r.drawn, 20u);
  EXPECT_DOUBLE_EQ(r.lo, 0.2);
  EXPECT_DOUBLE_EQ(r.hi, 0.2);
  o.slice = "x=0";
  EXPECT_EQ(render_png(f, o, path("slice_x.png")).drawn, 16u);
  o.slice = "z=0.0015";  // midway between two layers: the lower one only
  r = render_png(f, o, path("slice_mid.png"));
  EXPECT_EQ(r.drawn, 20u);
  EXPECT_DOUBLE_EQ(r.lo, 0.1);
  o.slice.clear();
  r = render_png(f, o, path("top.png"));
  EXPECT_EQ(r.drawn, 80u);
  EXPECT_DOUBLE_EQ(r.hi, 0.3);
  o.slice = "z=0.01";
  try {
    render_png(f, o, path("none.png"));
    FAIL() << "expected horizon::Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("z = 0 to 0.003"), std::string::npos) << e.what();
  }
  o.slice = "w=1";
  EXPECT_THROW(render_png(f, o, path("none.png")), Error);
  o.slice = "z=";
  EXPECT_THROW(render_png(f, o, path("none.png")), Error);
  f.dimension = 2;  // a plane body has no slices
  o.slice = "z=0";
  EXPECT_THROW(render_png(f, o, path("none.png")), Error);
}

TEST_F(OutputTest, RenderPicksVectorComponentsAndMagnitude) {
  Frame f = sample_frame();
  for (const char* name : {"displacement", "displacement_x", "displacement_z", "damage"}) {
    RenderOptions o;
    o.field = name;
    o.width = 320;
    o.displacement_scale = 100;
    EXPECT_NO_THROW(render_png(f, o, path(std::string(name) + ".png"))) << name;
    EXPECT_EQ(read_png(path(std::string(name) + ".png")).width, 320);
  }
}

TEST_F(OutputTest, RenderOfMissingFieldListsTheAvailableOnes) {
  const Frame f = sample_frame();
  RenderOptions o;
  o.field = "stress";
  try {
    render_png(f, o, path("x.png"));
    FAIL() << "expected horizon::Error";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("stress"), std::string::npos) << what;
    EXPECT_NE(what.find("damage"), std::string::npos) << what;
    EXPECT_NE(what.find("displacement"), std::string::npos) << what;
  }
  o.field = "damage_x";  // a suffix only applies to vector fields
  EXPECT_THROW(render_png(f, o, path("x.png")), Error);
  EXPECT_FALSE(fs::exists(path("x.png")));
}

TEST_F(OutputTest, ResolveFrameFollowsIndexesAndFolders) {
  write_vtu(path("out/frames/f0.vtu"), sample_frame());
  write_vtu(path("out/frames/f1.vtu"), sample_frame());
  PvdIndex pvd(path("out/run.pvd"));
  pvd.add(0.0, "frames/f0.vtu");
  pvd.add(1.0, "frames/f1.vtu");

  const fs::path last = fs::path(path("out")) / "frames/f1.vtu";
  EXPECT_EQ(fs::path(resolve_frame(path("out/frames/f0.vtu"))), fs::path(path("out/frames/f0.vtu")));
  EXPECT_EQ(fs::path(resolve_frame(path("out/run.pvd"))), last);
  EXPECT_EQ(fs::path(resolve_frame(path("out"))), last);
  EXPECT_THROW(resolve_frame(path("nothing")), Error);
  EXPECT_THROW(resolve_frame(path("out/frames")), Error);  // a folder without an index
  write_file_atomic(path("notes.txt"), "x");
  EXPECT_THROW(resolve_frame(path("notes.txt")), Error);
}
