// The CARMEN reader against a log written by hand from the format: old and new laser lines, PARAM
// lines, ODOM lines, comments and other message types.

#include "dynamap/input/carmen_reader.h"

#include <gtest/gtest.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/math/wrap2pi.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

namespace dynamap {
namespace {

namespace fs = std::filesystem;
constexpr double kDeg = M_PI / 180.0;

/// A fresh directory per test, removed afterwards.
class CarmenTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("dynamap_carmen_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& text) const {
    const std::string path = (dir_ / name).string();
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }
  std::string writeGz(const std::string& name, const std::string& text) const {
    const std::string path = (dir_ / name).string();
    mrpt::io::CFileGZOutputStream out(path);
    out.Write(text.data(), text.size());
    return path;
  }

  fs::path dir_;
};

std::string num(double v) {
  char b[64];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

/// Range of beam i in the sample lines: 1 m + 1 cm per beam.
double sampleRange(std::size_t i) {
  return 1.0 + 0.01 * static_cast<double>(i);
}

std::string ranges(std::size_t n) {
  std::string s;
  for (std::size_t i = 0; i < n; ++i) s += " " + num(sampleRange(i));
  return s;
}

// The sample log, one line per entry; its line numbers are used below.
const std::vector<std::string>& sampleLines() {
  static const std::vector<std::string> kLines = {
      /* 1*/ "# CARMEN Logfile",
      /* 2*/ "# message_name [message contents] ipc_timestamp ipc_hostname logger_timestamp",
      /* 3*/ "PARAM robot_frontlaser_offset 0.25 1000.0 host 1000.0",
      /* 4*/ "PARAM laser_front_laser_resolution 1.0 1000.0 host 1000.0",
      /* 5*/ "PARAM robot_front_laser_max 50.0 1000.0 host 1000.0",
      /* 6*/ "PARAM robot_use_sonar off 1000.0 host 1000.0",
      /* 7*/ "SYNC start 1000.5 host 1000.5",
      /* 8*/ "ODOM 1.0 2.0 0.1 0.3 0.05 0 1001.0 host 1001.5",
      /* 9*/ "FLASER 180" + ranges(180) + " 5.0 6.0 0.5 4.0 5.5 0.4 1001.25 host 1001.75",
      /*10*/ "NEFF 10",
      /*11*/ "ODOM 5.0 6.0 0.5 0 0 0 0 host 0",
      /*12*/ "",
      /*13*/ "RLASER 360" + ranges(360) + " 7.0 8.0 -0.5 7.5 8.5 -0.25 1002.0 host 1002.25",
      /*14*/ "ROBOTLASER1 0 " + num(-M_PI / 2) + " " + num(M_PI) + " " + num(M_PI / 180) +
          " 80.0 0.01 0 181" + ranges(181) + " 0 2.0 3.1 " + num(M_PI / 2) + " 2.0 3.0 " +
          num(M_PI / 2) + " 0.3 0.05 1 0.5 0 1002.5 host 1002.75",
  };
  return kLines;
}

std::string joinLines(const std::vector<std::string>& lines) {
  std::string s;
  for (const auto& l : lines) s += l + "\n";
  return s;
}

std::vector<CarmenEvent> readAll(const std::string& path, const CarmenOptions& options = {},
                                 SourceStats* stats = nullptr) {
  CarmenReader reader(path, options);
  std::vector<CarmenEvent> events;
  CarmenEvent e;
  while (reader.next(e)) events.push_back(e);
  if (stats) *stats = reader.stats();
  return events;
}

/// The world-frame angle of beam i relative to the robot: sensor yaw + MRPT's beam angle.
double beamAngle(const mrpt::obs::CObservation2DRangeScan& s, std::size_t i) {
  return s.sensorPose.yaw() + s.getScanAngle(i);
}

TEST_F(CarmenTest, ReadsEveryScanAndOdomLineWithTheLogsTimestamps) {
  SourceStats stats;
  const auto events = readAll(write("sample.log", joinLines(sampleLines())), {}, &stats);
  ASSERT_EQ(events.size(), 4u);  // ODOM, FLASER, RLASER, ROBOTLASER1 (the 0-stamped ODOM skipped)
  EXPECT_EQ(events[0].kind, CarmenEvent::Kind::Odometry);
  EXPECT_DOUBLE_EQ(events[0].t, 1001.0);
  EXPECT_DOUBLE_EQ(events[0].tv, 0.3);
  const double times[] = {1001.25, 1002.0, 1002.5};  // the ipc timestamps
  const std::size_t lines[] = {9, 13, 14};
  for (int k = 0; k < 3; ++k) {
    const CarmenEvent& e = events[k + 1];
    ASSERT_EQ(e.kind, CarmenEvent::Kind::Scan);
    EXPECT_DOUBLE_EQ(e.t, times[k]);
    EXPECT_EQ(e.line, lines[k]);
    EXPECT_NEAR(mrpt::Clock::toDouble(e.scan->timestamp), times[k], 1e-6);
    EXPECT_EQ(e.scan->sensorLabel, "LASER");
    EXPECT_TRUE(e.scan->rightToLeft);
  }
  EXPECT_EQ(stats.records, sampleLines().size());
  EXPECT_EQ(stats.scans, 3u);
  EXPECT_EQ(stats.skipped["comment"], 2u);
  EXPECT_EQ(stats.skipped["line type SYNC"], 1u);
  EXPECT_EQ(stats.skipped["line type NEFF"], 1u);
  EXPECT_EQ(stats.skipped["PARAM not used"], 1u);
  EXPECT_EQ(stats.skipped["ODOM with zero timestamp"], 1u);
  EXPECT_EQ(stats.skipped["empty line"], 1u);
  EXPECT_EQ(stats.skipped.count("bad line"), 0u);
}

TEST_F(CarmenTest, OldFormatFrontLaserTakesStepRangeAndOffsetFromParams) {
  const auto events = readAll(write("sample.log", joinLines(sampleLines())));
  const auto& s = *events[1].scan;
  ASSERT_EQ(s.getScanSize(), 180u);
  EXPECT_NEAR(s.aperture, 179 * kDeg, 1e-6);  // MRPT's aperture spans first to last beam
  EXPECT_NEAR(beamAngle(s, 0), -90 * kDeg, 1e-6);
  EXPECT_NEAR(beamAngle(s, 1) - beamAngle(s, 0), 1 * kDeg, 1e-6);
  EXPECT_NEAR(beamAngle(s, 179), 89 * kDeg, 1e-6);
  EXPECT_NEAR(s.sensorPose.x(), 0.25, 1e-9);
  EXPECT_NEAR(s.sensorPose.y(), 0.0, 1e-9);
  EXPECT_FLOAT_EQ(s.maxRange, 50.0f);
  EXPECT_NEAR(s.getScanRange(7), sampleRange(7), 1e-5);
  EXPECT_TRUE(s.getScanRangeValidity(7));
}

TEST_F(CarmenTest, RearLaserWithoutParamsFacesBackwardsWithHalfDegreeBeams) {
  const auto events = readAll(write("sample.log", joinLines(sampleLines())));
  const auto& s = *events[2].scan;
  ASSERT_EQ(s.getScanSize(), 360u);
  EXPECT_NEAR(beamAngle(s, 1) - beamAngle(s, 0), 0.5 * kDeg, 1e-6);
  // First beam at -90 deg in the rear laser's frame, which faces backwards.
  EXPECT_NEAR(mrpt::math::wrapToPi(beamAngle(s, 0) - M_PI), -90 * kDeg, 1e-6);
  EXPECT_NEAR(s.sensorPose.x(), 0.0, 1e-9);
  EXPECT_FLOAT_EQ(s.maxRange, 81.0f);  // the default
}

TEST_F(CarmenTest, RobotLaserTakesItsGeometryAndMountFromTheLine) {
  const auto events = readAll(write("sample.log", joinLines(sampleLines())));
  const auto& s = *events[3].scan;
  ASSERT_EQ(s.getScanSize(), 181u);
  EXPECT_NEAR(s.aperture, M_PI, 1e-6);
  EXPECT_NEAR(beamAngle(s, 0), -M_PI / 2, 1e-6);
  EXPECT_NEAR(beamAngle(s, 180), M_PI / 2, 1e-6);
  // laser pose (2, 3.1, 90 deg) seen from robot pose (2, 3, 90 deg): 10 cm ahead.
  EXPECT_NEAR(s.sensorPose.x(), 0.1, 1e-9);
  EXPECT_NEAR(s.sensorPose.y(), 0.0, 1e-9);
  EXPECT_FLOAT_EQ(s.maxRange, 80.0f);
}

TEST_F(CarmenTest, InvalidBeamsAreZeroMaxRangeAndNonFinite) {
  std::string line = "FLASER 180";
  for (int i = 0; i < 180; ++i) {
    line += i == 0 ? " 0" : i == 1 ? " 50" : i == 2 ? " nan" : i == 3 ? " 49.99" : " -1";
  }
  line += " 0 0 0 0 0 0 1.0 host 1.0";
  const auto events =
      readAll(write("beams.log", "PARAM robot_front_laser_max 50.0 0 host 0\n" + line + "\n"));
  const auto& s = *events.at(0).scan;
  EXPECT_FALSE(s.getScanRangeValidity(0));
  EXPECT_FALSE(s.getScanRangeValidity(1));
  EXPECT_FALSE(s.getScanRangeValidity(2));
  EXPECT_TRUE(s.getScanRangeValidity(3));
  EXPECT_FALSE(s.getScanRangeValidity(4));
}

TEST_F(CarmenTest, PosesUnderGroundTruthAndOdometry) {
  const std::string path = write("sample.log", joinLines(sampleLines()));
  auto gt = openCarmenSource(path, PoseSource::Auto, {});
  EXPECT_EQ(gt->poseSource(), PoseSource::GroundTruth);
  auto odo = openCarmenSource(path, PoseSource::Odometry, {});
  EXPECT_EQ(odo->poseSource(), PoseSource::Odometry);
  // Ground truth: the line's pose (FLASER's is the laser's: 0.25 m ahead of the robot's);
  // odometry: FLASER/RLASER odom fields, ROBOTLASER1 the last ODOM.
  const mrpt::poses::CPose2D want_gt[] = {
      {5 - 0.25 * std::cos(0.5), 6 - 0.25 * std::sin(0.5), 0.5}, {7, 8, -0.5}, {2, 3, M_PI / 2}};
  const mrpt::poses::CPose2D want_odo[] = {{4, 5.5, 0.4}, {7.5, 8.5, -0.25}, {1, 2, 0.1}};
  ScanRecord r;
  for (std::size_t k = 0; k < 3; ++k) {
    ASSERT_TRUE(gt->next(r));
    EXPECT_EQ(r.index, k);
    EXPECT_LT((r.pose - want_gt[k]).norm(), 1e-9) << k;
    EXPECT_NEAR(r.pose.phi(), want_gt[k].phi(), 1e-9) << k;
    ASSERT_TRUE(odo->next(r));
    EXPECT_EQ(r.index, k);
    EXPECT_LT((r.pose - want_odo[k]).norm(), 1e-9) << k;
    EXPECT_NEAR(r.pose.phi(), want_odo[k].phi(), 1e-9) << k;
  }
  EXPECT_FALSE(gt->next(r));
  EXPECT_FALSE(odo->next(r));
  EXPECT_EQ(gt->stats().scans, 3u);
  EXPECT_THROW(openCarmenSource(path, PoseSource::Simplemap, {}), InputError);
}

// A corrected log writes its corrected pose, the laser's, into both triples: the robot's pose and
// odometry both lie the offset behind it, and the laser lands on the line's pose. A line whose
// triples differ (CARMEN's logger) keeps its odom fields as the robot's odometry.
TEST_F(CarmenTest, CorrectedLinesPoseIsTheLasersInBothTriples) {
  const std::string path =
      write("corrected.log", "PARAM robot_frontlaser_offset -0.04 0 host 0\nFLASER 180" +
                                 ranges(180) + " 3.0 4.0 1.0 3.0 4.0 1.0 1.0 host 1.0\nFLASER 180" +
                                 ranges(180) + " 3.0 4.0 1.0 2.9 4.0 1.0 2.0 host 2.0\n");
  const auto events = readAll(path);
  ASSERT_EQ(events.size(), 2u);
  const mrpt::poses::CPose2D robot(3 + 0.04 * std::cos(1.0), 4 + 0.04 * std::sin(1.0), 1.0);
  for (const CarmenEvent& e : events) {
    EXPECT_LT((e.pose - robot).norm(), 1e-12);
    EXPECT_DOUBLE_EQ(e.pose.phi(), 1.0);
    const mrpt::poses::CPose3D laser = mrpt::poses::CPose3D(e.pose) + e.scan->sensorPose;
    EXPECT_NEAR(laser.x(), 3.0, 1e-12);
    EXPECT_NEAR(laser.y(), 4.0, 1e-12);
  }
  ASSERT_TRUE(events[0].odometry && events[1].odometry);
  EXPECT_LT((*events[0].odometry - robot).norm(), 1e-12);
  EXPECT_LT((*events[1].odometry - mrpt::poses::CPose2D(2.9, 4.0, 1.0)).norm(), 1e-12);
}

TEST_F(CarmenTest, RobotLaserWithoutOdometryIsAnErrorUnderOdometryOnly) {
  const auto& l = sampleLines();
  const std::string path = write("robotlaser.log", l[13] + "\n");
  ScanRecord r;
  EXPECT_TRUE(openCarmenSource(path, PoseSource::GroundTruth, {})->next(r));
  try {
    openCarmenSource(path, PoseSource::Odometry, {})->next(r);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("robotlaser.log:1:"), std::string::npos) << e.what();
  }
}

/// The sample with line `at` (1-based) replaced by `bad`.
std::string sampleWithBadLine(std::size_t at, const std::string& bad) {
  auto lines = sampleLines();
  lines.at(at - 1) = bad;
  return joinLines(lines);
}

TEST_F(CarmenTest, MalformedLinesAreErrorsNamingFileAndLine) {
  const std::vector<std::pair<std::size_t, std::string>> cases = {
      {9, "FLASER 180 1.0 2.0"},                                    // too few fields
      {9, "FLASER 3 1.0 2.0 3.0 0 0 0 0 0 0 1.0 host 1.0 7.0"},     // count does not match
      {9, "FLASER 3 1.0 x 3.0 0 0 0 0 0 0 1.0 host 1.0"},           // a non-number
      {9, "FLASER many 1.0 2.0"},                                   // a non-count
      {8, "ODOM 1.0 2.0 0.1 0.3 0.05 0 1001.0 host"},               // ODOM one short
      {8, "ODOM 1.0 2.0 nan 0.3 0.05 0 1001.0 host 1001.5"},        // non-finite pose
      {14, "ROBOTLASER1 0 -1.57 3.14 0.0174 80 0.01 0 181 1 2 3"},  // truncated
      {5, "PARAM robot_front_laser_max fifty 0 host 0"},            // a PARAM that matters
  };
  for (const auto& [at, bad] : cases) {
    const std::string path = write("bad.log", sampleWithBadLine(at, bad));
    try {
      readAll(path);
      ADD_FAILURE() << "no error for: " << bad;
    } catch (const InputError& e) {
      const std::string want = path + ":" + std::to_string(at) + ":";
      EXPECT_EQ(std::string(e.what()).rfind(want, 0), 0u) << e.what() << " for: " << bad;
    }
  }
}

TEST_F(CarmenTest, SkipBadLinesCountsThem) {
  auto lines = sampleLines();
  lines[8] = "FLASER 180 1.0 2.0";
  lines[10] = "ODOM a b c d e f g h i";
  CarmenOptions options;
  options.skip_bad_lines = true;
  SourceStats stats;
  const auto events = readAll(write("bad.log", joinLines(lines)), options, &stats);
  EXPECT_EQ(stats.scans, 2u);
  EXPECT_EQ(stats.skipped["bad line"], 2u);
  EXPECT_EQ(stats.records, lines.size());
  EXPECT_EQ(events.size(), 3u);
}

// Runs of empty lines are passed over in bulk (a gz of a few MB can hold billions of them); every
// one is still a line: counted, and the lines after them keep their numbers.
TEST_F(CarmenTest, RunsOfEmptyLinesAreCountedAndKeepLineNumbers) {
  auto lines = sampleLines();
  const std::size_t kRun = 3000000;
  std::string text;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    text += lines[i] + "\n";
    if (i == 8) text += std::string(kRun, '\n');  // after the FLASER line (9)
  }
  SourceStats stats;
  const auto events = readAll(writeGz("empty.log.gz", text), {}, &stats);
  EXPECT_EQ(stats.records, lines.size() + kRun);
  EXPECT_EQ(stats.skipped["empty line"], kRun + 1);  // the run and line 12
  ASSERT_EQ(stats.scans, 3u);
  EXPECT_EQ(events.back().line, 14 + kRun);  // ROBOTLASER1, line 14 before the run
  // A malformed line after the run is named by its number.
  lines[12] = "RLASER 360 1.0";
  text.clear();
  for (std::size_t i = 0; i < lines.size(); ++i) text += lines[i] + (i == 8 ? "\n\n\n" : "\n");
  try {
    readAll(write("bad-after-empty.log", text));
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad-after-empty.log:15: "), std::string::npos)
        << e.what();
  }
}

