#pragma once
// The `contact` section of the deck (short-range contact, rigid indenters) and the
// `partial_volume` rule. docs/input.md documents both.
#include "horizon/deck/config.hpp"
#include "horizon/deck/reader.hpp"

namespace horizon::deck {

// `partial_volume: none | linear | lammps`, or a boolean (true = linear, false = none).
PartialVolume read_partial_volume(const DeckContext& ctx, const Item& item);

// `contact: {short_range: {...}, indenters: [...]}`.
// `bodies`: the deck's bodies, which short_range.pairs names.
ContactConfig read_contact(const DeckContext& ctx, const Item& item, const std::vector<BodyConfig>& bodies);

}  // namespace horizon::deck
