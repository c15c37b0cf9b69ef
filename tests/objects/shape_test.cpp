// Circle fit and size estimates from cells and from hit points on a partial arc.

#include "dynamap/objects/shape.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <set>
#include <utility>

namespace dynamap {
namespace {

constexpr double kRes = 0.05;

// The cells a laser at (sx, sy) with `step` rad between beams hits on a cylinder.
std::vector<CellXY> arcCells(double sx, double sy, double cx, double cy, double diameter,
                             double step) {
  const double r = diameter / 2, d = std::hypot(cx - sx, cy - sy);
  const double bearing = std::atan2(cy - sy, cx - sx), half = std::asin(r / d);
  std::set<std::pair<int, int>> seen;
  std::vector<CellXY> out;
  for (double a = bearing - half; a <= bearing + half; a += step) {
    const double along = d * std::cos(a - bearing), perp = d * std::sin(a - bearing);
    if (std::abs(perp) > r) continue;
    const double range = along - std::sqrt(r * r - perp * perp);
    const int x = static_cast<int>(std::floor((sx + range * std::cos(a)) / kRes));
    const int y = static_cast<int>(std::floor((sy + range * std::sin(a)) / kRes));
    if (seen.insert({x, y}).second) out.push_back({x, y});
  }
  return out;
}

TEST(EstimateShape, CylinderSeenFromOneSide) {
  ObjectOptions o;
  // 0.4 m cylinder 2 m away, 0.5 degree beams: a half circle of hit cells.
  const auto cells = arcCells(0.0, 0.0, 2.03, 1.01, 0.4, 0.5 * M_PI / 180);
  ASSERT_GE(cells.size(), 6u);
  const ShapeEstimate s = estimateShape(cells, kRes, o);
  EXPECT_TRUE(s.circle);
  EXPECT_NEAR(s.size, 0.4, 0.05);
  EXPECT_NEAR(s.cx, 2.03, 0.06);
  EXPECT_NEAR(s.cy, 1.01, 0.06);
  // The box is the object's, not the arc's: it reaches behind the visible side.
  EXPECT_NEAR(s.x_max - s.x_min, s.size, 1e-9);
}

TEST(EstimateShape, CylinderSeenFromAfarWithFewBeams) {
  ObjectOptions o;
  // 1 degree beams 4 m away: a handful of cells, the width decides.
  const auto cells = arcCells(0.0, 0.0, 4.0, 0.0, 0.3, M_PI / 180);
  const ShapeEstimate s = estimateShape(cells, kRes, o);
  EXPECT_NEAR(s.size, 0.3, 0.08);
}

TEST(EstimateShape, StraightLineIsNotACircle) {
  ObjectOptions o;
  std::vector<CellXY> line;
  for (int x = 0; x < 12; ++x) line.push_back({x, 3});
  const ShapeEstimate s = estimateShape(line, kRes, o);
  EXPECT_FALSE(s.circle);
  EXPECT_NEAR(s.size, 0.6, 1e-9);
}

// The hit points a laser at (sx, sy) with `step` rad between beams puts on a cylinder, each
// range off by up to +-`noise` m (a fixed pseudo-random sequence).
void arcPoints(double sx, double sy, double cx, double cy, double diameter, double step,
               double noise, std::vector<double>& xs, std::vector<double>& ys) {
  const double r = diameter / 2, d = std::hypot(cx - sx, cy - sy);
  const double bearing = std::atan2(cy - sy, cx - sx), half = std::asin(r / d);
  std::uint32_t seed = 777;
  for (double a = bearing - half; a <= bearing + half; a += step) {
    const double along = d * std::cos(a - bearing), perp = d * std::sin(a - bearing);
    if (std::abs(perp) > r) continue;
    seed = seed * 1664525u + 1013904223u;
    const double jitter = noise * (static_cast<int>((seed >> 8) % 201) - 100) / 100.0;
    const double range = along - std::sqrt(r * r - perp * perp) + jitter;
    xs.push_back(sx + range * std::cos(a));
    ys.push_back(sy + range * std::sin(a));
  }
}

TEST(EstimatePointShape, HalfACylinderGivesItsSizeToTwoCentimetres) {
  ObjectOptions o;
  // 0.3 m cylinder 1.5 m away, 1 degree beams, +-1 cm of range noise: the cells would say
  // anything from 0.25 to 0.4 m; the points give the circle.
  std::vector<double> xs, ys;
  arcPoints(0.0, 0.0, 1.5, 0.3, 0.3, M_PI / 180, 0.01, xs, ys);
  ASSERT_GE(xs.size(), 6u);
  ShapeEstimate s;
  ASSERT_TRUE(estimatePointShape(xs, ys, 1.5 * M_PI / 180, 0.0, 0.0, o, s));
  EXPECT_TRUE(s.circle);
  EXPECT_NEAR(s.size, 0.3, 0.02);
  EXPECT_NEAR(s.cx, 1.5, 0.02);
  EXPECT_NEAR(s.cy, 0.3, 0.02);
}

TEST(EstimatePointShape, ArcsFromTwoViewpointsTellSizesTenCentimetresApart) {
  ObjectOptions o;
  // Two cylinders of 0.4 and 0.5 m, each seen as the robot drives past (three viewpoints):
  // the estimates fall on the right side of the 0.45 m midpoint with room to spare.
  for (const double diameter : {0.4, 0.5}) {
    std::vector<double> xs, ys;
    for (const double sx : {-1.0, 0.0, 1.0}) {
      arcPoints(sx, 0.0, 0.0, 1.2, diameter, 0.5 * M_PI / 180, 0.01, xs, ys);
    }
    ShapeEstimate s;
    ASSERT_TRUE(estimatePointShape(xs, ys, 0.01, 0.0, 0.0, o, s));
    EXPECT_TRUE(s.circle);
    EXPECT_NEAR(s.size, diameter, 0.02) << diameter;
  }
}

TEST(EstimatePointShape, FewBeamsOnASmallObjectGiveWidthPlusTheBeamGap) {
  ObjectOptions o;
  // A 0.1 m pole 3 m away with 1 degree beams (5 cm apart there): 2 beams hit it, 2 cm of arc.
  std::vector<double> xs, ys;
  arcPoints(0.0, 0.0, 3.0, 0.0, 0.1, M_PI / 180, 0.0, xs, ys);
  ASSERT_EQ(xs.size(), 2u);
  // Repeated scans from the same place add nothing new but fill the minimum count.
  for (int k = 0; k < 3; ++k) {
    xs.push_back(xs[0]), ys.push_back(ys[0]);
    xs.push_back(xs[1]), ys.push_back(ys[1]);
  }
  const double gap = 3.0 * M_PI / 180;
  ShapeEstimate s;
  ASSERT_TRUE(estimatePointShape(xs, ys, gap, 0.0, 0.0, o, s));
  EXPECT_FALSE(s.circle);
  EXPECT_NEAR(s.size, std::hypot(xs[0] - xs[1], ys[0] - ys[1]) + gap, 1e-9);
  EXPECT_NEAR(s.size, 0.1, 0.03);
  // Fewer points than min_fit_cells: no estimate, the cells decide.
  std::vector<double> two_x(xs.begin(), xs.begin() + 2), two_y(ys.begin(), ys.begin() + 2);
  EXPECT_FALSE(estimatePointShape(two_x, two_y, gap, 0.0, 0.0, o, s));
}

TEST(EstimatePointShape, AWallIsNotACircleAndAHollowIsNotACylinder) {
  ObjectOptions o;
  std::vector<double> xs, ys;
  for (int i = 0; i < 20; ++i) xs.push_back(1.0), ys.push_back(-0.2 + 0.02 * i);
  ShapeEstimate s;
  ASSERT_TRUE(estimatePointShape(xs, ys, 0.01, 0.0, 0.0, o, s));
  EXPECT_FALSE(s.circle);
  EXPECT_NEAR(s.size, 0.39, 1e-9);
  // The inside of a ring, seen from its centre: a circle fits, but it curves the wrong way.
  xs.clear(), ys.clear();
  for (int i = 0; i < 20; ++i) {
    xs.push_back(0.3 * std::cos(-0.5 + 0.05 * i)), ys.push_back(0.3 * std::sin(-0.5 + 0.05 * i));
  }
  ASSERT_TRUE(estimatePointShape(xs, ys, 0.01, 0.0, 0.0, o, s));
  EXPECT_FALSE(s.circle);
}

TEST(FitCircle, ExactPointsGiveTheCircle) {
  std::vector<double> xs, ys;
  for (int i = 0; i < 8; ++i) {
    const double a = 0.2 * i;  // a 80 degree arc
    xs.push_back(1.0 + 0.25 * std::cos(a));
    ys.push_back(-2.0 + 0.25 * std::sin(a));
  }
  Circle c{};
  ASSERT_TRUE(fitCircle(xs, ys, c));
  EXPECT_NEAR(c.cx, 1.0, 1e-6);
  EXPECT_NEAR(c.cy, -2.0, 1e-6);
  EXPECT_NEAR(c.r, 0.25, 1e-6);
}

}  // namespace
}  // namespace dynamap
