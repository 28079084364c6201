// `horizon plot` (output/plot.hpp): history.csv columns to a line plot with its peak, axis
// titles with units (output/units.hpp), several curves, PNG, SVG and PDF.
#include <gtest/gtest.h>
#include <png.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "horizon/core/error.hpp"
#include "horizon/output/plot.hpp"
#include "horizon/output/units.hpp"

namespace horizon {
namespace {

namespace fs = std::filesystem;

class PlotTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("horizon_plot_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
            std::to_string(::getpid()));
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // A beam's history: the force rises linearly to 480 N at 12 µm, then falls to 40 N.
  std::string history(const std::string& run, double f_scale = 1) const {
    fs::create_directories(dir_ / run);
    std::ofstream out(dir_ / run / "history.csv");
    out << "time,step,kinetic_energy,load:displacement_uy,load:displacement_fy\n";
    for (int k = 0; k <= 20; ++k) {
      const double u = -1e-6 * k, f = f_scale * (k <= 12 ? -40.0 * k : -40.0 * 12 + 55.0 * (k - 12));
      out << 1e-6 * k << "," << k << "," << 1e-3 * k * k << "," << u << "," << f << "\n";
    }
    return (dir_ / run).string();
  }
  fs::path dir_;
};

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

struct Rgb8 {
  int r, g, b;
};
struct Picture {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;
  Rgb8 at(int x, int y) const {
    const size_t i = (size_t(y) * size_t(width) + size_t(x)) * 3;
    return {rgb[i], rgb[i + 1], rgb[i + 2]};
  }
  // Whether a pixel within `r` of (x, y) is clearly coloured (the curve), not white,
  // grey grid or black ink.
  bool coloured_near(double x, double y, int r) const {
    for (int dy = -r; dy <= r; ++dy)
      for (int dx = -r; dx <= r; ++dx) {
        const int px = int(std::lround(x)) + dx, py = int(std::lround(y)) + dy;
        if (px < 0 || py < 0 || px >= width || py >= height) continue;
        const Rgb8 c = at(px, py);
        if (std::max({c.r, c.g, c.b}) - std::min({c.r, c.g, c.b}) > 60) return true;
      }
    return false;
  }
};

Picture read_png(const std::string& path) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, path.c_str())) throw std::runtime_error(image.message);
  image.format = PNG_FORMAT_RGB;
  Picture p{int(image.width), int(image.height), std::vector<uint8_t>(PNG_IMAGE_SIZE(image))};
  if (!png_image_finish_read(&image, nullptr, p.rgb.data(), 0, nullptr)) throw std::runtime_error(image.message);
  return p;
}

TEST_F(PlotTest, FindsThePeakAndDrawsTheCurveWhereItIs) {
  PlotRequest q;
  q.histories = {history("beam")};
  q.x_column = "load:displacement_uy";
  q.y_columns = {"load:displacement_fy"};
  q.x_scale = q.y_scale = -1;
  const PlotCommandResult r = plot_history(q);
  ASSERT_EQ(r.peaks.size(), 1u);
  EXPECT_DOUBLE_EQ(r.peaks[0].y, 480.0);
  EXPECT_NEAR(r.peaks[0].x, 12e-6, 1e-18);
  EXPECT_EQ(r.peaks[0].index, 12u);
  EXPECT_EQ(r.path, (dir_ / "beam" / "load_displacement_fy.png").string());
  EXPECT_DOUBLE_EQ(r.x_factor, 1e6);  // displacements up to 20 µm are shown in µm
  EXPECT_DOUBLE_EQ(r.y_factor, 1.0);  // forces up to 480 N in N

  const Picture png = read_png(r.path);
  EXPECT_EQ(png.width, 900);
  EXPECT_EQ(png.height, 560);
  // Every data point and the middle of every segment lies on the drawn curve...
  for (int k = 0; k <= 20; ++k) {
    const double x = 1e-6 * k * r.x_factor, y = (k <= 12 ? 40.0 * k : 480 - 55.0 * (k - 12)) * r.y_factor;
    EXPECT_TRUE(png.coloured_near(r.frame.px(x), r.frame.py(y), 2)) << "point " << k;
  }
  // ...and away from it the plot is background: above the rising line, below the peak.
  EXPECT_FALSE(png.coloured_near(r.frame.px(2), r.frame.py(400), 6));
  EXPECT_FALSE(png.coloured_near(r.frame.px(18), r.frame.py(400), 6));
  EXPECT_GE(r.frame.x0, -1e-12);
  EXPECT_GE(r.frame.x1, 20);
  EXPECT_GE(r.frame.y1, 480);

  q.y_columns = {"load:displacement_ux"};
  try {
    plot_history(q);
    ADD_FAILURE() << "no error for a missing column";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("the columns are: time, step"), std::string::npos) << e.what();
  }
}

