#pragma once
// One mapping run: configuration, the per-scan step, and the outputs of `dynamap map`.

#include <cstdint>
#include <functional>
#include <iosfwd>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "dynamap/base/option_table.h"
#include "dynamap/input/carmen_reader.h"
#include "dynamap/input/scan_source.h"
#include "dynamap/localization/scan_matcher.h"
#include "dynamap/localization/slam.h"
#include "dynamap/mapping/dynamic_grid_map.h"
#include "dynamap/objects/object_tracker.h"
#include "dynamap/people/leg_classifier.h"
#include "dynamap/people/person_tracker.h"
#include "dynamap/pipeline/people_objects.h"
#include "dynamap/pipeline/robot_path.h"
#include "dynamap/pipeline/session_changes.h"

namespace dynamap {

class IniFile;

/// Everything `dynamap map` reads from its .ini file.
struct MapConfig {
  DynamicMapOptions map;
  InsertionOptions insertion;
  ObjectOptions objects;
  PeopleOptions people;
  ScanMatchOptions scan_matching;       ///< used when poses is ScanMatching
  SlamOptions slam;                     ///< used when poses is Slam
  ChangeOptions changes;                ///< used when a session continues a prior one
  PoseSource poses = PoseSource::Auto;  ///< [input] poses
  mrpt::poses::CPose2D fixed_pose;      ///< [input] fixed_pose: every scan's pose when Fixed
  /// [input] pose_max_gap [s]: PoseTrackOptions::max_gap (0: from the log's own spacing).
  double pose_max_gap = 0;
  /// [input] carmen_odometry: the odometry stream of a CARMEN log.
  CarmenOdometrySource carmen_odometry = CarmenOdometrySource::LaserLines;

  /// Strict: unknown sections or keys, bad values: ConfigError naming file, section and key.
  static MapConfig load(const IniFile& ini);
  /// The effective configuration as a reloadable .ini ([slam] only when poses is Slam).
  void writeIni(std::ostream& out) const;
  /// Every key of every section with its default, unit, range and meaning (for docs and tests).
  static std::vector<OptionDoc> describe();
};

/// Counts of a run, for summary.json.
struct RunCounts {
  std::size_t scans_used = 0;
  std::map<std::string, std::size_t> scans_skipped;  ///< by reason
  std::uint64_t beams_bad = 0;                       ///< NaN / inf / negative ranges
  std::size_t time_backwards = 0;                    ///< scans older than the one before
  std::size_t first_backwards_index = 0;             ///< the first of them (ScanRecord::index)
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

/// What the per-scan step did with one scan.
struct ScanResult {
  bool inserted = false;              ///< false: skipped, see skip_reason
  const char* skip_reason = nullptr;  ///< why it was skipped (counted in RunCounts)
  /// The robot pose the scan was mapped at: the record's, or corrected by scan matching.
  mrpt::poses::CPose2D pose;
  std::size_t object_events = 0;  ///< events the object table gained with this scan
};

/// The per-scan step: detect people in S's free space, insert into S and D, track the people,
/// update the object table (never where a person is), extend the robot's path.
class Mapper {
 public:
  explicit Mapper(const MapConfig& config);

  /// The per-scan step: S and D, the object table, the robot's path. A skipped scan is counted
  /// by reason. With scan matching, the scan's pose is the odometry increment since the last
  /// scan applied to the last pose used, then corrected by matching the scan against S.
  ScanResult process(const ScanRecord& rec);

  /// Continues an earlier session (before the first scan): S becomes the prior's, D stays
  /// empty, the object table is the prior's (every object absent until found again, from the
  /// first scan on) and the run reports what changed (changes()). Throws std::invalid_argument
  /// when the prior's grid does not fit this run's [dynamic_map] (its resolution, its size).
  void continueFrom(SessionState prior);
  /// After the last scan of a continued session: objects on structure the session added are
  /// retired (ObjectTracker::retire), then the carried ids settle on the objects present
  /// (ObjectTracker::settleCarried). Nothing when not continuing one.
  void finishSession();
  /// The change report of a continued session (empty otherwise): after finishSession() the one
  /// it settled on, else as the maps stand.
  std::vector<ChangeRow> changeReport() const;
  /// The change report's state when continuing a prior session; null otherwise.
  const SessionChanges* changes() const { return changes_.get(); }
  /// What this run leaves for the next session: S, the object table, the last pose and time.
  SessionState sessionState() const;
  /// Which session of its building this run is: 1, or the prior's count plus one.
  int sessions() const { return sessions_; }

