#pragma once
// Pose source slam: pass 1 reads the whole log once and estimates its trajectory offline
// (Slam: submaps, a pose graph, loop closures); pass 2 maps the log again on those poses through
// OptimisedPoseSource, so S, D, the object table and every output use them.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "dynamap/input/scan_source.h"
#include "dynamap/localization/consistency.h"
#include "dynamap/localization/slam.h"
#include "dynamap/pipeline/mapper.h"

namespace dynamap {

/// What pass 1 produced.
struct SlamRun {
  std::unique_ptr<Slam> slam;               ///< the graph and the counts
  std::vector<mrpt::poses::CPose2D> poses;  ///< one per scan the source returned, in order
  InputOutcome outcome;                     ///< a fault ends pass 1 (and pass 2) at that scan
  double wall_s = 0;                        ///< time of pass 1
  /// keep_better_odometry: the scans laid out at the odometry and at slam's poses, scored
  /// (`checked`); `poses` are the odometry when its global figure is the smaller.
  bool checked = false;
  Consistency odometry_consistency, slam_consistency;
  bool kept_odometry = false;
  bool layout_full = false;  ///< a log too long for the check (ScanLayout::kMaxPoints): not made
};

/// keep_better_odometry: the scans as pass 1 reads them (their hits, as the mapper inserts
/// them, in a ScanLayout of at most `max_points`), the odometry of every scan; then decide()
/// scores the scans at the odometry and at run.poses and puts the odometry in run.poses when
/// its global figure is the smaller. No check (run.checked false) when nothing was kept, when
/// run.poses are not one per scan added, or when the layout filled up: odometry that is good
/// at first may drift later, and the first scans alone cannot tell (run.layout_full).
class OdometryCheck {
 public:
  explicit OdometryCheck(std::size_t max_points = ScanLayout::kMaxPoints);
  /// The scan of `rec`, worked out as `rd` (makeRangeData() at the insertion range).
  void add(const ScanRecord& rec, const RangeData& rd);
  void decide(SlamRun& run) const;

 private:
  ScanLayout layout_;
  std::vector<mrpt::poses::CPose2D> odometry_;  // every scan's
  std::vector<std::size_t> kept_;               // the scans in the layout
};

/// True when a run asked for `requested` maps with slam on `source` (opened with it): asked
/// for, or auto on a log whose best poses are its odometry.
bool usesSlam(PoseSource requested, const ScanSource& source);

/// Pass 1: every scan of `source` (opened with odometry poses) through Slam, then the last
/// optimisation, with `config`'s [slam], [scan_matching] (the front end), [dynamic_map] and
/// [insertion] (the submaps); then, with keep_better_odometry, the odometry instead of slam's
/// poses when it lays the scans (as the mapper inserts them) onto each other better.
/// `on_scan(done)` is called after each scan (progress). With `prior` (an earlier session's S,
/// the source's poses moved to start where the search found the log's start in it) the
/// trajectory is tied to the prior's frame (Slam::tieTo).
SlamRun estimateTrajectory(ScanSource& source, const MapConfig& config,
                           const std::function<void(std::size_t)>& on_scan = {},
                           const mrpt::maps::COccupancyGridMap2D* prior = nullptr);

/// Pass 2's source: `inner` (the same log, opened again the same way) with each scan's pose
/// replaced by pass 1's, in order. Ends where pass 1 ended.
class OptimisedPoseSource : public ScanSource {
 public:
  OptimisedPoseSource(std::unique_ptr<ScanSource> inner, std::vector<mrpt::poses::CPose2D> poses);
  bool next(ScanRecord& out) override;
  PoseSource poseSource() const override { return PoseSource::Slam; }
  const SourceStats& stats() const override { return inner_->stats(); }
  const std::string& path() const override { return inner_->path(); }
  double fractionRead() const override { return inner_->fractionRead(); }

 private:
  std::unique_ptr<ScanSource> inner_;
  std::vector<mrpt::poses::CPose2D> poses_;
  std::size_t next_ = 0;
};

}  // namespace dynamap
