#include "dynamap/pipeline/slam_run.h"

#include <chrono>
#include <optional>

namespace dynamap {

bool usesSlam(PoseSource requested, const ScanSource& source) {
  return requested == PoseSource::Slam ||
         (requested == PoseSource::Auto && source.poseSource() == PoseSource::Odometry);
}

OdometryCheck::OdometryCheck(std::size_t max_points) : layout_(ConsistencyOptions{}, max_points) {}

void OdometryCheck::add(const ScanRecord& rec, const RangeData& rd) {
  odometry_.push_back(rec.pose);
  if (layout_.addRange(rd)) kept_.push_back(odometry_.size() - 1);
}

void OdometryCheck::decide(SlamRun& run) const {
  run.layout_full = layout_.full();
  if (kept_.empty() || layout_.full() || odometry_.size() != run.poses.size()) return;
  std::vector<mrpt::poses::CPose2D> at_odometry, at_slam;
  for (std::size_t i : kept_) {
    at_odometry.push_back(odometry_[i]);
    at_slam.push_back(run.poses[i]);
  }
  run.checked = true;
  run.odometry_consistency = layout_.score(at_odometry);
  run.slam_consistency = layout_.score(at_slam);
  // A tie (a log too short for any scan to have partners: both figures the cap) or NaN
  // compares false: slam's poses stay.
  if (run.odometry_consistency.global_m < run.slam_consistency.global_m) {
    run.poses = odometry_;
    run.kept_odometry = true;
  }
}

SlamRun estimateTrajectory(ScanSource& source, const MapConfig& config,
                           const std::function<void(std::size_t)>& on_scan,
                           const mrpt::maps::COccupancyGridMap2D* prior) {
  const auto start = std::chrono::steady_clock::now();
  SlamRun run;
  run.slam =
      std::make_unique<Slam>(config.slam, config.scan_matching, config.map, config.insertion);
  if (prior) {
    run.slam->tieTo(LikelihoodField::fromGrid(*prior, config.slam.occupied_threshold,
                                              config.slam.field_sigma_m));
  }
  std::optional<OdometryCheck> check;
  if (config.slam.keep_better_odometry) check.emplace();
  ScanRecord rec;
  RangeData rd;
  std::size_t done = 0;
  while (true) {
    try {
      if (!source.next(rec)) break;
    } catch (const InputError& e) {
      run.outcome.fault = e.what();
      break;
    }
    // The scan's geometry once, as the mapper works it out, for Slam and the check alike.
    config.insertion.rangeData(*rec.scan, rd);
    run.slam->add(rec.pose, rd);
    if (check) check->add(rec, rd);
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
