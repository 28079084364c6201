// The members of ModelSet (state/model_set.hpp) that need a whole Model.
#include "horizon/state/model_set.hpp"

#include "horizon/material/model.hpp"

namespace horizon {

ModelSet::ModelSet() = default;
ModelSet::ModelSet(const ModelSet& o) { *this = o; }
ModelSet::ModelSet(ModelSet&&) noexcept = default;
ModelSet& ModelSet::operator=(const ModelSet& o) {
  if (this == &o) return *this;
  models_.clear();
  for (const auto& m : o.models_) models_.push_back(m ? m->clone() : nullptr);
  return *this;
}
ModelSet& ModelSet::operator=(ModelSet&&) noexcept = default;
ModelSet::~ModelSet() = default;

void ModelSet::clear() { models_.clear(); }
void ModelSet::add(std::unique_ptr<Model> m) { models_.push_back(std::move(m)); }

Model* ModelSet::owner() const {
  for (const auto& m : models_)
    if (m->owns_force_pass()) return m.get();
  return nullptr;
}

bool ModelSet::all_unified() const {
  for (const auto& m : models_)
    if (!m->unified()) return false;
  return true;
}

}  // namespace horizon
