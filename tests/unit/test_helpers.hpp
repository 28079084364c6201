#pragma once
// Small bodies built in code for the physics tests: a lattice block of one material
// (through Config + build_system, the path a deck takes), the classical energy of a
// homogeneous strain, and a portable deterministic random source.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <omp.h>

#include "horizon/deck/config.hpp"
#include "horizon/material/constants.hpp"
#include "horizon/solver/build.hpp"
#include "../single_thread.hpp"

namespace horizon::test {

// A material with all four isotropic constants filled in from E and nu (as the deck does).
inline MaterialConfig make_material(const std::string& model, double E, double nu, double density = 2000.0,
                                    InfluenceKind omega = InfluenceKind::constant) {
  MaterialConfig m;
  m.name = "solid";
  m.model = model;
  m.density = density;
  m.youngs_modulus = E;
  m.poissons_ratio = nu;
  m.bulk_modulus = E / (3 * (1 - 2 * nu));
  m.shear_modulus = E / (2 * (1 + nu));
  m.influence = omega;
  return m;
}

// A block of n[0] x n[1] x n[2] lattice points (only the first `dimension` counts are
// used) at X = (i, j, k) * spacing, i.e. lattice_origin = 0.
struct BlockSpec {
  int dimension = 3;
  PlaneMode plane = PlaneMode::none;  // 2-D: stress or strain
  std::array<int, 3> n{8, 8, 8};
  double spacing = 1e-3;
  double horizon_factor = 3;  // horizon = factor * spacing
  double thickness = 1e-3;    // 2-D
  double area = 1e-6;         // 1-D
  bool partial_volume = false;
};

inline Config block_config(const BlockSpec& b, const MaterialConfig& mat) {
  Config c;
  c.dimension = b.dimension;
  c.plane = b.dimension == 2 ? b.plane : PlaneMode::none;
  c.thickness = b.thickness;
  c.area = b.area;
  c.spacing = b.spacing;
  c.horizon = b.horizon_factor * b.spacing;
  c.lattice_origin = Vec3{};
  c.partial_volume = b.partial_volume;
  c.materials = {mat};
  Vec3 lo, hi;
  for (int k = 0; k < 3; ++k) {
    lo[k] = -0.5 * b.spacing;
    hi[k] = k < b.dimension ? (b.n[k] - 0.5) * b.spacing : 0.5 * b.spacing;
  }
  c.bodies = {BodyConfig{"block", mat.name, Shape::box(lo, hi)}};
  return c;
}

inline System make_block(const BlockSpec& b, const MaterialConfig& mat) { return build_system(block_config(b, mat)); }

inline Dimensioning dimensioning_of(const Config& c) { return {c.dimension, c.plane, c.thickness, c.area, c.horizon}; }

// Particles whose whole family lies inside the block: at least one horizon from every
// face of the block of lattice points.
inline std::vector<std::size_t> interior_particles(const System& s, const BlockSpec& b) {
  std::vector<std::size_t> ids;
  const double h = b.spacing, r = b.horizon_factor;
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    bool inside = true;
    for (int k = 0; k < b.dimension; ++k) {
      const double index = s.particles.X[i][k] / h;
      if (index < r - 1e-9 || index > (b.n[k] - 1) - r + 1e-9) inside = false;
    }
    if (inside) ids.push_back(i);
  }
  return ids;
}

// Lattice offsets n (integer vectors) of a complete family: |n| <= horizon_factor.
inline std::vector<Vec3> family_offsets(const BlockSpec& b) {
  std::vector<Vec3> out;
  // Partial volumes extend the family to horizon + spacing/2 (family_radius).
  const double reach = b.horizon_factor + (b.partial_volume ? 0.5 : 0.0);
  const int r = static_cast<int>(std::ceil(reach));
  const int rz = b.dimension > 2 ? r : 0, ry = b.dimension > 1 ? r : 0;
  for (int k = -rz; k <= rz; ++k)
    for (int j = -ry; j <= ry; ++j)
      for (int i = -r; i <= r; ++i) {
        const double n2 = i * i + j * j + k * k;
        if (n2 > 0 && n2 <= reach * reach * (1 + 1e-12))
          out.push_back(Vec3{1.0 * i, 1.0 * j, 1.0 * k});
      }
  return out;
}

inline double cell_volume(const BlockSpec& b) {
  const double h = b.spacing;
  if (b.dimension == 3) return h * h * h;
  if (b.dimension == 2) return h * h * b.thickness;
  return h * b.area;
}

// Volume of a neighbour at distance r, with the partial-volume rule when enabled
// (written out here, independently of apply_partial_volume).
inline double neighbour_volume(const BlockSpec& b, double r) {
  const double d = b.horizon_factor * b.spacing, h = b.spacing;
  double v = cell_volume(b);
  if (b.partial_volume && r > d - 0.5 * h) v *= std::clamp((d + 0.5 * h - r) / h, 0.0, 1.0);
  return v;
}

// A symmetric small strain, stored as a full 3x3 matrix.
using Strain = std::array<std::array<double, 3>, 3>;

inline Vec3 apply(const Strain& e, const Vec3& x) {
  Vec3 r;
  for (int a = 0; a < 3; ++a) r[a] = e[a][0] * x.x + e[a][1] * x.y + e[a][2] * x.z;
  return r;
}

// Classical strain energy density of a small strain: W = k'/2 (tr e)^2 + mu e_dev:e_dev,
// with the trace and deviator taken over the first `dimension` axes (2-D: in-plane,
// with k' = lps_bulk_modulus, the in-plane bulk modulus of plane stress or strain).
inline double classical_energy(const Strain& e, int dimension, double bulk, double shear) {
  double tr = 0;
  for (int a = 0; a < dimension; ++a) tr += e[a][a];
  double dev2 = 0;
  for (int a = 0; a < dimension; ++a)
    for (int b = 0; b < dimension; ++b) {
      const double d = e[a][b] - (a == b ? tr / dimension : 0.0);
      dev2 += d * d;
    }
  return 0.5 * bulk * tr * tr + shear * dev2;
}

// splitmix64: the same numbers on every platform and standard library.
class Rng {
 public:
  explicit Rng(uint64_t seed) : state_(seed) {}
  uint64_t next() {
    uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  // Uniform in [lo, hi).
  double uniform(double lo = 0.0, double hi = 1.0) {
    return lo + (hi - lo) * static_cast<double>(next() >> 11) * 0x1.0p-53;
  }

 private:
  uint64_t state_;
};

}  // namespace horizon::test
