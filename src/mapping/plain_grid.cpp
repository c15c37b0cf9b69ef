#include "dynamap/mapping/plain_grid.h"

#include <cmath>

namespace dynamap {

PlainGrid::PlainGrid(const DynamicMapOptions& map, const InsertionOptions& insertion)
    : PlainGrid(map, insertion, -10.f, 10.f, -10.f, 10.f) {}

PlainGrid::PlainGrid(const DynamicMapOptions& map, const InsertionOptions& insertion, float x_min,
                     float x_max, float y_min, float y_max)
    : grid_(x_min, x_max, y_min, y_max, static_cast<float>(map.resolution)) {
  auto& o = grid_.insertionOptions;
  o.maxDistanceInsertion = static_cast<float>(insertion.max_distance_insertion);
  o.considerInvalidRangesAsFreeSpace = insertion.invalid_ranges_as_free;
  o.horizontalTolerance = static_cast<float>(insertion.horizontal_tolerance_deg * M_PI / 180.0);
}

void PlainGrid::insert(const mrpt::obs::CObservation2DRangeScan& scan,
                       const mrpt::poses::CPose2D& pose) {
  grid_.insertObservation(scan, mrpt::poses::CPose3D(pose));
}

PlainComparison comparePlain(const DynamicGridMap& map,
                             const mrpt::maps::COccupancyGridMap2D& plain) {
  PlainComparison c;
  for (unsigned cy = 0; cy < map.getSizeY(); ++cy) {
    const float y = map.idx2y(cy);
    const int py = plain.y2idx(y);
    for (unsigned cx = 0; cx < map.getSizeX(); ++cx) {
      const bool s_occ = map.getCell(cx, cy) < 0.5f;
      const bool s_free = map.isStaticFree(cx, cy);
      // Outside the plain grid: unknown there (getCell answers 0.5).
      const bool p_occ = plain.getCell(plain.x2idx(map.idx2x(cx)), py) < 0.5f;
      c.plain_occupied_static_free += p_occ && s_free;
      c.static_occupied_plain_not += s_occ && !p_occ;
      c.both_occupied += s_occ && p_occ;
    }
  }
  return c;
}

}  // namespace dynamap
