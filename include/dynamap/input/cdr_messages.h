#pragma once
// ROS 2's CDR serialization (an encapsulation header, then XCDR1 fields, as rmw writes them) of
// the three messages dynamap reads, through Debian's Fast-CDR. A ROS 2 message is decoded into
// the ROS 1 message of the same definition, so that the bag reader treats both alike: the only
// difference in the fields read is the header (ROS 2 has no seq; its stamp is int32 sec and
// uint32 nanosec).
//
// decode: throws std::runtime_error saying why when the bytes are not the message (too short, a
// length past the end, a negative time); never reads past `n` bytes, and never allocates more
// than the bytes could hold. encode: the bytes a ROS 2 publisher would record.

#include <nav_msgs/Odometry.h>
#include <sensor_msgs/LaserScan.h>
#include <tf2_msgs/TFMessage.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace dynamap::ros2 {

void decode(const std::uint8_t* p, std::size_t n, sensor_msgs::LaserScan& out);
void decode(const std::uint8_t* p, std::size_t n, tf2_msgs::TFMessage& out);
void decode(const std::uint8_t* p, std::size_t n, nav_msgs::Odometry& out);

std::vector<std::uint8_t> encode(const sensor_msgs::LaserScan& m);
std::vector<std::uint8_t> encode(const tf2_msgs::TFMessage& m);
std::vector<std::uint8_t> encode(const nav_msgs::Odometry& m);

}  // namespace dynamap::ros2
