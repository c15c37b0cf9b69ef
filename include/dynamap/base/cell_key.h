#pragma once
// One 64-bit key per grid cell, from its integer coordinates: x in the high 32 bits, y in the
// low ones. The object tracker keys cells in global coordinates (valid when the map grows), the
// people detector keys the wall cells one scan met.

#include <cstdint>

namespace dynamap {

using CellKey = std::int64_t;
inline CellKey cellKey(int x, int y) {
  // Shifted as unsigned: a negative x shifted left is undefined behaviour before C++20.
  return static_cast<CellKey>((static_cast<std::uint64_t>(static_cast<std::uint32_t>(x)) << 32) ^
                              static_cast<std::uint32_t>(y));
}

}  // namespace dynamap
