// eval --sessions' scoring: each truth change found, under a wrong id, misplaced or missed, and
// the report's rows that match none are false; parts of one wall are no false changes.

#include <gtest/gtest.h>

#include "dynamap/evaluation/session_scores.h"

namespace dynamap {
namespace {

MaybePoint at(double x, double y) {
  return {true, x, y};
}

ScoredRow row(const std::string& kind, int id, MaybePoint from, MaybePoint to, int session = 0) {
  ScoredRow r;
  r.session = session;
  r.kind = kind;
  r.id = id;
  r.size = 0.3;
  r.from = from;
  r.to = to;
  return r;
}

// Session 2's truth: object 4 (table id 7 at (1, 1)) moved to (3, 1); object 5 of S moved;
// object 6 new; object 8 gone; wall 9 added from (0, -2) to (2, -2).
std::vector<ScoredRow> truth() {
  return {row("object_moved", 4, at(1, 1), at(3, 1), 2),
          row("object_moved", 5, at(-1, -1), at(-3, -1), 2),
          row("object_new", 6, {}, at(0, 3), 2),
          row("object_gone", 8, at(4, 4), {}, 2),
          row("structure_added", 9, at(0, -2), at(2, -2), 2),
          row("object_new", 1, {}, at(9, 9), 3)};  // another session's: not scored
}

const std::vector<TableRow> kTable = {{7, 0.3, 1.02, 0.98}, {2, 0.4, 8, 8}};

TEST(SessionScores, EveryVerdict) {
  const std::vector<ScoredRow> report = {
      row("object_moved", 7, at(1.0, 1.0), at(3.1, 1.0)),       // found (the table's id)
      row("object_moved", 12, at(-1.0, -1.0), at(-2.0, -1.0)),  // misplaced: the end is off
      row("object_new", 2, {}, at(0.1, 3.0)),                   // wrong id: 2 is the table's
      row("structure_added", 1, {}, at(0.5, -2.1)),             // found
      row("structure_added", 2, {}, at(1.8, -1.9)),             // a part of the same wall
      row("object_gone", 0, at(6, 6), {}),                      // false; object 8 missed
  };
  const SessionScore s = scoreSession(2, truth(), report, kTable);
  ASSERT_EQ(s.changes.size(), 5u);
  EXPECT_EQ(s.changes[0].verdict, ChangeVerdict::Found);
  EXPECT_EQ(s.changes[0].expected_id, 7);
  EXPECT_EQ(s.changes[1].verdict, ChangeVerdict::Misplaced);
  EXPECT_EQ(s.changes[1].expected_id, -1);
  EXPECT_EQ(s.changes[2].verdict, ChangeVerdict::WrongId);
  EXPECT_EQ(s.changes[3].verdict, ChangeVerdict::Missed);
  EXPECT_EQ(s.changes[4].verdict, ChangeVerdict::Found);
  ASSERT_EQ(s.false_changes.size(), 1u);
  EXPECT_EQ(s.false_changes[0], 5);
  EXPECT_EQ(s.count(ChangeVerdict::Found), 2);
}

TEST(SessionScores, AMoveUnderAnotherIdThanTheTablesIsAWrongId) {
  const std::vector<ScoredRow> report = {row("object_moved", 3, at(1, 1), at(3, 1))};
  const SessionScore s = scoreSession(2, truth(), report, kTable);
  EXPECT_EQ(s.changes[0].verdict, ChangeVerdict::WrongId);
  EXPECT_TRUE(s.false_changes.empty());
}

TEST(SessionScores, EachReportedRowServesOneChangeAtMost) {
  // One gone row at object 8's place, and a second one there: the second is false.
  const std::vector<ScoredRow> report = {row("object_gone", 0, at(4, 4), {}),
                                         row("object_gone", 0, at(4.1, 4), {})};
  const SessionScore s = scoreSession(2, truth(), report, kTable);
  EXPECT_EQ(s.changes[3].verdict, ChangeVerdict::Found);
  EXPECT_EQ(s.changes[3].reported, 0);
  EXPECT_EQ(s.false_changes, std::vector<int>{1});
}

TEST(SessionScores, ARegionFarFromTheWallIsFalse) {
  const std::vector<ScoredRow> report = {row("structure_added", 1, {}, at(1, -3))};
  const SessionScore s = scoreSession(2, truth(), report, kTable);
  EXPECT_EQ(s.changes[4].verdict, ChangeVerdict::Missed);
  EXPECT_EQ(s.false_changes.size(), 1u);
}

}  // namespace
}  // namespace dynamap
