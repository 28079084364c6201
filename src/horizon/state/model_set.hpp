#pragma once
// The model objects of a run, one per material (index = MaterialConfig index), built by
// setup_model from the registry. Copying a System copies its models' state.
// The run's state holds the set; the models are material/'s (material/model.hpp), one
// floor up, so what needs a whole Model is defined there (material/model_set.cpp).
#include <cstddef>
#include <memory>
#include <vector>

namespace horizon {

class Model;  // material/model.hpp

class ModelSet {
 public:
  ModelSet();
  ModelSet(const ModelSet& o);
  ModelSet(ModelSet&&) noexcept;
  ModelSet& operator=(const ModelSet& o);
  ModelSet& operator=(ModelSet&&) noexcept;
  ~ModelSet();

  void clear();
  void add(std::unique_ptr<Model> m);
  std::size_t size() const { return models_.size(); }
  bool empty() const { return models_.empty(); }
  Model& operator[](std::size_t material) { return *models_[material]; }
  const Model& operator[](std::size_t material) const { return *models_[material]; }
  auto begin() const { return models_.begin(); }
  auto end() const { return models_.end(); }

  // The model that computes the whole force pass (ModelTraits::exclusive), or null.
  Model* owner() const;
  // True when every material runs in the unified form (the fast loops and the analytic
  // tangent of the static solvers); true for a system without models (neutral arrays).
  bool all_unified() const;

 private:
  std::vector<std::unique_ptr<Model>> models_;
};

}  // namespace horizon
