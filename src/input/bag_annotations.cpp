#include "dynamap/input/bag_annotations.h"

#include <geometry_msgs/PoseArray.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/LaserScan.h>

#include <cstring>
#include <stdexcept>

#include "bag_index_check.h"
#include "dynamap/input/bag_source.h"

namespace dynamap {

namespace {

const char* const kPersonType = "leg_tracker/Person";
// geometry_msgs/Pose (seven float64) then a uint32 id.
constexpr std::size_t kPersonBytes = 7 * 8 + 4;

// rosbag follows what a bag's index says without checking it: the bag is checked first, and an
// annotated bag whose index cannot be followed is refused (it is no training or truth data).
void open(rosbag::Bag& bag, const std::string& path) {
  if (!looksLikeRosBag(path)) throw std::runtime_error(path + ": not a ROS 1 bag");
  const bag::IndexCheck check = bag::checkBagIndex(path);
  if (check.verdict != bag::IndexCheck::Verdict::kSound) {
    throw std::runtime_error(path + ": a ROS bag whose index cannot be followed" +
                             (check.reason.empty() ? std::string() : " (" + check.reason + ")"));
  }
  try {
    bag.open(path, rosbag::bagmode::Read);
  } catch (const std::exception& e) {
    throw std::runtime_error(path + ": cannot read it as a ROS bag (" + e.what() + ")");
  }
}

// Throws unless `topic` is in the bag with message type `type`.
void requireTopic(rosbag::Bag& bag, const std::string& path, const std::string& topic,
                  const std::string& type) {
  rosbag::View all(bag);
  for (const rosbag::ConnectionInfo* c : all.getConnections()) {
    if (c->topic != topic) continue;
    if (c->datatype == type) return;
    throw std::runtime_error(path + ": topic " + topic + " holds " + c->datatype + ", not " + type);
  }
  throw std::runtime_error(path + ": no topic " + topic);
}

PolarScan polar(const sensor_msgs::LaserScan& m, std::size_t index, double t) {
  PolarScan s;
  s.index = index;
  s.t = t;
  s.angle_min = m.angle_min;
  s.angle_increment = m.angle_increment;
  s.range_min = m.range_min;
  s.range_max = m.range_max;
  s.ranges = m.ranges;
  return s;
}

// The serialised bytes of a message whose type dynamap has no C++ class for.
std::vector<std::uint8_t> rawBytes(const rosbag::MessageInstance& m) {
  std::vector<std::uint8_t> buf(m.size());
  ros::serialization::OStream stream(buf.data(), static_cast<std::uint32_t>(buf.size()));
  m.write(stream);
  return buf;
}

double float64At(const std::vector<std::uint8_t>& b, std::size_t offset) {
  double v = 0;
  std::memcpy(&v, b.data() + offset, sizeof v);  // ROS serialises little-endian, as this host
  return v;
}

}  // namespace

std::vector<LegTrainingScan> readLegTrainingBag(const std::string& path,
                                                const std::string& scan_topic,
                                                const std::string& positions_topic,
                                                std::size_t max_scans) {
  rosbag::Bag bag;
  open(bag, path);
  requireTopic(bag, path, scan_topic, "sensor_msgs/LaserScan");
  std::vector<std::string> topics{scan_topic};
  if (!positions_topic.empty()) {
    requireTopic(bag, path, positions_topic, "geometry_msgs/PoseArray");
    topics.push_back(positions_topic);
  }
  std::vector<LegTrainingScan> out;
  std::vector<LaserPoint> legs;
  std::size_t index = 0;
  try {
    for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery(topics))) {
      if (auto p = m.instantiate<geometry_msgs::PoseArray>()) {
        legs.clear();
        for (const auto& pose : p->poses) legs.push_back({pose.position.x, pose.position.y});
      } else if (auto s = m.instantiate<sensor_msgs::LaserScan>()) {
        out.push_back({polar(*s, index++, m.getTime().toSec()), legs});
        if (max_scans > 0 && out.size() >= max_scans) break;
      }
    }
  } catch (const std::exception& e) {
    throw std::runtime_error(path + ": message after scan " + std::to_string(index) + ": " +
                             e.what());
  }
  return out;
}

std::vector<PersonTruth> readPersonTruthBag(const std::string& path, const std::string& scan_topic,
                                            const std::string& person_topic) {
  rosbag::Bag bag;
  open(bag, path);
  requireTopic(bag, path, scan_topic, "sensor_msgs/LaserScan");
  requireTopic(bag, path, person_topic, kPersonType);
  std::vector<PersonTruth> out;
  std::size_t scans = 0, messages = 0;
  try {
    for (const rosbag::MessageInstance& m : rosbag::View(
             bag, rosbag::TopicQuery(std::vector<std::string>{scan_topic, person_topic}))) {
      if (m.getTopic() == scan_topic) {
        ++scans;
        continue;
      }
      ++messages;
      const std::vector<std::uint8_t> b = rawBytes(m);
      if (b.size() != kPersonBytes)
        throw std::runtime_error(std::to_string(b.size()) + " bytes, not " +
                                 std::to_string(kPersonBytes) + " of a " + kPersonType);
      if (scans == 0) continue;
      std::uint32_t id = 0;
      std::memcpy(&id, b.data() + 56, sizeof id);
      out.push_back({scans - 1,
                     m.getTime().toSec(),
                     static_cast<int>(id),
                     {float64At(b, 0), float64At(b, 8)}});
    }
  } catch (const std::exception& e) {
    throw std::runtime_error(path + ": " + person_topic + " message " + std::to_string(messages) +
                             ": " + e.what());
  }
  return out;
}

}  // namespace dynamap
