#include "bag_test_util.h"

#include <geometry_msgs/PoseArray.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <sensor_msgs/LaserScan.h>
#include <tf2_msgs/TFMessage.h>

#include <cmath>
#include <limits>

// leg_tracker/Person, which Debian ships no class of: a Pose and an id, serialised as ROS does
// (its MD5 is made up: readers check the type name and the size).
namespace dynamap::test {
struct PersonMsg {
  geometry_msgs::Pose pose;
  std::uint32_t id = 0;
};
}  // namespace dynamap::test

namespace ros::message_traits {
template <>
struct MD5Sum<dynamap::test::PersonMsg> {
  static const char* value() { return "0a7d6fc2f4e5ef5ca8b2f5e10f2c5b4e"; }
  static const char* value(const dynamap::test::PersonMsg&) { return value(); }
};
template <>
struct DataType<dynamap::test::PersonMsg> {
  static const char* value() { return "leg_tracker/Person"; }
  static const char* value(const dynamap::test::PersonMsg&) { return value(); }
};
template <>
struct Definition<dynamap::test::PersonMsg> {
  static const char* value() { return "geometry_msgs/Pose pose\nuint32 id\n"; }
  static const char* value(const dynamap::test::PersonMsg&) { return value(); }
};
}  // namespace ros::message_traits

namespace ros::serialization {
template <>
struct Serializer<dynamap::test::PersonMsg> {
  template <typename Stream, typename T>
  inline static void allInOne(Stream& stream, T m) {
    stream.next(m.pose);
    stream.next(m.id);
  }
  ROS_DECLARE_ALLINONE_SERIALIZER
};
}  // namespace ros::serialization

namespace dynamap::test {
namespace {

geometry_msgs::Quaternion yawQuaternion(double yaw) {
  geometry_msgs::Quaternion q;
  q.w = std::cos(yaw / 2);
  q.z = std::sin(yaw / 2);
  return q;
}

}  // namespace

BagWriter::BagWriter(const std::string& path, int compression)
    : bag_(std::make_unique<rosbag::Bag>(path, rosbag::bagmode::Write)) {
  bag_->setChunkThreshold(4096);  // many chunks: a cut file keeps some whole
  bag_->setCompression(static_cast<rosbag::compression::CompressionType>(compression));
}

BagWriter::~BagWriter() = default;

void BagWriter::scan(const std::string& topic, double t, const RosScan& s) {
  sensor_msgs::LaserScan m;
  m.header.stamp = ros::Time(t);
  m.header.frame_id = s.frame;
  m.angle_min = s.angle_min;
  m.angle_increment = s.increment;
  m.angle_max = s.angle_min + s.increment * static_cast<float>(s.ranges.size() - 1);
  m.range_min = s.range_min;
  m.range_max = s.range_max;
  m.ranges = s.ranges;
  bag_->write(topic, ros::Time(t), m);
}

void BagWriter::poseArray(const std::string& topic, double t,
                          const std::vector<std::pair<double, double>>& points) {
  geometry_msgs::PoseArray m;
  m.header.frame_id = "laser";
  for (const auto& [x, y] : points) {
    geometry_msgs::Pose p;
    p.position.x = x;
    p.position.y = y;
    m.poses.push_back(p);
  }
  bag_->write(topic, ros::Time(t), m);
}

void BagWriter::person(const std::string& topic, double t, double x, double y, unsigned id) {
  PersonMsg m;
  m.pose.position.x = x;
  m.pose.position.y = y;
  m.id = id;
  bag_->write(topic, ros::Time(t), m);
}

void BagWriter::tf(double t, const std::string& parent, const std::string& child,
                   const mrpt::poses::CPose2D& pose, bool is_static) {
  tf2_msgs::TFMessage msg;
  geometry_msgs::TransformStamped tr;
  tr.header.stamp = ros::Time(t);
  tr.header.frame_id = parent;
  tr.child_frame_id = child;
  tr.transform.translation.x = pose.x();
  tr.transform.translation.y = pose.y();
  tr.transform.rotation = yawQuaternion(pose.phi());
  msg.transforms.push_back(tr);
  bag_->write(is_static ? "/tf_static" : "/tf", ros::Time(t), msg);
}

void BagWriter::odometry(const std::string& topic, double t, const mrpt::poses::CPose2D& pose) {
  nav_msgs::Odometry o;
  o.header.stamp = ros::Time(t);
  o.header.frame_id = "odom";
  o.child_frame_id = "base_link";
  o.pose.pose.position.x = pose.x();
  o.pose.pose.position.y = pose.y();
  o.pose.pose.orientation = yawQuaternion(pose.phi());
  bag_->write(topic, ros::Time(t), o);
}

void BagWriter::close() {
  bag_->close();
}

namespace {

std::uint32_t get32(const std::string& b, std::size_t pos) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = v << 8 | static_cast<std::uint8_t>(b[pos + i]);
  return v;
}

}  // namespace

std::vector<BagRecord> bagRecords(const std::string& bag, std::size_t begin, std::size_t end) {
  std::vector<BagRecord> out;
  for (std::size_t pos = begin; pos + 8 <= end;) {
    BagRecord r;
    r.pos = pos;
    const std::uint32_t hlen = get32(bag, pos);
    if (hlen > end - pos - 8) break;
    for (std::size_t f = pos + 4; f + 4 <= pos + 4 + hlen;) {
      const std::uint32_t n = get32(bag, f);
      const std::string field = bag.substr(f + 4, n);
      const auto eq = field.find('=');
      r.fields[field.substr(0, eq)] = eq == std::string::npos ? "" : field.substr(eq + 1);
      f += 4 + n;
    }
    r.data_pos = pos + 4 + hlen;
    r.data_len = get32(bag, r.data_pos);
    if (r.data_len > end - r.data_pos - 4) break;
    pos = r.data_pos + 4 + r.data_len;
    out.push_back(std::move(r));
  }
  return out;
}

void put32(std::string& bytes, std::size_t pos, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) bytes[pos + i] = static_cast<char>(v >> (8 * i));
}

RosScan rosScanOf(const mrpt::obs::CObservation2DRangeScan& scan) {
  RosScan s;
  const std::size_t n = scan.getScanSize();
  const float step = n > 1 ? scan.aperture / static_cast<float>(n - 1) : 0.0f;
  s.angle_min = scan.rightToLeft ? -scan.aperture / 2 : scan.aperture / 2;
  s.increment = scan.rightToLeft ? step : -step;
  s.range_min = 0.0f;
  s.range_max = scan.maxRange;
  for (std::size_t i = 0; i < n; ++i) {
    s.ranges.push_back(scan.getScanRangeValidity(i) ? scan.getScanRange(i)
                                                    : std::numeric_limits<float>::infinity());
  }
  return s;
}

}  // namespace dynamap::test
