#pragma once
// `output.history_columns`: probes written as extra columns of history.csv
// (driver/history_columns.hpp computes them). docs/input.md documents the keys.
#include "horizon/deck/config.hpp"
#include "horizon/deck/reader.hpp"

namespace horizon::deck {

// A list of {name, quantity, body | region | nearest, reduce}; `config` has its bodies
// and regions read already.
std::vector<HistoryColumnConfig> read_history_columns(const DeckContext& ctx, const Item& item, const Config& config);

}  // namespace horizon::deck
