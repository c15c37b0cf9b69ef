// DynamicGridMap: the inverse sensor model of each row of the table, cell by cell, and the
// behaviour of S and D on small scenes whose every beam is known.

#include "dynamap/mapping/dynamic_grid_map.h"

#include <gtest/gtest.h>

#include <cmath>

#include "../test_util.h"

namespace dynamap {
namespace {

using mrpt::poses::CPose2D;
using mrpt::poses::CPose3D;
using test::makeScan;

// A 10 x 10 m grid of 0.1 m cells: cell i spans [-5 + 0.1 i, -5 + 0.1 (i + 1)).
// The robot stands at the centre of cell (50, 50) and looks along +x.
constexpr double kRes = 0.1;
const CPose3D kRobot(0.05, 0.05, 0, 0, 0, 0);

DynamicMapOptions smallCells() {
  DynamicMapOptions o;
  o.resolution = kRes;
  return o;
}

DynamicGridMap emptyMap() {
  return DynamicGridMap(smallCells(), {}, -5, 5, -5, 5);
}

// For the table's rows: D may fall to P(occ) 0.05, so its "low" updates show in the cells.
DynamicGridMap tableMap() {
  DynamicMapOptions o = smallCells();
  o.d_min = 0.05;
  return DynamicGridMap(o, {}, -5, 5, -5, 5);
}

// Raw S and D along row 50, cells [from, to].
std::vector<int> staticRow(const DynamicGridMap& m, int from, int to) {
  std::vector<int> v;
  for (int x = from; x <= to; ++x) v.push_back(m.getRawMap()[x + 50 * m.getSizeX()]);
  return v;
}
std::vector<int> dynamicRow(const DynamicGridMap& m, int from, int to) {
  std::vector<int> v;
  for (int x = from; x <= to; ++x) v.push_back(m.dynamicRaw()[x + 50 * m.getSizeX()]);
  return v;
}

// One beam straight ahead: range 0.5 ends in cell 55 and crosses cells 50..54.
void beamAhead(DynamicGridMap& m, float range) {
  m.insertObservation(*makeScan({range}, 0.01), kRobot);
}

TEST(DynamicGridMap, ModelStepsFollowTheOptions) {
  const DynamicGridMap m = emptyMap();
  const auto& d = m.deltas();
  // Cells hold log-odds of FREE: occupied evidence is negative.
  EXPECT_EQ(d.s_hit_notfree, -14);  // P(occ) 0.7
  EXPECT_EQ(d.s_hit_free, 3);       // 0.45
  EXPECT_EQ(d.s_miss, 6);           // 0.4
  EXPECT_EQ(d.d_hit_free, -6);      // 0.59
  EXPECT_EQ(d.d_hit_notfree, 6);    // 0.4
  EXPECT_EQ(d.d_miss, 6);           // 0.4
  EXPECT_EQ(m.getSizeX(), 100u);
}

TEST(DynamicGridMap, RowNotFreeOccupied_And_RowNotFreeFree) {
  DynamicGridMap m = tableMap();
  beamAhead(m, 0.5f);
  // cells 49..56: untouched, five crossed (NotFree + Free obs), the hit (NotFree + Occupied),
  // untouched.
  const std::vector<int> s_expected = {0, 6, 6, 6, 6, 6, -14, 0};
  const std::vector<int> d_expected = {0, 6, 6, 6, 6, 6, 6, 0};
  EXPECT_EQ(staticRow(m, 49, 56), s_expected);
  EXPECT_EQ(dynamicRow(m, 49, 56), d_expected);
  EXPECT_GT(m.staticOccupancy(55, 50), 0.5f);   // S: high
  EXPECT_LT(m.dynamicOccupancy(55, 50), 0.5f);  // D: low
}

TEST(DynamicGridMap, RowFreeOccupied_And_RowFreeFree) {
  DynamicGridMap m = tableMap();
  // Six beams through cell 55 make it Free in S (6 * 6 = 36 > the 0.1 threshold's 35.2).
  for (int i = 0; i < 6; ++i) beamAhead(m, 1.0f);
  ASSERT_TRUE(m.isStaticFree(55, 50));
  ASSERT_EQ(staticRow(m, 55, 55), std::vector<int>{36});
  // Something appears at 0.5 m where S knew free space: S low, D high.
  beamAhead(m, 0.5f);
  EXPECT_EQ(staticRow(m, 54, 56), (std::vector<int>{42, 39, 36}));
  // D: 36 from the misses, then the hit: -6; cells before: a miss again (Free + Free: low).
  EXPECT_EQ(dynamicRow(m, 54, 56), (std::vector<int>{42, 30, 36}));
  EXPECT_LT(m.staticOccupancy(55, 50), 0.1f);
}

TEST(DynamicGridMap, DStaysBetweenDMinAndDMax) {
  DynamicGridMap m = emptyMap();  // d_min 0.5: D never below the prior
  for (int i = 0; i < 10; ++i) beamAhead(m, 1.0f);
  EXPECT_EQ(dynamicRow(m, 50, 59), std::vector<int>(10, 0));
  // Six hits where S is free: 5 * -6 = -30, then d_max 0.95 (-47) would only stop at -47.
  for (int i = 0; i < 6; ++i) beamAhead(m, 0.5f);
  EXPECT_EQ(dynamicRow(m, 55, 55), std::vector<int>{-36});
  for (int i = 0; i < 10; ++i) beamAhead(m, 0.5f);
  EXPECT_EQ(dynamicRow(m, 55, 55), std::vector<int>{-47});
  EXPECT_NEAR(m.dynamicOccupancy(55, 50), 0.95f, 0.01f);
}

TEST(DynamicGridMap, AHitBeatsAMissInTheSameCellAndEachCellIsUpdatedOnce) {
  DynamicGridMap m = emptyMap();
  // Two beams 0.001 rad apart along +x: one ends in cell 55, the other crosses it to cell 60.
  m.insertObservation(*makeScan({0.5f, 1.0f}, 0.001), kRobot);
  EXPECT_EQ(staticRow(m, 50, 61), (std::vector<int>{6, 6, 6, 6, 6, -14, 6, 6, 6, 6, -14, 0}));
  EXPECT_EQ(m.lastInsertStats().hit_cells, 2u);
  EXPECT_EQ(m.lastInsertStats().free_cells, 9u);
}

TEST(DynamicGridMap, MaxDistanceInsertionCutsRaysWithoutAHit) {
  InsertionOptions ins;
  ins.max_distance_insertion = 0.5;
  DynamicGridMap m(smallCells(), ins, -5, 5, -5, 5);
  beamAhead(m, 2.0f);  // longer than the cut: free up to 0.5 m, no hit anywhere
  EXPECT_EQ(staticRow(m, 49, 56), (std::vector<int>{0, 6, 6, 6, 6, 6, 0, 0}));
  EXPECT_EQ(m.lastInsertStats().hit_cells, 0u);
}

TEST(DynamicGridMap, InvalidRangesFreeHalfTheLastValidRangeOnlyWhenAsked) {
  DynamicGridMap m = emptyMap();
  // Beam 0 valid at 1.0 m (0.001 rad right of ahead), beam 1 no echo: frees 0.5 m.
  m.insertObservation(*makeScan({1.0f, -1.0f}, 0.001), kRobot);
  EXPECT_EQ(m.lastInsertStats().beams_used, 2u);
  InsertionOptions ins;
  ins.invalid_ranges_as_free = false;
  DynamicGridMap strict(smallCells(), ins, -5, 5, -5, 5);
  strict.insertObservation(*makeScan({-1.0f}, 0.01), kRobot);
  EXPECT_EQ(strict.lastInsertStats().beams_used, 0u);
  EXPECT_EQ(staticRow(strict, 50, 55), (std::vector<int>(6, 0)));
}

TEST(DynamicGridMap, BadRangesAreCountedAndNotInserted) {
  DynamicGridMap m = emptyMap();
  auto scan = makeScan({0.5f, 0.5f, 0.5f}, 0.002);
  scan->setScanRange(0, std::nanf(""));
  scan->setScanRange(1, -3.0f);
  m.insertObservation(*scan, kRobot);
  EXPECT_EQ(m.lastInsertStats().beams_bad, 2u);
  EXPECT_EQ(m.lastInsertStats().beams_used, 1u);
}

TEST(DynamicGridMap, AScanWhoseOwnMountIsNotFiniteIsSkippedWithItsReason) {
  DynamicGridMap m = emptyMap();
  auto scan = makeScan({0.5f}, 0.01);
  scan->sensorPose = CPose3D(std::nan(""), 0, 0, 0, 0, 0);  // as a corrupt file may state it
  EXPECT_FALSE(m.insertObservation(*scan, kRobot));
  ASSERT_NE(m.lastInsertStats().skip_reason, nullptr);
  EXPECT_STREQ(m.lastInsertStats().skip_reason, "sensor pose not finite");
  EXPECT_EQ(staticRow(m, 49, 56), std::vector<int>(8, 0));
}

TEST(DynamicGridMap, SensorPoseOnTheRobotIsApplied) {
  DynamicGridMap m = emptyMap();
  auto scan = makeScan({0.5f}, 0.01);
  scan->sensorPose = CPose3D(0.2, 0, 0, 0, 0, 0);  // laser 0.2 m ahead of the base
  m.insertObservation(*scan, kRobot);
  // The beam now starts in cell 52 and ends in cell 57.
  EXPECT_EQ(staticRow(m, 51, 58), (std::vector<int>{0, 6, 6, 6, 6, 6, -14, 0}));
}

TEST(DynamicGridMap, APoseJumpNeverGrowsTheGridPastMaxMapSize) {
  DynamicMapOptions o = smallCells();
  o.max_map_size_m = 50;
  DynamicGridMap m(o, {}, -5, 5, -5, 5);
  beamAhead(m, 0.5f);
  const auto size = m.getRawMap().size();
  EXPECT_FALSE(m.insertObservation(*makeScan({0.5f}, 0.01), CPose3D(1e6, 0, 0, 0, 0, 0)));
  EXPECT_STREQ(m.lastInsertStats().skip_reason, "beyond max_map_size_m");
  EXPECT_FALSE(m.insertObservation(*makeScan({0.5f}, 0.01), CPose3D(std::nan(""), 0, 0, 0, 0, 0)));
  EXPECT_STREQ(m.lastInsertStats().skip_reason, "pose not finite");
  EXPECT_EQ(m.getRawMap().size(), size);
  EXPECT_EQ(m.dynamicRaw().size(), size);
  // Within the limit the grid still grows.
  EXPECT_TRUE(m.insertObservation(*makeScan({0.5f}, 0.01), CPose3D(20, 0, 0, 0, 0, 0)));
  EXPECT_GT(m.getRawMap().size(), size);
  EXPECT_EQ(m.lastInsertStats().skip_reason, nullptr);
}

TEST(DynamicGridMap, TiltedScansAreNotInserted) {
  DynamicGridMap m = emptyMap();
  auto scan = makeScan({0.5f}, 0.01);
  scan->sensorPose = CPose3D(0, 0, 0, 0, 0.2, 0);  // pitched 0.2 rad
  EXPECT_FALSE(m.insertObservation(*scan, kRobot));
  EXPECT_STREQ(m.lastInsertStats().skip_reason, "not horizontal");
  EXPECT_EQ(staticRow(m, 50, 55), (std::vector<int>(6, 0)));
}

// --- scenes --------------------------------------------------------------------------------

// 181 beams over 90 degrees towards a wall at x = 1.0 m; beams within +-5 degrees of ahead
// stop at `object_at` instead when it is > 0.
constexpr int kBeams = 181;
constexpr double kAperture = M_PI / 2;

void scanWall(DynamicGridMap& m, double object_at = 0) {
  std::vector<float> r(kBeams);
  for (int i = 0; i < kBeams; ++i) {
    const double a = -kAperture / 2 + kAperture * i / (kBeams - 1);
    r[i] = static_cast<float>((1.0 - 0.05) / std::cos(a));
    if (object_at > 0 && std::abs(a) < 5 * M_PI / 180)
      r[i] = static_cast<float>(object_at / std::cos(a));
  }
  m.insertObservation(*makeScan(r, kAperture), kRobot);
}

std::size_t objectCells(const DynamicGridMap& m) {
  return m.countCells().dynamic_occupied;
}

TEST(DynamicGridMapScenes, AWallScannedAgainAndAgainStaysInSAndNeverEntersD) {
  DynamicGridMap m = emptyMap();
  for (int k = 0; k < 50; ++k) {
    scanWall(m);
    ASSERT_EQ(objectCells(m), 0u) << "scan " << k;
  }
  // The wall: x = 1.0 is the start of cell 60.
  for (int y = 45; y <= 55; ++y) EXPECT_GT(m.staticOccupancy(60, y), 0.9f) << "y " << y;
  EXPECT_TRUE(m.isStaticFree(57, 50));
}

// A wall along x = 0.8 m (a cell boundary) seen at 5 cm resolution with +-1 cm of range noise
// by a 180 degree, 8 m laser sliding past it 0.8 m away, as down a corridor: far along the wall
// the beams graze it, crossing the cells its own hits land in.
struct NoisyWall {
  std::size_t object_cells = 0;
  std::size_t wall_cells = 0, wall_cells_freed = 0;  // the two columns the wall's hits land in
};
NoisyWall grazeNoisyWall(int wall_guard_cells, double surface_guard) {
  DynamicMapOptions o;  // 5 cm cells
  o.wall_guard_cells = wall_guard_cells;
  o.surface_guard = surface_guard;
  DynamicGridMap m(o, {}, -10, 10, -10, 10);
  constexpr double kWall = 0.8;
  std::uint32_t noise = 12345;
  for (int k = 0; k < 300; ++k) {
    const CPose3D robot(0.0, -3.0 + 0.02 * k, 0, 0, 0, 0);
    std::vector<float> r(kBeams);
    for (int i = 0; i < kBeams; ++i) {
      const double a = -M_PI / 2 + M_PI * i / (kBeams - 1);
      noise = noise * 1664525u + 1013904223u;  // a fixed pseudo-random sequence
      const double jitter = (static_cast<int>((noise >> 8) % 21) - 10) * 0.001;
      const double range = std::cos(a) > 1e-6 ? kWall / std::cos(a) + jitter : 100.0;
      r[i] = range < 8.0 ? static_cast<float>(range) : -1.0f;  // no echo beyond 8 m
    }
    m.insertObservation(*makeScan(r, M_PI, 0, 8.0f), robot);
  }
  NoisyWall out;
  out.object_cells = objectCells(m);
  for (int y = m.y2idx(-3.0); y <= m.y2idx(3.0); ++y) {
    for (const int x : {m.x2idx(kWall - 0.025), m.x2idx(kWall + 0.025)}) {
      ++out.wall_cells;
      out.wall_cells_freed += m.staticOccupancy(x, y) < 0.5f;
    }
  }
  return out;
}

TEST(DynamicGridMapScenes, AWallSeenAtGrazingAnglesKeepsItsCellsAndMakesNoObject) {
  const NoisyWall ours = grazeNoisyWall(1, 0.05);  // the defaults
  EXPECT_EQ(ours.wall_cells, 242u);
  EXPECT_EQ(ours.wall_cells_freed, 0u);
  EXPECT_EQ(ours.object_cells, 0u);
  // The surface guard alone keeps the wall's cells, and with them every object cell away.
  const NoisyWall surface_only = grazeNoisyWall(0, 0.05);
  EXPECT_EQ(surface_only.wall_cells_freed, 0u);
  EXPECT_EQ(surface_only.object_cells, 0u);
  // Without it grazing beams free wall cells; the paper's rule then takes hits there for
  // objects, and the wall guard only hides that.
  const NoisyWall wall_guard_only = grazeNoisyWall(1, 0.0);
  EXPECT_GT(wall_guard_only.wall_cells_freed, 5u);
  EXPECT_EQ(wall_guard_only.object_cells, 0u);
  const NoisyWall paper = grazeNoisyWall(0, 0.0);
  EXPECT_GT(paper.wall_cells_freed, 20u);
  EXPECT_GT(paper.object_cells, 10u);
}

TEST(DynamicGridMapScenes, AnObjectInFreeSpaceGoesIntoDAfterFiveScansAndNotIntoS) {
  DynamicGridMap m = emptyMap();
  for (int k = 0; k < 20; ++k) scanWall(m);
  // The object appears at x = 0.65 m (cell 56) in space S knows as free.
  for (int k = 1; k <= 4; ++k) {
    scanWall(m, 0.65);
    EXPECT_EQ(objectCells(m), 0u) << "after " << k << " scans";
  }
  scanWall(m, 0.65);  // the fifth scan: 1 s at 5 Hz
  EXPECT_GT(objectCells(m), 0u);
  EXPECT_TRUE(m.isObjectCell(56, 50));
  EXPECT_LT(m.staticOccupancy(56, 50), 0.1f);  // not in S
  // It leaves: from d_max (-47), four misses of +6 take D below the threshold (-27.7).
  for (int k = 0; k < 20; ++k) scanWall(m, 0.65);
  for (int k = 0; k < 3; ++k) scanWall(m);
  EXPECT_GT(objectCells(m), 0u);
  scanWall(m);
  EXPECT_EQ(objectCells(m), 0u);
}

TEST(DynamicGridMap, AHitInFreeSpaceLeavesDAsItIsWhileHeldAndSAsUnheld) {
  DynamicGridMap held = tableMap(), free_run = tableMap();
  for (DynamicGridMap* m : {&held, &free_run}) {
    for (int i = 0; i < 6; ++i) beamAhead(*m, 1.0f);
    ASSERT_TRUE(m->isStaticFree(55, 50));
  }
  held.holdDynamic(true);
  EXPECT_TRUE(held.dynamicHeld());
  beamAhead(held, 0.5f);
  beamAhead(free_run, 0.5f);
  // S moves as without the hold; D's cell 55 keeps the 36 of its misses (unheld: 30), while
  // the cells the beam crossed still fade (miss: 42).
  EXPECT_EQ(staticRow(held, 54, 56), staticRow(free_run, 54, 56));
  EXPECT_EQ(dynamicRow(held, 54, 56), (std::vector<int>{42, 36, 36}));
  EXPECT_EQ(dynamicRow(free_run, 54, 56), (std::vector<int>{42, 30, 36}));
}

TEST(DynamicGridMapScenes, AnObjectSeenWhileDIsHeldNeverEntersD) {
  DynamicGridMap m = emptyMap();
  for (int k = 0; k < 20; ++k) scanWall(m);
  m.holdDynamic(true);
  for (int k = 0; k < 10; ++k) scanWall(m, 0.65);
  EXPECT_EQ(objectCells(m), 0u);
  m.holdDynamic(false);  // the same hits count again: five make it an object
  for (int k = 0; k < 5; ++k) scanWall(m, 0.65);
  EXPECT_TRUE(m.isObjectCell(56, 50));
}

TEST(DynamicGridMapScenes, AnObjectPresentFromTheStartIsStaticUntilItLeaves) {
  DynamicGridMap m = emptyMap();
  for (int k = 0; k < 20; ++k) scanWall(m, 0.65);
  EXPECT_GT(m.staticOccupancy(56, 50), 0.9f);
  EXPECT_EQ(objectCells(m), 0u);
  // It leaves. S saturates at MRPT's 8-bit limit (-127) and Free needs >= 36, so 28 misses
  // of +6 make the cell Free again: 27 are not enough.
  for (int k = 0; k < 27; ++k) scanWall(m);
  EXPECT_FALSE(m.isStaticFree(56, 50));
  scanWall(m);
  EXPECT_LT(m.staticOccupancy(56, 50), 0.5f);
  EXPECT_TRUE(m.isStaticFree(56, 50));
  EXPECT_EQ(objectCells(m), 0u);
  EXPECT_GT(m.staticOccupancy(60, 50), 0.9f);  // the wall stays
}

TEST(DynamicGridMapScenes, ChangedObjectCellsListsExactlyTheCellsThatCrossedTheThreshold) {
  DynamicGridMap m = emptyMap();
  for (int k = 0; k < 20; ++k) scanWall(m);
  for (int k = 0; k < 4; ++k) scanWall(m, 0.65);
  EXPECT_TRUE(m.changedObjectCells().empty());
  scanWall(m, 0.65);
  const auto changed = m.changedObjectCells();
  EXPECT_EQ(changed.size(), objectCells(m));
  for (auto idx : changed) EXPECT_TRUE(m.isObjectIndex(idx));
}

TEST(DynamicGridMapScenes, GrowingTheMapKeepsSAndDAligned) {
  DynamicGridMap m = emptyMap();
  for (int k = 0; k < 20; ++k) scanWall(m);
  for (int k = 0; k < 5; ++k) scanWall(m, 0.65);
  ASSERT_TRUE(m.isObjectCell(56, 50));
  const double ox = m.idx2x(56), oy = m.idx2y(50);
  const float s_before = m.staticOccupancy(60, 50);
  const std::size_t objects_before = objectCells(m);
  const double wx = m.idx2x(60);
  // A scan far outside the initial bounds grows the grid on every side it reaches.
  m.insertObservation(*makeScan({5.0f}, 0.01), CPose3D(-20, -20, 0, 0, 0, 0));
  m.insertObservation(*makeScan({5.0f}, 0.01), CPose3D(20, 20, 0, 0, 0, 0));
  ASSERT_GT(m.getSizeX(), 100u);
  ASSERT_EQ(m.dynamicRaw().size(), m.getRawMap().size());
  EXPECT_TRUE(m.isObjectCell(m.x2idx(ox), m.y2idx(oy)));
  EXPECT_FLOAT_EQ(m.staticOccupancy(m.x2idx(wx), m.y2idx(oy)), s_before);
  EXPECT_EQ(objectCells(m), objects_before);
}

TEST(DynamicGridMapScenes, SetSizeGivesSAndDTheNewGeometryTogether) {
  DynamicGridMap m = emptyMap();
  for (int k = 0; k < 20; ++k) scanWall(m);
  for (int k = 0; k < 5; ++k) scanWall(m, 0.65);
  const double ox = m.idx2x(56), oy = m.idx2y(50);
  m.setSize(-8, 8, -6, 6, static_cast<float>(kRes));
  EXPECT_TRUE(m.layersAligned());
  ASSERT_EQ(m.dynamicRaw().size(), m.getRawMap().size());
  EXPECT_TRUE(m.isObjectCell(m.x2idx(ox), m.y2idx(oy)));               // D kept where it was
  EXPECT_FLOAT_EQ(m.staticOccupancy(m.x2idx(ox), m.y2idx(oy)), 0.5f);  // S refilled, as MRPT does
}

TEST(DynamicGridMapScenes, ResizingSAloneThroughTheBaseNeverReadsDOutOfItsBounds) {
  DynamicGridMap m = emptyMap();
  for (int k = 0; k < 20; ++k) scanWall(m);
  for (int k = 0; k < 5; ++k) scanWall(m, 0.65);
  const double ox = m.idx2x(56), oy = m.idx2y(50);
  mrpt::maps::COccupancyGridMap2D& base = m;  // the base's setSize is not virtual
  base.setSize(-30, 30, -30, 30, static_cast<float>(kRes));
  EXPECT_FALSE(m.layersAligned());
  std::size_t objects = 0;  // every cell of the new geometry asked: in bounds (ASan checks)
  for (unsigned y = 0; y < m.getSizeY(); ++y) {
    for (unsigned x = 0; x < m.getSizeX(); ++x) {
      objects += m.isObjectCell(static_cast<int>(x), static_cast<int>(y)) ? 1 : 0;
      EXPECT_GE(m.dynamicOccupancy(static_cast<int>(x), static_cast<int>(y)), 0.5f);
    }
  }
  EXPECT_GT(objects, 0u);
  EXPECT_EQ(m.countCells().dynamic_occupied, objects);
  // The next insertion realigns D with S, keeping each D cell at its place in the world (a beam
  // looking the other way, so the model leaves the object's cells as they were).
  m.insertObservation(*makeScan({1.0f}, 0.01), CPose3D(0.05, 0.05, 0, M_PI, 0, 0));
  EXPECT_TRUE(m.layersAligned());
  EXPECT_TRUE(m.isObjectCell(m.x2idx(ox), m.y2idx(oy)));
}

}  // namespace
}  // namespace dynamap