TEST_F(CarmenTest, OverlongLineIsAnErrorNamingIt) {
  CarmenOptions options;
  options.max_line_length = 1000;  // the FLASER line (9) is longer
  try {
    readAll(write("long.log", joinLines(sampleLines())), options);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("long.log:9: line longer than 1000"), std::string::npos)
        << e.what();
  }
}

TEST_F(CarmenTest, MissingFileIsAnInputErrorNamingIt) {
  const std::string path = (dir_ / "missing.log").string();
  try {
    CarmenReader reader(path, {});
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), path + ": no such file");
  }
}

TEST_F(CarmenTest, GzCopyReadsTheSame) {
  const std::string text = joinLines(sampleLines());
  SourceStats plain_stats, gz_stats;
  const auto plain = readAll(write("sample.log", text), {}, &plain_stats);
  const auto gz = readAll(writeGz("sample.log.gz", text), {}, &gz_stats);
  ASSERT_EQ(plain.size(), gz.size());
  for (std::size_t k = 0; k < plain.size(); ++k) {
    EXPECT_EQ(plain[k].kind, gz[k].kind);
    EXPECT_EQ(plain[k].line, gz[k].line);
    EXPECT_DOUBLE_EQ(plain[k].t, gz[k].t);
    EXPECT_EQ(plain[k].pose, gz[k].pose);
    if (plain[k].scan) {
      EXPECT_EQ(plain[k].scan->getScanSize(), gz[k].scan->getScanSize());
      EXPECT_EQ(plain[k].scan->getScanRange(5), gz[k].scan->getScanRange(5));
    }
  }
  EXPECT_EQ(plain_stats.records, gz_stats.records);
  EXPECT_EQ(plain_stats.skipped, gz_stats.skipped);
}

