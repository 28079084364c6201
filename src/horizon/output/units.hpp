#pragma once
// What a history column or a frame field measures, in which SI unit, and the scaled unit
// (mm, kN, us, MPa, ...) in which a range of values reads best: the axis titles of
// `horizon plot` and the colour bar and clock of `horizon render`.
#include <string>

namespace horizon {

struct Quantity {
  std::string name;  // readable, e.g. "force y on load:displacement", "kinetic energy"
  std::string kind;  // what it is, e.g. "force", "energy"; empty when unknown
  std::string unit;  // SI, e.g. "N"; empty for a ratio (damage) or an unknown column
  bool prefixed = true;  // whether SI prefixes apply (not for m³, K, 1/m)
};

// From the names Horizon writes (driver/run.cpp history columns, the frame fields of
// driver/run.cpp and the models): unknown names give the name itself and no unit.
Quantity history_quantity(const std::string& column);
Quantity field_quantity(const std::string& field);

// A unit with an SI prefix: the values in it are SI values times `factor`.
struct ScaledUnit {
  std::string unit;
  double factor = 1;
};
// The prefix (n, µ, m, none, k, M, G) that puts `largest` (the largest magnitude shown)
// in [1, 1000); no prefix when the quantity takes none or largest is 0 or not finite.
ScaledUnit scaled_unit(const Quantity& q, double largest);

// "Force y on load:displacement (kN)": the name with a capital first letter and the unit.
std::string axis_title(const std::string& name, const std::string& unit);

// A number with at most `digits` significant digits and no trailing zeros ("43.01", "0.5").
std::string short_number(double v, int digits = 4);

}  // namespace horizon
