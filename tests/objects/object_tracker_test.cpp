// ObjectTracker: the events of a tracker fed by a real DynamicGridMap with synthetic scans.

#include "dynamap/objects/object_tracker.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "../test_util.h"
#include "dynamap/mapping/dynamic_grid_map.h"

namespace dynamap {
namespace {

struct Cylinder {
  double x, y, diameter;
};

// A scan from `pose` in the room [-3, 3]^2 with cylinders in it.
mrpt::obs::CObservation2DRangeScan::Ptr roomScan(const mrpt::poses::CPose2D& pose,
                                                 const std::vector<Cylinder>& cylinders,
                                                 int n = 361) {
  const double aperture = M_PI;
  auto ranges = test::roomRanges(-3, 3, -3, 3, pose, n, aperture);
  for (const Cylinder& c : cylinders) {
    const double r = c.diameter / 2, cx = c.x, cy = c.y;
    for (int i = 0; i < n; ++i) {
      const double a = pose.phi() - aperture / 2 + aperture * i / (n - 1);
      const double dx = cx - pose.x(), dy = cy - pose.y();
      const double along = dx * std::cos(a) + dy * std::sin(a);
      const double perp = -dx * std::sin(a) + dy * std::cos(a);
      if (along <= 0 || std::abs(perp) > r) continue;
      const double hit = along - std::sqrt(r * r - perp * perp);
      if (hit < ranges[i]) ranges[i] = static_cast<float>(hit);
    }
  }
  return test::makeScan(ranges, aperture);
}

// The tests below move objects every few seconds, sooner than min_rest_s would let a new one
// count: it has a test of its own (ANewObjectSeenGoneWithinMinRest...).
ObjectOptions quickMoves() {
  ObjectOptions o;
  o.min_rest_s = 0;
  return o;
}

struct TrackerRun {
  DynamicGridMap map;
  ObjectTracker tracker{quickMoves()};
  std::size_t index = 0;
  int beams = 361;  // over 180 degrees
  void steps(int n, const mrpt::poses::CPose2D& pose, const std::vector<Cylinder>& cylinders) {
    for (int i = 0; i < n; ++i) step(pose, cylinders);
  }
  void step(const mrpt::poses::CPose2D& pose, const std::vector<Cylinder>& cylinders) {
    const auto scan = roomScan(pose, cylinders, beams);
    map.insertObservation(*scan, mrpt::poses::CPose3D(pose));
    tracker.update(map, makeScanView(makeRangeData(*scan, 15.0, 0.05 * M_PI / 180.0), pose),
                   0.2 * index, index);
    ++index;
  }
  std::vector<ObjectEvent> events() const {
    std::vector<ObjectEvent> e;
    for (const auto& r : tracker.events()) e.push_back(r.event);
    return e;
  }
};

TEST(ObjectTracker, NewDisappearedReappearedMoved) {
  TrackerRun run;
  const mrpt::poses::CPose2D pose(-2.0, 0.0, 0.0);
  run.steps(10, pose, {});  // the empty room
  EXPECT_TRUE(run.tracker.objects().empty());
  run.steps(15, pose, {{1.0, 0.5, 0.4}});
  ASSERT_EQ(run.tracker.objects().size(), 1u);
  const TrackedObject& o = run.tracker.objects()[0];
  EXPECT_EQ(o.state, ObjectState::Present);
  EXPECT_NEAR(o.shape.size, 0.4, 0.05);
  EXPECT_NEAR(o.shape.cx, 1.0, 0.05);
  EXPECT_NEAR(o.shape.cy, 0.5, 0.05);
  run.steps(10, pose, {});  // taken away
  EXPECT_EQ(run.tracker.objects()[0].state, ObjectState::Absent);
  run.steps(15, pose, {{1.0, 0.5, 0.4}});  // back
  run.steps(10, pose, {});
  run.steps(15, pose, {{0.5, -1.5, 0.4}});  // elsewhere
  ASSERT_EQ(run.tracker.objects().size(), 1u);
  EXPECT_EQ(run.tracker.objects()[0].n_moves, 1);
  EXPECT_NEAR(run.tracker.objects()[0].shape.cx, 0.5, 0.05);
  EXPECT_NEAR(run.tracker.objects()[0].shape.cy, -1.5, 0.05);
  EXPECT_EQ(run.events(), (std::vector<ObjectEvent>{ObjectEvent::New, ObjectEvent::Disappeared,
                                                    ObjectEvent::Reappeared,
                                                    ObjectEvent::Disappeared, ObjectEvent::Moved}));
}

// A place passed by, seen in a few scans of one-degree beams: D has crossed the threshold on
// only part of the cylinder's arc when the robot turns away, so its cells and hit points show
// a part; the whole outlines those scans showed give its size.
TEST(ObjectTracker, APlacePassedByGetsTheSizeOfTheWholeOutlinesSeen) {
  TrackerRun run;
  run.beams = 181;
  const mrpt::poses::CPose2D ahead(-2.5, -2.0, 0.6), away(-2.5, -2.0, M_PI + 0.6);
  run.steps(10, ahead, {});
  const Cylinder bin{2.0, 0.5, 0.5};
  run.steps(5, ahead, {bin});
  run.steps(20, away, {bin});
  ASSERT_EQ(run.tracker.objects().size(), 1u);
  // Its cells and hit points alone: 0.27 m.
  EXPECT_NEAR(run.tracker.objects()[0].shape.size, 0.5, 0.03);
}

TEST(ObjectTracker, AnObjectWhereAPersonStandsIsReportedOnceTheyHaveLeft) {
  TrackerRun run;
  const mrpt::poses::CPose2D pose(-2.0, 0.0, 0.0);
  run.steps(10, pose, {});
  // Someone puts a bin down and stays beside it 4 s: no object while they are there...
  run.tracker.setKeepOut({{1.0, 0.5, 0.5}});
  run.steps(20, pose, {{1.0, 0.5, 0.4}});
  EXPECT_TRUE(run.tracker.objects().empty());
  // ...nor while its place is out of view once they have gone (what a person's legs left in
  // D, not yet seen empty, is no object)...
  run.tracker.setKeepOut({});
  run.steps(20, mrpt::poses::CPose2D(-2.0, 0.0, M_PI), {{1.0, 0.5, 0.4}});
  EXPECT_TRUE(run.tracker.objects().empty());
  // ...and the bin, whose cells no longer change, is reported once seen there again.
  run.steps(15, pose, {{1.0, 0.5, 0.4}});
  ASSERT_EQ(run.tracker.objects().size(), 1u);
  EXPECT_NEAR(run.tracker.objects()[0].shape.cx, 1.0, 0.05);
}

// A bin stands in view, and its cluster has begun to settle, when someone walks up and stays
// beside it: it is no part of them (they came to it), and it is reported while they stand
// there. (One that appears with them beside it waits until they have left: the test above.)
TEST(ObjectTracker, AnObjectSettlingBeforeSomeoneCameNearIsReportedWhileTheyStand) {
  TrackerRun run;
  const mrpt::poses::CPose2D pose(-2.0, 0.0, 0.0);
  run.steps(10, pose, {});
  run.steps(5, pose, {{1.0, 0.5, 0.4}});  // D has crossed, its size is settling
  ASSERT_TRUE(run.tracker.objects().empty());
  run.tracker.setKeepOut({{1.0, 0.5, 0.5}});  // someone walks up to it and stays
  run.steps(20, pose, {{1.0, 0.5, 0.4}});
  ASSERT_EQ(run.tracker.objects().size(), 1u);
  EXPECT_EQ(run.tracker.objects()[0].state, ObjectState::Present);
  EXPECT_NEAR(run.tracker.objects()[0].shape.cx, 1.0, 0.05);
}

TEST(ObjectTracker, AWithdrawnObjectIsNeverAnIdentityAgain) {
  TrackerRun run;
  const mrpt::poses::CPose2D pose(-2.0, 0.0, 0.0);
  run.steps(10, pose, {});
  run.steps(15, pose, {{1.0, 0.5, 0.4}});
  run.steps(10, pose, {});  // gone: absent
  ASSERT_EQ(run.tracker.objects().size(), 1u);
  EXPECT_TRUE(run.tracker.withdraw(1, 7.0, 35));
  EXPECT_EQ(run.tracker.objects()[0].state, ObjectState::Withdrawn);
  EXPECT_EQ(run.events().back(), ObjectEvent::Withdrawn);
  EXPECT_FALSE(run.tracker.withdraw(1, 7.0, 35));  // once
  EXPECT_FALSE(run.tracker.withdraw(2, 7.0, 35));  // no such object
  // The same size elsewhere would have "moved" there; it is a new object.
  run.steps(15, pose, {{0.5, -1.5, 0.4}});
  ASSERT_EQ(run.tracker.objects().size(), 2u);
  EXPECT_EQ(run.tracker.objects()[1].n_moves, 0);
  EXPECT_EQ(run.events().back(), ObjectEvent::New);
}

TEST(ObjectTracker, TwoSimilarSizesKeepTheirIds) {
  TrackerRun run;
  const mrpt::poses::CPose2D pose(-2.5, 0.0, 0.0);
  run.steps(10, pose, {});
  // Two objects of 0.30 and 0.35 m: sizes closer than the size tolerance.
  run.steps(15, pose, {{0.5, 1.0, 0.30}, {0.5, -1.0, 0.35}});
  ASSERT_EQ(run.tracker.objects().size(), 2u);
  const int id_30 = run.tracker.objects()[0].shape.cy > 0 ? 1 : 2;
  const int id_35 = 3 - id_30;
  // The 0.35 m one leaves (its place seen free), then turns up elsewhere: by size alone it
  // could be either; the one seen still in place is not it.
  run.steps(10, pose, {{0.5, 1.0, 0.30}});
  run.steps(15, pose, {{0.5, 1.0, 0.30}, {1.5, -0.2, 0.35}});
  ASSERT_EQ(run.tracker.objects().size(), 2u);
  const TrackedObject& moved = run.tracker.objects()[id_35 - 1];
  const TrackedObject& stayed = run.tracker.objects()[id_30 - 1];
  EXPECT_EQ(moved.state, ObjectState::Present);
  EXPECT_EQ(moved.n_moves, 1);
  EXPECT_NEAR(moved.shape.cx, 1.5, 0.05);
  EXPECT_EQ(stayed.state, ObjectState::Present);
  EXPECT_EQ(stayed.n_moves, 0);
}

// An object pushed 1.2 m across the room in 40 scans stays one object, and its row ends where
// it is: the row's shape is its track's estimate (the one copy), not one left at confirmation.
TEST(ObjectTracker, AnObjectPushedAcrossTheRoomStaysOneObjectAndItsRowFollowsIt) {
  TrackerRun run;
  const mrpt::poses::CPose2D pose(-2.0, 0.0, 0.0);
  run.steps(10, pose, {});
  run.steps(15, pose, {{1.0, 0.6, 0.4}});
  ASSERT_EQ(run.tracker.objects().size(), 1u);
  for (int i = 1; i <= 40; ++i) run.step(pose, {{1.0, 0.6 - 0.03 * i, 0.4}});  // to y = -0.6
  run.steps(15, pose, {{1.0, -0.6, 0.4}});
  ASSERT_EQ(run.tracker.objects().size(), 1u);
  const TrackedObject& o = run.tracker.objects()[0];
  EXPECT_EQ(o.state, ObjectState::Present);
  EXPECT_NEAR(o.shape.cx, 1.0, 0.05);
  EXPECT_NEAR(o.shape.cy, -0.6, 0.05);
  EXPECT_NEAR(o.shape.size, 0.4, 0.05);
  EXPECT_EQ(run.events(), (std::vector<ObjectEvent>{ObjectEvent::New, ObjectEvent::Moved}));
  EXPECT_NEAR(run.tracker.events().back().cy, -0.6, 0.05);
}

// An object of the same size appearing behind the robot seconds after the first was seen in
// place is another object: the first cannot have crossed the room unseen (min_unseen_s).
int objectsAfterATwinAppearsBehind(double min_unseen_s) {
  ObjectOptions o = quickMoves();
  o.min_unseen_s = min_unseen_s;
  TrackerRun run{DynamicGridMap(), ObjectTracker(o)};
  const mrpt::poses::CPose2D ahead(0.0, 0.0, 0.0), behind(0.0, 0.0, M_PI);
  run.steps(10, ahead, {});
  run.steps(15, ahead, {{1.0, 0.5, 0.4}});
  run.steps(10, behind, {{1.0, 0.5, 0.4}});  // it is out of view now
  run.steps(15, behind, {{1.0, 0.5, 0.4}, {-1.5, 0.0, 0.4}});
  return static_cast<int>(run.tracker.objects().size());
}

TEST(ObjectTracker, AnObjectSeenInPlaceSecondsAgoIsNotTakenForOneThatMovedUnseen) {
  EXPECT_EQ(objectsAfterATwinAppearsBehind(30.0), 2);
  // Without the rule the twin is taken for the first object, moved.
  EXPECT_EQ(objectsAfterATwinAppearsBehind(0.0), 1);
}

// Object A (0.30 m) leaves its place and one of its size turns up 2.5 m away while object B,
// of size `b_size`, stands in the room: a match farther than far_match_distance needs a size
// no other known object has as nearly.
std::size_t objectsAfterAFarMatch(double far_match_distance, double b_size) {
  ObjectOptions o = quickMoves();
  o.far_match_distance = far_match_distance;
  TrackerRun run{DynamicGridMap(), ObjectTracker(o)};
  const mrpt::poses::CPose2D pose(-2.5, 0.0, 0.0);
  run.steps(10, pose, {});
  run.steps(15, pose, {{1.5, 1.2, 0.30}, {1.5, -1.2, b_size}});
  run.steps(10, pose, {{1.5, -1.2, b_size}});  // A's place seen empty
  run.steps(15, pose, {{1.5, -1.2, b_size}, {-0.5, -0.3, 0.30}});
  return run.tracker.objects().size();
}

TEST(ObjectTracker, AFarMatchIsTakenOnlyForASizeNoOtherObjectShares) {
  EXPECT_EQ(objectsAfterAFarMatch(10.0, 0.31), 2u);  // near enough: A moved
  EXPECT_EQ(objectsAfterAFarMatch(2.0, 0.31), 3u);   // far, B of A's size: a new object
  EXPECT_EQ(objectsAfterAFarMatch(2.0, 0.50), 2u);   // far, A's size its own: A moved
}

// Objects A and B, both 0.30 m, out of view; A turns up behind the robot and is taken for B,
// nearer. The robot turns back: A's place is seen empty, B's seen still occupied. B gets its
// place back, and the detection the identity that fits now: A, moved; not a third object.
TEST(ObjectTracker, ARevivedPlaceGivesItsDetectionTheIdentityThatFitsNow) {
  ObjectOptions o = quickMoves();
  o.min_unseen_s = 5;
  TrackerRun run{DynamicGridMap(), ObjectTracker(o)};
  const mrpt::poses::CPose2D ahead(0.0, 0.0, 0.0), behind(0.0, 0.0, M_PI);
  const Cylinder a{1.5, -1.0, 0.30}, b{1.5, 1.0, 0.30}, a_moved{-1.5, 0.5, 0.30};
  run.steps(10, ahead, {});
  run.steps(10, behind, {});
  run.steps(15, ahead, {a, b});
  ASSERT_EQ(run.tracker.objects().size(), 2u);
  const int id_a = run.tracker.objects()[0].shape.cy < 0 ? 1 : 2;
  const int id_b = 3 - id_a;
  run.steps(40, behind, {a, b});  // 8 s out of view
  run.steps(20, behind, {b, a_moved});
  ASSERT_EQ(run.tracker.objects().size(), 2u);  // taken for B, the nearer
  EXPECT_NEAR(run.tracker.objects()[id_b - 1].shape.cx, a_moved.x, 0.05);
  run.steps(25, ahead, {b, a_moved});
  ASSERT_EQ(run.tracker.objects().size(), 2u);
  const TrackedObject& oa = run.tracker.objects()[id_a - 1];
  const TrackedObject& ob = run.tracker.objects()[id_b - 1];
  EXPECT_EQ(oa.state, ObjectState::Present);
  EXPECT_NEAR(oa.shape.cx, a_moved.x, 0.05);
  EXPECT_NEAR(oa.shape.cy, a_moved.y, 0.05);
  EXPECT_EQ(oa.n_moves, 1);
  EXPECT_EQ(ob.state, ObjectState::Present);
  EXPECT_NEAR(ob.shape.cx, b.x, 0.05);
  EXPECT_NEAR(ob.shape.cy, b.y, 0.05);
  EXPECT_EQ(ob.n_moves, 0);
}

// Scans `c` from `pose` (at most 30) until the tracker's last event is `until`; the scans from
// the first one that put an object cell in D to then.
std::size_t scansFromDTo(TrackerRun& run, const mrpt::poses::CPose2D& pose, const Cylinder& c,
                         ObjectEvent until) {
  std::size_t crossed = 0;
  for (int i = 0; i < 30 && (run.events().empty() || run.events().back() != until); ++i) {
    run.step(pose, {c});
    if (!crossed && run.tracker.objectCellCount() > 0) crossed = run.index - 1;
  }
  EXPECT_GT(crossed, 0u);
  EXPECT_FALSE(run.events().empty());
  if (!run.events().empty()) {
    EXPECT_EQ(run.events().back(), until);
  }
  EXPECT_EQ(run.tracker.objects().size(), 1u);
  return run.index - 1 - crossed;
}

// The first report comes within 5 scans of D crossing the threshold on the object's cells
// (once the scans show its whole outline), not confirm_scans later.
std::size_t scansFromDToReport(int report_scans) {
  ObjectOptions o = quickMoves();
  o.report_scans = report_scans;
  TrackerRun run{DynamicGridMap(), ObjectTracker(o)};
  const mrpt::poses::CPose2D pose(-2.0, 0.0, 0.0);
  run.steps(10, pose, {});
  return scansFromDTo(run, pose, {1.0, 0.5, 0.4}, ObjectEvent::New);
}

TEST(ObjectTracker, ANewObjectIsReportedWithinFiveScansOfDCrossingTheThreshold) {
  EXPECT_LE(scansFromDToReport(2), 5u);
  // Reporting only once the size has settled for confirm_scans takes longer.
  EXPECT_GT(scansFromDToReport(10), 5u);
}

// A first report's identity must hold for any size within report_errors of its outlines'
// errors. An object seen gone that turns up elsewhere is reported at once as moved with the
// default; with errors wide enough to leave size_tolerance ("a new object" at the ends) it
// waits for more outlines, which shrink the error.
std::size_t scansFromDToMoved(double report_errors) {
  ObjectOptions o = quickMoves();
  o.report_errors = report_errors;
  TrackerRun run{DynamicGridMap(), ObjectTracker(o)};
  const mrpt::poses::CPose2D pose(-2.0, 0.0, 0.0);
  run.steps(10, pose, {});
  run.steps(15, pose, {{1.0, 0.5, 0.4}});
  run.steps(10, pose, {});  // taken away, seen gone
  return scansFromDTo(run, pose, {0.5, -1.5, 0.4}, ObjectEvent::Moved);
}

TEST(ObjectTracker, AFirstReportWaitsWhileTheIdentityCouldChangeWithinReportErrors) {
  const std::size_t narrow = scansFromDToMoved(1);
  EXPECT_LE(narrow, 5u);
  EXPECT_GT(scansFromDToMoved(10), narrow);  // waits until ten errors fit the size tolerance
}

// A twin of an object appears behind the robot while the object is out of view: the twin is
// first reported as the object, moved. Its old place is then seen still occupied before the
// twin's size has settled: the report is relabeled to a new object, and the object keeps its
// place and its id.
TEST(ObjectTracker, AProvisionalIdentityLaterCorrectedIsRelabeledAndTheTableEndsRight) {
  ObjectOptions o = quickMoves();
  o.min_unseen_s = 0;  // any object out of view may have moved
  TrackerRun run{DynamicGridMap(), ObjectTracker(o)};
  const mrpt::poses::CPose2D ahead(0.0, 0.0, 0.0), behind(0.0, 0.0, M_PI);
  const Cylinder first{1.0, 0.5, 0.4}, twin{-1.5, 0.0, 0.4};
  run.steps(10, ahead, {});
  run.steps(15, ahead, {first});
  run.steps(10, behind, {first});
  for (int i = 0; i < 15 && run.events().back() != ObjectEvent::Moved; ++i) {
    run.step(behind, {first, twin});
  }
  ASSERT_EQ(run.events().back(), ObjectEvent::Moved);  // provisional: the object, moved
  EXPECT_EQ(run.tracker.events().back().object_id, 1);
  run.steps(15, ahead, {first, twin});
  const auto& ev = run.tracker.events();
  const auto relabel = std::find_if(
      ev.begin(), ev.end(), [](const EventRecord& e) { return e.event == ObjectEvent::Relabeled; });
  ASSERT_NE(relabel, ev.end());
  EXPECT_EQ(relabel->from_id, 1);
  EXPECT_EQ(relabel->object_id, 2);
  ASSERT_EQ(run.tracker.objects().size(), 2u);
  const TrackedObject& a = run.tracker.objects()[0];
  const TrackedObject& b = run.tracker.objects()[1];
  EXPECT_EQ(a.state, ObjectState::Present);
  EXPECT_EQ(a.n_moves, 0);
  EXPECT_NEAR(a.shape.cx, first.x, 0.05);
  EXPECT_NEAR(a.shape.cy, first.y, 0.05);
  EXPECT_EQ(b.state, ObjectState::Present);
  EXPECT_NEAR(b.shape.cx, twin.x, 0.05);
  EXPECT_NEAR(b.shape.cy, twin.y, 0.05);
}

// A cluster seen for a moment and then seen gone, before its size settled, is withdrawn from
// the table (retracted), not left in it as an absent object.
TEST(ObjectTracker, AReportSeenGoneBeforeItSettledIsRetracted) {
  TrackerRun run;
  const mrpt::poses::CPose2D pose(-2.0, 0.0, 0.0);
  run.steps(10, pose, {});
  for (int i = 0; i < 15 && run.tracker.objects().empty(); ++i) run.step(pose, {{1.0, 0.5, 0.4}});
  ASSERT_EQ(run.tracker.objects().size(), 1u);
  run.steps(10, pose, {});
  EXPECT_EQ(run.tracker.objects()[0].state, ObjectState::Retracted);
  EXPECT_FALSE(listedInTable(run.tracker.objects()[0].state));
  EXPECT_EQ(run.events(), (std::vector<ObjectEvent>{ObjectEvent::New, ObjectEvent::Retracted}));
}

// Something that stood 3 s where nothing stood before (someone pausing, a door) is no object.
TEST(ObjectTracker, ANewObjectSeenGoneWithinMinRestIsRetractedAndOneThatRestedIsAbsent) {
  for (const double min_rest_s : {10.0, 0.0}) {
    ObjectOptions o;
    o.min_rest_s = min_rest_s;
    TrackerRun run{DynamicGridMap{}, ObjectTracker(o)};
    const mrpt::poses::CPose2D pose(-2.0, 0.0, 0.0);
    run.steps(10, pose, {});
    run.steps(15, pose, {{1.0, 0.5, 0.4}});  // reported, its size settled, 3 s in all
    ASSERT_EQ(run.tracker.objects().size(), 1u);
    EXPECT_EQ(run.tracker.objects()[0].state, ObjectState::Present);
    run.steps(10, pose, {});
    const ObjectState gone = min_rest_s > 0 ? ObjectState::Retracted : ObjectState::Absent;
    EXPECT_EQ(run.tracker.objects()[0].state, gone) << "min_rest_s " << min_rest_s;
    EXPECT_EQ(run.events().back(),
              min_rest_s > 0 ? ObjectEvent::Retracted : ObjectEvent::Disappeared);
  }
}

// Two objects whose sizes differ by 3 cm (half the size tolerance) each move twice in turn,
// the other seen in place meanwhile: every move goes to the right id, and none makes a new one.
TEST(ObjectTracker, TwoObjectsThreeCentimetresApartInSizeKeepTheirIdsOverSeveralMoves) {
  TrackerRun run;
  const mrpt::poses::CPose2D pose(-2.5, 0.0, 0.0);
  Cylinder a{0.5, 1.2, 0.30}, b{0.5, -1.2, 0.33};
  run.steps(10, pose, {});
  run.steps(15, pose, {a, b});
  ASSERT_EQ(run.tracker.objects().size(), 2u);
  const int id_a = run.tracker.objects()[0].shape.cy > 0 ? 1 : 2;
  const int id_b = 3 - id_a;
  const std::vector<std::pair<Cylinder*, Cylinder>> moves{{&a, {1.6, 0.6, 0.30}},
                                                          {&b, {0.0, -0.4, 0.33}},
                                                          {&a, {-0.8, 1.4, 0.30}},
                                                          {&b, {1.8, -1.3, 0.33}}};
  for (const auto& [which, to] : moves) {
    run.steps(10, pose, {which == &a ? b : a});  // the mover's place seen empty
    *which = to;
    run.steps(15, pose, {a, b});
  }
  ASSERT_EQ(run.tracker.objects().size(), 2u);
  for (const auto& [id, c] : {std::pair<int, Cylinder>{id_a, a}, {id_b, b}}) {
    const TrackedObject& o = run.tracker.objects()[static_cast<std::size_t>(id - 1)];
    EXPECT_EQ(o.state, ObjectState::Present) << id;
    EXPECT_EQ(o.n_moves, 2) << id;
    EXPECT_NEAR(o.shape.cx, c.x, 0.05) << id;
    EXPECT_NEAR(o.shape.cy, c.y, 0.05) << id;
  }
}

// An object put down 5 cm from a wall is reported, at its place and size; the wall behind it
// yields no object.
TEST(ObjectTracker, AnObjectFiveCentimetresFromAWallIsReportedAndTheWallIsNot) {
  TrackerRun run;
  const mrpt::poses::CPose2D pose(-2.0, 0.0, 0.0);
  const Cylinder c{3.0 - 0.05 - 0.15, 0.5, 0.30};  // the east wall is x = 3
  run.steps(10, pose, {});
  run.steps(20, pose, {c});
  ASSERT_EQ(run.tracker.objects().size(), 1u);
  const TrackedObject& o = run.tracker.objects()[0];
  EXPECT_EQ(o.state, ObjectState::Present);
  EXPECT_NEAR(o.shape.cx, c.x, 0.05);
  EXPECT_NEAR(o.shape.cy, c.y, 0.05);
  EXPECT_NEAR(o.shape.size, c.diameter, 0.05);
  EXPECT_EQ(run.events(), (std::vector<ObjectEvent>{ObjectEvent::New}));
}

// A table carried over from an earlier session: its objects keep their ids, absent until found,
// and a detection of a carried object's size takes its id; a new size gets the next id.
TEST(ObjectTracker, ACarriedTableKeepsItsIdsAndHandsThemToWhatItFinds) {
  TrackerRun run;
  std::vector<TrackedObject> rows(3);
  const double sizes[3] = {0.4, 0.3, 0.2};
  for (int k = 0; k < 3; ++k) {
    rows[k].id = k + 1;
    rows[k].state = k == 1 ? ObjectState::Withdrawn : ObjectState::Present;
    rows[k].shape.size = sizes[k];
    rows[k].shape.cx = 1.0 - k;
    rows[k].shape.cy = 2.0;
  }
  run.tracker.carryOver(rows, 0.0);
  ASSERT_EQ(run.tracker.objects().size(), 3u);
  EXPECT_EQ(run.tracker.objects()[0].state, ObjectState::Absent);
  EXPECT_EQ(run.tracker.objects()[1].state, ObjectState::Withdrawn);  // never chosen
  EXPECT_EQ(run.tracker.objects()[0].history.size(), 1u);
  const mrpt::poses::CPose2D pose(-2.0, 0.0, 0.0);
  run.steps(10, pose, {});
  run.steps(15, pose, {{1.0, -1.5, 0.4}, {0.0, 1.0, 0.6}});
  ASSERT_EQ(run.tracker.objects().size(), 4u);
  EXPECT_EQ(run.tracker.objects()[0].state, ObjectState::Present);  // the 0.4 m one, moved
  EXPECT_NEAR(run.tracker.objects()[0].shape.cy, -1.5, 0.05);
  EXPECT_EQ(run.tracker.objects()[0].history.size(), 2u);
  EXPECT_EQ(run.tracker.objects()[2].state, ObjectState::Absent);  // not seen
  EXPECT_NEAR(run.tracker.objects()[3].shape.size, 0.6, 0.05);     // new: the next id
  EXPECT_THROW(run.tracker.carryOver(rows, 0.0), std::logic_error);
  ObjectTracker fresh;
  rows[2].id = 7;
  EXPECT_THROW(fresh.carryOver(rows, 0.0), std::logic_error);
}

// A 0.6 m cylinder 3.5 m off, seen with beams 2.25 degrees apart (14 cm there): D crosses on
// two arcs of it whose cells lie farther apart than join_distance, two clusters that pass two
// scans apart. The second lies within the first's radius + follow_margin while the scan hits
// the first's cells: the same object, not a second one (before, two objects, both new).
TEST(ObjectTracker, AFarObjectCrossingDInTwoArcsIsOneObject) {
  TrackerRun run;
  run.beams = 81;
  const mrpt::poses::CPose2D pose(-2.5, 0.1, 0.0);
  run.steps(10, pose, {});
  run.steps(30, pose, {{1.0, 0.3, 0.6}});
  ASSERT_EQ(run.tracker.objects().size(), 1u);
  EXPECT_EQ(run.events(), std::vector<ObjectEvent>{ObjectEvent::New});
  EXPECT_NEAR(run.tracker.objects()[0].shape.cx, 1.0, 0.3);
}

/// Objects found after a 0.15 m cylinder 6.4 m off is seen in six scans of half-degree beams
/// (5.6 cm apart there) as the robot passes, then not again.
std::size_t objectsAfterAFarGlance(double support_threshold) {
  ObjectOptions o = quickMoves();
  o.support_threshold = support_threshold;
  TrackerRun run{DynamicGridMap{}, ObjectTracker{o}};
  const mrpt::poses::CPose2D start(-2.8, -2.5, 0.7);
  run.steps(10, start, {});
  const Cylinder far{1.5, 2.2, 0.15};
  for (int i = 0; i < 6; ++i) run.step(mrpt::poses::CPose2D(-2.8 + 0.05 * i, -2.5, 0.7), {far});
  run.steps(20, mrpt::poses::CPose2D(-2.8, -2.5, 0.7 + M_PI), {far});
  return run.tracker.objects().size();
}

// Far off, the hits spread over the arc's cells from scan to scan and D crosses on one cell
// only: min_cells (2) alone never lets it through; the D cells beside it above
// support_threshold count towards it.
TEST(ObjectTracker, AFarObjectWhoseHitsSpreadOverItsArcIsFoundByTheCellsBesideIt) {
  EXPECT_EQ(objectsAfterAFarGlance(0.0), 0u);
  EXPECT_EQ(objectsAfterAFarGlance(0.8), 1u);
}

}  // namespace
}  // namespace dynamap
