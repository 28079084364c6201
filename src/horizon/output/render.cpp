#include "horizon/output/render.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "horizon/core/error.hpp"
#include "horizon/output/bitmap_font.hpp"
#include "horizon/output/colormap.hpp"
#include "horizon/output/image.hpp"

namespace horizon {

namespace {

constexpr Rgb white{255, 255, 255};
constexpr Rgb ink{30, 30, 30};
constexpr Rgb not_finite{160, 160, 160};  // grey, outside viridis, so NaNs stand out

// One value per point for the requested field name (see RenderOptions::field).
std::vector<double> field_values(const Frame& frame, const std::string& name) {
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

std::string number(double v) { return fmt::format("{:.4g}", v); }

}  // namespace

void render_png(const Frame& frame, const RenderOptions& options, const std::string& png_path) {
  if (options.width < 64 || options.width > 20000)
    throw Error(fmt::format("render width {} is outside 64..20000 pixels", options.width));
  const std::vector<double> values = field_values(frame, options.field);
  const size_t n = frame.points.size();

  std::vector<Vec3> at = frame.points;
  const FrameField* u = frame.field("displacement");
  if (options.deformed && u && u->components == 3)
    for (size_t i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c) at[i][c] += options.displacement_scale * u->data[3 * i + c];

  // Colour range: the finite values unless the caller fixed it.
  double lo = INFINITY, hi = -INFINITY;
  for (double v : values)
    if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  if (!std::isfinite(lo)) lo = 0, hi = 1;
  lo = options.vmin.value_or(lo);
  hi = options.vmax.value_or(hi);
  const double range = hi > lo ? hi - lo : 1.0;  // a constant field shows the bottom colour

  // Layout, top to bottom: title, plot, colour bar, its labels. Everything scales with
  // the width so that text stays legible on large pictures.
  const int W = options.width;
  const int s = std::max(1, W / 400);
  const int pad = 8 * s, text_h = glyph_height * s, bar_h = 8 * s;
  const int plot_w = W - 2 * pad;
  const double spacing = estimate_spacing(frame.points);
  // A particle whose position went non-finite is not drawn rather than spoiling the frame.
  auto drawable = [&](size_t i) { return std::isfinite(at[i].x) && std::isfinite(at[i].y); };
  double xmin = INFINITY, xmax = -INFINITY, ymin = INFINITY, ymax = -INFINITY;
  for (size_t i = 0; i < n; ++i)
    if (drawable(i))
      xmin = std::min(xmin, at[i].x), xmax = std::max(xmax, at[i].x),
      ymin = std::min(ymin, at[i].y), ymax = std::max(ymax, at[i].y);
  if (!std::isfinite(xmin)) xmin = xmax = ymin = ymax = 0;
  // Extents include half a particle on each side so that edge particles show whole.
  const double ext_x = xmax - xmin + spacing, ext_y = ymax - ymin + spacing;
  double scale = plot_w / ext_x;
  const int plot_h = std::clamp(int(std::lround(ext_y * scale)), 20 * s, 2 * plot_w);
  scale = std::min(scale, plot_h / ext_y);
  const int plot_top = pad + text_h + pad;
  const double x0 = pad + (plot_w - ext_x * scale) / 2;
  const double y0 = plot_top + (plot_h - ext_y * scale) / 2;
  const int bar_top = plot_top + plot_h + pad;
  const int labels_top = bar_top + bar_h + 2 * s;
  Image image(W, labels_top + text_h + pad, white);

  std::vector<size_t> order(n);
  std::iota(order.begin(), order.end(), size_t(0));
  if (frame.dimension == 3)
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return at[a].z < at[b].z; });
  const double size = std::max(1.0, spacing * scale);
  for (size_t i : order) {
    if (!drawable(i)) continue;
    // Screen y grows downwards; the body's y grows upwards.
    const double cx = x0 + (at[i].x - xmin + spacing / 2) * scale;
    const double cy = y0 + (ymax - at[i].y + spacing / 2) * scale;
    // Rounding outwards closes the sub-pixel gaps that a stretched lattice would show as
    // stripes; a real crack opening still shows once it is wider than a pixel.
    const int left = int(std::floor(cx - size / 2)), top = int(std::floor(cy - size / 2));
    const int right = std::max(left + 1, int(std::ceil(cx + size / 2)));
    const int bottom = std::max(top + 1, int(std::ceil(cy + size / 2)));
    const Rgb c = std::isfinite(values[i]) ? viridis((values[i] - lo) / range) : not_finite;
    image.fill_rect(left, top, right, bottom, c);
  }

  const int bar_w = W - 2 * pad;
  for (int x = 0; x < bar_w; ++x)
    image.fill_rect(pad + x, bar_top, pad + x + 1, bar_top + bar_h,
                    viridis(bar_w > 1 ? double(x) / (bar_w - 1) : 1.0));
  const std::string lo_text = number(lo), hi_text = number(hi);
  draw_text(image, pad, labels_top, lo_text, s, ink);
  draw_text(image, W - pad - text_width(hi_text, s), labels_top, hi_text, s, ink);
  draw_text(image, (W - text_width(options.field, s)) / 2, labels_top, options.field, s, ink);

  std::string title = options.title.empty() ? "" : options.title + "   ";
  title += options.field + "   t = " + number(frame.time) + " s   step " +
           std::to_string(frame.step);
  draw_text(image, pad, pad, title, s, ink);
  write_png(image, png_path);
}

}  // namespace horizon
