#pragma once
// Scanline filling of a polygon over grid cells: each cell whose centre lies inside is visited
// exactly once, in row-major spans. The mapper frees the area a scan swept with it, so cells
// near the sensor, which hundreds of beams cross, are touched once instead of once per beam.

#include <cstdint>
#include <vector>

namespace dynamap {

/// A point in grid units: cell (i, j) spans [i, i + 1) x [j, j + 1); its centre is (i + .5, j +
/// .5).
struct GridPoint {
  double u, v;
};

/// Reusable buffers, so filling does not allocate once warmed up.
struct PolygonFillScratch {
  std::vector<std::uint32_t> row_count;
  std::vector<double> crossings;
};

/// Calls `span(cy, cx_begin, cx_end)` for every row of cells and every maximal run
/// [cx_begin, cx_end) of cells whose centres are inside the closed polygon `vertices` (any simple
/// polygon, either orientation; the last vertex joins the first). Centres exactly on the boundary
/// follow the usual half-open rule: every interior cell once, no cell twice. Cells outside
/// [0, size_x) x [0, size_y) are never reported.
template <typename Span>
void fillPolygon(const std::vector<GridPoint>& vertices, int size_x, int size_y,
                 PolygonFillScratch& scratch, Span&& span);

}  // namespace dynamap

#include "dynamap/mapping/polygon_fill_impl.h"
