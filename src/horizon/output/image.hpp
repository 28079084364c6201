#pragma once
// An 8-bit RGB raster for the PNG renderer, and writing it as a PNG file.
#include <cstdint>
#include <string>
#include <vector>

namespace horizon {

struct Rgb {
  uint8_t r = 0, g = 0, b = 0;
  friend bool operator==(const Rgb&, const Rgb&) = default;
};

class Image {
 public:
  Image(int width, int height, Rgb background);

  int width() const { return width_; }
  int height() const { return height_; }
  Rgb at(int x, int y) const;

  // Drawing clips to the image, so callers may draw partly (or wholly) outside it.
  void set(int x, int y, Rgb c);
  void fill_rect(int x0, int y0, int x1, int y1, Rgb c);  // [x0,x1) x [y0,y1)

  const std::vector<uint8_t>& pixels() const { return pixels_; }  // row-major RGB

 private:
  int width_, height_;
  std::vector<uint8_t> pixels_;
};

// Encodes with libpng and writes atomically. Throws horizon::Error naming the path.
void write_png(const Image& image, const std::string& path);

}  // namespace horizon
