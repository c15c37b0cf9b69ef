// Pictures of the maps: north up, one pixel per cell, the grey and red levels of S and D.

#include "dynamap/outputs/render.h"

#include <gtest/gtest.h>

#include <array>

#include "../test_util.h"
#include "dynamap/pipeline/session_changes.h"

namespace dynamap {
namespace {

using mrpt::poses::CPose3D;

// A 2 x 1 m grid of 0.1 m cells with one object in D and a wall in S, seen from the left.
DynamicGridMap scene() {
  DynamicMapOptions o;
  o.resolution = 0.1;
  DynamicGridMap m(o, {}, 0, 2, 0, 1);
  // A wall at x = 1.55 m, then an object appears at 0.95 m in the space S knows free.
  for (int k = 0; k < 20; ++k)
    m.insertObservation(*test::makeScan({1.5f}, 0.001), CPose3D(0.05, 0.55, 0, 0, 0, 0));
  for (int k = 0; k < 5; ++k)
    m.insertObservation(*test::makeScan({0.9f}, 0.001), CPose3D(0.05, 0.55, 0, 0, 0, 0));
  return m;
}

std::uint8_t greyAt(const mrpt::img::CImage& img, int x, int y) {
  return *img.ptr<std::uint8_t>(static_cast<unsigned>(x), static_cast<unsigned>(y));
}

TEST(Render, StaticIsOneGreyPixelPerCellNorthUp) {
  const DynamicGridMap m = scene();
  const mrpt::img::CImage img = renderStatic(m);
  ASSERT_EQ(img.getWidth(), m.getSizeX());
  ASSERT_EQ(img.getHeight(), m.getSizeY());
  const int wall_x = m.x2idx(1.55), row_y = m.y2idx(0.55);
  const int py = static_cast<int>(m.getSizeY()) - 1 - row_y;  // row 0 is the largest y
  EXPECT_LT(greyAt(img, wall_x, py), 40);                     // occupied: dark
  EXPECT_GT(greyAt(img, m.x2idx(0.5), py), 215);              // crossed: light
  EXPECT_EQ(greyAt(img, wall_x, 0), greyAt(img, 0, 0));       // unknown: the prior's grey
  EXPECT_NEAR(greyAt(img, 0, 0), 127, 1);
}

TEST(Render, DynamicShowsDsObjectInRedAndSsWallInGrey) {
  const DynamicGridMap m = scene();
  const mrpt::img::CImage img = renderDynamic(m);
  ASSERT_EQ(img.getWidth(), m.getSizeX());
  const int py = static_cast<int>(m.getSizeY()) - 1 - m.y2idx(0.55);
  const auto* obj =
      img.ptr<std::uint8_t>(static_cast<unsigned>(m.x2idx(0.95)), static_cast<unsigned>(py));
  EXPECT_GT(obj[2], 150);  // BGR: red dominates
  EXPECT_LT(obj[1], 100);
  const auto* wall =
      img.ptr<std::uint8_t>(static_cast<unsigned>(m.x2idx(1.55)), static_cast<unsigned>(py));
  EXPECT_EQ(wall[0], wall[2]);  // grey, not red
  EXPECT_LT(wall[0], 250);
}

TEST(Render, PixelsAndScales) {
  EXPECT_EQ(overlayScale(100), 8);  // small maps are scaled up, at most 8 times
  EXPECT_EQ(overlayScale(300), 3);
  EXPECT_EQ(overlayScale(2000), 1);
  const DynamicGridMap m = scene();
  const View v{0, 0, static_cast<int>(m.getSizeX()), static_cast<int>(m.getSizeY()), 4};
  const Pixel p = toPixel(m, v, m.idx2x(3), m.idx2y(2));
  EXPECT_NEAR(p.x, 3 * 4 + 2, 1);  // the cell's centre, scaled
  EXPECT_NEAR(p.y, (static_cast<int>(m.getSizeY()) - 1 - 2) * 4 + 2, 1);
}

TEST(Render, PlainGridOnStaticGeometryKeepsSizeOriginAndResolution) {
  const DynamicGridMap m = scene();  // 20 x 10 cells from (0, 0)
  // A plain grid of another extent: 1 m more to the west, less to the east.
  mrpt::maps::COccupancyGridMap2D plain(-1, 1.5, 0, 1, 0.1f);
  plain.setCell(plain.x2idx(0.55), plain.y2idx(0.55), 0.0f);  // occupied at (0.55, 0.55)
  const mrpt::img::CImage img = renderStaticOn(plain, m);
  EXPECT_EQ(img.getWidth(), m.getSizeX());
  EXPECT_EQ(img.getHeight(), m.getSizeY());
  const int top = static_cast<int>(m.getSizeY()) - 1;
  auto pixelOf = [&](double x, double y) {  // S's cell of (x, y), north up
    return std::pair<int, int>{m.x2idx(x), top - m.y2idx(y)};
  };
  const auto [ox, oy] = pixelOf(0.55, 0.55);
  EXPECT_EQ(greyAt(img, ox, oy), 0);  // the occupied cell, at its place in S's grid
  const auto [fx, fy] = pixelOf(0.25, 0.55);
  EXPECT_EQ(greyAt(img, fx, fy), DynamicGridMap::l2p_255(0));  // observed by neither
  // East of the plain grid (x > 1.5 m): never observed there, the prior's grey.
  const auto [ex, ey] = pixelOf(1.85, 0.35);
  EXPECT_EQ(greyAt(img, ex, ey), DynamicGridMap::l2p_255(0));
}

TEST(Render, OverlayHasItsLegendStripBelowTheMap) {
  const DynamicGridMap m = scene();
  const View v = observedView(m);
  const mrpt::img::CImage img = renderOverlay(m, {});
  EXPECT_EQ(img.getWidth(), static_cast<std::size_t>((v.cx1 - v.cx0) * v.scale));
  EXPECT_GT(img.getHeight(), static_cast<std::size_t>((v.cy1 - v.cy0) * v.scale));
  EXPECT_EQ(img.getHeight() % 2, 0u);  // video frames need even sizes
}

// The first cell value whose grey lies in [lo, hi] other than `not_this` (cell values span the
// int8 range).
std::int8_t cellOfGrey(int lo, int hi, int not_this) {
  for (int v = -127; v <= 127; ++v) {
    const int g = DynamicGridMap::cellGrey(static_cast<DynamicGridMap::cellType>(v));
    if (g >= lo && g <= hi && g != not_this) return static_cast<std::int8_t>(v);
  }
  ADD_FAILURE() << "no cell value of grey " << lo << ".." << hi;
  return 0;
}

// A change report's map is the prior's S in three tones, the changes in colour: a wall black,
// free space white (even where its shade is not), the unknown and the unsure the unknown's
// grey, an added structure's cells green.
TEST(Render, ChangesShowThePriorInThreeTonesAndTheChangesInColour) {
  SessionState prior;
  prior.resolution = 0.05;
  prior.size_x = 20;
  prior.size_y = 10;
  prior.static_cells.assign(200, 0);  // unknown
  const std::int8_t wall = cellOfGrey(0, 60, -1), pale = cellOfGrey(180, 240, -1),
                    unsure = cellOfGrey(95, 160, 127);
  const auto at = [&](int x, int y) -> std::int8_t& { return prior.static_cells[x + 20 * y]; };
  at(2, 5) = wall;
  at(3, 5) = pale;
  at(4, 5) = unsure;
  DynamicGridMap map;
  map.loadStatic(0, 0, 0.05, 20, 10, prior.static_cells);
  const SessionChanges changes(prior, ChangeOptions{}, ObjectOptions{});
  ChangeRow added;
  added.kind = "structure_added";
  added.region = {{6, 5}};
  const mrpt::img::CImage img = renderChanges(map, changes, {added});
  const View v = observedView(map);
  const auto bgr = [&](int x, int y) {
    const Pixel p = toPixel(map, v, map.idx2x(x), map.idx2y(y));
    const auto* c = img.ptr<std::uint8_t>(static_cast<unsigned>(p.x), static_cast<unsigned>(p.y));
    return std::array<int, 3>{c[0], c[1], c[2]};
  };
  EXPECT_EQ(bgr(2, 5), (std::array<int, 3>{0, 0, 0}));
  EXPECT_EQ(bgr(3, 5), (std::array<int, 3>{255, 255, 255}));
  EXPECT_EQ(bgr(4, 5), (std::array<int, 3>{127, 127, 127}));
  EXPECT_EQ(bgr(8, 2), (std::array<int, 3>{127, 127, 127}));  // never observed
  const auto green = bgr(6, 5);
  EXPECT_GT(green[1], 100);
  EXPECT_LT(green[2], 50);
}

}  // namespace
}  // namespace dynamap
