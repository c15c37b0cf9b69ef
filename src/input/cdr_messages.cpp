// CDR (de)serialization of sensor_msgs/msg/LaserScan, tf2_msgs/msg/TFMessage and
// nav_msgs/msg/Odometry with Fast-CDR, field by field in the order of their .msg definitions.
#include "dynamap/input/cdr_messages.h"

#include <fastcdr/Cdr.h>
#include <fastcdr/FastBuffer.h>
#include <fastcdr/exceptions/Exception.h>
#include <fastcdr/exceptions/NotEnoughMemoryException.h>

#include <stdexcept>
#include <string>

namespace dynamap::ros2 {
namespace {

using eprosima::fastcdr::Cdr;
using eprosima::fastcdr::FastBuffer;

// A TransformStamped takes at least: stamp (8), two empty strings (8), 7 doubles (56).
constexpr std::size_t kMinTransformBytes = 72;

/// Reading: a Cdr over the message's bytes, past its encapsulation header.
class Reader {
 public:
  Reader(const std::uint8_t* p, std::size_t n)
      : buffer_(reinterpret_cast<char*>(const_cast<std::uint8_t*>(p)), n),
        cdr_(buffer_, Cdr::DEFAULT_ENDIAN, Cdr::DDS_CDR) {
    if (n < 4) throw std::runtime_error("shorter than its CDR encapsulation header");
    cdr_.read_encapsulation();
  }
  Cdr& cdr() { return cdr_; }
  std::size_t left() const {
    return static_cast<std::size_t>(buffer_.getBufferSize() - cdr_.getSerializedDataLength());
  }

 private:
  FastBuffer buffer_;
  Cdr cdr_;
};

ros::Time readTime(Cdr& c) {
  std::int32_t sec = 0;
  std::uint32_t nsec = 0;
  c >> sec >> nsec;
  if (sec < 0) throw std::runtime_error("a negative time");
  if (nsec >= 1000000000u) throw std::runtime_error("a time with nanosec >= 1e9");
  return ros::Time(static_cast<std::uint32_t>(sec), nsec);
}

void readHeader(Cdr& c, std_msgs::Header& h) {
  h.stamp = readTime(c);
  c >> h.frame_id;
}

void writeHeader(Cdr& c, const std_msgs::Header& h) {
  c << static_cast<std::int32_t>(h.stamp.sec) << h.stamp.nsec << h.frame_id;
}

void readQuaternion(Cdr& c, geometry_msgs::Quaternion& q) {
  c >> q.x >> q.y >> q.z >> q.w;
}

/// Decoding with Fast-CDR's exceptions (which derive from std::exception) said in one voice.
template <class F>
void decoding(const char* type, F&& f) {
  try {
    f();
  } catch (const eprosima::fastcdr::exception::Exception& e) {
    throw std::runtime_error(std::string("not a CDR ") + type + ": " + e.what());
  }
}

/// Writing: a Cdr over a zeroed buffer, its encapsulation written (CDR, little-endian). Fast-CDR
/// skips alignment padding without writing it: a zeroed buffer makes the same message the same
/// bytes. A buffer found too small is doubled and the message written again.
template <class F>
std::vector<std::uint8_t> encoding(F&& f) {
  for (std::size_t size = 4096;; size *= 2) {
    std::vector<char> bytes(size, 0);
    FastBuffer buffer(bytes.data(), bytes.size());
    Cdr cdr(buffer, Cdr::LITTLE_ENDIANNESS, Cdr::DDS_CDR);
    try {
      cdr.serialize_encapsulation();
      f(cdr);
    } catch (const eprosima::fastcdr::exception::NotEnoughMemoryException&) {
      continue;
    }
    const auto* p = reinterpret_cast<const std::uint8_t*>(bytes.data());
    return std::vector<std::uint8_t>(p, p + cdr.getSerializedDataLength());
  }
}

}  // namespace

void decode(const std::uint8_t* p, std::size_t n, sensor_msgs::LaserScan& m) {
  decoding("sensor_msgs/msg/LaserScan", [&] {
    Reader r(p, n);
    Cdr& c = r.cdr();
    readHeader(c, m.header);
    c >> m.angle_min >> m.angle_max >> m.angle_increment >> m.time_increment >> m.scan_time >>
        m.range_min >> m.range_max;
    c >> m.ranges >> m.intensities;
  });
}

void decode(const std::uint8_t* p, std::size_t n, tf2_msgs::TFMessage& m) {
  decoding("tf2_msgs/msg/TFMessage", [&] {
    Reader r(p, n);
    Cdr& c = r.cdr();
    std::uint32_t count = 0;
    c >> count;
    if (count > r.left() / kMinTransformBytes) {
      throw std::runtime_error("states " + std::to_string(count) + " transforms in " +
                               std::to_string(r.left()) + " bytes");
    }
    m.transforms.resize(count);
    for (auto& t : m.transforms) {
      readHeader(c, t.header);
      c >> t.child_frame_id;
      auto& v = t.transform.translation;
      c >> v.x >> v.y >> v.z;
      readQuaternion(c, t.transform.rotation);
    }
  });
}

void decode(const std::uint8_t* p, std::size_t n, nav_msgs::Odometry& m) {
  decoding("nav_msgs/msg/Odometry", [&] {
    Reader r(p, n);
    Cdr& c = r.cdr();
    readHeader(c, m.header);
    c >> m.child_frame_id;
    auto& pose = m.pose.pose;
    c >> pose.position.x >> pose.position.y >> pose.position.z;
    readQuaternion(c, pose.orientation);
    c.deserializeArray(m.pose.covariance.data(), m.pose.covariance.size());
    auto& tw = m.twist.twist;
    c >> tw.linear.x >> tw.linear.y >> tw.linear.z >> tw.angular.x >> tw.angular.y >> tw.angular.z;
    c.deserializeArray(m.twist.covariance.data(), m.twist.covariance.size());
  });
}

std::vector<std::uint8_t> encode(const sensor_msgs::LaserScan& m) {
  return encoding([&](Cdr& c) {
    writeHeader(c, m.header);
    c << m.angle_min << m.angle_max << m.angle_increment << m.time_increment << m.scan_time
      << m.range_min << m.range_max << m.ranges << m.intensities;
  });
}

std::vector<std::uint8_t> encode(const tf2_msgs::TFMessage& m) {
  return encoding([&](Cdr& c) {
    c << static_cast<std::uint32_t>(m.transforms.size());
    for (const auto& t : m.transforms) {
      writeHeader(c, t.header);
      const auto& v = t.transform.translation;
      const auto& q = t.transform.rotation;
      c << t.child_frame_id << v.x << v.y << v.z << q.x << q.y << q.z << q.w;
    }
  });
}

std::vector<std::uint8_t> encode(const nav_msgs::Odometry& m) {
  return encoding([&](Cdr& c) {
    writeHeader(c, m.header);
    const auto& p = m.pose.pose;
    c << m.child_frame_id << p.position.x << p.position.y << p.position.z << p.orientation.x
      << p.orientation.y << p.orientation.z << p.orientation.w;
    c.serializeArray(m.pose.covariance.data(), m.pose.covariance.size());
    const auto& tw = m.twist.twist;
    c << tw.linear.x << tw.linear.y << tw.linear.z << tw.angular.x << tw.angular.y << tw.angular.z;
    c.serializeArray(m.twist.covariance.data(), m.twist.covariance.size());
  });
}

}  // namespace dynamap::ros2
