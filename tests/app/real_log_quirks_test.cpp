// The quirks of real logs, end to end on small logs written here: a CARMEN log maps the same
// directly and through import-carmen + map; poses are found by time despite rounding, sparse
// scans and a clock stepping back; degenerate timestamps, radian fields of view and subnormal
// numbers are handled and reported; lines and scans are counted apart.

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "../test_util.h"

namespace dynamap {
namespace {

namespace fs = std::filesystem;

/// One laser line of the synthetic log: the pose and the line's ipc_timestamp.
struct Line {
  double t;
  double x, y, phi;
};

std::string num(double v) {
  char b[64];
  std::snprintf(b, sizeof b, "%.6f", v);
  return b;
}

/// An FLASER line of 181 beams over 180 deg seen from `l` in a room of about [-3, 12] x [-3, 3]
/// (its walls off the cells' edges), odometry fields equal to the pose (a "corrected" log).
std::string flaser(const Line& l) {
  const std::vector<float> r =
      test::roomRanges(-3.02, 12.03, -2.97, 3.01, mrpt::poses::CPose2D(l.x, l.y, l.phi), 181, M_PI);
  std::string s = "FLASER 181";
  for (float v : r) s += " " + num(v);
  const std::string pose = " " + num(l.x) + " " + num(l.y) + " " + num(l.phi);
  return s + pose + pose + " " + num(l.t) + " host " + num(l.t) + "\n";
}

/// A drive along the room, `n` scans `dt` apart from t0, with the clutter of real logs:
/// comments, NEFF lines, ODOM lines stamped 0 and ODOM lines with the pose 5 cm off.
std::vector<Line> drive(int n, double t0, double dt) {
  std::vector<Line> lines;
  for (int k = 0; k < n; ++k) lines.push_back({t0 + dt * k, 0.5 * k, 0.1 * std::sin(k), 0.05 * k});
  return lines;
}

std::string carmenLog(const std::vector<Line>& lines, const std::string& header = "") {
  std::string log = "# CARMEN Logfile\n" + header;
  for (const Line& l : lines) {
    log += flaser(l) + "NEFF 1\n";
    log += "ODOM " + num(l.x + 0.05) + " " + num(l.y) + " " + num(l.phi) + " 0 0 0 " +
           num(l.t + 0.01) + " host " + num(l.t + 0.01) + "\n";
    log += "ODOM 0 0 0 0 0 0 0 host 0\n";
  }
  return log;
}

class RealLogQuirks : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = test::tempDir("quirks"); }
  void TearDown() override { fs::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(dir_ + "/" + name, std::ios::binary) << text;
    return dir_ + "/" + name;
  }
  int dynamap(const std::string& args, std::string* out = nullptr) const {
    return test::run(std::string(DYNAMAP_EXE) + " " + args, out);
  }
  /// Maps `input` into dir_/<out>; returns the exit status, the output in `out`.
  int map(const std::string& input, const std::string& out, const std::string& more = "",
          std::string* text = nullptr) const {
    return dynamap("map --no-baseline --input " + input + " --out " + dir_ + "/" + out + " " + more,
                   text);
  }
  std::string summary(const std::string& out) const {
    return test::readFile(dir_ + "/" + out + "/summary.json");
  }
  std::string dir_;
};

long number(const std::string& summary, const std::string& key) {
  const auto pos = summary.find("\"" + key + "\": ");
  if (pos == std::string::npos) return -1;
  return std::stol(summary.substr(pos + key.size() + 4));
}

/// Scans used and S's cells of two runs are the same.
void expectSameMap(const std::string& a, const std::string& b, long scans) {
  EXPECT_EQ(number(a, "used"), scans) << a;
  EXPECT_EQ(number(b, "used"), scans) << b;
  EXPECT_GT(number(a, "static_occupied"), 100) << a;
  EXPECT_EQ(number(a, "static_occupied"), number(b, "static_occupied"));
  EXPECT_EQ(number(a, "static_free"), number(b, "static_free"));
}

// Scans 4 s apart (no pose within 2 s of another) and one stamped before the scan ahead of it:
// every scan is mapped, both ways, at the same poses.
TEST_F(RealLogQuirks, SparseScansAndABackwardStampMapTheSameDirectlyAndThroughImport) {
  std::vector<Line> lines = drive(12, 1000.0, 4.0);
  lines[6].t = lines[5].t - 0.1;  // the clock steps back
  const std::string log = write("sparse.log", carmenLog(lines));
  std::string out;
  ASSERT_EQ(map(log, "direct", "", &out), 0) << out;
  ASSERT_EQ(dynamap("import-carmen " + log + " --out " + dir_ + "/sparse.rawlog", &out), 0) << out;
  ASSERT_EQ(map(dir_ + "/sparse.rawlog", "import", "", &out), 0) << out;
  expectSameMap(summary("direct"), summary("import"), 12);
  EXPECT_EQ(test::readFile(dir_ + "/direct/poses.txt"), test::readFile(dir_ + "/import/poses.txt"));
}

