// Why a move was not detected (explainMisses) on hand-written truth, tracks and people.

#include <gtest/gtest.h>

#include "dynamap/evaluation/evaluation.h"

namespace dynamap {
namespace {

using sim::BodyKind;

// Scans at 1 Hz; object 1 (0.3 m) jumps from (0, 0) to (5, 0) in [2, 3] and is seen by
// `hits` beams at every scan; visible from scan 3, its window (10 s) scans 3 to 13.
struct Case {
  std::vector<TruthRow> rows;
  std::vector<TruthMove> moves;
  std::vector<TrackRow> tracks;
  std::vector<PersonTrackRow> people;

  explicit Case(int hits = 10) {
    TruthMove m;
    m.move_id = m.object_id = 1;
    m.t_start = 2.0, m.t_end = 3.0;
    m.to = {5, 0};
    moves.push_back(m);
    for (std::size_t k = 0; k < 20; ++k) {
      const double t = static_cast<double>(k);
      rows.push_back({k, t, BodyKind::Object, 1, t < 3 ? 0.0 : 5.0, 0.0, 0.3, hits});
    }
  }
  void person(std::size_t from, std::size_t to, double x, double y) {
    for (std::size_t k = from; k < to; ++k) people.push_back({k, 7, x, y});
  }
  /// Object 4 reported at (x, 0) at scan `scan`.
  void report(std::size_t scan, double x) {
    TrackRow r;
    r.scan_index = scan;
    r.object_id = 4;
    r.cx = x;
    tracks.push_back(r);
  }
  MissCause cause() const {
    EvalOptions o;
    o.detect_window_scans = 10;
    o.few_views_scans = 8;
    ObjectScores s = evaluateObjects(rows, moves, tracks, o);
    explainMisses(s, rows, moves, tracks, people, o);
    return s.moves.at(0).missed_because;
  }
};

TEST(MissCauses, SeenOftenAndNothingNearIsUnreported) {
  EXPECT_EQ(Case().cause(), MissCause::Unreported);
  EXPECT_STREQ(toString(MissCause::Unreported), "unreported");
}

TEST(MissCauses, SeenInFewScansOfItsWindow) {
  Case c;
  // Seen at scans 3-9 (7 of them, fewer than 8), then by two beams only.
  for (auto& r : c.rows) r.hits = r.scan_index <= 9 ? 10 : 2;
  EXPECT_EQ(c.cause(), MissCause::FewViews);
  c.rows[10].hits = 10;  // an eighth view
  EXPECT_EQ(c.cause(), MissCause::Unreported);
}

TEST(MissCauses, APersonTrackOnItsPlaceForFiveScans) {
  Case c;
  c.person(3, 7, 5.2, 0.1);  // four scans within 0.15 + 0.15 m
  EXPECT_EQ(c.cause(), MissCause::Unreported);
  c.person(7, 8, 5.2, 0.1);  // a fifth
  EXPECT_EQ(c.cause(), MissCause::PersonOnPlace);
}

TEST(MissCauses, PeopleWithinAMetre) {
  Case c;
  c.person(3, 8, 5.7, 0.0);  // 0.7 m off: near, not on its place
  EXPECT_EQ(c.cause(), MissCause::PeopleNear);
  Case late;
  late.person(14, 20, 5.0, 0.0);  // on it, after its window
  EXPECT_EQ(late.cause(), MissCause::Unreported);
}

TEST(MissCauses, AnObjectReportedNearButOffItsPlace) {
  Case c;
  c.report(6, 5.6);  // 0.6 m off: no match (max(0.25, 0.3) m)
  EXPECT_EQ(c.cause(), MissCause::ReportedOffPlace);
  c.person(3, 8, 5.0, 0.0);  // a person on its place comes first
  EXPECT_EQ(c.cause(), MissCause::PersonOnPlace);
}

TEST(MissCauses, ADetectedMoveHasNoCause) {
  Case c;
  c.report(5, 5.05);
  EXPECT_EQ(c.cause(), MissCause::None);
  EXPECT_EQ(toString(MissCause::None), nullptr);
}

}  // namespace
}  // namespace dynamap
