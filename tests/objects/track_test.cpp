// Track: its states, its shape from cells and hit points, and the filters a tentative passes.

#include "dynamap/objects/track.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace dynamap {
namespace {

constexpr double kRes = 0.05;

TEST(Track, EachStateSaysWhichObjectItIsReportedAs) {
  Track tr;
  EXPECT_NE(tr.tentative(), nullptr);  // a new track is tentative
  EXPECT_EQ(tr.objectId(), 0);
  tr.state = Confirmed{7, 1.0, 2.0, 12, std::nullopt};
  EXPECT_EQ(tr.objectId(), 7);
  EXPECT_EQ(tr.tentative(), nullptr);
  EXPECT_FALSE(tr.isStale());
  EXPECT_EQ(tr.ownShape(), nullptr);  // its object's row holds its shape
  Stale st;
  st.object_id = 7;
  st.shape.size = 0.4;
  tr.state = st;
  EXPECT_EQ(tr.objectId(), 0);  // a stale place is never reported
  EXPECT_TRUE(tr.isStale());
  EXPECT_EQ(tr.stale()->object_id, 7);
  ASSERT_NE(tr.ownShape(), nullptr);
  EXPECT_EQ(tr.ownShape()->size, 0.4);
  tr.state = Tentative{};
  ASSERT_NE(tr.ownShape(), nullptr);
  EXPECT_EQ(tr.ownShape()->size, 0.0);  // a reopened place starts a shape of its own
}

// A track of the cells a 0.3 m cylinder at (1, 0) shows a sensor at the origin, with the hit
// points of 1 degree beams on it.
Track cylinderTrack() {
  Track tr;
  const double r = 0.15, d = 1.0, half = std::asin(r / d);
  for (double a = -half; a <= half; a += M_PI / 180) {
    const double along = d * std::cos(a), perp = d * std::sin(a);
    const double range = along - std::sqrt(r * r - perp * perp);
    const double x = range * std::cos(a), y = range * std::sin(a);
    const CellKey cell =
        cellKey(static_cast<int>(std::floor(x / kRes)), static_cast<int>(std::floor(y / kRes)));
    tr.cells.push_back(cell);
    const CellKey bin =
        cellKey(static_cast<int>(std::floor(x / 0.01)), static_cast<int>(std::floor(y / 0.01)));
    tr.points[bin] = {x, y, range * M_PI / 180, cell};
  }
  std::sort(tr.cells.begin(), tr.cells.end());
  tr.cells.erase(std::unique(tr.cells.begin(), tr.cells.end()), tr.cells.end());
  return tr;
}

TEST(MeasureShape, HitPointsGiveTheSizeTheCellsKeepTheirCount) {
  const ObjectOptions o;
  Track tr = cylinderTrack();
  ASSERT_GE(tr.points.size(), 6u);
  const ShapeEstimate s = measureShape(tr, kRes, 0.0, 0.0, o);
  EXPECT_TRUE(s.circle);
  EXPECT_NEAR(s.size, 0.3, 0.005);
  EXPECT_NEAR(s.cx, 1.0, 0.005);
  EXPECT_EQ(s.cells, tr.cells.size());  // the filters count cells, not points
}

TEST(MeasureShape, PointsWhoseCellLeftTheTrackAreDropped) {
  const ObjectOptions o;
  Track tr = cylinderTrack();
  const std::size_t before = tr.points.size();
  tr.cells.erase(tr.cells.begin());  // one cell faded
  measureShape(tr, kRes, 0.0, 0.0, o);
  EXPECT_LT(tr.points.size(), before);
  for (const auto& kv : tr.points) {
    EXPECT_TRUE(std::binary_search(tr.cells.begin(), tr.cells.end(), kv.second.cell));
  }
}

TEST(MeasureShape, WithoutEnoughPointsTheCellsDecideAndAWallLosesItsPoints) {
  ObjectOptions o;
  Track tr = cylinderTrack();
  tr.points.clear();
  std::vector<CellXY> xy;
  for (const CellKey k : tr.cells) xy.push_back(cellOf(k));
  const ShapeEstimate cells_only = estimateShape(xy, kRes, o);
  EXPECT_DOUBLE_EQ(measureShape(tr, kRes, 0.0, 0.0, o).size, cells_only.size);
  // Cells longer than max_size: a wall seen off by localisation keeps no points.
  Track wall = cylinderTrack();
  o.max_size = 0.2;
  o.min_size = 0.1;
  measureShape(wall, kRes, 0.0, 0.0, o);
  EXPECT_TRUE(wall.points.empty());
}

TEST(PassesFilters, CellsSizeAndAThinRowAlongAWall) {
  const ObjectOptions o;  // min_cells 2, sizes [0.06, 1.2], thin_width 0.02, thin_length 0.15
  Track tr;
  tr.cells = {cellKey(0, 0), cellKey(1, 0), cellKey(2, 0), cellKey(3, 0)};
  ShapeEstimate s;
  s.size = 0.3;
  s.thickness = 0.0;
  s.length = 0.2;
  EXPECT_TRUE(passesFilters(tr, s, o));  // a row, but not next to a wall
  tr.hugs_wall = true;
  EXPECT_FALSE(passesFilters(tr, s, o));  // a row along a wall: the wall itself
  s.thickness = 0.03;
  EXPECT_TRUE(passesFilters(tr, s, o));  // thick enough to be something standing there
  s.size = 0.05;
  EXPECT_FALSE(passesFilters(tr, s, o));  // below min_size
  s.size = 1.3;
  EXPECT_FALSE(passesFilters(tr, s, o));  // above max_size
  s.size = 0.3;
  tr.cells.resize(1);
  EXPECT_FALSE(passesFilters(tr, s, o));  // fewer than min_cells
  // One cell, and one beside it above support_threshold (a far object's arc): enough.
  EXPECT_TRUE(passesFilters(tr, s, o, 1));
}

}  // namespace
}  // namespace dynamap
