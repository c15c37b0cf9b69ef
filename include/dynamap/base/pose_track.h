#pragma once
// PoseTrack: timestamped robot poses (ground truth or odometry), looked up by time.

#include <mrpt/poses/CPose2D.h>

#include <deque>
#include <utility>
#include <vector>

namespace dynamap {

/// A robot pose at a time (a line of poses.txt or <name>.gt.txt: `timestamp x y phi`).
struct TimedPose {
  double t = 0;
  double x = 0, y = 0, phi = 0;
};

/// How a PoseTrack matches a time to its samples ([input] pose_max_gap sets max_gap).
struct PoseTrackOptions {
  /// The widest gap [s] between two samples that a pose is interpolated across; 0 = derived
  /// from the track's own spacing: the larger of kMinAutoGap and kAutoGapFactor times the median
  /// spacing of its first kSpacingSamples gaps (a log with scans 3-5 s apart and a pose per scan
  /// interpolates across 10-15 s; a 10 Hz odometry stream across 2 s).
  double max_gap = 0;
  /// A sample this close in time [s] is the pose itself, whatever the gap around it: a scan and
  /// its pose line whose printed times differ by a rounding error still match.
  double match_tolerance = 1e-3;
  /// A time before the first or after the last sample takes that sample when this close [s].
  double end_tolerance = 0.1;
  /// Samples sharing a time but not a pose make a lookup at that time kAmbiguous (a ground
  /// truth whose timestamps repeat cannot place a scan). Off, the first sample added wins (an
  /// odometry stream's duplicate stamps are its own noise).
  bool shared_time_ambiguous = false;
};

class PoseTrack {
 public:
  static constexpr double kMinAutoGap = 2.0;  // [s]
  static constexpr double kAutoGapFactor = 3.0;
  static constexpr std::size_t kSpacingSamples = 1000;

  /// kFound (pose filled); kLater (t is past the last sample: a later sample may still come);
  /// kMissing (no sample near enough before or around t); kAmbiguous (shared_time_ambiguous
  /// only: the sample matching t shares its time with another of a different pose: the log's
  /// timestamps repeat, so time cannot say which pose is t's).
  enum class Lookup { kFound, kLater, kMissing, kAmbiguous };

  PoseTrack() = default;
  explicit PoseTrack(const PoseTrackOptions& options) : options_(options) {}

  /// Appends a sample. Samples older than the newest are inserted in order (rare: logs are
  /// nearly sorted), so lookups always see a sorted track.
  void add(double t, const mrpt::poses::CPose2D& pose);
  /// The pose at time t: the sample within match_tolerance of t if any, else interpolated
  /// between the samples around t when they are at most maxGap() apart, else the nearest end
  /// sample when within end_tolerance of it. With `complete` (no more samples will come), a t
  /// just past the last sample takes it and kLater is never returned.
  Lookup at(double t, mrpt::poses::CPose2D& pose, bool complete) const;
  /// Drops samples no lookup at time >= t can need (keeps the last one at or before t).
  void forgetBefore(double t);
  std::size_t size() const { return samples_.size(); }
  /// Samples added so far (forgotten ones included).
  std::size_t added() const { return added_; }
  /// The gap limit in force: options' max_gap, or the one derived from the spacing so far.
  double maxGap() const;

 private:
  using Sample = std::pair<double, mrpt::poses::CPose2D>;
  using Iter = std::deque<Sample>::const_iterator;
  /// The sample nearest t within match_tolerance, or end().
  Iter match(double t) const;
  bool sharedTime(Iter s) const;

  PoseTrackOptions options_;
  std::deque<Sample> samples_;
  std::size_t added_ = 0;
  std::vector<double> spacing_;     // the first kSpacingSamples positive gaps, in add order
  mutable double median_gap_ = -1;  // of spacing_; < 0 when it must be recomputed
};

}  // namespace dynamap
