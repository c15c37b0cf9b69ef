#pragma once
// ScanView: the beams of one scan in the map frame, and what they show of a round place.

#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose2D.h>

#include <vector>

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
  bool empty() const { return ranges.empty(); }
};
/// The view of a scan taken from `robot` (sensor pose from the scan itself); `max_range` cuts.
ScanView makeScanView(const mrpt::obs::CObservation2DRangeScan& scan,
                      const mrpt::poses::CPose2D& robot, double max_range);
/// Whether the scan's beams crossed the disc (cx, cy, r) (SeenFree), ended in it
/// (SeenOccupied), or never reached it (NotInView: out of range, out of the field of view, or
/// hidden behind something nearer). `margin` [m] tolerates range noise and cell size.
PlaceView viewOf(const ScanView& view, double cx, double cy, double r, double margin);

}  // namespace dynamap
