// Check 2 (docs/verification.md): a 3-D LPS block under a small uniform stretch, run to
// rest with damping, gives Young's modulus and Poisson's ratio within 3 % in its interior.
//
// examples/block_tension.yaml: 20 x 10 x 10 spacings, horizon 3 spacings, a traction of
// 20 MPa on each end layer, mass-proportional damping. At rest:
// - the strains are the least-squares displacement gradient over the particles more than
//   one horizon from every surface (the interior, 14 x 4 x 4 particles);
// - the interior stress is the force of the bonds that cross the mid-plane inside the
//   interior square, over its area (the Lehoucq-Silling force flux). The end force over
//   the whole section is not the interior stress: the layers within a horizon of the free
//   surfaces are stiffer and carry more than their share, so F/A over the interior strain
//   overestimates E by 11 % at this size (the surface effect; reported, not asserted).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "horizon/solver/forces.hpp"
#include "verification_support.hpp"

namespace horizon::verification {
namespace {

struct TensionResult {
  double youngs_interior = 0;  // interior stress / interior axial strain
  double youngs_apparent = 0;  // end force / section area / interior axial strain
  double poisson = 0;          // -lateral / axial strain, interior
  double interior_stress = 0;
  double end_force = 0;
};

// Runs a block_tension deck to its end time and measures E and nu as described above.
TensionResult run_block(Config config) {
  const double traction = config.loads.at(1).value[0]->operator()(0, 0, 0, 0);
  const Box3 box = config.bodies.at(0).shape.bounds();
  Simulation sim(std::move(config));
  const System& s = sim.system;
  const auto& P = s.particles;

  sim.run_to(sim.config.solver.end_time);
  sim.solver->step(true);  // brings the ledger's energies up to date
  const Ledger& g = sim.solver->ledger();
  EXPECT_LT(g.kinetic, 1e-9 * g.strain) << "the block is not at rest: run longer or damp more";

  const double d = s.horizon;
  std::vector<std::size_t> interior;
  for (std::size_t i = 0; i < P.size(); ++i) {
    bool inside = true;
    for (int k = 0; k < 3; ++k) inside = inside && P.X[i][k] > box.min[k] + d && P.X[i][k] < box.max[k] - d;
    if (inside) interior.push_back(i);
  }
  EXPECT_GE(interior.size(), 100u);
  const Eigen::Matrix3d G = displacement_gradient(P, interior);
  // Uniaxial stress along x: no shear, equal lateral strains (the square section).
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      if (r != c) {
        EXPECT_LT(std::abs(G(r, c)), 1e-3 * G(0, 0)) << "G(" << r << "," << c << ")";
      }
  EXPECT_NEAR(G(1, 1) / G(2, 2), 1.0, 1e-6);

  // The interior square of the mid-plane: y, z more than one horizon from the faces. The
  // mid-plane lies between two lattice layers (an even number of layers).
  const double lo = box.min.y + d, hi = box.max.y - d;
  EXPECT_NEAR(box.max.y - box.min.y, box.max.z - box.min.z, 1e-12);
  const Vec3 F_interior = force_through_patch(s, 0, 0.5 * (box.min.x + box.max.x), lo, hi);
  const double area = (box.max.y - box.min.y) * (box.max.z - box.min.z);

  TensionResult r;
  r.end_force = sim.loads.loads().at(1).reaction.x;
  EXPECT_NEAR(r.end_force, traction * area, 1e-9 * traction * area) << "the traction's total force";
  r.interior_stress = F_interior.x / ((hi - lo) * (hi - lo));
  r.youngs_interior = r.interior_stress / G(0, 0);
  r.youngs_apparent = traction / G(0, 0);
  r.poisson = -0.5 * (G(1, 1) + G(2, 2)) / G(0, 0);
  return r;
}

// Young's modulus and Poisson's ratio of the infinite lattice loaded along a lattice axis:
// C11 and C12 from the strain energy density of an interior particle of a cube under
// homogeneous strains (u = eps X), then E = (C11 - C12)(C11 + 2 C12)/(C11 + C12) and
// nu = C12/(C11 + C12) of a cubic crystal pulled along [100].
std::pair<double, double> lattice_constants_along_x(const Config& deck) {
  Config c = deck;
  const double h = c.spacing;
  const int n = 2 * static_cast<int>(std::ceil(c.horizon / h)) + 3;
  c.bodies.resize(1);
  c.bodies[0].shape = Shape::box({0, 0, 0}, Vec3{1, 1, 1} * (n * h));
  c.loads.clear();
  c.regions.clear();
  c.initial_conditions.clear();
  System s = build_system(c);
  const std::size_t mid = [&] {
    std::size_t best = 0;
    const Vec3 centre = Vec3{1, 1, 1} * (0.5 * n * h);
    for (std::size_t i = 0; i < s.particles.size(); ++i)
      if (norm2(s.particles.X[i] - centre) < norm2(s.particles.X[best] - centre)) best = i;
    return best;
  }();
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
  const TensionResult r = run_block(config);
  report("youngs_interior", r.youngs_interior,
         fmt::format("LPS block, interior: E = {:.2f} GPa ({:+.2f} %) from the interior stress {:.2f} MPa", 
                     r.youngs_interior / 1e9, 100 * (r.youngs_interior / E - 1), r.interior_stress / 1e6));
  report("poisson_interior", r.poisson,
         fmt::format("LPS block, interior: nu = {:.4f} ({:+.2f} %), nominal {}", r.poisson, 100 * (r.poisson / nu - 1), nu));
  report("youngs_apparent", r.youngs_apparent,
         fmt::format("LPS block: end force / section over the interior strain gives E = {:.2f} GPa ({:+.2f} %): the "
                     "surface effect", r.youngs_apparent / 1e9, 100 * (r.youngs_apparent / E - 1)));
  EXPECT_NEAR(r.youngs_interior / E, 1.0, 0.03);
  EXPECT_NEAR(r.poisson / nu, 1.0, 0.03);
}

// The same block with omega = 1: the cubic lattice with a horizon of 3 spacings makes
// the LPS anisotropic (docs/models.md section 8: its shear energy is off by up to 11 %),
// so E and nu along a lattice axis miss the nominal values by 12 % and 9 %. The check
// here is that the block's interior still has the constants of the discrete lattice
// (computed from homogeneous deformations): the solver reaches the right rest state of
// the discrete model, whose anisotropy is what the nominal comparison sees.
TEST(UniaxialTension, ConstantInfluenceBlockMatchesItsAnisotropicLattice) {
  Config config = load_deck(source_path("examples/block_tension.yaml"));
  config.materials.at(0).influence = InfluenceKind::constant;
  const double E = config.materials.at(0).youngs_modulus, nu = config.materials.at(0).poissons_ratio;
  const auto [E_lattice, nu_lattice] = lattice_constants_along_x(config);
  const TensionResult r = run_block(config);
  report("youngs_constant_influence", r.youngs_interior,
         fmt::format("LPS block, omega = 1: E = {:.2f} GPa ({:+.2f} % from nominal), lattice along x {:.2f} GPa "
                     "({:+.2f} %)", r.youngs_interior / 1e9, 100 * (r.youngs_interior / E - 1), E_lattice / 1e9,
                     100 * (E_lattice / E - 1)));
  report("poisson_constant_influence", r.poisson,
         fmt::format("LPS block, omega = 1: nu = {:.4f} ({:+.2f} % from nominal), lattice along x {:.4f} ({:+.2f} %)",
                     r.poisson, 100 * (r.poisson / nu - 1), nu_lattice, 100 * (nu_lattice / nu - 1)));
  EXPECT_NEAR(r.youngs_interior / E_lattice, 1.0, 0.03);
  EXPECT_NEAR(r.poisson / nu_lattice, 1.0, 0.03);
}

}  // namespace
}  // namespace horizon::verification
