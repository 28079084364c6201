// output.history_columns (driver/history_columns.hpp): sums, minima, maxima and the
// nearest particle over bodies and regions, vector columns NAMEX/Y/Z, and the globals.
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "horizon/deck/deck.hpp"
#include "horizon/driver/history_columns.hpp"
#include "horizon/solver/build.hpp"
#include "horizon/state/system.hpp"

namespace horizon {
namespace {

const char* const kDeck = R"deck(dimension: 3
spacing: 1.0
horizon: 1.5
lattice_origin: [0, 0, 0]
materials:
  steel: {model: pmb, density: 2.0, youngs_modulus: 1.0e9}
bodies:
  - {name: left, material: steel, shape: {box: {min: [-0.5, -0.5, -0.5], max: [1.5, 0.5, 0.5]}}}
  - {name: right, material: steel, shape: {box: {min: [2.5, -0.5, -0.5], max: [3.5, 0.5, 0.5]}}}
regions:
  far: {box: {min: [0.5, -1, -1], max: [4, 1, 1]}}
solver: {end_time: 1.0e-6, time_step: 1.0e-7}
output:
  history_columns:
    - {name: KE, quantity: kinetic_energy}
    - {name: P, quantity: linear_momentum}
    - {name: L, quantity: angular_momentum}
    - {name: left_vol, quantity: volume, body: left}
    - {name: far_max_vx, quantity: velocity, region: far, reduce: max}
    - {name: far_min_vx, quantity: velocity, region: far, reduce: min}
    - {name: probe, quantity: reference_position, nearest: [2.9, 0.2, 0]}
    - {name: left_force, quantity: force, body: left, reduce: sum}
)deck";

std::vector<double> cells(const std::string& row) {
  std::vector<double> out;
  std::stringstream in(row);
  std::string cell;
  std::getline(in, cell, ',');  // the row starts with a comma
  while (std::getline(in, cell, ',')) out.push_back(std::stod(cell));
  return out;
}

TEST(HistoryColumns, HeaderAndValues) {
  const Config c = parse_deck(kDeck, "probes.yaml");
  EXPECT_EQ(history_columns_header(c),
            ",KE,PX,PY,PZ,LX,LY,LZ,left_vol,far_max_vxX,far_max_vxY,far_max_vxZ,far_min_vxX,far_min_vxY,far_min_vxZ,"
            "probeX,probeY,probeZ,left_forceX,left_forceY,left_forceZ");
  System s = build_system(c);
  ASSERT_EQ(s.particles.size(), 3u);  // left: x = 0, 1; right: x = 3
  auto& P = s.particles;
  const double m = 2.0 * 1.0;  // density x volume
  P.v[0] = {1, 0, 0};
  P.v[1] = {-2, 0, 1};
  P.v[2] = {4, 0, 0};
  P.f[0] = {5, 0, 0};
  P.f[1] = {-1, 0, 0};
  const std::vector<double> v = cells(history_columns_row(c, s));
  ASSERT_EQ(v.size(), 20u);
  EXPECT_DOUBLE_EQ(v[0], 0.5 * m * (1 + 5 + 16));
  EXPECT_DOUBLE_EQ(v[1], m * (1 - 2 + 4));
  EXPECT_DOUBLE_EQ(v[3], m * 1);
  // L = sum x cross m v: particle 1 at (1, 0, 0) with m v = (-4, 0, 2): (0, -2, 0).
  EXPECT_DOUBLE_EQ(v[4], 0.0);
  EXPECT_DOUBLE_EQ(v[5], -2.0);
  EXPECT_DOUBLE_EQ(v[7], 2.0);  // left: two unit volumes
  EXPECT_DOUBLE_EQ(v[8], 4.0);   // far holds particles 1 and 2: max vx
  EXPECT_DOUBLE_EQ(v[10], 1.0);  // max vz
  EXPECT_DOUBLE_EQ(v[11], -2.0); // min vx
  EXPECT_DOUBLE_EQ(v[14], 3.0);  // the nearest particle to (2.9, 0.2, 0) is at x = 3
  EXPECT_DOUBLE_EQ(v[17], 4.0);  // force density times volume, summed over left
}

TEST(HistoryColumns, ModelFields) {
  // A model's output field: the correspondence model's von_mises_stress, zero at rest;
  // a field no model of the run writes is an error naming the ones there are.
  std::string deck = kDeck;
  deck.replace(deck.find("model: pmb"), 10, "model: correspondence, poissons_ratio: 0.25");
  const auto right = deck.find("  - {name: right");  // a lone particle: no family to correspond
  deck.erase(right, deck.find('\n', right) + 1 - right);
  deck += "    - {name: vm, field: von_mises_stress, body: left, reduce: max}\n";
  const Config c = parse_deck(deck, "fields.yaml");
  System s = build_system(c);
  EXPECT_EQ(cells(history_columns_row(c, s)).back(), 0.0);
  std::string other = kDeck;
  other += "    - {name: vm, field: von_mises_stress}\n";
  const Config o = parse_deck(other, "fields.yaml");
  System so = build_system(o);
  try {
    history_columns_row(o, so);
    FAIL() << "no error";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("no model of this run writes the field 'von_mises_stress'"),
              std::string::npos) << e.what();
  }
}

TEST(HistoryColumns, DeckErrors) {
  std::string bad = kDeck;
  bad.replace(bad.find("body: left}"), 10, "body: lift");
  try {
    parse_deck(bad, "probes.yaml");
    FAIL() << "no error";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("probes.yaml:"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("lift"), std::string::npos) << e.what();
  }
  std::string both = kDeck;
  both.replace(both.find("nearest: [2.9"), 7, "reduce: max, nearest:");
  EXPECT_THROW(parse_deck(both, "probes.yaml"), std::exception);
}

}  // namespace
}  // namespace horizon
