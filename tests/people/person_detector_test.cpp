// Person detections: clusters of neighbouring beams, legs paired into people, hit points kept
// only where the static map holds free space.

#include "dynamap/people/person_detector.h"

#include <gtest/gtest.h>

#include <cmath>

#include "../test_util.h"
#include "dynamap/mapping/dynamic_grid_map.h"

namespace dynamap {
namespace {

// Points on the near side of a disc (cx, cy, r) seen from the origin, one per beam of `step`.
std::vector<HitPoint2> arc(double cx, double cy, double r, double step, std::size_t first_beam) {
  std::vector<HitPoint2> out;
  const double d = std::hypot(cx, cy), bearing = std::atan2(cy, cx), half = std::asin(r / d);
  std::size_t beam = first_beam;
  for (double a = bearing - half + step / 2; a < bearing + half; a += step) {
    // The near intersection of the ray with the circle.
    const double along = d * std::cos(a - bearing), perp = d * std::sin(a - bearing);
    const double t = along - std::sqrt(r * r - perp * perp);
    out.push_back({t * std::cos(a), t * std::sin(a), beam++});
  }
  return out;
}

TEST(ClusterPoints, SplitsOnDistanceAndOnBeamGapsAndFindsTheCentre) {
  const double step = M_PI / 360;
  auto pts = arc(3, 0, 0.2, step, 0);
  const std::size_t n = pts.size();
  auto far = arc(3, 1.0, 0.2, step, n + 5);  // five beams later: another cluster
  pts.insert(pts.end(), far.begin(), far.end());
  const auto clusters = clusterPoints(pts, 0, 0, PeopleOptions{});
  ASSERT_EQ(clusters.size(), 2u);
  EXPECT_EQ(clusters[0].points, n);
  // The centroid of the near half pushed back by pi/4 of the radius: within 2 cm of the centre.
  EXPECT_NEAR(clusters[0].cx, 3.0, 0.02);
  EXPECT_NEAR(clusters[0].cy, 0.0, 0.01);
  EXPECT_NEAR(clusters[0].width, 0.4, 0.03);
}

TEST(ClusterPoints, AClusterWiderThanAPersonIsOverMaxPersonWidthAndNoPerson) {
  // 4000 points 1 mm apart on a line 1 m ahead (a wall S does not know yet): one cluster 4 m
  // wide, whose width is only known to be over max_person_width (0.8 m), and no detection.
  std::vector<HitPoint2> line;
  for (std::size_t i = 0; i < 4000; ++i) line.push_back({1.0, -2.0 + 0.001 * i, i});
  const PeopleOptions o;
  const auto clusters = clusterPoints(line, 0, 0, o);
  ASSERT_EQ(clusters.size(), 1u);
  EXPECT_EQ(clusters[0].points, 4000u);
  EXPECT_GT(clusters[0].width, o.max_person_width);
  EXPECT_TRUE(pairLegs(clusters, o).empty());
}

TEST(ClusterPoints, FewerThanMinPointsIsNoCluster) {
  PeopleOptions o;
  o.min_points = 3;
  const std::vector<HitPoint2> two = {{1, 0, 0}, {1, 0.01, 1}};
  EXPECT_TRUE(clusterPoints(two, 0, 0, o).empty());
}

TEST(PairLegs, TwoLegsCloseTogetherAreOnePersonBetweenThem) {
  const std::vector<PointCluster> c = {{2.0, 0.15, 0.12, 5}, {2.0, -0.15, 0.12, 5}};
  const auto d = pairLegs(c, PeopleOptions{});
  ASSERT_EQ(d.size(), 1u);
  EXPECT_EQ(d[0].legs, 2);
  EXPECT_DOUBLE_EQ(d[0].x, 2.0);
  EXPECT_DOUBLE_EQ(d[0].y, 0.0);
}

TEST(PairLegs, NearestPairsFirstAndFarLegsStayAlone) {
  // Legs at y = 0, 0.3 (one person), 0.75 (0.45 from the second: a pair too, but the second is
  // taken by the nearer first), and a leg 3 m away.
  const std::vector<PointCluster> c = {
      {2, 0, 0.1, 4}, {2, 0.3, 0.1, 4}, {2, 0.75, 0.1, 4}, {5, 0, 0.1, 4}};
  const auto d = pairLegs(c, PeopleOptions{});
  ASSERT_EQ(d.size(), 3u);
  EXPECT_EQ(d[0].legs, 2);
  EXPECT_DOUBLE_EQ(d[0].y, 0.15);
  EXPECT_EQ(d[1].legs, 1);
  EXPECT_DOUBLE_EQ(d[1].y, 0.75);
  EXPECT_EQ(d[2].legs, 1);
  EXPECT_DOUBLE_EQ(d[2].x, 5);
}

TEST(PairLegs, BodySizedClustersAreAPersonAndWiderOnesNothing) {
  const std::vector<PointCluster> c = {{1, 1, 0.45, 9}, {3, 3, 1.5, 30}};
  const auto d = pairLegs(c, PeopleOptions{});
  ASSERT_EQ(d.size(), 1u);
  EXPECT_EQ(d[0].legs, 0);
  EXPECT_DOUBLE_EQ(d[0].x, 1);
}

TEST(DetectPeople, HitsOnAWallAreNeverADetection) {
  // A 6 x 4 m room seen 20 times: its inside is Free in S, its walls are not.
  DynamicGridMap map;
  const mrpt::poses::CPose2D pose(0, 0, 0);
  const int n = 181;
  const auto ranges = test::roomRanges(-3, 3, -2, 2, pose, n, M_PI);
  for (int i = 0; i < 20; ++i) {
    map.insertObservation(*test::makeScan(ranges, M_PI, i * 0.2), mrpt::poses::CPose3D(pose));
  }
  const auto scan = test::makeScan(ranges, M_PI, 5.0);
  const ScanHits hits = scanHits(*scan, pose, 15.0);
  EXPECT_EQ(hits.points.size(), static_cast<std::size_t>(n));
  EXPECT_TRUE(freeSpaceHits(map, hits, 1).empty());
  EXPECT_TRUE(detectPeople(map, hits, PeopleOptions{}).empty());
  // A person-sized bump 1 m in front of the sensor, inside the free room: one detection.
  std::vector<float> bumped = ranges;
  for (int i = 85; i <= 95; ++i) bumped[static_cast<std::size_t>(i)] = 1.0f;
  const auto d = detectPeople(map, scanHits(*test::makeScan(bumped, M_PI, 5.2), pose, 15.0),
                              PeopleOptions{});
  ASSERT_EQ(d.size(), 1u);
  EXPECT_NEAR(d[0].x, 1.0, 0.1);
  EXPECT_NEAR(d[0].y, 0.0, 0.02);
}

TEST(DetectPeople, NextToASmallBodyOfSIsNearStaticNextToAWallIsNot) {
  // The room above with a 0.35 m box 2 m ahead (beams 85..95), in S from the start.
  DynamicGridMap map;
  const mrpt::poses::CPose2D pose(0, 0, 0);
  const int n = 181;
  std::vector<float> ranges = test::roomRanges(-3, 3, -2, 2, pose, n, M_PI);
  for (int i = 85; i <= 95; ++i) ranges[static_cast<std::size_t>(i)] = 2.0f;
  for (int i = 0; i < 20; ++i) {
    map.insertObservation(*test::makeScan(ranges, M_PI, i * 0.2), mrpt::poses::CPose3D(pose));
  }
  // Someone beside the box (beams 97..103 at 1.7 m, 0.3 m from it), and someone 0.3 m in front
  // of the east wall (beams 60..64, where the wall is 3.2-3.5 m away).
  std::vector<float> seen = ranges;
  for (int i = 97; i <= 103; ++i) seen[static_cast<std::size_t>(i)] = 1.7f;
  for (int i = 60; i <= 64; ++i) seen[static_cast<std::size_t>(i)] -= 0.3f;
  const auto d = detectPeople(map, scanHits(*test::makeScan(seen, M_PI, 5.0), pose, 15.0),
                              PeopleOptions{});
  ASSERT_EQ(d.size(), 2u);
  for (const PersonDetection& p : d) {
    const bool by_box = p.y > 0;
    EXPECT_EQ(p.near_static, by_box) << p.x << " " << p.y;
  }
  // A box as wide as the room's walls are long counts as a wall.
  PeopleOptions small_objects;
  small_objects.object_max_extent = 0.2;
  for (const PersonDetection& p :
       detectPeople(map, scanHits(*test::makeScan(seen, M_PI, 5.2), pose, 15.0), small_objects))
    EXPECT_FALSE(p.near_static);
}

// A 0.35 m box stood in front of the east wall since the map began. With object_max_extent
// below its size S's body there counts as a wall, as a box 5 cm from a wall (one body with it in
// S) does: near_static cannot tell it from the wall. Once it glides off, the scan sees through
// its cells to the wall behind: its detection beside the old place has static_left; someone in
// front of the wall elsewhere, where nothing is seen through, has not.
TEST(DetectPeople, SomethingLeavingAPlaceByAWallIsStaticLeftAPersonByTheWallIsNot) {
  DynamicGridMap map;
  const mrpt::poses::CPose2D pose(0, 0, 0);
  const int n = 181;
  std::vector<float> ranges = test::roomRanges(-3, 3, -2, 2, pose, n, M_PI);
  for (int i = 87; i <= 93; ++i) ranges[static_cast<std::size_t>(i)] = 2.6f;  // the box
  for (int i = 0; i < 20; ++i) {
    map.insertObservation(*test::makeScan(ranges, M_PI, i * 0.2), mrpt::poses::CPose3D(pose));
  }
  // The box gone from beams 87..93 (the wall behind it at 3 m) and a body at 2.45 m on beams
  // 82..85, beside its old place; someone 0.3 m in front of the east wall on beams 60..64.
  std::vector<float> seen = test::roomRanges(-3, 3, -2, 2, pose, n, M_PI);
  for (int i = 82; i <= 85; ++i) seen[static_cast<std::size_t>(i)] = 2.45f;
  for (int i = 60; i <= 64; ++i) seen[static_cast<std::size_t>(i)] -= 0.3f;
  const auto hits = scanHits(*test::makeScan(seen, M_PI, 5.0), pose, 15.0);
  PeopleOptions o;
  o.object_max_extent = 0.2;
  const auto d = detectPeople(map, hits, o);
  ASSERT_EQ(d.size(), 2u);
  for (const PersonDetection& p : d) {
    const bool by_box = p.y > -0.5;
    EXPECT_FALSE(p.near_static) << p.x << " " << p.y;
    EXPECT_EQ(p.static_left, by_box) << p.x << " " << p.y;
  }
  // Beams must end static_left_margin beyond the cells: the wall is 0.4 m behind the box's face.
  PeopleOptions far = o;
  far.static_left_margin = 0.5;
  for (const PersonDetection& p : detectPeople(map, hits, far)) EXPECT_FALSE(p.static_left);
}

}  // namespace
}  // namespace dynamap
