// mapConsistency: exact figures on hand-made scans; ScanLayout: the same figures, bounded.

#include "dynamap/localization/consistency.h"

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

// ---- ScanLayout ------------------------------------------------------------------------------

/// Scan i of a corridor seen from x = 0.1 i: its two walls, in the robot's frame (every 2 cm).
std::vector<mrpt::math::TPoint2D> corridorHits(std::size_t i) {
  std::vector<mrpt::math::TPoint2D> hits;
  for (int k = -100; k <= 100; ++k) {
    hits.emplace_back(0.02 * k - 0.1 * double(i), 1.0);
    hits.emplace_back(0.02 * k - 0.1 * double(i), -1.2);
  }
  return hits;
}

TEST(ScanLayout, ScoresAsMapConsistencyOnTheScansLaidOut) {
  ConsistencyOptions o;
  o.neighbour_scans = 2;
  ScanLayout layout(o);
  std::vector<mrpt::poses::CPose2D> poses;
  std::vector<std::vector<MapPoint>> laid;
  for (std::size_t i = 0; i < 12; ++i) {
    // Every third scan 2 cm and 0.3 deg off its true pose.
    const double off = i % 3 == 0 ? 0.02 : 0.0;
    poses.emplace_back(0.1 * double(i) + off, off, off * 0.26);
    ASSERT_TRUE(layout.add(corridorHits(i)));
    std::vector<MapPoint>& pts = laid.emplace_back();
    for (const auto& h : corridorHits(i)) {
      const mrpt::math::TPoint2D g = poses.back() + h;
      pts.push_back({g.x, g.y});
    }
  }
  const Consistency a = layout.score(poses), b = mapConsistency(laid, o);
  EXPECT_EQ(layout.size(), 12u);
  EXPECT_FALSE(layout.full());
  EXPECT_EQ(a.global_points, b.global_points);
  EXPECT_EQ(a.local_points, b.local_points);
  EXPECT_EQ(a.global_m, b.global_m);  // the same points, the same sums: equal, not near
  EXPECT_EQ(a.local_m, b.local_m);
  EXPECT_GT(a.global_m, 0.0005);  // the scans 2 cm off lie 2 cm from their partners
}

TEST(ScanLayout, KeepsNoScanPastItsBoundOfPoints) {
  // 402 hits a scan, every 3rd kept: 134 points; room for two scans in 300.
  ScanLayout layout(ConsistencyOptions{}, 300);
  EXPECT_TRUE(layout.add(corridorHits(0)));
  EXPECT_TRUE(layout.add(corridorHits(1)));
  EXPECT_FALSE(layout.add(corridorHits(2)));
  EXPECT_FALSE(layout.add({}));  // once full, nothing more
  EXPECT_TRUE(layout.full());
  EXPECT_EQ(layout.size(), 2u);
  const Consistency c = layout.score({mrpt::poses::CPose2D(0, 0, 0), mrpt::poses::CPose2D(0.1, 0, 0)});
  EXPECT_EQ(c.scans, 2u);
  EXPECT_NEAR(c.local_m, 0.0, 1e-12);  // the two scans, each at its pose, lie on each other
  EXPECT_THROW(layout.score({mrpt::poses::CPose2D(0, 0, 0)}), std::invalid_argument);
  ConsistencyOptions bad;
  bad.cap_m = 0;
  EXPECT_THROW(ScanLayout{bad}, std::invalid_argument);
}

}  // namespace
}  // namespace dynamap