TEST_F(CarmenTest, WindowsLineEndsAndNoFinalNewlineAreRead) {
  std::string text;
  for (const auto& l : sampleLines()) text += l + "\r\n";
  text.resize(text.size() - 2);
  SourceStats stats;
  readAll(write("crlf.log", text), {}, &stats);
  EXPECT_EQ(stats.scans, 3u);
  EXPECT_EQ(stats.records, sampleLines().size());
}

TEST_F(CarmenTest, LooksLikeCarmenByContent) {
  const std::string text = joinLines(sampleLines());
  EXPECT_TRUE(looksLikeCarmen(write("a.log", text)));
  EXPECT_TRUE(looksLikeCarmen(writeGz("a.log.gz", text)));
  EXPECT_TRUE(looksLikeCarmen(write("odom_first.txt", "ODOM 0 0 0 0 0 0 0.1 h 0.1\n")));
  std::string binary(4096, '\0');
  std::mt19937 rng(42);
  for (auto& c : binary) c = static_cast<char>(rng());
  EXPECT_FALSE(looksLikeCarmen(write("random.bin", binary)));
  EXPECT_FALSE(looksLikeCarmen(write("config.ini", "[map]\nresolution = 0.05\n")));
  EXPECT_FALSE(looksLikeCarmen(write("empty.log", "")));
  EXPECT_FALSE(looksLikeCarmen(write("comments.log", "# only a comment\n")));
  EXPECT_FALSE(looksLikeCarmen((dir_ / "missing.log").string()));
}

