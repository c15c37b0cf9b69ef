// Mapper::continueFrom: a session continued from a prior state keeps the prior's S and its
// table even when no scan of the new log could be mapped, and its change report is then empty.
// SessionChanges::priorOnGrid: the prior's S on a grid grown from it, or laid elsewhere; and the
// places of the prior's S an object left that gridChanges finds.

#include <gtest/gtest.h>

#include <cmath>

#include "dynamap/pipeline/mapper.h"
#include "dynamap/pipeline/session_changes.h"

namespace dynamap {
namespace {

SessionState priorState() {
  SessionState s;
  s.resolution = 0.05;
  s.x_min = -1;
  s.y_min = -2;
  s.size_x = 40;
  s.size_y = 20;
  s.static_cells.assign(800, 20);  // free everywhere...
  s.static_cells[5] = -60;         // ...but one occupied cell
  s.objects = {{1, "present", 0.5, -1.5, 0.3, 1, 10, 20}, {2, "retracted", 0, 0, 0.2, 0, 11, 12}};
  s.sessions = 4;
  return s;
}

TEST(SessionContinue, WithNoScanMappedTheStateIsThePriorsAndNothingChanged) {
  Mapper mapper{MapConfig{}};
  mapper.continueFrom(priorState());
  const SessionState again = mapper.sessionState();
  EXPECT_EQ(again.sessions, 5);
  EXPECT_EQ(again.static_cells, priorState().static_cells);
  EXPECT_EQ(again.x_min, -1);
  EXPECT_EQ(again.y_min, -2);
  ASSERT_EQ(again.objects.size(), 2u);
  EXPECT_EQ(again.objects[0].state, "present");
  EXPECT_EQ(again.objects[1].state, "retracted");
  EXPECT_EQ(again.objects[0].cx, 0.5);
  ASSERT_NE(mapper.changes(), nullptr);
  EXPECT_TRUE(mapper.changes()->report(mapper.map(), mapper.tracker()).empty());
}

// The prior's S laid on the map's grid: cell by cell what priorCell says at each centre, on the
// prior's own grid, on that grid grown (whole cells, on every side), and on a finer grid whose
// cells do not line up with the prior's. Returns how many cells hold the prior's occupied one.
int expectPriorOnGridIsPriorCell(const DynamicGridMap& map, const SessionChanges& changes) {
  const std::vector<std::int8_t> on_grid = changes.priorOnGrid(map);
  EXPECT_EQ(on_grid.size(), static_cast<std::size_t>(map.getSizeX()) * map.getSizeY());
  int occupied = 0;
  for (unsigned y = 0; y < map.getSizeY(); ++y) {
    for (unsigned x = 0; x < map.getSizeX(); ++x) {
      const std::int8_t want = changes.priorCell(map.idx2x(x), map.idx2y(y));
      EXPECT_EQ(on_grid[x + static_cast<std::size_t>(y) * map.getSizeX()], want) << x << " " << y;
      occupied += want == -60 ? 1 : 0;
    }
  }
  return occupied;
}

TEST(SessionContinue, ThePriorOnTheMapsGridIsThePriorCellAtEachCentre) {
  const SessionState prior = priorState();
  const SessionChanges changes(prior, ChangeOptions{}, ObjectOptions{});
  DynamicGridMap map;
  map.loadStatic(prior.x_min, prior.y_min, prior.resolution, prior.size_x, prior.size_y,
                 prior.static_cells);
  EXPECT_EQ(expectPriorOnGridIsPriorCell(map, changes), 1);
  EXPECT_EQ(changes.priorOnGrid(map)[5], -60);  // the same grid: the same index
  map.resizeGrid(-3.0f, 2.5f, -2.75f, 0.5f, 0.5f, false);  // grown on every side
  EXPECT_EQ(expectPriorOnGridIsPriorCell(map, changes), 1);
  EXPECT_EQ(changes.priorOnGrid(map)[5], 0);  // moved: cell 5 is off the prior's grid now
  map.setSize(-1.5f, 1.5f, -2.5f, -0.5f, 0.03f, 0.5f);  // 3 cm cells: 1-4 in the 5 cm one
  const int finer = expectPriorOnGridIsPriorCell(map, changes);
  EXPECT_GE(finer, 1);
  EXPECT_LE(finer, 4);
}

// A 4 x 4 m prior, free but for the half of a 0.6 m object's outline facing -x (sure
// occupied), with what lies inside and behind it never seen; the map starts as that prior.
struct SeenThroughScene {
  SessionState prior;
  DynamicGridMap map;
  std::vector<std::pair<int, int>> arc, inside;
  SeenThroughScene() {
    prior.resolution = 0.05;
    prior.size_x = prior.size_y = 80;
    prior.static_cells.assign(6400, 100);  // surely free
    for (int y = 0; y < 80; ++y) {
      for (int x = 0; x < 80; ++x) {
        const double cx = (x + 0.5) * 0.05 - 2.0, cy = (y + 0.5) * 0.05 - 2.0;
        const double d = std::hypot(cx, cy);
        std::int8_t& v = prior.static_cells[x + 80 * y];
        if (d <= 0.3 && d >= 0.25 && cx < 0) arc.push_back({x, y}), v = -100;
        if (d < 0.25 || (cx >= 0 && std::abs(cy) < 0.3)) inside.push_back({x, y}), v = 0;
      }
    }
    map.loadStatic(0, 0, 0.05, 80, 80, prior.static_cells);
  }
  std::vector<ChangeRow> vacated() const {
    return SessionChanges(prior, ChangeOptions{}, ObjectOptions{}).gridChanges(map).vacated;
  }
};

TEST(SessionChangesGrid, APlaceSeenThroughButNotYetFreeIsWhereAnObjectWent) {
  SeenThroughScene scene;
  EXPECT_TRUE(scene.vacated().empty());  // nothing changed
  for (const auto& [x, y] : scene.arc) scene.map.setCell(x, y, 0.4f);  // P(occ) 0.6: unsure
  EXPECT_TRUE(scene.vacated().empty());  // no longer sure, but nothing seen behind it
  for (const auto& [x, y] : scene.inside) scene.map.setCell(x, y, 0.95f);  // seen free
  const std::vector<ChangeRow> v = scene.vacated();
  ASSERT_EQ(v.size(), 1u);
  EXPECT_EQ(v[0].kind, "vacated_seen_through");
  EXPECT_NEAR(v[0].from_x, 2.0, 0.05);
  EXPECT_NEAR(v[0].from_y, 2.0, 0.05);
  EXPECT_NEAR(v[0].size, 0.6, 0.1);
}

TEST(SessionChangesGrid, AnOutlineStillSureIsNoPlaceLeftWhateverIsSeenBehindIt) {
  SeenThroughScene scene;
  for (const auto& [x, y] : scene.inside) scene.map.setCell(x, y, 0.95f);
  EXPECT_TRUE(scene.vacated().empty());
}

TEST(SessionChangesGrid, AnOutlineSeenFreeIsAPlaceLeftOnceNotTwice) {
  SeenThroughScene scene;
  for (const auto& [x, y] : scene.arc) scene.map.setCell(x, y, 0.97f);  // free: removed
  for (const auto& [x, y] : scene.inside) scene.map.setCell(x, y, 0.95f);
  const std::vector<ChangeRow> v = scene.vacated();
  ASSERT_EQ(v.size(), 1u);
  EXPECT_EQ(v[0].kind, "vacated");
}

TEST(SessionContinue, APriorOfAnotherResolutionDoesNotFit) {
  MapConfig config;
  config.map.resolution = 0.1;
  Mapper mapper(config);
  EXPECT_THROW(mapper.continueFrom(priorState()), std::invalid_argument);
}

}  // namespace
}  // namespace dynamap