// A rawlog with its ground truth in <log>.gt.txt, printed to the microsecond: each scan's time
// differs from its line by a rounding error, and the lines are 4 s apart, wider than the gap
// limit of 2 s given here. The tolerance of the match, not the gap, finds each pose.
TEST_F(RealLogQuirks, AGroundTruthFileOffByARoundingErrorStillGivesEveryScanItsPose) {
  std::vector<test::LogStep> steps;
  std::string gt;
  for (int k = 0; k < 8; ++k) {
    const double t = 1000.0 + 4.0 * k + 0.12345678;  // not a whole microsecond
    const mrpt::poses::CPose2D pose(0.5 * k, 0, 0.05 * k);
    steps.push_back(
        {t, pose,
         test::makeScan(test::roomRanges(-3.02, 12.03, -2.97, 3.01, pose, 181, M_PI), M_PI, t)});
    gt += num(t) + " " + num(pose.x()) + " " + num(pose.y()) + " " + num(pose.phi()) + "\n";
  }
  test::writeObsRawlog(dir_ + "/rounded.rawlog", steps, false);
  write("rounded.gt.txt", gt);
  const std::string config = write("gap2.ini", "[input]\npose_max_gap = 2\n");
  std::string out;
  ASSERT_EQ(map(dir_ + "/rounded.rawlog", "o", "--poses ground_truth --config " + config, &out), 0)
      << out;
  EXPECT_EQ(number(summary("o"), "used"), 8);
  // Off by half a second, a scan is between two lines 4 s apart: no pose under a 2 s limit, and
  // the error says which limit.
  std::string shifted;
  for (const auto& s : steps) {
    shifted += num(s.t + (&s == &steps[0] ? 0.0 : 0.5)) + " " + num(s.pose.x()) + " " +
               num(s.pose.y()) + " " + num(s.pose.phi()) + "\n";
  }
  write("rounded.gt.txt", shifted);
  EXPECT_NE(map(dir_ + "/rounded.rawlog", "o2", "--poses ground_truth --config " + config, &out),
            0);
  EXPECT_NE(out.find("rounded.rawlog: scan 1 (t=1004.123457) has no ground_truth pose within "
                     "2.000000 s (see [input] pose_max_gap)"),
            std::string::npos)
      << out;
  // The default limit follows the lines' spacing (3 x 4 s): interpolated, every scan mapped.
  ASSERT_EQ(map(dir_ + "/rounded.rawlog", "o3", "--poses ground_truth", &out), 0) << out;
  EXPECT_EQ(number(summary("o3"), "used"), 8);
}

// Every laser line stamped 0: the scans are timed by their order (with a warning in stderr and
// summary.json), so the import's rawlog maps them at their own poses, not all at the first.
TEST_F(RealLogQuirks, TimestampsAllZeroFallBackToTheLogsOrderBothWays) {
  std::vector<Line> lines = drive(10, 0.0, 0.0);
  const std::string log = write("zero.log", carmenLog(lines));
  std::string out;
  ASSERT_EQ(map(log, "direct", "", &out), 0) << out;
  EXPECT_NE(out.find("zero.log: its first 10 laser lines carry timestamp 0 only"),
            std::string::npos)
      << out;
  EXPECT_NE(summary("direct").find("laser lines carry timestamp 0 only"), std::string::npos);
  EXPECT_DOUBLE_EQ(nlohmann::json::parse(summary("direct"))["scans"]["last_t"].get<double>(), 0.9);
  ASSERT_EQ(dynamap("import-carmen " + log + " --out " + dir_ + "/zero.rawlog", &out), 0) << out;
  EXPECT_NE(out.find("warning:     " + log + ": its first 10"), std::string::npos) << out;
  ASSERT_EQ(map(dir_ + "/zero.rawlog", "import", "", &out), 0) << out;
  expectSameMap(summary("direct"), summary("import"), 10);
}

// A rawlog whose ground-truth poses all share one time (converted with the conversion's time,
// say): time cannot place a scan, and the error says so instead of mapping every scan at one pose.
// (Streaming, the second scan is the first to meet a second pose at its time.)
TEST_F(RealLogQuirks, GroundTruthPosesSharingOneTimeAreAClearError) {
  std::vector<test::LogStep> steps;
  for (int k = 0; k < 5; ++k) {
    const mrpt::poses::CPose2D pose(0.5 * k, 0, 0);
    steps.push_back(
        {7.0, pose,
         test::makeScan(test::roomRanges(-3.02, 12.03, -2.97, 3.01, pose, 181, M_PI), M_PI, 7.0)});
  }
  test::writeObsRawlog(dir_ + "/same.rawlog", steps);
  std::string out;
  EXPECT_NE(map(dir_ + "/same.rawlog", "o", "--poses ground_truth", &out), 0);
  EXPECT_NE(out.find("same.rawlog: scan 1 (t=7.000000): several different ground_truth poses "
                     "share its timestamp"),
            std::string::npos)
      << out;
}

