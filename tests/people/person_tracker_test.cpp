// PersonTracker: the Kalman filter, and whole runs of the Mapper over small simulated worlds
// (known poses) in which walkers walk, cross, follow a wall, stop, and a cylinder is moved.

#include "dynamap/people/person_tracker.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

#include "../test_util.h"
#include "dynamap/base/ini.h"
#include "dynamap/pipeline/mapper.h"
#include "dynamap/sim/scenario.h"
#include "dynamap/sim/simulator.h"

namespace dynamap {
namespace {

TEST(ConstantVelocityFilter, ConvergesToTheVelocityOfEvenlySpacedPositions) {
  ConstantVelocityFilter f(0, 0, 0.05, 1.0);
  for (int k = 1; k <= 50; ++k) {
    f.predict(0.2, 1.0);
    f.update(0.2 * k * 1.2, -0.2 * k * 0.5, 0.05);  // 1.2 m/s along x, -0.5 along y
  }
  EXPECT_NEAR(f.vx(), 1.2, 0.01);
  EXPECT_NEAR(f.vy(), -0.5, 0.01);
  EXPECT_NEAR(f.x(), 12.0, 0.01);
}

TEST(ViewDisc, OccupiedEmptyAndUnseen) {
  ScanHits h;
  h.max_range = 8;
  for (int i = 0; i < 181; ++i) h.angles.push_back(-M_PI / 2 + M_PI * i / 180);
  h.ranges.assign(181, 5.0f);
  EXPECT_EQ(viewDisc(h, 3, 0, 0.2), DiscView::Empty);     // beams pass through to 5 m
  EXPECT_EQ(viewDisc(h, 5, 0, 0.2), DiscView::Occupied);  // they end there
  EXPECT_EQ(viewDisc(h, 7, 0, 0.2), DiscView::Unseen);    // hidden behind the 5 m surface
  EXPECT_EQ(viewDisc(h, -3, 0, 0.2), DiscView::Unseen);   // behind the sensor
}

TEST(ViewDisc, ABeamWithoutEchoSeesOnlyAsFarAsTheSensorReaches) {
  // An 8 m laser that saw nothing; the grid inserts up to 15 m. A disc 5 m out was seen empty,
  // one 10 m out was not seen at all (before: "empty", and a person walking out of the laser's
  // range was taken for gone).
  std::vector<float> none(181, 0.0f);  // every beam without an echo
  const auto scan = test::makeScan(none, M_PI, 0.0, 8.0f);
  const ScanHits h = scanHits(*scan, mrpt::poses::CPose2D(0, 0, 0), 15.0);
  EXPECT_DOUBLE_EQ(h.max_range, 8.0);
  EXPECT_EQ(viewDisc(h, 5, 0, 0.2), DiscView::Empty);
  EXPECT_EQ(viewDisc(h, 10, 0, 0.2), DiscView::Unseen);
}

// Feeds a tracker `dets_of(t)` every 0.2 s up to `until` s; returns the first time a person is
// reported, or -1.
template <typename F>
double firstReported(F dets_of, double until) {
  PersonTracker tracker;
  const ScanHits nothing;
  for (int k = 0; 0.2 * k <= until; ++k) {
    const double t = 0.2 * k;
    tracker.update(dets_of(t), nothing, t);
    if (!tracker.reported().empty()) return t;
  }
  return -1;
}

TEST(PersonTracker, TwoLegsWalkingOffFromAnObjectsPlaceAreAPersonSoon) {
  // Something stands 2 s next to an object (near_static), then walks off along x at 1 m/s.
  auto walker = [](int legs) {
    return [legs](double t) {
      PersonDetection d{t < 2 ? 0.0 : t - 2, 0, legs};
      d.near_static = t < 3;  // the object's place is left behind after a metre
      return std::vector<PersonDetection>{d};
    };
  };
  // Seen as a pair of legs: a person after confirm_s (0.6 s) of walking and 0.5 m.
  const double legs = firstReported(walker(2), 6);
  EXPECT_GE(legs, 2.6);
  EXPECT_LE(legs, 3.0);
  // One cluster, as a moved object is seen: it must keep moving confirm_static_s (6 s).
  EXPECT_EQ(firstReported(walker(0), 6), -1);
  EXPECT_GE(firstReported(walker(0), 10), 8.0);
}

// One cluster glides off at 1 m/s from where it appeared, by a wall (not near_static); its
// place is seen empty from the second scan on (static_left on the next two detections): it must
// keep moving confirm_static_s, like an object. Without static_left it is a person at once.
TEST(PersonTracker, AClusterSeenLeavingAPlaceSHeldIsJudgedAsAnObjectMovingOff) {
  auto glide = [](bool left) {
    return [left](double t) {
      PersonDetection d{t, 0, 0};
      d.static_left = left && t > 0.1 && t < 0.5;
      return std::vector<PersonDetection>{d};
    };
  };
  EXPECT_LE(firstReported(glide(false), 6), 1.0);
  EXPECT_EQ(firstReported(glide(true), 5.8), -1);
  EXPECT_GE(firstReported(glide(true), 10), 6.0);
}

TEST(PersonTracker, LegsSeenAsAPairOneScanInTwoAreLegs) {
  // A walker seen across the beams: one leg hides the other every other scan. Walking off from
  // an object's place, it is a person after confirm_s, not confirm_static_s.
  auto gait = [](double t) {
    const int k = static_cast<int>(std::lround(t / 0.2));
    PersonDetection d{t < 2 ? 0.0 : t - 2, 0, k % 2 == 1 ? 2 : 1};  // a pair in every second scan, never more
    d.near_static = t < 3;
    return std::vector<PersonDetection>{d};
  };
  const double t = firstReported(gait, 6);
  EXPECT_GE(t, 2.6);
  EXPECT_LE(t, 3.2);
  TentativeState st;
  st.detections = 6;
  st.leg_pairs = 3;
  EXPECT_TRUE(st.mostlyLegs());
  st.leg_pairs = 2;  // a third is not more than a third
  EXPECT_FALSE(st.mostlyLegs());
}

TEST(PersonTracker, ALegLeftOverBesideAPersonIsNoNewTrack) {
  // A person walks along x at 1 m/s, seen as a pair. From 2 s a single leg is also detected
  // 0.3 m beside them (the pairing left it over): no second track. A leg 1 m away is someone.
  for (const double off : {0.3, 1.0}) {
    PersonTracker tracker;
    const ScanHits nothing;
    std::size_t most = 0;
    for (int k = 0; k <= 20; ++k) {
      const double t = 0.2 * k;
      std::vector<PersonDetection> dets{{t, 0, 2}};
      if (t >= 2) dets.push_back({t, off, 1});
      tracker.update(dets, nothing, t);
      most = std::max(most, tracker.tracks().size());
    }
    EXPECT_EQ(most, off < 0.4 ? 1u : 2u) << "leg " << off << " m beside";
  }
}

TEST(PersonTracker, AWalkerNoLongerDetectedIsNotHeldByTheWallBesideThem) {
  // A walker goes along x at 1 m/s, 0.1 m from a wall (y = 0.1) that every beam of a sensor at
  // (0, -3) ends on. Detected until 2 s, then not: beams still end within hold_radius of where
  // they would be, but on the wall. Walking, they are not held there (before, the track walked
  // on along the wall, reported every scan, as long as the wall went on).
  ScanHits wall;
  wall.sensor_x = 0;
  wall.sensor_y = -3;
  wall.max_range = 20;
  for (int i = 1; i < 180; ++i) {
    const double a = M_PI * i / 180;
    wall.angles.push_back(a);
    wall.ranges.push_back(static_cast<float>(3.1 / std::sin(a)));
  }
  PersonTracker tracker;
  std::size_t reported_after = 0;
  for (int k = 0; k <= 25; ++k) {
    const double t = 0.2 * k;
    std::vector<PersonDetection> dets;
    if (t <= 2.0) dets.push_back({-2 + t, 0, 2});
    tracker.update(dets, wall, t);
    if (t <= 2.0) continue;
    reported_after += tracker.reported().size();
  }
  EXPECT_EQ(reported_after, 0u);
}

// --- runs over simulated worlds ----------------------------------------------------------------

// A 20 m wide hall, 2 * half_height tall; the robot stands at `robot` ("x y") looking along +x
// with a 361-beam, 180 deg, 20 m laser at 5 Hz (every beam echoes; insertion cuts at 15 m); `extra` adds [objects], [moves], [people].
// Walkers walk across the robot's view: one walking straight away from a standing robot walks
// into its own shadow, where S has never seen the floor free.
std::string hall(const std::string& extra, double duration_s, const std::string& robot = "-9 0",
                 double half_height = 5) {
  const std::string h = std::to_string(half_height), mh = std::to_string(-half_height);
  return "[scenario]\nname = t\nduration_s = " + std::to_string(duration_s) +
         "\nseed = 7\n[world]\nwall.1 = -10 " + mh + " 10 " + mh + "\nwall.2 = 10 " + mh + " 10 " +
         h + "\nwall.3 = 10 " + h + " -10 " + h + "\nwall.4 = -10 " + h + " -10 " + mh +
         "\n[robot]\nwaypoints = " + robot +
         "\n[laser]\nbeams = 361\nfov_deg = 180\nmax_range_m = 20\nrange_noise_std_m = 0.01\n" +
         extra;
}

struct Row {
  double t;
  PersonRow p;
};
struct WorldRun {
  std::vector<Row> rows;               // every reported person, every scan
  std::vector<sim::ScanTruth> truth;   // every scan
  std::vector<PersonSummary> people;
  std::size_t objects = 0;  // ever reported, withdrawn ones included
  std::vector<TrackedObject> table;  // the final table (objects.csv): present or absent ones
  std::size_t withdrawn = 0;
};

WorldRun runWorld(const std::string& ini_text, MapConfig config = {}) {
  const sim::Scenario sc = sim::parseScenario(IniFile::fromText(ini_text, "t.ini"), ".");
  Mapper mapper(config);
  sim::Simulator simulator(sc);
  sim::ScanTruth st;
  WorldRun out;
  while (simulator.next(st)) {
    std::vector<float> ranges(st.ranges.size());
    for (std::size_t i = 0; i < ranges.size(); ++i) ranges[i] = st.valid[i] ? st.ranges[i] : 0.f;
    ScanRecord rec;
    rec.index = st.index;
    rec.t = st.t;
    rec.pose = mrpt::poses::CPose2D(st.pose.x, st.pose.y, st.pose.phi);
    rec.scan = test::makeScan(ranges, sc.laser.fov_deg * M_PI / 180, st.t, 20.0f);
    mapper.process(rec);
    for (const PersonRow& p : mapper.people().reported()) out.rows.push_back({st.t, p});
    out.truth.push_back(st);
  }
  out.people = mapper.people().summaries();
  out.objects = mapper.tracker().objects().size();
  for (const TrackedObject& o : mapper.tracker().objects()) {
    if (o.state == ObjectState::Withdrawn) {
      ++out.withdrawn;
    } else if (listedInTable(o.state)) {
      out.table.push_back(o);
    }
  }
  return out;
}

// The true centre of person `id` at scan k (between its legs).
sim::Vec2 truthOf(const sim::Scenario& sc, int id, double t) {
  for (const auto& p : sc.people) {
    if (p.id == id) return sim::personPositionAt(p, t);
  }
  return {};
}

// The person ids reported within `gate` of the true person `id`, over the run but for
// [skip_from, skip_to] (while two walkers are too close together to tell whose row is whose).
std::set<int> idsNear(const WorldRun& r, const sim::Scenario& sc, int id, double gate,
                      double skip_from = 0, double skip_to = -1) {
  std::set<int> ids;
  for (const Row& row : r.rows) {
    if (row.t >= skip_from && row.t <= skip_to) continue;
    const sim::Vec2 c = truthOf(sc, id, row.t);
    if (std::hypot(row.p.x - c.x, row.p.y - c.y) < gate) ids.insert(row.p.person_id);
  }
  return ids;
}

sim::Scenario scenarioOf(const std::string& text) {
  return sim::parseScenario(IniFile::fromText(text, "t.ini"), ".");
}

TEST(PersonTracking, ConstantVelocityWalkerHasOneIdAndItsVelocity) {
  const std::string text =
      hall("[people]\nperson.1 = 0.45 1.0  -3 -4.5  -3 4.5\nlegs.1 = 0.15 0.25\n", 8.8);
  const WorldRun r = runWorld(text);
  ASSERT_EQ(r.people.size(), 1u);
  ASSERT_GT(r.rows.size(), 5u);
  for (const Row& row : r.rows) EXPECT_EQ(row.p.person_id, 1);
  // Its velocity, averaged over the rows before it turns at the end of its path (8.5 s).
  double vx = 0, vy = 0;
  int n = 0;
  for (const Row& row : r.rows) {
    if (row.t > 8.4) continue;
    vx += row.p.vx;
    vy += row.p.vy;
    ++n;
  }
  ASSERT_GT(n, 3);
  EXPECT_NEAR(vx / n, 0.0, 0.1);
  EXPECT_NEAR(vy / n, 1.0, 0.1);
  const Row& last = r.rows.back();
  const sim::Vec2 c = truthOf(scenarioOf(text), 1, last.t);
  EXPECT_NEAR(last.p.x, c.x, 0.15);
  EXPECT_NEAR(last.p.y, c.y, 0.1);
  EXPECT_EQ(r.objects, 0u);
}

TEST(PersonTracking, TwoWalkersCrossingKeepTheirIds) {
  // Both wait 3 s behind the robot (out of its view), then walk diagonally across the hall at
  // 0.8 m/s, crossing at (-3.3, 0) at 12.3 s.
  const std::string text = hall(
      "[people]\nperson.1 = 0.45 0.8  -9.6 -4  3 4\nlegs.1 = 0.15 0.25\npause.1 = 1 1 3\n"
      "person.2 = 0.45 0.8  -9.6 4  3 -4\nlegs.2 = 0.15 0.25\npause.2 = 2 1 3\n",
      20);
  const sim::Scenario sc = scenarioOf(text);
  const WorldRun r = runWorld(text);
  // Within 0.4 m of each other from 11.8 s to 12.8 s.
  const std::set<int> a = idsNear(r, sc, 1, 0.4, 11.5, 13.1);
  const std::set<int> b = idsNear(r, sc, 2, 0.4, 11.5, 13.1);
  ASSERT_EQ(a.size(), 1u);
  ASSERT_EQ(b.size(), 1u);
  EXPECT_NE(*a.begin(), *b.begin());
  // Both are still tracked after the crossing.
  bool a_after = false, b_after = false;
  for (const Row& row : r.rows) {
    if (row.t < 15) continue;
    a_after |= row.p.person_id == *a.begin();
    b_after |= row.p.person_id == *b.begin();
  }
  EXPECT_TRUE(a_after);
  EXPECT_TRUE(b_after);
}

TEST(PersonTracking, WalkerAlongAWallIsTrackedAndTheWallIsNot) {
  // Along the wall y = -5, the body's edge 0.1 m from it, after 3 s behind the robot.
  const std::string text = hall(
      "[people]\nperson.1 = 0.45 1.0  -9.6 -4.675  6 -4.675\nlegs.1 = 0.15 0.25\n"
      "pause.1 = 1 1 3\n",
      17);
  const WorldRun r = runWorld(text);
  ASSERT_EQ(r.people.size(), 1u);
  EXPECT_EQ(idsNear(r, scenarioOf(text), 1, 0.3), std::set<int>{1});
  for (const Row& row : r.rows) EXPECT_GT(row.p.y, -4.9) << "t = " << row.t;
}

TEST(PersonTracking, WalkerWhoStopsKeepsTheId) {
  // Walks 8 m, stands 12 s at (-3, 3.5), walks back.
  const std::string text = hall(
      "[people]\nperson.1 = 0.45 1.0  -3 -4.5  -3 3.5\nlegs.1 = 0.15 0.25\npause.1 = 1 2 12\n",
      28);
  const sim::Scenario sc = scenarioOf(text);
  MapConfig config;
  config.people.exclusion_radius = 0.5;  // and no object is confirmed where they stand
  const WorldRun r = runWorld(text, config);
  ASSERT_EQ(r.people.size(), 1u);
  EXPECT_EQ(idsNear(r, sc, 1, 0.4), std::set<int>{1});
  // Reported all the time it stands (8 s .. 20 s) and after it walks on.
  std::size_t standing = 0, after = 0;
  for (const Row& row : r.rows) {
    standing += row.t > 8.5 && row.t < 19.5;
    after += row.t > 21;
  }
  EXPECT_EQ(standing, 55u);
  EXPECT_GT(after, 20u);
  EXPECT_EQ(r.objects, 0u);
}

TEST(PersonTracking, WalkerWhoStopsOutOfViewKeepsTheId) {
  // The robot at (-5, 0) faces east 12 s, turns, faces west 8 s (away), turns back east at
  // about 22 s. The walker comes from (6, 2), stands at (0, 2) from 6 s to 26 s, walks back.
  // Unseen while it stood, nobody saw the place empty: looked at again, the one standing there
  // is the same person, reported again before they walk on, with the same id.
  const std::string robot =
      "-5 0  -3.8 0  -4.6 0  -3.8 0\nloop = false\nspeed_mps = 0.1\nturn_rate_dps = 90";
  const std::string text = hall(
      "[people]\nperson.1 = 0.45 1.0  6 2  0 2\nlegs.1 = 0.13 0.25\npause.1 = 1 2 20\n", 34,
      robot);
  const WorldRun r = runWorld(text);
  ASSERT_EQ(r.people.size(), 1u);
  std::size_t away = 0, back_standing = 0;
  for (const Row& row : r.rows) {
    away += row.t > 15 && row.t < 21;
    back_standing += row.t > 24 && row.t < 25.8;
  }
  EXPECT_EQ(away, 0u);  // not reported where it is not seen
  EXPECT_GE(back_standing, 5u);
}

TEST(PersonTracking, MovedCylinderIsNoPerson) {
  // A 0.4 m cylinder glides 5 m in 5 s (a walker's pace), then stands; one jumps 3 m at once.
  const std::string text = hall(
      "[objects]\nobject.1 = 0.4 -3 -4\nobject.2 = 0.3 -4 2\n[moves]\nmove.1 = 4 1 -3 1 5\n"
      "move.2 = 10 2 -1 2 0\n",
      25);
  const WorldRun r = runWorld(text);
  EXPECT_TRUE(r.people.empty());
  EXPECT_TRUE(r.rows.empty());
}

// Walks 4.6 m from (-5, -3) to behind the standing robot (x < -9, out of its 180 deg view),
// stands there 6 s (longer than coast_s: the track is lost), and walks back into view.
const char* kBehindTheRobot =
    "[people]\nperson.1 = 0.45 1.0  -5 -3  -9.6 -3\nlegs.1 = 0.15 0.25\npause.1 = 1 2 6\n";

TEST(PersonTracking, WalkerBackInViewGetsTheirIdBack) {
  const std::string text = hall(kBehindTheRobot, 20);
  const WorldRun r = runWorld(text);
  ASSERT_EQ(r.people.size(), 1u);
  EXPECT_EQ(idsNear(r, scenarioOf(text), 1, 0.5), std::set<int>{1});
  // Seen before it leaves (t < 4) and again after it is back in view (t > 13).
  std::size_t before = 0, after = 0;
  for (const Row& row : r.rows) {
    before += row.t < 4;
    after += row.t > 13;
  }
  EXPECT_GT(before, 5u);
  EXPECT_GT(after, 5u);
  // Without re-identification the walker back in view is a second person.
  MapConfig config;
  config.people.lost_s = 0;
  EXPECT_EQ(runWorld(text, config).people.size(), 2u);
}

TEST(PersonTracking, ALostIdIsNotGivenToSomeoneTooFarAwayToHaveWalkedThere) {
  // Walker 1 leaves the view as above at 4 s; walker 2 waits 5 s behind the robot too, 7 m from
  // walker 1, then walks into view: confirmed a moment after walker 1 went out of sight, it is
  // too far from them to be them (max_speed), though the only person the tracker lost.
  const std::string text = hall(std::string(kBehindTheRobot) +
                                    "person.2 = 0.45 1.0  -9.6 4  5 4\nlegs.2 = 0.15 0.25\n"
                                    "pause.2 = 2 1 5\n",
                                12);
  const sim::Scenario sc = scenarioOf(text);
  const WorldRun r = runWorld(text);
  ASSERT_EQ(r.people.size(), 2u);
  EXPECT_EQ(idsNear(r, sc, 1, 0.5), std::set<int>{1});
  EXPECT_EQ(idsNear(r, sc, 2, 0.5), std::set<int>{2});
  // Were people as fast as 20 m/s, walker 2 could be walker 1 back in view.
  MapConfig config;
  config.people.max_speed = 20;
  EXPECT_EQ(idsNear(runWorld(text, config), sc, 2, 0.5), std::set<int>{1});
}

TEST(PersonTracker, AnIdGivenBackIsNeverAlsoKeptByTheTrackThatHadIt) {
  // B stands at the origin (a tentative track); A walks from (5, 0) at 1 m/s, is a person,
  // and is unseen from 1 s on. From 3 s B walks: it is a lost person back in view, and takes
  // A's id. In the scan it does, A is detected again. Whatever that scan is, A's old track
  // must not go on as a person without an id.
  for (int back = 16; back <= 22; ++back) {
    PersonTracker tracker;
    const ScanHits nothing;  // no beam: every place unseen
    for (int k = 0; k <= back + 5; ++k) {
      const double t = 0.2 * k;
      std::vector<PersonDetection> dets;
      dets.push_back({t < 3 ? 0.0 : t - 3.0, 0, 0});
      if (t <= 1.0 || k >= back) dets.push_back({5 + t, 0, 0});
      tracker.update(dets, nothing, t);
      for (const PersonTrack& tr : tracker.tracks()) {
        if (tr.kind() != PersonState::Tentative && tr.kind() != PersonState::Ended) {
          EXPECT_NE(tr.id, 0) << "back at scan " << back << ", scan " << k;
        }
      }
      for (const PersonRow& r : tracker.reported()) EXPECT_GE(r.person_id, 1);
    }
  }
}

// A stands at (2, 0) from 2 s, seen, then out of view from 4 s. B, out of view from 2 s, comes
// back at 6 s at (3.5, 1.5), nearer where A stood than where B went: re-identification gives B
// A's id. At 10 s A walks off from their place. Unless `seen_empty_from` comes first (a beam
// through A's place from then on), A takes their id back and B goes on under a new one.
struct StoodUnseenRun {
  int a_id = 0, b_id = 0;  // reported at the end
  std::size_t ids = 0;     // people ever confirmed
};
StoodUnseenRun runStoodUnseen(double seen_empty_from) {
  PersonTracker tracker;
  // One beam from (2, -3) through where B comes back, to 10 m: B walks into view there (and is
  // taken back at once, reacquire_unseen_speed); every other place is unseen.
  ScanHits window;
  window.sensor_x = 2, window.sensor_y = -3, window.max_range = 10;
  window.angles = {std::atan2(1.5 + 3, 3.5 - 2)};
  window.ranges = {-1.f};
  ScanHits through = window;  // and one north, through A's place
  through.angles.push_back(M_PI / 2);
  through.ranges.push_back(-1.f);
  StoodUnseenRun out;
  for (int k = 0; k <= 65; ++k) {
    const double t = 0.2 * k;
    std::vector<PersonDetection> dets;
    if (t <= 4.0) dets.push_back({std::min(t, 2.0), 0, 0});             // A
    if (t >= 10.0) dets.push_back({2, -(t - 10), 0});                   // A walks off
    if (t <= 2.0) dets.push_back({8 - t, 3, 0});                        // B
    if (t >= 6.0) dets.push_back({3.5 + (t - 6), 1.5, 0});              // B back
    tracker.update(dets, t >= seen_empty_from ? through : window, t);
  }
  for (const PersonRow& r : tracker.reported()) {
    if (std::hypot(r.x - 2, r.y + 3) < 0.5) out.a_id = r.person_id;
    if (std::hypot(r.x - 10.5, r.y - 1.5) < 0.5) out.b_id = r.person_id;
  }
  out.ids = tracker.summaries().size();
  return out;
}

TEST(PersonTracker, SomeoneWhoStoodOutOfViewTakesTheirIdBackWhenTheyWalkOff) {
  const StoodUnseenRun r = runStoodUnseen(1e9);
  EXPECT_EQ(r.a_id, 1);
  EXPECT_EQ(r.b_id, 3);  // not 1: one id is one person at a time
  EXPECT_EQ(r.ids, 3u);
  // Their place seen empty before (from 8 s), they walked off unseen: the one who walks off
  // there later is re-identified as usual (B's id, B being the nearest lost person).
  const StoodUnseenRun seen = runStoodUnseen(8.0);
  EXPECT_EQ(seen.a_id, 2);
  EXPECT_EQ(seen.b_id, 1);
}

// A walks along x at 1 m/s, detected until 2 s, then unseen (lost from 6 s). At 8 s a body
// appears 4.5 m from A's last detection, its first views jumping 0.3 m along x (more of its
// outline coming into view) before it stands, or walking on at 1 m/s. When the scan before saw
// its place, it walked into view: A back at once. When the view came to it (nothing saw the
// place before) and A, unseen 6 s, would have had to walk there (beyond gate +
// reacquire_unseen_speed x 6 s = 2.4 m), the body that stands is no person; the one that walks
// on is A, once confirmed by walking (confirm_s, confirm_travel).
int idAppearingAt(bool place_seen_before, bool walks_on) {
  PersonTracker tracker;
  ScanHits unseen;  // no beam
  ScanHits seen;    // one beam from (6, -3) north through (6, 2), to 10 m
  seen.sensor_x = 6, seen.sensor_y = -3, seen.max_range = 10;
  seen.angles = {M_PI / 2};
  seen.ranges = {-1.f};
  int id = 0;
  for (int k = 0; k <= 60; ++k) {
    const double t = 0.2 * k;
    std::vector<PersonDetection> dets;
    if (t <= 2.0) dets.push_back({t, 0, 2});
    const double x = walks_on ? 6 + (t - 8) : 6 + std::min(0.3, 0.15 * std::round((t - 8) / 0.2));
    if (t >= 8.0) dets.push_back({x, 2, 0});
    tracker.update(dets, place_seen_before && t < 8.0 ? seen : unseen, t);
    for (const PersonRow& r : tracker.reported()) {
      if (t >= 8.0 && r.x > 5) id = r.person_id;
    }
  }
  return id;
}

TEST(PersonTracker, ABodyTheViewComesToFarFromWhereSomeoneWasLostIsNotThem) {
  EXPECT_EQ(idAppearingAt(true, false), 1);   // walked into view, then stood: A back
  EXPECT_EQ(idAppearingAt(false, false), 0);  // was there when the robot looked: no person
  EXPECT_EQ(idAppearingAt(false, true), 1);   // walks on: A, confirmed by walking
}

// --- people standing still, and the object table ---------------------------------------------

// The robot at (-5, 0) looks east 2 s (the floor at (0, 2) seen free), turns and drives west
// facing away 8 s, and turns back east at 14 s. Meanwhile a walker seen as two legs comes from
// (6, 2), unseen, and stands at (0, 2) from 10 s for `stand_s`, then walks back east: the robot
// first sees them standing, as D sees an object.
std::string standingWorld(const std::string& extra, double stand_s, double duration_s) {
  const std::string robot = "-5 0  -4 0  -8 0  -5 0\nloop = false\nspeed_mps = 0.5\nturn_rate_dps = 90";
  return hall("[people]\nperson.1 = 0.45 1.0  6 2  0 2\nlegs.1 = 0.13 0.25\npause.1 = 1 1 4\n"
              "pause.2 = 1 2 " + std::to_string(stand_s) + "\n" + extra,
              duration_s, robot);
}

TEST(PeopleAndObjects, LegsOfSomeoneFirstSeenStandingAreWithdrawnWhenTheyWalkOff) {
  const WorldRun r = runWorld(standingWorld("", 12, 30));
  EXPECT_GE(r.withdrawn, 1u);  // reported while they stood: nobody could tell yet
  EXPECT_TRUE(r.table.empty());
  EXPECT_EQ(r.people.size(), 1u);  // and they are a person once they walk
}

TEST(PeopleAndObjects, AnObjectPutDownBesideThemStays) {
  // A 0.35 m bin jumps (unseen, at 6 s) from the far south-east corner to beside the walker's
  // place: it is an object, and stays one after they walk off.
  const WorldRun r =
      runWorld(standingWorld("[objects]\nobject.1 = 0.35  9 -4.5\n[moves]\nmove.1 = 6 1 0.6 1.2 0\n",
                             12, 30));
  ASSERT_EQ(r.table.size(), 1u);
  EXPECT_NEAR(r.table[0].shape.cx, 0.6, 0.1);
  EXPECT_NEAR(r.table[0].shape.cy, 1.2, 0.1);
  EXPECT_EQ(r.table[0].state, ObjectState::Present);
  EXPECT_GE(r.withdrawn, 1u);
}

TEST(PeopleAndObjects, TwoSmallObjectsPutDownSideBySideStay) {
  // Leg-sized (0.18 m and 0.22 m), 0.5 m apart, both jumped there at once while the robot looks
  // away: as like a pair of legs as objects get. They never leave: they stay objects.
  const std::string robot = "-5 0  -4 0  -8 0  -5 0\nloop = false\nspeed_mps = 0.5\nturn_rate_dps = 90";
  const WorldRun r = runWorld(hall("[objects]\nobject.1 = 0.18  9 -4.5\nobject.2 = 0.22  9 4.5\n"
                                   "[moves]\nmove.1 = 5 1 0 2 0\nmove.2 = 5.4 2 0.5 2 0\n",
                                   30, robot));
  ASSERT_EQ(r.table.size(), 2u);
  EXPECT_EQ(r.withdrawn, 0u);
  for (const TrackedObject& o : r.table) EXPECT_EQ(o.state, ObjectState::Present);
}

}  // namespace
}  // namespace dynamap
