#include "horizon/output/plot.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "horizon/core/error.hpp"
#include "horizon/output/bitmap_font.hpp"
#include "horizon/output/image.hpp"

namespace horizon {

std::size_t CsvTable::column(const std::string& name) const {
  for (std::size_t c = 0; c < columns.size(); ++c)
    if (columns[c] == name) return c;
  std::string list;
  for (const auto& c : columns) list += (list.empty() ? "" : ", ") + c;
  throw Error("no column '" + name + "'; the columns are: " + list);
}

CsvTable read_csv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Error("cannot open '" + path + "'");
  CsvTable t;
  std::string line;
  if (!std::getline(in, line)) throw Error("'" + path + "' is empty");
  std::stringstream header(line);
  for (std::string cell; std::getline(header, cell, ',');) t.columns.push_back(cell);
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::vector<double> row;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) row.push_back(std::strtod(cell.c_str(), nullptr));
    row.resize(t.columns.size(), std::nan(""));
    t.rows.push_back(std::move(row));
  }
  return t;
}

CurvePeak curve_peak(const std::vector<double>& x, const std::vector<double>& y) {
  CurvePeak p;
  for (std::size_t i = 0; i < y.size(); ++i)
    if (i == 0 || y[i] > p.y) p = {x[i], y[i], i};
  return p;
}

namespace {

// Tick spacing 1, 2 or 5 times a power of ten giving about `count` ticks over [lo, hi].
double nice_step(double lo, double hi, int count) {
  const double raw = (hi - lo) / count;
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0})
    if (m * p >= raw) return m * p;
  return 10 * p;
}

void line(Image& img, int x0, int y0, int x1, int y1, Rgb c, int thick) {
  // Bresenham, with a square pen.
  const int dx = std::abs(x1 - x0), dy = -std::abs(y1 - y0);
  const int sx = x0 < x1 ? 1 : -1, sy = y0 < y1 ? 1 : -1;
  int err = dx + dy;
  while (true) {
    img.fill_rect(x0 - thick / 2, y0 - thick / 2, x0 - thick / 2 + thick, y0 - thick / 2 + thick, c);
    if (x0 == x1 && y0 == y1) break;
    const int e2 = 2 * err;
    if (e2 >= dy) {
      err += dy;
      x0 += sx;
    }
    if (e2 <= dx) {
      err += dx;
      y0 += sy;
    }
  }
}

std::string tick_label(double v, double step) {
  if (v == 0) return "0";
  const double a = std::max(std::abs(v), step);
  if (a >= 1e-3 && a < 1e5) {
    const int decimals = std::max(0, -static_cast<int>(std::floor(std::log10(step))));
    return fmt::format("{:.{}f}", v, decimals);
  }
  return fmt::format("{:.3g}", v);
}

}  // namespace

void write_line_plot(const std::vector<double>& x, const std::vector<double>& y, const PlotOptions& o,
                     const std::string& png_path) {
  if (x.size() < 2 || x.size() != y.size()) throw Error("a plot needs at least two points");
  const Rgb white{255, 255, 255}, black{0, 0, 0}, grey{200, 200, 200}, blue{31, 90, 170}, red{200, 40, 40};
  Image img(o.width, o.height, white);
  const int scale = 2;
  const int left = 110, right = 30, top = 60, bottom = 80;
  const int W = o.width - left - right, H = o.height - top - bottom;
  auto [xmin_it, xmax_it] = std::minmax_element(x.begin(), x.end());
  auto [ymin_it, ymax_it] = std::minmax_element(y.begin(), y.end());
  double x0 = *xmin_it, x1 = *xmax_it, y0 = std::min(0.0, *ymin_it), y1 = *ymax_it;
  if (x1 <= x0) x1 = x0 + 1;
  if (y1 <= y0) y1 = y0 + 1;
  const double xs = nice_step(x0, x1, 6), ys = nice_step(y0, y1, 6);
  x0 = std::floor(x0 / xs) * xs;
  x1 = std::ceil(x1 / xs) * xs;
  y0 = std::floor(y0 / ys) * ys;
  y1 = std::ceil(y1 / ys) * ys;
  auto px = [&](double v) { return left + static_cast<int>(std::lround((v - x0) / (x1 - x0) * W)); };
  auto py = [&](double v) { return top + H - static_cast<int>(std::lround((v - y0) / (y1 - y0) * H)); };

  for (double v = x0; v <= x1 + 0.5 * xs; v += xs) {
    line(img, px(v), top, px(v), top + H, grey, 1);
    const std::string s = tick_label(v, xs);
    draw_text(img, px(v) - text_width(s, scale) / 2, top + H + 10, s, scale, black);
  }
  for (double v = y0; v <= y1 + 0.5 * ys; v += ys) {
    line(img, left, py(v), left + W, py(v), grey, 1);
    const std::string s = tick_label(v, ys);
    draw_text(img, left - 10 - text_width(s, scale), py(v) - glyph_height * scale / 2, s, scale, black);
  }
  line(img, left, top, left, top + H, black, 2);
  line(img, left, top + H, left + W, top + H, black, 2);
  for (std::size_t i = 1; i < x.size(); ++i)
    if (std::isfinite(x[i - 1] + y[i - 1] + x[i] + y[i])) line(img, px(x[i - 1]), py(y[i - 1]), px(x[i]), py(y[i]), blue, 3);
  const CurvePeak p = curve_peak(x, y);
  img.fill_rect(px(p.x) - 5, py(p.y) - 5, px(p.x) + 6, py(p.y) + 6, red);
  const std::string peak = fmt::format("PEAK {:.4g} AT {:.4g}", p.y, p.x);
  draw_text(img, std::min(px(p.x) + 10, left + W - text_width(peak, scale)), std::max(top + 4, py(p.y) - 20), peak,
            scale, red);
  draw_text(img, left, 6, o.title, scale, black);
  draw_text(img, left + W / 2 - text_width(o.x_label, scale) / 2, o.height - 35, o.x_label, scale, black);
  draw_text(img, 10, top - 26, o.y_label, scale, black);
  write_png(img, png_path);
}

PlotCommandResult plot_history(const std::string& history, const std::string& x_column, const std::string& y_column,
                               double x_scale, double y_scale, const std::string& png_path) {
  namespace fs = std::filesystem;
  fs::path csv = history;
  if (fs::is_directory(csv)) csv /= "history.csv";
  const CsvTable t = read_csv(csv.string());
  const std::size_t cx = t.column(x_column), cy = t.column(y_column);
  std::vector<double> x, y;
  for (const auto& row : t.rows) {
    x.push_back(row[cx] * x_scale);
    y.push_back(row[cy] * y_scale);
  }
  PlotCommandResult r;
  r.png = png_path;
  if (r.png.empty()) {
    std::string name = y_column;
    std::replace(name.begin(), name.end(), ':', '_');
    r.png = (csv.parent_path() / (name + ".png")).string();
  }
  PlotOptions o;
  o.title = csv.parent_path().filename().string();
  o.x_label = x_scale == 1 ? x_column : fmt::format("{} X {:g}", x_column, x_scale);
  o.y_label = y_scale == 1 ? y_column : fmt::format("{} X {:g}", y_column, y_scale);
  write_line_plot(x, y, o, r.png);
  r.peak = curve_peak(x, y);
  return r;
}

}  // namespace horizon
