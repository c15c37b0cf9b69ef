// Mapper::continueFrom: a session continued from a prior state keeps the prior's S and its
// table even when no scan of the new log could be mapped, and its change report is then empty.

#include <gtest/gtest.h>

#include "dynamap/pipeline/mapper.h"

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

TEST(SessionContinue, APriorOfAnotherResolutionDoesNotFit) {
  MapConfig config;
  config.map.resolution = 0.1;
  Mapper mapper(config);
  EXPECT_THROW(mapper.continueFrom(priorState()), std::invalid_argument);
}

}  // namespace
}  // namespace dynamap
