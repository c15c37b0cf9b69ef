#pragma once
// How well a trajectory lays a log's own scans onto each other: a score that needs no ground
// truth, so that the pose sources of an odometry-only log (odometry, scan_matching, slam, another
// SLAM's poses) can be compared on it, and so that a reference trajectory can be checked too.
//
// Two figures, each a mean distance from a scan's hit points (map frame) to the nearest hit
// point of other scans, every distance capped at cap_m (a point with no partner within cap_m
// counts cap_m: what one trajectory leaves apart, another may lay together):
//  - global: the scans taken more than neighbour_scans before or after it (loops, corridors
//    driven twice): where the map would be doubled, a shape error over many metres shows;
//  - local: the scan just before it: the jitter from one scan to the next.
// A trajectory that is right makes both small; laser noise and the beams' spacing set their
// floor, so the figures compare trajectories of one log, never logs with each other.
// Cost: each query point reads the points in the 3 x 3 cells of cap_m around it, at most 4096
// a cell (a cell that sees more keeps the points of every 2nd, 4th, ... scan only: a robot that
// stands still fills the same cells scan after scan). Deterministic.

#include <mrpt/math/TPoint2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose2D.h>

#include <cstddef>
#include <vector>

#include "dynamap/base/range_data.h"
#include "dynamap/mapping/dynamic_map_options.h"

namespace dynamap {

struct ConsistencyOptions {
  std::size_t neighbour_scans = 50;  ///< global: scans closer than this in index do not count
  std::size_t scan_stride = 7;       ///< global: every n-th scan's points are queried
  /// Every n-th hit point of a scan is used at all (of a scan of more than 6000 points, fewer:
  /// at most 2000 of each scan).
  std::size_t point_stride = 3;
  double cap_m = 0.2;  ///< [m] a distance counts at most this
};

/// A hit point in the map frame.
struct MapPoint {
  double x = 0, y = 0;
};

struct Consistency {
  std::size_t scans = 0;          ///< scans given
  std::size_t global_points = 0;  ///< query points of the global figure
  double global_m = 0;            ///< [m] mean capped distance to non-neighbour scans; NaN: none
  std::size_t local_points = 0;   ///< query points of the local figure
  double local_m = 0;             ///< [m] mean capped distance to the scan before; NaN: none
};

/// `scans[i]`: the hit points of scan i (in log order) laid out at the trajectory's pose.
/// Throws std::invalid_argument when an option is zero or cap_m is not positive and finite.
Consistency mapConsistency(const std::vector<std::vector<MapPoint>>& scans,
                           const ConsistencyOptions& options = {});

/// A log's scans kept once, in each scan's robot frame, to be laid out at several trajectories
/// and scored without reading the log again (slam's pass 1 scores the odometry against its own
/// poses). Only the points mapConsistency would use are kept, so score() gives the figures
/// mapConsistency gives on the scans' whole hit lists. Bounded: once max_points are kept, no
/// further scan is (full()), and a score is of the scans kept before.
class ScanLayout {
 public:
  static constexpr std::size_t kMaxPoints = 2'000'000;  // 32 MB
  /// Throws std::invalid_argument for options mapConsistency refuses.
  explicit ScanLayout(const ConsistencyOptions& options = {}, std::size_t max_points = kMaxPoints);
  /// Keeps scan size() (`hits`: its hit points, robot frame, in beam order); false when full.
  bool add(const std::vector<mrpt::math::TPoint2D>& hits);
  /// add() of the hits the mapper inserts of `scan` (beams within `insertion`'s range, the
  /// mount applied); false, and nothing kept, for a scan that is not planar, or when full.
  bool addScan(const mrpt::obs::CObservation2DRangeScan& scan, const InsertionOptions& insertion);
  /// addScan() of a scan already worked out (makeRangeData() at the insertion range).
  bool addRange(const RangeData& rd);
  std::size_t size() const { return scans_.size(); }
  bool full() const { return full_; }
  /// The kept scans laid out at poses[0], poses[1], ... (one per kept scan) and scored.
  /// Throws std::invalid_argument when poses.size() != size().
  Consistency score(const std::vector<mrpt::poses::CPose2D>& poses) const;

 private:
  ConsistencyOptions options_;
  std::size_t max_points_, points_ = 0;
  bool full_ = false;
  std::vector<std::vector<MapPoint>> scans_;
  RangeData rd_;  // addScan's, reused scan after scan
};

}  // namespace dynamap
