// mapConsistency: exact figures on hand-made scans.

#include "dynamap/evaluation/consistency.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iomanip>
#include <stdexcept>
#include <string>

#include "../test_util.h"

namespace dynamap {
namespace {

/// A wall along x at height y: points every 1 cm over [0, 1] m.
std::vector<MapPoint> wall(double y) {
  std::vector<MapPoint> pts;
  for (int i = 0; i <= 100; ++i) pts.push_back({0.01 * i, y});
  return pts;
}

ConsistencyOptions every(std::size_t neighbour_scans) {
  ConsistencyOptions o;
  o.neighbour_scans = neighbour_scans;
  o.scan_stride = 1;
  o.point_stride = 1;
  return o;
}

TEST(Consistency, ScansLaidOnEachOtherScoreZero) {
  const Consistency c = mapConsistency({wall(0), wall(0), wall(0)}, every(0));
  EXPECT_EQ(c.scans, 3u);
  EXPECT_EQ(c.global_points, 303u);
  EXPECT_DOUBLE_EQ(c.global_m, 0.0);
  EXPECT_EQ(c.local_points, 202u);
  EXPECT_DOUBLE_EQ(c.local_m, 0.0);
}

TEST(Consistency, AShiftedScanScoresItsShift) {
  // Scan 1 lies 3 cm off scans 0 and 2: each of its points is 3 cm from theirs, theirs from it.
  const Consistency c = mapConsistency({wall(0), wall(0.03), wall(0)}, every(0));
  EXPECT_NEAR(c.local_m, 0.03, 1e-12);
  // Global (every other scan counts): scans 0 and 2 find each other at 0, scan 1 finds 3 cm.
  EXPECT_NEAR(c.global_m, 0.01, 1e-12);
}

TEST(Consistency, DistancesAreCappedAndNeighboursExcluded) {
  ConsistencyOptions o = every(1);  // only scans 2 or more apart count in the global figure
  o.cap_m = 0.2;
  const Consistency c = mapConsistency({wall(0), wall(0), wall(0.5)}, o);
  // Scan 0 meets scan 2 only, 0.5 m away: capped. Scan 1 has no scan 2 apart; scan 2 meets scan 0.
  EXPECT_EQ(c.global_points, 303u);
  EXPECT_NEAR(c.global_m, 0.2, 1e-12);
  EXPECT_NEAR(c.local_m, 0.1, 1e-12);  // 0 from scan 1 to scan 0, capped from scan 2 to scan 1
}

TEST(Consistency, StridesThinTheQueries) {
  ConsistencyOptions o = every(0);
  o.scan_stride = 2;
  o.point_stride = 10;
  const Consistency c = mapConsistency({wall(0), wall(0.02), wall(0), wall(0.02)}, o);
  EXPECT_EQ(c.global_points, 22u);  // scans 0 and 2, 11 points each
  EXPECT_EQ(c.local_points, 33u);   // scans 1, 2 and 3
  EXPECT_NEAR(c.local_m, 0.02, 1e-12);
  EXPECT_NEAR(c.global_m, 0.0, 1e-12);  // scans 0 and 2 lie on each other
}

TEST(Consistency, NothingToScoreIsNaN) {
  const Consistency c = mapConsistency({wall(0)}, every(0));
  EXPECT_NEAR(c.global_m, 0.2, 1e-12);  // a lone scan's points have no partner: capped
  EXPECT_EQ(c.global_points, 101u);
  EXPECT_TRUE(std::isnan(c.local_m));
  EXPECT_EQ(c.local_points, 0u);
  EXPECT_TRUE(std::isnan(mapConsistency({}, every(0)).global_m));
}

TEST(Consistency, ARobotStandingStillScoresZero) {
  // Every scan the same: the cells fill past their bound and are thinned, evenly over the scans,
  // so each query still finds partners more than neighbour_scans away.
  const std::vector<std::vector<MapPoint>> scans(3000, wall(0));
  const Consistency c = mapConsistency(scans, ConsistencyOptions{});
  EXPECT_EQ(c.global_points, 429u * 34u);  // every 7th scan, every 3rd point
  EXPECT_DOUBLE_EQ(c.global_m, 0.0);
  EXPECT_DOUBLE_EQ(c.local_m, 0.0);
}

TEST(Consistency, AScanOfManyPointsIsThinnedToABoundedNumber) {
  std::vector<MapPoint> dense;  // 100,001 points over 1 m: every 51st used, 1,961
  for (int i = 0; i <= 100000; ++i) dense.push_back({1e-5 * i, 0});
  const Consistency c = mapConsistency({dense, dense}, every(0));
  EXPECT_EQ(c.global_points, 2u * 1961u);
  EXPECT_EQ(c.local_points, 1961u);
  EXPECT_DOUBLE_EQ(c.global_m, 0.0);
  EXPECT_DOUBLE_EQ(c.local_m, 0.0);
}

TEST(Consistency, PointsOffEveryCellScoreTheCap) {
  // A NaN or astronomically far point (a corrupt pose) gets a cell, partners nothing and is
  // partnered by nothing: every distance is the cap.
  const double far = 1e300;
  const std::vector<MapPoint> odd = {{std::nan(""), 0}, {far, far}, {-far, 5}};
  const Consistency c = mapConsistency({wall(0), odd}, every(0));
  EXPECT_EQ(c.global_points, 104u);
  EXPECT_NEAR(c.global_m, 0.2, 1e-12);
  EXPECT_EQ(c.local_points, 3u);
  EXPECT_NEAR(c.local_m, 0.2, 1e-12);
}

TEST(Consistency, BadOptionsThrow) {
  ConsistencyOptions o;
  o.point_stride = 0;
  EXPECT_THROW(mapConsistency({wall(0)}, o), std::invalid_argument);
  o = ConsistencyOptions{};
  o.cap_m = 0;
  EXPECT_THROW(mapConsistency({wall(0)}, o), std::invalid_argument);
}

// ---- dynamap eval --input LOG --trajectory FILE ---------------------------------------------

/// The truth of the bundled tiny log, with every pose from scan `from` on moved by (dx, dy) and
/// every timestamp by dt, into `path`.
void writeMovedTruth(const std::string& path, std::size_t from, double dx, double dy,
                     double dt = 0) {
  std::ifstream in(std::string(DYNAMAP_SOURCE_DIR) + "/rawlogs/tiny/tiny.gt.txt");
  std::ofstream out(path);
  out << std::fixed << std::setprecision(6);
  double t, x, y, phi;
  for (std::size_t i = 0; in >> t >> x >> y >> phi; ++i) {
    const bool moved = i >= from;
    out << t + dt << ' ' << x + (moved ? dx : 0) << ' ' << y + (moved ? dy : 0) << ' ' << phi
        << '\n';
  }
}

/// The figure after `what` ("global ", "local ") in eval's consistency line, in mm.
double figure(const std::string& out, const std::string& what) {
  const auto at = out.find(what);
  EXPECT_NE(at, std::string::npos) << out;
  return at == std::string::npos ? NAN : std::stod(out.substr(at + what.size()));
}

TEST(EvalConsistency, AMapDoubledByAJumpScoresWorseGloballyNotLocally) {
  const std::string dir = test::tempDir("consistency");
  const std::string log = std::string(DYNAMAP_SOURCE_DIR) + "/rawlogs/tiny/tiny.rawlog";
  const std::string cmd = std::string(DYNAMAP_EXE) + " eval --input " + log + " --trajectory ";
  writeMovedTruth(dir + "/truth.txt", 0, 0, 0);
  writeMovedTruth(dir + "/jump.txt", 150, 0.1, 0.05);  // the second half 11 cm off the first
  std::string truth, jump;
  ASSERT_EQ(test::run(cmd + dir + "/truth.txt", &truth), 0) << truth;
  ASSERT_EQ(test::run(cmd + dir + "/jump.txt", &jump), 0) << jump;
  EXPECT_NE(truth.find("301 scans scored, 0 without a pose"), std::string::npos) << truth;
  EXPECT_GT(figure(jump, "global "), figure(truth, "global ") + 10) << truth << jump;
  // One pair of consecutive scans of 300 straddles the jump.
  EXPECT_NEAR(figure(jump, "local "), figure(truth, "local "), 1.0) << truth << jump;
  // The same bytes again.
  std::string again;
  ASSERT_EQ(test::run(cmd + dir + "/jump.txt", &again), 0);
  EXPECT_EQ(again, jump);
}

TEST(EvalConsistency, PosesAtNoScanTimeAndMisusedFlagsAreErrors) {
  const std::string dir = test::tempDir("consistency-err");
  const std::string log = std::string(DYNAMAP_SOURCE_DIR) + "/rawlogs/tiny/tiny.rawlog";
  const std::string exe = std::string(DYNAMAP_EXE) + " eval";
  writeMovedTruth(dir + "/late.txt", 0, 0, 0, 1000);  // every pose 1000 s after the log
  std::string out;
  EXPECT_EQ(test::run(exe + " --input " + log + " --trajectory " + dir + "/late.txt", &out), 1);
  EXPECT_NE(out.find(dir + "/late.txt: no pose at the time of any scan of " + log),
            std::string::npos)
      << out;
  EXPECT_EQ(test::run(exe + " --input " + log, &out), 2) << out;  // nothing to lay out
  std::ofstream(dir + "/empty.txt") << "% no poses\n";
  EXPECT_EQ(test::run(exe + " --input " + log + " --trajectory " + dir + "/empty.txt", &out), 1);
  EXPECT_NE(out.find("no pose (expected"), std::string::npos) << out;
}

}  // namespace
}  // namespace dynamap
