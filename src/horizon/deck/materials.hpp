#pragma once
// One entry of the deck's `materials` map: model, density, elastic constants (all four
// derived from the ones given), influence function and damage law.
#include "horizon/deck/config.hpp"
#include "horizon/deck/reader.hpp"

namespace horizon::deck {

MaterialConfig read_material(const DeckContext& ctx, const std::string& name, const Item& item);

// A PMB material given by its micromodulus: fills in the four elastic constants (the
// bond-based Poisson's ratio and the Young's modulus whose micromodulus is c). Needs
// the deck's dimension and horizon; does nothing for other materials.
void derive_from_micromodulus(MaterialConfig& mat, const Config& config);

}  // namespace horizon::deck
