// ROS bags end to end: a bag made from the bundled tiny scenario (its rawlog's scans, its
// ground truth as tf map -> base_link, the laser mount on /tf_static) maps to the same S as the
// rawlog, directly and through import-bag; skipped scans are named in summary.json; a standing
// robot maps at its fixed pose; a truncated bag maps up to its cut; bad topics name the file.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "../bag_test_util.h"
#include "../test_util.h"
#include "dynamap/input/open_source.h"

namespace dynamap {
namespace {

namespace fs = std::filesystem;
using mrpt::poses::CPose2D;

const std::string kTiny = std::string(DYNAMAP_SOURCE_DIR) + "/rawlogs/tiny/tiny.rawlog";

// A number of summary.json, by its (unique enough) key.
long summaryNumber(const std::string& summary, const std::string& key) {
  const auto pos = summary.find("\"" + key + "\": ");
  if (pos == std::string::npos) return -1;
  return std::stol(summary.substr(pos + key.size() + 4));
}

/// tiny.rawlog as a bag: /scan (frame laser), /tf map -> base_link at every scan's stamp (the
/// rawlog's ground truth), /tf_static base_link -> laser (its mount). Returns the scan count.
std::size_t writeTinyBag(const std::string& bag_path, const std::string& ghost_every = "") {
  auto src = openScanSource(kTiny, PoseSource::GroundTruth);
  test::BagWriter bag(bag_path);
  ScanRecord r;
  std::size_t n = 0;
  while (src->next(r)) {
    if (n == 0) bag.tf(r.t, "base_link", "laser", CPose2D(r.scan->sensorPose), true);
    bag.tf(r.t, "map", "base_link", r.pose);
    test::RosScan s = test::rosScanOf(*r.scan);
    if (!ghost_every.empty() && n % 10 == 5) s.frame = ghost_every;
    bag.scan("/scan", r.t, s);
    ++n;
  }
  return n;
}

class BagEndToEnd : public ::testing::Test {
 protected:
  std::string dir_ = test::tempDir("bag_e2e");
  std::string path(const std::string& name) const { return dir_ + "/" + name; }
  int map(const std::string& args, std::string* out = nullptr) const {
    return test::run(std::string(DYNAMAP_EXE) + " map --no-baseline " + args, out);
  }
  std::string summary(const std::string& out) const {
    return test::readFile(path(out) + "/summary.json");
  }
  void expectSameStaticMap(const std::string& a, const std::string& b, long tolerance) const {
    const std::string sa = summary(a), sb = summary(b);
    EXPECT_EQ(summaryNumber(sa, "used"), summaryNumber(sb, "used"));
    for (const char* key : {"static_occupied", "static_free", "dynamic_occupied"}) {
      EXPECT_NEAR(summaryNumber(sa, key), summaryNumber(sb, key), tolerance) << key;
    }
  }
};

TEST_F(BagEndToEnd, ABagOfTheTinyScenarioMapsToTheSameStaticMapAsItsRawlog) {
  const std::size_t scans = writeTinyBag(path("tiny.bag"));
  ASSERT_GT(scans, 50u);
  std::string out;
  ASSERT_EQ(map("--poses ground_truth --input " + kTiny + " --out " + path("raw")), 0);
  ASSERT_EQ(map("--input " + path("tiny.bag") + " --out " + path("bag"), &out), 0) << out;
  const std::string s = summary("bag");
  EXPECT_NE(s.find("\"pose_source\": \"ground_truth\""), std::string::npos);
  EXPECT_EQ(summaryNumber(s, "used"), static_cast<long>(scans));
  EXPECT_GT(summaryNumber(s, "static_occupied"), 100);
  // The bag holds the same scans and poses (stamps to the nanosecond): the same S, cell for cell.
  expectSameStaticMap("raw", "bag", 0);
}

TEST_F(BagEndToEnd, ImportBagWritesARawlogThatMapsLikeTheBag) {
  const std::size_t scans = writeTinyBag(path("tiny.bag"));
  std::string out;
  ASSERT_EQ(test::run(std::string(DYNAMAP_EXE) + " import-bag " + path("tiny.bag") + " --out " +
                          path("tiny.rawlog"),
                      &out),
            0)
      << out;
  EXPECT_NE(out.find("scans:         " + std::to_string(scans) + " on /scan, " +
                     std::to_string(scans) + " written"),
            std::string::npos)
      << out;
  ASSERT_TRUE(fs::exists(path("tiny.gt.txt")));
  std::ifstream gt(path("tiny.gt.txt"));
  std::size_t lines = 0;
  for (std::string line; std::getline(gt, line);) ++lines;
  EXPECT_EQ(lines, scans);
  ASSERT_EQ(map("--input " + path("tiny.bag") + " --out " + path("bag")), 0);
  ASSERT_EQ(map("--input " + path("tiny.rawlog") + " --out " + path("imported")), 0);
  expectSameStaticMap("bag", "imported", 0);
}

TEST_F(BagEndToEnd, ScansWithoutATransformAreSkippedAndNamedInTheSummary) {
  const std::size_t scans = writeTinyBag(path("ghost.bag"), "ghost");
  std::string out;
  ASSERT_EQ(map("--input " + path("ghost.bag") + " --out " + path("o"), &out), 0) << out;
  const std::string s = summary("o");
  const long ghosts = static_cast<long>((scans + 4) / 10);
  EXPECT_EQ(summaryNumber(s, "used"), static_cast<long>(scans) - ghosts);
  EXPECT_EQ(summaryNumber(s, "scan frame 'ghost' has no transform to 'base_link'"), ghosts) << s;
}

TEST_F(BagEndToEnd, AStandingRobotMapsAtTheFixedPose) {
  {
    auto src = openScanSource(kTiny, PoseSource::GroundTruth);
    test::BagWriter bag(path("still.bag"));
    ScanRecord r;
    for (int k = 0; k < 5 && src->next(r); ++k) bag.scan("/scan", r.t, test::rosScanOf(*r.scan));
  }
  std::string out;
  EXPECT_EQ(map("--input " + path("still.bag") + " --out " + path("auto"), &out), 1);
  EXPECT_NE(out.find("--poses fixed maps a robot that stands still"), std::string::npos) << out;
  ASSERT_EQ(map("--input " + path("still.bag") + " --poses fixed --fixed-pose '1 2 0.5' --out " +
                    path("fixed"),
                &out),
            0)
      << out;
  EXPECT_NE(summary("fixed").find("\"pose_source\": \"fixed\""), std::string::npos);
  EXPECT_EQ(summaryNumber(summary("fixed"), "used"), 5);
  const std::string poses = test::readFile(path("fixed") + "/poses.txt");
  EXPECT_NE(poses.find(" 1.000000 2.000000 0.500000"), std::string::npos) << poses;
  EXPECT_NE(test::readFile(path("fixed") + "/config.ini").find("fixed_pose = 1 2 0.5"),
            std::string::npos);
}

TEST_F(BagEndToEnd, BadBagsAndTopicsFailNamingTheFile) {
  writeTinyBag(path("tiny.bag"));
  std::string out;
  EXPECT_EQ(map("--input " + path("tiny.bag") + " --scan-topic /nope --out " + path("o"), &out), 1);
  EXPECT_NE(out.find(path("tiny.bag") + ": no sensor_msgs/LaserScan topic /nope (topics: /scan "
                                        "(sensor_msgs/LaserScan), /tf (tf2_msgs/TFMessage), "
                                        "/tf_static (tf2_msgs/TFMessage))"),
            std::string::npos)
      << out;
}

TEST_F(BagEndToEnd, ATruncatedBagMapsEveryScanBeforeTheCutAndExits4) {
  const std::size_t scans = writeTinyBag(path("tiny.bag"));
  fs::copy_file(path("tiny.bag"), path("cut.bag"));
  fs::resize_file(path("cut.bag"), fs::file_size(path("tiny.bag")) / 2);
  std::string out;
  EXPECT_EQ(map("--input " + path("cut.bag") + " --out " + path("o"), &out), 4) << out;
  EXPECT_NE(out.find("input ended in a fault"), std::string::npos) << out;
  const std::string s = summary("o");
  EXPECT_NE(s.find("\"complete_input\": false"), std::string::npos);
  EXPECT_NE(s.find("(truncated bag)"), std::string::npos) << s;
  const long used = summaryNumber(s, "used");
  // Half the file: about half the scans (the other half of the file is mostly scans too).
  EXPECT_GT(used, static_cast<long>(scans) * 2 / 5);
  EXPECT_LT(used, static_cast<long>(scans) * 3 / 5);
  // import-bag keeps the same scans in a rawlog, and says the bag ended in a fault.
  EXPECT_EQ(test::run(std::string(DYNAMAP_EXE) + " import-bag " + path("cut.bag") + " --out " +
                          path("cut.rawlog"),
                      &out),
            4)
      << out;
  ASSERT_EQ(map("--input " + path("cut.rawlog") + " --out " + path("imported")), 0);
  EXPECT_EQ(summaryNumber(summary("imported"), "used"), used);
}

}  // namespace
}  // namespace dynamap
