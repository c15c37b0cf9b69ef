#include "dynamap/pipeline/slam_run.h"

#include <chrono>
#include <cmath>
#include <optional>

#include "dynamap/localization/likelihood_field.h"

namespace dynamap {

bool usesSlam(PoseSource requested, const ScanSource& source) {
  return requested == PoseSource::Slam ||
         (requested == PoseSource::Auto && source.poseSource() == PoseSource::Odometry);
}

namespace {

/// The scans as pass 1 reads them, kept for keep_better_odometry: their hits (as the mapper
/// inserts them) in a ScanLayout, the odometry of every scan, and which scans the layout holds.
struct OdometryCheck {
  ScanLayout layout;
  std::vector<mrpt::poses::CPose2D> odometry;  // every scan's
  std::vector<std::size_t> kept;               // the scans in the layout
  RangeData rd;

  void add(const ScanRecord& rec, const InsertionOptions& insertion) {
    odometry.push_back(rec.pose);
    if (layout.full()) return;
    makeRangeData(*rec.scan, insertion.max_distance_insertion,
                  insertion.horizontal_tolerance_deg * M_PI / 180.0, rd);
    if (rd.planar && layout.add(hitPoints(rd))) kept.push_back(odometry.size() - 1);
  }

  /// Scores both trajectories on the scans kept; the odometry replaces run.poses if better.
  /// Not when the layout filled up: odometry that is good at first may drift later, so the
  /// first scans alone cannot tell.
  void decide(SlamRun& run) const {
    run.layout_full = layout.full();
    if (kept.empty() || layout.full() || odometry.size() != run.poses.size()) return;
    std::vector<mrpt::poses::CPose2D> at_odometry, at_slam;
    for (std::size_t i : kept) {
      at_odometry.push_back(odometry[i]);
      at_slam.push_back(run.poses[i]);
    }
    run.checked = true;
    run.odometry_consistency = layout.score(at_odometry);
    run.slam_consistency = layout.score(at_slam);
    // NaN (too few scans for the global figure) compares false: slam's poses stay.
    if (run.odometry_consistency.global_m < run.slam_consistency.global_m) {
      run.poses = odometry;
      run.kept_odometry = true;
    }
  }
};

}  // namespace

SlamRun estimateTrajectory(ScanSource& source, const MapConfig& config,
                           const std::function<void(std::size_t)>& on_scan) {
  const auto start = std::chrono::steady_clock::now();
  SlamRun run;
  run.slam =
      std::make_unique<Slam>(config.slam, config.scan_matching, config.map, config.insertion);
  std::optional<OdometryCheck> check;
  if (config.slam.keep_better_odometry) check.emplace();
  ScanRecord rec;
  std::size_t done = 0;
  while (true) {
    try {
      if (!source.next(rec)) break;
    } catch (const InputError& e) {
      run.outcome.fault = e.what();
      break;
    }
    run.slam->add(rec.pose, *rec.scan);
    if (check) check->add(rec, config.insertion);
    if (on_scan) on_scan(++done);
  }
  run.slam->finish();
  run.poses = run.slam->poses();
  if (check) check->decide(run);
  run.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return run;
}

OptimisedPoseSource::OptimisedPoseSource(std::unique_ptr<ScanSource> inner,
                                         std::vector<mrpt::poses::CPose2D> poses)
    : inner_(std::move(inner)), poses_(std::move(poses)) {}

bool OptimisedPoseSource::next(ScanRecord& out) {
  // Pass 1 stopped at a fault after poses_.size() scans: pass 2 stops there too.
  if (next_ >= poses_.size() || !inner_->next(out)) return false;
  out.pose = poses_[next_++];
  return true;
}

}  // namespace dynamap
