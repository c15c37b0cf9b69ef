// The cell level of the evaluation (docs/evaluation.md): the truth rasterised onto a hand-made
// 5 x 5 map, SA/DA and precision/recall on it.

#include <gtest/gtest.h>

#include <cmath>

#include "dynamap/evaluation/evaluation.h"

namespace dynamap {
namespace {

using sim::BodyKind;

// A 5 x 5 grid of 1 m cells on [0, 5) x [0, 5).
GridGeometry fiveByFive() {
  return {0.0, 0.0, 1.0, 5, 5};
}

CellMask maskOf(const char* rows[5]) {  // rows[0] is the top (iy = 4)
  CellMask m(25, 0);
  for (int r = 0; r < 5; ++r) {
    for (int ix = 0; ix < 5; ++ix) m[(4 - r) * 5 + ix] = rows[r][ix] == '#';
  }
  return m;
}

TEST(EvalCells, SegmentTouchesTheCellsOnBothSidesOfABorder) {
  const GridGeometry g = fiveByFive();
  CellMask m(g.cells(), 0);
  rasteriseSegment({{0.5, 2.0}, {2.5, 2.0}}, g, m);  // on the border between rows 1 and 2
  const char* expected[5] = {".....", ".....", "###..", "###..", "....."};
  EXPECT_EQ(m, maskOf(expected));
}

TEST(EvalCells, DiscCoversTheCellsItOverlaps) {
  const GridGeometry g = fiveByFive();
  CellMask m(g.cells(), 0);
  rasteriseDisc({2.5, 2.5}, 0.6, g, m);
  const char* expected[5] = {".....", "..#..", ".###.", "..#..", "....."};
  EXPECT_EQ(m, maskOf(expected));
}

TEST(EvalCells, WallImagePixelsCoverTheCellsTheyOverlap) {
  const GridGeometry g = fiveByFive();
  sim::WallGrid w;
  w.resolution = 0.5;
  w.origin = {1.0, 1.0};
  w.width = 2;
  w.height = 1;
  w.wall = {0, 1};  // the pixel [1.5, 2) x [1, 1.5): inside cell (1, 1) only
  CellMask m(g.cells(), 0);
  rasteriseWallGrid(w, g, m);
  CellMask expected(g.cells(), 0);
  expected[g.index(1, 1)] = 1;
  EXPECT_EQ(m, expected);
}

TEST(EvalCells, SaDaOnAHandMadeMap) {
  const GridGeometry g = fiveByFive();
  CellTruth truth;
  const char* walls[5] = {"#####", ".....", ".....", ".....", "....."};
  const char* dyn[5] = {".....", ".##..", ".....", "...#.", "....."};
  truth.static_cells = maskOf(walls);
  truth.dynamic_cells = maskOf(dyn);
  // S holds the wall at x = 1 and one row down at x = 0: x = 0, 1, 2 are kept (x = 0 and 2 by
  // a 4-neighbour), x = 3 is lost; one dynamic cell is still occupied; the top-right cell was
  // never observed.
  const char* occ[5] = {".#...", "#....", ".....", "...#.", "....."};
  const char* unseen[5] = {"....#", ".....", ".....", ".....", "....."};
  const CellMask occupied = maskOf(occ), not_observed = maskOf(unseen);
  std::vector<float> s_occ(g.cells());
  CellMask observed(g.cells());
  for (std::size_t i = 0; i < g.cells(); ++i) {
    s_occ[i] = occupied[i] ? 0.9f : 0.2f;
    observed[i] = !not_observed[i];
  }
  const CellScores c = scoreStaticMap(s_occ, truth, observed, g);
  EXPECT_EQ(c.static_cells, 4u);  // the unobserved wall cell does not count
  EXPECT_EQ(c.static_kept, 3u);
  EXPECT_EQ(c.dynamic_cells, 3u);
  EXPECT_EQ(c.dynamic_clear, 2u);
  EXPECT_DOUBLE_EQ(c.sa, 75.0);
  EXPECT_NEAR(c.da, 200.0 / 3, 1e-9);
  EXPECT_NEAR(c.aa, std::sqrt(75.0 * 200.0 / 3), 1e-9);
  EXPECT_NEAR(c.ha, 2 * 75.0 * (200.0 / 3) / (75.0 + 200.0 / 3), 1e-9);
}

TEST(EvalCells, PrecisionRecallWithOneCellTolerance) {
  const GridGeometry g = fiveByFive();
  const char* t[5] = {"#####", ".....", ".....", ".....", "....."};
  const char* p[5] = {"###..", "#....", ".....", "..#..", "....."};
  const CellMask observed(g.cells(), 1);
  const PrecisionRecall pr = scoreOccupied(maskOf(p), maskOf(t), observed, g);
  EXPECT_EQ(pr.predicted, 5u);
  EXPECT_EQ(pr.predicted_right, 4u);  // the stray one in the middle is wrong
  EXPECT_EQ(pr.truth, 5u);
  EXPECT_EQ(pr.truth_found, 4u);  // x = 3 by its neighbour at x = 2; x = 4 missed
  EXPECT_DOUBLE_EQ(pr.precision, 80.0);
  EXPECT_DOUBLE_EQ(pr.recall, 80.0);
}

TEST(EvalCells, TruthKeepsObjectsOutOfDynamicUntilTheirFirstMove) {
  const GridGeometry g = fiveByFive();
  sim::StaticWorld world;
  world.segments.push_back({{0.0, 4.5}, {5.0, 4.5}});  // the top row
  std::vector<TruthRow> rows = {
      {0, 0, BodyKind::Object, 1, 0.5, 0.5, 0.4, 5},  // before its move: not dynamic
      {1, 1, BodyKind::Object, 1, 2.5, 0.5, 0.4, 5},  // after: dynamic
      {1, 1, BodyKind::Object, 2, 4.5, 0.5, 0.4, 5},  // never moves: neither
      {0, 0, BodyKind::Person, 1, 2.5, 4.5, 0.4, 5},  // on the wall: static wins
      {1, 1, BodyKind::Person, 1, 2.5, 2.5, 0.4, 5},  // a person: dynamic
  };
  const std::vector<TruthMove> moves = {{1, 1, 0.5, 1.0, {0.5, 0.5}, {2.5, 0.5}}};
  const CellTruth t = cellTruth(world, rows, moves, g);
  const char* st[5] = {"#####", ".....", ".....", ".....", "....."};
  const char* dy[5] = {".....", ".....", "..#..", ".....", "..#.."};
  const char* end[5] = {"#####", ".....", "..#..", ".....", "..#.#"};
  EXPECT_EQ(t.static_cells, maskOf(st));
  EXPECT_EQ(t.dynamic_cells, maskOf(dy));
  EXPECT_EQ(t.world_at_end, maskOf(end));
}

TEST(EvalCells, ObservedMeansOffThePriorInAnyLayer) {
  const std::vector<float> a = {0.5f, 0.7f, 0.5f}, b = {0.5f, 0.5f, 0.3f};
  EXPECT_EQ(observedCells({&a, &b}), (CellMask{0, 1, 1}));
  EXPECT_TRUE(std::isnan(harmonicMean(std::nan(""), 50)));
  EXPECT_DOUBLE_EQ(harmonicMean(0, 0), 0.0);
}

}  // namespace
}  // namespace dynamap
