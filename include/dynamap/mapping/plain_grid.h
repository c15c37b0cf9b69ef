#pragma once
// The baseline a user gets without dynamap: a plain MRPT COccupancyGridMap2D built from the same
// scans and poses, at the same resolution and with the same insertion options, and how dynamap's
// static map S differs from it.
//
// The grid is fed from files: whatever a scan holds, MRPT's insertion must never see a range it
// cannot place (NaN, infinite, negative: MRPT casts them to cell indices) nor a pose that grows
// the grid without bound. The pipeline feeds it only the scans the mapper accepted, at the
// mapper's pose; insert() holds its own bounds on top, for every other caller.

#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose2D.h>

#include <cstddef>

#include "dynamap/mapping/dynamic_grid_map.h"

namespace dynamap {

class PlainGrid {
 public:
  /// A grid over [-10, 10] m that grows to fit what is inserted, as MRPT's would.
  PlainGrid(const DynamicMapOptions& map, const InsertionOptions& insertion);
  /// A grid over the given extents [m] (the geometry of a map to compare with cell for cell).
  PlainGrid(const DynamicMapOptions& map, const InsertionOptions& insertion, float x_min,
            float x_max, float y_min, float y_max);
  /// MRPT's own insertion of `scan` taken from robot pose `pose`. Beams dynamap calls Bad
  /// (NaN, infinite or negative range) are given to MRPT as invalid (no echo). False, and the
  /// grid untouched, when the scan is not planar, has no beams or more than kMaxScanBeams, an
  /// aperture not positive, a non-finite robot or sensor pose, or could take the grid past
  /// max_map_size_m plus the insertion range on a side: lastSkipReason() then says which, in
  /// DynamicGridMap's words (ScanInsertStats::skip_reason) for the same refusal.
  bool insert(const mrpt::obs::CObservation2DRangeScan& scan, const mrpt::poses::CPose2D& pose);
  /// Why the last insert() returned false; nullptr after one that inserted (or none).
  const char* lastSkipReason() const { return skip_reason_; }
  const mrpt::maps::COccupancyGridMap2D& grid() const { return grid_; }

 private:
  /// Whether a scan from `sensor` keeps the grid within its bound (every end point lies within
  /// the insertion range of the sensor).
  bool withinBound(const mrpt::poses::CPose2D& sensor) const;

  mrpt::maps::COccupancyGridMap2D grid_;
  double max_size_m_;                         // max_map_size_m + 2 insertion ranges
  double reach_m_;                            // the insertion range
  double horizontal_tolerance_;               // [rad]
  mrpt::obs::CObservation2DRangeScan clean_;  // a scan with Bad beams made invalid
  const char* skip_reason_ = nullptr;
};

/// Cell counts over S's grid, each S cell compared with the plain grid's cell at its centre.
struct PlainComparison {
  /// The plain grid holds it occupied (P(occ) > 0.5) and S holds it Free: something that moved,
  /// smeared into the plain map and kept out of S.
  std::size_t plain_occupied_static_free = 0;
  /// S holds it occupied and the plain grid does not.
  std::size_t static_occupied_plain_not = 0;
  std::size_t both_occupied = 0;
};
PlainComparison comparePlain(const DynamicGridMap& map,
                             const mrpt::maps::COccupancyGridMap2D& plain);

}  // namespace dynamap
