// traceRay / rayCells: which cells a beam crosses.

#include "dynamap/mapping/ray_cast.h"

#include <gtest/gtest.h>

#include <cstdlib>

namespace dynamap {
namespace {

using Cells = std::vector<std::pair<int, int>>;

TEST(RayCast, AlongAnAxisVisitsEveryCellBeforeTheEnd) {
  EXPECT_EQ(rayCells(2, 3, 6, 3), (Cells{{2, 3}, {3, 3}, {4, 3}, {5, 3}}));
  EXPECT_EQ(rayCells(2, 3, 2, 0), (Cells{{2, 3}, {2, 2}, {2, 1}}));
}

TEST(RayCast, DiagonalSteps) {
  EXPECT_EQ(rayCells(0, 0, 3, 3), (Cells{{0, 0}, {1, 1}, {2, 2}}));
  EXPECT_EQ(rayCells(3, 3, 0, 0), (Cells{{3, 3}, {2, 2}, {1, 1}}));
}

TEST(RayCast, ShallowSlopeFollowsTheFloorOfTheExactLine) {
  // Cell i is floor(start + i * d / n) on each axis: 0, 0.5, 1, 1.5 -> 0, 0, 1, 1.
  EXPECT_EQ(rayCells(0, 0, 4, 2), (Cells{{0, 0}, {1, 0}, {2, 1}, {3, 1}}));
  EXPECT_EQ(rayCells(4, 2, 0, 0), (Cells{{4, 2}, {3, 1}, {2, 1}, {1, 0}}));
}

TEST(RayCast, SameCellIsNoRay) {
  EXPECT_TRUE(rayCells(5, 5, 5, 5).empty());
}

TEST(RayCast, LongRaysStayOnTheLineAndStopBeforeTheEnd) {
  // 9 fractional bits would drift by up to n / 1024 cells; this ray is 100000 cells long.
  const int n = 100000;
  const Cells c = rayCells(0, 0, n, 33333);
  ASSERT_EQ(c.size(), static_cast<std::size_t>(n));
  for (int i = 0; i < n; i += 997) {
    EXPECT_EQ(c[i].first, i);
    EXPECT_EQ(c[i].second, static_cast<int>((static_cast<long long>(i) * 33333) / n)) << i;
  }
  EXPECT_EQ(c.back(), (std::pair<int, int>{n - 1, 33332}));
}

TEST(RayCast, EveryStepMovesOneCellAlongTheMajorAxis) {
  for (int dy = -7; dy <= 7; ++dy) {
    const Cells c = rayCells(10, 10, 17, 10 + dy);
    ASSERT_EQ(c.size(), 7u);
    for (std::size_t k = 1; k < c.size(); ++k) {
      EXPECT_EQ(c[k].first - c[k - 1].first, 1);
      EXPECT_LE(std::abs(c[k].second - c[k - 1].second), 1);
    }
  }
}

}  // namespace
}  // namespace dynamap

namespace dynamap {
namespace {

TEST(RayCast, IndexStepperVisitsTraceRaysCellsInOrder) {
  // Every direction and length up to 40 cells from a start inside a 100-cell-wide grid, and a
  // few long rays: the stepped index must be x + y * width of traceRay's cell at every step.
  constexpr std::size_t kWidth = 100;
  std::size_t rays = 0;
  auto check = [&](int x0, int y0, int x1, int y1) {
    std::vector<std::size_t> got;
    traceRayIndex(x0, y0, x1, y1, kWidth, [&](std::size_t i) { got.push_back(i); });
    std::vector<std::size_t> want;
    for (const auto& [cx, cy] : rayCells(x0, y0, x1, y1)) want.push_back(cx + cy * kWidth);
    ASSERT_EQ(got, want) << "(" << x0 << "," << y0 << ") -> (" << x1 << "," << y1 << ")";
    ++rays;
  };
  for (int dx = -40; dx <= 40; ++dx) {
    for (int dy = -40; dy <= 40; ++dy) check(50, 50, 50 + dx, 50 + dy);
  }
  check(0, 0, 99, 37);
  check(99, 99, 1, 0);
  check(3, 97, 98, 2);
  EXPECT_EQ(rays, 81u * 81u + 3u);
}

}  // namespace
}  // namespace dynamap
