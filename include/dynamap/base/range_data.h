#pragma once
// RangeData: one laser scan's geometry, worked out once per scan and read by every consumer
// (the dual grid's insertion, the scan matcher, the object tracker's view of the scan), so that
// all of them place every beam in the same direction, with the whole mount (a laser mounted
// upside down sweeps the other way round), and agree on which beams are hits.

#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPose3D.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace dynamap {

/// What one beam is good for.
enum class BeamKind : std::uint8_t {
  Bad,     ///< NaN, infinite or negative range: used by nobody (counted)
  NoEcho,  ///< flagged invalid by the sensor: no return (may free space, see insertion)
  Hit,     ///< a valid range below the insertion range: something is there
  Beyond,  ///< a valid range at or past the insertion range: free up to it, no hit
};

struct RangeData {
  mrpt::poses::CPose3D mount;  ///< the sensor on the robot (the scan's sensorPose), 6 DoF
  bool upside_down = false;    ///< the mount turns the scan plane over
  bool planar = false;         ///< pitch and roll within the horizontal tolerance
  /// Beam i looks along dir * (first + i * step) [rad] in the sensor's 2D frame: the beams span
  /// the aperture from its right edge (a lone beam looks ahead), dir = -1 when they sweep from
  /// left to right as seen from above (rightToLeft false, or an upside-down mount).
  double first = 0, step = 0, dir = 1;
  double aperture = 0;          ///< [rad] as the scan states it
  double insertion_range = 0;   ///< [m] the cut that tells Hit from Beyond
  double sensor_max_range = 0;  ///< [m] the sensor's own maximum range
  std::vector<float> ranges;    ///< [m] as measured
  std::vector<BeamKind> kinds;
  std::uint32_t bad_beams = 0;
  /// cos and sin of angle(i) for every beam. makeRangeData() into a RangeData that held a scan
  /// of the same beam geometry keeps them, so a log's scans (which share one) compute them once.
  std::vector<double> cos_angle, sin_angle;

  std::size_t size() const { return ranges.size(); }
  /// Beam i's direction in the sensor's 2D frame [rad].
  double angle(std::size_t i) const { return dir * (first + step * static_cast<double>(i)); }
  /// The sensor's 2D pose in the map frame with the robot at `robot`: the 3D composition of the
  /// robot's pose and the mount, projected on the floor.
  mrpt::poses::CPose2D sensorIn(const mrpt::poses::CPose3D& robot) const;
  /// The sensor's 2D pose on the robot (the mount projected on the floor).
  mrpt::poses::CPose2D mount2D() const { return mrpt::poses::CPose2D(mount); }
};

/// The geometry of `scan`: ranges at `insertion_range` [m] or beyond are Beyond, a scan whose
/// pitch or roll exceeds `horizontal_tolerance` [rad] is not planar.
RangeData makeRangeData(const mrpt::obs::CObservation2DRangeScan& scan, double insertion_range,
                        double horizontal_tolerance);
/// The same into `out`, reusing its buffers: the per-scan step allocates nothing once warm.
void makeRangeData(const mrpt::obs::CObservation2DRangeScan& scan, double insertion_range,
                   double horizontal_tolerance, RangeData& out);

}  // namespace dynamap