// --- real-log quirks ---------------------------------------------------------------------------

namespace quirks {

/// An FLASER line of `n` beams at pose (x, 0, 0) stamped t; odom fields (ox, 0, 0).
std::string flaser(std::size_t n, double x, double t, double ox = 0) {
  return "FLASER " + std::to_string(n) + ranges(n) + " " + num(x) + " 0 0 " + num(ox) + " 0 0 " +
         num(t) + " host " + num(t) + "\n";
}
std::string odom(double x, double t) {
  return "ODOM " + num(x) + " 0 0 0 0 0 " + num(t) + " host " + num(t) + "\n";
}

bool anyContains(const std::vector<std::string>& v, const std::string& what) {
  for (const auto& s : v) {
    if (s.find(what) != std::string::npos) return true;
  }
  return false;
}

}  // namespace quirks

TEST_F(CarmenTest, ALineWithASubnormalNumberIsSkippedAndCounted) {
  using namespace quirks;
  std::string bad_range = flaser(4, 2, 3.0);
  bad_range.replace(bad_range.find(" 1.01 "), 6, " 4.9e-320 ");
  const std::string path =
      write("subnormal.log", flaser(4, 0, 1.0) + "ODOM 1 0 0 0 0 0 5.45506e-312 host 0\n" +
                                 flaser(4, 1, 2.0) + bad_range + flaser(4, 3, 4.0));
  SourceStats stats;
  const auto events = readAll(path, {}, &stats);
  ASSERT_EQ(events.size(), 3u);  // the ODOM line and the third laser line are gone
  EXPECT_DOUBLE_EQ(events[2].pose.x(), 3.0);
  EXPECT_EQ(events[2].line, 5u);
  EXPECT_EQ(stats.skipped.at("line with a subnormal number"), 2u);
  EXPECT_EQ(stats.scans, 3u);
  EXPECT_EQ(stats.record_unit, "lines");
}

