#pragma once
// Model constants from the elastic constants, per dimension. Each formula cites its
// source; docs/models.md collects them and tests/unit/test_constants.cpp checks them.
#include "horizon/deck/config.hpp"

namespace horizon {

struct Dimensioning {
  int dimension = 3;
  PlaneMode plane = PlaneMode::none;
  double thickness = 1;  // 2-D
  double area = 1;       // 1-D
  double horizon = 0;
};

// Poisson's ratio a bond-based material is forced to: 1/4 in 3-D, plane strain and
// 1-D; 1/3 in plane stress (seed 002 digest sec. 2.1 table).
double bond_based_poisson_ratio(int dimension, PlaneMode plane);

// Classical strain energy density per s^2 under isotropic extension s in the given
// dimension, for a bond-based material of Young's modulus E: 9k/2 (3-D), E/(1-nu)
// (plane stress), E/((1+nu)(1-2nu)) (plane strain), E/2 (1-D).
double isotropic_energy_per_s2(double youngs_modulus, const Dimensioning& d);

// PMB micromodulus c such that the peridynamic energy of an isotropic extension,
// W = (1/4) c s^2 int_H omega |xi| dV, equals the classical one (seed 002 eq. 17-18 and
// its 2-D/1-D analogues). With omega = 1: 18k/(pi delta^4), 9E/(pi t delta^3) (plane
// stress), 48E/(5 pi t delta^3) (plane strain), 2E/(A delta^2) (1-D).
double pmb_micromodulus(double youngs_modulus, InfluenceKind omega, const Dimensioning& d);

// Critical stretch for which breaking every bond across a plane costs G0 per unit
// area (seed 002 eq. 26-29): G0 = int_0^delta w0(r) h(r) dr, w0 = c omega(r) s0^2 r / 2,
// with h(r) = pi r^3 (3-D), 2 t r^2 (2-D), A r (1-D). With omega = 1:
// sqrt(5 G0/(9 k delta)) in 3-D, sqrt(4 pi G0/(9 E delta)) plane stress,
// sqrt(5 pi G0/(12 E delta)) plane strain, sqrt(3 G0/(E delta)) 1-D.
double pmb_critical_stretch(double fracture_energy, double micromodulus, InfluenceKind omega,
                            const Dimensioning& d);

// The bulk modulus that multiplies the dilatation in the LPS: k in 3-D; in 2-D,
// lambda + mu (plane strain) or 9 k mu/(3k + 4mu) = E/(2(1-nu)) (plane stress)
// (seed 003 digest sec. 8).
double lps_bulk_modulus(double bulk_modulus, double shear_modulus, const Dimensioning& d);

// LPS deviatoric factor: alpha = 15 mu/m in 3-D (seed 003 eq. 112), 8 mu/m in 2-D
// (seed 003 digest sec. 8).
double lps_deviatoric_factor(int dimension);

// LPS critical stretch from G0 (Madenci and Oterkus 2014, "Peridynamic Theory and Its
// Applications", sec. 5.4: s_c = sqrt(G0 / ((3 mu + (3/4)^4 (k - 5mu/3)) delta)) in 3-D
// and sqrt(G0 / ((6mu/pi + 16/(9 pi^2) (k - 2mu)) delta)) in 2-D).
double lps_critical_stretch(double fracture_energy, double bulk_modulus, double shear_modulus, const Dimensioning& d);

// Micromodulus of the bond-based material with the same bulk modulus, used for the
// stable time step of any model (as Peridigm does: c = 18k/(pi delta^4) in 3-D).
double equivalent_micromodulus(double bulk_modulus, double shear_modulus, InfluenceKind omega, const Dimensioning& d);

}  // namespace horizon
