// Check 2 (docs/verification.md): a 3-D LPS block under a small uniform stretch, run to
// rest with damping, gives Young's modulus and Poisson's ratio within 3 % in its interior.
//
// examples/block_tension.yaml: 20 x 10 x 10 spacings, horizon 3 spacings, partial
// volumes, a traction of 20 MPa on each end layer, mass-proportional damping. At rest
// (measure_tension in verification_support.hpp):
// - the strains are the least-squares displacement gradient over the particles more than
//   one horizon from every surface (the interior, 14 x 4 x 4 particles);
// - the interior stress is the force of the bonds that cross the mid-plane inside the
//   interior square, over its area (the Lehoucq-Silling force flux). The traction over
//   the interior strain is not the interior modulus: the layers within a horizon of the
//   free surfaces are stiffer and carry more than their share of the end force, so that
//   ratio overestimates E by 15 % at this size (the surface effect; reported, not asserted).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>

#include <fmt/format.h>

#include "horizon/solver/forces.hpp"
#include "verification_support.hpp"

namespace horizon::verification {
namespace {

// Young's modulus and Poisson's ratio of the unbounded lattice pulled along a lattice
// axis: C11 and C12 from the strain energy density of an interior particle of a cube
// under homogeneous strains (u = eps X), then E = (C11 - C12)(C11 + 2 C12)/(C11 + C12)
// and nu = C12/(C11 + C12), those of a cubic crystal pulled along [100].
std::pair<double, double> lattice_constants_along_x(const Config& deck) {
  Config c = deck;
  const double h = c.spacing;
  const int n = 2 * static_cast<int>(std::ceil(c.horizon / h)) + 5;
  c.bodies.resize(1);
  c.bodies[0].shape = Shape::box({0, 0, 0}, Vec3{1, 1, 1} * (n * h));
  c.loads.clear();
  c.regions.clear();
  c.initial_conditions.clear();
  System s = build_system(c);
  std::size_t mid = 0;
  const Vec3 centre = Vec3{1, 1, 1} * (0.5 * n * h);
  for (std::size_t i = 0; i < s.particles.size(); ++i)
    if (norm2(s.particles.X[i] - centre) < norm2(s.particles.X[mid] - centre)) mid = i;
  auto energy = [&](double exx, double eyy) {
    for (std::size_t i = 0; i < s.particles.size(); ++i)
      s.particles.u[i] = Vec3{exx * s.particles.X[i].x, eyy * s.particles.X[i].y, 0};
    compute_forces(s, true);
    return s.particles.energy[mid];
  };
  const double e = 1e-7;
  const double C11 = 2 * energy(e, 0) / (e * e);
  const double C12 = energy(e, e) / (e * e) - C11;  // W = (C11 + C12) e^2 for exx = eyy = e
  return {(C11 - C12) * (C11 + 2 * C12) / (C11 + C12), C12 / (C11 + C12)};
}

TEST(UniaxialTension, LpsBlockRecoversYoungsModulusAndPoissonsRatio) {
  const Config config = load_deck(source_path("examples/block_tension.yaml"));
  const double E = config.materials.at(0).youngs_modulus, nu = config.materials.at(0).poissons_ratio;
  const TensionResult r = measure_tension(config);
  EXPECT_EQ(r.interior_particles, 14u * 4u * 4u);
  EXPECT_NEAR(r.end_force, r.traction * 1e-4, 1e-9 * r.traction * 1e-4) << "traction x section area";
  report("youngs_interior", r.youngs_interior,
         fmt::format("LPS block, interior: E = {:.2f} GPa ({:+.2f} %) from the interior stress {:.2f} MPa",
                     r.youngs_interior / 1e9, 100 * (r.youngs_interior / E - 1), r.interior_stress / 1e6));
  report("poisson_interior", r.poisson,
         fmt::format("LPS block, interior: nu = {:.4f} ({:+.2f} %), nominal {}", r.poisson, 100 * (r.poisson / nu - 1),
                     nu));
  report("youngs_apparent", r.youngs_apparent,
         fmt::format("LPS block: traction / interior strain = {:.2f} GPa ({:+.2f} %), traction / section strain = "
                     "{:.2f} GPa ({:+.2f} %), section nu = {:.4f}: the surface effect",
                     r.youngs_apparent / 1e9, 100 * (r.youngs_apparent / E - 1), r.youngs_section / 1e9,
                     100 * (r.youngs_section / E - 1), r.poisson_section));
  EXPECT_NEAR(r.youngs_interior / E, 1.0, 0.03);
  EXPECT_NEAR(r.poisson / nu, 1.0, 0.03);
}

// The same block without partial volumes: on the cubic lattice with a horizon of 3
// spacings the LPS is then anisotropic (docs/models.md section 8: its shear energy is off
// by 11 %), and E and nu along a lattice axis miss the nominal values by 14 % and 15 %.
// The check is that the block's interior has the constants of its discrete lattice
// (computed from homogeneous deformations): the solver reaches the right rest state of
// the discrete model, whose anisotropy is what the nominal comparison sees.
TEST(UniaxialTension, BlockWithoutPartialVolumesMatchesItsAnisotropicLattice) {
  Config config = load_deck(source_path("examples/block_tension.yaml"));
  config.partial_volume = false;
  const double E = config.materials.at(0).youngs_modulus, nu = config.materials.at(0).poissons_ratio;
  const auto [E_lattice, nu_lattice] = lattice_constants_along_x(config);
  const TensionResult r = measure_tension(config);
  report("youngs_no_partial_volume", r.youngs_interior,
         fmt::format("LPS block, no partial volumes: E = {:.2f} GPa ({:+.2f} % from nominal), lattice along x "
                     "{:.2f} GPa ({:+.2f} %)",
                     r.youngs_interior / 1e9, 100 * (r.youngs_interior / E - 1), E_lattice / 1e9,
                     100 * (E_lattice / E - 1)));
  report("poisson_no_partial_volume", r.poisson,
         fmt::format("LPS block, no partial volumes: nu = {:.4f} ({:+.2f} % from nominal), lattice along x {:.4f} "
                     "({:+.2f} %)",
                     r.poisson, 100 * (r.poisson / nu - 1), nu_lattice, 100 * (nu_lattice / nu - 1)));
  EXPECT_NEAR(r.youngs_interior / E_lattice, 1.0, 0.03);
  EXPECT_NEAR(r.poisson / nu_lattice, 1.0, 0.03);
}

}  // namespace
}  // namespace horizon::verification
