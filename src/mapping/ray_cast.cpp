#include "dynamap/mapping/ray_cast.h"

namespace dynamap {

std::vector<std::pair<int, int>> rayCells(int x0, int y0, int x1, int y1) {
  std::vector<std::pair<int, int>> cells;
  traceRay(x0, y0, x1, y1, [&](int cx, int cy) { cells.emplace_back(cx, cy); });
  return cells;
}

}  // namespace dynamap
