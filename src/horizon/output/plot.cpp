#include "horizon/output/plot.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "horizon/core/error.hpp"
#include "horizon/output/canvas.hpp"
#include "horizon/output/units.hpp"

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
  bool found = false;
  for (std::size_t i = 0; i < y.size(); ++i)
    if (std::isfinite(y[i]) && (!found || y[i] > p.y)) p = {x[i], y[i], i}, found = true;
  return p;
}

double nice_step(double lo, double hi, int count) {
  // Heckbert's nicenum with rounding: the nice number nearest the raw step.
  const double raw = (hi - lo) / count;
  if (!(raw > 0) || !std::isfinite(raw)) return 1;
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  const double f = raw / p;
  return (f < 1.5 ? 1 : f < 3 ? 2 : f < 7 ? 5 : 10) * p;
}

std::string tick_label(double v, double step) {
  if (std::abs(v) < 1e-9 * step) return "0";
  const int decimals = std::max(0, -static_cast<int>(std::floor(std::log10(step) + 1e-9)));
  std::string s = std::abs(v) < 1e6 ? fmt::format("{:.{}f}", v, decimals) : fmt::format("{:.3g}", v);
  // 0.10 -> 0.1: a step of 0.05 needs two decimals, its even ticks only one.
  if (s.find('.') != std::string::npos && s.find('e') == std::string::npos) {
    while (s.back() == '0') s.pop_back();
    if (s.back() == '.') s.pop_back();
  }
  if (s[0] == '-') s = "−" + s.substr(1);  // the typographic minus sign, as wide as '+'
  return s;
}

namespace {

// Okabe & Ito, "Color universal design" (2008): told apart by colour-blind readers.
constexpr std::array<Rgb, 7> palette{{{0, 114, 178}, {213, 94, 0}, {0, 158, 115}, {204, 121, 167},
                                      {230, 159, 0}, {86, 180, 233}, {0, 0, 0}}};
constexpr Rgb ink{25, 25, 25}, grid{225, 225, 225}, peak_colour{200, 30, 30};

struct Range {
  double lo = INFINITY, hi = -INFINITY;
  void add(double v) {
    if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  }
};

// The axis from the data's range: ticks at whole steps from t0 to t1, the frame from lo
// to hi.
struct Axis {
  double lo, hi, step, t0, t1;
};
Axis make_axis(Range r, bool include_zero, int ticks) {
  if (include_zero) r.lo = std::min(r.lo, 0.0), r.hi = std::max(r.hi, 0.0);
  if (!(r.hi > r.lo)) {
    const double pad = r.lo == 0 ? 1 : std::abs(r.lo) * 0.1;
    r.lo -= pad, r.hi += pad;
  }
  const double step = nice_step(r.lo, r.hi, ticks);
  // Data past its last tick by less than a tenth of a step (a run that ends at 120.3 us
  // on a 20 us step) ends the frame at the data instead of adding a tick of empty axis.
  constexpr double slack = 0.1;
  const double t0 = std::floor(r.lo / step + slack) * step, t1 = std::ceil(r.hi / step - slack) * step;
  return {std::min(t0, r.lo), std::max(t1, r.hi), step, t0, t1};
}

}  // namespace

