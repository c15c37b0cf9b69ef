#include "dynamap/mapping/plain_grid.h"

#include <algorithm>
#include <cmath>

namespace dynamap {

PlainGrid::PlainGrid(const DynamicMapOptions& map, const InsertionOptions& insertion)
    : PlainGrid(map, insertion, -10.f, 10.f, -10.f, 10.f) {}

PlainGrid::PlainGrid(const DynamicMapOptions& map, const InsertionOptions& insertion, float x_min,
                     float x_max, float y_min, float y_max)
    : grid_(x_min, x_max, y_min, y_max, static_cast<float>(map.resolution)),
      max_size_m_(map.max_map_size_m + 2 * insertion.max_distance_insertion),
      reach_m_(insertion.max_distance_insertion),
      horizontal_tolerance_(insertion.horizontal_tolerance_deg * M_PI / 180.0) {
  auto& o = grid_.insertionOptions;
  o.maxDistanceInsertion = static_cast<float>(insertion.max_distance_insertion);
  o.considerInvalidRangesAsFreeSpace = insertion.invalid_ranges_as_free;
  o.horizontalTolerance = static_cast<float>(insertion.horizontal_tolerance_deg * M_PI / 180.0);
}

namespace {

bool finitePose(const mrpt::poses::CPose2D& p) {
  return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.phi());
}

bool badRange(float r) { return !std::isfinite(r) || r < 0.0f; }

}  // namespace

bool PlainGrid::withinBound(const mrpt::poses::CPose2D& sensor) const {
  const double x_min = std::min<double>(grid_.getXMin(), sensor.x() - reach_m_);
  const double x_max = std::max<double>(grid_.getXMax(), sensor.x() + reach_m_);
  const double y_min = std::min<double>(grid_.getYMin(), sensor.y() - reach_m_);
  const double y_max = std::max<double>(grid_.getYMax(), sensor.y() + reach_m_);
  return x_max - x_min <= max_size_m_ && y_max - y_min <= max_size_m_;
}

bool PlainGrid::insert(const mrpt::obs::CObservation2DRangeScan& scan,
                       const mrpt::poses::CPose2D& pose) {
  // The refusals of DynamicGridMap::insertScan, in its order and words: what the mapper skips
  // never reaches MRPT here either (nor would it through any other caller).
  const std::size_t n = scan.getScanSize();
  const mrpt::poses::CPose3D robot(pose);
  const auto refuse = [&]() -> const char* {
    if (!scan.isPlanarScan(horizontal_tolerance_)) return "not horizontal";
    if (n == 0) return "no beams";
    if (n > kMaxScanBeams) return kTooManyBeams;  // MRPT's insertion: 8 bytes of stack a beam
    if (!(scan.aperture > 0.0f) || !std::isfinite(scan.aperture)) return "aperture not positive";
    if (!finitePose(pose)) return "pose not finite";
    const mrpt::poses::CPose2D sensor(robot + scan.sensorPose);
    if (!finitePose(sensor)) return "sensor pose not finite";
    if (!withinBound(sensor)) return "beyond max_map_size_m";
    return nullptr;
  };
  skip_reason_ = refuse();
  if (skip_reason_) return false;
  const mrpt::obs::CObservation2DRangeScan* use = &scan;
  for (std::size_t i = 0; i < n; ++i) {
    if (!badRange(scan.getScanRange(i))) continue;
    if (use == &scan) {  // copied only when a beam needs mending
      clean_ = scan;
      use = &clean_;
    }
    clean_.setScanRange(i, 0.0f);
    clean_.setScanRangeValidity(i, false);
  }
  grid_.insertObservation(*use, robot);
  return true;
}

PlainComparison comparePlain(const DynamicGridMap& map,
                             const mrpt::maps::COccupancyGridMap2D& plain) {
  // On raw cells: P(occ) > 0.5 is a value below 0 in both grids (MRPT's log-odds of being
  // free), and MRPT's getCell looks its probability table up on every call.
  PlainComparison c;
  const auto& s_cells = map.getRawMap();
  const auto& p_cells = plain.getRawMap();
  const int psx = static_cast<int>(plain.getSizeX()), psy = static_cast<int>(plain.getSizeY());
  for (unsigned cy = 0; cy < map.getSizeY(); ++cy) {
    const int py = plain.y2idx(map.idx2y(cy));
    const std::size_t row = static_cast<std::size_t>(cy) * map.getSizeX();
    for (unsigned cx = 0; cx < map.getSizeX(); ++cx) {
      const bool s_occ = DynamicGridMap::isOccupiedValue(s_cells[row + cx]);
      const bool s_free = map.isStaticFree(cx, cy);
      // Outside the plain grid: unknown there.
      const int px = plain.x2idx(map.idx2x(cx));
      const bool p_occ = px >= 0 && px < psx && py >= 0 && py < psy &&
                         p_cells[px + static_cast<std::size_t>(py) * psx] < 0;
      c.plain_occupied_static_free += p_occ && s_free;
      c.static_occupied_plain_not += s_occ && !p_occ;
      c.both_occupied += s_occ && p_occ;
    }
  }
  return c;
}

}  // namespace dynamap
