#pragma once
// ScanView: the beams of one scan in the map frame, and what they show of a round place.

#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose2D.h>

#include <cstddef>
#include <functional>
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
/// hidden behind something nearer). `margin` [m] tolerates range noise and cell size. With
/// `on_wall` (whether beam i's hit lies on a wall, a cell S holds occupied; asked only of beams
/// ending at the disc's surface), a wall hit within the margin of the surface says nothing of
/// it: a wall 5 cm from an object's place is no sign the object is still there.
PlaceView viewOf(const ScanView& view, double cx, double cy, double r, double margin,
                 const std::function<bool(std::size_t)>& on_wall = {});

/// A run of consecutive beams whose hits lie on one surface: each hit within `jump` [m] of
/// range of the one before. An end is an outline edge when the beam beyond it ends farther
/// than `jump` behind (or has no echo): the surface ends there, it is not hidden by something
/// nearer nor cut by the field of view.
struct BeamRun {
  std::size_t first = 0, last = 0;  ///< beam indices, first <= last
  bool edge_before = false, edge_after = false;
  bool whole() const { return edge_before && edge_after; }
};
/// The run of beam `beam` (which must have a hit: 0 <= range < max_range).
BeamRun beamRunAround(const ScanView& view, std::size_t beam, double jump);
/// The direction of beam `i` in the map frame [rad], not wrapped.
inline double beamAngle(const ScanView& view, std::size_t i) {
  return view.phi + view.dir * (view.first + view.step * static_cast<double>(i));
}
/// Where beam `i`'s hit lies in the map frame.
void hitPoint(const ScanView& view, std::size_t i, double& x, double& y);

}  // namespace dynamap
