#pragma once
// Frames as VTK XML UnstructuredGrid files (.vtu), the format ParaView opens directly.
// Arrays go in one raw appended binary block (UInt64 byte-count headers, little endian):
// no base64 or compression, so writing costs little more than a memory copy and the
// values read back bit for bit. Each point is one VTK_VERTEX cell so that ParaView
// shows the particles without a glyph filter.
#include <string>

#include "horizon/output/frame.hpp"

namespace horizon {

// Writes `frame` to `path` atomically. FieldData holds TIME, CYCLE (the step) and
// "dimension" so that read_vtu restores the whole Frame. Throws horizon::Error when a
// field's size does not match the point count or the file cannot be written.
void write_vtu(const std::string& path, const Frame& frame);

// The particles `which` of a frame (the piece of one rank of a decomposed run).
Frame frame_subset(const Frame& frame, const std::vector<uint32_t>& which);

// A ParaView parallel index (.pvtu) of the pieces (paths relative to its folder) of one
// frame whose fields are those of `like`. Atomic, as write_vtu.
void write_pvtu(const std::string& path, const Frame& like, const std::vector<std::string>& pieces);

// Reads back a file written by write_vtu. Throws horizon::Error naming the path when
// the file is missing, truncated, or not laid out the way write_vtu lays it out.
Frame read_vtu(const std::string& path);

}  // namespace horizon
