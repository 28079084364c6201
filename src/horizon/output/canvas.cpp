#include "horizon/output/canvas.hpp"

#include <cairo-pdf.h>
#include <cairo-svg.h>

#include <algorithm>
#include <cctype>

#include "horizon/core/error.hpp"
#include "horizon/output/atomic_file.hpp"
#include "horizon/output/xml_tags.hpp"

namespace horizon {

namespace {

cairo_status_t append(void* closure, const unsigned char* data, unsigned int length) {
  static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
}

void check(cairo_status_t status, const std::string& path) {
  if (status != CAIRO_STATUS_SUCCESS)
    throw Error("cannot draw '" + path + "': " + cairo_status_to_string(status));
}

}  // namespace

ImageFormat image_format(const std::string& path) {
  const auto dot = path.find_last_of('.');
  std::string ext = dot == std::string::npos ? "" : path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (ext == "png") return ImageFormat::png;
  if (ext == "svg") return ImageFormat::svg;
  if (ext == "pdf") return ImageFormat::pdf;
  throw Error("cannot tell the picture format of '" + path + "': the file name should end in .png, .svg or .pdf");
}

Canvas::Canvas(const std::string& path, int width, int height)
    : path_(path), format_(image_format(path)), width_(width), height_(height) {
  if (width <= 0 || height <= 0 || width > 32767 || height > 32767)
    throw Error("picture size " + std::to_string(width) + "x" + std::to_string(height) + " is outside 1..32767");
  switch (format_) {
    // RGB24: an opaque picture, written as a PNG without an alpha channel.
    case ImageFormat::png: surface_ = cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height); break;
    case ImageFormat::svg: surface_ = cairo_svg_surface_create_for_stream(append, &bytes_, width, height); break;
    case ImageFormat::pdf: surface_ = cairo_pdf_surface_create_for_stream(append, &bytes_, width, height); break;
  }
  cr_ = cairo_create(surface_);
  const cairo_status_t status = cairo_status(cr_);
  if (status != CAIRO_STATUS_SUCCESS) {
    cairo_destroy(cr_);
    cairo_surface_destroy(surface_);
    throw Error("cannot draw '" + path + "': " + cairo_status_to_string(status));
  }
  cairo_select_font_face(cr_, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  set_colour({255, 255, 255});
  cairo_paint(cr_);
}

Canvas::~Canvas() {
  cairo_destroy(cr_);
  cairo_surface_destroy(surface_);
}

void Canvas::set_colour(Rgb c) const { cairo_set_source_rgb(cr_, c.r / 255.0, c.g / 255.0, c.b / 255.0); }

void Canvas::text(double x, double y, std::string_view s, double size, double h, double v, double angle) const {
  const std::string str(s);
  cairo_set_font_size(cr_, size);
  cairo_text_extents_t te;
  cairo_text_extents(cr_, str.c_str(), &te);
  // The vertical anchor uses DejaVu Sans' cap height (0.729 em), not the string's ink,
  // so that labels in a row share one baseline whatever their letters.
  const double cap = 0.729 * size;
  cairo_save(cr_);
  cairo_translate(cr_, x, y);
  cairo_rotate(cr_, angle);
  cairo_move_to(cr_, -h * te.x_advance, (1 - v) * cap);
  cairo_show_text(cr_, str.c_str());
  cairo_restore(cr_);
}

double Canvas::text_width(std::string_view s, double size) const {
  const std::string str(s);
  cairo_set_font_size(cr_, size);
  cairo_text_extents_t te;
  cairo_text_extents(cr_, str.c_str(), &te);
  return te.x_advance;
}

void Canvas::describe(std::string title, std::string description) {
  title_ = std::move(title);
  description_ = std::move(description);
}

void Canvas::write() {
  check(cairo_status(cr_), path_);
  if (format_ == ImageFormat::png) {
    cairo_surface_flush(surface_);
    check(cairo_surface_write_to_png_stream(surface_, append, &bytes_), path_);
  } else {
    cairo_surface_finish(surface_);
    check(cairo_surface_status(surface_), path_);
  }
  if (format_ == ImageFormat::svg && !(title_.empty() && description_.empty())) {
    // Right after the root element's opening tag, where SVG expects <title> and <desc>.
    const auto root = bytes_.find("<svg");
    const auto end = root == std::string::npos ? root : bytes_.find('>', root);
    if (end != std::string::npos)
      bytes_.insert(end + 1, "\n<title>" + xml_escape(title_) + "</title>\n<desc>" + xml_escape(description_) +
                                 "</desc>");
  }
  write_file_atomic(path_, bytes_);
}

}  // namespace horizon
