#pragma once
// The correspondence model's part of a flat copy (kernels/flat_affine.hpp FlatAffine): its
// constants, the affine pass's records and positions, and the law's history, copied from
// the model (material/models/correspondence.hpp CorrespondenceState) and written back at
// a frame, a history row, a checkpoint or the end, so that the model, its fields and its
// checkpoint read what the CPU backend leaves.
#include <cstdint>
#include <string>
#include <vector>

#include "horizon/core/vec3.hpp"
#include "horizon/kernels/flat_system.hpp"
#include "horizon/state/system.hpp"

namespace horizon {

struct FlatAffineStorage {
  bool on = false;
  kernels::FlatAffine constants;  // the scalars (the pointers are view()'s)
  std::vector<kernels::FlatAffineLaw> laws;  // per material
  std::vector<uint32_t> material;            // per particle
  std::vector<kernels::FlatPoint> ref, kind_record;
  std::vector<kernels::FlatBondKind> bond_kinds;
  std::vector<double> omega_volume, record, work, von_mises, u_committed, yield_factor, kinv, F, sigma, d, F_pass;
  std::vector<Vec3> y_old;
  std::vector<uint8_t> singular;
  std::vector<kernels::J2History> j2_committed, j2_trial;
  std::vector<kernels::HypoHistory> hypo_committed, hypo_trial;
  kernels::FlatAffine view();
};

// Whether every model of the run (one per material) is correspondence (then
// flat_affine_unsupported says whether the flat rows take it).
bool flat_affine_model(const System& s);
// Why the flat rows cannot take this correspondence run, or "".
std::string flat_affine_unsupported(const System& s);
FlatAffineStorage flat_affine_copy(const System& s);
void flat_affine_write_back(const FlatAffineStorage& c, System& s);

}  // namespace horizon
