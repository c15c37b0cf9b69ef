#pragma once
// Cells of the grid by global key, and clusters of them: the tracker groups object cells into
// objects with these.

#include <algorithm>
#include <cstdint>
#include <unordered_set>
#include <vector>

#include "dynamap/base/cell_key.h"

namespace dynamap {

/// A grid cell in global integer coordinates (cell (0,0) holds the world origin), so that keys
/// stay valid when the map grows.
struct CellXY {
  int x, y;
};
inline CellXY cellOf(CellKey k) {
  return {static_cast<int>(k >> 32), static_cast<int>(static_cast<std::uint32_t>(k & 0xffffffff))};
}


/// Offsets of the cells within `join_cells` (Euclidean, centre to centre) of a cell, (0, 0)
/// excluded, in row order.
std::vector<CellXY> joinOffsets(double join_cells);

/// Breadth-first growth of one cluster from `seed` (which the caller found usable) over the
/// cells `usable(CellKey)` accepts, stepping by `offsets`. Every cell reached is added to
/// `visited`, and cells already in it are not entered. The cells come out sorted by key.
template <typename Usable>
std::vector<CellXY> growCluster(CellKey seed, const std::vector<CellXY>& offsets, Usable usable,
                                std::unordered_set<CellKey>& visited) {
  std::vector<CellXY> out;
  std::vector<CellKey> queue{seed};
  visited.insert(seed);
  while (!queue.empty()) {
    const CellKey k = queue.back();
    queue.pop_back();
    const CellXY c = cellOf(k);
    out.push_back(c);
    for (const CellXY& o : offsets) {
      const CellKey n = cellKey(c.x + o.x, c.y + o.y);
      if (visited.count(n) || !usable(n)) continue;
      visited.insert(n);
      queue.push_back(n);
    }
  }
  // Deterministic content order, whatever the hash set's order.
  std::sort(out.begin(), out.end(),
            [](CellXY a, CellXY b) { return cellKey(a.x, a.y) < cellKey(b.x, b.y); });
  return out;
}

/// Groups cells into clusters: two cells whose centres are within `join_cells` cells (Euclidean)
/// belong to the same cluster. Deterministic order (by the smallest key of each cluster).
std::vector<std::vector<CellXY>> clusterCells(const std::vector<CellXY>& cells, double join_cells);

}  // namespace dynamap
