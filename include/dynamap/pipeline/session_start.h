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
/// on the scans of the first metre alone. When other places at least 1 m or 5 degrees away fit
/// almost as well (0.9 of the best; a symmetric building), each of them (at most 8) is followed
/// along the log's next scans, up to 25 m of path and 500 scans, as scan matching would (each
/// scan searched within 0.25 m and 3 degrees of where the one before and odometry put it, on the
/// prior's likelihood field; where nothing fits, odometry's step is kept). A place wins when it
/// beats every other scan by scan: of the scans where one of the two fits clearly better (mean
/// field value higher by 0.1), it takes at least 20 and so many that two equal places would
/// with probability below 0.001 (a sign test). Throws InputError naming `log` when there is no
/// unique answer: the points fit nowhere well (mean field value below 0.35), or a second place
/// fits almost as well (0.9 of the best) and following tells none apart; the message gives the
/// two best places, for --initial-pose. Cost: a second or two; following, as much again.
GlobalPlacement locateStart(ScanSource& source, const mrpt::maps::COccupancyGridMap2D& prior_map,
                            const InsertionOptions& insertion, const std::string& log);

}  // namespace dynamap
