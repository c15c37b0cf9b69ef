#include "dynamap/pipeline/slam_run.h"

#include <chrono>

namespace dynamap {

bool usesSlam(PoseSource requested, const ScanSource& source) {
  return requested == PoseSource::Slam ||
         (requested == PoseSource::Auto && source.poseSource() == PoseSource::Odometry);
}

SlamRun estimateTrajectory(ScanSource& source, const MapConfig& config,
                           const std::function<void(std::size_t)>& on_scan) {
  const auto start = std::chrono::steady_clock::now();
  SlamRun run;
  run.slam =
      std::make_unique<Slam>(config.slam, config.scan_matching, config.map, config.insertion);
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
    if (on_scan) on_scan(++done);
  }
  run.slam->finish();
  run.poses = run.slam->poses();
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
