#include "dynamap/input/rawlog_source.h"

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <cmath>
#include <deque>

#include "dynamap/base/pose_track.h"
#include "dynamap/input/mrpt_records.h"
#include "dynamap/input/pose_file.h"

namespace dynamap {
namespace {

using mrpt::obs::CObservation2DRangeScan;

/// Streams an MRPT rawlog (either format), one record at a time, resolving each scan's pose by
/// time from the chosen pose source.
class RawlogSource : public ScanSource {
 public:
  RawlogSource(const std::string& path, PoseSource source, const PoseTrackOptions& track)
      : path_(path),
        source_(source),
        bytes_(static_cast<double>(uncompressedSize(path))),
        size_bound_(uncompressedSizeBound(path)),
        poses_(trackOptions(track, source)) {
    if (!in_.open(path)) throw InputError(path + ": cannot open");
    if (source_ == PoseSource::GroundTruth && !hasGroundTruthInLog(path)) {
      const std::string gt = companionGroundTruth(path);
      if (!fileExists(gt)) {
        throw InputError(path +
                         ": no ground-truth poses (no CObservationRobotPose in the log, "
                         "no companion file " +
                         gt + ")");
      }
      for (const TimedPose& p : readPoseFile(gt)) {
        poses_.add(p.t, mrpt::poses::CPose2D(p.x, p.y, p.phi));
      }
      poses_from_file_ = true;
    }
  }

  static bool hasGroundTruthInLog(const std::string& path);

  /// Ground truth whose times repeat cannot place a scan: an error, not the first pose.
  static PoseTrackOptions trackOptions(PoseTrackOptions o, PoseSource source) {
    o.shared_time_ambiguous = source == PoseSource::GroundTruth;
    return o;
  }

  bool next(ScanRecord& out) override {
    while (true) {
      if (!ready_.empty()) {
        out = std::move(ready_.front());
        ready_.pop_front();
        return true;
      }
      if (eof_) return flushPending(out);
      readRecord();
      resolvePending(false);
    }
  }

  PoseSource poseSource() const override { return source_; }
  const SourceStats& stats() const override { return stats_; }
  const std::string& path() const override { return path_; }
  double fractionRead() const override {
    return bytes_ > 0 ? std::min(1.0, static_cast<double>(in_.getPosition()) / bytes_) : -1.0;
  }

 private:
  struct Pending {
    std::size_t index;
    double t;
    CObservation2DRangeScan::Ptr scan;
    std::size_t samples_before;  // poses_.added() when the scan was read
  };

  void readRecord() {
    const uint64_t start = in_.getPosition();
    mrpt::serialization::CSerializable::Ptr obj;
    try {
      obj = readBoundedObject(in_, recordAllocationBound(size_bound_, start));
    } catch (const std::exception& e) {
      eof_ = true;
      // The end of the file between two records is the log's end, not a fault.
      const bool clean_end =
          dynamic_cast<const mrpt::serialization::CExceptionEOF*>(&e) && in_.getPosition() == start;
      if (!clean_end) {
        fault_ = describeRecordFault(e, in_, "record " + std::to_string(stats_.records), start);
      }
      return;
    }
    ++stats_.records;
    if (!obj) return;
    if (auto sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(obj)) {
      for (const auto& o : *sf) take(o);
      if (!odometry_observed_) {
        // Action / sensory-frame format: the odometry integrated so far (the origin before the
        // first action) is the pose of this frame's observations.
        const double t = frameTime(*sf);
        if (std::isfinite(t) && source_ == PoseSource::Odometry) poses_.add(t, odometry_);
      }
    } else if (auto acts = std::dynamic_pointer_cast<mrpt::obs::CActionCollection>(obj)) {
      if (auto mv = acts->getBestMovementEstimation()) {
        odometry_ = odometry_ + mv->poseChange->getMeanVal();
      }
    } else if (auto o = std::dynamic_pointer_cast<mrpt::obs::CObservation>(obj)) {
      take(o);
    } else {
      ++stats_.skipped[std::string("record of class ") + obj->GetRuntimeClass()->className];
    }
  }

  static double frameTime(const mrpt::obs::CSensoryFrame& sf) {
    for (const auto& o : sf) {
      if (o && o->timestamp != INVALID_TIMESTAMP) return toSeconds(o->timestamp);
    }
    return NAN;
  }

  void take(const mrpt::obs::CObservation::Ptr& o) {
    if (!o) return;
    const double t = o->timestamp == INVALID_TIMESTAMP ? NAN : toSeconds(o->timestamp);
    if (auto scan = std::dynamic_pointer_cast<CObservation2DRangeScan>(o)) {
      normalizeFlags(*scan);
      const std::size_t index = stats_.scans++;
      if (!std::isfinite(t)) {
        throw InputError(path_ + ": scan " + std::to_string(index) + " has no timestamp");
      }
      pending_.push_back({index, t, scan, poses_.added()});
      if (pending_.size() > kMaxPending) {
        throw InputError(path_ + ": scan " + std::to_string(pending_.front().index) + " has no " +
                         toString(source_) + " pose within " + std::to_string(kMaxPending) +
                         " scans after it");
      }
    } else if (auto odo = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(o)) {
      odometry_observed_ = true;
      if (source_ == PoseSource::Odometry && std::isfinite(t)) poses_.add(t, odo->odometry);
    } else if (auto gt = std::dynamic_pointer_cast<mrpt::obs::CObservationRobotPose>(o)) {
      if (source_ == PoseSource::GroundTruth && !poses_from_file_ && std::isfinite(t)) {
        poses_.add(t, mrpt::poses::CPose2D(gt->pose.mean));
      }
    }
  }

