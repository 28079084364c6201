// Peridigm's bond filters (survey sec. 1.8) as native precracks (family/precrack.hpp):
// a bond whose segment crosses the filter is never made, in both codes.
#include <fmt/format.h>

#include <cmath>

#include "horizon/deck/peridigm/sections.hpp"

namespace horizon::peridigm {

using namespace horizon::deck;

YAML::Node read_bond_filters(const DeckContext& ctx, const Item& item) {
  YAML::Node cracks(YAML::NodeType::Sequence);
  for (const auto& e : map_entries(ctx, item)) {
    const Item type = MapReader(ctx, e.value,
                                {"Type", "Normal_X", "Normal_Y", "Normal_Z", "Lower_Left_Corner_X",
                                 "Lower_Left_Corner_Y", "Lower_Left_Corner_Z", "Bottom_Unit_Vector_X",
                                 "Bottom_Unit_Vector_Y", "Bottom_Unit_Vector_Z", "Bottom_Length", "Side_Length",
                                 "Center_X", "Center_Y", "Center_Z", "Radius", "File Name"})
                          .get("Type", "Rectangular_Plane");
    const std::string w = squash_words(read_string(ctx, type));
    if (w != "rectangularplane") {
      // Disk filters and shell-mesh (Exodus Mesh) filters have no native precrack shape yet.
      fail_choice(ctx, type, read_string(ctx, type), {"Rectangular_Plane"}, "bond filter Horizon reads");
    }
    MapReader m(ctx, e.value,
                {"Type", "Normal_X", "Normal_Y", "Normal_Z", "Lower_Left_Corner_X", "Lower_Left_Corner_Y",
                 "Lower_Left_Corner_Z", "Bottom_Unit_Vector_X", "Bottom_Unit_Vector_Y", "Bottom_Unit_Vector_Z",
                 "Bottom_Length", "Side_Length"});
    auto vec = [&](const std::string& prefix, const char* what) {
      Vec3 v;
      const char* axes[3] = {"X", "Y", "Z"};
      for (int k = 0; k < 3; ++k) v[k] = read_number(ctx, m.get(prefix + "_" + axes[k], what));
      return v;
    };
    const Vec3 n = vec("Normal", "the filter plane's normal");
    const Vec3 corner = vec("Lower_Left_Corner", "the rectangle's lower left corner");
    const Vec3 given = vec("Bottom_Unit_Vector", "the direction of the rectangle's bottom edge");
    const double lb = read_positive(ctx, m.get("Bottom_Length", "the bottom edge's length, > 0"));
    const double ls = read_positive(ctx, m.get("Side_Length", "the side edge's length, > 0"));
    if (!(std::abs(norm(n) - 1) < 1e-9)) ctx.fail(e.value.mark, e.value.path + ": the Normal must be a unit vector");
    // A point of the plane is inside when its offset from the corner projects onto the
    // bottom vector within [0, Bottom_Length] (and onto the side within [0, Side_Length]),
    // so a part of the bottom vector along the normal changes nothing: only its part in
    // the plane counts, which must be a unit vector (PrecrackedPlateTwoCracks gives
    // (1, 4, 0) with the normal (0, 1, 0): the in-plane part is (1, 0, 0)).
    const Vec3 b = given - n * dot(given, n);
    if (!(std::abs(norm(b) - 1) < 1e-9))
      ctx.fail(e.value.mark, e.value.path + ": the Bottom_Unit_Vector's part in the filter's plane must be a unit "
                                            "vector (the normal's part aside)");
    // The side edge runs along bottom x normal: with the normal +y and the bottom +x, the
    // rectangle rises along +z from its lower left corner (PrecrackedPlate's filter,
    // corner z = -10 and side 20, spans the plate's thickness z in [-10, 10]).
    const Vec3 side = cross(b, n);
    YAML::Node poly(YAML::NodeType::Sequence);
    for (const Vec3& p : {corner, corner + b * lb, corner + b * lb + side * ls, corner + side * ls}) {
      YAML::Node row(YAML::NodeType::Sequence);
      row.SetStyle(YAML::EmitterStyle::Flow);
      for (int k = 0; k < 3; ++k) row.push_back(fmt::format("{}", p[k]));
      poly.push_back(row);
    }
    YAML::Node crack;
    crack["polygon"] = poly;
    cracks.push_back(crack);
  }
  return cracks;
}

}  // namespace horizon::peridigm
