#include "dynamap/objects/clustering.h"

#include <algorithm>
#include <cmath>
#include <unordered_set>

namespace dynamap {

// Offsets of the cells within `join_cells` (Euclidean, centre to centre) of a cell.
std::vector<CellXY> joinOffsets(double join_cells) {
  std::vector<CellXY> off;
  const int r = static_cast<int>(std::floor(join_cells + 1e-9));
  for (int dy = -r; dy <= r; ++dy) {
    for (int dx = -r; dx <= r; ++dx) {
      if ((dx || dy) && dx * dx + dy * dy <= join_cells * join_cells + 1e-9)
        off.push_back({dx, dy});
    }
  }
  return off;
}

std::vector<std::vector<CellXY>> clusterCells(const std::vector<CellXY>& cells, double join_cells) {
  std::unordered_set<CellKey> all;
  std::vector<CellKey> keys;
  for (const CellXY& c : cells) {
    if (all.insert(cellKey(c.x, c.y)).second) keys.push_back(cellKey(c.x, c.y));
  }
  std::sort(keys.begin(), keys.end());
  const auto offsets = joinOffsets(join_cells);
  std::unordered_set<CellKey> visited;
  std::vector<std::vector<CellXY>> clusters;
  for (const CellKey k : keys) {
    if (visited.count(k)) continue;
    clusters.push_back(growCluster(
        k, offsets, [&](CellKey n) { return all.count(n) > 0; }, visited));
  }
  return clusters;
}

}  // namespace dynamap
