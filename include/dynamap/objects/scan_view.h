#pragma once
// ScanView: the beams of one scan in the map frame, and what they show of a round place.

#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose2D.h>

#include <vector>

#include "dynamap/base/range_data.h"

namespace dynamap {

/// What one scan tells about a round place.
enum class PlaceView { NotInView, SeenFree, SeenOccupied };

/// The beams of one scan in the map frame, enough to ask whether a place was seen.
struct ScanView {
  double x = 0, y = 0, phi = 0;  ///< sensor pose
  double first = 0, step = 0;    ///< beam i looks at phi + dir * (first + i * step)
  double dir = 1;
  double max_range = 0;
  std::vector<float> ranges;  ///< < 0: no echo
  /// cos and sin of each beam's direction in the map frame (from RangeData's cached ones: equal
  /// to cos/sin of phi + dir * (first + i * step) up to rounding); empty: not worked out.
  std::vector<double> cosines, sines;
  bool empty() const { return ranges.empty(); }
};
/// The view of the scan `rd` taken with the robot at `robot`: the same beam directions the grid
/// inserted, ranges cut at the insertion range, beams without an echo (or bad) < 0.
ScanView makeScanView(const RangeData& rd, const mrpt::poses::CPose2D& robot);
/// Whether the scan's beams crossed the disc (cx, cy, r) (SeenFree), ended in it
/// (SeenOccupied), or never reached it (NotInView: out of range, out of the field of view, or
/// hidden behind something nearer). `margin` [m] tolerates range noise and cell size.
PlaceView viewOf(const ScanView& view, double cx, double cy, double r, double margin);

}  // namespace dynamap
