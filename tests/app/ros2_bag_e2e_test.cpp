// ROS 2 bags end to end: the bundled people log (and Freiburg 079, the real MCAP file and
// a ROS 1 bag when at hand) exported with `dynamap export-bag` to .mcap (zstd, none) and .db3
// maps to the same S, D, object table and people as the log itself, byte for byte; a cut MCAP
// maps up to its cut with exit 4; the real ROS 2 MCAP decodes every message.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include "../test_util.h"
#include "dynamap/input/cdr_messages.h"
#include "dynamap/input/ros2_bag.h"

namespace dynamap {
namespace {

namespace fs = std::filesystem;

const std::string kPeople = std::string(DYNAMAP_SOURCE_DIR) + "/rawlogs/people/people.rawlog";
const std::string kRos1Bag = std::string(DYNAMAP_SOURCE_DIR) + "/fuzz/seeds/bag/small.bag";

/// What a map is: the outputs of S, D, the object table and the people, compared byte for byte.
const char* const kMapFiles[] = {
    "static.gridmap.gz", "dynamic.gridmap.gz", "static.pgm", "static.png", "dynamic.png",
    "overlay.png",       "objects.csv",        "events.csv", "people.csv", "tracks.csv"};

/// A file under DYNAMAP_DATASETS; "" when it is unset or the file is absent.
std::string dataset(const std::string& relative) {
  const char* root = std::getenv("DYNAMAP_DATASETS");
  if (!root || !*root) return "";
  const std::string p = std::string(root) + "/" + relative;
  return fs::exists(p) ? p : "";
}

/// summary.json's "map" (extent) and "cells" (S and D counts) objects.
std::string mapCells(const std::string& summary) {
  const auto at = summary.find("\"map\"");
  const auto cells = summary.find("\"cells\"", at);
  const auto end = summary.find('}', cells);
  return at == std::string::npos || end == std::string::npos ? "" : summary.substr(at, end - at);
}

class Ros2EndToEnd : public ::testing::Test {
 protected:
  std::string dir_ = test::tempDir("ros2_e2e");
  std::string path(const std::string& name) const { return dir_ + "/" + name; }
  int dynamap(const std::string& args, std::string* out = nullptr) const {
    return test::run(std::string(DYNAMAP_EXE) + " " + args, out);
  }

