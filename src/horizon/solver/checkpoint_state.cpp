// The system's part of a checkpoint (state/system.hpp checkpoint_system).
#include "horizon/solver/build.hpp"

#include "horizon/fe/fe_region.hpp"
#include "horizon/parallel/decomposition.hpp"

namespace horizon {

void checkpoint_system(System& s, StateArchive& a) {
  auto& P = s.particles;
  auto& M = s.model;
  const std::size_t n = P.size(), nb = s.bonds.size();
  // The whole system's count: a run with local particles (parallel/decomposition.hpp)
  // holds fewer here, and the file every particle (gather_checkpoint).
  const Decomposition* d = s.decomposition;
  a.check("particles", d && d->local_particles ? d->global_particles : n, "particles");
  // The whole system's count: a run with local rows (parallel/decomposition.hpp) holds
  // fewer here, and the file the whole system's bonds (gather_checkpoint).
  a.check("bonds", checkpoint_bond_count(s), "bonds");
  a.check("materials", s.models.size(), "materials");
  for (std::size_t m = 0; m < s.models.size(); ++m)
    a.check("model " + std::to_string(m), s.models[m].traits().name, "for material " + std::to_string(m) + " the model");

  a.io_sized("u", P.u, n, Extent::particles);
  a.io_sized("v", P.v, n, Extent::particles);
  a.io_sized("f", P.f, n, Extent::particles);
  a.io_sized("b", P.b, n, Extent::particles);
  a.io_sized("damage", P.damage, n, Extent::particles);
  a.io_sized("energy", P.energy, n, Extent::particles);
  a.io_sized("intact", s.bonds.intact, nb, Extent::bonds);

  // The shared model arrays that the force passes change (the rest is set up from the deck).
  a.io_particles("min_stretch", M.min_stretch);
  a.io_particles("theta", M.theta);
  a.io_particles("P", M.P);
  a.io_particles("damage_total", M.damage_total);
  a.io_particles("intact_weight", M.intact_weight);
  a.io_bonds("deformed_length", M.deformed_length);
  a.io_bonds("force_state", M.force_state);
  a.io_bonds("force_scalar", M.force_scalar);
  a.io_particles("affine_record", M.affine_record);
  a.io_particles("affine_position", M.affine_position);

  a.io("time", s.time);
  a.io("dt", s.dt);
  a.io_sized("dissipated_at", s.dissipated_at, s.dissipated_at.size(), Extent::particles);
  a.io("broken", s.broken);
  // The temperature and what follows from it are per particle: on ranks each entry comes
  // from its owner (thermal/heat.cpp advances the owned temperatures).
  a.io_particles("thermal_strain", s.thermal_strain);
  a.io_particles("critical_stretch_factor", s.critical_stretch_factor);

  auto& H = s.heat;
  a.check("heat boundaries", H.boundary.size(), "thermal boundary conditions");
  a.io_particles("heat_T", H.T);
  a.io_particles("heat_flux", H.flux);
  for (auto& bc : H.boundary) a.io("heat_boundary " + bc.name, bc.heat);
  a.io("heat_plastic", H.plastic_heat);
  a.io("heat_time", H.time);

  // The elements' plastic history (fe/fe_region.hpp; only a deck with J2 elements has it)
  // and the coupling's energy account (every deck with elements).
  if (s.fe) {
    a.push("fe");
    if (s.fe->plastic()) s.fe->checkpoint(a);
    s.fe->checkpoint_account(a);
    a.pop();
  }
  for (std::size_t m = 0; m < s.models.size(); ++m) {
    a.push("model " + std::to_string(m));
    s.models[m].checkpoint(a);
    a.pop();
  }
}

}  // namespace horizon
