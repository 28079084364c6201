#pragma once
// The model objects of a run, one per material (index = MaterialConfig index), built by
// setup_model from the registry. Copying a System copies its models' state.
#include <memory>
#include <vector>

#include "horizon/material/model.hpp"

namespace horizon {

class ModelSet {
 public:
  ModelSet() = default;
  ModelSet(const ModelSet& o) { *this = o; }
  ModelSet(ModelSet&&) noexcept = default;
  ModelSet& operator=(const ModelSet& o) {
    if (this == &o) return *this;
    models_.clear();
    for (const auto& m : o.models_) models_.push_back(m ? m->clone() : nullptr);
    return *this;
  }
  ModelSet& operator=(ModelSet&&) noexcept = default;

  void clear() { models_.clear(); }
  void add(std::unique_ptr<Model> m) { models_.push_back(std::move(m)); }
  std::size_t size() const { return models_.size(); }
  bool empty() const { return models_.empty(); }
  Model& operator[](std::size_t material) { return *models_[material]; }
  const Model& operator[](std::size_t material) const { return *models_[material]; }
  auto begin() const { return models_.begin(); }
  auto end() const { return models_.end(); }

  // The model that computes the whole force pass (ModelTraits::exclusive), or null.
  Model* owner() const {
    for (const auto& m : models_)
      if (m->owns_force_pass()) return m.get();
    return nullptr;
  }
  // True when every material runs in the unified form (the fast loops and the analytic
  // tangent of the static solvers); true for a system without models (neutral arrays).
  bool all_unified() const {
    for (const auto& m : models_)
      if (!m->unified()) return false;
    return true;
  }

 private:
  std::vector<std::unique_ptr<Model>> models_;
};

}  // namespace horizon
