#pragma once
// The truss view of a bond-based body (seed 002, Macek and Silling, sec. 6, eq. 44-49):
// multiplying the discrete equation of motion by V_i gives M u'' + F_T = F_e, the form of
// an explicit finite-element code, in which every bond i-j is a truss between nodes i and
// j with axial stiffness EA_ij (truss force = EA_ij s, s the bond stretch = the truss's
// engineering strain), a failure strain, and zero density; the nodes carry lumped masses
// rho_i V_i. From the unified bond form of state/system.hpp, the bond-based part of the
// force of bond i-j on i is omega_ij (R_i + R_j) s V_i v_j (v_j the partial-volume scaled
// neighbour volume), hence EA_ij = omega_ij (R_i + R_j) V_i v_j (= c V_i V_j for PMB with
// c = 2R). The seed's split into a section and a modulus, A = (V_i V_j)^(1/3) and
// E = EA/A (eq. 47), is written alongside. Only bonds whose force has no dilatation part
// are trusses: a material with a state-based part (P, Q of the unified form), or one that
// computes its own force pass, is an error. The file format is in docs/input.md
// ("horizon export-truss").
#include <cstdint>
#include <string>
#include <vector>

#include "horizon/state/system.hpp"

namespace horizon {

struct Truss {
  uint32_t i = 0, j = 0;     // node (particle) indices, i < j
  double length = 0;         // reference length |xi| [m]
  double stiffness = 0;      // EA [N]
  double section = 0;        // A = (V_i V_j)^(1/3) [m^2] (seed 002 eq. 47)
  double failure_strain = 0; // min(s0_i, s0_j); +inf: never fails
  bool intact = true;
};

struct TrussNetwork {
  std::vector<double> mass;  // lumped nodal masses rho_i V_i [kg]
  std::vector<Truss> trusses;
};

// One truss per bond pair (both directed copies must agree; an error if they do not).
TrussNetwork truss_network(const System& s);
// Writes the documented text format; throws Error if the file cannot be written.
void write_truss_file(const std::string& path, const System& s, const TrussNetwork& net);

}  // namespace horizon
