// The three paths of a miss (scalar, SSE2 blocks of 16 cells, AVX2 blocks of 32) forced one at a
// time over the same scans: S, D, the scan stamps' effect (cells updated per scan) and the list
// of D cells that crossed the object threshold must come out the same, cell by cell.

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "../test_util.h"
#include "dynamap/mapping/dynamic_grid_map.h"

namespace dynamap {
namespace {

using mrpt::poses::CPose2D;
using mrpt::poses::CPose3D;
using Path = DynamicGridMap::MissPath;

struct MappedLayers {
  std::vector<DynamicGridMap::cellType> s, d;
  std::vector<std::size_t> freed;                   // cells a miss updated, per scan
  std::vector<std::vector<std::uint32_t>> crossed;  // D cells across the threshold, per scan
};

// 120 scans of 361 beams from poses that wander through a 12 x 9 m room, a 0.4 m box in it
// that moves twice: long rows of swept area (blocks of 32 and 16 and their ragged ends), short
// rows near the swept disc's top and bottom, beam tails, and D cells crossing both ways.
MappedLayers mapWith(Path path) {
  DynamicGridMap::forceMissPath(path);
  DynamicMapOptions o;
  o.resolution = 0.05;
  o.d_min = 0.05;  // D falls far enough for every miss to show
  DynamicGridMap map(o, {}, -7, 7, -5, 5);
  MappedLayers run;
  for (int k = 0; k < 120; ++k) {
    const CPose2D pose(2.5 * std::cos(k * 0.07), 1.8 * std::sin(k * 0.05), k * 0.13);
    std::vector<float> ranges = test::roomRanges(-6, 6, -4.5, 4.5, pose, 361, 2 * M_PI * 0.99);
    const double bx = k < 40 ? 1.0 : (k < 80 ? -2.0 : 3.0), by = k < 80 ? 1.5 : -2.0;
    for (int i = 0; i < 361; ++i) {  // the box: a disc of 0.2 m radius
      const double a = pose.phi() + (-M_PI * 0.99) + i * (2 * M_PI * 0.99 / 360);
      const double dx = bx - pose.x(), dy = by - pose.y();
      const double along = dx * std::cos(a) + dy * std::sin(a);
      const double off = std::abs(-dx * std::sin(a) + dy * std::cos(a));
      if (along > 0 && off < 0.2) ranges[i] = std::min<float>(ranges[i], along - 0.2f);
    }
    EXPECT_TRUE(map.insertObservation(*test::makeScan(ranges, 2 * M_PI * 0.99),
                                      CPose3D(pose.x(), pose.y(), 0, pose.phi(), 0, 0)));
    run.freed.push_back(map.lastInsertStats().free_cells);
    run.crossed.push_back(map.changedObjectCells());
  }
  run.s = map.getRawMap();
  run.d = map.dynamicRaw();
  DynamicGridMap::forceMissPath(Path::Auto);
  return run;
}

void expectSame(const MappedLayers& a, const MappedLayers& b) {
  ASSERT_EQ(a.s.size(), b.s.size());
  for (std::size_t i = 0; i < a.s.size(); ++i) {
    ASSERT_EQ(a.s[i], b.s[i]) << "S cell " << i;
    ASSERT_EQ(a.d[i], b.d[i]) << "D cell " << i;
  }
  EXPECT_EQ(a.freed, b.freed);
  EXPECT_EQ(a.crossed, b.crossed);
}

TEST(MissKernel, ScalarSse2AndAvx2GiveTheSameCells) {
  const MappedLayers scalar = mapWith(Path::Scalar);
  std::size_t crossings = 0;
  for (const auto& c : scalar.crossed) crossings += c.size();
  EXPECT_GT(crossings, 0u);  // the box's moves took D cells across the threshold
  if (!DynamicGridMap::missPathAvailable(Path::Sse2)) GTEST_SKIP() << "no SSE2 in this build";
  expectSame(scalar, mapWith(Path::Sse2));
  if (!DynamicGridMap::missPathAvailable(Path::Avx2)) GTEST_SKIP() << "no AVX2 here";
  expectSame(scalar, mapWith(Path::Avx2));
}

TEST(MissKernel, AutoIsTheFastestPathThereIs) {
  EXPECT_TRUE(DynamicGridMap::missPathAvailable(Path::Auto));
  EXPECT_TRUE(DynamicGridMap::missPathAvailable(Path::Scalar));
  expectSame(mapWith(Path::Auto),
             mapWith(DynamicGridMap::missPathAvailable(Path::Avx2) ? Path::Avx2 : Path::Sse2));
}

}  // namespace
}  // namespace dynamap
