// Peridigm's bond filters (survey sec. 1.8) as native precracks (family/precrack.hpp):
// a bond whose segment crosses the filter is never made, in both codes (or, under the
// Initial Damage model, made broken).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "horizon/geometry/mesh.hpp"

#include "horizon/deck/peridigm/sections.hpp"

namespace horizon::peridigm {

using namespace horizon::deck;

namespace {

YAML::Node row_of(const Vec3& p) {
  YAML::Node row(YAML::NodeType::Sequence);
  row.SetStyle(YAML::EmitterStyle::Flow);
  for (int k = 0; k < 3; ++k) row.push_back(fmt::format("{}", p[k]));
  return row;
}

// Rectangular_Plane {Normal, Lower_Left_Corner, Bottom_Unit_Vector, Bottom_Length,
// Side_Length} as a native rectangle (Peridigm's own test).
YAML::Node rectangular_plane(const DeckContext& ctx, const Item& item) {
  MapReader m(ctx, item,
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
  if (!(std::abs(norm(n) - 1) < 1e-9)) ctx.fail(item.mark, item.path + ": the Normal must be a unit vector");
  // Peridigm's own test, its bottom vector as given (family/precrack.hpp crosses_rectangle):
  // a point of the plane is inside when its offset d from the corner has d.bottom in
  // [0, Bottom_Length] and d.(bottom x normal) in [0, Side_Length], both with Peridigm's
  // tolerance of 1e-15, so a rectangle's edges cut the bonds through them (PrecrackedPlate's
  // gold: 64 neighbours at node 182, an open rectangle leaves 71). PrecrackedPlateTwoCracks
  // gives the bottom (1, 4, 0) with the normal (0, 1, 0): d.bottom = d.x + 4 d.y, whose
  // rounding of d.y decides the bonds through its edge x = 0 (its gold keeps
  // (-0.5, 3.5) -> (0.5, 4.5) and cuts (0.5, 3.5) -> (-0.5, 4.5)); with Peridigm's element
  // centres and this arithmetic both decks' neighbour counts are the golds' at every point.
  if (!(norm(given - n * dot(given, n)) > 1e-9))
    ctx.fail(item.mark, item.path + ": the Bottom_Unit_Vector must not be along the Normal");
  YAML::Node rect;
  rect.SetStyle(YAML::EmitterStyle::Flow);
  rect["corner"] = row_of(corner);
  rect["normal"] = row_of(n);
  rect["bottom"] = row_of(given);
  rect["bottom_length"] = fmt::format("{}", lb);
  rect["side_length"] = fmt::format("{}", ls);
  YAML::Node crack;
  crack["rectangle"] = rect;
  return crack;
}

// Disk {Center, Normal, Radius} as a native disk (survey sec. 1.8).
YAML::Node disk(const DeckContext& ctx, const Item& item) {
  MapReader m(ctx, item, {"Type", "Center_X", "Center_Y", "Center_Z", "Normal_X", "Normal_Y", "Normal_Z", "Radius"});
  auto vec = [&](const std::string& prefix, const char* what) {
    Vec3 v;
    const char* axes[3] = {"X", "Y", "Z"};
    for (int k = 0; k < 3; ++k) v[k] = read_number(ctx, m.get(prefix + "_" + axes[k], what));
    return v;
  };
  const Vec3 c = vec("Center", "the disk's centre");
  const Vec3 n = vec("Normal", "the disk plane's normal");
  if (!(std::abs(norm(n) - 1) < 1e-9)) ctx.fail(item.mark, item.path + ": the Normal must be a unit vector");
  YAML::Node d;
  d["center"] = row_of(c);
  d["normal"] = row_of(n);
  d["radius"] = fmt::format("{}", read_positive(ctx, m.get("Radius", "the disk's radius, > 0")));
  YAML::Node crack;
  crack["disk"] = d;
  return crack;
}

// Exodus Mesh {File Name}: a shell mesh's elements (triangles, quadrilaterals) as the
// facets of one native surface precrack; a quadrilateral off one plane becomes two
// triangles through its first and third corners.
YAML::Node exodus_mesh(const DeckContext& ctx, const Item& item) {
  MapReader m(ctx, item, {"Type", "File Name"});
  const Item file = m.get("File Name", "the shell mesh (.g) of the crack surface");
  std::filesystem::path path = read_string(ctx, file);
  if (path.is_relative()) path = std::filesystem::path(ctx.file).parent_path() / path;
  std::vector<std::vector<Vec3>> facets;
  try {
    facets = read_exodus_surface(path.string());
  } catch (const MeshError& e) {
    ctx.fail(file.mark, file.path + ": " + e.what());
  }
  YAML::Node list(YAML::NodeType::Sequence);
  auto add = [&](const std::vector<Vec3>& f) {
    YAML::Node poly(YAML::NodeType::Sequence);
    for (const Vec3& p : f) poly.push_back(row_of(p));
    list.push_back(poly);
  };
  for (const auto& f : facets) {
    if (f.size() == 4) {
      const Vec3 n = cross(f[1] - f[0], f[2] - f[0]);
      const double size = std::max(norm(f[2] - f[0]), norm(f[3] - f[1]));
      if (!(norm(n) > 0) || std::abs(dot(f[3] - f[0], n / norm(n))) > 1e-9 * size) {
        add({f[0], f[1], f[2]});
        add({f[0], f[2], f[3]});
        continue;
      }
    }
    add(f);
  }
  YAML::Node crack;
  crack["facets"] = list;
  return crack;
}

}  // namespace

YAML::Node read_bond_filters(const DeckContext& ctx, const Item& item, bool broken) {
  YAML::Node cracks(YAML::NodeType::Sequence);
  for (const auto& e : map_entries(ctx, item)) {
    const Item type = MapReader(ctx, e.value,
                                {"Type", "Normal_X", "Normal_Y", "Normal_Z", "Lower_Left_Corner_X",
                                 "Lower_Left_Corner_Y", "Lower_Left_Corner_Z", "Bottom_Unit_Vector_X",
                                 "Bottom_Unit_Vector_Y", "Bottom_Unit_Vector_Z", "Bottom_Length", "Side_Length",
                                 "Center_X", "Center_Y", "Center_Z", "Radius", "File Name"})
                          .get("Type", "Rectangular_Plane, Disk or Exodus Mesh");
    const std::string w = squash_words(read_string(ctx, type));
    YAML::Node crack;
    if (w == "rectangularplane") crack = rectangular_plane(ctx, e.value);
    else if (w == "disk") crack = disk(ctx, e.value);
    else if (w == "exodusmesh") crack = exodus_mesh(ctx, e.value);
    else fail_choice(ctx, type, read_string(ctx, type), {"Rectangular_Plane", "Disk", "Exodus Mesh"}, "bond filter");
    // Initial Damage keeps the crossing bonds as broken bonds (they count in the
    // damage and the neighbour count); a discretisation's filter never makes them.
    if (broken) crack["bonds"] = "broken";
    cracks.push_back(crack);
  }
  return cracks;
}

}  // namespace horizon::peridigm
