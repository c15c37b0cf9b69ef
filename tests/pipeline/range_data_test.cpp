// One scan's geometry, read by the grid, the matcher and the tracker: with the laser mounted
// centred, offset, turned or upside down, all three put every beam where it really went.

#include "dynamap/base/range_data.h"

#include <gtest/gtest.h>
#include <mrpt/math/wrap2pi.h>

#include <cmath>
#include <vector>

#include "../test_util.h"
#include "dynamap/localization/scan_matcher.h"
#include "dynamap/mapping/dynamic_grid_map.h"
#include "dynamap/objects/object_tracker.h"
#include "dynamap/sim/world.h"

namespace dynamap {
namespace {

using mrpt::poses::CPose2D;
using mrpt::poses::CPose3D;

constexpr double kDeg = M_PI / 180.0;
constexpr int kBeams = 271;
constexpr double kAperture = 270 * kDeg;
constexpr double kRange = 8.0;
const double kTolerance = 0.05 * kDeg;

// An L-shaped room with a pillar: no symmetry a mirrored scan could match.
sim::StaticWorld room() {
  sim::StaticWorld w;
  const double c[][4] = {{-4.01, -3.02, 3.99, -3.02}, {3.99, -3.02, 3.99, 0.98},
                         {3.99, 0.98, 0.49, 0.98},    {0.49, 0.98, 0.49, 2.98},
                         {0.49, 2.98, -4.01, 2.98},   {-4.01, 2.98, -4.01, -3.02},
                         {1.5, -1.6, 2.1, -1.1},      {-2.2, 0.5, -1.6, 0.5}};
  for (const auto& s : c) w.segments.push_back({{s[0], s[1]}, {s[2], s[3]}});
  return w;
}

// Where beam i of a scan from `robot` with `mount` goes, worked out in 3D by MRPT's own pose
// composition: independent of the code under test.
struct Ray {
  double x, y, angle;
};
Ray worldRay(const CPose2D& robot, const CPose3D& mount, int i) {
  const double a = -kAperture / 2 + i * kAperture / (kBeams - 1);  // rightToLeft
  const CPose3D sensor = CPose3D(robot) + mount;
  double x1, y1, z1;
  sensor.composePoint(std::cos(a), std::sin(a), 0.0, x1, y1, z1);
  return {sensor.x(), sensor.y(), std::atan2(y1 - sensor.y(), x1 - sensor.x())};
}

mrpt::obs::CObservation2DRangeScan::Ptr scanFrom(const sim::StaticWorld& world,
                                                 const CPose2D& robot, const CPose3D& mount) {
  std::vector<float> ranges(kBeams, 0.0f);
  for (int i = 0; i < kBeams; ++i) {
    const Ray r = worldRay(robot, mount, i);
    const sim::RayHit h = sim::castRay(world, {}, {r.x, r.y}, r.angle, kRange);
    if (h.hit() && h.range < kRange) ranges[i] = static_cast<float>(h.range);
  }
  auto scan = test::makeScan(ranges, kAperture, 0.0, static_cast<float>(kRange));
  scan->sensorPose = mount;
  return scan;
}

double distanceToWalls(const sim::StaticWorld& w, double x, double y) {
  double best = 1e9;
  for (const sim::Segment& s : w.segments) {
    const double dx = s.b.x - s.a.x, dy = s.b.y - s.a.y;
    const double t =
        std::clamp(((x - s.a.x) * dx + (y - s.a.y) * dy) / (dx * dx + dy * dy), 0.0, 1.0);
    best = std::min(best, std::hypot(x - s.a.x - t * dx, y - s.a.y - t * dy));
  }
  return best;
}

struct Mount {
  const char* name;
  CPose3D pose;
};
const Mount kMounts[] = {
    {"centred", CPose3D()},
    {"offset", CPose3D(0.25, -0.1, 0.3, 0, 0, 0)},
    {"turned", CPose3D(0.1, 0.05, 0.3, 90 * kDeg, 0, 0)},
    {"upside down", CPose3D(0.2, 0, 0.3, 0, 0, M_PI)},
    {"upside down and turned", CPose3D(0, 0.1, 0.3, -60 * kDeg, 0, M_PI)},
};

TEST(RangeData, GridMatcherAndTrackerAgreeForEveryMount) {
  const sim::StaticWorld world = room();
  const CPose2D robot(-0.7, -0.4, 20 * kDeg);
  for (const Mount& m : kMounts) {
    SCOPED_TRACE(m.name);
    const auto scan = scanFrom(world, robot, m.pose);
    const RangeData rd = makeRangeData(*scan, kRange, kTolerance);
    ASSERT_TRUE(rd.planar);
    // The grid: every cell S holds occupied lies on a wall.
    DynamicGridMap map;
    for (int k = 0; k < 4; ++k) ASSERT_TRUE(map.insertRange(rd, robot));
    std::size_t occupied = 0;
    for (unsigned cy = 0; cy < map.getSizeY(); ++cy) {
      for (unsigned cx = 0; cx < map.getSizeX(); ++cx) {
        if (map.staticOccupancy(cx, cy) <= 0.5f) continue;
        ++occupied;
        EXPECT_LT(distanceToWalls(world, map.idx2x(cx), map.idx2y(cy)), 0.05)
            << "cell " << cx << ", " << cy;
      }
    }
    EXPECT_GT(occupied, 150u);
    // The matcher: started 5 cm and half a degree off, it comes back onto the robot's pose (a
    // scan whose points it placed wrongly, mirrored or shifted, would not fit S there).
    const ScanMatchResult r =
        ScanMatcher({}).match(map, rd, robot + CPose2D(0.04, -0.03, 0.5 * kDeg));
    EXPECT_TRUE(r.matched) << (r.fallback_reason ? r.fallback_reason : "");
    EXPECT_LT(std::hypot(r.pose.x() - robot.x(), r.pose.y() - robot.y()), 0.02);
    EXPECT_LT(std::abs(mrpt::math::wrapToPi(r.pose.phi() - robot.phi())), 0.5 * kDeg);
    // The tracker's view: a beam's end point is seen occupied, its middle seen free.
    const ScanView view = makeScanView(rd, robot);
    for (int i = 10; i < kBeams; i += 37) {
      if (scan->getScanRange(i) <= 0) continue;
      const Ray ray = worldRay(robot, m.pose, i);
      const double r_i = scan->getScanRange(i);
      const double ex = ray.x + r_i * std::cos(ray.angle), ey = ray.y + r_i * std::sin(ray.angle);
      EXPECT_EQ(viewOf(view, ex, ey, 0.02, 0.05), PlaceView::SeenOccupied) << "beam " << i;
      const double mx = ray.x + 0.5 * r_i * std::cos(ray.angle);
      const double my = ray.y + 0.5 * r_i * std::sin(ray.angle);
      EXPECT_EQ(viewOf(view, mx, my, 0.02, 0.05), PlaceView::SeenFree) << "beam " << i;
    }
  }
}

TEST(RangeData, BeamKindsFollowTheRangesAndTheirFlags) {
  auto scan = test::makeScan({1.0f, 20.0f, 1.0f, 1.0f, 0.0f}, M_PI / 2);
  scan->setScanRange(2, NAN);  // flagged valid, read as is: a corrupt reading
  scan->setScanRange(3, -1.0f);
  scan->setScanRangeValidity(2, true);
  scan->setScanRangeValidity(3, true);
  const RangeData rd = makeRangeData(*scan, 15.0, kTolerance);
  ASSERT_EQ(rd.size(), 5u);
  EXPECT_EQ(rd.kinds[0], BeamKind::Hit);
  EXPECT_EQ(rd.kinds[1], BeamKind::Beyond);
  EXPECT_EQ(rd.kinds[2], BeamKind::Bad);
  EXPECT_EQ(rd.kinds[3], BeamKind::Bad);
  EXPECT_EQ(rd.kinds[4], BeamKind::NoEcho);
  EXPECT_EQ(rd.bad_beams, 2u);
  EXPECT_NEAR(rd.angle(0), -M_PI / 4, 1e-7);  // the aperture is a float
  EXPECT_NEAR(rd.angle(4), M_PI / 4, 1e-7);
  scan->sensorPose = CPose3D(0, 0, 0, 0, 0, M_PI);  // upside down: the sweep turns round
  EXPECT_NEAR(makeRangeData(*scan, 15.0, kTolerance).angle(0), M_PI / 4, 1e-7);
  scan->sensorPose = CPose3D(0, 0, 0, 0, 10 * kDeg, 0);  // tilted
  EXPECT_FALSE(makeRangeData(*scan, 15.0, kTolerance).planar);
}

}  // namespace
}  // namespace dynamap
