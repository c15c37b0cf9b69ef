// CLEAR MOT as the evaluation counts it (docs/evaluation.md), on hand-written person truth and
// tracks.

#include <gtest/gtest.h>

#include <cmath>

#include "dynamap/evaluation/evaluation.h"

namespace dynamap {
namespace {

using sim::BodyKind;

TruthRow personAt(std::size_t scan, int id, double x, double y, int hits = 5) {
  TruthRow r;
  r.scan_index = scan;
  r.kind = sim::BodyKind::Person;
  r.id = id;
  r.x = x;
  r.y = y;
  r.diameter = 0.4;
  r.hits = hits;
  return r;
}

TEST(ClearMot, CountsMatchesMissesFalsePositivesAndSwitches) {
  std::vector<TruthRow> truth;
  std::vector<PersonTrackRow> tracks;
  for (std::size_t k = 0; k < 10; ++k) {
    truth.push_back(personAt(k, 1, 0.1 * k, 0));
    truth.push_back(personAt(k, 2, 0.1 * k, 3, k == 9 ? 2 : 5));  // scan 9: 2 beams, not counted
    // Person 1: track 7 at 0.1 m, but scans 6.. track 8 takes over (one switch); scan 3 missed.
    if (k != 3) tracks.push_back({k, k < 6 ? 7 : 8, 0.1 * k + 0.1, 0});
    // Person 2: track 9 at 0.05 m every scan (at scan 9 matched to an uncounted person).
    tracks.push_back({k, 9, 0.1 * k, 3.05});
    // A ghost 5 m from everyone at scans 0 and 1.
    if (k < 2) tracks.push_back({k, 10, 5, 5});
  }
  const MotScores s = evaluateClearMot(truth, tracks);
  EXPECT_EQ(s.ground_truth, 19u);
  EXPECT_EQ(s.matches, 18u);
  EXPECT_EQ(s.misses, 1u);
  EXPECT_EQ(s.false_positives, 2u);
  EXPECT_EQ(s.id_switches, 1u);
  ASSERT_EQ(s.switches.size(), 1u);  // where it happened, for report.md
  EXPECT_EQ(s.switches[0].scan_index, 6u);
  EXPECT_EQ(s.switches[0].person, 1);
  EXPECT_EQ(s.switches[0].from_id, 7);
  EXPECT_EQ(s.switches[0].to_id, 8);
  EXPECT_NEAR(s.mota, 1.0 - 4.0 / 19.0, 1e-12);
  EXPECT_NEAR(s.motp_m, (9 * 0.1 + 9 * 0.05) / 18.0, 1e-9);
  EXPECT_EQ(s.people, 2u);
  EXPECT_EQ(s.track_ids, 4u);
}

// A walker at 1 m/s (5 scans/s) who stands 3 s at x = 2 and then walks on: a switch as they walk
// off is at a stop, one 10 s later is not, nor one just after the walker turns back (no stop).
TEST(ClearMot, SwitchesWhileStandingOrWalkingOffAreAtAStop) {
  std::vector<TruthRow> truth;
  std::vector<PersonTrackRow> tracks;
  double x = 0;
  for (std::size_t k = 0; k < 150; ++k) {
    const double t = 0.2 * static_cast<double>(k);
    if (t >= 2.0 && t < 5.0) {
      x = 2.0;  // standing
    } else {
      x = t < 2.0 ? t : (t < 20.0 ? 2.0 + (t - 5.0) : 17.0 - (t - 20.0));  // back from x = 17
    }
    TruthRow r = personAt(k, 1, x, 0);
    r.t = t;
    truth.push_back(r);
    // Track 1 until 5.4 s (walking off), 2 until 15 s, 3 until 20.4 s (after the turn), then 4.
    const int id = t < 5.4 ? 1 : (t < 15.0 ? 2 : (t < 20.4 ? 3 : 4));
    tracks.push_back({k, id, x, 0});
  }
  const MotScores s = evaluateClearMot(truth, tracks);
  ASSERT_EQ(s.id_switches, 3u);
  EXPECT_EQ(s.id_switches_at_stops, 1u);
  EXPECT_TRUE(s.switches[0].at_stop);   // 5.4 s: walking off, 0.4 s after the stop
  EXPECT_FALSE(s.switches[1].at_stop);  // 15 s: 10 s after it
  EXPECT_FALSE(s.switches[2].at_stop);  // 20.4 s: the turn at x = 17 is no stop
  MotOptions o;
  o.after_stop_s = 0.2;  // a shorter walking-off window leaves the first switch out too
  EXPECT_EQ(evaluateClearMot(truth, tracks, o).id_switches_at_stops, 0u);
}

TEST(ClearMot, TrackBeyondTheGateIsAMissAndAFalsePositive) {
  const std::vector<TruthRow> truth = {personAt(0, 1, 0, 0)};
  const std::vector<PersonTrackRow> tracks = {{0, 1, 0.8, 0}};
  const MotScores s = evaluateClearMot(truth, tracks);
  EXPECT_EQ(s.misses, 1u);
  EXPECT_EQ(s.false_positives, 1u);
  EXPECT_DOUBLE_EQ(s.mota, -1.0);
}
}  // namespace
}  // namespace dynamap
