#pragma once
// Particles as a structure of arrays: one array per field, index = particle.
#include <cstdint>
#include <vector>

#include "horizon/core/vec3.hpp"

namespace horizon {

struct Particles {
  std::vector<Vec3> X;            // reference position [m]
  std::vector<Vec3> u;            // displacement [m]
  std::vector<Vec3> v;            // velocity [m/s]
  std::vector<Vec3> f;            // internal force density [N/m^3]
  std::vector<Vec3> b;            // external force density [N/m^3] (body force, traction)
  std::vector<double> volume;     // [m^3] (2-D: area x thickness; 1-D: length x area)
  std::vector<double> density;    // [kg/m^3]
  std::vector<double> damage;     // phi in [0, 1]
  std::vector<double> energy;     // strain energy density W [J/m^3], filled when asked
  std::vector<int32_t> block;     // index of the body the particle belongs to
  std::vector<int32_t> material;  // index of its material
  std::vector<int64_t> id;        // global id, stable across reordering
  std::vector<uint8_t> no_fail;   // 1: bonds of this particle never break

  std::size_t size() const { return X.size(); }

  // Appends one particle at rest.
  void add(const Vec3& x, double vol, double rho, int32_t blk, int32_t mat) {
    X.push_back(x);
    u.push_back({});
    v.push_back({});
    f.push_back({});
    b.push_back({});
    volume.push_back(vol);
    density.push_back(rho);
    damage.push_back(0);
    energy.push_back(0);
    block.push_back(blk);
    material.push_back(mat);
    id.push_back(static_cast<int64_t>(id.size()));
    no_fail.push_back(0);
  }

  Vec3 position(std::size_t i) const { return X[i] + u[i]; }
};

}  // namespace horizon
