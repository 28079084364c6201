#pragma once
// The thermal parts of the deck (docs/input.md, "thermal"): a material's thermal map and
// the run's thermal section.
#include "horizon/deck/config.hpp"
#include "horizon/deck/reader.hpp"

namespace horizon::deck {

// materials.NAME.thermal: {conductivity, specific_heat, expansion, reference_temperature,
// plastic_heat_fraction}.
ThermalMaterialConfig read_thermal_material(const DeckContext& ctx, const Item& item);

// The top-level thermal section; `regions` are the names boundary conditions may use.
ThermalConfig read_thermal(const DeckContext& ctx, const Item& item, const std::vector<std::string>& regions);

}  // namespace horizon::deck
