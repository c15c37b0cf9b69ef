#pragma once
// PoseTrack: timestamped robot poses (ground truth or odometry), looked up by time.

#include <mrpt/poses/CPose2D.h>

#include <deque>
#include <utility>

namespace dynamap {

/// A robot pose at a time (a line of poses.txt or <name>.gt.txt: `timestamp x y phi`).
struct TimedPose {
  double t = 0;
  double x = 0, y = 0, phi = 0;
};

class PoseTrack {
 public:
  /// A pose at time t, interpolated between the samples around it when they are at most
  /// kMaxGap apart, or taken from the nearest end sample when within kEndTolerance of it.
  static constexpr double kMaxGap = 2.0;        // [s]
  static constexpr double kEndTolerance = 0.1;  // [s]

  enum class Lookup { kFound, kLater, kMissing };

  /// Appends a sample. Samples older than the newest are inserted in order (rare: logs are
  /// nearly sorted), so lookups always see a sorted track.
  void add(double t, const mrpt::poses::CPose2D& pose);
  /// kFound (pose filled), kLater (t is past the last sample: a later sample may still come), or
  /// kMissing (no sample near enough before or around t). With `complete` (no more samples will
  /// come), a t just past the last sample takes it and kLater is never returned.
  Lookup at(double t, mrpt::poses::CPose2D& pose, bool complete) const;
  /// Drops samples no lookup at time >= t can need (keeps the last one at or before t).
  void forgetBefore(double t);
  std::size_t size() const { return samples_.size(); }

 private:
  std::deque<std::pair<double, mrpt::poses::CPose2D>> samples_;
};

}  // namespace dynamap
