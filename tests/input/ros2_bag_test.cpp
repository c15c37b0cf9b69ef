// ROS 2 bags: the MCAP and .db3 readers over bags written by ros2::BagWriter (every compression,
// with and without the summary, several .db3 files of one folder), the CDR messages read back
// field for field, and bad input (cut, bit-flipped, not a bag) named with the file and offset.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "../test_util.h"
#include "dynamap/input/bag_source.h"
#include "dynamap/input/cdr_messages.h"
#include "dynamap/input/ros2_bag.h"
#include "dynamap/input/ros2_writer.h"

namespace dynamap {
namespace {

namespace fs = std::filesystem;
using mrpt::poses::CPose2D;

constexpr std::uint64_t kSecond = 1000000000;

sensor_msgs::LaserScan laserScan(double t, int beams) {
  sensor_msgs::LaserScan m;
  m.header.stamp = ros::Time(t);
  m.header.frame_id = "laser";
  m.angle_min = -1.0f;
  m.angle_increment = 0.5f;
  m.angle_max = m.angle_min + m.angle_increment * static_cast<float>(beams - 1);
  m.range_min = 0.1f;
  m.range_max = 20.0f;
  for (int i = 0; i < beams; ++i) m.ranges.push_back(1.0f + 0.25f * static_cast<float>(i));
  return m;
}

tf2_msgs::TFMessage transform(double t, const std::string& parent, const std::string& child,
                              const CPose2D& p) {
  geometry_msgs::TransformStamped tr;
  tr.header.stamp = ros::Time(t);
  tr.header.frame_id = parent;
  tr.child_frame_id = child;
  tr.transform.translation.x = p.x();
  tr.transform.translation.y = p.y();
  tr.transform.rotation.z = std::sin(p.phi() / 2);
  tr.transform.rotation.w = std::cos(p.phi() / 2);
  tf2_msgs::TFMessage m;
  m.transforms.push_back(tr);
  return m;
}

/// A robot driving along x at 1 m/s: /tf_static base_link -> laser, then per step /tf odom ->
/// base_link and a 5-beam /scan, both stamped 100 + k / 10 s, written in time order.
void writeDrive(ros2::BagWriter& bag, int steps, int first = 0) {
  if (first == 0) {
    bag.write("/tf_static", "tf2_msgs/msg/TFMessage", 100 * kSecond,
              ros2::encode(transform(100, "base_link", "laser", CPose2D(0.2, 0, 0))));
  }
  for (int k = first; k < first + steps; ++k) {
    const double t = 100 + k / 10.0;
    const auto ns = static_cast<std::uint64_t>(ros::Time(t).toNSec());
    bag.write("/tf", "tf2_msgs/msg/TFMessage", ns,
              ros2::encode(transform(t, "odom", "base_link", CPose2D(k / 10.0, 0, 0))));
    bag.write("/scan", "sensor_msgs/msg/LaserScan", ns, ros2::encode(laserScan(t, 5)));
  }
}

class Ros2BagTest : public ::testing::Test {
 protected:
  std::string dir_ = test::tempDir("ros2_bag");
  std::string path(const std::string& name) const { return dir_ + "/" + name; }

  std::string writeBag(const std::string& name, const std::string& compression, int steps) {
    ros2::BagWriter bag(path(name), compression);
    writeDrive(bag, steps);
    bag.close();
    return path(name);
  }

