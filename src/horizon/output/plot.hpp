#pragma once
// Line plots of history.csv columns (load against displacement, energies against time) as
// PNG, SVG or PDF, drawn with Cairo (output/canvas.hpp): axes titled with the quantity and
// its unit, nice tick labels, several curves with a legend, the peak of a single curve
// marked, so that a run's curve needs no plotting package.
#include <optional>
#include <string>
#include <vector>

namespace horizon {

// A CSV file with a header line: column names and rows of numbers.
struct CsvTable {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  // Index of a column; throws horizon::Error listing the columns when there is none.
  std::size_t column(const std::string& name) const;
};
CsvTable read_csv(const std::string& path);

// Where the curve peaks (largest y).
struct CurvePeak {
  double x = 0, y = 0;
  std::size_t index = 0;
};
CurvePeak curve_peak(const std::vector<double>& x, const std::vector<double>& y);

// Tick spacing 1, 2 or 5 times a power of ten giving about `count` intervals over
// [lo, hi] (Heckbert, "Nice numbers for graph labels", Graphics Gems, 1990).
double nice_step(double lo, double hi, int count);
// A tick value with the decimals the step needs and no more ("0.05", "500", "−2").
std::string tick_label(double v, double step);

struct Series {
  std::string label;  // the legend's entry (no legend for a single unlabelled curve)
  std::vector<double> x, y;
};

struct PlotOptions {
  std::string title;             // above the plot; may be empty
  std::string x_title, y_title;  // axis titles, units included
  std::string peak_x_unit, peak_y_unit;  // in the peak's note
  int width = 900, height = 560;  // pixels (PNG) or points (SVG, PDF)
  bool mark_peak = true;          // for a single curve
};

// Where the axes landed, so that tests can find a data point's pixel.
struct PlotFrame {
  double left = 0, top = 0, width = 0, height = 0;  // the plotting area
  double x0 = 0, x1 = 1, y0 = 0, y1 = 1;            // the axes' ranges
  double px(double x) const { return left + (x - x0) / (x1 - x0) * width; }
  double py(double y) const { return top + height - (y - y0) / (y1 - y0) * height; }
};

// Draws the series on shared axes and writes the picture atomically (the format from the
// extension: .png, .svg, .pdf). Throws horizon::Error when a series has fewer than two
// finite points or x and y differ in length.
PlotFrame write_line_plot(const std::vector<Series>& series, const PlotOptions& options, const std::string& path);

// `horizon plot`: column x against each column y of each history (a history.csv or a run
// directory holding one). Values are multiplied by the scales (e.g. -1 for the sign) and
// shown in a unit scaled to their range (mm, kN, µs) unless a label is given.
struct PlotRequest {
  std::vector<std::string> histories;
  std::string x_column;
  std::vector<std::string> y_columns;
  double x_scale = 1, y_scale = 1;
  std::string x_label, y_label;  // replace the titles derived from the columns
  std::string output;            // default: <first history's dir>/<first y, ':' as '_'>.png
  std::optional<std::string> title;  // default: the run's directory name (none for a sweep)
  int width = 900, height = 560;
};
struct PlotCommandResult {
  std::vector<std::string> labels;  // one per curve
  std::vector<CurvePeak> peaks;     // one per curve, in the request's (scaled) SI values
  std::string path;
  PlotFrame frame;
  double x_factor = 1, y_factor = 1;  // the scaled units' factors: frame value = SI value x factor
};
PlotCommandResult plot_history(const PlotRequest& request);

}  // namespace horizon
