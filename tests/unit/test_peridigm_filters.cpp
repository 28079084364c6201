// Peridigm's bond filters, Initial Damage and PdQuickGrid's box neighbourhood through
// the importer (deck/peridigm/bond_filters.cpp, peridigm.cpp), on small decks written by
// the test with the native deck each must become; and the native shapes they map to
// (precracks `disk` and `facets`, `family_box`) on bonds whose answer is known by hand.
#include <exodusII.h>
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "horizon/core/error.hpp"
#include "horizon/deck/deck.hpp"
#include "horizon/family/precrack.hpp"
#include "horizon/solver/build.hpp"
#include "horizon/state/system.hpp"

namespace horizon {
namespace {

namespace fs = std::filesystem;

fs::path test_dir() {
  // A folder per test: ctest runs the tests of this file in parallel processes.
  const fs::path dir = fs::temp_directory_path() / "horizon_peridigm_filters" /
                       ::testing::UnitTest::GetInstance()->current_test_info()->name();
  fs::create_directories(dir);
  return dir;
}

// A deck of a 2 x 2 x 2 PdQuickGrid cube [0, 2]^3 with `discretization` keys appended to
// its Discretization, and `damage` (a Damage Models entry, "" for none).
std::string write_deck(const std::string& discretization, const std::string& damage = "",
                       const std::string& grid = "2", double horizon = 1.5) {
  const fs::path path = test_dir() / "deck.yaml";
  std::ofstream(path) << "Peridigm:\n"
                         "  Discretization:\n"
                         "    Type: \"PdQuickGrid\"\n"
                         "    TensorProduct3DMeshGenerator:\n"
                         "      Type: \"PdQuickGrid\"\n"
                         "      X Origin: 0.0\n      Y Origin: 0.0\n      Z Origin: 0.0\n"
                         "      X Length: 2.0\n      Y Length: 2.0\n      Z Length: 2.0\n"
                         "      Number Points X: " +
                             grid + "\n      Number Points Y: " + grid + "\n      Number Points Z: " + grid +
                             "\n" + discretization +
                             "  Materials:\n"
                             "    Steel: {Material Model: \"Elastic\", Density: 7800.0, Bulk Modulus: 130.0e9, "
                             "Shear Modulus: 78.0e9}\n" +
                             (damage.empty() ? "" : "  Damage Models:\n    Cut:\n" + damage) +
                             "  Blocks:\n"
                             "    All:\n"
                             "      Block Names: \"block_1\"\n"
                             "      Material: \"Steel\"\n" +
                             (damage.empty() ? "" : "      Damage Model: \"Cut\"\n") +
                             "      Horizon: " + std::to_string(horizon) +
                             "\n"
                             "  Solver:\n"
                             "    Final Time: 1.0e-6\n"
                             "    Verlet:\n"
                             "      Fixed dt: 1.0e-7\n";
  return path.string();
}

YAML::Node convert(const std::string& path) { return YAML::Load(convert_peridigm_deck(path)); }

std::string flow(const YAML::Node& n) {
  YAML::Emitter e;
  e.SetMapFormat(YAML::Flow);
  e.SetSeqFormat(YAML::Flow);
  e << n;
  return e.c_str();
}

std::string error_of(const std::string& path) {
  try {
    convert_peridigm_deck(path);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// A shell mesh of one QUAD4 in the plane x = 1 (y, z in [0, 1.2]) and one TRI3 in the
// plane z = 1 (x, y >= 0, x + y <= 2.4), written through the Exodus library.
std::string write_shells() {
  const std::string path = (test_dir() / "shells.g").string();
  int cpu_ws = sizeof(double), io_ws = sizeof(double);
  const int id = ex_create(path.c_str(), EX_CLOBBER, &cpu_ws, &io_ws);
  EXPECT_GE(id, 0);
  EXPECT_GE(ex_put_init(id, "shells", 3, 7, 2, 2, 0, 0), 0);
  const double x[7] = {1, 1, 1, 1, 0, 2.4, 0}, y[7] = {0, 1.2, 1.2, 0, 0, 0, 2.4}, z[7] = {0, 0, 1.2, 1.2, 1, 1, 1};
  ex_put_coord(id, x, y, z);
  const int quad[4] = {1, 2, 3, 4}, tri[3] = {5, 6, 7};
  ex_put_block(id, EX_ELEM_BLOCK, 1, "SHELL4", 1, 4, 0, 0, 0);
  ex_put_conn(id, EX_ELEM_BLOCK, 1, quad, nullptr, nullptr);
  ex_put_block(id, EX_ELEM_BLOCK, 2, "TRI3", 1, 3, 0, 0, 0);
  ex_put_conn(id, EX_ELEM_BLOCK, 2, tri, nullptr, nullptr);
  EXPECT_GE(ex_close(id), 0);
  return path;
}

}  // namespace

TEST(PeridigmFilters, DiskFilterIsADiskPrecrack) {
  // DiskFilter's filter: centre 0, normal +y, radius 2.5 (here centred in the cube).
  const std::string path = write_deck(
      "    Bond Filters:\n"
      "      My Disk:\n"
      "        Type: \"Disk\"\n"
      "        Center_X: 1.0\n        Center_Y: 1.0\n        Center_Z: 1.0\n"
      "        Normal_X: 0.0\n        Normal_Y: 1.0\n        Normal_Z: 0.0\n"
      "        Radius: 0.75\n");
  EXPECT_EQ(flow(convert(path)["precracks"]), "[{disk: {center: [1, 1, 1], normal: [0, 1, 0], radius: 0.75}}]");
  // A filter type Peridigm does not have is refused, with the three it has.
  std::string text;
  {
    std::ifstream in(path);
    text.assign(std::istreambuf_iterator<char>(in), {});
  }
  text.replace(text.find("\"Disk\""), 6, "\"Sphere\"");
  std::ofstream(path) << text;
  const std::string e = error_of(path);
  EXPECT_NE(e.find("deck.yaml:17:15"), std::string::npos) << e;
  EXPECT_NE(e.find("Exodus Mesh"), std::string::npos) << e;
}

TEST(PeridigmFilters, ExodusMeshFilterIsASurfacePrecrack) {
  write_shells();
  const std::string path = write_deck(
      "    Bond Filters:\n"
      "      My Shells:\n"
      "        Type: \"Exodus Mesh\"\n"
      "        File Name: \"shells.g\"\n");
  EXPECT_EQ(flow(convert(path)["precracks"]),
            "[{facets: [[[1, 0, 0], [1, 1.2, 0], [1, 1.2, 1.2], [1, 0, 1.2]], [[0, 0, 1], [2.4, 0, 1], [0, 2.4, 1]]]}]");
  // A missing mesh is an error at File Name's value.
  std::string text;
  {
    std::ifstream in(path);
    text.assign(std::istreambuf_iterator<char>(in), {});
  }
  text.replace(text.find("shells.g"), 8, "absent.g");
  std::ofstream(path) << text;
  const std::string e = error_of(path);
  EXPECT_NE(e.find("deck.yaml:18:20"), std::string::npos) << e;
  EXPECT_NE(e.find("absent.g"), std::string::npos) << e;
}

TEST(PeridigmFilters, InitialDamageKeepsTheCutBondsBroken) {
  write_shells();
  const std::string path = write_deck("    NeighborhoodType: \"Spherical\"\n",
                                      "      Damage Model: \"Initial Damage\"\n"
                                      "      Bond Filters:\n"
                                      "        My Shells:\n"
                                      "          Type: \"Exodus Mesh\"\n"
                                      "          File Name: \"shells.g\"\n");
  const YAML::Node native = convert(path);
  EXPECT_EQ(native["precracks"].size(), 1u);
  EXPECT_EQ(native["precracks"][0]["bonds"].as<std::string>(), "broken");
  EXPECT_FALSE(native["materials"]["All"]["damage"]);  // no bond breaks later
  // The bonds: horizon 1.5 on the spacing-1 grid of 8 cells bonds the axis and face-
  // diagonal neighbours (sqrt 2 <= 1.5 < sqrt 3): 48 directed bonds. The quad cuts the x
  // bond at (y, z) = (0.5, 0.5), the two xy diagonals of the layer z = 0.5 and the two xz
  // diagonals of the layer y = 0.5 (5 pairs); the triangle the z bonds at (x, y) = (0.5,
  // 0.5), (1.5, 0.5), (0.5, 1.5), the xz diagonals of y = 0.5 (cut by the quad too) and
  // the yz diagonals of x = 0.5 (7 pairs): 10 pairs, 20 directed bonds, kept broken.
  const System s = build_system(load_deck(path));
  EXPECT_EQ(s.bonds.size(), 48u);
  EXPECT_EQ(s.precrack_bonds, 20u);
  std::size_t intact = 0;
  for (std::size_t k = 0; k < s.bonds.size(); ++k) intact += s.bonds.intact[k] ? 1 : 0;
  EXPECT_EQ(intact, 28u);
  // Under a discretisation's filter the same bonds are never made.
  const std::string filtered = write_deck(
      "    NeighborhoodType: \"Spherical\"\n"
      "    Bond Filters:\n"
      "      My Shells:\n"
      "        Type: \"Exodus Mesh\"\n"
      "        File Name: \"shells.g\"\n");
  EXPECT_EQ(build_system(load_deck(filtered)).bonds.size(), 28u);
}

TEST(PeridigmFilters, BoxNeighbourhoodBecomesFamilyBox) {
  // A PdQuickGrid of nx x ny x 1 cells over 2.1 x 2 x 1.
  auto grid_deck = [](int nx, int ny, double horizon) {
    const fs::path path = test_dir() / "box.yaml";
    std::ofstream(path) << "Peridigm:\n"
                           "  Discretization:\n"
                           "    Type: \"PdQuickGrid\"\n"
                           "    TensorProduct3DMeshGenerator:\n"
                           "      Type: \"PdQuickGrid\"\n"
                           "      X Origin: 0.0\n      Y Origin: 0.0\n      Z Origin: 0.0\n"
                           "      X Length: 2.1\n      Y Length: 2.0\n      Z Length: 1.0\n"
                           "      Number Points X: "
                        << nx << "\n      Number Points Y: " << ny
                        << "\n      Number Points Z: 1\n"
                           "  Materials:\n"
                           "    Steel: {Material Model: \"Elastic\", Density: 7800.0, Bulk Modulus: 130.0e9, "
                           "Shear Modulus: 60.0e9}\n"
                           "  Blocks:\n"
                           "    All: {Block Names: \"block_1\", Material: \"Steel\", Horizon: "
                        << horizon
                        << "}\n"
                           "  Solver:\n"
                           "    Final Time: 1.0e-6\n"
                           "    Verlet: {Fixed dt: 1.0e-7}\n";
    return path.string();
  };
  // BondBreakingInitialVelocity's grid: 2 x 2 x 1 cells of 1.05 x 1 x 1, horizon 0.51:
  // the box of round(0.51/1.05) = 0, round(0.51/1) = 1 and 1 cells bonds the pairs along y,
  // which the sphere of 0.51 would not.
  const std::string path = grid_deck(2, 2, 0.51);
  EXPECT_EQ(flow(convert(path)["family_box"]), "[0, 1, 1]");
  const Config config = load_deck(path);
  ASSERT_TRUE(config.family_box);
  const System s = build_system(config);
  EXPECT_EQ(s.bonds.size(), 4u);  // two pairs along y, both directions
  for (std::size_t i = 0; i < 4; ++i)
    for (uint64_t k = s.bonds.begin(i); k < s.bonds.end(i); ++k) {
      const Vec3 d = s.particles.X[s.bonds.nbr[k]] - s.particles.X[i];
      EXPECT_EQ(d.x, 0);
      EXPECT_EQ(std::abs(d.y), 1);
    }
  // Where the box and the sphere bond the same pairs (a row of 3 cells of 0.7, horizon
  // 0.8: the next neighbours on both sides, in both), the deck is left as it was.
  EXPECT_FALSE(convert(grid_deck(3, 1, 0.8))["family_box"]);
}

TEST(PeridigmFilters, NativeDiskAndFacetsCutTheBondsTheyCross) {
  Precrack disk;
  disk.points = {{0, 0, 0}};
  disk.normal = {0, 1, 0};
  disk.radius = 1;
  EXPECT_TRUE(crosses({0.5, -1, 0.5}, {0.5, 1, 0.5}, disk, 3));   // through |x| = 0.71 < 1
  EXPECT_FALSE(crosses({0.8, -1, 0.8}, {0.8, 1, 0.8}, disk, 3));  // |x| = 1.13 > 1
  EXPECT_FALSE(crosses({0.5, 0.1, 0}, {0.5, 1, 0}, disk, 3));     // one side of the plane
  EXPECT_TRUE(crosses({-1, -1, 0}, {1, 1, 0}, disk, 3));          // oblique, through the centre
  Precrack surface;
  set_facets(surface, {{{1, 0, 0}, {1, 1.2, 0}, {1, 1.2, 1.2}, {1, 0, 1.2}}, {{0, 0, 1}, {2.4, 0, 1}, {0, 2.4, 1}}});
  EXPECT_TRUE(crosses({0.5, 0.5, 0.5}, {1.5, 0.5, 0.5}, surface, 3));   // the quad
  EXPECT_FALSE(crosses({0.5, 1.5, 0.5}, {1.5, 1.5, 0.5}, surface, 3));  // beside the quad
  EXPECT_TRUE(crosses({0.5, 0.5, 0.5}, {0.5, 0.5, 1.5}, surface, 3));   // the triangle
  EXPECT_FALSE(crosses({1.5, 1.5, 0.5}, {1.5, 1.5, 1.5}, surface, 3));  // x + y = 3 > 2.4
  // Facets are closed: a bond through the edge two facets share is cut (Peridigm's
  // QuadBondFilter and PrecrackedPlate golds), where an open polygon keeps it.
  Precrack two;
  set_facets(two, {{{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}}, {{1, 1, 0}, {1, 2, 0}, {1, 2, 1}, {1, 1, 1}}});
  EXPECT_TRUE(crosses({0.5, 1, 0.5}, {1.5, 1, 0.5}, two, 3));
  EXPECT_TRUE(crosses({0.5, 2, 0.5}, {1.5, 2, 0.5}, two, 3));   // the outer edge too
  EXPECT_FALSE(crosses({0.5, 2.01, 0.5}, {1.5, 2.01, 0.5}, two, 3));
  Precrack open;
  open.points = {{1, 0, 0}, {1, 2, 0}, {1, 2, 1}, {1, 0, 1}};
  EXPECT_TRUE(crosses({0.5, 1, 0.5}, {1.5, 1, 0.5}, open, 3));
  EXPECT_FALSE(crosses({0.5, 2, 0.5}, {1.5, 2, 0.5}, open, 3));
  Vec3 lo, hi;
  bounding_box(surface, lo, hi);
  EXPECT_EQ(lo.x, 0);
  EXPECT_EQ(hi.x, 2.4);
  EXPECT_EQ(hi.y, 2.4);
  EXPECT_EQ(lo.z, 0);
  bounding_box(disk, lo, hi);
  EXPECT_EQ(lo.x, -1);
  EXPECT_EQ(hi.z, 1);
}

}  // namespace horizon