  /// Moves pending scans whose pose is now known to ready_. At the end of input (`final`), a
  /// scan past the last pose can only take it if close enough in time.
  void resolvePending(bool final) {
    while (!pending_.empty()) {
      Pending& p = pending_.front();
      // Poses from a file are all there; from the log, the scan's own pose may follow it (a
      // scan stamped before poses already read, its clock stepped back, must not be
      // interpolated between others): a scan waits for at least one sample read after it.
      const bool complete = final || poses_from_file_;
      if (!complete && source_ != PoseSource::Fixed && poses_.added() == p.samples_before) return;
      mrpt::poses::CPose2D pose;  // the origin under Fixed: withFixedPose sets the pose
      const PoseTrack::Lookup r =
          source_ == PoseSource::Fixed ? PoseTrack::Lookup::kFound : poses_.at(p.t, pose, complete);
      if (r == PoseTrack::Lookup::kLater) return;  // wait for a later pose
      if (r != PoseTrack::Lookup::kFound) {
        if (!ready_.empty()) return;     // the scans before it go out first; the error next
        if (final && !fault_.empty()) {  // the fault, not the pose, is what went wrong
          pending_.clear();
          return;
        }
        throw InputError(path_ + ": " + noPose(p, r));
      }
      const double t = p.t;
      ready_.push_back({p.index, t, pose, std::move(p.scan)});
      pending_.pop_front();  // p is gone from here on
      // Poses from a little before it stay: a later scan stamped earlier (a clock stepping back)
      // still finds its pose.
      poses_.forgetBefore(t - kPoseHistory_s);
    }
  }

  std::string noPose(const Pending& p, PoseTrack::Lookup r) const {
    const std::string scan = "scan " + std::to_string(p.index) + " (t=" + std::to_string(p.t) + ")";
    if (r == PoseTrack::Lookup::kAmbiguous) {
      return scan + ": several different " + toString(source_) +
             " poses share its timestamp, so time cannot place it (the log's timestamps repeat: "
             "all zero, or the time of a conversion?)";
    }
    return scan + " has no " + toString(source_) + " pose within " +
           std::to_string(poses_.maxGap()) + " s (see [input] pose_max_gap)";
  }

  bool flushPending(ScanRecord& out) {
    resolvePending(true);
    if (!ready_.empty()) {
      out = std::move(ready_.front());
      ready_.pop_front();
      return true;
    }
    if (!fault_.empty()) {
      const std::string f = fault_;
      fault_.clear();
      throw InputError(path_ + ": " + f);
    }
    return false;
  }

  static constexpr std::size_t kMaxPending = 10000;
  static constexpr double kPoseHistory_s = 10.0;

  std::string path_;
  PoseSource source_;
  double bytes_;              // uncompressed size, for fractionRead (0: unknown)
  std::uint64_t size_bound_;  // what the file can hold at most, bounding a record's allocations
  mrpt::io::CFileGZInputStream in_;
  SourceStats stats_;
  PoseTrack poses_;
  bool poses_from_file_ = false;
  mrpt::poses::CPose2D odometry_;
  bool odometry_observed_ = false;  // CObservationOdometry seen: frames carry no pose of their own
  std::deque<Pending> pending_;
  std::deque<ScanRecord> ready_;
  bool eof_ = false;
  std::string fault_;
};

}  // namespace

RawlogPeek peekRawlog(const std::string& path) {
  RawlogPeek peek;
  mrpt::io::CFileGZInputStream in;
  if (!in.open(path)) throw InputError(path + ": cannot open");
  const std::uint64_t size_bound = uncompressedSizeBound(path);
  auto see = [&](const mrpt::obs::CObservation::Ptr& o) {
    if (std::dynamic_pointer_cast<mrpt::obs::CObservationRobotPose>(o)) peek.ground_truth = true;
    if (std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(o)) peek.odometry = true;
  };
  // A few hundred records tell which kinds of pose the log carries.
  for (int i = 0; i < 300; ++i) {
    mrpt::serialization::CSerializable::Ptr obj;
    try {
      obj = readBoundedObject(in, recordAllocationBound(size_bound, in.getPosition()));
    } catch (const std::exception&) {
      break;  // faults are reported by the real pass, at their record
    }
    if (auto sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(obj)) {
      for (const auto& o : *sf) see(o);
    } else if (std::dynamic_pointer_cast<mrpt::obs::CActionCollection>(obj)) {
      peek.odometry = true;
    } else if (auto o = std::dynamic_pointer_cast<mrpt::obs::CObservation>(obj)) {
      see(o);
    }
  }
  return peek;
}

bool RawlogSource::hasGroundTruthInLog(const std::string& path) {
  return peekRawlog(path).ground_truth;
}

std::unique_ptr<ScanSource> openRawlogSource(const std::string& path, PoseSource source,
                                             const PoseTrackOptions& track) {
  return std::make_unique<RawlogSource>(path, source, track);
}

}  // namespace dynamap
