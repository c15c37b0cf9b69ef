#pragma once
// Scan matching against the static map S (section [scan_matching]).
//
// With odometry only, the pose of each scan drifts. ScanMatcher corrects it: the scan's points
// are aligned to the occupied cells of S near the robot, the odometry increment since the last
// scan giving the initial guess: first a grid search (one cell, half a degree), then ICP from
// its best pose: MRPT's point-to-point ICP (mrpt::slam::CICP) against points laid along S's
// walls, or point-to-line ICP on S's cells (point_to_line). Only S is matched
// against, never D: S holds no people and no objects that moved, so they cannot drag the match
// off. A match that is poor (too few map or scan points, too few inliers, a correction too large
// to be drift) is rejected and the guess is used instead: the caller counts it as a fallback.
//
// Cost per scan: the cells of S around the scan's end points (bounded by the sensor's range,
// never by the map's size) and a few passes over the scan's points.
// Deterministic: the same S, scan and guess always give the same pose.

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose2D.h>

#include <cstddef>
#include <iosfwd>
#include <limits>
#include <string>
#include <vector>

#include "dynamap/base/range_data.h"
#include "dynamap/mapping/dynamic_grid_map.h"

namespace dynamap {

class IniFile;
template <typename T>
class OptionTable;

struct ScanMatchOptions : public mrpt::config::CLoadableOptions {
  static constexpr const char* kSection = "scan_matching";

  /// An S cell is a reference point when its P(occ) is above this; in (0.5, 1).
  double occupied_threshold = 0.6;
  /// [m] MRPT's ICP: S is searched for reference points this far around the scan's end points;
  /// in [0, 5].
  double window_margin_m = 0.5;
  /// Fewer occupied S cells than this near the scan: no match (the map is still empty there).
  /// Near: within window_margin_m of the scan's end points for MRPT's ICP, in the cells within
  /// overlap_distance_m of them for point-to-line (fewer: one per cell, not five); an integer in
  /// [3, 100000].
  int min_map_points = 30;
  /// Fewer scan points on what S holds than this: no match; an integer in [3, 100000].
  int min_scan_points = 20;
  /// [m] only scan points within this distance of an occupied S cell, seen from the guess, are
  /// matched: a point in space S has never seen (a wall seen further along a corridor than
  /// before) has no partner in S and would pull the pose towards the known end of the wall. It
  /// also bounds the odometry error a match can correct across a wall; in (0, 2].
  double overlap_distance_m = 0.1;
  /// [m] a scan point within this distance of a reference point after the match is an inlier;
  /// in (0, 1].
  double inlier_distance_m = 0.1;
  /// A match with fewer inliers than this fraction of the scan's usable points is rejected;
  /// in [0, 1].
  double min_inlier_ratio = 0.4;
  /// [m] a match that moves the guess further than this is rejected; in (0, 10].
  double max_correction_m = 0.3;
  /// [deg] a match that turns the guess by more than this is rejected; in (0, 90].
  double max_correction_deg = 5;
  // MRPT's ICP (mrpt::slam::CICP, classic point-to-point), when point_to_line is false.
  /// [m] initial distance for a scan point and a map point to correspond; in (0, 5].
  double icp_threshold_dist_m = 0.4;
  /// [m] ICP ends when the (halved after each convergence) distance drops below this;
  /// in (0, icp_threshold_dist_m].
  double icp_smallest_threshold_dist_m = 0.02;
  /// Upper bound of ICP iterations (either ICP); an integer in [1, 1000].
  int icp_max_iterations = 100;
  /// A direction of the pose (x, y, heading mixed) that the matched points pin down less than
  /// this keeps the guess's value: the eigenvalue, per inlier, of the point-to-line information
  /// (a wall constrains the pose across itself only; 1 = every inlier's normal along that
  /// direction). Along a straight corridor ICP's answer is noise, odometry is better; in [0, 1].
  double min_constraint = 0.05;
  /// [m] Before ICP, the guess is moved to the best of a grid search this far around it in x
  /// and y (in steps of one cell) against a distance field of S's occupied cells: drift larger
  /// than overlap_distance_m (a corridor's far wall coming back into view) is caught; 0 = off;
  /// in [0, 2].
  double search_xy_m = 0.3;
  /// [deg] ...and this far in heading, in steps of 0.5 deg; in [0, 20].
  double search_deg = 2.0;
  /// What a search pose loses, in scan points on S, per squared cell of offset from the guess:
  /// odometry drifts little from one scan to the next, so texture along a wall must not pull
  /// the pose along it. On corridors_odom the error is fragile in it: 2, 3, 5, 8, 10, 20 give
  /// 0.128, 0.169, 0.124, 0.327, 0.136, 0.136 m; 0.5 diverges; in [0, 1000].
  double search_offset_cost = 5.0;

