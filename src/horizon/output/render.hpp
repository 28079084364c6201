#pragma once
// A quick look at a frame without ParaView: particles drawn as squares in the x-y
// plane, coloured by one field, with a colour bar and a title, written as a PNG.
#include <optional>
#include <string>

#include "horizon/output/frame.hpp"
#include "horizon/output/resolve_frame.hpp"

namespace horizon {

struct RenderOptions {
  // A field of the frame; a 3-component field is shown by its magnitude, and
  // "<name>_x", "_y", "_z" pick one component of the vector field <name>.
  std::string field = "damage";
  int width = 1200;                  // pixels; the height follows the body's shape
  bool deformed = true;              // draw at X + scale * u when "displacement" exists
  double displacement_scale = 1.0;
  std::optional<double> vmin, vmax;  // colour range; defaults to the field's range
  std::string title;                 // shown before the field name and time
};

// Renders `frame` to `png_path` (atomically). 3-D bodies are projected onto x-y with
// the largest z drawn last, so the top face shows. Throws horizon::Error when the field
// does not exist (listing those that do) or the options make no picture.
void render_png(const Frame& frame, const RenderOptions& options, const std::string& png_path);

}  // namespace horizon
