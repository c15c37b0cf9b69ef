#pragma once
// ScanSource: a stream of (timestamp, pose, scan) read from a log one record at a time.
//
// Readers: MRPT rawlogs (action/sensory-frame pairs or observations only, plain or gz), MRPT
// simplemaps (.simplemap[.gz]), CARMEN logs and ROS 1 bags. The pose of each scan comes from the
// source the user picks (PoseSource); a scan without a pose under that source is an error naming
// the scan.

#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose2D.h>

#include <cstdint>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace dynamap {

/// Where the robot's pose for each scan comes from.
enum class PoseSource {
  Auto,       ///< the best one present: simplemap > ground_truth > slam (a log with odometry only)
  Simplemap,  ///< the keyframe poses of a simplemap
  GroundTruth,  ///< CObservationRobotPose in the log, or a companion <log>.gt.txt file
  Odometry,     ///< CObservationOdometry, or integrated CActionRobotMovement2D
  /// Odometry corrected by matching each scan against the static map (ScanMatcher). A source
  /// opened with it reads odometry; the Mapper does the matching.
  ScanMatching,
  /// One pose for every scan (a standing robot): InputOptions::fixed_pose. Every format offers
  /// it; the log's own poses, if any, are ignored.
  Fixed,
  /// Odometry and scans turned into a trajectory offline (pose graph with loop closure, see
  /// localization/slam.h), then mapped on it. A source opened with it reads odometry.
  Slam,
};

/// "auto", "simplemap", "ground_truth", "odometry", "scan_matching", "fixed", "slam";
/// throws
/// std::invalid_argument otherwise.
PoseSource parsePoseSource(const std::string& name);
std::string toString(PoseSource source);

/// One laser scan with the robot pose it was taken from.
struct ScanRecord {
  std::size_t index = 0;  ///< 0-based, counting every scan read (used or skipped)
  double t = 0;           ///< timestamp, seconds since the UNIX epoch
  mrpt::poses::CPose2D pose;
  mrpt::obs::CObservation2DRangeScan::Ptr scan;
};

/// A fault in the input data itself (truncated file, corrupt record, missing pose). The message
/// names the file and the record index or line.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Counts a source keeps while reading, for the run summary.
struct SourceStats {
  /// What a record is: "records" (rawlog objects), "lines" (CARMEN), "messages" (ROS bag).
  std::string record_unit = "records";
  std::size_t records = 0;  ///< top-level records (objects, lines, messages) read
  std::size_t scans = 0;    ///< 2D laser scans seen
  /// Records not turned into scans, by reason (a CARMEN comment line is a line, not a scan).
  std::map<std::string, std::size_t> skipped;
  /// What the reader assumed about the input that a user should know (each names the file).
  std::vector<std::string> warnings;
};

class ScanSource {
 public:
  virtual ~ScanSource() = default;
  /// Fills `out` with the next scan and returns true; false at the end of the input.
  /// Throws InputError on a fault; every scan returned before it stays valid.
  virtual bool next(ScanRecord& out) = 0;
  /// The pose source in use (never Auto once the source is open).
  virtual PoseSource poseSource() const = 0;
  virtual const SourceStats& stats() const = 0;
  /// The file being read.
  virtual const std::string& path() const = 0;
  /// How much of the input has been read, in [0, 1], or negative when unknown (compressed
  /// streams); drives the progress line's estimate of the time left.
  virtual double fractionRead() const { return -1.0; }
  /// Which of the format's streams the poses are, when it has several (e.g. a CARMEN log's
  /// "the odometry fields of each laser line"); empty when poseSource() says it all.
  virtual std::string poseDetail() const { return {}; }
};

/// The bytes a reader of `path` will see: the file's size, or for gzip the trailer's ISIZE (the
/// uncompressed size modulo 4 GiB); 0 when unknown. For progress estimates only.
std::uint64_t uncompressedSize(const std::string& path);

/// The bytes a reader of `path` can at most see, for bounding what a record may allocate: the
/// file's size, or for gzip the trailer's ISIZE when the file is too small to inflate past 4 GiB
/// (so ISIZE cannot have wrapped); 0 when no bound is known. A gzip file of several members
/// states only its last member's size: such files are not written by MRPT or CARMEN tools.
std::uint64_t uncompressedSizeBound(const std::string& path);

}  // namespace dynamap
