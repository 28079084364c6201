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
// Side_Length} as a native polygon.
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
  // A point of the plane is inside when its offset from the corner projects onto the
  // bottom vector within [0, Bottom_Length] (and onto the side within [0, Side_Length]),
  // so a part of the bottom vector along the normal changes nothing: only its part in
  // the plane counts, which must be a unit vector (PrecrackedPlateTwoCracks gives
  // (1, 4, 0) with the normal (0, 1, 0): the in-plane part is (1, 0, 0)).
  const Vec3 b = given - n * dot(given, n);
  if (!(std::abs(norm(b) - 1) < 1e-9))
    ctx.fail(item.mark, item.path + ": the Bottom_Unit_Vector's part in the filter's plane must be a unit "
                                    "vector (the normal's part aside)");
  // The side edge runs along bottom x normal: with the normal +y and the bottom +x, the
  // rectangle rises along +z from its lower left corner (PrecrackedPlate's filter,
  // corner z = -10 and side 20, spans the plate's thickness z in [-10, 10]).
  const Vec3 side = cross(b, n);
  YAML::Node poly(YAML::NodeType::Sequence);
  poly.SetStyle(YAML::EmitterStyle::Flow);
  for (const Vec3& p : {corner, corner + b * lb, corner + b * lb + side * ls, corner + side * ls})
    poly.push_back(row_of(p));
  // A surface of this one facet rather than a `polygon`: a facet includes its boundary,
  // and Peridigm's filter cuts the bonds through the rectangle's edges (PrecrackedPlate's
  // gold: 64 neighbours at node 182, where an open rectangle leaves 71). Not always:
  // PrecrackedPlateTwoCracks's gold cuts (0.5, 3.5) -> (-0.5, 4.5) but keeps (-0.5, 3.5)
  // -> (0.5, 4.5), both through the edge x = 0 of its filter at y = 4: Peridigm's lists
  // are directed and its test rounds differently along each; Horizon's bonds are one
  // piece, cut in both directions or neither (docs/peridigm.md).
  YAML::Node facets(YAML::NodeType::Sequence);
  facets.push_back(poly);
  YAML::Node crack;
  crack["facets"] = facets;
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
