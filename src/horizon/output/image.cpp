#include "horizon/output/image.hpp"

#include <png.h>

#include <algorithm>

#include "horizon/core/error.hpp"
#include "horizon/output/atomic_file.hpp"

namespace horizon {

Image::Image(int width, int height, Rgb background)
    : width_(width), height_(height), pixels_(size_t(width) * size_t(height) * 3) {
  if (width <= 0 || height <= 0)
    throw Error("image size " + std::to_string(width) + "x" + std::to_string(height) +
                " is not positive");
  fill_rect(0, 0, width, height, background);
}

Rgb Image::at(int x, int y) const {
  const size_t i = (size_t(y) * size_t(width_) + size_t(x)) * 3;
  return {pixels_[i], pixels_[i + 1], pixels_[i + 2]};
}

void Image::set(int x, int y, Rgb c) {
  if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
  const size_t i = (size_t(y) * size_t(width_) + size_t(x)) * 3;
  pixels_[i] = c.r;
  pixels_[i + 1] = c.g;
  pixels_[i + 2] = c.b;
}

void Image::fill_rect(int x0, int y0, int x1, int y1, Rgb c) {
  x0 = std::max(x0, 0), y0 = std::max(y0, 0);
  x1 = std::min(x1, width_), y1 = std::min(y1, height_);
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) set(x, y, c);
}

void write_png(const Image& image, const std::string& path) {
  // libpng's simplified API reports errors through its return value instead of
  // longjmp, which would skip C++ destructors.
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  png.width = png_uint_32(image.width());
  png.height = png_uint_32(image.height());
  png.format = PNG_FORMAT_RGB;
  png_alloc_size_t size = 0;
  const auto* pixels = image.pixels().data();
  const auto stride = png_int_32(image.width() * 3);
  if (!png_image_write_to_memory(&png, nullptr, &size, 0, pixels, stride, nullptr))
    throw Error("cannot encode PNG '" + path + "': " + png.message);
  std::string bytes(size, '\0');
  if (!png_image_write_to_memory(&png, bytes.data(), &size, 0, pixels, stride, nullptr))
    throw Error("cannot encode PNG '" + path + "': " + png.message);
  bytes.resize(size);
  write_file_atomic(path, bytes);
}

}  // namespace horizon
