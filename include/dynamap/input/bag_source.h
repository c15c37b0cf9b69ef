#pragma once
// Reading ROS 1 bags (format 2.0) with ROS's own rosbag library: sensor_msgs/LaserScan scans,
// their poses from /tf and /tf_static or from nav_msgs/Odometry, and ground truth from a map
// frame.
//
// A scan keeps its header stamp (the bag's record time when the stamp is zero), its frame (as
// the MRPT sensorLabel) and its beam geometry: beam i at angle_min + i * angle_increment, valid
// when finite and within [range_min, range_max] (ROS: values outside are to be discarded).
// Poses are 2D (x, y, yaw) and taken at each scan's stamp, interpolated between the transforms
// around it (PoseTrack's rules: samples at most PoseTrack::maxGap() apart, an end sample within
// 0.1 s):
//   mount        base_frame -> the scan's frame (usually /tf_static), as the scan's sensorPose;
//   odometry     odom_frame -> base_frame from /tf, or the pose of nav_msgs/Odometry on
//                odom_topic;
//   ground truth gt_frame -> base_frame from /tf (e.g. map -> odom -> base_link).
// Transforms are kept only for a sliding window of time around the scans waiting for them, so
// memory stays bounded however long the bag. rosbag's own exceptions stop at this boundary: a
// file rosbag cannot read is an InputError naming it.
//
// Built only with the CMake option DYNAMAP_ROSBAG (defines DYNAMAP_HAVE_ROSBAG); looksLikeRosBag
// is always there, so a build without it can say what a .bag input needs.

#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose2D.h>

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "dynamap/input/scan_source.h"

namespace dynamap {

/// How a bag is read (dynamap map / import-bag options of the same names).
struct BagOptions {
  std::string scan_topic;                ///< "" = the bag's only sensor_msgs/LaserScan topic
  std::string odom_topic;                ///< nav_msgs/Odometry topic; "" = odometry from /tf
  std::string odom_frame = "odom";       ///< the odometry's fixed frame in /tf
  std::string base_frame = "base_link";  ///< the robot's frame
  std::string gt_frame = "map";          ///< ground truth: this frame's transform to base_frame
};

/// True when the file starts with "#ROSBAG V2.0\n" (a ROS 1 bag); never throws.
bool looksLikeRosBag(const std::string& path);

/// One scan of a bag with every pose the reader was asked for.
struct BagScan {
  std::size_t index = 0;  ///< 0-based, counting every LaserScan on the topic (used or skipped)
  double t = 0;           ///< header stamp [s]
  mrpt::obs::CObservation2DRangeScan::Ptr scan;  ///< sensorPose = the mount from /tf
  std::optional<mrpt::poses::CPose2D> odometry, ground_truth;
};

/// What a bag holds, as far as the reader needs it.
struct BagContents {
  std::vector<std::pair<std::string, std::string>> topics;  ///< topic, message type
  std::string scan_topic;                                   ///< the topic read
  bool odometry = false;      ///< odom_frame in /tf (first messages) or odom_topic given
  bool ground_truth = false;  ///< gt_frame in /tf or /tf_static (first messages)
};

/// Streams the scans of a bag in the bag's time order.
/// stats(): records = messages read, scans = LaserScans seen, skipped = scans (and tf entries)
/// skipped by reason, e.g. "scan frame 'laser' has no transform to 'base_link'".
class BagReader {
 public:
  /// Opens the bag and reads /tf_static and the first /tf messages. Throws InputError naming the
  /// file when rosbag cannot read it, and naming every topic when the scan topic (or odom_topic)
  /// is missing, or is no single LaserScan topic.
  BagReader(const std::string& path, const BagOptions& options);
  ~BagReader();
  BagReader(const BagReader&) = delete;
  BagReader& operator=(const BagReader&) = delete;

  const BagContents& contents() const;
  /// The poses every scan must have; a scan lacking one is skipped and counted. With neither, a
  /// scan whose mount is unknown gets the identity mount (a bag with no /tf at all). Call
  /// before the first next().
  void require(bool odometry, bool ground_truth);
  /// The next scan; false at the end. Throws InputError after the last good scan when the bag
  /// turns out corrupt part-way.
  bool next(BagScan& out);

  const SourceStats& stats() const;
  const std::string& path() const;
  /// Messages read over the messages of the topics read, in [0, 1].
  double fractionRead() const;
  /// Timed transforms and odometry samples held now: those of a sliding window of kHistory_s
  /// (10 s) before the oldest scan still waiting, whatever the bag's length.
  std::size_t samplesKept() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// A ScanSource over a bag: Auto takes ground truth when the bag has gt_frame, else odometry;
/// GroundTruth and Odometry are InputErrors naming the file when the bag has none; Fixed needs
/// no transform (withFixedPose then sets each pose); Simplemap is an InputError.
std::unique_ptr<ScanSource> openBagSource(const std::string& path, PoseSource source,
                                          const BagOptions& options);

}  // namespace dynamap
