#pragma once
// output.history_columns (deck/config.hpp HistoryColumnConfig): probes written as extra
// columns of history.csv by every driver. Sums are exact grid sums (GridSum::exact), and
// minima, maxima and the nearest particle are taken over the ranks exactly, so the
// columns have the same bits on any number of ranks or threads.
#include <string>
#include <vector>

#include "horizon/deck/config.hpp"

namespace horizon {

struct System;

// ",NAME,NAMEX,NAMEY,NAMEZ,...": the header cells of the columns (empty without any).
std::string history_columns_header(const Config& config);

// ",v,vx,vy,vz,...": the values now. Collective when decomposed.
std::string history_columns_row(const Config& config, const System& s);

// The same cells as numbers (full precision), and their names (NAME, or NAMEX NAMEY NAMEZ):
// the Exodus files' global variables (driver/exodus_output.hpp). Collective when decomposed.
std::vector<double> history_columns_values(const Config& config, const System& s);
std::vector<std::string> history_columns_names(const Config& config);

}  // namespace horizon
