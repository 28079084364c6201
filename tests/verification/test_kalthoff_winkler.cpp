// Kalthoff-Winkler test with the bond-based PMB (examples/kalthoff_winkler_pmb.yaml) at
// half resolution: horizon 3.7 mm, horizon/spacing 5, 36,992 particles, 70 us. The crack
// angle at each notch (summary.json fracture.crack_angles_signed_deg, the ridge fit of
// src/horizon/damage/crack_angle.cpp) against the experiment's band (Kalthoff: about
// 70 degrees; the band 60-72 of the thesis's Table 6.2 discussion), and the effect of the
// contact range on sliding crack faces (docs/input.md, contact; docs/verification.md).
#include <gtest/gtest.h>

#include <fmt/format.h>

#include "verification_support.hpp"

namespace horizon::verification {
namespace {

std::pair<double, double> pmb_angles(double max_distance, const std::string& name) {
  Config config = load_deck(source_path("examples/kalthoff_winkler_pmb.yaml"));
  config.contact.short_range.max_distance = max_distance;
  const auto out = output_dir(name);
  RunOptions options;
  options.output_dir = out.string();
  options.coarsen = 2;
  options.quiet = true;
  EXPECT_EQ(run_deck(config, options), 0);
  const auto j = read_json(out / "summary.json");
  const auto& a = j["fracture"]["crack_angles_signed_deg"];
  EXPECT_EQ(a.size(), 2u);
  if (a.size() != 2 || a[0].is_null() || a[1].is_null()) return {0.0, 0.0};
  std::filesystem::remove_all(out / "frames");
  return {a[0].get<double>(), a[1].get<double>()};
}

TEST(KalthoffWinkler, PmbCracksLeaveTheNotchesAtTheExperimentsAngle) {
  const auto [upper, lower] = pmb_angles(0.9, "kalthoff_pmb");
  report("kalthoff_pmb_upper", upper,
         fmt::format("Kalthoff-Winkler, PMB, horizon 3.7 mm: crack angles {:+.1f} / {:+.1f} deg (experiment ~70)",
                     upper, lower));
  // Measured +63.2 / -64.0. Both cracks turn away from the struck strip (+ above, - below).
  EXPECT_GE(upper, 60.0);
  EXPECT_LE(upper, 72.0);
  EXPECT_LE(lower, -60.0);
  EXPECT_GE(lower, -72.0);
}

TEST(KalthoffWinkler, GrindingFacesOfLammpsContactRangeLowerTheAngle) {
  // With d = min(0.9 |xi|, 1.35 h) the notch and crack faces repel as they slide past
  // each other at the lattice distance; measured +53.2 / -53.1.
  const auto [upper, lower] = pmb_angles(1.35, "kalthoff_pmb_135");
  report("kalthoff_pmb_135_upper", upper,
         fmt::format("Kalthoff-Winkler, PMB, contact range 1.35 spacings: {:+.1f} / {:+.1f} deg", upper, lower));
  EXPECT_GT(upper, 0.0);
  EXPECT_LT(upper, 58.0);
  EXPECT_LT(lower, 0.0);
  EXPECT_GT(lower, -58.0);
}

}  // namespace
}  // namespace horizon::verification