  /// Every scan of the bag through the bag reader (odometry poses); the fault, if any.
  std::vector<BagScan> readScans(const std::string& bag, std::string* fault = nullptr) {
    BagReader reader(bag, BagOptions{});
    reader.require(true, false);
    std::vector<BagScan> out;
    BagScan s;
    try {
      while (reader.next(s)) out.push_back(s);
    } catch (const InputError& e) {
      if (!fault) throw;
      *fault = e.what();
    }
    return out;
  }
};

TEST_F(Ros2BagTest, CdrMessagesReadBackFieldForField) {
  sensor_msgs::LaserScan scan = laserScan(1234.5, 7);
  scan.ranges[3] = std::numeric_limits<float>::infinity();
  scan.intensities = {1, 2, 3};
  const auto bytes = ros2::encode(scan);
  // The CDR encapsulation ROS 2 records: CDR, little-endian.
  ASSERT_GE(bytes.size(), 4u);
  EXPECT_EQ(bytes[0], 0);
  EXPECT_EQ(bytes[1], 1);
  sensor_msgs::LaserScan back;
  ros2::decode(bytes.data(), bytes.size(), back);
  EXPECT_EQ(back.header.stamp, scan.header.stamp);
  EXPECT_EQ(back.header.frame_id, "laser");
  EXPECT_EQ(back.angle_increment, 0.5f);
  EXPECT_EQ(back.ranges, scan.ranges);
  EXPECT_EQ(back.intensities, scan.intensities);

  nav_msgs::Odometry odom;
  odom.header.stamp = ros::Time(7, 5);
  odom.header.frame_id = "odom";
  odom.child_frame_id = "base_link";
  odom.pose.pose.position.x = 1.5;
  odom.pose.pose.orientation.w = 1;
  odom.pose.covariance[35] = 0.25;
  odom.twist.twist.angular.z = -0.5;
  nav_msgs::Odometry o;
  const auto ob = ros2::encode(odom);
  ros2::decode(ob.data(), ob.size(), o);
  EXPECT_EQ(o.header.stamp, odom.header.stamp);
  EXPECT_EQ(o.child_frame_id, "base_link");
  EXPECT_EQ(o.pose.pose.position.x, 1.5);
  EXPECT_EQ(o.pose.covariance[35], 0.25);
  EXPECT_EQ(o.twist.twist.angular.z, -0.5);

  const auto tb = ros2::encode(transform(3, "map", "base_link", CPose2D(1, 2, 0.5)));
  tf2_msgs::TFMessage tf;
  ros2::decode(tb.data(), tb.size(), tf);
  ASSERT_EQ(tf.transforms.size(), 1u);
  EXPECT_EQ(tf.transforms[0].child_frame_id, "base_link");
  EXPECT_EQ(tf.transforms[0].transform.translation.y, 2.0);
}

TEST_F(Ros2BagTest, ACutOrLyingMessageIsAnErrorSayingWhy) {
  const auto bytes = ros2::encode(laserScan(1, 50));
  sensor_msgs::LaserScan m;
  for (const std::size_t n : {std::size_t{0}, std::size_t{3}, std::size_t{30}, bytes.size() - 1}) {
    EXPECT_THROW(ros2::decode(bytes.data(), n, m), std::runtime_error) << n;
  }
  // A TFMessage stating 2^32 - 1 transforms in a few bytes: refused before any allocation.
  std::vector<std::uint8_t> lying = {0, 1, 0, 0, 0xff, 0xff, 0xff, 0xff, 0, 0, 0, 0};
  tf2_msgs::TFMessage tf;
  try {
    ros2::decode(lying.data(), lying.size(), tf);
    FAIL() << "decoded";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("4294967295 transforms"), std::string::npos) << e.what();
  }
}

TEST_F(Ros2BagTest, EveryCompressionAndTheDb3ReadBackTheSameScansAndPoses) {
  std::vector<std::vector<BagScan>> all;
  for (const auto& [name, compression] : std::vector<std::pair<std::string, std::string>>{
           {"z.mcap", "zstd"}, {"l.mcap", "lz4"}, {"n.mcap", "none"}, {"d.db3", "zstd"}}) {
    const std::string bag = writeBag(name, compression, 10000);  // 3 chunks of 1 MiB
    EXPECT_TRUE(ros2::looksLikeRos2Bag(bag));
    EXPECT_FALSE(looksLikeRosBag(bag));
    all.push_back(readScans(bag));
    ASSERT_EQ(all.back().size(), 10000u) << name;
  }
  for (const auto& scans : all) {
    for (const std::size_t k : {std::size_t{0}, std::size_t{5234}, std::size_t{9999}}) {
      const BagScan& s = scans[k];
      EXPECT_EQ(s.index, k);
      EXPECT_NEAR(s.t, 100 + static_cast<double>(k) / 10, 1e-9);
      ASSERT_TRUE(s.odometry);
      EXPECT_NEAR(s.odometry->x(), static_cast<double>(k) / 10, 1e-9);
      EXPECT_NEAR(s.scan->sensorPose.x(), 0.2, 1e-12);  // the mount from /tf_static
      EXPECT_EQ(s.scan->getScanSize(), 5u);
      EXPECT_EQ(s.scan->getScanRange(4), 2.0f);
    }
  }
}

TEST_F(Ros2BagTest, TheSameMessagesGiveTheSameBytes) {
  for (const char* name : {"a.mcap", "a.db3"}) {
    const std::string one = writeBag(std::string("1") + name, "zstd", 200);
    const std::string two = writeBag(std::string("2") + name, "zstd", 200);
    EXPECT_TRUE(test::readFile(one) == test::readFile(two)) << name;  // no bytes printed
  }
}

TEST_F(Ros2BagTest, AnMcapWithoutItsSummaryIsReadRecordByRecord) {
  const std::string whole = writeBag("whole.mcap", "zstd", 10000);
  std::string bytes = test::readFile(whole);
  // The footer's summary_start zeroed: no summary, the data section read from the start.
  const std::size_t footer = bytes.size() - 8 - 29;
  ASSERT_EQ(bytes[footer], 0x02);
  for (int i = 0; i < 8; ++i) bytes[footer + 9 + i] = 0;
  std::ofstream(path("nosummary.mcap"), std::ios::binary) << bytes;
  EXPECT_EQ(readScans(path("nosummary.mcap")).size(), 10000u);
  auto stream = ros2::openRos2Bag(path("nosummary.mcap"), {});
  const ros2::TopicList topics = stream->topics();
  ASSERT_EQ(topics.size(), 3u);
  EXPECT_EQ(topics[0].first, "/scan");
  EXPECT_EQ(topics[0].second, "sensor_msgs/msg/LaserScan");
}

TEST_F(Ros2BagTest, ACutMcapGivesEveryScanBeforeTheCutThenNamesTheOffset) {
  for (const char* compression : {"zstd", "none"}) {
    const std::string whole =
        writeBag(std::string("w_") + compression + ".mcap", compression, 20000);
    const std::string bytes = test::readFile(whole);
    const std::string cut = path(std::string("cut_") + compression + ".mcap");
    std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() * 2 / 3);
    std::string fault;
    const auto scans = readScans(cut, &fault);
    EXPECT_GT(scans.size(), 4000u) << compression;
    EXPECT_LT(scans.size(), 20000u) << compression;
    EXPECT_EQ(fault.rfind(cut + ": record at offset ", 0), 0u) << fault;
    EXPECT_NE(fault.find("cut off"), std::string::npos) << fault;
  }
}

