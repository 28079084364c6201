#include "horizon/output/truss.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <limits>

#include "horizon/core/error.hpp"
#include "horizon/output/atomic_file.hpp"
#include "horizon/family/bond_helpers.hpp"

namespace horizon {

TrussNetwork truss_network(const System& s) {
  const auto& P = s.particles;
  const auto& B = s.bonds;
  const auto& M = s.model;
  if (s.models.owner() || !s.models.all_unified())
    throw Error("the truss view needs bond-based materials; a material of this deck computes its own force pass");
  const std::size_t n = P.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (M.dilatation_coef[i] != 0 || M.deviatoric_coef[i] != 0) {
      throw Error("the truss view needs bond-based materials: particle " + std::to_string(i) + " (body '" +
                  s.block_names.at(static_cast<std::size_t>(P.block[i])) +
                  "') has a state-based (dilatation) part, whose bonds are not independent trusses");
    }
  }
  TrussNetwork net;
  net.mass.resize(n);
  for (std::size_t i = 0; i < n; ++i) net.mass[i] = P.density[i] * P.volume[i];
  // Force on i per unit stretch of bond k = i->j: V_i omega (R_i + R_j) v_j (state/system.hpp).
  auto axial = [&](std::size_t i, uint64_t k) {
    const BondKind& c = B.kind_of(k);
    return P.volume[i] * c.weight * (M.pair_coef[i] + M.pair_coef[B.nbr[k]]) * c.volume * c.fraction;
  };
  const std::vector<uint64_t> reverse = reverse_bonds(B);
  for (std::size_t i = 0; i < n; ++i) {
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
      const uint32_t j = B.nbr[k];
      if (j < i) continue;  // each pair once, from its lower end
      Truss t;
      t.i = static_cast<uint32_t>(i);
      t.j = j;
      t.length = B.kind_of(k).length;
      t.stiffness = axial(i, k);
      // The other end's copy of the bond gives the same truss (Newton's third law).
      const double other = axial(j, reverse[k]);
      if (!(std::abs(other - t.stiffness) <= 1e-12 * std::abs(t.stiffness))) {
        throw Error(fmt::format("bond {}-{}: the two ends give the axial stiffnesses {:.17g} and {:.17g} N; no truss view",
                                i, j, t.stiffness, other));
      }
      t.section = std::cbrt(P.volume[i] * P.volume[j]);
      t.failure_strain = std::min(M.critical_stretch[i], M.critical_stretch[j]);
      t.intact = B.intact[k] != 0;
      net.trusses.push_back(t);
    }
  }
  return net;
}

void write_truss_file(const std::string& path, const System& s, const TrussNetwork& net) {
  const auto& P = s.particles;
  std::string text;
  text += "# Horizon truss export (docs/input.md, \"horizon export-truss\"): the bond network as truss\n";
  text += "# elements (Macek and Silling, seed 002 sec. 6). Truss force = EA * strain along the deformed\n";
  text += "# truss, strain = (l - L)/L; trusses have zero density; nodes carry lumped masses. SI units.\n";
  text += fmt::format("dimension {}\n", s.dimension);
  text += fmt::format("nodes {}\n", P.size());
  text += "# node x y z mass volume block\n";
  for (std::size_t i = 0; i < P.size(); ++i) {
    text += fmt::format("{} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} {}\n", i + 1, P.X[i].x, P.X[i].y, P.X[i].z,
                        net.mass[i], P.volume[i], s.block_names.at(static_cast<std::size_t>(P.block[i])));
  }
  text += fmt::format("trusses {}\n", net.trusses.size());
  text += "# truss node_i node_j L EA A E failure_strain intact\n";
  std::size_t id = 0;
  for (const auto& t : net.trusses) {
    const std::string fail = std::isfinite(t.failure_strain) ? fmt::format("{:.17g}", t.failure_strain) : "inf";
    text += fmt::format("{} {} {} {:.17g} {:.17g} {:.17g} {:.17g} {} {}\n", ++id, t.i + 1, t.j + 1, t.length,
                        t.stiffness, t.section, t.stiffness / t.section, fail, t.intact ? 1 : 0);
  }
  write_file_atomic(path, text);
}

}  // namespace horizon
