#pragma once
// Line plots of two columns of a history.csv as PNG (load against displacement, energy
// against time), with the peak of the curve marked, so that a run's curve needs no
// plotting package. Drawn with the renderer's raster and bitmap font (upper case only).
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

struct PlotOptions {
  std::string title;
  std::string x_label, y_label;
  int width = 900, height = 600;
};

// Where the curve peaks (largest y).
struct CurvePeak {
  double x = 0, y = 0;
  std::size_t index = 0;
};
CurvePeak curve_peak(const std::vector<double>& x, const std::vector<double>& y);

// Draws y against x as a polyline on axes with tick labels and marks the peak; writes the
// PNG atomically. Throws horizon::Error when there are fewer than two points.
void write_line_plot(const std::vector<double>& x, const std::vector<double>& y, const PlotOptions& options,
                     const std::string& png_path);

// `horizon plot`: columns x and y (times the scales) of history.csv (or <dir>/history.csv)
// to png (default: <dir>/<y with ':' as '_'>.png). Returns the peak and the file written.
struct PlotCommandResult {
  CurvePeak peak;
  std::string png;
};
PlotCommandResult plot_history(const std::string& history, const std::string& x_column, const std::string& y_column,
                               double x_scale, double y_scale, const std::string& png_path);

}  // namespace horizon
