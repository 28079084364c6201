#include "horizon/output/units.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace horizon {

namespace {

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

bool starts_with(const std::string& s, const std::string& head) { return s.rfind(head, 0) == 0; }

std::string spaced(std::string s) {
  std::replace(s.begin(), s.end(), '_', ' ');
  return s;
}

// "<load>_fy": a per-axis column of a load, a projectile or a body (driver/run.cpp).
struct AxisColumn {
  std::string owner;
  char axis = 0;
};
bool axis_column(const std::string& c, const std::string& letter, AxisColumn& out, const std::string& tail = "") {
  const std::string mid = "_" + letter;
  if (c.size() < mid.size() + 2 + tail.size() || !ends_with(c, tail)) return false;
  const std::string head = c.substr(0, c.size() - tail.size());
  const char axis = head.back();
  if (axis < 'x' || axis > 'z' || !ends_with(head.substr(0, head.size() - 1), mid)) return false;
  out = {head.substr(0, head.size() - 1 - mid.size()), axis};
  return !out.owner.empty();
}

}  // namespace

Quantity history_quantity(const std::string& c) {
  if (c == "time") return {"time", "time", "s"};
  if (c == "dt") return {"time step", "time", "s"};
  if (c == "heat_time") return {"heat time", "time", "s"};
  if (c == "step") return {"step", "", ""};
  if (c == "energy_balance_error" || c == "broken_bond_fraction" || starts_with(c, "damage_"))
    return {spaced(c), "", ""};
  if (ends_with(c, "_energy") || ends_with(c, "_work") || ends_with(c, "_heat") || c == "heat_content")
    return {spaced(c), "energy", "J"};
  if (starts_with(c, "temperature_")) return {spaced(c), "temperature", "K", false};
  AxisColumn a;
  const auto of = [&](const char* what, const char* joint) {
    return fmt::format("{} {} {} {}", what, a.axis, joint, a.owner);
  };
  if (axis_column(c, "f", a)) return {of("force", "on"), "force", "N"};
  if (axis_column(c, "u", a)) return {of("displacement", "of"), "displacement", "m"};
  if (axis_column(c, "v", a)) return {of("velocity", "of"), "velocity", "m/s"};
  if (axis_column(c, "a", a, "_filtered")) return {of("filtered acceleration", "of"), "acceleration", "m/s²", false};
  if (axis_column(c, "a", a)) return {of("acceleration", "of"), "acceleration", "m/s²", false};
  if (axis_column(c, "", a)) return {of("position", "of"), "position", "m"};
  return {c, "", ""};
}

Quantity field_quantity(const std::string& f) {
  if (f == "displacement" || f == "deflection") return {spaced(f), "displacement", "m"};
  if (f == "velocity") return {f, "velocity", "m/s"};
  if (f == "force_density") return {"force density", "force density", "N/m³"};
  if (f == "energy_density") return {"energy density", "energy density", "J/m³"};
  if (f == "volume") return {f, "volume", "m³", false};
  if (f == "temperature") return {f, "temperature", "K", false};
  if (f == "heat_flux") return {"heat flux", "heat flux", "W/m²"};
  if (f == "von_mises_stress") return {"von Mises stress", "stress", "Pa"};
  if (starts_with(f, "stress_")) return {spaced(f), "stress", "Pa"};
  if (f == "curvature") return {f, "curvature", "1/m", false};
  if (f == "damage" || f == "ductile_damage" || f == "equivalent_plastic_strain") return {spaced(f), "", ""};
  return {spaced(f), "", ""};
}

ScaledUnit scaled_unit(const Quantity& q, double largest) {
  if (!(largest > 0) || !std::isfinite(largest)) return {q.unit, 1};
  int e = 3 * static_cast<int>(std::floor(std::log10(largest) / 3 + 1e-9));
  if (q.prefixed && !q.unit.empty()) {
    // No km or ks: lengths and times above one metre or second read best as they are.
    const int top = (q.unit == "m" || q.unit == "s") ? 0 : 9;
    e = std::clamp(e, -9, top);
    static constexpr std::array<const char*, 7> prefix{"n", "µ", "m", "", "k", "M", "G"};
    return {prefix[size_t(e / 3 + 3)] + q.unit, std::pow(10.0, -e)};
  }
  // Without prefixes, a power of ten in the unit keeps tick labels short: damage in 10⁻³.
  if (largest >= 1e-2 && largest < 1e4) return {q.unit, 1};
  static constexpr std::array<const char*, 10> sup{"⁰", "¹", "²", "³", "⁴", "⁵", "⁶", "⁷", "⁸", "⁹"};
  std::string power = "10";
  if (e < 0) power += "⁻";
  for (char d : std::to_string(std::abs(e))) power += sup[size_t(d - '0')];
  return {q.unit.empty() ? power : power + " " + q.unit, std::pow(10.0, -e)};
}

std::string axis_title(const std::string& name, const std::string& unit) {
  std::string t = name;
  if (!t.empty() && t[0] >= 'a' && t[0] <= 'z' && !starts_with(t, "von ")) t[0] = char(t[0] - 'a' + 'A');
  return unit.empty() ? t : t + " (" + unit + ")";
}

std::string short_number(double v, int digits) {
  if (v == 0) return "0";
  std::string s = fmt::format("{:.{}g}", v, digits);
  if (s[0] == '-') s = "−" + s.substr(1);  // the typographic minus sign
  return s;
}

}  // namespace horizon