TEST_F(Ros2BagTest, ABitFlippedChunkFailsItsCrcNamingTheChunk) {
  const std::string whole = writeBag("flip.mcap", "none", 10000);
  std::string bytes = test::readFile(whole);
  bytes[bytes.size() / 2] ^= 0x10;
  std::ofstream(path("flipped.mcap"), std::ios::binary) << bytes;
  std::string fault;
  const auto scans = readScans(path("flipped.mcap"), &fault);
  EXPECT_GT(scans.size(), 2000u);
  EXPECT_LT(scans.size(), 10000u);
  EXPECT_NE(fault.find("record at offset "), std::string::npos) << fault;
  EXPECT_NE(fault.find("CRC"), std::string::npos) << fault;
}

TEST_F(Ros2BagTest, TheSummaryAnswersTopicsAndSkipsChunksWithoutTheTopicsAsked) {
  // A bit flipped in the middle chunk: what the summary answers never reads that chunk. A reader
  // that ignored the summary (and read the data section record by record) would meet the bad CRC.
  const std::string whole = writeBag("indexed.mcap", "none", 10000);  // 3 chunks
  std::string bytes = test::readFile(whole);
  bytes[bytes.size() / 2] ^= 0x10;
  std::ofstream(path("indexed_flipped.mcap"), std::ios::binary) << bytes;
  auto all = ros2::openRos2Bag(path("indexed_flipped.mcap"), {});
  EXPECT_EQ(all->topics().size(), 3u);
  EXPECT_EQ(all->fault(), "");
  auto statics = ros2::openRos2Bag(path("indexed_flipped.mcap"), {"/tf_static"});
  int n = 0;
  while (statics->next()) ++n;
  EXPECT_EQ(n, 1);  // /tf_static is in the first chunk only
  EXPECT_EQ(statics->fault(), "");
  EXPECT_EQ(statics->fractionRead(), 1.0);
}

TEST_F(Ros2BagTest, AFolderReadsItsDb3FilesInTheOrderOfMetadataYaml) {
  fs::create_directories(path("bag"));
  {
    ros2::BagWriter a(path("bag/drive_0.db3"), "none");
    writeDrive(a, 100, 0);
    ros2::BagWriter b(path("bag/drive_1.db3"), "none");
    writeDrive(b, 100, 100);
  }
  std::ofstream(path("bag/metadata.yaml")) << "rosbag2_bagfile_information:\n"
                                              "  version: 5\n  storage_identifier: sqlite3\n"
                                              "  relative_file_paths:\n"
                                              "    - drive_0.db3\n    - drive_1.db3\n"
                                              "  duration:\n    nanoseconds: 20000000000\n";
  EXPECT_TRUE(ros2::looksLikeRos2Bag(path("bag")));
  const auto scans = readScans(path("bag"));
  ASSERT_EQ(scans.size(), 200u);
  EXPECT_NEAR(scans[150].odometry->x(), 15.0, 1e-9);
  // A metadata.yaml naming a file that is not there names both.
  std::ofstream(path("bag/metadata.yaml")) << "  relative_file_paths:\n    - gone.db3\n";
  try {
    readScans(path("bag"));
    FAIL() << "read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("metadata.yaml: relative_file_paths names gone.db3"),
              std::string::npos)
        << e.what();
  }
}

