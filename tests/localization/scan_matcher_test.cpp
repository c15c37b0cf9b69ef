// ScanMatcher: aligning a scan to the static map S, and the Mapper's fallback to odometry.

#include "dynamap/localization/scan_matcher.h"

#include <gtest/gtest.h>
#include <mrpt/math/wrap2pi.h>

#include <cmath>
#include <limits>
#include <vector>

#include "../test_util.h"
#include "dynamap/base/ini.h"
#include "dynamap/pipeline/mapper.h"
#include "dynamap/sim/world.h"

namespace dynamap {
namespace {

using mrpt::poses::CPose2D;

constexpr double kDeg = M_PI / 180.0;
constexpr int kBeams = 361;
constexpr double kAperture = 2 * M_PI * 360.0 / 361.0;  // all round, no beam twice
constexpr double kRange = 8.0;

// A scan's range data as the pipeline works it out (8 m insertion range, MRPT's tilt tolerance).
RangeData rangeOf(const mrpt::obs::CObservation2DRangeScan& scan) {
  return makeRangeData(scan, kRange, 0.05 * M_PI / 180.0);
}

/// A 10 x 7 m room with a pillar and a short wall inside, so every direction of the pose is
/// pinned down; walls off the grid's cell borders and at an angle.
sim::StaticWorld room() {
  sim::StaticWorld w;
  auto wall = [&](double x0, double y0, double x1, double y1) {
    w.segments.push_back({{x0, y0}, {x1, y1}});
  };
  wall(-5.013, -3.488, 4.987, -3.488);
  wall(4.987, -3.488, 4.987, 3.512);
  wall(4.987, 3.512, -5.013, 3.512);
  wall(-5.013, 3.512, -5.013, -3.488);
  wall(1.2, 1.0, 2.7, 2.1);  // at an angle
  wall(-2.0, -1.0, -2.0, 0.4);
  wall(-2.0, 0.4, -1.3, 0.4);
  return w;
}

/// A noise-free scan of `world` (and `bodies`) from `pose`.
mrpt::obs::CObservation2DRangeScan::Ptr scanFrom(const sim::StaticWorld& world, const CPose2D& pose,
                                                 const std::vector<sim::Body>& bodies = {}) {
  std::vector<float> ranges(kBeams, 0.0f);
  for (int i = 0; i < kBeams; ++i) {
    const double a = -kAperture / 2 + i * kAperture / (kBeams - 1);
    const sim::RayHit h = sim::castRay(world, bodies, {pose.x(), pose.y()}, pose.phi() + a, kRange);
    if (h.hit() && h.range < kRange) ranges[i] = static_cast<float>(h.range);
  }
  return test::makeScan(ranges, kAperture, 0.0, static_cast<float>(kRange));
}

/// S after clean scans from a few poses around the middle of the room.
DynamicGridMap mappedRoom(const sim::StaticWorld& world, double resolution = 0.05) {
  DynamicMapOptions options;
  options.resolution = resolution;
  DynamicGridMap map(options);
  for (const CPose2D& p : {CPose2D(0, 0, 0), CPose2D(0.5, 0.3, 0.4), CPose2D(-0.6, -0.5, -0.3),
                           CPose2D(1.0, -1.0, 1.2), CPose2D(-1.0, 1.2, 2.5)}) {
    for (int k = 0; k < 3; ++k) map.insertObservation(*scanFrom(world, p), mrpt::poses::CPose3D(p));
  }
  return map;
}

double headingError(const CPose2D& a, const CPose2D& b) {
  return std::abs(mrpt::math::wrapToPi(a.phi() - b.phi()));
}

/// The options with point-to-line ICP on S's cells instead of MRPT's point-to-point ICP.
ScanMatchOptions pointToLine() {
  ScanMatchOptions o;
  o.point_to_line = true;
  return o;
}

// S knows a wall only to the cell it falls in: the match is as exact as S's cells, about a
// third of a cell here. With 2 cm cells that is within 1 cm; with the default 5 cm, 2.5 cm.
void expectRecovered(double resolution, double tolerance_m, const ScanMatchOptions& options) {
  const auto world = room();
  const DynamicGridMap map = mappedRoom(world, resolution);
  const ScanMatcher matcher(options);
  const CPose2D truth(0.3, -0.2, 0.15);
  const auto scan = scanFrom(world, truth);
  // Offsets up to overlap_distance_m (0.1 m) from every wall; turns up to 3 degrees.
  for (const CPose2D& offset :
       {CPose2D(0.07, -0.05, 2 * kDeg), CPose2D(-0.06, 0.05, -3 * kDeg), CPose2D(0.0, 0.08, 0.0)}) {
    SCOPED_TRACE(offset.asString());
    const CPose2D guess = truth + offset;
    const ScanMatchResult r = matcher.match(map, rangeOf(*scan), guess);
    ASSERT_TRUE(r.matched) << r.fallback_reason;
    EXPECT_LT(std::hypot(r.pose.x() - truth.x(), r.pose.y() - truth.y()), tolerance_m);
    EXPECT_LT(headingError(r.pose, truth), 0.5 * kDeg);
    EXPECT_GT(r.inlier_ratio, 0.8);
    EXPECT_EQ(r.degenerate_directions, 0);
  }
}

TEST(ScanMatcher, RecoversAKnownOffsetWithinACentimetreAndHalfADegree) {
  expectRecovered(0.02, 0.01, {});
  expectRecovered(0.02, 0.01, pointToLine());
}

TEST(ScanMatcher, RecoversAKnownOffsetWithinHalfACellAtFiveCentimetres) {
  expectRecovered(0.05, 0.025, {});
  expectRecovered(0.05, 0.025, pointToLine());
}

// Point-to-line pairs a point with the line through a wall's cells, not with the cell's centre:
// a wall between two rows of cells is matched to a fraction of a cell, as MRPT's ICP against
// points laid along the walls is.
TEST(ScanMatcher, PointToLineIsAsExactAsMrptIcpOnTheSameScans) {
  const auto world = room();
  const DynamicGridMap map = mappedRoom(world);
  const CPose2D truth(-0.4, 0.6, -0.35);
  const CPose2D guess = truth + CPose2D(0.05, 0.06, -1.5 * kDeg);
  const auto rd = rangeOf(*scanFrom(world, truth));
  const ScanMatchResult line = ScanMatcher(pointToLine()).match(map, rd, guess);
  const ScanMatchResult icp = ScanMatcher({}).match(map, rd, guess);
  ASSERT_TRUE(line.matched) << line.fallback_reason;
  ASSERT_TRUE(icp.matched) << icp.fallback_reason;
  const double line_error = std::hypot(line.pose.x() - truth.x(), line.pose.y() - truth.y());
  const double icp_error = std::hypot(icp.pose.x() - truth.x(), icp.pose.y() - truth.y());
  EXPECT_LT(line_error, 0.015);
  EXPECT_LT(line_error, icp_error + 0.005);
  EXPECT_LT(headingError(line.pose, truth), 0.3 * kDeg);
  EXPECT_GT(line.icp_iterations, 0u);
}

// In a straight corridor nothing pins the position along it down: point-to-line keeps the
// guess's value along the corridor and corrects across it and in heading.
TEST(ScanMatcher, AlongAStraightCorridorTheGuessIsKept) {
  sim::StaticWorld corridor;
  corridor.segments.push_back({{-20, -1.013}, {20, -1.013}});
  corridor.segments.push_back({{-20, 0.987}, {20, 0.987}});
  DynamicGridMap map{DynamicMapOptions{}};
  for (const double x : {-0.5, 0.0, 0.5}) {
    for (int k = 0; k < 3; ++k) {
      map.insertObservation(*scanFrom(corridor, {x, 0, 0}), mrpt::poses::CPose3D(x, 0, 0, 0, 0, 0));
    }
  }
  const CPose2D truth(0.1, -0.05, 0.0);
  const CPose2D guess = truth + CPose2D(0.07, 0.06, 1.0 * kDeg);
  const ScanMatchResult r =
      ScanMatcher(pointToLine()).match(map, rangeOf(*scanFrom(corridor, truth)), guess);
  ASSERT_TRUE(r.matched) << r.fallback_reason;
  EXPECT_EQ(r.degenerate_directions, 1);
  EXPECT_NEAR(r.pose.y(), truth.y(), 0.02);            // across: the walls
  EXPECT_LT(headingError(r.pose, truth), 0.3 * kDeg);  // the walls' direction
  // Along: the guess's (the search's cell steps move it at most by the grid's search, which a
  // flat direction does not pay for).
  EXPECT_NEAR(r.pose.x(), guess.x(), 1e-9);
}

// Drift beyond the overlap gate (0.1 m), turned too: the grid search before ICP starts it from
// the best pose within search_xy_m and search_deg.
TEST(ScanMatcher, DriftBeyondTheOverlapGateIsRecovered) {
  const auto world = room();
  const DynamicGridMap map = mappedRoom(world);
  const CPose2D truth(0.3, -0.2, 0.15);
  const auto scan = scanFrom(world, truth);
  const CPose2D guess = truth + CPose2D(0.11, -0.09, 1.5 * kDeg);  // 0.14 m
  const ScanMatchResult r = ScanMatcher({}).match(map, rangeOf(*scan), guess);
  ASSERT_TRUE(r.matched) << r.fallback_reason;
  EXPECT_LT(std::hypot(r.pose.x() - truth.x(), r.pose.y() - truth.y()), 0.025);
  EXPECT_LT(headingError(r.pose, truth), 0.5 * kDeg);
}

void expectNotPulledByAMovedObject(const ScanMatchOptions& options) {
  const auto world = room();
  const DynamicGridMap map = mappedRoom(world);  // S knows the middle of the room as free
  const ScanMatcher matcher(options);
  const CPose2D truth(0.2, 0.1, -0.1);
  const CPose2D guess = truth + CPose2D(0.06, 0.05, 2 * kDeg);
  // A 0.8 m object now stands 1.5 m in front of the robot, where S holds free space, and near
  // a wall it hides partly.
  const std::vector<sim::Body> moved = {{{1.6, -0.1}, 0.4, sim::BodyKind::Object, 1},
                                        {{3.4, 2.9}, 0.3, sim::BodyKind::Object, 2}};
  const ScanMatchResult clean = matcher.match(map, rangeOf(*scanFrom(world, truth)), guess);
  const ScanMatchResult with = matcher.match(map, rangeOf(*scanFrom(world, truth, moved)), guess);
  ASSERT_TRUE(clean.matched) << clean.fallback_reason;
  ASSERT_TRUE(with.matched) << with.fallback_reason;
  EXPECT_LT(with.inlier_ratio, clean.inlier_ratio);  // the object was in view
  EXPECT_LT(std::hypot(with.pose.x() - clean.pose.x(), with.pose.y() - clean.pose.y()), 0.005);
  EXPECT_LT(headingError(with.pose, clean.pose), 0.2 * kDeg);
  EXPECT_LT(std::hypot(with.pose.x() - truth.x(), with.pose.y() - truth.y()), 0.025);
}

TEST(ScanMatcher, AMovedObjectInViewDoesNotPullThePose) {
  expectNotPulledByAMovedObject({});
  expectNotPulledByAMovedObject(pointToLine());
}

TEST(ScanMatcher, APoorMatchKeepsTheGuessAndSaysWhy) {
  const auto world = room();
  const DynamicGridMap map = mappedRoom(world);
  const ScanMatcher matcher({});
  const CPose2D truth(0.3, -0.2, 0.15);
  // Odometry 1 m and 20 degrees off: no match within max_correction_m.
  const CPose2D guess = truth + CPose2D(1.0, 0.5, 20 * kDeg);
  const ScanMatchResult r = matcher.match(map, rangeOf(*scanFrom(world, truth)), guess);
  EXPECT_FALSE(r.matched);
  ASSERT_NE(r.fallback_reason, nullptr);
  EXPECT_EQ(r.pose, guess);
  // Nothing mapped yet: nothing to match against.
  const ScanMatchResult empty =
      matcher.match(DynamicGridMap{}, rangeOf(*scanFrom(world, truth)), truth);
  EXPECT_FALSE(empty.matched);
  EXPECT_STREQ(empty.fallback_reason, "too few map points");
}

TEST(ScanMatcher, SameInputGivesTheSamePose) {
  const auto world = room();
  const DynamicGridMap map = mappedRoom(world);
  const ScanMatcher matcher({});
  const auto scan = scanFrom(world, CPose2D(0.3, -0.2, 0.15));
  const CPose2D guess(0.35, -0.25, 0.2);
  const ScanMatchResult a = matcher.match(map, rangeOf(*scan), guess),
                        b = matcher.match(map, rangeOf(*scan), guess);
  EXPECT_EQ(a.pose.x(), b.pose.x());
  EXPECT_EQ(a.pose.y(), b.pose.y());
  EXPECT_EQ(a.pose.phi(), b.pose.phi());
}

// The Mapper: odometry that drifts is corrected; a jump it cannot match falls back and is counted.
// The search's table must say of every cell what staticOccupancy() > threshold says: checked on
// a mapped room's cells (walls, free space, unknown) and on every value a cell can hold.
TEST(OccupiedByRawValue, AgreesWithStaticOccupancyOnEveryCellAndValue) {
  const DynamicGridMap map = mappedRoom(room());
  for (const double threshold : {0.55, 0.6, 0.65, 0.9}) {
    const OccupiedByRawValue occupied(threshold);
    const auto& raw = map.getRawMap();
    int agree = 0, occupied_cells = 0;
    for (int cy = 0; cy < static_cast<int>(map.getSizeY()); ++cy) {
      for (int cx = 0; cx < static_cast<int>(map.getSizeX()); ++cx) {
        const bool expected = map.staticOccupancy(cx, cy) > threshold;
        agree += occupied(raw[cx + cy * map.getSizeX()]) == expected;
        occupied_cells += expected;
      }
    }
    EXPECT_EQ(agree, static_cast<int>(map.getSizeX() * map.getSizeY())) << threshold;
    EXPECT_GT(occupied_cells, 100) << threshold;  // the room's walls are there to be judged
    using V = OccupiedByRawValue::Value;
    for (long v = std::numeric_limits<V>::min(); v <= std::numeric_limits<V>::max(); ++v) {
      ASSERT_EQ(occupied(static_cast<V>(v)),
                DynamicGridMap::staticOccupancyOfValue(static_cast<V>(v)) > threshold)
          << v;
    }
  }
}

TEST(ScanMatchingMapper, CorrectsDriftAndCountsFallbacks) {
  const auto world = room();
  MapConfig config;
  config.poses = PoseSource::ScanMatching;
  config.objects.enabled = false;
  Mapper mapper(config);
  // The robot drives along x; odometry over-reads every step by 3 cm and 0.5 degrees.
  CPose2D odo(0, 0, 0), truth(0, 0, 0);
  const CPose2D step(0.1, 0, 0), drift(0.03, 0, 0.5 * kDeg);
  std::vector<CPose2D> truths, used;
  for (int i = 0; i < 20; ++i) {
    if (i > 0) {
      truth = truth + step;
      odo = odo + step + drift;
    }
    if (i == 12) odo = odo + CPose2D(0.8, 0.6, 25 * kDeg);  // a slip the scan contradicts
    ScanRecord rec;
    rec.index = static_cast<std::size_t>(i);
    rec.t = i * 0.2;
    rec.pose = odo;
    rec.scan = scanFrom(world, truth);
    used.push_back(mapper.process(rec).pose);
    truths.push_back(truth);
  }
  const ScanMatchCounts& c = mapper.scanMatchCounts();
  EXPECT_EQ(c.fallbacks.at("too few map points"), 1u);  // the first scan: S is empty
  EXPECT_EQ(c.fallbackTotal(), 2u);                     // ... and the slip
  EXPECT_EQ(c.matched, 18u);
  ASSERT_EQ(used.size(), 20u);
  const CPose2D slipped = used[11] + step + drift + CPose2D(0.8, 0.6, 25 * kDeg);
  EXPECT_NEAR(used[12].x(), slipped.x(), 1e-9);  // odometry's
  EXPECT_NEAR(used[12].y(), slipped.y(), 1e-9);
  // Before the slip every pose is on the truth, to S's 5 cm cells; odometry is 33 cm off.
  for (int i = 0; i < 12; ++i) {
    const CPose2D& p = used[i];
    EXPECT_LT(std::hypot(p.x() - truths[i].x(), p.y() - truths[i].y()), 0.025) << "scan " << i;
    EXPECT_LT(headingError(p, truths[i]), 0.5 * kDeg) << "scan " << i;
  }
}

TEST(ScanMatchOptions, BadValuesAreErrorsNamingTheKey) {
  auto load = [](const std::string& text) {
    ScanMatchOptions o;
    o.load(IniFile::fromText("[scan_matching]\n" + text, "t.ini"));
    return o;
  };
  EXPECT_EQ(load("max_correction_m = 0.5\n").max_correction_m, 0.5);
  for (const char* bad :
       {"occupied_threshold = 0.5\n", "min_inlier_ratio = 1.5\n", "max_correction_deg = 0\n",
        "icp_max_iterations = 0\n", "icp_smallest_threshold_dist_m = 0.9\n",
        "min_constraint = -1\n", "overlap_distance_m = 0\n", "min_map_points = x\n",
        "line_distance_m = 0\n", "line_distance_m = 1.5\n", "point_to_line = maybe\n"}) {
    try {
      load(bad);
      ADD_FAILURE() << "accepted " << bad;
    } catch (const ConfigError& e) {
      const std::string key = std::string(bad).substr(0, std::string(bad).find(' '));
      EXPECT_NE(std::string(e.what()).find("t.ini: [scan_matching] " + key), std::string::npos)
          << e.what();
    }
  }
  EXPECT_THROW(load("max_corection_m = 1\n"), ConfigError);
}

}  // namespace
}  // namespace dynamap