  const DynamicGridMap& map() const { return map_; }
  DynamicGridMap& map() { return map_; }
  const ObjectTracker& tracker() const { return tracker_; }
  const PersonTracker& people() const { return people_; }
  /// The robot's path (RobotPath: decimated and bounded).
  const std::vector<PathPoint>& path() const { return path_.points(); }
  const RunCounts& counts() const { return counts_; }
  const MapConfig& config() const { return config_; }
  bool scanMatching() const { return matcher_ != nullptr; }
  const ScanMatchCounts& scanMatchCounts() const { return match_counts_; }
  /// The pose source of this run: the source's, or scan_matching.
  std::string poseSourceName(const ScanSource& source) const;

 private:
  void countTime(const ScanRecord& rec);
  /// The odometry pose of `rec` turned into the pose to insert it at (scan matching).
  mrpt::poses::CPose2D correctPose(const ScanRecord& rec, const RangeData& rd);
  /// People in the scan at `pose`, seen against S before it (the paper's S_{t-1}); and D held
  /// while the last scans' hits land mostly where S holds free space (d_hold_share), some of
  /// them on surfaces wider than any object: the poses are off, and what D would gain there is
  /// the map's own walls seen from the wrong place.
  std::vector<PersonDetection> detectAndCheck(const RangeData& rd, const mrpt::poses::CPose2D& pose,
                                              double& free_share);

  MapConfig config_;
  DynamicGridMap map_;
  ObjectTracker tracker_;
  PersonTracker people_;
  LegClassifier own_legs_;               // a model of [people] leg_model
  const LegClassifier* legs_ = nullptr;  // the one in use; null: no leg classifier
  PeopleObjects people_objects_;
  RobotPath path_;
  RangeData range_;                   // this scan's geometry; its buffers kept from scan to scan
  ScanHits hits_;                     // this scan's hit points for the people detector; likewise
  std::vector<HitPoint2> free_hits_;  // this scan's hits where S holds free space
  ShareAverage free_share_;           // of the scans' hits, where S holds free space
  ShareAverage surface_share_;        // ...on surfaces wider than objects.max_size
  /// D holds only while some hits (one in twenty) lie on such surfaces, besides.
  static constexpr double kSurfaceShare = 0.05;
  RunCounts counts_;
  bool have_t_ = false;
  // A prior session: its table waits for the first scan's time; sessions counts them.
  std::unique_ptr<std::vector<TrackedObject>> carried_;
  std::unique_ptr<SessionChanges> changes_;
  int sessions_ = 1;
  mrpt::poses::CPose2D last_scan_pose_;                  // of the last scan inserted
  std::optional<std::vector<ChangeRow>> final_changes_;  // set by finishSession()
  double last_scan_t_ = 0;
  std::size_t last_scan_index_ = 0;
  std::unique_ptr<ScanMatcher> matcher_;  // null unless poses is ScanMatching
  ScanMatchCounts match_counts_;
  bool have_pose_ = false;
  mrpt::poses::CPose2D last_odometry_, last_pose_;
};

/// What happened to the input: empty `fault` means it was read to its end.
struct InputOutcome {
  std::string fault;
};

/// Called after each scan with the record as mapped (its pose the one used) and the result.
using ScanCallback = std::function<void(const ScanRecord&, const ScanResult&)>;
/// Feeds every scan of `source` to `mapper`, calling `on_scan` after each. An InputError from
/// the source ends the loop and is returned as the outcome's fault: everything before it stays.
InputOutcome runMapping(ScanSource& source, Mapper& mapper, const ScanCallback& on_scan = {});

}  // namespace dynamap
