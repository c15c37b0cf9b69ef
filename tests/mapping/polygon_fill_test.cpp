// fillPolygon: cells whose centres are inside, each once.

#include "dynamap/mapping/polygon_fill.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

namespace dynamap {
namespace {

using CellSet = std::set<std::pair<int, int>>;

CellSet fill(const std::vector<GridPoint>& poly, int sx = 20, int sy = 20) {
  PolygonFillScratch scratch;
  CellSet cells;
  std::size_t visits = 0;
  fillPolygon(poly, sx, sy, scratch, [&](int cy, int b, int e) {
    for (int cx = b; cx < e; ++cx) {
      cells.insert({cx, cy});
      ++visits;
    }
  });
  EXPECT_EQ(visits, cells.size()) << "a cell was visited twice";
  return cells;
}

// Brute force: the even-odd rule on cell centres.
CellSet bruteForce(const std::vector<GridPoint>& poly, int sx = 20, int sy = 20) {
  CellSet cells;
  for (int cy = 0; cy < sy; ++cy) {
    for (int cx = 0; cx < sx; ++cx) {
      const double u = cx + 0.5, v = cy + 0.5;
      bool inside = false;
      for (std::size_t k = 0, j = poly.size() - 1; k < poly.size(); j = k++) {
        const GridPoint& a = poly[k];
        const GridPoint& b = poly[j];
        if ((a.v <= v) != (b.v <= v) && u < a.u + (v - a.v) * (b.u - a.u) / (b.v - a.v)) {
          inside = !inside;
        }
      }
      if (inside) cells.insert({cx, cy});
    }
  }
  return cells;
}

TEST(PolygonFill, AxisAlignedSquareCoversExactlyItsCells) {
  const CellSet c = fill({{2, 3}, {6, 3}, {6, 5}, {2, 5}});
  CellSet expected;
  for (int y = 3; y < 5; ++y)
    for (int x = 2; x < 6; ++x) expected.insert({x, y});
  EXPECT_EQ(c, expected);
}

TEST(PolygonFill, TriangleMatchesTheCentreRule) {
  const std::vector<GridPoint> tri{{1.2, 1.1}, {15.7, 4.3}, {6.1, 17.9}};
  EXPECT_EQ(fill(tri), bruteForce(tri));
}

TEST(PolygonFill, ConcaveStarOfWedgesMatchesTheCentreRule) {
  // A scan-like star around (10, 10): radii alternate short and long.
  std::vector<GridPoint> star{{10, 10}};
  for (int k = 0; k <= 24; ++k) {
    const double a = -1.5 + 3.0 * k / 24, r = (k % 3 == 0) ? 3.2 : 8.7;
    star.push_back({10 + r * std::cos(a), 10 + r * std::sin(a)});
  }
  EXPECT_EQ(fill(star), bruteForce(star));
}

TEST(PolygonFill, ClipsToTheGrid) {
  const std::vector<GridPoint> big{{-5, -5}, {30, -5}, {30, 30}, {-5, 30}};
  EXPECT_EQ(fill(big, 7, 4).size(), 28u);
}

TEST(PolygonFill, DegeneratePolygonsFillNothing) {
  EXPECT_TRUE(fill({{1, 1}, {5, 5}}).empty());
  EXPECT_TRUE(fill({{1, 1}, {5, 5}, {9, 9}}).empty());  // collinear
}

}  // namespace
}  // namespace dynamap
