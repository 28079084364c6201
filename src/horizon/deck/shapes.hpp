#pragma once
// Shapes in the deck: a map with one key naming the kind (box, cylinder, disk, sphere,
// half_space, union, subtract). Used by bodies and regions.
#include "horizon/deck/reader.hpp"
#include "horizon/geometry/shape.hpp"

namespace horizon::deck {

Shape read_shape(const DeckContext& ctx, const Item& item);

// A body needs a finite box to lay its lattice in: fails when the shape reaches to
// infinity along an axis of the deck (a half space, or a union containing one).
void check_bounded(const DeckContext& ctx, const Item& item, const Shape& shape);

}  // namespace horizon::deck