TEST_F(CarmenTest, AFieldOfViewInRadiansIsReadAsRadiansAndSaidSo) {
  using namespace quirks;
  const std::string path =
      write("rad.log", "PARAM laser_front_laser_fov 3.14159 0 host 0\n" + flaser(181, 0, 1.0));
  SourceStats stats;
  const auto events = readAll(path, {}, &stats);
  ASSERT_EQ(events.size(), 1u);
  const auto& s = *events[0].scan;
  EXPECT_NEAR(beamAngle(s, 0), -3.14159 / 2, 1e-6);
  EXPECT_NEAR(beamAngle(s, 180), 3.14159 / 2, 1e-6);
  ASSERT_EQ(stats.warnings.size(), 1u);
  EXPECT_NE(stats.warnings[0].find(path + ": line 1: PARAM laser_front_laser_fov 3.14159 read as "
                                          "radians (180 deg)"),
            std::string::npos)
      << stats.warnings[0];
  CarmenOptions fov90;  // --fov still decides
  fov90.fov_deg = 90;
  const auto over = readAll(path, fov90);
  EXPECT_NEAR(beamAngle(*over[0].scan, 0), -M_PI / 4, 1e-6);
  CarmenParams params;  // degrees stay degrees
  ASSERT_TRUE(params.applyParam("laser_front_laser_fov", "100"));
  EXPECT_DOUBLE_EQ(*params.front.fov_deg, 100.0);
}

