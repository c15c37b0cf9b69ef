// ScanView: a scan's beams in the map frame (mount included), and what they show of a place.

#include "dynamap/objects/scan_view.h"

#include <gtest/gtest.h>
#include <mrpt/poses/CPose3D.h>

#include <cmath>

#include "../test_util.h"

namespace dynamap {
namespace {

TEST(MakeScanView, BeamsRangesAndTheMountInTheMapFrame) {
  // Three beams over 180 degrees: right, ahead, left. One without echo, one past max_range.
  auto scan = test::makeScan({2.0f, 0.0f, 20.0f}, M_PI);
  scan->sensorPose = mrpt::poses::CPose3D(0.5, 0.0, 0.0, 0.0, 0.0, 0.0);
  const ScanView v = makeScanView(makeRangeData(*scan, 10.0, 0.05 * M_PI / 180.0),
                                  mrpt::poses::CPose2D(1.0, 2.0, M_PI / 2));
  EXPECT_NEAR(v.x, 1.0, 1e-9);  // the mount is 0.5 m ahead of a robot facing +y
  EXPECT_NEAR(v.y, 2.5, 1e-9);
  EXPECT_NEAR(v.phi, M_PI / 2, 1e-9);
  EXPECT_NEAR(v.first, -M_PI / 2, 1e-6);
  EXPECT_NEAR(v.step, M_PI / 2, 1e-6);
  EXPECT_EQ(v.dir, 1.0);
  EXPECT_EQ(v.max_range, 10.0);
  ASSERT_EQ(v.ranges.size(), 3u);
  EXPECT_FLOAT_EQ(v.ranges[0], 2.0f);
  EXPECT_FLOAT_EQ(v.ranges[1], -1.0f);  // invalid: no echo
  EXPECT_FLOAT_EQ(v.ranges[2], 10.0f);  // cut at max_range
}

TEST(MakeScanView, AnUpsideDownMountTurnsTheBeamsTheOtherWay) {
  auto scan = test::makeScan({1.0f, 1.0f}, M_PI);
  scan->sensorPose = mrpt::poses::CPose3D(0.0, 0.0, 0.0, 0.0, 0.0, M_PI);  // rolled over
  EXPECT_EQ(
      makeScanView(makeRangeData(*scan, 10.0, 0.05 * M_PI / 180.0), mrpt::poses::CPose2D()).dir,
      -1.0);
  scan->rightToLeft = false;  // and a scanner turning left to right, rolled over, turns back
  EXPECT_EQ(
      makeScanView(makeRangeData(*scan, 10.0, 0.05 * M_PI / 180.0), mrpt::poses::CPose2D()).dir,
      1.0);
}

TEST(MakeScanView, EachBeamsDirectionInTheMapFrameIsCachedAsItsCosineAndSine) {
  std::vector<float> ranges(181, 3.0f);
  auto scan = test::makeScan(ranges, M_PI);
  scan->sensorPose = mrpt::poses::CPose3D(0.2, 0.1, 0.0, 0.3, 0.0, 0.0);
  const ScanView v = makeScanView(makeRangeData(*scan, 10.0, 0.05 * M_PI / 180.0),
                                  mrpt::poses::CPose2D(-4.0, 7.0, 2.5));
  ASSERT_EQ(v.cosines.size(), 181u);
  ASSERT_EQ(v.sines.size(), 181u);
  for (std::size_t i = 0; i < 181; ++i) {
    const double a = v.phi + v.dir * (v.first + v.step * static_cast<double>(i));
    EXPECT_NEAR(v.cosines[i], std::cos(a), 1e-12) << i;
    EXPECT_NEAR(v.sines[i], std::sin(a), 1e-12) << i;
  }
}

TEST(MakeScanView, AnEmptyScanGivesAnEmptyView) {
  const auto scan = test::makeScan({}, M_PI);
  EXPECT_TRUE(makeScanView(makeRangeData(*scan, 10.0, 0.05 * M_PI / 180.0), mrpt::poses::CPose2D())
                  .empty());
}

// 181 beams, one a degree from -90 to +90, all ending on a wall 5 m away unless set.
ScanView wallView(double dir) {
  ScanView v;
  v.first = -M_PI / 2;
  v.step = M_PI / 180;
  v.dir = dir;
  v.max_range = 10.0;
  v.ranges.assign(181, 5.0f);
  return v;
}

void setBeams(ScanView& v, int from, int to, float range) {
  for (int i = from; i <= to; ++i) v.ranges[static_cast<std::size_t>(i)] = range;
}

// An object 2 m away on beams 80..90 of a wall at 5 m: its run, with both edges seen.
TEST(BeamRunAround, ARunEndsWhereTheNextBeamPassesBehindOrIsHidden) {
  ScanView v = wallView(1.0);
  setBeams(v, 80, 90, 2.0f);
  v.ranges[85] = 1.95f;  // its surface bulges: steps within the jump continue the run
  BeamRun run = beamRunAround(v, 83, 0.15);
  EXPECT_EQ(run.first, 80u);
  EXPECT_EQ(run.last, 90u);
  EXPECT_TRUE(run.whole());
  // Something nearer beside it hides one edge: not whole.
  v.ranges[91] = 1.0f;
  run = beamRunAround(v, 83, 0.15);
  EXPECT_TRUE(run.edge_before);
  EXPECT_FALSE(run.edge_after);
  // No echo beside it is an edge; the end of the field of view is not.
  v.ranges[91] = -1.0f;
  EXPECT_TRUE(beamRunAround(v, 83, 0.15).whole());
  setBeams(v, 0, 10, 2.0f);
  run = beamRunAround(v, 4, 0.15);
  EXPECT_EQ(run.first, 0u);
  EXPECT_EQ(run.last, 10u);
  EXPECT_FALSE(run.edge_before);
  EXPECT_TRUE(run.edge_after);
  // A wall 5 cm behind it continues the run: an object against a wall shows no outline.
  setBeams(v, 91, 180, 2.05f);
  EXPECT_FALSE(beamRunAround(v, 83, 0.15).edge_after);
}

TEST(ViewOf, BeamsPastThePlaceSeeItFreeBeamsEndingThereSeeItOccupied) {
  ScanView v = wallView(1.0);
  EXPECT_EQ(viewOf(v, 2.0, 0.0, 0.2, 0.1), PlaceView::SeenFree);
  setBeams(v, 85, 95, 1.85f);  // a surface 1.8 m ahead, within the margin of the disc's front
  EXPECT_EQ(viewOf(v, 2.0, 0.0, 0.2, 0.1), PlaceView::SeenOccupied);
  setBeams(v, 80, 100, 1.0f);  // something nearer hides it
  EXPECT_EQ(viewOf(v, 2.0, 0.0, 0.2, 0.1), PlaceView::NotInView);
  setBeams(v, 80, 100, -1.0f);  // no echo at all there: nothing is known
  EXPECT_EQ(viewOf(v, 2.0, 0.0, 0.2, 0.1), PlaceView::NotInView);
}

// An object stood 5 cm behind a wall (a partition seen from its other side): the wall's hits
// lie within the margin of the place's front. Marked as wall hits, they say nothing of it.
TEST(ViewOf, AWallWithinTheMarginOfThePlaceIsNoSignOfTheObject) {
  ScanView v = wallView(1.0);
  setBeams(v, 85, 95, 1.75f);  // the partition, 5 cm before the disc's front at 1.8 m
  EXPECT_EQ(viewOf(v, 2.0, 0.0, 0.2, 0.1), PlaceView::SeenOccupied);
  std::vector<char> wall(v.ranges.size(), 0);
  const auto on_wall = [&](std::size_t i) { return wall[i] != 0; };
  EXPECT_EQ(viewOf(v, 2.0, 0.0, 0.2, 0.1, on_wall), PlaceView::SeenOccupied);
  for (int i = 85; i <= 95; ++i) wall[static_cast<std::size_t>(i)] = 1;
  EXPECT_EQ(viewOf(v, 2.0, 0.0, 0.2, 0.1, on_wall), PlaceView::NotInView);
  // A wall hit beyond the place still shows it crossed, and so free.
  setBeams(v, 85, 95, 2.5f);
  EXPECT_EQ(viewOf(v, 2.0, 0.0, 0.2, 0.1, on_wall), PlaceView::SeenFree);
}

TEST(ViewOf, PlacesOutOfRangeBehindOrAroundTheSensorAreNotInView) {
  const ScanView v = wallView(1.0);
  EXPECT_EQ(viewOf(v, -2.0, 0.0, 0.2, 0.1), PlaceView::NotInView);          // behind
  EXPECT_EQ(viewOf(v, 12.0, 0.0, 0.2, 0.1), PlaceView::NotInView);          // past max_range
  EXPECT_EQ(viewOf(v, 0.1, 0.0, 0.2, 0.1), PlaceView::NotInView);           // the sensor is inside
  EXPECT_EQ(viewOf(ScanView(), 2.0, 0.0, 0.2, 0.1), PlaceView::NotInView);  // no scan
}

TEST(ViewOf, TheBeamDirectionDecidesWhichBeamsLookAtAPlace) {
  // A place 45 degrees to the left: beam 135 looks at it when beams turn left, beam 45 when
  // they turn right. Only beams 40 to 50 end at its front.
  for (const double dir : {1.0, -1.0}) {
    ScanView v = wallView(dir);
    setBeams(v, 40, 50, 1.95f);
    const PlaceView want = dir > 0 ? PlaceView::SeenFree : PlaceView::SeenOccupied;
    EXPECT_EQ(viewOf(v, 1.5, 1.5, 0.2, 0.1), want) << "dir " << dir;
  }
}

}  // namespace
}  // namespace dynamap
