// Cells by global key and clusters of them.

#include "dynamap/objects/clustering.h"

#include <gtest/gtest.h>

#include <set>

namespace dynamap {
namespace {

constexpr double kRes = 0.05;

TEST(CellKey, RoundTripsNegativeAndLargeCoordinates) {
  for (const CellXY c : {CellXY{0, 0}, CellXY{-1, 1}, CellXY{1, -1}, CellXY{-70000, 123456},
                         CellXY{2147483647, -2147483647 - 1}}) {
    const CellXY back = cellOf(cellKey(c.x, c.y));
    EXPECT_EQ(back.x, c.x);
    EXPECT_EQ(back.y, c.y);
  }
  EXPECT_NE(cellKey(-1, 0), cellKey(0, -1));
  EXPECT_LT(cellKey(0, 5), cellKey(1, 0));  // ordered by x first: deterministic cluster order
}

TEST(JoinOffsets, TheCellsWithinTheDistanceBarTheCellItself) {
  EXPECT_EQ(joinOffsets(1.0).size(), 4u);   // the 4-neighbours
  EXPECT_EQ(joinOffsets(1.5).size(), 8u);   // and the diagonals (1.41)
  EXPECT_EQ(joinOffsets(3.0).size(), 28u);  // 29 lattice points within 3 of a cell, less itself
  EXPECT_TRUE(joinOffsets(0.5).empty());
}

TEST(GrowCluster, StopsAtUnusableAndVisitedCellsAndSortsByKey) {
  // A row of 6 cells; cell 3 is unusable, so 4-neighbour growth from 0 reaches 0..2 only.
  std::unordered_set<CellKey> visited;
  const auto usable = [](CellKey k) {
    const CellXY c = cellOf(k);
    return c.y == 0 && c.x >= 0 && c.x < 6 && c.x != 3;
  };
  const auto offsets = joinOffsets(1.0);
  const auto a = growCluster(cellKey(2, 0), offsets, usable, visited);
  ASSERT_EQ(a.size(), 3u);
  EXPECT_EQ(a[0].x, 0);
  EXPECT_EQ(a[2].x, 2);
  EXPECT_EQ(visited.size(), 3u);
  // Growing again into the visited cells finds only the seed.
  EXPECT_EQ(growCluster(cellKey(4, 0), offsets, usable, visited).size(), 2u);
  EXPECT_EQ(growCluster(cellKey(-1, 0), offsets, usable, visited).size(), 1u);
}

// A square blob of n x n cells with its lower-left cell at (x0, y0).
std::vector<CellXY> blob(int x0, int y0, int n) {
  std::vector<CellXY> out;
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) out.push_back({x0 + x, y0 + y});
  }
  return out;
}

TEST(ClusterCells, BlobsCloserThanTheJoinDistanceMerge) {
  const double join_cells = 0.15 / kRes;  // 3 cells
  auto cells = blob(0, 0, 3);
  const auto b = blob(5, 0, 3);  // 3 cells (0.15 m) from the first: within reach
  cells.insert(cells.end(), b.begin(), b.end());
  const auto clusters = clusterCells(cells, join_cells);
  ASSERT_EQ(clusters.size(), 1u);
  EXPECT_EQ(clusters[0].size(), 18u);
}

TEST(ClusterCells, BlobsFartherThanTheJoinDistanceStayApart) {
  const double join_cells = 0.15 / kRes;
  auto cells = blob(0, 0, 3);
  const auto b = blob(6, 0, 3);  // 4 cells (0.2 m) apart
  cells.insert(cells.end(), b.begin(), b.end());
  const auto diagonal = blob(-5, -5, 2);  // (-4,-4) to (0,0): 5.7 cells
  cells.insert(cells.end(), diagonal.begin(), diagonal.end());
  const auto clusters = clusterCells(cells, join_cells);
  ASSERT_EQ(clusters.size(), 3u);
  std::multiset<std::size_t> sizes;
  for (const auto& c : clusters) sizes.insert(c.size());
  EXPECT_EQ(sizes, (std::multiset<std::size_t>{4, 9, 9}));
}

}  // namespace
}  // namespace dynamap
