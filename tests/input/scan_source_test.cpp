// ScanSource: formats told apart by content, poses from the chosen source, faults reported with
// the record and byte, and everything before a fault kept.

#include "dynamap/input/open_source.h"

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <mrpt/serialization/CArchive.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>

#include "../test_util.h"

namespace dynamap {
namespace {

using test::inputError;
using test::readAll;

namespace fs = std::filesystem;

using mrpt::poses::CPose2D;

// Ten scans 0.2 s apart, the robot driving along x.
std::vector<test::LogStep> tenSteps() {
  std::vector<test::LogStep> steps;
  for (int k = 0; k < 10; ++k) {
    const double t = 1000.0 + 0.2 * k;
    steps.push_back(
        {t, CPose2D(0.1 * k, 0.5, 0.01 * k), test::makeScan({1.0f, 2.0f, 3.0f}, 1.0, t)});
  }
  return steps;
}

TEST(ScanSource, ObservationRawlogWithGroundTruth) {
  const std::string dir = test::tempDir("src");
  const auto steps = tenSteps();
  test::writeObsRawlog(dir + "/a.rawlog", steps);
  auto src = openScanSource(dir + "/a.rawlog", PoseSource::Auto);
  EXPECT_EQ(src->poseSource(), PoseSource::GroundTruth);
  const auto recs = readAll(*src);
  ASSERT_EQ(recs.size(), 10u);
  for (std::size_t k = 0; k < recs.size(); ++k) {
    EXPECT_EQ(recs[k].index, k);
    EXPECT_NEAR(recs[k].t, steps[k].t, 1e-6);
    EXPECT_NEAR(recs[k].pose.x(), steps[k].pose.x(), 1e-9);
    EXPECT_NEAR(recs[k].pose.phi(), steps[k].pose.phi(), 1e-9);
    EXPECT_EQ(recs[k].scan->getScanSize(), 3u);
  }
  EXPECT_EQ(src->stats().scans, 10u);
  EXPECT_EQ(src->stats().records, 30u);
}

TEST(ScanSource, OdometryIsUsedWhenAskedOrWhenItIsAllThereIs) {
  const std::string dir = test::tempDir("src");
  auto steps = tenSteps();
  test::writeObsRawlog(dir + "/odo.rawlog", steps, /*with_gt=*/false);
  auto src = openScanSource(dir + "/odo.rawlog", PoseSource::Auto);
  EXPECT_EQ(src->poseSource(), PoseSource::Odometry);
  EXPECT_EQ(readAll(*src).size(), 10u);
  EXPECT_NE(inputError([&] {
              openScanSource(dir + "/odo.rawlog", PoseSource::GroundTruth);
            }).find("no ground-truth poses"),
            std::string::npos);
}

TEST(ScanSource, CompanionGroundTruthFileIsInterpolatedByTime) {
  const std::string dir = test::tempDir("src");
  test::writeObsRawlog(dir + "/c.rawlog", tenSteps(), /*with_gt=*/false);
  std::ofstream(dir + "/c.gt.txt") << "# t x y phi\n999.9 0 0 0\n1000.9 10 0 0\n1001.9 20 0 0\n";
  auto src = openScanSource(dir + "/c.rawlog", PoseSource::GroundTruth);
  const auto recs = readAll(*src);
  ASSERT_EQ(recs.size(), 10u);
  EXPECT_NEAR(recs[0].pose.x(), 1.0, 1e-6);   // t = 1000.0: a tenth of the way
  EXPECT_NEAR(recs[5].pose.x(), 11.0, 1e-6);  // t = 1001.0
}

// A companion file that is /dev/zero, or holds one line of 3 MB: an error naming it, read no
// further than the line cap (it once read 13 GB of /dev/zero, 1.3 GB of a 300 MB line).
TEST(ScanSource, ACompanionGroundTruthFileIsReadWithItsLinesCapped) {
  const std::string dir = test::tempDir("src");
  test::writeObsRawlog(dir + "/z.rawlog", tenSteps(), /*with_gt=*/false);
  fs::create_symlink("/dev/zero", dir + "/z.gt.txt");
  EXPECT_NE(inputError([&] {
              openScanSource(dir + "/z.rawlog", PoseSource::GroundTruth);
            }).find("z.gt.txt:1: line longer than 1048576 bytes"),
            std::string::npos);
  test::writeObsRawlog(dir + "/l.rawlog", tenSteps(), /*with_gt=*/false);
  std::ofstream(dir + "/l.gt.txt") << "999.9 0 0 0\n1000 1 " << std::string(3 << 20, '1') << "\n";
  EXPECT_NE(inputError([&] {
              openScanSource(dir + "/l.rawlog", PoseSource::GroundTruth);
            }).find("l.gt.txt:2: line longer than"),
            std::string::npos);
}

TEST(ScanSource, ActionSensoryFrameRawlogIntegratesOdometry) {
  const std::string dir = test::tempDir("src");
  const auto steps = tenSteps();
  test::writeActionSfRawlog(dir + "/sf.rawlog", steps);
  auto src = openScanSource(dir + "/sf.rawlog", PoseSource::Auto);
  EXPECT_EQ(src->poseSource(), PoseSource::Odometry);
  const auto recs = readAll(*src);
  ASSERT_EQ(recs.size(), 10u);
  for (std::size_t k = 0; k < recs.size(); ++k) {
    EXPECT_NEAR(recs[k].pose.x(), steps[k].pose.x(), 1e-6) << k;
    EXPECT_NEAR(recs[k].pose.phi(), steps[k].pose.phi(), 1e-6) << k;
  }
}

// MRPT's own logs (the SENA one) may open with a sensory frame before any action: the robot is
// at the origin of its odometry then.
TEST(ScanSource, ActionSensoryFrameRawlogMayStartWithAFrame) {
  const std::string dir = test::tempDir("src");
  {
    mrpt::io::CFileGZOutputStream out(dir + "/first-frame.rawlog");
    auto ar = mrpt::serialization::archiveFrom(out);
    const auto steps = tenSteps();
    mrpt::poses::CPose2D prev;
    for (std::size_t k = 0; k < 3; ++k) {
      if (k > 0) {
        mrpt::obs::CActionCollection acts;
        mrpt::obs::CActionRobotMovement2D mv;
        mv.computeFromOdometry(steps[k].pose - prev, {});
        acts.insert(mv);
        ar << acts;
      }
      mrpt::obs::CSensoryFrame sf;
      steps[k].scan->timestamp = mrpt::Clock::fromDouble(steps[k].t);
      sf.insert(steps[k].scan);
      ar << sf;
      prev = steps[k].pose;
    }
  }
  auto src = openScanSource(dir + "/first-frame.rawlog", PoseSource::Odometry);
  const auto recs = readAll(*src);
  ASSERT_EQ(recs.size(), 3u);
  EXPECT_NEAR(recs[0].pose.x(), 0.0, 1e-9);
  EXPECT_NEAR(recs[2].pose.x(), (tenSteps()[2].pose - tenSteps()[0].pose).x(), 1e-6);
}

TEST(ScanSource, ASimplemapGivesEachKeyframesScansAtItsPose) {
  const std::string dir = test::tempDir("simplemap");
  mrpt::maps::CSimpleMap sm;
  for (int k = 0; k < 3; ++k) {
    auto sf = mrpt::obs::CSensoryFrame::Create();
    sf->insert(test::makeScan({1.0f, 2.0f, 3.0f}, M_PI / 2, 10.0 + k));
    auto pose = mrpt::poses::CPose3DPDFGaussian::Create();
    pose->mean = mrpt::poses::CPose3D(0.5 * k, -0.25 * k, 0, 0.1 * k, 0, 0);
    sm.insert(pose, sf);
  }
  ASSERT_TRUE(sm.saveToFile(dir + "/three.simplemap"));
  auto src = openScanSource(dir + "/three.simplemap", PoseSource::Auto);
  EXPECT_EQ(src->poseSource(), PoseSource::Simplemap);
  const std::vector<ScanRecord> recs = readAll(*src);
  ASSERT_EQ(recs.size(), 3u);
  for (int k = 0; k < 3; ++k) {
    EXPECT_DOUBLE_EQ(recs[k].pose.x(), 0.5 * k);
    EXPECT_DOUBLE_EQ(recs[k].pose.y(), -0.25 * k);
    EXPECT_NEAR(recs[k].pose.phi(), 0.1 * k, 1e-12);
    EXPECT_NEAR(recs[k].t, 10.0 + k, 1e-6);
    EXPECT_EQ(recs[k].scan->getScanSize(), 3u);
  }
  EXPECT_NE(inputError([&] {
              openScanSource(dir + "/three.simplemap", PoseSource::Odometry);
            }).find("simplemap"),
            std::string::npos);
}

TEST(ScanSource, SimplemapOfMrptsExamples) {
  const std::string path = "/usr/share/mrpt/datasets/malaga-cs-fac-building.simplemap.gz";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "mrpt-common's datasets are not installed";
  auto src = openScanSource(path, PoseSource::Auto);
  EXPECT_EQ(src->poseSource(), PoseSource::Simplemap);
  EXPECT_EQ(readAll(*src).size(), 99u);
  EXPECT_NE(inputError([&] { openScanSource(path, PoseSource::Odometry); }).find("simplemap"),
            std::string::npos);
}

// The simplemap format before MRPT 1.0 (CSensFrameProbSequence of CSensorialFrame): 72 keyframes.
TEST(ScanSource, OldFormatSimplemapOfMrptsExamples) {
  const std::string path = "/usr/share/mrpt/datasets/localization_demo.simplemap.gz";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "mrpt-common's datasets are not installed";
  auto src = openScanSource(path, PoseSource::Auto);
  EXPECT_EQ(src->poseSource(), PoseSource::Simplemap);
  const auto recs = readAll(*src);
  ASSERT_EQ(recs.size(), 72u);
  EXPECT_EQ(openScanSource(path, PoseSource::Simplemap)->poseSource(), PoseSource::Simplemap);
  EXPECT_NE(recs.back().pose.distanceTo(recs.front().pose), 0.0);
}

// A simplemap is read keyframe by keyframe: cut or damaged in keyframe 3 of 10, the scans of
// keyframes 0-2 come out, then the fault naming the keyframe and its byte.
TEST(ScanSource, ASimplemapCutOrDamagedGivesEveryKeyframeBeforeTheFault) {
  const std::string dir = test::tempDir("simplemap-cut");
  const auto starts = test::writeSimplemap(dir + "/ten.simplemap", tenSteps());
  ASSERT_EQ(starts.size(), 11u);
  const std::string bytes = test::readFile(dir + "/ten.simplemap");
  std::string damaged = bytes;
  for (std::size_t i = 0; i < 8; ++i) damaged[starts[3] + i] = '\xff';
  std::ofstream(dir + "/cut.simplemap", std::ios::binary)
      << bytes.substr(0, (starts[3] + starts[4]) / 2);
  std::ofstream(dir + "/damaged.simplemap", std::ios::binary) << damaged;
  for (const auto& [name, why] :
       {std::pair<std::string, std::string>{"cut", "is cut off"}, {"damaged", "is corrupt"}}) {
    auto src = openScanSource(dir + "/" + name + ".simplemap", PoseSource::Auto);
    std::vector<ScanRecord> got;
    const std::string err = inputError([&] {
      for (ScanRecord r; src->next(r);) got.push_back(r);
    });
    ASSERT_EQ(got.size(), 3u) << name;
    EXPECT_DOUBLE_EQ(got[2].pose.x(), tenSteps()[2].pose.x());
    const std::string fault = dir + "/" + name + ".simplemap: keyframe 3 of 10 at byte " +
                              std::to_string(starts[3]) + " " + why;
    EXPECT_EQ(err.rfind(fault, 0), 0u) << err;
    EXPECT_EQ(src->stats().records, 3u);
  }
  // Cut inside the keyframe count (after the class name and its version byte): no keyframe.
  std::ofstream(dir + "/header.simplemap", std::ios::binary)
      << bytes.substr(0, bytes.find("CSimpleMap") + 10 + 1 + 2);
  EXPECT_EQ(inputError([&] { openScanSource(dir + "/header.simplemap", PoseSource::Simplemap); }),
            dir +
                "/header.simplemap: cannot read simplemap: header at byte 0 is cut off "
                "(truncated file)");
}

TEST(ScanSource, TruncatedRawlogKeepsEveryCompleteRecordAndNamesTheFault) {
  const std::string dir = test::tempDir("src");
  test::writeObsRawlog(dir + "/full.rawlog", tenSteps());
  // Decompress, cut in the middle of the 6th scan's record, store plain.
  ASSERT_EQ(test::run("gzip -dc " + dir + "/full.rawlog > " + dir + "/plain.rawlog"), 0);
  const std::string bytes = test::readFile(dir + "/plain.rawlog");
  const std::size_t per_step = bytes.size() / 10;
  std::ofstream(dir + "/cut.rawlog", std::ios::binary)
      << bytes.substr(0, 5 * per_step + per_step / 2);
  auto src = openScanSource(dir + "/cut.rawlog", PoseSource::GroundTruth);
  std::vector<ScanRecord> got;
  const std::string err = inputError([&] {
    ScanRecord r;
    while (src->next(r)) got.push_back(r);
  });
  EXPECT_EQ(got.size(), 5u);
  EXPECT_NE(err.find("cut.rawlog: record"), std::string::npos) << err;
  EXPECT_NE(err.find("at byte"), std::string::npos) << err;
}

TEST(ScanSource, NotALogIsAnErrorNamingTheFile) {
  const std::string dir = test::tempDir("src");
  std::ofstream(dir + "/junk.bin", std::ios::binary) << std::string(300, '\x07');
  EXPECT_EQ(inputError([&] { openScanSource(dir + "/junk.bin", PoseSource::Auto); }),
            dir + "/junk.bin: not an MRPT rawlog, simplemap, CARMEN log or ROS bag");
  std::ofstream(dir + "/empty.rawlog");
  EXPECT_EQ(inputError([&] { openScanSource(dir + "/empty.rawlog", PoseSource::Auto); }),
            dir + "/empty.rawlog: empty file");
  EXPECT_EQ(inputError([&] { openScanSource(dir + "/none.rawlog", PoseSource::Auto); }),
            dir + "/none.rawlog: no such file");
}

// Built with -DDYNAMAP_ROSBAG=OFF, a bag is still told by its first line, and refused by name.
TEST(ScanSource, ABagInABuildWithoutRosbagIsAnErrorSayingSo) {
#ifdef DYNAMAP_HAVE_ROSBAG
  GTEST_SKIP() << "this build reads bags: bag_source_test covers them";
#else
  const std::string dir = test::tempDir("src");
  std::ofstream(dir + "/run.bag", std::ios::binary) << "#ROSBAG V2.0\n" << std::string(64, '\0');
  EXPECT_EQ(inputError([&] { openScanSource(dir + "/run.bag", PoseSource::Auto); }),
            dir +
                "/run.bag: a ROS bag, but this dynamap was built without ROS bag support "
                "(-DDYNAMAP_ROSBAG=OFF); rebuild with -DDYNAMAP_ROSBAG=ON");
#endif
}

TEST(ScanSource, PoseSourceNames) {
  for (auto s : {PoseSource::Auto, PoseSource::Simplemap, PoseSource::GroundTruth,
                 PoseSource::Odometry, PoseSource::ScanMatching, PoseSource::Fixed}) {
    EXPECT_EQ(parsePoseSource(toString(s)), s);
  }
  EXPECT_THROW(parsePoseSource("gps"), std::invalid_argument);
}

}  // namespace
}  // namespace dynamap