TEST_F(Ros2BagTest, Db3MessagesComeInTimeOrderWhateverOrderTheyWereWritten) {
  {
    ros2::BagWriter bag(path("shuffled.db3"), "none");
    writeDrive(bag, 0);  // /tf_static only
    for (int k : {4, 0, 3, 1, 2}) writeDrive(bag, 1, k);
  }
  const auto scans = readScans(path("shuffled.db3"));
  ASSERT_EQ(scans.size(), 5u);
  for (std::size_t k = 0; k < 5; ++k) EXPECT_NEAR(scans[k].odometry->x(), k / 10.0, 1e-9);
}

/// The quirks of real recordings: /tf_static latched again by every late subscriber (QoS
/// transient local), scans recorded before the first /tf, a header stamp earlier than the one
/// before it.
TEST_F(Ros2BagTest, DuplicatedTfStaticEarlyScansAndStampsGoingBackAreReadAsTheyMean) {
  {
    ros2::BagWriter bag(path("quirks.mcap"), "zstd");
    const auto ns = [](double t) { return static_cast<std::uint64_t>(ros::Time(t).toNSec()); };
    // Five scans first, their /tf after them (a recorder subscribing to /tf late).
    for (int k = 0; k < 5; ++k) {
      bag.write("/scan", "sensor_msgs/msg/LaserScan", ns(100 + k / 10.0),
                ros2::encode(laserScan(100 + k / 10.0, 5)));
    }
    for (int copy = 0; copy < 3; ++copy) {  // /tf_static three times, as late joiners get it
      bag.write("/tf_static", "tf2_msgs/msg/TFMessage", ns(100.45),
                ros2::encode(transform(100, "base_link", "laser", CPose2D(0.2, 0, 0))));
    }
    for (int k = 0; k < 10; ++k) {
      const double t = 100 + k / 10.0;
      bag.write("/tf", "tf2_msgs/msg/TFMessage", ns(100.45),
                ros2::encode(transform(t, "odom", "base_link", CPose2D(k / 10.0, 0, 0))));
    }
    // A scan stamped 0.25 s before the scan recorded before it.
    bag.write("/scan", "sensor_msgs/msg/LaserScan", ns(100.5),
              ros2::encode(laserScan(100.8, 5)));
    bag.write("/scan", "sensor_msgs/msg/LaserScan", ns(100.6),
              ros2::encode(laserScan(100.55, 5)));
  }
  const auto scans = readScans(path("quirks.mcap"));
  ASSERT_EQ(scans.size(), 7u);
  for (std::size_t k = 0; k < 5; ++k) {
    ASSERT_TRUE(scans[k].odometry);
    EXPECT_NEAR(scans[k].odometry->x(), k / 10.0, 1e-9);
    EXPECT_NEAR(scans[k].scan->sensorPose.x(), 0.2, 1e-12);
  }
  EXPECT_NEAR(scans[5].odometry->x(), 0.8, 1e-9);
  EXPECT_NEAR(scans[6].odometry->x(), 0.55, 1e-9);  // interpolated at its own stamp
}

TEST_F(Ros2BagTest, FilesThatAreNoRos2BagAreInputErrorsNamingThem) {
  std::ofstream(path("text.db3")) << "not a bag";
  EXPECT_FALSE(ros2::looksLikeRos2Bag(path("text.db3")));
  std::ofstream(path("magic.mcap"), std::ios::binary) << std::string("\x89MCAP0\r\n", 8);
  try {
    readScans(path("magic.mcap"));
    FAIL() << "read";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(path("magic.mcap") + ": ", 0), 0u) << e.what();
  }
  // An SQLite file without rosbag2's tables.
  { ros2::BagWriter bag(path("empty.db3"), "none"); }
  std::string text = test::readFile(path("empty.db3"));
  const auto at = text.find("CREATE TABLE topics");
  ASSERT_NE(at, std::string::npos);
  text[at + 13] = 'X';  // the table is now "topiXs"
  std::ofstream(path("notopics.db3"), std::ios::binary) << text;
  EXPECT_THROW(readScans(path("notopics.db3")), InputError);
}

}  // namespace
}  // namespace dynamap
