#pragma once
// Where a log starts in a map it was not mapped with (dynamap map --prior without
// --initial-pose): the scans of its first metres, laid on each other by their own poses, searched
// for over the whole map and every heading.
//
// Branch and bound (field_matcher.h's searchWide) on a coarse copy of the map (cells of at least
// 0.2 m, at most 640 on a side) over every offset and heading in 1.5 degree steps, then the same
// search at the map's own resolution within a cell and a step of the coarse answer, then
// Levenberg-Marquardt on the fine field; the runner-up place of the coarse search likewise.
// Cost: the map's cells twice (the two fields) plus the coarse search's bounds, (640 / 16)^2 x
// 240 sums of at most 400 points and those of the blocks near the best: under a second.

#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/math/TPoint2D.h>
#include <mrpt/poses/CPose2D.h>

#include <utility>
#include <vector>

namespace dynamap {

struct GlobalPlacement {
  mrpt::poses::CPose2D pose;  ///< where the points' frame lies in the map
  double score = 0;           ///< mean field value of the points there, in [0, 1] (fine field)
  double coarse_score = 0;    ///< the same on the coarse field
  /// The best place of the coarse search at least 1 m or 5 degrees away, sharpened on the fine
  /// field as the best was, and its score there: near `score`, the map has two places the
  /// points fit. 0 when the coarse search found none within 0.9 of the best.
  double runner_up = 0;
  mrpt::poses::CPose2D runner_up_pose;
  /// Every distinct place the coarse search found within 0.9 of its best (at most 8), sharpened
  /// as the best was, with its fine score: the best first, the runner-up second when there is one.
  std::vector<std::pair<mrpt::poses::CPose2D, double>> places;
  /// [m] of the log's path along which the places were followed to tell them apart (0: not
  /// needed); score and runner_up are then mean fits along it: of the place that won and the
  /// best of the others, or, when none won, of the two best.
  double followed_m = 0;
};

/// Places `pts` (points in one frame, e.g. the first scan's robot frame) in `map` (its cells with
/// P(occ) > 0.5 are walls). Given `head` (points of the same frame, e.g. the first scans alone),
/// the pose is then refined on those alone, within 0.3 m and 3 degrees: the many scans that make
/// a place unique carry their odometry's error, the first few hardly any. An empty map or no
/// points: score 0.
GlobalPlacement placeInMap(const mrpt::maps::COccupancyGridMap2D& map,
                           const std::vector<mrpt::math::TPoint2D>& pts,
                           const std::vector<mrpt::math::TPoint2D>& head = {});

}  // namespace dynamap
