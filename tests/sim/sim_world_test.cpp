// Exact ray casting on geometry whose answers are known in closed form.

#include <gtest/gtest.h>

#include <cmath>

#include "dynamap/sim/world.h"

namespace dynamap::sim {
namespace {

constexpr double kTol = 1e-6;
constexpr double kPi = 3.14159265358979323846;

StaticWorld walls(std::vector<Segment> segments) {
  return {std::move(segments), {}};
}

TEST(SimWorld, WallStraightAhead) {
  const auto w = walls({{{5, -1}, {5, 1}}});
  const RayHit hit = castRay(w, {}, {0, 0}, 0, 8);
  ASSERT_TRUE(hit.hit());
  EXPECT_NEAR(hit.range, 5.0, kTol);
  EXPECT_EQ(hit.body, -1);
}

TEST(SimWorld, WallAtAnAngle) {
  const auto w = walls({{{2, -10}, {2, 10}}});
  EXPECT_NEAR(castRay(w, {}, {0, 0}, 30 * kPi / 180, 8).range, 2 / std::cos(30 * kPi / 180), kTol);
  // A slanted wall x + y = 4, met head-on at 45 degrees and obliquely along x.
  const auto slanted = walls({{{4, 0}, {0, 4}}});
  EXPECT_NEAR(castRay(slanted, {}, {0, 0}, kPi / 4, 8).range, 2 * std::sqrt(2.0), kTol);
  EXPECT_NEAR(castRay(slanted, {}, {1, 1}, 0, 8).range, 2.0, kTol);
}

TEST(SimWorld, WallBehindOrBesideIsMissed) {
  const auto w = walls({{{5, -1}, {5, 1}}});
  EXPECT_FALSE(castRay(w, {}, {0, 0}, kPi, 8).hit());
  EXPECT_FALSE(castRay(w, {}, {0, 0}, 0.3, 8).hit());  // passes above the wall's end
}

TEST(SimWorld, CircleHitCentrally) {
  const std::vector<Body> bodies = {{{5, 0}, 0.5, BodyKind::Object, 1}};
  const RayHit hit = castRay(walls({}), bodies, {0, 0}, 0, 8);
  ASSERT_TRUE(hit.hit());
  EXPECT_NEAR(hit.range, 4.5, kTol);
  EXPECT_EQ(hit.body, 0);
}

TEST(SimWorld, CircleHitNearTangent) {
  const double h = 0.5 - 1e-7;  // the beam passes 1e-7 m inside the edge
  const std::vector<Body> bodies = {{{5, h}, 0.5, BodyKind::Object, 1}};
  const double expected = 5 - std::sqrt(0.25 - h * h);
  EXPECT_NEAR(castRay(walls({}), bodies, {0, 0}, 0, 8).range, expected, kTol);
  const std::vector<Body> beside = {{{5, 0.5 + 1e-7}, 0.5, BodyKind::Object, 1}};
  EXPECT_FALSE(castRay(walls({}), beside, {0, 0}, 0, 8).hit());
}

TEST(SimWorld, BeamPassesBetweenTwoObjects) {
  const std::vector<Body> bodies = {{{4, 0.3}, 0.25, BodyKind::Object, 1},
                                    {{4, -0.3}, 0.25, BodyKind::Object, 2}};
  const RayHit hit = castRay(walls({{{7, -3}, {7, 3}}}), bodies, {0, 0}, 0, 8);
  EXPECT_NEAR(hit.range, 7.0, kTol);
  EXPECT_EQ(hit.body, -1);
  // Tilted toward the upper one, the same beam ends on it.
  const RayHit up = castRay(walls({{{7, -3}, {7, 3}}}), bodies, {0, 0}, std::atan2(0.3, 4), 8);
  EXPECT_EQ(up.body, 0);
  EXPECT_NEAR(up.range, std::hypot(4, 0.3) - 0.25, kTol);
}

TEST(SimWorld, NearestSurfaceWins) {
  const std::vector<Body> bodies = {{{6, 0}, 0.5, BodyKind::Person, 1}};
  const auto w = walls({{{3, -1}, {3, 1}}});
  const RayHit hit = castRay(w, bodies, {0, 0}, 0, 8);
  EXPECT_NEAR(hit.range, 3.0, kTol);
  EXPECT_EQ(hit.body, -1);
}

TEST(SimWorld, NothingWithinMaxRangeIsNoEcho) {
  const auto w = walls({{{10, -1}, {10, 1}}});
  EXPECT_FALSE(castRay(w, {}, {0, 0}, 0, 8).hit());
  EXPECT_FALSE(castRay(walls({}), {}, {0, 0}, 0, 8).hit());
  // A surface at exactly the max range still echoes.
  EXPECT_NEAR(castRay(walls({{{8, -1}, {8, 1}}}), {}, {0, 0}, 0, 8).range, 8.0, kTol);
}

TEST(SimWorld, SensorInsideACircleSeesOut) {
  const std::vector<Body> bodies = {{{0.1, 0}, 0.5, BodyKind::Person, 1}};
  EXPECT_NEAR(castRay(walls({{{4, -1}, {4, 1}}}), bodies, {0, 0}, 0, 8).range, 4.0, kTol);
}

WallGrid gridWithColumn(int column) {
  WallGrid g;
  g.resolution = 0.05;
  g.origin = {-1, -1};
  g.width = 100;
  g.height = 40;
  g.wall.assign(g.width * g.height, 0);
  for (int iy = 0; iy < g.height; ++iy) g.wall[iy * g.width + column] = 1;
  return g;
}

TEST(SimWorld, MapImageCellsAreExact) {
  StaticWorld w;
  w.grid = gridWithColumn(60);  // x from -1 + 60·0.05 = 2.0 to 2.05
  EXPECT_NEAR(castRay(w, {}, {0, 0}, 0, 8).range, 2.0, kTol);
  EXPECT_NEAR(castRay(w, {}, {0.013, 0.2}, 0.3, 8).range, (2.0 - 0.013) / std::cos(0.3), kTol);
  EXPECT_FALSE(castRay(w, {}, {0, 0}, kPi, 8).hit());
  EXPECT_FALSE(castRay(w, {}, {0, 0}, 0, 1.5).hit());
  // From outside the image, the ray enters it and still meets the column.
  EXPECT_NEAR(castRay(w, {}, {-3, 0}, 0, 8).range, 5.0, kTol);
}

TEST(SimWorld, OverlapHelpers) {
  const Segment s{{0, 0}, {4, 0}};
  EXPECT_TRUE(discOverlapsSegment({2, 0.2}, 0.3, s));
  EXPECT_FALSE(discOverlapsSegment({2, 0.4}, 0.3, s));
  EXPECT_TRUE(segmentsIntersect(s, {{1, -1}, {1, 1}}));
  EXPECT_FALSE(segmentsIntersect(s, {{5, -1}, {5, 1}}));
  const WallGrid g = gridWithColumn(60);
  EXPECT_TRUE(discOverlapsGrid({1.9, 0}, 0.2, g));
  EXPECT_FALSE(discOverlapsGrid({1.7, 0}, 0.2, g));
  EXPECT_TRUE(segmentCrossesGrid({{0, 0}, {3, 0}}, g));
  EXPECT_FALSE(segmentCrossesGrid({{0, 0}, {1.9, 0}}, g));
}

}  // namespace
}  // namespace dynamap::sim