TEST_F(CarmenTest, AGeometryThatDoesNotAgreeIsAWarningSayingWhatWasAssumed) {
  using namespace quirks;
  // 180 beams 0.5 deg apart span 90 deg, not the 180 deg assumed without a fov PARAM.
  const std::string path = write("geom.log", "PARAM laser_front_laser_resolution 0.5 0 host 0\n" +
                                                 flaser(180, 0, 1.0) + flaser(180, 0, 2.0));
  SourceStats stats;
  const auto events = readAll(path, {}, &stats);
  ASSERT_EQ(stats.warnings.size(), 1u);  // once, not per line
  EXPECT_NE(stats.warnings[0].find("geom.log: line 2: 180 beams 0.5 deg apart"), std::string::npos)
      << stats.warnings[0];
  EXPECT_NE(stats.warnings[0].find("assumed: beams 0.5 deg apart from -90 deg"), std::string::npos);
  EXPECT_NEAR(beamAngle(*events[0].scan, 0), -M_PI / 2, 1e-6);
  SourceStats agree;  // Freiburg's: 360 beams of 0.5 deg over 180
  readAll(
      write("ok.log", "PARAM laser_front_laser_resolution 0.5 0 host 0\n" + flaser(360, 0, 1.0)),
      {}, &agree);
  EXPECT_TRUE(agree.warnings.empty());
}