namespace dynamap {
namespace {

TEST(DynamicGridMap, AFullCircleOfBeamsFreesEveryCellWithinItExactlyOnce) {
  // The swept disc's rows run from a cell or two (near its top and bottom) to ~40 cells (its
  // middle): short rows, rows of whole 16-cell blocks and rows whose last block overlaps the one
  // before. Each cell within must take exactly one miss per scan, whichever way it was freed.
  DynamicGridMap m = tableMap();
  const std::vector<float> ranges(720, 2.0f);
  const auto miss = [&](int n) {
    return std::vector<int>{n * m.deltas().s_miss, n * m.deltas().d_miss};
  };
  for (int scan = 1; scan <= 2; ++scan) {
    ASSERT_TRUE(m.insertObservation(*makeScan(ranges, 2 * M_PI - 2 * M_PI / 720), kRobot));
    std::size_t once = 0;
    for (int cy = 0; cy < static_cast<int>(m.getSizeY()); ++cy) {
      for (int cx = 0; cx < static_cast<int>(m.getSizeX()); ++cx) {
        const std::size_t i = cx + cy * m.getSizeX();
        const std::vector<int> cell{m.getRawMap()[i], m.dynamicRaw()[i]};
        const double r = std::hypot(m.idx2x(cx) - 0.05, m.idx2y(cy) - 0.05);
        if (r < 1.7) {
          ASSERT_EQ(cell, miss(scan)) << "cell " << cx << "," << cy << " after scan " << scan;
        }
        once += cell == miss(scan) ? 1 : 0;
      }
    }
    // Every cell the scan freed was freed once: none twice, none left out of the count.
    EXPECT_EQ(m.lastInsertStats().free_cells, once) << "scan " << scan;
  }
}

TEST(DynamicGridMap, EveryScanUpdatesItsCellsAfterTheScanMarksWrapRound) {
  // The marks that keep a scan from updating a cell twice start again every 255 scans. A cell
  // left marked from before would be skipped: then a scan would update fewer cells than the same
  // scan does in a fresh map of the same geometry. 600 scans from poses that wander and return.
  const std::vector<float> ranges(91, 3.0f);
  std::size_t compared = 0;
  DynamicGridMap run = emptyMap();
  for (int k = 0; k < 600; ++k) {
    const CPose3D pose(1.5 * std::cos(k * 0.05), 1.5 * std::sin(k * 0.031), k * 0.2, 0, 0, 0);
    ASSERT_TRUE(run.insertObservation(*makeScan(ranges, M_PI), pose));
    DynamicGridMap fresh = emptyMap();
    ASSERT_TRUE(fresh.insertObservation(*makeScan(ranges, M_PI), pose));
    ASSERT_EQ(run.getSizeX(), fresh.getSizeX());  // nothing grew: the same cell geometry
    ASSERT_EQ(run.lastInsertStats().free_cells, fresh.lastInsertStats().free_cells) << "scan " << k;
    ASSERT_EQ(run.lastInsertStats().hit_cells, fresh.lastInsertStats().hit_cells) << "scan " << k;
    ++compared;
  }
  EXPECT_EQ(compared, 600u);
}

// A prior session's S: loaded cell for cell at its place, D empty, and refused at another
// resolution or beyond the largest map.
TEST(DynamicGridMap, LoadStaticTakesAnotherSessionsCellsAsTheyWere) {
  DynamicGridMap first;
  const CPose2D pose(0.3, -0.2, 0.4);
  first.insertObservation(*makeScan(std::vector<float>(181, 3.0f), M_PI), CPose3D(pose));
  const std::vector<std::int8_t> cells(first.getRawMap().begin(), first.getRawMap().end());
  DynamicGridMap second;
  second.loadStatic(first.getXMin(), first.getYMin(), first.getResolution(), first.getSizeX(),
                    first.getSizeY(), cells);
  EXPECT_EQ(second.getXMin(), first.getXMin());
  EXPECT_EQ(second.getYMin(), first.getYMin());
  EXPECT_EQ(second.getSizeX(), first.getSizeX());
  EXPECT_EQ(second.getSizeY(), first.getSizeY());
  EXPECT_EQ(std::vector<std::int8_t>(second.getRawMap().begin(), second.getRawMap().end()), cells);
  EXPECT_TRUE(second.layersAligned());
  for (const auto d : second.dynamicRaw()) ASSERT_EQ(d, 0);
  EXPECT_THROW(second.loadStatic(0, 0, 0.1, 4, 4, std::vector<std::int8_t>(16, 0)),
               std::invalid_argument);
  EXPECT_THROW(second.loadStatic(0, 0, 0.05, 4, 4, std::vector<std::int8_t>(15, 0)),
               std::invalid_argument);
  EXPECT_THROW(second.loadStatic(0, 0, 0.05, 100000, 1, std::vector<std::int8_t>(100000, 0)),
               std::invalid_argument);  // 5 km: past max_map_size_m
}

}  // namespace
}  // namespace dynamap