// An ODOM line stamped 5.45506e-312 is a corrupt line: skipped and counted, the run goes on.
TEST_F(RealLogQuirks, ASubnormalNumberIsALineSkippedNotTheEndOfTheRun) {
  std::string log = carmenLog(drive(6, 50.0, 0.25));
  log.insert(log.find("NEFF"), "NEFF 1\nODOM 1 2 0 0 0 0 5.45506e-312 host 5.45506e-312\n");
  const std::string path = write("subnormal.log", log);
  std::string out;
  ASSERT_EQ(map(path, "o", "", &out), 0) << out;
  EXPECT_EQ(number(summary("o"), "used"), 6);
  EXPECT_EQ(number(summary("o"), "line with a subnormal number"), 1);
  ASSERT_EQ(dynamap("import-carmen " + path + " --out " + dir_ + "/s.rawlog", &out), 0) << out;
  EXPECT_NE(out.find("skipped:     1 line with a subnormal number (lines)"), std::string::npos)
      << out;
}

// `PARAM laser_front_laser_fov 3.14159` is half a turn, not 3 degrees: the same map as 180.
TEST_F(RealLogQuirks, AFieldOfViewInRadiansMapsAsItsDegrees) {
  const std::vector<Line> lines = drive(6, 50.0, 0.25);
  const std::string rad =
      write("rad.log", carmenLog(lines, "PARAM laser_front_laser_fov 3.14159 0 h 0\n"));
  const std::string deg =
      write("deg.log", carmenLog(lines, "PARAM laser_front_laser_fov 180 0 h 0\n"));
  std::string out;
  ASSERT_EQ(map(rad, "rad", "", &out), 0) << out;
  EXPECT_NE(out.find("rad.log: line 2: PARAM laser_front_laser_fov 3.14159 read as radians"),
            std::string::npos)
      << out;
  ASSERT_EQ(map(deg, "deg", "", &out), 0) << out;
  expectSameMap(summary("rad"), summary("deg"), 6);
  ASSERT_EQ(map(rad, "fov90", "--fov 90", &out), 0) << out;  // --fov still decides
  EXPECT_NE(number(summary("fov90"), "static_occupied"), number(summary("rad"), "static_occupied"));
}

// Pose source odometry on a CARMEN log: the laser lines' odometry fields (here the pose), or the
// ODOM lines (5 cm off, 10 ms after each scan) interpolated to each scan's time; auto says what
// it took.
TEST_F(RealLogQuirks, TheUserChoosesWhichOdometryStreamAndAutoSaysWhatItTook) {
  const std::string log = write("odo.log", carmenLog(drive(6, 50.0, 0.25)));
  std::string out;
  ASSERT_EQ(map(log, "auto", "", &out), 0) << out;
  EXPECT_NE(out.find("poses auto: ground_truth (each laser line's own pose)"), std::string::npos)
      << out;
  ASSERT_EQ(map(log, "laser", "--poses odometry", &out), 0) << out;
  EXPECT_NE(summary("laser").find("\"pose_detail\": \"the odometry fields of each laser line\""),
            std::string::npos);
  ASSERT_EQ(map(log, "odom", "--poses odometry --carmen-odometry odom", &out), 0) << out;
  EXPECT_NE(summary("odom").find("ODOM lines, interpolated to each scan's time"),
            std::string::npos);
  // The scan at 50.5 s lies between the ODOM lines at 50.26 (x 0.55) and 50.51 (x 1.05).
  const std::string poses = test::readFile(dir_ + "/odom/poses.txt");
  EXPECT_NE(poses.find("\n50.500000 1.030000 "), std::string::npos) << poses;
  EXPECT_NE(test::readFile(dir_ + "/laser/poses.txt").find("\n50.500000 1.000000 "),
            std::string::npos);
  EXPECT_NE(map(log, "bad", "--carmen-odometry wheel", &out), 0);
  EXPECT_NE(out.find("--carmen-odometry: 'wheel' is not laser or odom"), std::string::npos) << out;
}

// Comments, NEFF and 0-stamped ODOM lines are lines skipped, not scans skipped.
TEST_F(RealLogQuirks, LinesAndScansAreCountedApart) {
  const std::string log = write("count.log", carmenLog(drive(4, 50.0, 0.25)));
  std::string out;
  ASSERT_EQ(map(log, "o", "", &out), 0) << out;
  // 1 comment + per scan: NEFF and an ODOM stamped 0 (and the FLASER and the good ODOM, read).
  EXPECT_NE(out.find("warning: 9 lines of 17 skipped: ODOM with zero timestamp (4), comment (1), "
                     "line type NEFF (4)"),
            std::string::npos)
      << out;
  EXPECT_EQ(out.find("scans of"), std::string::npos) << out;
  const std::string s = summary("o");
  EXPECT_NE(s.find("\"unit\": \"lines\""), std::string::npos) << s;
  EXPECT_EQ(number(s, "total"), 9);
  EXPECT_EQ(number(s, "skipped"), 0);
}

}  // namespace
}  // namespace dynamap
