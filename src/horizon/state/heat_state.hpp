#pragma once
// The temperature field of a body and what its conduction needs, per particle and per
// bond kind (thermal/heat.hpp computes with it). Plain data: System holds one; it is
// empty (active() false) in runs without a thermal section.
#include <cstdint>
#include <string>
#include <vector>

#include "horizon/core/expression.hpp"
#include "horizon/core/vec3.hpp"
#include "horizon/deck/config.hpp"

namespace horizon {

// A boundary condition on a set of particles (deck: thermal.boundary).
struct HeatBoundary {
  std::string name;  // "region:kind", the history column prefix
  ThermalBoundaryKind kind = ThermalBoundaryKind::temperature;
  std::vector<uint32_t> particles;
  Expression value;        // temperature [K] or flux [W/m^2]
  double coefficient = 0;  // convection: h [W/(m^2 K)]
  Expression ambient;      // convection: ambient temperature [K]
  double scale = 1;        // flux and convection: 1/d, d the depth of the layer (as tractions)
  double heat = 0;         // heat it brought into the body so far [J]
};

struct HeatState {
  std::vector<double> T;          // temperature [K]
  std::vector<double> capacity;   // rho c [J/(m^3 K)]
  std::vector<double> kappa;      // micro-conductivity kappa_i (the bond uses (kappa_i + kappa_j)/2)
  std::vector<double> expansion;  // alpha_i [1/K]
  std::vector<double> reference;  // T_ref,i [K]
  std::vector<double> plastic_fraction;  // Taylor-Quinney beta_i
  std::vector<double> stretch_slope;     // d(s0/s0_ref)/dT [1/K] (temperature-dependent critical stretch)
  std::vector<double> kind_factor;       // per bond kind: g(|xi|) V_j (partial-volume scaled)
  // Per bond, where the kinds cannot hold it: g(|xi|) omega_ij with the improved
  // quadrature's weights, or g(|xi|) V_j when the bonds keep their own lengths (meshes'
  // centroids: Bonds::length_per_bond). Empty: kind_factor. (thermal/heat.cpp bond_factor)
  std::vector<double> bond_factor;
  std::vector<uint8_t> fixed;            // 1: temperature prescribed by a boundary condition
  std::vector<Vec3> flux;                // heat flux vector q_i [W/m^2] (output)
  std::vector<HeatBoundary> boundary;
  HeatKernel kernel = HeatKernel::inverse;
  HeatCalibration calibration = HeatCalibration::continuum;
  HeatQuadrature quadrature = HeatQuadrature::one_point;  // improved: a_ij != a_ji (BiCGSTAB solves)
  bool conduction = true;  // false: T is a prescribed field (thermal.conduction: false), no heat flows
  bool expands = false;    // some material has alpha != 0: mechanics sees the thermal strain
  bool softens = false;    // some material has a critical_stretch_slope != 0
  double plastic_heat = 0; // heat released by plastic work so far [J]
  double time = 0;         // the time of T [s]

  bool active() const { return !T.empty(); }
};

}  // namespace horizon