PlotFrame write_line_plot(const std::vector<Series>& series, const PlotOptions& o, const std::string& path) {
  if (series.empty()) throw Error("a plot needs at least one curve");
  Range xr, yr;
  for (const Series& s : series) {
    if (s.x.size() != s.y.size()) throw Error("curve '" + s.label + "': x and y differ in length");
    std::size_t finite = 0;
    for (std::size_t i = 0; i < s.x.size(); ++i)
      if (std::isfinite(s.x[i]) && std::isfinite(s.y[i])) xr.add(s.x[i]), yr.add(s.y[i]), ++finite;
    if (finite < 2) throw Error("a plot needs at least two points" + (s.label.empty() ? "" : " (curve '" + s.label + "')"));
  }
  // A peak inside the curve is marked; a largest value at either end (a curve that only
  // rises or only falls) is no peak.
  std::size_t first = 0, last = 0;
  if (series.size() == 1) {
    const Series& s = series[0];
    first = s.x.size(), last = 0;
    for (std::size_t i = 0; i < s.x.size(); ++i)
      if (std::isfinite(s.x[i]) && std::isfinite(s.y[i])) first = std::min(first, i), last = i;
  }
  const CurvePeak p = series.size() == 1 ? curve_peak(series[0].x, series[0].y) : CurvePeak{};
  const bool marked = series.size() == 1 && o.mark_peak && p.index != first && p.index != last;
  // Room above a marked peak for its label (a line of text is about 7 % of the frame).
  if (marked) yr.add(p.y + 0.1 * (std::max(yr.hi, 0.0) - std::min(yr.lo, 0.0)));
  Canvas canvas(path, o.width, o.height);
  cairo_t* cr = canvas.cr();
  const double u = std::min(o.width / 900.0, o.height / 560.0);  // text and lines grow with the picture
  const double tick_size = 15 * u, title_size = 17 * u;
  // x from the data (time starts at its first row), y from zero: forces and energies
  // read against their origin.
  const Axis ax = make_axis(xr, false, 7), ay = make_axis(yr, true, 6);

  double label_w = 0;
  for (double v = ay.t0; v <= ay.t1 + 0.5 * ay.step; v += ay.step)
    label_w = std::max(label_w, canvas.text_width(tick_label(v, ay.step), tick_size));
  PlotFrame f;
  f.left = 18 * u + title_size + 12 * u + label_w + 10 * u;
  f.top = (o.title.empty() ? 20 : 24 + title_size) * u;
  f.width = o.width - f.left - 28 * u;
  f.height = o.height - f.top - (tick_size + title_size + 40 * u);
  f.x0 = ax.lo, f.x1 = ax.hi, f.y0 = ay.lo, f.y1 = ay.hi;
  if (f.width < 20 || f.height < 20) throw Error(fmt::format("a plot of {}x{} is too small", o.width, o.height));

  // Grid and tick labels.
  cairo_set_line_width(cr, 1 * u);
  canvas.set_colour(grid);
  for (double v = ax.t0; v <= ax.t1 + 0.5 * ax.step; v += ax.step) {
    cairo_move_to(cr, f.px(v), f.top);
    cairo_line_to(cr, f.px(v), f.top + f.height);
  }
  for (double v = ay.t0; v <= ay.t1 + 0.5 * ay.step; v += ay.step) {
    cairo_move_to(cr, f.left, f.py(v));
    cairo_line_to(cr, f.left + f.width, f.py(v));
  }
  cairo_stroke(cr);
  canvas.set_colour(ink);
  for (double v = ax.t0; v <= ax.t1 + 0.5 * ax.step; v += ax.step)
    canvas.text(f.px(v), f.top + f.height + 8 * u, tick_label(v, ax.step), tick_size, 0.5, 0);
  for (double v = ay.t0; v <= ay.t1 + 0.5 * ay.step; v += ay.step)
    canvas.text(f.left - 8 * u, f.py(v), tick_label(v, ay.step), tick_size, 1, 0.5);
  cairo_set_line_width(cr, 1.5 * u);
  cairo_rectangle(cr, f.left, f.top, f.width, f.height);
  cairo_stroke(cr);

  // Titles: x below its ticks, y reading upwards at the left edge, the plot's above.
  canvas.text(f.left + f.width / 2, o.height - 14 * u, o.x_title, title_size, 0.5, 1);
  canvas.text(18 * u + 0.73 * title_size, f.top + f.height / 2, o.y_title, title_size, 0.5, 1, -M_PI / 2);
  if (!o.title.empty()) canvas.text(f.left, 14 * u, o.title, title_size, 0, 0);

  // The curves, clipped to the plotting area; a non-finite point breaks the line.
  cairo_save(cr);
  cairo_rectangle(cr, f.left, f.top, f.width, f.height);
  cairo_clip(cr);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  cairo_set_line_width(cr, 2.2 * u);
  for (std::size_t k = 0; k < series.size(); ++k) {
    const Series& s = series[k];
    bool pen = false;
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) {
        pen = false;
        continue;
      }
      if (pen) cairo_line_to(cr, f.px(s.x[i]), f.py(s.y[i]));
      else cairo_move_to(cr, f.px(s.x[i]), f.py(s.y[i]));
      pen = true;
    }
    canvas.set_colour(palette[k % palette.size()]);
    cairo_stroke(cr);
  }
  cairo_restore(cr);
  // A few points (a sweep's table) are measurements: each gets a dot, whole even on the frame.
  for (std::size_t k = 0; k < series.size(); ++k) {
    const Series& s = series[k];
    if (s.x.size() > 30) continue;
    for (std::size_t i = 0; i < s.x.size(); ++i)
      if (std::isfinite(s.x[i]) && std::isfinite(s.y[i])) {
        cairo_new_sub_path(cr);
        cairo_arc(cr, f.px(s.x[i]), f.py(s.y[i]), 3.5 * u, 0, 2 * M_PI);
      }
    canvas.set_colour(palette[k % palette.size()]);
    cairo_fill(cr);
  }

  std::string description = "x: " + o.x_title + "; y: " + o.y_title;
  if (marked) {
    const double cx = f.px(p.x), cy = f.py(p.y);
    canvas.set_colour(peak_colour);
    cairo_arc(cr, cx, cy, 5 * u, 0, 2 * M_PI);
    cairo_fill(cr);
    const std::string note = fmt::format("peak {}{} at {}{}", short_number(p.y), o.peak_y_unit.empty() ? "" : " " + o.peak_y_unit,
                                         short_number(p.x), o.peak_x_unit.empty() ? "" : " " + o.peak_x_unit);
    const double w = canvas.text_width(note, tick_size);
    const double tx = std::clamp(cx + 10 * u, f.left + 6 * u, f.left + f.width - w - 6 * u);
    // Above the dot, where the axis keeps room for it: below, the falling curve runs through it.
    const double ty = cy - 10 * u < f.top + tick_size + 4 * u ? cy + 10 * u + tick_size : cy - 10 * u;
    canvas.text(tx, ty, note, tick_size, 0, 1);
    description += "; " + note;
  }

  // The legend in the corner of the plotting area that the curves cross least.
  std::vector<const Series*> listed;
  for (const Series& s : series)
    if (!s.label.empty()) listed.push_back(&s);
  if (series.size() > 1 && !listed.empty()) {
    const double row = tick_size * 1.5, swatch = 28 * u;
    double w = 0;
    for (const Series* s : listed) w = std::max(w, canvas.text_width(s->label, tick_size));
    w += swatch + 24 * u;
    const double h = row * double(series.size()) + 10 * u;
    std::array<std::size_t, 4> hits{};
    const std::array<std::pair<double, double>, 4> corners{{{f.left + f.width - w - 8 * u, f.top + 8 * u},
                                                            {f.left + 8 * u, f.top + 8 * u},
                                                            {f.left + f.width - w - 8 * u, f.top + f.height - h - 8 * u},
                                                            {f.left + 8 * u, f.top + f.height - h - 8 * u}}};
    for (const Series& s : series)
      for (std::size_t i = 0; i < s.x.size(); ++i)
        for (std::size_t c = 0; c < 4; ++c) {
          const double x = f.px(s.x[i]), y = f.py(s.y[i]);
          hits[c] += x >= corners[c].first && x <= corners[c].first + w && y >= corners[c].second &&
                     y <= corners[c].second + h;
        }
    const std::size_t best = std::size_t(std::min_element(hits.begin(), hits.end()) - hits.begin());
    const auto [lx, ly] = corners[best];
    cairo_rectangle(cr, lx, ly, w, h);
    cairo_set_source_rgba(cr, 1, 1, 1, 0.9);
    cairo_fill_preserve(cr);
    canvas.set_colour({160, 160, 160});
    cairo_set_line_width(cr, 1 * u);
    cairo_stroke(cr);
    cairo_set_line_width(cr, 2.2 * u);
    for (std::size_t k = 0; k < series.size(); ++k) {
      const double y = ly + 5 * u + row * (double(k) + 0.5);
      canvas.set_colour(palette[k % palette.size()]);
      cairo_move_to(cr, lx + 8 * u, y);
      cairo_line_to(cr, lx + 8 * u + swatch, y);
      cairo_stroke(cr);
      canvas.set_colour(ink);
      canvas.text(lx + 16 * u + swatch, y, series[k].label, tick_size, 0, 0.5);
      description += "; curve: " + series[k].label;
    }
  }
  canvas.describe(o.title.empty() ? o.y_title + " against " + o.x_title : o.title, description);
  canvas.write();
  return f;
}

