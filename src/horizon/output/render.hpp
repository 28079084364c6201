#pragma once
// A picture of a frame without ParaView, drawn with Cairo (output/canvas.hpp): particles
// as discs at their size coloured by one field, a colour bar with the field's name, unit
// and range, a length scale bar and the time; 3-D bodies as a slice or a projection.
// PNG, SVG or PDF by the output file's extension.
#include <optional>
#include <string>

#include "horizon/output/frame.hpp"
#include "horizon/output/resolve_frame.hpp"

namespace horizon {

struct RenderOptions {
  // A field of the frame; a 3-component field is shown by its magnitude, and
  // "<name>_x", "_y", "_z" pick one component of the vector field <name>.
  std::string field = "damage";
  int width = 1200;                  // pixels (points for SVG, PDF); the height follows the body
  bool deformed = true;              // draw at X + scale * u when "displacement" exists
  double displacement_scale = 1.0;
  std::optional<double> vmin, vmax;  // colour range; defaults to the field's range
  std::string title;                 // shown before the time
  // 3-D bodies: "z=0.001" draws the particles within half a spacing of that plane (by
  // their reference position); empty draws them all projected along `view`, the nearest
  // (largest coordinate along it) last.
  std::string slice;
  char view = 'z';
};

// What was drawn, for the caller's message and for tests.
struct RenderResult {
  double lo = 0, hi = 1;    // the colour bar's range (SI units of the field)
  std::string field_title;  // e.g. "Displacement magnitude (mm)"
  double bar_left = 0, bar_right = 0, bar_top = 0, bar_bottom = 0;  // the colour bar's pixels
  std::size_t drawn = 0;    // particles drawn
};

// Renders `frame` to `path` (atomically). Throws horizon::Error when the field does not
// exist (listing those that do), the slice holds no particle, or the options make no picture.
RenderResult render_png(const Frame& frame, const RenderOptions& options, const std::string& path);

}  // namespace horizon