  /// After the grid search, refine by point-to-line ICP on S's cells (each scan point paired
  /// with the wall through the nearest occupied cell, Gauss-Newton on the distances along the
  /// walls' normals) instead of MRPT's point-to-point ICP (the icp_* keys) against points laid
  /// along S's walls. No point cloud and no KD-tree: a whole slam run on Freiburg 079 takes
  /// 10.8 s instead of 25.3 s, as accurate there, but less steady on Intel's sparse scans (README,
  /// "Point-to-line front end"), hence not the default.
  bool point_to_line = false;
  /// [m] point-to-line ICP pairs a scan point with a wall (the sub-cell line through an occupied
  /// cell) no farther than this; in (0, 1].
  double line_distance_m = 0.15;

  /// Every key of [scan_matching]: name, member, range, unit, meaning (see OptionTable).
  static const OptionTable<ScanMatchOptions>& table();
  /// Strict load: unknown keys, malformed numbers and out-of-range values throw ConfigError.
  void load(const IniFile& ini);
  /// Throws ConfigError ("<source>: [scan_matching] key: why") for the first rule broken.
  void validate(const std::string& source) const;
  /// Writes the section, one key per line with its meaning, in ini syntax (reloadable).
  void writeIni(std::ostream& out) const;

  // mrpt::config::CLoadableOptions
  void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                          const std::string& section) override;
  void dumpToTextStream(std::ostream& out) const override;
};

/// What one match did.
struct ScanMatchResult {
  mrpt::poses::CPose2D pose;  ///< the corrected pose, or the guess when the match was rejected
  bool matched = false;       ///< false: fell back to the guess (see fallback_reason)
  /// Why the match was rejected: "too few scan points", "too few map points", "too little
  /// overlap", "correction too large", "low inlier ratio"; nullptr when matched.
  const char* fallback_reason = nullptr;
  std::size_t map_points = 0;   ///< reference points taken from S
  std::size_t scan_points = 0;  ///< scan points matched (those on what S holds)
  std::size_t inliers = 0;      ///< scan points within inlier_distance_m of S after the match
  double inlier_ratio = 0;      ///< inliers / every usable scan point
  double correction_m = 0;      ///< distance between the guess and ICP's pose
  double correction_rad = 0;    ///< |heading difference| between the guess and ICP's pose
  unsigned icp_iterations = 0;
  int degenerate_directions = 0;  ///< pose directions kept at the guess (see min_constraint)
};

/// Whether S holds a cell occupied, DynamicGridMap::staticOccupancy() above `threshold`, by the
/// cell's raw value: worked out once for every value a cell can hold, so that a search over
/// thousands of cells per scan reads a table instead of converting each log-odds.
class OccupiedByRawValue {
 public:
  using Value = DynamicGridMap::cellType;
  explicit OccupiedByRawValue(double threshold);
  bool operator()(Value v) const { return table_[static_cast<std::size_t>(v - kMin)] != 0; }

 private:
  static constexpr long kMin = std::numeric_limits<Value>::min();
  std::vector<unsigned char> table_;
};

class ScanMatcher {
 public:
  explicit ScanMatcher(const ScanMatchOptions& options);

  /// Aligns the scan `rd` (its hits: beams short of the insertion range and of the sensor's
  /// maximum) to the occupied cells of S (never D) of `map`, starting from `guess` (the robot's
  /// pose). Returns ICP's pose when the match is good, `guess` otherwise; a scan that is not
  /// planar is not matched ("not horizontal").
  ScanMatchResult match(const DynamicGridMap& map, const RangeData& rd,
                        const mrpt::poses::CPose2D& guess) const;

  const ScanMatchOptions& options() const { return options_; }

 private:
  ScanMatchOptions options_;
  OccupiedByRawValue occupied_;  ///< S's cells above options_.occupied_threshold
};

}  // namespace dynamap
