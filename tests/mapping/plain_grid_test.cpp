// PlainGrid / comparePlain: what a plain MRPT grid keeps that S does not.

#include "dynamap/mapping/plain_grid.h"

#include <gtest/gtest.h>

#include <cmath>

#include "../test_util.h"

namespace dynamap {
namespace {

using mrpt::poses::CPose2D;

// 181 beams over 90 degrees to a wall at x = 1.0 m; within +-5 degrees of ahead an object at
// 0.625 m when `object`.
mrpt::obs::CObservation2DRangeScan::Ptr wallScan(bool object) {
  constexpr int n = 181;
  const double aperture = M_PI / 2;
  std::vector<float> r(n);
  for (int i = 0; i < n; ++i) {
    const double a = -aperture / 2 + aperture * i / (n - 1);
    r[i] =
        static_cast<float>((object && std::abs(a) < 5 * M_PI / 180 ? 0.625 : 0.975) / std::cos(a));
  }
  return test::makeScan(r, aperture);
}

// Both maps fed `scans` wall scans, the object present from scan `object_from` on.
struct Both {
  DynamicGridMap map{DynamicMapOptions{}, InsertionOptions{}};
  PlainGrid plain{DynamicMapOptions{}, InsertionOptions{}};
  Both(int scans, int object_from) {
    for (int k = 0; k < scans; ++k) {
      const auto scan = wallScan(k >= object_from);
      map.insertObservation(*scan, mrpt::poses::CPose3D());
      plain.insert(*scan, CPose2D(0, 0, 0));
    }
  }
};

TEST(PlainGrid, AnObjectThatCameLaterStaysInThePlainGridButNotInS) {
  const Both b(30, 15);
  const DynamicGridMap& map = b.map;
  const PlainGrid& plain = b.plain;
  const PlainComparison c = comparePlain(map, plain.grid());
  // The object's face: about 0.1 m wide at 5 cm cells, held by MRPT, Free in S.
  EXPECT_GE(c.plain_occupied_static_free, 2u);
  EXPECT_LE(c.plain_occupied_static_free, 6u);
  // The wall is in both.
  EXPECT_GT(c.both_occupied, 20u);
  const int ox = map.x2idx(0.625), oy = map.y2idx(0.0);
  EXPECT_TRUE(map.isStaticFree(ox, oy));
  EXPECT_LT(plain.grid().getCell(plain.grid().x2idx(0.625), plain.grid().y2idx(0.0)), 0.5f);
}

TEST(PlainGrid, AStaticSceneHasNothingThatMoved) {
  const Both b(20, 20);
  const PlainComparison c = comparePlain(b.map, b.plain.grid());
  EXPECT_EQ(c.plain_occupied_static_free, 0u);
  EXPECT_GT(c.both_occupied, 20u);
}

// What a corrupt file can put in a scan: a pose 1e9 m away, non-finite poses, NaN, infinite
// and negative ranges. MRPT's own insertion turns such values into cell indices (a crash, or a
// grid of gigabytes); PlainGrid refuses the scan or mends the beams first.
TEST(PlainGrid, AFarPoseIsRefusedAndTheGridKeepsItsSize) {
  PlainGrid plain{DynamicMapOptions{}, InsertionOptions{}};
  const auto scan = wallScan(false);
  EXPECT_FALSE(plain.insert(*scan, CPose2D(1e9, 1e9, 0)));
  EXPECT_FALSE(plain.insert(*scan, CPose2D(std::nan(""), 0, 0)));
  EXPECT_FALSE(plain.insert(*scan, CPose2D(0, 0, INFINITY)));
  // max_map_size_m 600 plus 15 m of insertion range on each side: 630 m in all.
  EXPECT_FALSE(plain.insert(*scan, CPose2D(621, 0, 0)));
  EXPECT_EQ(plain.grid().getSizeX(), 400u);  // [-10, 10] m at 5 cm, as constructed
  EXPECT_TRUE(plain.insert(*scan, CPose2D(300, 0, 0)));
  EXPECT_GT(plain.grid().getSizeX(), 400u);
}

TEST(PlainGrid, BadBeamsAreNoEchoesAndTheRestIsInserted) {
  PlainGrid mended{DynamicMapOptions{}, InsertionOptions{}};
  PlainGrid clean{DynamicMapOptions{}, InsertionOptions{}};
  auto scan = wallScan(false);
  clean.insert(*scan, CPose2D(0, 0, 0));
  // The same scan with three beams no sensor could measure, marked valid.
  scan->setScanRange(10, std::nanf(""));
  scan->setScanRange(90, -1.0f);
  scan->setScanRange(170, INFINITY);
  EXPECT_TRUE(mended.insert(*scan, CPose2D(0, 0, 0)));
  EXPECT_EQ(mended.grid().getSizeX(), clean.grid().getSizeX());
  EXPECT_EQ(mended.grid().getSizeY(), clean.grid().getSizeY());
  // Every other beam's wall cell is there: the wall ahead, at x = 1 m.
  const auto& g = mended.grid();
  EXPECT_LT(g.getCell(g.x2idx(0.99), g.y2idx(0.3)), 0.5f);
  EXPECT_FALSE(std::isfinite(scan->getScanRange(10)));  // the caller's scan untouched
}

// A scan dynamap's grid refuses is refused by the plain grid too, for the same reason in the same
// words: MRPT's insertion keeps 8 bytes of stack per beam, and 2,000,000 beams overflowed it
// (SIGSEGV, every output lost) while dynamap's grid took the scan.
TEST(PlainGrid, RefusesWhatDynamapsGridRefusesWithTheSameReason) {
  const auto wide = [](std::size_t n) { return test::makeScan(std::vector<float>(n, 2.0f), M_PI); };
  auto tilted = wallScan(false);
  tilted->sensorPose = mrpt::poses::CPose3D(0, 0, 0, 0, 0.5, 0);
  auto mount = wallScan(false);
  mount->sensorPose = mrpt::poses::CPose3D(NAN, 0, 0, 0, 0, 0);
  auto shut = wallScan(false);
  shut->aperture = 0;
  const struct {
    mrpt::obs::CObservation2DRangeScan::Ptr scan;
    CPose2D pose;
    const char* reason;
  } cases[] = {{wide(kMaxScanBeams + 1), CPose2D(), kTooManyBeams},
               {wide(2000000), CPose2D(), kTooManyBeams},
               {wide(0), CPose2D(), "no beams"},
               {tilted, CPose2D(), "not horizontal"},
               {shut, CPose2D(), "aperture not positive"},
               {wallScan(false), CPose2D(NAN, 0, 0), "pose not finite"},
               {mount, CPose2D(), "sensor pose not finite"},
               {wallScan(false), CPose2D(1e9, 0, 0), "beyond max_map_size_m"},
               {wide(kMaxScanBeams), CPose2D(), nullptr}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.reason ? c.reason : "inserted");
    DynamicGridMap map{DynamicMapOptions{}, InsertionOptions{}};
    PlainGrid plain{DynamicMapOptions{}, InsertionOptions{}};
    map.insertObservation(*c.scan, mrpt::poses::CPose3D(c.pose));
    EXPECT_EQ(plain.insert(*c.scan, c.pose), c.reason == nullptr);
    const char* mine = map.lastInsertStats().skip_reason;
    const char* its = plain.lastSkipReason();
    EXPECT_EQ(std::string(mine ? mine : "inserted"), std::string(c.reason ? c.reason : "inserted"));
    EXPECT_EQ(std::string(its ? its : "inserted"), std::string(c.reason ? c.reason : "inserted"));
  }
}

}  // namespace
}  // namespace dynamap
