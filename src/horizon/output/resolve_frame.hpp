#pragma once
// Turns what a user passes to `horizon render` (a frame, an index, or an output
// folder) into the path of one .vtu frame.
#include <string>

namespace horizon {

// A .vtu is returned as is; a .pvd gives its last dataset; a directory gives the last
// dataset of the one .pvd inside it. Throws horizon::Error saying what was expected.
std::string resolve_frame(const std::string& frame_or_dir);

}  // namespace horizon
