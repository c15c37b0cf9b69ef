#pragma once
// Bags written by the tests themselves, with ROS's own rosbag library in write mode.

#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose2D.h>

#include <cstdint>
#include <map>
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

/// One record of a bag's bytes, as the format lays it out: <header_len><header><data_len><data>.
struct BagRecord {
  std::size_t pos = 0;       ///< where header_len is
  std::size_t data_pos = 0;  ///< where data_len is (the data follow it)
  std::uint32_t data_len = 0;
  std::map<std::string, std::string> fields;  ///< the header's, by name
  char op() const { return fields.count("op") ? fields.at("op")[0] : 0; }
};
/// The records in bytes [begin, end) of `bag` (a whole file from byte 13, or a chunk's data),
/// up to the first that does not fit.
std::vector<BagRecord> bagRecords(const std::string& bag, std::size_t begin, std::size_t end);
/// The 4 bytes at `pos` set to `v` (little-endian, as the format).
void put32(std::string& bytes, std::size_t pos, std::uint32_t v);

/// A rawlog scan as the LaserScan it came from (invalid beams as +inf; frame "laser").
RosScan rosScanOf(const mrpt::obs::CObservation2DRangeScan& scan);

}  // namespace dynamap::test
