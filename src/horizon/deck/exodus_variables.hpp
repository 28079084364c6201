#pragma once
// Peridigm's variables an Exodus file (output.exodus_files' `variables`) writes from the
// models' fields; driver/exodus_output.hpp exodus_field_variable has their components.
#include <string>
#include <vector>

namespace horizon {

inline const std::vector<std::string>& model_field_variables() {
  static const std::vector<std::string> names = {
      "Hourglass_Force_Density", "Left_Stretch_Tensor", "Rotation_Tensor", "Shape_Tensor_Inverse",
      "Unrotated_Rate_Of_Deformation", "Cauchy_Stress", "Unrotated_Cauchy_Stress", "Von_Mises_Stress",
      "Equivalent_Plastic_Strain"};
  return names;
}

}  // namespace horizon
