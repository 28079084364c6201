#pragma once
#include <string>

#include "horizon/material/model.hpp"

namespace horizon {

// The names of the registered models whose traits pass `keep`, comma-separated, in
// registry order (for driver messages that list the models able to do something, so that
// no driver names a model). Defined in check.cpp.
std::string model_list(bool (*keep)(const ModelTraits&));

}  // namespace horizon
