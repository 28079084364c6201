#pragma once
// A position with one more value, 32-byte aligned: what the bond loops gather per
// neighbour in one aligned load (the current position and, e.g., the critical stretch).
namespace horizon {

struct alignas(32) Point4 {
  double x = 0, y = 0, z = 0, w = 0;
};

}  // namespace horizon
