#pragma once
// The parts of the deck that refer to regions: precracks, initial conditions, loads.
#include "horizon/deck/config.hpp"
#include "horizon/deck/reader.hpp"

namespace horizon::deck {

PrecrackConfig read_precrack(const DeckContext& ctx, const Item& item);

// A region reference: a name from `regions`, or `all` (stored as "") for every particle.
std::string read_region_name(const DeckContext& ctx, const Item& item, const std::vector<std::string>& regions);

InitialConditionConfig read_initial_condition(const DeckContext& ctx, const Item& item,
                                              const std::vector<std::string>& regions);
LoadConfig read_load(const DeckContext& ctx, const Item& item, const std::vector<std::string>& regions);

}  // namespace horizon::deck
