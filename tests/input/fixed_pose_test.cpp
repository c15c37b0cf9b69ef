// The fixed pose source: every format's scans at one pose (a robot standing still), the pose's
// text form, and the [input] keys that choose it.

#include "dynamap/input/fixed_pose.h"

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/serialization/CArchive.h>

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "../test_util.h"
#include "dynamap/base/ini.h"
#include "dynamap/input/open_source.h"
#include "dynamap/pipeline/mapper.h"

namespace dynamap {
namespace {

using mrpt::poses::CPose2D;
using test::readAll;

InputOptions fixedAt(const CPose2D& pose) {
  InputOptions o;
  o.poses = PoseSource::Fixed;
  o.fixed_pose = pose;
  return o;
}

void expectAllAt(const std::vector<ScanRecord>& recs, const CPose2D& pose) {
  for (const auto& r : recs) {
    EXPECT_DOUBLE_EQ(r.pose.x(), pose.x());
    EXPECT_DOUBLE_EQ(r.pose.y(), pose.y());
    EXPECT_DOUBLE_EQ(r.pose.phi(), pose.phi());
  }
}

TEST(FixedPose, ParsesThreeFiniteNumbersAndNothingElse) {
  const CPose2D p = parseFixedPose("  1.5 -2\t0.25 ");
  EXPECT_DOUBLE_EQ(p.x(), 1.5);
  EXPECT_DOUBLE_EQ(p.y(), -2.0);
  EXPECT_DOUBLE_EQ(p.phi(), 0.25);
  for (const char* bad : {"", "1 2", "1 2 3 4", "1 2 x", "1 nan 0", "1 2 inf"}) {
    EXPECT_THROW(parseFixedPose(bad), std::invalid_argument) << bad;
  }
  for (const CPose2D& q : {CPose2D(), CPose2D(0.1, -1e-7, 3.0), CPose2D(1 / 3.0, 2, -0.5)}) {
    const CPose2D back = parseFixedPose(formatFixedPose(q));
    EXPECT_EQ(back.x(), q.x());
    EXPECT_EQ(back.y(), q.y());
    EXPECT_EQ(back.phi(), q.phi());
  }
  EXPECT_EQ(formatFixedPose(CPose2D(1, 2, 0.5)), "1 2 0.5");
}

// A rawlog of scans only (no odometry, no ground truth): no poses of its own.
TEST(FixedPose, ARawlogOfScansOnlyMapsAtTheFixedPose) {
  const std::string dir = test::tempDir("fixed");
  {
    mrpt::io::CFileGZOutputStream out(dir + "/scans.rawlog");
    auto ar = mrpt::serialization::archiveFrom(out);
    for (int k = 0; k < 4; ++k) {
      auto scan = test::makeScan({1.0f, 2.0f, 3.0f}, 1.0, 50.0 + k);
      scan->timestamp = mrpt::Clock::fromDouble(50.0 + k);
      ar << *scan;
    }
  }
  try {
    openScanSource(dir + "/scans.rawlog", PoseSource::Auto);
    ADD_FAILURE() << "a rawlog without poses opened under auto";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--poses fixed"), std::string::npos) << e.what();
  }
  const CPose2D at(3.0, 4.0, -1.0);
  auto src = openScanSource(dir + "/scans.rawlog", fixedAt(at));
  EXPECT_EQ(src->poseSource(), PoseSource::Fixed);
  const auto recs = readAll(*src);
  ASSERT_EQ(recs.size(), 4u);
  EXPECT_DOUBLE_EQ(recs[3].t, 53.0);
  expectAllAt(recs, at);
}

// A rawlog that has poses: fixed ignores them.
TEST(FixedPose, OverridesTheLogsOwnPoses) {
  const std::string dir = test::tempDir("fixed");
  std::vector<test::LogStep> steps;
  for (int k = 0; k < 5; ++k) {
    steps.push_back({10.0 + k, CPose2D(k, 0, 0), test::makeScan({1.0f, 2.0f}, 0.5, 10.0 + k)});
  }
  test::writeObsRawlog(dir + "/moving.rawlog", steps);
  auto src = openScanSource(dir + "/moving.rawlog", fixedAt(CPose2D(0, 0, 0)));
  const auto recs = readAll(*src);
  ASSERT_EQ(recs.size(), 5u);
  expectAllAt(recs, CPose2D());
}

TEST(FixedPose, ACarmenLogMapsAtTheFixedPose) {
  const std::string dir = test::tempDir("fixed");
  std::string beams;
  for (int i = 0; i < 181; ++i) beams += " 2.5";
  std::ofstream(dir + "/still.log") << "FLASER 181" << beams << " 5 6 0.5 5 6 0.5 10.5 h 10.6\n"
                                    << "FLASER 181" << beams << " 5 6 0.5 5 6 0.5 10.7 h 10.8\n";
  const CPose2D at(-1.0, 0.5, 0.0);
  auto src = openScanSource(dir + "/still.log", fixedAt(at));
  const auto recs = readAll(*src);
  ASSERT_EQ(recs.size(), 2u);
  expectAllAt(recs, at);
}

TEST(FixedPose, ASimplemapMapsAtTheFixedPose) {
  const std::string path = "/usr/share/mrpt/datasets/malaga-cs-fac-building.simplemap.gz";
  if (!std::ifstream(path).good()) GTEST_SKIP() << "mrpt-common's datasets are not installed";
  const CPose2D at(7.0, 0.0, 1.0);
  auto src = openScanSource(path, fixedAt(at));
  const auto recs = readAll(*src);
  EXPECT_EQ(recs.size(), 99u);
  expectAllAt(recs, at);
}

TEST(FixedPose, ChosenInTheInputSectionAndWrittenBackOnlyWhenUsed) {
  const MapConfig c =
      MapConfig::load(IniFile::fromText("[input]\nposes = fixed\nfixed_pose = 1 2 0.5\n", "f.ini"));
  EXPECT_EQ(c.poses, PoseSource::Fixed);
  EXPECT_DOUBLE_EQ(c.fixed_pose.y(), 2.0);
  std::ostringstream fixed_ini, auto_ini;
  c.writeIni(fixed_ini);
  EXPECT_NE(fixed_ini.str().find("fixed_pose = 1 2 0.5"), std::string::npos);
  MapConfig().writeIni(auto_ini);
  EXPECT_EQ(auto_ini.str().find("fixed_pose"), std::string::npos);
  try {
    MapConfig::load(IniFile::fromText("[input]\nfixed_pose = 1 2\n", "bad.ini"));
    ADD_FAILURE() << "a two-number fixed_pose loaded";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.ini: [input] fixed_pose"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace dynamap
