#pragma once
// Where a new session's log starts in the prior session's map, when nobody says
// (dynamap map --prior without --initial-pose, on odometry-based poses): the first scans, laid
// on each other by the log's own poses, placed by a global search over the prior's S
// (localization's placeInMap). Several scans over the first metres, not one: a corridor seen
// once fits many corridors; the turn into a room behind it seldom does.

#include <mrpt/maps/COccupancyGridMap2D.h>

#include <string>

#include "dynamap/input/scan_source.h"
#include "dynamap/localization/global_search.h"
#include "dynamap/mapping/dynamic_map_options.h"

namespace dynamap {

/// Reads the first scans of `source` (the scans of its first 4 m of path, at most 100, each
/// worked out by `insertion`), places them in the prior's S (`prior_map`), and refines the pose
/// on the scans of the first metre alone. Throws InputError naming `log` when the search finds
/// no unique answer: the points fit nowhere well (mean field value below 0.35), or a second
/// place at least 1 m or 5 degrees away fits almost as well (0.9 of the best); the message gives
/// both places, for --initial-pose.
GlobalPlacement locateStart(ScanSource& source, const mrpt::maps::COccupancyGridMap2D& prior_map,
                            const InsertionOptions& insertion, const std::string& log);

}  // namespace dynamap
