#pragma once
// The grid search before ICP (scan_matcher.cpp's step 2). Private to the localization layer.

#include <mrpt/math/TPoint2D.h>
#include <mrpt/poses/CPose2D.h>

#include <vector>

#include "dynamap/localization/scan_matcher.h"

namespace dynamap {

/// The pose near `guess` (within search_xy_m in x and y, on the grid's cells, and search_deg in
/// heading, in 0.5 degree steps) whose scan points lie best on S's occupied cells, scored through
/// a distance field of the window the search can reach. A prior on the offset keeps flat
/// directions (a straight corridor) and small gains from wall texture at the guess. Cost: the
/// window's cells plus (headings x offsets x at most 120 points) lookups, never the map's size.
mrpt::poses::CPose2D correlativeGuess(const DynamicGridMap& map,
                                      const std::vector<mrpt::math::TPoint2D>& pts,
                                      const mrpt::poses::CPose2D& guess, const ScanMatchOptions& o,
                                      const OccupiedByRawValue& occupied);

}  // namespace dynamap