TEST_F(CarmenTest, DegenerateTimestampsAreReplacedByTheLogsOrderWithAWarning) {
  using namespace quirks;
  std::string zero, two, fine;
  for (int k = 0; k < 6; ++k) {
    zero += flaser(4, k, 0.0) + (k == 2 ? odom(9, 0.5) : "");
    two += flaser(4, k, k < 3 ? 100.0 : 200.0);
    fine += flaser(4, k, 100.0 + k);
  }
  SourceStats stats;
  const auto events = readAll(write("zero.log", zero), {}, &stats);
  ASSERT_EQ(events.size(), 7u);
  const double want[] = {0.0, 0.1, 0.2, 0.2, 0.3, 0.4, 0.5};  // the ODOM line: its scan's time
  for (std::size_t k = 0; k < events.size(); ++k) {
    EXPECT_NEAR(events[k].t, want[k], 1e-12) << k;
    if (events[k].scan) {
      EXPECT_NEAR(mrpt::Clock::toDouble(events[k].scan->timestamp), want[k], 1e-6);
    }
  }
  EXPECT_TRUE(anyContains(stats.warnings, "laser lines carry timestamp 0 only"))
      << stats.warnings[0];
  SourceStats stats2;
  const auto events2 = readAll(write("two.log", two), {}, &stats2);
  EXPECT_NEAR(events2.back().t, 0.5, 1e-12);
  EXPECT_TRUE(anyContains(stats2.warnings, "only 2 distinct timestamps"));
  SourceStats stats3;
  const auto events3 = readAll(write("fine.log", fine), {}, &stats3);
  EXPECT_DOUBLE_EQ(events3.back().t, 105.0);
  EXPECT_TRUE(stats3.warnings.empty());
  // Two scans at two times are a log, not a degenerate one.
  EXPECT_DOUBLE_EQ(readAll(write("short.log", flaser(4, 0, 7.0) + flaser(4, 1, 8.0)))[1].t, 8.0);
}

TEST_F(CarmenTest, AFaultWhileReadingAheadComesAfterTheScansBeforeIt) {
  using namespace quirks;
  const std::string path = write("fault.log", flaser(4, 0, 1.0) + flaser(4, 1, 2.0) + "FLASER x\n");
  CarmenReader reader(path, {});
  CarmenEvent e;
  ASSERT_TRUE(reader.next(e));
  ASSERT_TRUE(reader.next(e));
  try {
    reader.next(e);
    FAIL() << "expected the bad line";
  } catch (const InputError& err) {
    EXPECT_EQ(std::string(err.what()).rfind(path + ":3:", 0), 0u) << err.what();
  }
}

TEST_F(CarmenTest, OdometryFromTheLaserLinesOrFromTheOdomLinesInterpolated) {
  using namespace quirks;
  const std::string path =
      write("two_streams.log", odom(0, 10.0) + flaser(4, 5, 10.25, 7.0) + odom(1, 11.0) +
                                   flaser(4, 6, 11.0, 8.0) + odom(3, 12.0));
  CarmenOptions laser, lines;
  lines.odometry = CarmenOdometrySource::OdomLines;
  auto a = openCarmenSource(path, PoseSource::Odometry, laser);
  auto b = openCarmenSource(path, PoseSource::Odometry, lines);
  EXPECT_EQ(a->poseDetail(), "the odometry fields of each laser line");
  EXPECT_EQ(b->poseDetail(), "the ODOM lines, interpolated to each scan's time");
  EXPECT_EQ(openCarmenSource(path, PoseSource::Auto, lines)->poseDetail(),
            "each laser line's own pose");
  ScanRecord r;
  const double want_a[] = {7.0, 8.0}, want_b[] = {0.25, 1.0};
  for (int k = 0; k < 2; ++k) {
    ASSERT_TRUE(a->next(r));
    EXPECT_DOUBLE_EQ(r.pose.x(), want_a[k]);
    ASSERT_TRUE(b->next(r));
    EXPECT_DOUBLE_EQ(r.pose.x(), want_b[k]);
    EXPECT_EQ(r.index, static_cast<std::size_t>(k));
  }
  EXPECT_FALSE(b->next(r));
  // A scan long after the last ODOM line has none: an error naming its line.
  const std::string late = write("late.log", odom(0, 10.0) + odom(1, 11.0) + flaser(4, 0, 30.0));
  try {
    openCarmenSource(late, PoseSource::Odometry, lines)->next(r);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(late + ":3: scan 0", 0), 0u) << e.what();
  }
}

}  // namespace
}  // namespace dynamap