// The frame ends at the data when the data passes its last tick by less than a tenth of
// a step (no tick of empty axis), and keeps room above a marked peak for its label.
TEST_F(PlotTest, FrameEndsAtTheDataAndLeavesRoomForThePeakLabel) {
  fs::create_directories(dir_ / "ball");
  {
    std::ofstream out(dir_ / "ball" / "history.csv");
    out << "time,step,kinetic_energy\n";
    for (int k = 0; k <= 121; ++k) out << 1e-6 * k << "," << k << "," << 100.0 * std::exp(-std::pow((k - 36) / 20.0, 2)) << "\n";
  }
  PlotRequest q;
  q.histories = {(dir_ / "ball").string()};
  q.x_column = "time";
  q.y_columns = {"kinetic_energy"};
  const PlotCommandResult r = plot_history(q);
  ASSERT_EQ(r.peaks.size(), 1u);
  EXPECT_DOUBLE_EQ(r.x_factor, 1e6);  // µs
  // 121 µs on ticks of 20 µs: the frame ends at 121, not at a tick of 140.
  EXPECT_NEAR(r.frame.x1, 121, 1e-9);
  // The peak (100 J) sits at least a tenth of the range below the frame's top.
  EXPECT_GE(r.frame.y1, 110 - 1e-9);
  const Picture png = read_png(r.path);
  // The peak's label is above the dot, clear of the curve: red ink up and to the right of
  // the peak, none below it where the curve falls.
  auto red_in = [&](double x0, double x1, double y0, double y1) {
    int n = 0;
    for (int y = int(y0); y <= int(y1); ++y)
      for (int x = int(x0); x <= int(x1); ++x) {
        if (x < 0 || y < 0 || x >= png.width || y >= png.height) continue;
        const Rgb8 c = png.at(x, y);
        n += c.r > 150 && c.g < 100 && c.b < 100;
      }
    return n;
  };
  const double cx = r.frame.px(36), cy = r.frame.py(100);
  EXPECT_GT(red_in(cx + 8, cx + 200, cy - 30, cy - 8), 20);
  EXPECT_EQ(red_in(cx + 8, cx + 200, cy + 8, cy + 40), 0);
}

TEST_F(PlotTest, SvgParsesAsXmlAndNamesTheAxesAndCurves) {
  PlotRequest q;
  q.histories = {history("beam")};
  q.x_column = "time";
  q.y_columns = {"kinetic_energy", "load:displacement_fy"};
  q.output = (dir_ / "two.svg").string();
  const PlotCommandResult r = plot_history(q);
  ASSERT_EQ(r.labels.size(), 2u);
  const std::string svg = slurp(q.output);
  const std::string check = "python3 -c \"import sys, xml.etree.ElementTree as E; E.parse(sys.argv[1])\" '" +
                            q.output + "'";
  EXPECT_EQ(std::system(check.c_str()), 0) << svg.substr(0, 400);
  EXPECT_NE(svg.find("Time (µs)"), std::string::npos);
  // Energy and force share no unit: the axis says so rather than inventing one.
  EXPECT_NE(svg.find("y: Value"), std::string::npos);
  EXPECT_NE(svg.find("curve: kinetic energy"), std::string::npos);
  EXPECT_NE(svg.find("curve: force y on load:displacement"), std::string::npos);

  q.y_columns = {"load:displacement_fy"};
  q.y_label = "Load <P> & more";
  plot_history(q);
  const std::string labelled = slurp(q.output);
  EXPECT_NE(labelled.find("Load &lt;P&gt; &amp; more"), std::string::npos);
  EXPECT_EQ(std::system(check.c_str()), 0);
}

