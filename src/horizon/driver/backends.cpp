// The choice of the explicit backend (solver.backend, --backend; solver/backend.hpp): the
// CPU backend, the flat backend (solver/flat_backend.hpp) and, in builds with
// -DHORIZON_CUDA=ON, the CUDA backend: the flat backend with its arrays on the GPU
// (cuda/cuda_backend.hpp). The flat and CUDA backends refuse the same runs, with the
// deck's name and the key's place.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <string>
#include <vector>

#include "horizon/driver/explicit_state.hpp"
#include "horizon/material/model.hpp"
#include "horizon/material/models/nonlinear_solid.hpp"
#include "horizon/solver/flat_backend.hpp"

#if defined(HORIZON_CUDA_BACKEND)
#include "horizon/cuda/cuda_backend.hpp"
#endif

namespace horizon {

namespace {

#if defined(HORIZON_CUDA_BACKEND)
// The flat backend over device copies of its arrays (cuda::FlatRun): the steps run on the
// GPU, fetch() copies the fields back, a new copy of the System goes to the device.
class CudaBackend final : public FlatBackend {
 public:
  CudaBackend(System& s, Loads& loads, ExplicitSolver& solver) : FlatBackend(s, loads, solver) { upload(); }
  const char* name() const override { return "cuda"; }

 protected:
  void take_steps(int64_t n) override {
    run_->advance(n, s_.contact.enabled() ? &contact_hook : nullptr, this, varies() ? &step_hook : nullptr);
  }
  void fetch() override { run_->download(view_); }
  bool went_non_finite() override { return run_->nonfinite(); }
  void upload() override {
    run_.reset();
    run_ = std::make_unique<cuda::FlatRun>(view_);
  }
  void step_changed() override { run_->set_dt(view_.dt); }
  // The nonlinear solid's adaptive step on the device (no copy back); others: the System's.
  bool stable_time_step(double& dt) override {
    if (!storage_.tupek) return FlatBackend::stable_time_step(dt);
    dt = run_->stable_time_step();
    return true;
  }

 private:
  std::unique_ptr<cuda::FlatRun> run_;
};
#endif

}  // namespace

// What a message about the choice starts with: the deck and the key's place, or --backend.
std::string backend_choice_prefix(const Config& c) {
  const SolverConfig& sc = c.solver;
  if (sc.backend_at == "--backend") return fmt::format("{}: --backend {}", c.deck_file, sc.backend);
  if (!sc.backend_at.empty()) return fmt::format("{}: solver.backend: {}", sc.backend_at, sc.backend);
  return fmt::format("{}: backend {}", c.deck_file, sc.backend);
}

void check_backend(const Config& c, const System& s, const Loads& loads) {
  const std::string& name = c.solver.backend;
  if (name == "cpu") return;
  const std::string prefix = backend_choice_prefix(c);
  if (name == "cuda") {
#if !defined(HORIZON_CUDA_BACKEND)
    throw Error(fmt::format("{}: this horizon was built without CUDA (configure with -DHORIZON_CUDA=ON, which needs "
                            "nvcc); backend flat runs the same kernels on the host",
                            prefix));
#else
    std::string why;
    if (!cuda::device_available(why)) throw Error(fmt::format("{}: {}", prefix, why));  // "no CUDA device: ..."
#endif
  }
  std::string why = flat_backend_refusal(s, loads, c.solver.damping);
  // A model without flat rows: name the first material of such a model (materials.NAME.model).
  if (why.rfind("a model without flat rows", 0) == 0)
    for (const MaterialConfig& m : c.materials) {
      const ModelEntry* e = find_model(m.model);
      if (e && (e->traits.unified || e->traits.name == "nonlinear_solid" || e->traits.name == "elastic_plastic" ||
                e->traits.name == "viscoelastic" || e->traits.name == "microplastic" || e->traits.name == "pals" ||
                e->traits.name == "correspondence"))
        continue;
      why = fmt::format("model {} (materials.{}.model), which has no flat rows", e ? e->traits.name : m.model, m.name);
      break;
    }
  if (why.empty() && s.heat.active()) why = "heat conduction";
  if (why.empty() && s.fe) why = "finite-element regions";
  // The adaptive step: the nonlinear solid's stable step has flat rows (kernels/tupek.hpp);
  // correspondence's is the model's own over the System, the fields copied back for it
  // (FlatBackend::stable_time_step).
  if (why.empty() && c.solver.adaptive_time_step && !nonlinear_state(s) && !flat_affine_model(s))
    why = "solver.adaptive_time_step with a model other than nonlinear_solid or correspondence";
  if (!why.empty()) {
    // The models the flat rows run: the registry's unified ones (ModelTraits::unified),
    // the nonlinear solid (kernels/tupek.hpp) and correspondence (kernels/flat_affine.hpp).
    std::vector<std::string> flat;
    for (const ModelEntry& e : model_registry())
      if (e.traits.unified || e.traits.name == "nonlinear_solid" || e.traits.name == "elastic_plastic" ||
          e.traits.name == "viscoelastic" || e.traits.name == "microplastic" || e.traits.name == "pals" ||
          e.traits.name == "correspondence")
        flat.push_back(e.traits.name);
    throw Error(fmt::format("{} cannot take this run: it has {}; the flat and cuda backends take explicit runs of "
                            "{} (the adaptive step with nonlinear_solid and correspondence), initial conditions, force densities, prescribed "
                            "displacements and velocities and short-range contact (docs/input.md, solver.backend); "
                            "use backend cpu",
                            prefix, why, fmt::join(flat, ", ")));
  }
}

std::unique_ptr<ExplicitBackend> make_backend(const Config& c, System& s, Loads& loads, ExplicitSolver& solver) {
  const std::string& name = c.solver.backend;
  if (name == "cpu") return std::make_unique<CpuBackend>(solver);
  check_backend(c, s, loads);
#if defined(HORIZON_CUDA_BACKEND)
  if (name == "cuda") return std::make_unique<CudaBackend>(s, loads, solver);
#endif
  return std::make_unique<FlatBackend>(s, loads, solver);
}

}  // namespace horizon
