#pragma once
// The ordinary history models' part of a flat copy (kernels/flat_ordinary.hpp): what the
// flat and CUDA backends copy of an elastic_plastic, viscoelastic, microplastic or pals run and write back, so
// that the model's state, its energy ledger and the checkpoints are as the CPU backend's
// steps leave them.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "horizon/kernels/flat_ordinary.hpp"
#include "horizon/state/system.hpp"

namespace horizon {

// Owning copies of the arrays kernels::FlatOrdinary points to; `view` points into them
// (point(), after any change of the vectors).
struct FlatOrdinaryStorage {
  kernels::FlatOrdinary view;
  std::vector<double> omega, vj, r[2], q[2], pending_amount, stored, theta, ep, eps_p, lambda, shear_factor,
      dissipated_density, theta_strain, sbar, sigma, tau;
  std::vector<kernels::FlatPalsKind> pals_kinds;
  std::vector<uint64_t> rev;
  std::vector<uint8_t> booked, pending_set, flowed, yielded, current{0};
  std::vector<double> back[kernels::kFlatBranches], theta_back[kernels::kFlatBranches];
  void point();
};

// Whether the run has an ordinary model with flat rows (elastic_plastic, viscoelastic,
// microplastic, pals).
bool flat_ordinary_model(const System& s);
// Why the flat rows cannot take this run of an ordinary model, or "": one material, kinds
// with their lengths.
std::string flat_ordinary_unsupported(const System& s);
// Whether the model's ledger is where the flat rows start from: the committed t_n and e_n
// rebuilt from the last pass (a pass of the lanes, committed; history_ledger.hpp
// LedgerRows::rebuild). After a restart they lie in the ledger's arrays until the first
// step: the backend takes that step on the CPU (FlatBackend::advance).
bool flat_ordinary_ready(const System& s);
// The copy of s's model (after a committed pass) with the step dt; null without one.
std::shared_ptr<FlatOrdinaryStorage> flat_ordinary_copy(const System& s, double dt);
// Writes the copy back: |Y| and q into System::model, the model's arrays and its ledger as
// its commit leaves them after a pass of its lanes written in place.
void flat_ordinary_write_back(const FlatOrdinaryStorage& c, System& s);

}  // namespace horizon
