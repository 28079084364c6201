#include "horizon/output/render.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "horizon/core/error.hpp"
#include "horizon/output/canvas.hpp"
#include "horizon/output/colormap.hpp"
#include "horizon/output/plot.hpp"
#include "horizon/output/units.hpp"

namespace horizon {

namespace {

constexpr Rgb ink{25, 25, 25};
constexpr Rgb not_finite{160, 160, 160};  // grey, outside viridis, so NaNs stand out

// One value per point for the requested field name (see RenderOptions::field), and what
// it measures.
std::vector<double> field_values(const Frame& frame, const std::string& name, Quantity& q) {
  const size_t n = frame.points.size();
  const FrameField* f = frame.field(name);
  int component = -1;  // -1: the field itself (magnitude when it is a vector)
  if (!f && name.size() > 2 && name[name.size() - 2] == '_') {
    const char axis = name.back();
    const FrameField* base = frame.field(name.substr(0, name.size() - 2));
    if (base && base->components == 3 && axis >= 'x' && axis <= 'z') {
      f = base;
      component = axis - 'x';
    }
  }
  if (!f) {
    std::string available;
    for (const FrameField& g : frame.fields)
      available += (available.empty() ? "" : ", ") + g.name +
                   (g.components == 3 ? " (or " + g.name + "_x/_y/_z)" : "");
    throw Error("frame has no field '" + name + "'; available fields: " +
                (available.empty() ? "none" : available));
  }
  q = field_quantity(f->name);
  if (f->components == 3) q.name += component >= 0 ? std::string(" ") + char('x' + component) : " magnitude";
  std::vector<double> v(n);
  for (size_t i = 0; i < n; ++i) {
    const double* d = f->data.data() + i * size_t(f->components);
    if (f->components == 1) v[i] = d[0];
    else if (component >= 0) v[i] = d[component];
    else v[i] = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  }
  return v;
}

// The particle spacing: the median nearest-neighbour distance over an evenly spread
// sample of at most 64 particles, which is exact on a lattice and cheap on millions.
double estimate_spacing(const std::vector<Vec3>& points) {
  const size_t n = points.size();
  if (n < 2) return 1.0;
  const size_t samples = std::min<size_t>(n, 64);
  std::vector<double> nearest;
  for (size_t s = 0; s < samples; ++s) {
    const Vec3& p = points[s * n / samples];
    double best = INFINITY;
    for (const Vec3& q : points) {
      const double d2 = norm2(q - p);
      if (d2 > 0 && d2 < best) best = d2;
    }
    if (std::isfinite(best)) nearest.push_back(std::sqrt(best));
  }
  if (nearest.empty()) return 1.0;  // all particles on one spot
  std::nth_element(nearest.begin(), nearest.begin() + nearest.size() / 2, nearest.end());
  return nearest[nearest.size() / 2];
}

int axis_index(char a, const std::string& what) {
  if (a < 'x' || a > 'z') throw Error(fmt::format("{}: the axis should be x, y or z, not '{}'", what, a));
  return a - 'x';
}

// "z=0.001" -> (2, 0.001).
std::pair<int, double> parse_slice(const std::string& s) {
  const auto eq = s.find('=');
  char* end = nullptr;
  const double at = eq == std::string::npos ? NAN : std::strtod(s.c_str() + eq + 1, &end);
  if (eq != 1 || !end || *end != '\0' || !std::isfinite(at) || eq + 1 == s.size())
    throw Error("slice '" + s + "': expected AXIS=POSITION, such as z=0.001");
  return {axis_index(s[0], "slice '" + s + "'"), at};
}

// "t = 43.01 µs": the time in the unit that gives it one to three digits before the point.
std::string time_text(double t) {
  const ScaledUnit u = scaled_unit(Quantity{"time", "time", "s"}, std::abs(t));
  return "t = " + short_number(t * u.factor) + " " + u.unit;
}

// A round length (1, 2 or 5 times a power of ten metres) near a fifth of the picture.
double scale_bar_length(double metres) {
  const double target = metres / 5;
  const double p = std::pow(10.0, std::floor(std::log10(target)));
  double best = p;
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (std::abs(std::log(m * p / target)) < std::abs(std::log(best / target))) best = m * p;
  return best;
}

}  // namespace

RenderResult render_png(const Frame& frame, const RenderOptions& options, const std::string& path) {
  if (options.width < 64 || options.width > 20000)
    throw Error(fmt::format("render width {} is outside 64..20000 pixels", options.width));
  image_format(path);  // a wrong extension fails before any work
  Quantity q;
  const std::vector<double> values = field_values(frame, options.field, q);
  const size_t n = frame.points.size();

  // Which particles, and the picture's two axes: a 2-D body in x-y; a 3-D body sliced
  // across, or projected along, one axis.
  int normal = 2;
  std::vector<size_t> order;
  const double spacing = estimate_spacing(frame.points);
  if (frame.dimension != 3 && !options.slice.empty())
    throw Error(fmt::format("slice {}: the frame is {}-D; slices are for 3-D bodies", options.slice, frame.dimension));
  if (frame.dimension == 3 && !options.slice.empty()) {
    const auto [axis, at] = parse_slice(options.slice);
    normal = axis;
    // The layer of particles nearest the plane (the lower one when the plane lies midway
    // between two layers): one layer, never two drawn over each other.
    double lo = INFINITY, hi = -INFINITY, nearest = INFINITY;
    for (size_t i = 0; i < n; ++i) {
      const double c = frame.points[i][axis];
      lo = std::min(lo, c), hi = std::max(hi, c);
      const double d = std::abs(c - at), best = std::abs(nearest - at);
      if (d < best * (1 - 1e-9) || (d <= best * (1 + 1e-9) && c < nearest)) nearest = c;
    }
    if (std::abs(nearest - at) <= 0.5 * spacing * (1 + 1e-9))
      for (size_t i = 0; i < n; ++i)
        if (std::abs(frame.points[i][axis] - nearest) < 0.5 * spacing) order.push_back(i);
    if (order.empty())
      throw Error(fmt::format("slice {} holds no particle: the body spans {} = {:.6g} to {:.6g}", options.slice,
                              char('x' + axis), lo, hi));
  } else {
    if (frame.dimension == 3) normal = axis_index(options.view, "view");
    order.resize(n);
    std::iota(order.begin(), order.end(), size_t(0));
  }
  const int ha = normal == 0 ? 1 : 0, va = normal == 2 ? 1 : 2;  // the picture's horizontal and vertical axes

  std::vector<Vec3> at = frame.points;
  const FrameField* u = frame.field("displacement");
  if (options.deformed && u && u->components == 3)
    for (size_t i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c) at[i][c] += options.displacement_scale * u->data[3 * i + c];
  // A particle whose position went non-finite is not drawn rather than spoiling the frame.
  std::erase_if(order, [&](size_t i) { return !(std::isfinite(at[i][ha]) && std::isfinite(at[i][va])); });
  if (normal != 2 || frame.dimension == 3)
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return at[a][normal] < at[b][normal]; });

  // Colour range: the finite values drawn, unless the caller fixed it.
  RenderResult result;
  double lo = INFINITY, hi = -INFINITY;
  for (size_t i : order)
    if (std::isfinite(values[i])) lo = std::min(lo, values[i]), hi = std::max(hi, values[i]);
  if (!std::isfinite(lo)) lo = 0, hi = 1;
  lo = options.vmin.value_or(lo);
  hi = options.vmax.value_or(hi);
  if (!(hi >= lo)) throw Error(fmt::format("colour range {:g} to {:g} is empty", lo, hi));
  const double range = hi > lo ? hi - lo : 1.0;  // a constant field shows the bottom colour
  result.lo = lo, result.hi = hi;
  const ScaledUnit su = scaled_unit(q, std::max(std::abs(lo), std::abs(hi)));
  result.field_title = axis_title(q.name, su.unit);

  double xmin = INFINITY, xmax = -INFINITY, ymin = INFINITY, ymax = -INFINITY;
  for (size_t i : order)
    xmin = std::min(xmin, at[i][ha]), xmax = std::max(xmax, at[i][ha]), ymin = std::min(ymin, at[i][va]),
    ymax = std::max(ymax, at[i][va]);
  if (order.empty()) xmin = xmax = ymin = ymax = 0;

  // Layout, top to bottom: the time and the scale bar, the body, the colour bar with its
  // ticks and title. Text and lines grow with the width.
  const int W = options.width;
  const double k = std::max(0.5, W / 1200.0);
  const double text = 20 * k, small = 17 * k, pad = 14 * k;
  const double header = pad + text + pad;
  const double plot_w = W - 2 * pad;
  // Extents include half a particle on each side so that edge particles show whole.
  const double ext_x = xmax - xmin + spacing, ext_y = ymax - ymin + spacing;
  double scale = plot_w / ext_x;
  // A tall body is drawn narrower than the picture, so that the text keeps its size
  // beside it when the picture is shown at a page's width.
  const double plot_h = std::clamp(std::round(ext_y * scale), 40 * k, 1.25 * plot_w);
  scale = std::min(scale, plot_h / ext_y);
  const double x0 = pad + (plot_w - ext_x * scale) / 2, y0 = header + (plot_h - ext_y * scale) / 2;
  const double bar_top = header + plot_h + pad + 4 * k, bar_h = 18 * k;
  const int H = int(std::ceil(bar_top + bar_h + 8 * k + small + 10 * k + text + pad));
  Canvas canvas(path, W, H);
  cairo_t* cr = canvas.cr();

  // Particles: discs through the corners of each particle's cell (diameter √2 spacing),
  // so that a lattice shows as a closed surface and an opening crack shows as a gap once
  // it is 0.4 spacing wide. Below 2.5 pixels a disc is drawn as its pixel-aligned square:
  // the same picture, and the fast path for bodies of millions of particles.
  const double d = std::sqrt(2.0) * spacing * scale;
  const bool squares = d < 2.5;
  cairo_save(cr);  // discs of edge particles stop at the frame's edge
  cairo_rectangle(cr, pad, header, plot_w, plot_h);
  cairo_clip(cr);
  // Discs under 12 pixels are drawn without anti-aliasing: their neighbours cover the
  // jagged rims, and a varying field's PNG halves (edge-on impact: 270 kB against 565 kB).
  if (d < 12) cairo_set_antialias(cr, CAIRO_ANTIALIAS_NONE);
  const double side = std::max(1.0, spacing * scale);
  // Consecutive particles of one colour go into one path, filled once: a uniform region
  // is one fill instead of thousands (docs/benchmarks.md, "Pictures").
  bool have = false;
  Rgb last;
  for (size_t i : order) {
    // Screen y grows downwards; the body's y grows upwards.
    const double cx = x0 + (at[i][ha] - xmin + spacing / 2) * scale;
    const double cy = y0 + (ymax - at[i][va] + spacing / 2) * scale;
    const Rgb c = std::isfinite(values[i]) ? viridis((values[i] - lo) / range) : not_finite;
    if (have && !(c == last)) canvas.set_colour(last), cairo_fill(cr);
    have = true, last = c;
    if (squares) {
      const double l = std::floor(cx - side / 2), t = std::floor(cy - side / 2);
      cairo_rectangle(cr, l, t, std::max(1.0, std::ceil(cx + side / 2) - l), std::max(1.0, std::ceil(cy + side / 2) - t));
    } else {
      cairo_new_sub_path(cr);
      cairo_arc(cr, cx, cy, d / 2, 0, 2 * M_PI);
    }
  }
  if (have) canvas.set_colour(last), cairo_fill(cr);
  cairo_restore(cr);
  result.drawn = order.size();

  // Header: the title and time at the left, the scale bar at the right.
  canvas.set_colour(ink);
  std::string head = options.title.empty() ? "" : options.title + "   ";
  head += time_text(frame.time) + "   step " + std::to_string(frame.step);
  if (frame.dimension == 3 && options.slice.empty()) {
    head += fmt::format("   seen along {}", char('x' + normal));
  } else if (frame.dimension == 3) {
    const double at = parse_slice(options.slice).second;
    const ScaledUnit su_at = scaled_unit(Quantity{"length", "length", "m"}, std::abs(at));
    head += fmt::format("   slice {} = {} {}", char('x' + normal), short_number(at * su_at.factor), su_at.unit);
  }
  canvas.text(pad, pad, head, text, 0, 0);
  const double bar_m = scale_bar_length(ext_x);
  const ScaledUnit lu = scaled_unit(Quantity{"length", "length", "m"}, bar_m);
  const double bar_px = bar_m * scale;
  const std::string bar_label = short_number(bar_m * lu.factor) + " " + lu.unit;
  const double label_w = canvas.text_width(bar_label, text);
  const double sx1 = W - pad, sx0 = sx1 - bar_px, sy = pad + 0.5 * text;
  cairo_set_line_width(cr, 3 * k);
  cairo_move_to(cr, sx0, sy);
  cairo_line_to(cr, sx1, sy);
  cairo_stroke(cr);
  cairo_set_line_width(cr, 2 * k);
  for (double x : {sx0, sx1}) cairo_move_to(cr, x, sy - 6 * k), cairo_line_to(cr, x, sy + 6 * k);
  cairo_stroke(cr);
  canvas.text(sx0 - 10 * k - label_w, pad, bar_label, text, 0, 0);

  // The colour bar: its ends at the field's range with the exact values, round ticks between.
  const double bl = W * 0.2, br = W * 0.8;
  cairo_pattern_t* gradient = cairo_pattern_create_linear(bl, 0, br, 0);
  for (int s = 0; s <= 32; ++s) {
    const Rgb c = viridis(s / 32.0);
    cairo_pattern_add_color_stop_rgb(gradient, s / 32.0, c.r / 255.0, c.g / 255.0, c.b / 255.0);
  }
  cairo_rectangle(cr, bl, bar_top, br - bl, bar_h);
  cairo_set_source(cr, gradient);
  cairo_fill(cr);
  cairo_pattern_destroy(gradient);
  result.bar_left = bl, result.bar_right = br, result.bar_top = bar_top, result.bar_bottom = bar_top + bar_h;
  canvas.set_colour(ink);
  cairo_set_line_width(cr, 1 * k);
  cairo_rectangle(cr, bl, bar_top, br - bl, bar_h);
  cairo_stroke(cr);
  const double slo = lo * su.factor, shi = hi * su.factor;
  const double tick_y = bar_top + bar_h + 6 * k;
  const std::string lo_text = short_number(slo, 3), hi_text = short_number(shi, 3);
  auto tick = [&](double x, const std::string& label) {
    cairo_move_to(cr, x, bar_top + bar_h);
    cairo_line_to(cr, x, bar_top + bar_h + 4 * k);
    cairo_stroke(cr);
    canvas.text(x, tick_y, label, small, 0.5, 0);
  };
  tick(bl, lo_text);
  if (hi > lo) {
    tick(br, hi_text);
    const double step = nice_step(slo, shi, 5);
    const double room = std::max(canvas.text_width(lo_text, small), canvas.text_width(hi_text, small)) / 2 + 24 * k;
    for (double v = std::ceil(slo / step) * step; v < shi; v += step) {
      const double x = bl + (v - slo) / (shi - slo) * (br - bl);
      const std::string label = tick_label(v, step);
      if (x - bl > room + canvas.text_width(label, small) / 2 && br - x > room + canvas.text_width(label, small) / 2)
        tick(x, label);
    }
  }
  canvas.text(W / 2.0, tick_y + small + 10 * k, result.field_title, text, 0.5, 0);
  canvas.describe(result.field_title + ", " + time_text(frame.time),
                  fmt::format("colour: {} from {} to {}; scale bar {}", result.field_title, lo_text, hi_text, bar_label));
  canvas.write();
  return result;
}

}  // namespace horizon
