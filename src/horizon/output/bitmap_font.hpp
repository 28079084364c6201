#pragma once
// A tiny 5x7 bitmap font for labels on rendered PNGs, so rendering needs no font
// library. Letters are upper case only: lower-case input is drawn in upper case.
#include <string_view>

#include "horizon/output/image.hpp"

namespace horizon {

constexpr int glyph_width = 5;
constexpr int glyph_height = 7;

// Width in pixels of `text` drawn at `scale` (one blank column between glyphs).
int text_width(std::string_view text, int scale);

// Draws `text` with its top-left corner at (x, y), each font pixel a scale x scale
// block. Characters without a glyph are drawn as '?'.
void draw_text(Image& image, int x, int y, std::string_view text, int scale, Rgb colour);

}  // namespace horizon