namespace {

// An axis: the columns' common quantity, the unit scaled to the values' range.
struct AxisUnit {
  std::string title, unit;
  double factor = 1;
};
AxisUnit axis_unit(const std::vector<std::string>& columns, double scale, double largest, const std::string& label) {
  std::vector<Quantity> q;
  for (const auto& c : columns) q.push_back(history_quantity(c));
  bool same_unit = true, same_name = true;
  for (const auto& k : q) same_unit &= k.unit == q[0].unit, same_name &= k.name == q[0].name;
  AxisUnit a;
  if (same_unit && std::abs(scale) == 1) {
    const ScaledUnit su = scaled_unit(q[0], largest);
    a.unit = su.unit, a.factor = su.factor;
  }
  std::string name = same_name ? q[0].name : (same_unit && !q[0].kind.empty() ? q[0].kind : "value");
  if (std::abs(scale) != 1) name += fmt::format(" × {:g}", scale);
  a.title = label.empty() ? axis_title(name, a.unit) : label;
  return a;
}

}  // namespace

PlotCommandResult plot_history(const PlotRequest& r) {
  namespace fs = std::filesystem;
  if (r.histories.empty()) throw Error("plot: no history given");
  if (r.y_columns.empty()) throw Error("plot: no column given for the vertical axis");
  struct Run {
    fs::path csv;
    CsvTable table;
  };
  std::vector<Run> runs;
  for (const auto& h : r.histories) {
    fs::path csv = h;
    if (fs::is_directory(csv)) csv /= "history.csv";
    runs.push_back({csv, read_csv(csv.string())});
  }
  PlotCommandResult result;
  std::vector<Series> series;
  double x_big = 0, y_big = 0;
  for (const Run& run : runs) {
    const std::size_t cx = run.table.column(r.x_column);
    for (const auto& yc : r.y_columns) {
      const std::size_t cy = run.table.column(yc);
      Series s;
      for (const auto& row : run.table.rows) {
        s.x.push_back(row[cx] * r.x_scale);
        s.y.push_back(row[cy] * r.y_scale);
        if (std::isfinite(s.x.back())) x_big = std::max(x_big, std::abs(s.x.back()));
        if (std::isfinite(s.y.back())) y_big = std::max(y_big, std::abs(s.y.back()));
      }
      // A sweep's curves are told apart by their run; several columns by their quantity.
      std::string name = run.csv.parent_path().filename().string();
      if (name.empty()) name = run.csv.string();
      const std::string what = history_quantity(yc).name;
      s.label = runs.size() > 1 && r.y_columns.size() > 1 ? name + ": " + what : runs.size() > 1 ? name : what;
      result.labels.push_back(s.label);
      result.peaks.push_back(curve_peak(s.x, s.y));
      series.push_back(std::move(s));
    }
  }
  const AxisUnit xu = axis_unit({r.x_column}, r.x_scale, x_big, r.x_label);
  const AxisUnit yu = axis_unit(r.y_columns, r.y_scale, y_big, r.y_label);
  for (Series& s : series) {
    for (double& v : s.x) v *= xu.factor;
    for (double& v : s.y) v *= yu.factor;
  }
  result.path = r.output;
  if (result.path.empty()) {
    std::string name = r.y_columns.front();
    std::replace(name.begin(), name.end(), ':', '_');
    result.path = (runs.front().csv.parent_path() / (name + ".png")).string();
  }
  PlotOptions o;
  o.x_title = xu.title;
  o.y_title = yu.title;
  o.peak_x_unit = xu.unit;
  o.peak_y_unit = yu.unit;
  o.width = r.width;
  o.height = r.height;
  if (r.title) o.title = *r.title;
  else if (runs.size() == 1) o.title = runs.front().csv.parent_path().filename().string();
  if (series.size() == 1) series.front().label.clear();
  result.frame = write_line_plot(series, o, result.path);
  result.x_factor = xu.factor;
  result.y_factor = yu.factor;
  return result;
}

}  // namespace horizon
