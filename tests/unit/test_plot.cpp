// `horizon plot` (output/plot.hpp): history.csv columns to a PNG line plot with its peak.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "horizon/core/error.hpp"
#include "horizon/output/plot.hpp"

namespace horizon {
namespace {

TEST(Plot, ReadsHistoryAndFindsThePeak) {
  const auto dir = std::filesystem::temp_directory_path() / "horizon_test_plot";
  std::filesystem::create_directories(dir);
  {
    std::ofstream out(dir / "history.csv");
    out << "time,step,load:displacement_uy,load:displacement_fy\n";
    for (int k = 0; k <= 20; ++k) {
      const double u = -1e-6 * k, f = k <= 12 ? -40.0 * k : -40.0 * 12 + 55.0 * (k - 12);
      out << k << "," << k << "," << u << "," << f << "\n";
    }
  }
  const PlotCommandResult r =
      plot_history(dir.string(), "load:displacement_uy", "load:displacement_fy", -1e3, -1, "");
  EXPECT_DOUBLE_EQ(r.peak.y, 480.0);
  EXPECT_NEAR(r.peak.x, 0.012, 1e-12);
  EXPECT_EQ(r.peak.index, 12u);
  EXPECT_EQ(r.png, (dir / "load_displacement_fy.png").string());
  EXPECT_GT(std::filesystem::file_size(r.png), 1000u);
  try {
    plot_history(dir.string(), "load:displacement_ux", "load:displacement_fy", 1, 1, "");
    ADD_FAILURE() << "no error for a missing column";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("the columns are: time, step"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace horizon
