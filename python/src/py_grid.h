#pragma once
// S and D as the Python module hands them out: P(occupied) per cell, float32, one row per cell
// row of increasing y (row 0 at y_min), one column per cell column of increasing x.

#include <pybind11/numpy.h>

#include <algorithm>
#include <vector>

#include "dynamap/mapping/dynamic_grid_map.h"

namespace dynamap::python {

struct Grid {
  std::vector<float> p;  // row by row, as MRPT stores its cells
  std::size_t nx = 0, ny = 0;
  double x_min = 0, y_min = 0, resolution = 0;
};

/// `grid`'s geometry with `raw` (log-odds of free, MRPT's scale, grid's layout) as P(occupied):
/// the values staticOccupancy() and dynamicOccupancy() give.
template <typename Raw>
Grid gridOf(const mrpt::maps::COccupancyGridMap2D& grid, const Raw& raw) {
  Grid g;
  g.nx = grid.getSizeX();
  g.ny = grid.getSizeY();
  g.x_min = grid.getXMin();
  g.y_min = grid.getYMin();
  g.resolution = grid.getResolution();
  g.p.resize(g.nx * g.ny);
  std::transform(raw.begin(), raw.begin() + static_cast<std::ptrdiff_t>(g.p.size()), g.p.begin(),
                 [](DynamicGridMap::cellType v) { return DynamicGridMap::staticOccupancyOfValue(v); });
  return g;
}

inline Grid staticGrid(const DynamicGridMap& map) { return gridOf(map, map.getRawMap()); }

/// D as dynamic.gridmap.gz holds it: S's geometry, D's cells (the layers are aligned at the
/// end of a run; a map whose D lags S's geometry gives P = 0.5 where D has no cell).
inline Grid dynamicGrid(const DynamicGridMap& map) {
  if (map.layersAligned()) return gridOf(map, map.dynamicRaw());
  Grid g = gridOf(map, map.getRawMap());
  for (std::size_t y = 0; y < g.ny; ++y)
    for (std::size_t x = 0; x < g.nx; ++x)
      g.p[x + y * g.nx] = map.dynamicOccupancy(static_cast<int>(x), static_cast<int>(y));
  return g;
}

inline pybind11::array_t<float> toArray(const Grid& g) {
  pybind11::array_t<float> a({g.ny, g.nx});
  std::copy(g.p.begin(), g.p.end(), a.mutable_data());
  return a;
}

}  // namespace dynamap::python
