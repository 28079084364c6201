#pragma once
// The state of an ordinary model (elastic_plastic, viscoelastic, microplastic, pals) as the flat
// backend copies it (solver/flat_ordinary_copy.hpp, kernels/flat_ordinary.hpp): the
// model's constants and pointers to its own arrays, which the copy reads and the
// write-back sets as the model's commit after a pass of its lanes leaves them.
#include <cstdint>
#include <vector>

#include "horizon/material/model.hpp"
#include "horizon/material/models/history_ledger.hpp"

namespace horizon {

constexpr int kOrdinaryFlatBranches = 3;  // viscoelastic's kMaxViscousBranches

struct OrdinaryModelState {
  enum Kind { none = 0, elastic_plastic = 1, viscoelastic = 2, microplastic = 3, pals = 4 };
  Kind kind = none;
  int dim = 3;
  HistoryLedger* ledger = nullptr;
  double mu = 0;
  // elastic_plastic: k' (lps_bulk_modulus), the yield stress, H, the yield function's
  // weighted volume (0: each particle's own), plasticity on or off; per particle eps_p,
  // lambda (committed and trial), theta of the last pass, the shear correction factor, the
  // row's flags (flowed in its last pass, ever flowed; yield_flags_stale: to be recomputed
  // from e^dp); per bond e^dp.
  double bulk = 0, yield = 0, hardening = 0, yield_volume = 0;
  bool plastic = true;
  std::vector<double>*eps_p = nullptr, *eps_p_trial = nullptr, *lambda = nullptr, *lambda_trial = nullptr,
  *theta = nullptr;
  const std::vector<double>* shear_factor = nullptr;
  std::vector<uint8_t>*flowed = nullptr, *yielded = nullptr;
  bool* yield_flags_stale = nullptr;
  BondHistory<double>* ep = nullptr;
  // viscoelastic: k (plane strain; else k'), mu/3 in plane strain (else 0), lambda_inf, the
  // branches' lambda and tau; per particle theta_n of the rows (committed and trial), in
  // plane strain theta and the back dilatations (committed and trial), the dissipated
  // density; per bond the back extensions.
  double bulk_elastic = 0, dilatation_shear = 0, lambda_inf = 1;
  int branches = 0;
  double branch_lambda[kOrdinaryFlatBranches] = {}, tau[kOrdinaryFlatBranches] = {};
  std::vector<double>*theta_row = nullptr, *theta_row_trial = nullptr, *theta_strain = nullptr,
  *theta_strain_trial = nullptr, *dissipated = nullptr;
  std::vector<double>*theta_back[kOrdinaryFlatBranches] = {}, *theta_back_trial[kOrdinaryFlatBranches] = {};
  BondHistory<double>* back[kOrdinaryFlatBranches] = {};
  // microplastic: the micromodulus c, the yield stretch; per bond the plastic stretch.
  double micro_c = 0, yield_stretch = 0;
  BondHistory<double>* sbar = nullptr;
  // pals: kappa (mu above); per bond sigma and tau (pals_tau); per particle theta (`theta` above). No
  // ledger (ledger stays null).
  double kappa = 0;
  const std::vector<double>*sigma = nullptr, *pals_tau = nullptr;
};

// The model's state when it is one of them (material/models/elastic_plastic.cpp,
// viscoelastic.cpp, microplastic.cpp, pals.cpp); false otherwise.
bool elastic_plastic_state(Model& m, OrdinaryModelState& out);
bool viscoelastic_state(Model& m, OrdinaryModelState& out);
bool microplastic_state(Model& m, OrdinaryModelState& out);
bool pals_state(Model& m, OrdinaryModelState& out);
inline OrdinaryModelState ordinary_model_state(Model& m) {
  OrdinaryModelState o;
  if (!elastic_plastic_state(m, o) && !viscoelastic_state(m, o) && !microplastic_state(m, o)) pals_state(m, o);
  return o;
}

}  // namespace horizon
