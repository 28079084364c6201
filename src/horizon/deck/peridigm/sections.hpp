#pragma once
// The sections of a Peridigm deck read outside peridigm.cpp (contact, compute classes,
// bond filters), each into its part of the native deck tree. docs/peridigm.md maps them.
#include <yaml-cpp/yaml.h>

#include <map>
#include <set>
#include <string>
#include <vector>

#include "horizon/core/vec3.hpp"
#include "horizon/deck/reader.hpp"

namespace horizon::peridigm {

// Where a file a deck names (a mesh, a text-file discretisation, a node-set file) may be,
// in the order tried: relative to the deck's folder; relative to the working directory
// (Peridigm's own rule: its test scripts run `cd npN; Peridigm ../deck.xml`, and the
// deck's `mesh.g` is npN/mesh.g); and where the name climbs out ("../x"), relative to a
// folder one level below the deck's (from np1/, "../mesh.csv" is the deck's folder's).
// An absolute name is its only candidate. docs/peridigm.md, "File names".
std::vector<std::string> deck_file_candidates(const std::string& folder, const std::string& name);
// The first candidate that exists; the first one when none does (the error names it).
std::string resolve_deck_file(const std::string& folder, const std::string& name);

// Peridigm compares type words without case, spaces or underscores (survey sec. 1.6).
std::string squash_words(const std::string& s);

// `Contact` {Search Radius, Search Frequency, Models, Interactions} as the native
// `contact: {short_range: {law: peridigm, ...}}`. `horizon`: the deck's one horizon;
// `blocks`: the block ids the discretisation has.
YAML::Node read_contact_section(const deck::DeckContext& ctx, const deck::Item& item, double horizon,
                                const std::set<int>& blocks);

}  // namespace horizon::peridigm

namespace horizon::peridigm {

// `Compute Class Parameters` (survey sec. 1.9): Nearest_Point_Data, Block_Data and
// Node_Set_Data as native `output.history_columns` under their Output Label.
struct ComputeClasses {
  YAML::Node columns{YAML::NodeType::Sequence};
  std::set<std::string> labels;     // the Output Labels (which Output Variables may name)
  std::set<std::string> node_sets;  // the node sets they read (regions of the native deck)
};
// `node_sets`: the names the deck's Boundary Conditions define; `blocks`: the block ids
// of the discretisation.
ComputeClasses read_compute_classes(const deck::DeckContext& ctx, const deck::Item& item,
                                    const std::vector<std::string>& node_sets, const std::set<int>& blocks);

// Peridigm's global output variables (Global_Kinetic_Energy, Global_Linear_Momentum,
// Global_Angular_Momentum, Global_Strain_Energy) as a history column under that name;
// false for another name.
bool add_global_column(const std::string& variable, YAML::Node& columns);

}  // namespace horizon::peridigm

namespace horizon::peridigm {

// `Bond Filters` (survey sec. 1.8) as native precracks: Rectangular_Plane as a planar
// quadrilateral, Disk as a disk, Exodus Mesh (a shell mesh) as a surface of facets.
// Bonds that cross one are never made (`Discretization: Bond Filters`), or with `broken`
// (the `Initial Damage` model's filters) made broken.
YAML::Node read_bond_filters(const deck::DeckContext& ctx, const deck::Item& item, bool broken = false);

}  // namespace horizon::peridigm
