#pragma once
// The MRPT rawlog reader: both formats (action / sensory-frame pairs, or observations only),
// plain or gz, streamed one record at a time.

#include <memory>
#include <string>

#include "dynamap/base/pose_track.h"
#include "dynamap/input/scan_source.h"

namespace dynamap {

/// What pose sources a rawlog offers, from its first few hundred records.
struct RawlogPeek {
  bool ground_truth = false;  ///< CObservationRobotPose records
  bool odometry = false;      ///< CObservationOdometry or CActionRobotMovement2D
};
/// Throws InputError if the file cannot be opened; a fault in the first records ends the peek.
RawlogPeek peekRawlog(const std::string& path);

/// A rawlog's scans with poses from `source` (GroundTruth: CObservationRobotPose, else the
/// companion <log>.gt.txt; Odometry: CObservationOdometry, else integrated actions), each looked
/// up by the scan's time under `track`'s rules; Fixed: every scan at the origin, the log's poses
/// unread. A scan waits for at least one pose sample read after it (its own may follow it: a
/// scan stamped before poses already read, its clock stepped back, takes its own, not one
/// interpolated between others). A scan without a pose, or whose time matches several
/// different poses (timestamps that repeat: time cannot place it), is an InputError naming it; a
/// record cut off or corrupt is an InputError naming its index and byte offset, after every scan
/// before it.
std::unique_ptr<ScanSource> openRawlogSource(const std::string& path, PoseSource source,
                                             const PoseTrackOptions& track = {});

}  // namespace dynamap
