// Irregular point clouds (family/bonds.hpp): when nearly every bond has its own length,
// the bonds keep their lengths per bond instead of a kind per bond. The reference data
// are the same values, the fast loops give the same bits as with kinds (every path, any
// thread count), and the memory estimate is not below what the run allocates.
#include <gtest/gtest.h>
#include <malloc.h>
#include <omp.h>

#include <cstdio>
#include <cstring>
#include <string>

#include "horizon/deck/deck.hpp"
#include "horizon/family/neighbors.hpp"
#include "horizon/loading/loads.hpp"
#include "horizon/solver/explicit.hpp"
#include "horizon/solver/forces.hpp"
#include "horizon/solver/build.hpp"
#include "horizon/solver/memory_guard.hpp"
#include "test_helpers.hpp"

namespace horizon {
namespace {

// A block of 12 x 10 x 8 cells of 1 mm, each point moved by up to `jitter` cells along
// each axis (as bench/clouds/cylinder.py moves its rings), volume one cell.
Shape cloud(double jitter) {
  test::Rng rng(42);
  std::vector<Vec3> at;
  std::vector<double> volume;
  const double h = 1e-3;
  for (int k = 0; k < 8; ++k)
    for (int j = 0; j < 10; ++j)
      for (int i = 0; i < 12; ++i) {
        Vec3 x{(i + 0.5) * h, (j + 0.5) * h, (k + 0.5) * h};
        for (int a = 0; a < 3; ++a) x[a] += rng.uniform(-jitter, jitter) * h;
        at.push_back(x);
        volume.push_back(h * h * h);
      }
  return Shape::points(std::move(at), std::move(volume));
}

// PMB or LPS with breaking, the compression term and short-range contact, so that every
// per-bond constant the loops finish from |xi| is used (stretch, pair, contact distance);
// the block pulled apart along x and squeezed along y.
Config deck(const std::string& model, double jitter, bool contact = true) {
  const std::string material = model == "pmb" ? "{model: pmb, density: 2200, micromodulus: 1.0e21, "
                                                 "damage: {critical_stretch: 0.002, alpha: 0.25}}"
                                               : "{model: lps, density: 2200, bulk_modulus: 14.9e9, "
                                                 "shear_modulus: 14.9e9, damage: {critical_stretch: 0.002, "
                                                 "alpha: 0.25, breaks: after_force}}";
  Config c = parse_deck("dimension: 3\nspacing: 1.0e-3\nhorizon: 3.015e-3\nmaterials:\n  m: " + material +
                            "\nbodies:\n  - {name: b, material: m, shape: {points: [[0, 0, 0, 1]]}}\n" +
                            std::string(contact ? "contact:\n  short_range: {stiffness_factor: 15, reference_fraction: 0.9, "
                                       "max_distance: 1.35}\n"
                                     : "") +
                            "initial_conditions:\n  - {velocity: [\"100*(x-0.006)/0.006\", \"-50*(y-0.005)/0.005\", 0]}\n"
                            "solver: {end_time: 1.0e-6, time_step: 5.0e-8}\noutput: {damage_measure: volume}\n",
                        "cloud.yaml");
  c.bodies[0].shape = cloud(jitter);
  return c;
}

struct Snapshot {
  std::vector<Vec3> u, v, f;
  std::vector<double> damage, dissipated;
  uint64_t broken = 0;
};

// 20 steps; `kinds`: the same cloud with kinds that carry their lengths (expand_kinds).
Snapshot run(const Config& c, bool kinds, KernelPath path, int threads) {
  set_kernel_path(path);
  omp_set_num_threads(threads);
  System s = build_system(c);
  EXPECT_TRUE(s.bonds.length_per_bond);
  if (kinds) {
    expand_kinds(s.bonds);
    build_kind_coefficients(s, c.output.damage_measure);
    EXPECT_FALSE(s.bonds.length_per_bond);
  }
  Loads loads(c, s);
  loads.apply_initial_conditions(c, s);
  ExplicitSolver solver(s, loads, 5e-8, 0.0);
  solver.initialize();
  for (int step = 0; step < 20; ++step) solver.step(step % 10 == 0);
  set_kernel_path(KernelPath::automatic);
  return {s.particles.u, s.particles.v, s.particles.f, s.particles.damage, s.dissipated_at, s.broken};
}

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

TEST(Clouds, JitteredPointsKeepTheirLengthsPerBondLatticesKeepKinds) {
  const test::SingleThread one;
  const Config c = deck("lps", 0.05);
  const System s = build_system(c);
  ASSERT_TRUE(s.bonds.length_per_bond);
  EXPECT_EQ(s.bonds.lengths.size(), s.bonds.size());
  EXPECT_LE(s.bonds.kinds.size(), 4u);  // one volume, one material
  // The same reference data, bond by bond, as kinds with lengths and the brute-force search.
  Bonds expanded = s.bonds;
  expand_kinds(expanded);
  EXPECT_FALSE(expanded.length_per_bond);
  EXPECT_GT(expanded.kinds.size(), s.bonds.size() / 3);  // nearly every pair its own length
  const Bonds brute = find_neighbors_brute_force(s.particles.X, s.particles.volume, 3.015e-3);
  ASSERT_EQ(brute.size(), s.bonds.size());
  for (std::size_t k = 0; k < s.bonds.size(); ++k) {
    ASSERT_EQ(s.bonds.nbr[k], brute.nbr[k]);
    ASSERT_EQ(s.bonds.length[k], brute.length[k]) << k;
    ASSERT_EQ(s.bonds.length[k], expanded.length[k]) << k;
    ASSERT_EQ(s.bonds.volume[k], expanded.volume[k]) << k;
    ASSERT_EQ(s.bonds.weight[k], expanded.weight[k]) << k;
  }
  // Without the jitter the cloud is a lattice: kinds.
  EXPECT_FALSE(build_system(deck("lps", 0.0)).bonds.length_per_bond);
  // A model off the fast loops reads kinds with lengths.
  Config ep = deck("lps", 0.05);
  ep.materials[0].influence = InfluenceKind::inverse;
  EXPECT_FALSE(build_system(ep).bonds.length_per_bond);
}

TEST(Clouds, LengthsPerBondGiveTheSameBitsAsKinds) {
  const int saved = omp_get_max_threads();
  for (const std::string model : {"pmb", "lps"}) {
    const Config c = deck(model, 0.05);
    const Snapshot ref = run(c, true, KernelPath::scalar, 1);
    EXPECT_GT(ref.broken, 0u) << model;
    std::printf("[ clouds ] %s: %llu directed bonds broken\n", model.c_str(),
                static_cast<unsigned long long>(ref.broken));
    for (const auto& [path, threads] : {std::pair{KernelPath::scalar, 1}, std::pair{KernelPath::avx2, 1},
                                         std::pair{KernelPath::automatic, 1}, std::pair{KernelPath::automatic, 2}}) {
      const Snapshot o = run(c, false, path, threads);
      EXPECT_EQ(ref.broken, o.broken) << model;
      EXPECT_TRUE(same_bits(ref.u, o.u)) << model << " path " << static_cast<int>(path) << ", " << threads;
      EXPECT_TRUE(same_bits(ref.v, o.v)) << model;
      EXPECT_TRUE(same_bits(ref.f, o.f)) << model;
      EXPECT_TRUE(same_bits(ref.damage, o.damage)) << model;
      EXPECT_TRUE(same_bits(ref.dissipated, o.dissipated)) << model;
    }
  }
  omp_set_num_threads(saved);
}

// What the heap holds (glibc: small blocks and mmapped ones).
double heap_bytes() {
  const struct mallinfo2 m = mallinfo2();
  return static_cast<double>(m.uordblks + m.hblkhd);
}

TEST(Clouds, MemoryEstimateIsNotBelowTheAllocation) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer replaces malloc: the heap counter reads 0 there";
#endif
  const test::SingleThread one;
  for (double jitter : {0.0, 0.05}) {
    const Config c = deck("lps", jitter, false);
    const double before = heap_bytes();
    System s = build_system(c);
    Loads loads(c, s);
    loads.apply_initial_conditions(c, s);
    ExplicitSolver solver(s, loads, 5e-8, 0.0);
    solver.initialize();
    solver.step(true);
    const double used = heap_bytes() - before;
    // The heap's share of the estimate (the program's code and libraries are not on it).
    const double estimate = static_cast<double>(memory_estimate(s) - kCodeBytes);
    const double guard = estimate_memory(c).bytes;
    std::printf("[ clouds ] jitter %.2f: %zu kinds, %zu bonds; allocated %.2f MiB, estimate %.2f MiB, guard %.2f MiB\n",
                jitter, s.bonds.kinds.size(), s.bonds.size(), used / 1048576, estimate / 1048576, guard / 1048576);
    EXPECT_GE(estimate, used) << "jitter " << jitter;
    EXPECT_GE(guard, used) << "jitter " << jitter;
    // Close: every array counted, the fixed allowance aside (and that of an output frame,
    // which this run does not write).
    EXPECT_LE(estimate - static_cast<double>(kProgramBytes - kCodeBytes), 1.25 * used) << "jitter " << jitter;
  }
}

}  // namespace
}  // namespace horizon
