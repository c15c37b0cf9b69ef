// ObjectTracker: clustering, size from a partial arc, identity by size, and the events of a
// tracker fed by a real DynamicGridMap with synthetic scans.

#include "dynamap/objects/object_tracker.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "../test_util.h"
#include "dynamap/base/ini.h"
#include "dynamap/mapping/dynamic_grid_map.h"

namespace dynamap {
namespace {

constexpr double kRes = 0.05;

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

ShapeEstimate detection(double x, double y, double size) {
  ShapeEstimate s;
  s.cx = x;
  s.cy = y;
  s.size = size;
  return s;
}

TEST(ChooseIdentity, TwoSimilarSizesTheAbsentOneIsTheOneThatMoved) {
  ObjectOptions o;
  // A (0.30) was seen gone; B (0.32) is seen where it was: the 0.31 detection is A.
  const std::vector<IdentityCandidate> c{
      {0.0, 0.0, 0.32, false, 0.0, PlaceView::SeenOccupied},
      {5.0, 5.0, 0.30, true, 90.0, PlaceView::NotInView},
  };
  EXPECT_EQ(chooseIdentity(detection(2, 2, 0.31), 100.0, c, o), 1);
  // Same sizes, roles swapped.
  const std::vector<IdentityCandidate> d{
      {0.0, 0.0, 0.32, true, 90.0, PlaceView::NotInView},
      {5.0, 5.0, 0.30, false, 0.0, PlaceView::SeenOccupied},
  };
  EXPECT_EQ(chooseIdentity(detection(2, 2, 0.31), 100.0, d, o), 0);
}

TEST(ChooseIdentity, TwoSimilarSizesBothAbsentTheRecentAndNearOneWins) {
  ObjectOptions o;
  const std::vector<IdentityCandidate> c{
      {-6.0, 0.0, 0.30, true, 10.0, PlaceView::NotInView},  // gone long ago, far
      {2.5, 2.0, 0.31, true, 98.0, PlaceView::NotInView},   // just gone, near
  };
  EXPECT_EQ(chooseIdentity(detection(2, 2, 0.30), 100.0, c, o), 1);
}

TEST(ChooseIdentity, PresentObjectSeenInPlaceOrOtherSizeMeansNew) {
  ObjectOptions o;
  const std::vector<IdentityCandidate> c{
      {0.0, 0.0, 0.30, false, 0.0, PlaceView::SeenOccupied},
      {3.0, 0.0, 0.60, true, 10.0, PlaceView::NotInView},
  };
  EXPECT_EQ(chooseIdentity(detection(2, 2, 0.30), 100.0, c, o), -1);
}

TEST(ChooseIdentity, PresentObjectOutOfSightMayHaveMoved) {
  ObjectOptions o;
  const std::vector<IdentityCandidate> c{
      {0.0, 0.0, 0.30, false, 0.0, PlaceView::NotInView},
  };
  EXPECT_EQ(chooseIdentity(detection(2, 2, 0.30), 100.0, c, o), 0);
}

struct Cylinder {
  double x, y, diameter;
};

// A scan from `pose` in the room [-3, 3]^2 with cylinders in it.
mrpt::obs::CObservation2DRangeScan::Ptr roomScan(const mrpt::poses::CPose2D& pose,
                                                 const std::vector<Cylinder>& cylinders) {
  const int n = 361;
  const double aperture = M_PI;
  auto ranges = test::roomRanges(-3, 3, -3, 3, pose, n, aperture);
  for (const Cylinder& c : cylinders) {
    const double r = c.diameter / 2, cx = c.x, cy = c.y;
    for (int i = 0; i < n; ++i) {
      const double a = pose.phi() - aperture / 2 + aperture * i / (n - 1);
      const double dx = cx - pose.x(), dy = cy - pose.y();
      const double along = dx * std::cos(a) + dy * std::sin(a);
      const double perp = -dx * std::sin(a) + dy * std::cos(a);
      if (along <= 0 || std::abs(perp) > r) continue;
      const double hit = along - std::sqrt(r * r - perp * perp);
      if (hit < ranges[i]) ranges[i] = static_cast<float>(hit);
    }
  }
  return test::makeScan(ranges, aperture);
}

struct TrackerRun {
  DynamicGridMap map;
  ObjectTracker tracker;
  std::size_t index = 0;
  void steps(int n, const mrpt::poses::CPose2D& pose, const std::vector<Cylinder>& cylinders) {
    for (int i = 0; i < n; ++i) step(pose, cylinders);
  }
  void step(const mrpt::poses::CPose2D& pose, const std::vector<Cylinder>& cylinders) {
    const auto scan = roomScan(pose, cylinders);
    map.insertObservation(*scan, mrpt::poses::CPose3D(pose));
    tracker.update(map, makeScanView(*scan, pose, 15.0), 0.2 * index, index);
    ++index;
  }
  std::vector<ObjectEvent> events() const {
    std::vector<ObjectEvent> e;
    for (const auto& r : tracker.events()) e.push_back(r.event);
    return e;
  }
};

TEST(ObjectTracker, NewDisappearedReappearedMoved) {
  TrackerRun run;
  const mrpt::poses::CPose2D pose(-2.0, 0.0, 0.0);
  run.steps(10, pose, {});  // the empty room
  EXPECT_TRUE(run.tracker.objects().empty());
  run.steps(15, pose, {{1.0, 0.5, 0.4}});
  ASSERT_EQ(run.tracker.objects().size(), 1u);
  const TrackedObject& o = run.tracker.objects()[0];
  EXPECT_EQ(o.state, ObjectState::Present);
  EXPECT_NEAR(o.shape.size, 0.4, 0.05);
  EXPECT_NEAR(o.shape.cx, 1.0, 0.05);
  EXPECT_NEAR(o.shape.cy, 0.5, 0.05);
  run.steps(10, pose, {});  // taken away
  EXPECT_EQ(run.tracker.objects()[0].state, ObjectState::Absent);
  run.steps(15, pose, {{1.0, 0.5, 0.4}});  // back
  run.steps(10, pose, {});
  run.steps(15, pose, {{0.5, -1.5, 0.4}});  // elsewhere
  ASSERT_EQ(run.tracker.objects().size(), 1u);
  EXPECT_EQ(run.tracker.objects()[0].n_moves, 1);
  EXPECT_NEAR(run.tracker.objects()[0].shape.cx, 0.5, 0.05);
  EXPECT_NEAR(run.tracker.objects()[0].shape.cy, -1.5, 0.05);
  EXPECT_EQ(run.events(), (std::vector<ObjectEvent>{ObjectEvent::New, ObjectEvent::Disappeared,
                                                    ObjectEvent::Reappeared,
                                                    ObjectEvent::Disappeared, ObjectEvent::Moved}));
}

TEST(ObjectTracker, TwoSimilarSizesKeepTheirIds) {
  TrackerRun run;
  const mrpt::poses::CPose2D pose(-2.5, 0.0, 0.0);
  run.steps(10, pose, {});
  // Two objects of 0.30 and 0.35 m: sizes closer than the size tolerance.
  run.steps(15, pose, {{0.5, 1.0, 0.30}, {0.5, -1.0, 0.35}});
  ASSERT_EQ(run.tracker.objects().size(), 2u);
  const int id_30 = run.tracker.objects()[0].shape.cy > 0 ? 1 : 2;
  const int id_35 = 3 - id_30;
  // The 0.35 m one leaves (its place seen free), then turns up elsewhere: by size alone it
  // could be either; the one seen still in place is not it.
  run.steps(10, pose, {{0.5, 1.0, 0.30}});
  run.steps(15, pose, {{0.5, 1.0, 0.30}, {1.5, -0.2, 0.35}});
  ASSERT_EQ(run.tracker.objects().size(), 2u);
  const TrackedObject& moved = run.tracker.objects()[id_35 - 1];
  const TrackedObject& stayed = run.tracker.objects()[id_30 - 1];
  EXPECT_EQ(moved.state, ObjectState::Present);
  EXPECT_EQ(moved.n_moves, 1);
  EXPECT_NEAR(moved.shape.cx, 1.5, 0.05);
  EXPECT_EQ(stayed.state, ObjectState::Present);
  EXPECT_EQ(stayed.n_moves, 0);
}

// An object of the same size appearing behind the robot seconds after the first was seen in
// place is another object: the first cannot have crossed the room unseen (min_unseen_s).
int objectsAfterATwinAppearsBehind(double min_unseen_s) {
  ObjectOptions o;
  o.min_unseen_s = min_unseen_s;
  TrackerRun run{DynamicGridMap(), ObjectTracker(o)};
  const mrpt::poses::CPose2D ahead(0.0, 0.0, 0.0), behind(0.0, 0.0, M_PI);
  run.steps(10, ahead, {});
  run.steps(15, ahead, {{1.0, 0.5, 0.4}});
  run.steps(10, behind, {{1.0, 0.5, 0.4}});  // it is out of view now
  run.steps(15, behind, {{1.0, 0.5, 0.4}, {-1.5, 0.0, 0.4}});
  return static_cast<int>(run.tracker.objects().size());
}

TEST(ObjectTracker, AnObjectSeenInPlaceSecondsAgoIsNotTakenForOneThatMovedUnseen) {
  EXPECT_EQ(objectsAfterATwinAppearsBehind(30.0), 2);
  // Without the rule the twin is taken for the first object, moved.
  EXPECT_EQ(objectsAfterATwinAppearsBehind(0.0), 1);
}

TEST(ObjectOptions, StrictLoadNamesKeyAndFile) {
  ObjectOptions o;
  EXPECT_NO_THROW(o.load(IniFile::fromText("[objects]\nmin_cells = 3\n", "a.ini")));
  EXPECT_EQ(o.min_cells, 3);
  try {
    o.load(IniFile::fromText("[objects]\nmin_cell = 3\n", "a.ini"));
    FAIL() << "unknown key accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("min_cell"), std::string::npos);
  }
  try {
    o.load(IniFile::fromText("[objects]\nmin_size = 2\nmax_size = 1\n", "b.ini"));
    FAIL() << "min_size above max_size accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("b.ini: [objects] min_size"), std::string::npos);
  }
}

TEST(ObjectOptions, WriteIniReloads) {
  ObjectOptions o;
  o.join_distance = 0.2;
  o.enabled = false;
  std::ostringstream out;
  o.writeIni(out);
  ObjectOptions back;
  back.load(IniFile::fromText(out.str(), "written"));
  EXPECT_DOUBLE_EQ(back.join_distance, 0.2);
  EXPECT_FALSE(back.enabled);
}

}  // namespace
}  // namespace dynamap
