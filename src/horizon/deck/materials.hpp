#pragma once
// One entry of the deck's `materials` map: model, density, elastic constants (all four
// derived from the ones given), influence function and damage law.
#include "horizon/deck/config.hpp"
#include "horizon/deck/reader.hpp"

namespace horizon::deck {

MaterialConfig read_material(const DeckContext& ctx, const std::string& name, const Item& item);

// Poisson's ratio that a bond-based model (PMB) is tied to: 1/4 in 3-D, plane strain
// and 1-D, 1/3 in plane stress (Gerstle, Sau & Silling 2007; Le & Bobaru 2018).
double bond_based_poissons_ratio(int dimension, PlaneMode plane);

}  // namespace horizon::deck
