#pragma once
// One entry of the deck's `materials` map: model, density, elastic constants (all four
// derived from the ones given), influence function and damage law.
#include "horizon/deck/config.hpp"
#include "horizon/deck/reader.hpp"

namespace horizon::deck {

MaterialConfig read_material(const DeckContext& ctx, const std::string& name, const Item& item);

}  // namespace horizon::deck
