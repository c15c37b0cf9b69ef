#pragma once
// One mapping run: configuration, the per-scan step, and the outputs of `dynamap map`.

#include <cstdint>
#include <fstream>
#include <functional>
#include <iosfwd>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "dynamap/dynamic_grid_map.h"
#include "dynamap/object_tracker.h"
#include "dynamap/plain_grid.h"
#include "dynamap/render.h"
#include "dynamap/scan_matcher.h"
#include "dynamap/scan_source.h"

namespace dynamap {

class IniFile;

/// Everything `dynamap map` reads from its .ini file.
struct MapConfig {
  DynamicMapOptions map;
  InsertionOptions insertion;
  ObjectOptions objects;
  ScanMatchOptions scan_matching;       ///< used when poses is ScanMatching
  PoseSource poses = PoseSource::Auto;  ///< [input] poses

  /// Strict: unknown sections or keys, bad values: ConfigError naming file, section and key.
  static MapConfig load(const IniFile& ini);
  /// The effective configuration as a reloadable .ini.
  void writeIni(std::ostream& out) const;
};

/// Counts of a run, for summary.json.
struct RunCounts {
  std::size_t scans_used = 0;
  std::map<std::string, std::size_t> scans_skipped;  ///< by reason
  std::uint64_t beams_bad = 0;                       ///< NaN / inf / negative ranges
  std::size_t time_backwards = 0;                    ///< scans older than the one before
  double first_t = 0, last_t = 0;
};

/// Counts of the scan matching, for summary.json (all zero without it).
struct ScanMatchCounts {
  std::size_t matched = 0;
  std::map<std::string, std::size_t> fallbacks;  ///< scans placed by odometry, by reason
  double sum_correction_m = 0;                   ///< over matched scans
  double max_correction_m = 0;
  std::size_t fallbackTotal() const;
};

/// The pose a scan was inserted at (poses.txt).
struct UsedPose {
  double t = 0;
  mrpt::poses::CPose2D pose;
};

/// The per-scan step: insert into S and D, update the object table, extend the robot's path.
class Mapper {
 public:
  explicit Mapper(const MapConfig& config);

  /// Inserts one scan; false when it was skipped (counted by reason). With scan matching, the
  /// scan's pose is the odometry increment since the last scan applied to the last pose used,
  /// then corrected by matching the scan against S.
  bool process(const ScanRecord& rec);

  const DynamicGridMap& map() const { return map_; }
  DynamicGridMap& map() { return map_; }
  const ObjectTracker& tracker() const { return tracker_; }
  /// The robot's path, a point every 5 cm (the cell size if larger); past kMaxPathPoints points
  /// it is thinned to every other point and the step doubles, so its memory stays bounded.
  const std::vector<PathPoint>& path() const { return path_; }
  static constexpr std::size_t kMaxPathPoints = 1 << 16;
  const RunCounts& counts() const { return counts_; }
  const MapConfig& config() const { return config_; }
  /// The pose each scan was processed at, in input order (the poses of poses.txt).
  const std::vector<UsedPose>& usedPoses() const { return used_poses_; }
  bool scanMatching() const { return matcher_ != nullptr; }
  const ScanMatchCounts& scanMatchCounts() const { return match_counts_; }
  /// The pose source of this run: the source's, or scan_matching.
  std::string poseSourceName(const ScanSource& source) const;

 private:
  /// The odometry pose of `rec` turned into the pose to insert it at (scan matching).
  mrpt::poses::CPose2D correctPose(const ScanRecord& rec);

  MapConfig config_;
  DynamicGridMap map_;
  ObjectTracker tracker_;
  std::vector<PathPoint> path_;  // decimated: a point every path_step_ metres
  double path_step_;
  RunCounts counts_;
  bool have_t_ = false;
  std::vector<UsedPose> used_poses_;
  std::unique_ptr<ScanMatcher> matcher_;  // null unless poses is ScanMatching
  ScanMatchCounts match_counts_;
  bool have_pose_ = false;
  mrpt::poses::CPose2D last_odometry_, last_pose_;
};

/// tracks.csv, streamed while the run goes: after every scan, one row per present object
/// (`scan_index,t,object_id,cx,cy,size_m,x_min,x_max,y_min,y_max`). Written under a temporary
/// name and renamed by finish(), so an interrupted run leaves no tracks.csv; rows are never
/// kept in memory.
class TrackLog {
 public:
  /// Opens the temporary file in `dir` (which must exist); throws std::runtime_error.
  explicit TrackLog(const std::string& dir);
  ~TrackLog();
  TrackLog(const TrackLog&) = delete;
  TrackLog& operator=(const TrackLog&) = delete;
  void append(std::size_t scan_index, double t, const ObjectTracker& tracker);
  /// Flushes and renames to tracks.csv; throws on I/O errors.
  void finish();

 private:
  std::string dir_, tmp_;
  std::unique_ptr<std::ofstream> out_;
};

/// poses.txt: `timestamp x y phi` per scan, the poses used (MRPT's .gt.txt format).
void writePosesTxt(std::ostream& out, const std::vector<UsedPose>& poses);

/// Writers of the object table, exact and fixed-format (byte-identical between runs).
void writeObjectsCsv(std::ostream& out, const ObjectTracker& tracker);
void writeEventsCsv(std::ostream& out, const ObjectTracker& tracker);

/// What happened to the input: empty `fault` means it was read to its end.
struct InputOutcome {
  std::string fault;
};

/// Feeds every scan of `source` to `mapper`, calling `on_scan` after each with the record as
/// mapped (its pose the one used, corrected when scan matching). An InputError from
/// the source ends the loop and is returned as the outcome's fault: everything before it stays.
InputOutcome runMapping(ScanSource& source, Mapper& mapper,
                        const std::function<void(const ScanRecord&)>& on_scan = {});

/// Writes every output of `dynamap map` into `dir` (which must exist).
struct OutputInfo {
  std::string input;
  double wall_s = 0;
  InputOutcome outcome;
  /// The plain MRPT grid of the same scans (nullptr: none): compared with S in summary.json
  /// and drawn as mrpt_plain.png.
  const PlainGrid* baseline = nullptr;
  double baseline_wall_s = 0;  ///< time spent building it
};
void writeMapOutputs(const std::string& dir, const Mapper& mapper, const ScanSource& source,
                     const OutputInfo& info);

}  // namespace dynamap
