#pragma once
// Bags written by the tests themselves, with ROS's own rosbag library in write mode.

#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose2D.h>

#include <memory>
#include <utility>
#include <string>
#include <vector>

namespace rosbag {
class Bag;
}

namespace dynamap::test {

/// One sensor_msgs/LaserScan: beam i at angle_min + i * increment.
struct RosScan {
  std::string frame = "laser";
  std::vector<float> ranges;
  float angle_min = -1.0f, increment = 0.5f;
  float range_min = 0.1f, range_max = 20.0f;
};

class BagWriter {
 public:
  /// `compression`: rosbag::compression::CompressionType (0 none, 1 bz2, 2 lz4).
  explicit BagWriter(const std::string& path, int compression = 0);
  ~BagWriter();
  /// A LaserScan on `topic`, stamped and recorded at t.
  void scan(const std::string& topic, double t, const RosScan& s);
  /// One transform parent -> child (pose of child in parent) on /tf, or /tf_static.
  void tf(double t, const std::string& parent, const std::string& child,
          const mrpt::poses::CPose2D& pose, bool is_static = false);
  /// A geometry_msgs/PoseArray of the points (x, y) on `topic` (leg training bags' markers).
  void poseArray(const std::string& topic, double t, const std::vector<std::pair<double, double>>& points);
  /// A leg_tracker/Person (a geometry_msgs/Pose and a uint32 id, no header) on `topic`.
  void person(const std::string& topic, double t, double x, double y, unsigned id);
  /// A nav_msgs/Odometry (frame odom, child base_link) on `topic`.
  void odometry(const std::string& topic, double t, const mrpt::poses::CPose2D& pose);
  void close();

 private:
  std::unique_ptr<rosbag::Bag> bag_;
};

/// A rawlog scan as the LaserScan it came from (invalid beams as +inf; frame "laser").
RosScan rosScanOf(const mrpt::obs::CObservation2DRangeScan& scan);

}  // namespace dynamap::test
