// Thermal shock (examples/thermal_shock.yaml reduced to a 6 mm x 3 mm plate): an alumina
// plate quenched on its four edges cracks from the edges inwards, in a periodic array of
// parallel edge cracks (Jiang et al. 2012, Acta Mater. 60:4540; docs/verification.md
// "Thermal shock"). Asserted: the first damage lies at the quenched edges; the long edges
// carry several cracks, roughly evenly spaced, at a spacing within a band.
#include <algorithm>
#include <fmt/format.h>

#include <regex>

#include "horizon/damage/crack_metrics.hpp"
#include "horizon/output/vtu.hpp"
#include "verification_support.hpp"

namespace horizon::verification {
namespace {

std::string reduced_deck(const std::string& out) {
  std::string deck = read_text(source_path("examples/thermal_shock.yaml"));
  deck = std::regex_replace(deck, std::regex(R"(max: \[0\.02, 0\.01\]\}\}\})"), "max: [0.006, 0.003]}}}");
  deck = std::regex_replace(deck, std::regex(R"(bottom: \{box: \{min: \[0, 0\], max: \[0\.02,)"),
                            "bottom: {box: {min: [0, 0], max: [0.006,");
  deck = std::regex_replace(deck, std::regex(R"(top:    \{box: \{min: \[0, 0\.0099\], max: \[0\.02, 0\.01\])"),
                            "top:    {box: {min: [0, 0.0029], max: [0.006, 0.003]");
  deck = std::regex_replace(deck, std::regex(R"(left:   \{box: \{min: \[0, 0\], max: \[0\.0001, 0\.01\])"),
                            "left:   {box: {min: [0, 0], max: [0.0001, 0.003]");
  deck = std::regex_replace(deck, std::regex(R"(right:  \{box: \{min: \[0\.0199, 0\], max: \[0\.02, 0\.01\])"),
                            "right:  {box: {min: [0.0059, 0], max: [0.006, 0.003]");
  deck = std::regex_replace(deck, std::regex(R"(end_time: 20\.0e-6)"), "end_time: 6.0e-6");
  deck = std::regex_replace(deck, std::regex(R"(directory: out/thermal_shock, frames: 20)"),
                            "directory: " + out + ", frames: 30");
  return deck;
}

TEST(ThermalShock, QuenchedPlateCracksFromItsEdges) {
  const auto dir = output_dir("thermal_shock");
  const std::string text = reduced_deck(dir.string());
  ASSERT_NE(text.find("0.006, 0.003"), std::string::npos);
  ASSERT_NE(text.find("end_time: 6.0e-6"), std::string::npos);
  Config c = parse_deck(text, "thermal_shock_reduced.yaml");
  ASSERT_NEAR(c.bodies.size(), 1, 0);
  RunOptions o;
  o.quiet = true;
  ASSERT_EQ(run_deck(c, o), 0);

  const double W = 0.006, H = 0.003, delta = c.horizon;
  // The first frame with damage: every damaged particle within two horizons of an edge.
  bool seen = false;
  for (int f = 0; f <= 30 && !seen; ++f) {
    const auto path = dir / "frames" / fmt::format("frame_{:05d}.vtu", f);
    if (!std::filesystem::exists(path)) break;
    const Frame fr = read_vtu(path.string());
    const auto dmg = std::find_if(fr.fields.begin(), fr.fields.end(), [](const auto& x) { return x.name == "damage"; });
    ASSERT_NE(dmg, fr.fields.end());
    double deepest = 0;
    for (std::size_t i = 0; i < fr.points.size(); ++i) {
      if (dmg->data[i] <= 0) continue;
      seen = true;
      const Vec3& X = fr.points[i];
      deepest = std::max(deepest, std::min({X.x, W - X.x, X.y, H - X.y}));
    }
    if (seen) {
      std::printf("[ figure ] first damage (frame %d) reaches %.3f mm from the nearest edge\n", f, deepest * 1e3);
      EXPECT_LE(deepest, 2 * delta);
    }
  }
  ASSERT_TRUE(seen) << "the quench broke no bond";

  // The edge cracks at the end, seen on lines 0.4 mm inside the long edges.
  const Frame last = read_vtu((dir / "frames" / "frame_00030.vtu").string());
  const auto dmg = std::find_if(last.fields.begin(), last.fields.end(), [](const auto& x) { return x.name == "damage"; });
  for (double at : {0.00045, H - 0.00045}) {
    const LineCracks lc = cracks_across_line(last.points, dmg->data, 0, 1, at, 0.5 * c.spacing, 0.25, 2 * delta);
    std::string where;
    for (double x : lc.positions) where += fmt::format(" {:.2f}", x * 1e3);
    std::printf("[ figure ] edge cracks at y = %.2f mm: %zu at x =%s mm, mean spacing %.2f mm\n", at * 1e3,
                lc.positions.size(), where.c_str(), lc.mean_spacing * 1e3);
    EXPECT_GE(lc.positions.size(), 2u);
    EXPECT_GT(lc.mean_spacing, 1.0e-3);  // a band around the full plate's ~2 mm
    EXPECT_LT(lc.mean_spacing, 3.0e-3);
    // Roughly periodic: no gap more than twice the mean.
    for (std::size_t k = 1; k < lc.positions.size(); ++k)
      EXPECT_LT(lc.positions[k] - lc.positions[k - 1], 2 * lc.mean_spacing);
  }
  // The interior stays intact: no damage more than 1.2 mm from every edge.
  for (std::size_t i = 0; i < last.points.size(); ++i) {
    const Vec3& X = last.points[i];
    if (std::min({X.x, W - X.x, X.y, H - X.y}) > 1.2e-3) {
      EXPECT_EQ(dmg->data[i], 0) << "particle " << i;
    }
  }
}

}  // namespace
}  // namespace horizon::verification
