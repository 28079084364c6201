#pragma once
// The ordinary history models' part of the CUDA backend (cuda_backend.cu's FlatRun):
// device copies of a kernels::FlatOrdinary's arrays and the kernels of its pass
// (kernels/flat_ordinary.hpp), one thread a particle. Internal to src/horizon/cuda/.
#include <cstdint>
#include <vector>

#include "horizon/kernels/flat_system.hpp"

namespace horizon::cuda {

// Copies h's arrays (of a run with n particles, nb bonds, nkinds kinds) to the device:
// `device` gets h with device pointers (for download_ordinary), and the returned address
// is a device copy of that struct, for FlatSystem::ordinary on the device. The
// allocations go to `owned`.
const kernels::FlatOrdinary* upload_ordinary(const kernels::FlatOrdinary& h, uint64_t n, uint64_t nb,
                                             uint64_t nkinds, kernels::FlatOrdinary& device,
                                             std::vector<void*>& owned);
// The model's state back into h's arrays (what flat_ordinary_write_back reads).
void download_ordinary(const kernels::FlatOrdinary& h, const kernels::FlatOrdinary& device, uint64_t n, uint64_t nb);
// One force pass (kernels::flat_ordinary_forces): pack, the rows, the sums, the flip.
void ordinary_pass(const kernels::FlatSystem& d, unsigned grid, int block);

}  // namespace horizon::cuda
