#pragma once
// One output frame: points and named per-point fields, as written to and read back
// from a VTU file. Kept free of solver types so that `horizon render` can read any
// frame Horizon wrote.
#include <cstdint>
#include <string>
#include <vector>

#include "horizon/core/vec3.hpp"

namespace horizon {

struct FrameField {
  std::string name;
  int components = 1;          // 1 (scalar) or 3 (vector)
  std::vector<double> data;    // size = points * components, point-major
};

struct Frame {
  double time = 0;
  int64_t step = 0;
  int dimension = 3;
  std::vector<Vec3> points;    // reference positions
  std::vector<FrameField> fields;

  const FrameField* field(const std::string& name) const {
    for (const auto& f : fields)
      if (f.name == name) return &f;
    return nullptr;
  }
};

}  // namespace horizon
