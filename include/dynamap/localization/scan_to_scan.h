#pragma once
// Scan-to-scan matching: a scan aligned to the one before it with every return the sensor gave,
// far ones past the insertion range included (point-to-line ICP, each point paired with the
// segment between two neighbouring beams of the earlier scan).
//
// Slam's front end matches a scan against a submap of the scans before it, built from returns
// short of the insertion range. In the open (a campus between buildings) most returns lie
// beyond it: the submap holds too few walls, the match fails, and odometry alone places the
// scan, turning the path by odometry's heading error. The earlier scan's far walls still fix
// the turn (0.1 degree moves a wall 40 m away by 7 cm), so slam uses this where the submap match
// fails.
//
// Cost: a few passes over the scan's points, each point looking at a fixed number of the earlier
// scan's beams around its bearing (never a tree, never the map). Deterministic.

#include <mrpt/poses/CPose2D.h>

#include <Eigen/Core>

#include <cstddef>
#include <vector>

#include "dynamap/base/range_data.h"

namespace dynamap {

/// One scan's returns in the robot's frame, beam by beam: every Hit and Beyond beam short of the
/// sensor's maximum range (a reading at it is no echo). A beam with no return is not `valid`.
struct ScanReturns {
  std::vector<Eigen::Vector2d> point;  ///< [m] in the robot's frame
  std::vector<double> range;           ///< [m] as measured
  std::vector<unsigned char> valid;
  std::size_t returns = 0;              ///< valid beams
  mrpt::poses::CPose2D sensor;          ///< the sensor on the robot, on the floor
  double first = 0, step = 0, dir = 1;  ///< the beams' bearings (RangeData's)

  /// The returns of `rd`, whose beams' cos_angle and sin_angle are worked out.
  static ScanReturns of(const RangeData& rd);
};

/// What one scan-to-scan match did.
struct ScanToScanResult {
  mrpt::poses::CPose2D increment;  ///< the later scan's pose in the earlier's robot frame
  bool matched = false;            ///< false: `increment` is the guess
  /// Why not matched: "too few returns", "diverged", "too few inliers", "correction too large";
  /// nullptr when matched.
  const char* rejected = nullptr;
  std::size_t paired = 0;         ///< points paired with a segment of the earlier scan
  std::size_t inliers = 0;        ///< ... within the inlier distance after the match
  int degenerate_directions = 0;  ///< pose directions kept at the guess
};

/// What makes a scan-to-scan match trusted.
struct ScanToScanLimits {
  std::size_t min_inliers = 40;   ///< fewer inliers: not matched
  double min_inlier_ratio = 0.5;  ///< inliers / the later scan's returns
  double max_correction_m = 0.3;  ///< a correction of the guess beyond this: not matched
  double max_correction_rad = 0.0873;
  double min_constraint = 0.05;  ///< see keepConstrained (per inlier)
  int max_iterations = 30;
};

/// Aligns `later` to `earlier`, starting from `guess` (the later scan's pose in the earlier's
/// robot frame, odometry's increment). A point pairs with the nearest of the earlier scan's
/// returns within a few beams of its bearing, and that return's segment to its neighbouring beam
/// (when the two lie close enough to be one surface); a point is an inlier within 5 cm plus 0.5 %
/// of its range of that segment, as far returns are noisier.
ScanToScanResult matchScans(const ScanReturns& earlier, const ScanReturns& later,
                            const mrpt::poses::CPose2D& guess, const ScanToScanLimits& limits);

}  // namespace dynamap
