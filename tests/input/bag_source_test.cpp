// The ROS bag reader on bags these tests write with rosbag itself: stamps, beam geometry and
// validity, poses from /tf, /tf_static and nav_msgs/Odometry (mount included), ground truth, the
// topic rules, the fixed pose, and every kind of bad input.

#include "dynamap/input/bag_source.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>

#include <rosbag/bag.h>
#include <rosbag/buffer.h>

#include "../bag_test_util.h"
#include "../test_util.h"
#include "dynamap/base/allocation_limit.h"
#include "dynamap/input/open_source.h"

namespace dynamap {
namespace {

using test::inputError;
using test::readAll;

using mrpt::poses::CPose2D;
using test::BagWriter;
using test::RosScan;

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr double kT0 = 100.0;
const CPose2D kMount(0.2, 0.05, 0.1);  // the laser on the robot (base_link -> laser)

RosScan fiveBeams(const std::string& frame = "laser") {
  RosScan s;
  s.frame = frame;
  s.ranges = {1.0f, 2.0f, 3.0f, 4.0f, 5.0f};
  return s;
}

/// The robot drives along x at 1 m/s turning at 0.1 rad/s: odom -> base_link at time t.
CPose2D odomAt(double t) {
  return CPose2D(t - kT0, 0.0, 0.1 * (t - kT0));
}

/// 2 s of /tf at 20 Hz, the static mount, and a scan every 0.25 s from kT0 + 0.1 (8 scans).
void writeDrive(BagWriter& bag, const std::function<void(double)>& extra_tf = {}) {
  bag.tf(kT0, "base_link", "laser", kMount, true);
  for (int k = 0; k <= 40; ++k) {
    const double t = kT0 + 0.05 * k;
    bag.tf(t, "odom", "base_link", odomAt(t));
    if (extra_tf) extra_tf(t);
  }
  for (int k = 0; k < 8; ++k) bag.scan("/scan", kT0 + 0.1 + 0.25 * k, fiveBeams());
}

void expectPose(const CPose2D& got, const CPose2D& want, double tol = 1e-6) {
  EXPECT_NEAR(got.x(), want.x(), tol);
  EXPECT_NEAR(got.y(), want.y(), tol);
  EXPECT_NEAR(got.phi(), want.phi(), tol);
}

class BagSourceTest : public ::testing::Test {
 protected:
  std::string dir_ = test::tempDir("bag");
  std::string path(const std::string& name) const { return dir_ + "/" + name; }
};

TEST_F(BagSourceTest, ScansReadBackWithStampsGeometryAndOdometryFromTf) {
  {
    BagWriter bag(path("drive.bag"));
    writeDrive(bag);
  }
  EXPECT_TRUE(looksLikeRosBag(path("drive.bag")));
  auto src = openScanSource(path("drive.bag"), PoseSource::Auto);
  EXPECT_EQ(src->poseSource(), PoseSource::Odometry);  // no map frame: no ground truth
  const auto recs = readAll(*src);
  ASSERT_EQ(recs.size(), 8u);
  EXPECT_EQ(src->stats().scans, 8u);
  for (std::size_t k = 0; k < recs.size(); ++k) {
    const double t = kT0 + 0.1 + 0.25 * static_cast<double>(k);
    const auto& r = recs[k];
    EXPECT_EQ(r.index, k);
    EXPECT_NEAR(r.t, t, 1e-6);
    expectPose(r.pose, odomAt(t), 1e-4);  // interpolated between the 20 Hz transforms
    const auto& s = *r.scan;
    EXPECT_EQ(s.sensorLabel, "laser");
    EXPECT_NEAR(s.aperture, 2.0, 1e-6);  // 4 steps of 0.5 rad
    EXPECT_TRUE(s.rightToLeft);
    EXPECT_FLOAT_EQ(s.maxRange, 20.0f);
    // angle_min -1 + 2 steps of 0.5: the middle beam looks along the laser's x axis.
    expectPose(CPose2D(s.sensorPose), kMount);
    ASSERT_EQ(s.getScanSize(), 5u);
    for (std::size_t i = 0; i < 5; ++i) {
      EXPECT_FLOAT_EQ(s.getScanRange(i), 1.0f + static_cast<float>(i));
      EXPECT_TRUE(s.getScanRangeValidity(i));
    }
  }
}

TEST_F(BagSourceTest, GroundTruthFromTheMapFrameThroughOdom) {
  const CPose2D map_odom(1.0, 2.0, 0.5);
  {
    BagWriter bag(path("gt.bag"));
    writeDrive(bag, [&](double t) { bag.tf(t, "map", "odom", map_odom); });
  }
  auto src = openScanSource(path("gt.bag"), PoseSource::Auto);
  EXPECT_EQ(src->poseSource(), PoseSource::GroundTruth);
  const auto recs = readAll(*src);
  ASSERT_EQ(recs.size(), 8u);
  expectPose(recs[3].pose, map_odom + odomAt(recs[3].t), 1e-4);
  auto odo = openScanSource(path("gt.bag"), PoseSource::Odometry);
  expectPose(readAll(*odo)[3].pose, odomAt(recs[3].t), 1e-4);
}

TEST_F(BagSourceTest, OdometryTopicComposedWithTheStaticMount) {
  {
    BagWriter bag(path("odom.bag"));
    bag.tf(kT0, "base_link", "laser", kMount, true);
    for (int k = 0; k <= 20; ++k) bag.odometry("/wheel_odom", kT0 + 0.1 * k, odomAt(kT0 + 0.1 * k));
    for (int k = 0; k < 4; ++k) bag.scan("/scan", kT0 + 0.15 + 0.5 * k, fiveBeams());
  }
  BagOptions o;
  o.odom_topic = "/wheel_odom";
  auto src = openBagSource(path("odom.bag"), PoseSource::Auto, o);
  EXPECT_EQ(src->poseSource(), PoseSource::Odometry);
  const auto recs = readAll(*src);
  ASSERT_EQ(recs.size(), 4u);
  for (const auto& r : recs) {
    expectPose(r.pose, odomAt(r.t), 1e-4);
    expectPose(CPose2D(r.scan->sensorPose), kMount);
  }
  o.odom_topic = "/odom";
  const std::string e = inputError([&] { openBagSource(path("odom.bag"), PoseSource::Auto, o); });
  EXPECT_NE(e.find("no nav_msgs/Odometry topic /odom"), std::string::npos) << e;
  EXPECT_NE(e.find("/wheel_odom (nav_msgs/Odometry)"), std::string::npos) << e;
}

TEST_F(BagSourceTest, BeamsOutOfRangeOrNotFiniteAreInvalidAndAClockwiseScanIsMirrored) {
  RosScan s;
  s.frame = "base_link";  // no mount transform needed
  s.ranges = {std::nanf(""), kInf, -kInf, 0.05f, 0.1f, 20.0f, 20.5f, 7.0f};
  s.angle_min = 0.7f;
  s.increment = -0.2f;  // beams clockwise
  {
    BagWriter bag(path("beams.bag"));
    bag.tf(kT0, "odom", "base_link", CPose2D());
    bag.scan("/scan", kT0, s);
    bag.tf(kT0 + 0.1, "odom", "base_link", CPose2D());
  }
  auto src = openScanSource(path("beams.bag"), PoseSource::Odometry);
  const auto recs = readAll(*src);
  ASSERT_EQ(recs.size(), 1u);
  const auto& scan = *recs[0].scan;
  const std::vector<bool> valid = {false, false, false, false, true, true, false, true};
  for (std::size_t i = 0; i < valid.size(); ++i) {
    EXPECT_EQ(scan.getScanRangeValidity(i), valid[i]) << "beam " << i;
  }
  EXPECT_FALSE(scan.rightToLeft);
  EXPECT_NEAR(scan.aperture, 1.4, 1e-6);
  // Beam 0 at +0.7, beam 7 at -0.7: the middle looks straight ahead.
  EXPECT_NEAR(CPose2D(scan.sensorPose).phi(), 0.0, 1e-6);
}

TEST_F(BagSourceTest, AScanWhoseFrameHasNoTransformIsSkippedAndNamed) {
  {
    BagWriter bag(path("ghost.bag"));
    writeDrive(bag);
    bag.scan("/scan", kT0 + 0.3, fiveBeams("ghost"));
    bag.scan("/scan", kT0 + 0.6, fiveBeams("ghost"));
  }
  auto src = openScanSource(path("ghost.bag"), PoseSource::Odometry);
  const auto recs = readAll(*src);
  EXPECT_EQ(recs.size(), 8u);
  EXPECT_EQ(src->stats().scans, 10u);
  EXPECT_EQ(src->stats().skipped.at("scan frame 'ghost' has no transform to 'base_link'"), 2u);
}

TEST_F(BagSourceTest, TheOnlyLaserScanTopicOrTheNamedOne) {
  {
    BagWriter bag(path("two.bag"));
    writeDrive(bag);
    for (int k = 0; k < 3; ++k) bag.scan("/rear_scan", kT0 + 0.2 + 0.5 * k, fiveBeams());
  }
  std::string e = inputError([&] { openScanSource(path("two.bag"), PoseSource::Auto); });
  EXPECT_NE(e.find("more than one sensor_msgs/LaserScan topic: pick one with --scan-topic"),
            std::string::npos)
      << e;
  EXPECT_NE(e.find("/rear_scan (sensor_msgs/LaserScan), /scan (sensor_msgs/LaserScan), "
                   "/tf (tf2_msgs/TFMessage), /tf_static (tf2_msgs/TFMessage)"),
            std::string::npos)
      << e;
  BagOptions o;
  o.scan_topic = "/rear_scan";
  auto src = openBagSource(path("two.bag"), PoseSource::Auto, o);
  EXPECT_EQ(readAll(*src).size(), 3u);
  o.scan_topic = "/front_scan";
  e = inputError([&] { openBagSource(path("two.bag"), PoseSource::Auto, o); });
  EXPECT_EQ(e.rfind(path("two.bag") + ": no sensor_msgs/LaserScan topic /front_scan (topics: ", 0),
            0u)
      << e;
}

TEST_F(BagSourceTest, AStandingRobotMapsAtTheFixedPose) {
  {
    BagWriter bag(path("still.bag"));
    for (int k = 0; k < 5; ++k) bag.scan("/scan", kT0 + 0.2 * k, fiveBeams());
  }
  const std::string e = inputError([&] { openScanSource(path("still.bag"), PoseSource::Auto); });
  EXPECT_NE(e.find("no poses found"), std::string::npos) << e;
  EXPECT_NE(e.find("--poses fixed"), std::string::npos) << e;
  InputOptions o;
  o.poses = PoseSource::Fixed;
  o.fixed_pose = CPose2D(1.0, -2.0, 0.5);
  auto src = openScanSource(path("still.bag"), o);
  EXPECT_EQ(src->poseSource(), PoseSource::Fixed);
  const auto recs = readAll(*src);
  ASSERT_EQ(recs.size(), 5u);
  for (const auto& r : recs) {
    expectPose(r.pose, o.fixed_pose);
    expectPose(CPose2D(r.scan->sensorPose), CPose2D());  // no tf: the laser is the robot
  }
}

// rosbag cannot open a bag whose index (at its end) is cut off: what is left is read in file
// order, every scan before the cut kept, and then the cut is an InputError.
void expectTruncatedBagKeepsItsScans(const std::string& whole, const std::string& cut,
                                     const std::size_t min_kept) {
  auto all = openScanSource(whole, PoseSource::Odometry);
  const auto want = readAll(*all);
  std::filesystem::copy_file(whole, cut);
  std::filesystem::resize_file(cut, std::filesystem::file_size(whole) * 2 / 3);
  EXPECT_TRUE(looksLikeRosBag(cut));
  auto src = openScanSource(cut, PoseSource::Auto);
  EXPECT_EQ(src->poseSource(), PoseSource::Odometry);
  std::vector<ScanRecord> got;
  const std::string e = inputError([&] {
    ScanRecord r;
    while (src->next(r)) got.push_back(r);
  });
  EXPECT_EQ(e.rfind(cut + ": a ROS bag without its index", 0), 0u) << e;
  EXPECT_NE(e.find("(truncated bag)"), std::string::npos) << e;
  EXPECT_GE(got.size(), min_kept);
  ASSERT_LT(got.size(), want.size());
  for (std::size_t k = 0; k < got.size(); ++k) {
    EXPECT_EQ(got[k].index, want[k].index);
    EXPECT_DOUBLE_EQ(got[k].t, want[k].t);
    expectPose(got[k].pose, want[k].pose, 1e-12);
  }
}

/// 10 s of /tf at 20 Hz and 40 scans, in chunks of 4 KB.
void writeLongDrive(BagWriter& bag) {
  bag.tf(kT0, "base_link", "laser", kMount, true);
  for (int k = 0; k <= 200; ++k) {
    const double t = kT0 + 0.05 * k;
    bag.tf(t, "odom", "base_link", odomAt(t));
    if (k % 5 == 2 && k < 200) bag.scan("/scan", t, fiveBeams());
  }
}

TEST_F(BagSourceTest, ATruncatedBagMapsEveryScanBeforeTheCut) {
  {
    BagWriter bag(path("whole.bag"));
    writeLongDrive(bag);
  }
  // Uncompressed chunks (rosbag's default): the cut chunk keeps its whole messages.
  expectTruncatedBagKeepsItsScans(path("whole.bag"), path("cut.bag"), 24);
}

TEST_F(BagSourceTest, ATruncatedCompressedBagMapsEveryWholeChunkBeforeTheCut) {
  for (const auto c : {rosbag::compression::LZ4, rosbag::compression::BZ2}) {
    const std::string name = c == rosbag::compression::LZ4 ? "lz4" : "bz2";
    {
      BagWriter bag(path(name + ".bag"), c);
      writeLongDrive(bag);
    }
    expectTruncatedBagKeepsItsScans(path(name + ".bag"), path(name + "-cut.bag"), 10);
  }
}

TEST_F(BagSourceTest, AFileThatIsNoBagIsAnInputErrorNamingIt) {
  std::ofstream(path("junk.bag")) << "#ROSBAG V2.0\nthis is no bag at all";
  EXPECT_TRUE(looksLikeRosBag(path("junk.bag")));
  const std::string e = inputError([&] { openScanSource(path("junk.bag"), PoseSource::Auto); });
  EXPECT_EQ(e.rfind(path("junk.bag") + ": ", 0), 0u) << e;
  std::ofstream(path("text.bag")) << "#ROSBAG V1.2\n";
  EXPECT_FALSE(looksLikeRosBag(path("text.bag")));
  EXPECT_FALSE(looksLikeRosBag(path("absent.bag")));
}

// rosbag sizes its buffers by what the bag says; dynamap's definition of Buffer::ensureCapacity
// (bag_source.cpp) replaces rosbag's and applies the record allocation limit. setSize is
// librosbag_storage's own: this fails as soon as rosbag's calls no longer reach dynamap's
// definition (rosbag's own would take the 1 GiB).
TEST(RosbagBuffer, GrowsUnderTheAllocationLimitOnly) {
  rosbag::Buffer b;
  {
    const AllocationLimit limit(1 << 20);
    EXPECT_THROW(b.setSize(1u << 30), std::bad_alloc);  // rosbag's own would take 1 GiB
    b.setSize(1000);
    EXPECT_GE(b.getCapacity(), 1000u);
    b.setSize(3000);  // doubled from 1000
    EXPECT_EQ(b.getCapacity(), 4000u);
  }
  b.setSize(4u << 20);  // no limit in force: doubled as rosbag does, 4000 * 2^11
  EXPECT_EQ(b.getCapacity(), 8192000u);
}

TEST_F(BagSourceTest, TransformsAreKeptForASlidingWindowOnly) {
  // 10 minutes of /tf at 20 Hz (12,000 transforms), a scan every second.
  {
    BagWriter bag(path("long.bag"));
    bag.tf(kT0, "base_link", "laser", kMount, true);
    for (int k = 0; k <= 12000; ++k) {
      const double t = kT0 + 0.05 * k;
      bag.tf(t, "odom", "base_link", CPose2D(0.01 * k, 0, 0));
      if (k % 20 == 10) bag.scan("/scan", t, fiveBeams());
    }
  }
  BagReader reader(path("long.bag"), BagOptions{});
  reader.require(true, false);
  BagScan s;
  std::size_t n = 0, most = 0;
  while (reader.next(s)) {
    ++n;
    most = std::max(most, reader.samplesKept());
  }
  EXPECT_EQ(n, 600u);
  // 10 s of history plus the 2 s a scan may wait, at 20 Hz: never the whole bag.
  EXPECT_LE(most, 260u);
  EXPECT_GE(most, 200u);
}

}  // namespace
}  // namespace dynamap
