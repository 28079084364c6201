#pragma once
// A drawing surface for `horizon plot` and `horizon render`: Cairo (cairographics.org)
// does the lines, discs and anti-aliased text in DejaVu Sans; the file format (PNG, SVG
// or PDF) follows the output file's extension, and the file is written atomically.
#include <cairo.h>

#include <string>
#include <string_view>

#include "horizon/output/colormap.hpp"

namespace horizon {

enum class ImageFormat { png, svg, pdf };

// The format named by `path`'s extension (.png, .svg, .pdf; any case). Throws
// horizon::Error naming the path and the extensions understood.
ImageFormat image_format(const std::string& path);

class Canvas {
 public:
  // A white canvas of width x height (pixels for PNG, points for SVG and PDF).
  Canvas(const std::string& path, int width, int height);
  ~Canvas();
  Canvas(const Canvas&) = delete;
  Canvas& operator=(const Canvas&) = delete;

  cairo_t* cr() const { return cr_; }
  int width() const { return width_; }
  int height() const { return height_; }

  void set_colour(Rgb c) const;
  // Text in DejaVu Sans of `size` (pixels) anchored at (x, y): `h` 0 left, 0.5 centred,
  // 1 right; `v` 0 top, 0.5 middle, 1 baseline. `angle` in radians (-pi/2: reads upwards).
  void text(double x, double y, std::string_view s, double size, double h = 0, double v = 1,
            double angle = 0) const;
  double text_width(std::string_view s, double size) const;

  // Words that SVG readers and search can find: Cairo writes text as glyph outlines, so
  // the SVG gets these as its <title> and <desc> (ignored for PNG and PDF).
  void describe(std::string title, std::string description);

  // Finishes the surface and writes the file atomically (horizon::OutputError on failure).
  void write();

 private:
  std::string path_;
  ImageFormat format_;
  int width_, height_;
  std::string bytes_;  // what the SVG and PDF surfaces stream out
  std::string title_, description_;
  cairo_surface_t* surface_ = nullptr;
  cairo_t* cr_ = nullptr;
};

}  // namespace horizon
