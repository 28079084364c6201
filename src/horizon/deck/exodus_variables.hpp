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
      "Equivalent_Plastic_Strain",
      // the bond-associated correspondence model's (material/models/bond_associated.hpp)
      "Velocity_Gradient", "Jacobian_Determinant",
      // lps and elastic_plastic with shear_correction (material/shear_correction.hpp)
      "Surface_Correction_Factor",
      // pals' normalisations and Lagrange multipliers (material/models/pals.hpp)
      "Dilatation_Normalization", "Deviatoric_Normalization",
      "Lagrange_Multiplier_Dilatation_1", "Lagrange_Multiplier_Dilatation_2", "Lagrange_Multiplier_Dilatation_3",
      "Lagrange_Multiplier_Dilatation_4", "Lagrange_Multiplier_Dilatation_5", "Lagrange_Multiplier_Dilatation_6",
      "Lagrange_Multiplier_Deviatoric_1", "Lagrange_Multiplier_Deviatoric_2", "Lagrange_Multiplier_Deviatoric_3",
      "Lagrange_Multiplier_Deviatoric_4", "Lagrange_Multiplier_Deviatoric_5", "Lagrange_Multiplier_Deviatoric_6"};
  return names;
}

}  // namespace horizon
