#pragma once
// The one factory of scan sources: a log's format is told by its content, not its name.

#include <mrpt/poses/CPose2D.h>

#include <memory>
#include <string>

#include "dynamap/input/bag_source.h"
#include "dynamap/input/carmen_reader.h"
#include "dynamap/input/scan_source.h"

namespace dynamap {

/// How a log is read, whatever its format.
struct InputOptions {
  PoseSource poses = PoseSource::Auto;
  mrpt::poses::CPose2D fixed_pose;  ///< the pose of every scan under PoseSource::Fixed
  /// How scans find their pose by time in a pose stream (rawlog ground truth and odometry,
  /// and a CARMEN log's ODOM lines: carmen.odometry_track is set from it).
  PoseTrackOptions pose_track;
  CarmenOptions carmen;             ///< applies to CARMEN logs
  BagOptions bag;                   ///< applies to ROS bags
};

/// Opens `path`, telling its format by content (ROS 1 bag, CARMEN text, simplemap, rawlog).
/// ScanMatching and Slam open the odometry poses (Slam: an InputError naming the log when a
/// rawlog has no odometry); Fixed opens any format and puts every scan at
/// options.fixed_pose. Throws InputError if the file cannot be read or no scan can have a pose
/// under the source asked for (a bag in a build without bag support, too).
std::unique_ptr<ScanSource> openScanSource(const std::string& path, const InputOptions& options);

/// The same with default options but `source` and `carmen` (nullptr: defaults).
std::unique_ptr<ScanSource> openScanSource(const std::string& path, PoseSource source,
                                           const CarmenOptions* carmen = nullptr);

}  // namespace dynamap