TEST_F(PlotTest, SweepGetsOneCurveAndLegendEntryPerRun) {
  PlotRequest q;
  q.histories = {history("v100"), history("v200", 2)};
  q.x_column = "load:displacement_uy";
  q.y_columns = {"load:displacement_fy"};
  q.x_scale = q.y_scale = -1;
  q.output = (dir_ / "sweep.pdf").string();
  const PlotCommandResult r = plot_history(q);
  ASSERT_EQ(r.labels.size(), 2u);
  EXPECT_EQ(r.labels[0], "v100");
  EXPECT_EQ(r.labels[1], "v200");
  EXPECT_DOUBLE_EQ(r.peaks[1].y, 960.0);
  EXPECT_EQ(slurp(q.output).rfind("%PDF", 0), 0u);

  q.output = (dir_ / "sweep.jpg").string();
  try {
    plot_history(q);
    ADD_FAILURE() << "no error for an unknown extension";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(".png, .svg or .pdf"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(q.output));
}

TEST(Units, ColumnsGetTheirQuantityAndAReadableUnit) {
  const Quantity f = history_quantity("load:displacement_fy");
  EXPECT_EQ(f.unit, "N");
  EXPECT_EQ(axis_title(f.name, scaled_unit(f, 2.5e4).unit), "Force y on load:displacement (kN)");
  EXPECT_EQ(history_quantity("support1:displacement_uz").unit, "m");
  EXPECT_EQ(history_quantity("striker_vx").unit, "m/s");
  EXPECT_EQ(history_quantity("striker_ay_filtered").unit, "m/s²");
  EXPECT_EQ(history_quantity("striker_z").name, "position z of striker");
  EXPECT_EQ(history_quantity("dissipated_energy").unit, "J");
  EXPECT_EQ(history_quantity("temperature_max").unit, "K");
  EXPECT_EQ(history_quantity("damage_max").unit, "");
  EXPECT_EQ(history_quantity("my_column").name, "my_column");

  const Quantity t = history_quantity("time");
  EXPECT_EQ(scaled_unit(t, 4.3e-5).unit, "µs");
  EXPECT_DOUBLE_EQ(scaled_unit(t, 4.3e-5).factor, 1e6);
  EXPECT_EQ(scaled_unit(t, 0.1).unit, "ms");
  EXPECT_EQ(scaled_unit(t, 250).unit, "s");  // no ks
  EXPECT_EQ(scaled_unit(field_quantity("displacement"), 2.5e-3).unit, "mm");
  EXPECT_EQ(scaled_unit(field_quantity("von_mises_stress"), 3.2e8).unit, "MPa");
  EXPECT_EQ(scaled_unit(field_quantity("temperature"), 593).unit, "K");
  EXPECT_EQ(scaled_unit(field_quantity("damage"), 1).unit, "");
  EXPECT_EQ(scaled_unit(field_quantity("damage"), 2e-4).unit, "10⁻⁶");
  EXPECT_DOUBLE_EQ(scaled_unit(field_quantity("damage"), 2e-4).factor, 1e6);
}

TEST(Units, TickLabelsCarryNoNeedlessDigits) {
  EXPECT_DOUBLE_EQ(nice_step(0, 0.12, 6), 0.02);
  EXPECT_DOUBLE_EQ(nice_step(0, 508, 6), 100);
  EXPECT_DOUBLE_EQ(nice_step(0, 43, 7), 5);
  EXPECT_EQ(tick_label(0.1 + 0.2, 0.1), "0.3");
  EXPECT_EQ(tick_label(500, 100), "500");
  EXPECT_EQ(tick_label(3 * 0.02, 0.02), "0.06");
  EXPECT_EQ(tick_label(-2, 1), "−2");
  EXPECT_EQ(tick_label(2 * 0.05, 0.05), "0.1");
  EXPECT_EQ(tick_label(3 * 0.05, 0.05), "0.15");
  EXPECT_EQ(tick_label(1e-17, 0.1), "0");
  EXPECT_EQ(short_number(4.30100000001e1), "43.01");
}

}  // namespace
}  // namespace horizon