  /// `log` mapped directly and through each ROS 2 bag export-bag makes of it: the same map.
  void expectSameMapThroughEveryBag(const std::string& log, const std::string& map_args) {
    std::string out;
    ASSERT_EQ(dynamap("map --input " + log + " " + map_args + " --out " + path("direct"), &out), 0)
        << out;
    const std::string direct = test::readFile(path("direct/summary.json"));
    for (const auto& [bag, compression] : std::map<std::string, std::string>{
             {"zstd.mcap", "zstd"}, {"none.mcap", "none"}, {"bag.db3", "zstd"}}) {
      ASSERT_EQ(
          dynamap("export-bag " + log + " --out " + path(bag) + " --compression " + compression,
                  &out),
          0)
          << out;
      const std::string o = path("o_" + bag);
      ASSERT_EQ(dynamap("map --input " + path(bag) + " " + map_args + " --out " + o, &out), 0)
          << out;
      const std::string summary = test::readFile(o + "/summary.json");
      EXPECT_EQ(mapCells(summary), mapCells(direct)) << bag;
      EXPECT_NE(mapCells(summary).find("static_occupied"), std::string::npos);
      for (const char* f : kMapFiles) {
        if (!fs::exists(path("direct/") + f)) continue;
        EXPECT_EQ(test::readFile(o + "/" + f), test::readFile(path("direct/") + f))
            << bag << ": " << f;
      }
    }
  }
};

TEST_F(Ros2EndToEnd, ThePeopleLogMapsTheSameThroughMcapAndDb3) {
  expectSameMapThroughEveryBag(kPeople, "--no-baseline");
}

TEST_F(Ros2EndToEnd, ARos1BagMapsTheSameThroughItsRos2Export) {
  expectSameMapThroughEveryBag(kRos1Bag, "--no-baseline");
}

TEST_F(Ros2EndToEnd, Freiburg079MapsTheSameThroughMcapAndDb3) {
  const std::string log = dataset("carmen/freiburg-079-corrected.log.gz");
  if (log.empty()) GTEST_SKIP() << "DYNAMAP_DATASETS unset or without Freiburg 079";
  expectSameMapThroughEveryBag(log, "--no-baseline");
}

TEST_F(Ros2EndToEnd, ACutMcapMapsUpToItsCutAndExits4) {
  std::string out;
  ASSERT_EQ(
      dynamap("export-bag " + kPeople + " --out " + path("p.mcap") + " --compression none", &out),
      0)
      << out;
  const std::string bytes = test::readFile(path("p.mcap"));
  std::ofstream(path("cut.mcap"), std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  EXPECT_EQ(dynamap("map --no-baseline --input " + path("cut.mcap") + " --out " + path("o"), &out),
            4)
      << out;
  const std::string summary = test::readFile(path("o/summary.json"));
  EXPECT_NE(summary.find("\"input_fault\": \"" + path("cut.mcap") + ": record at offset "),
            std::string::npos)
      << summary;
  EXPECT_NE(summary.find("\"complete_input\": false"), std::string::npos);
  EXPECT_TRUE(fs::exists(path("o/static.png")));
}

TEST_F(Ros2EndToEnd, ExportBagRefusesAnOutputThatIsNoRos2Bag) {
  std::string out;
  EXPECT_EQ(dynamap("export-bag " + kPeople + " --out " + path("x.bag"), &out), 2) << out;
  EXPECT_NE(out.find("written as .mcap or .db3"), std::string::npos) << out;
  EXPECT_EQ(
      dynamap("export-bag " + kPeople + " --out " + path("x.mcap") + " --compression bz2", &out), 2)
      << out;
}

/// The real ROS 2 MCAP (written by ROS 2's recorder, zstd chunks): every message of the three
/// types read decodes, the rest are of other types, and each /odom pose is the /tf odom ->
/// base_link transform of the same stamp (ROS 2's odometry publishes both).
TEST_F(Ros2EndToEnd, TheRealMcapDecodesEveryMessageAndItsOdometryIsItsTf) {
  const std::string bag = dataset("ros2/nav2_turtlebot.mcap");
  if (bag.empty()) GTEST_SKIP() << "DYNAMAP_DATASETS unset or without ros2/nav2_turtlebot.mcap";
  auto stream = ros2::openRos2Bag(bag, {});
  std::map<std::string, std::size_t> count;
  std::map<std::int64_t, std::array<double, 3>> tf_pose, odom_pose;
  while (stream->next()) {
    const std::string type = ros2::ros1TypeName(stream->type());
    ++count[type];
    if (type == "tf2_msgs/TFMessage") {
      tf2_msgs::TFMessage m;
      ASSERT_NO_THROW(ros2::decode(stream->data(), stream->size(), m)) << stream->where();
      for (const auto& t : m.transforms) {
        if (t.header.frame_id != "odom" || t.child_frame_id != "base_link") continue;
        const auto& q = t.transform.rotation;
        tf_pose[t.header.stamp.toNSec()] = {t.transform.translation.x, t.transform.translation.y,
                                            std::atan2(2 * q.w * q.z, 1 - 2 * q.z * q.z)};
      }
    } else if (type == "nav_msgs/Odometry") {
      nav_msgs::Odometry o;
      ASSERT_NO_THROW(ros2::decode(stream->data(), stream->size(), o)) << stream->where();
      const auto& q = o.pose.pose.orientation;
      odom_pose[o.header.stamp.toNSec()] = {o.pose.pose.position.x, o.pose.pose.position.y,
                                            std::atan2(2 * q.w * q.z, 1 - 2 * q.z * q.z)};
    }
  }
  EXPECT_EQ(stream->fault(), "");
  EXPECT_EQ(count["nav_msgs/Odometry"], 2639u);
  EXPECT_EQ(count["tf2_msgs/TFMessage"], 5423u);                      // /tf and the one /tf_static
  EXPECT_EQ(count["geometry_msgs/PoseWithCovarianceStamped"], 135u);  // /amcl_pose, not read
  ASSERT_EQ(odom_pose.size(), 2639u);
  for (const auto& [t, p] : odom_pose) {
    const auto it = tf_pose.find(t);
    ASSERT_NE(it, tf_pose.end()) << "no /tf at the stamp of /odom " << t;
    for (int i = 0; i < 3; ++i) EXPECT_EQ(it->second[i], p[i]) << t;
  }
  // The bag has no LaserScan: map says so, naming the file and every topic, and no warning.
  std::string out;
  EXPECT_EQ(dynamap("map --input " + bag + " --out " + path("nav"), &out), 1);
  EXPECT_NE(out.find("no sensor_msgs/LaserScan topic"), std::string::npos) << out;
  EXPECT_NE(out.find("/odom (nav_msgs/msg/Odometry)"), std::string::npos) << out;
  EXPECT_EQ(out.find("warning"), std::string::npos) << out;
}

}  // namespace
}  // namespace dynamap
