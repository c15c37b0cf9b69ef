// Cylinders added to scans (perturb --add-objects): the spec, the beams a disc gets, the edit
// of a scan against the exact geometry, and a plan's rules checked on a synthetic log.

#include "dynamap/sim/added_objects.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace dynamap::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// 181 beams over 180 deg (1 deg apart) from `sensor` facing `phi`, every range `range`.
ScanGeometry fan(Vec2 sensor, double phi, float range, double t = 0) {
  ScanGeometry g;
  g.t = t;
  g.robot = g.sensor = sensor;
  g.sensor_phi = phi;
  g.first_angle = -kPi / 2;
  g.step = kPi / 180;
  g.max_range = 30;
  g.ranges.assign(181, range);
  g.valid.assign(181, 1);
  return g;
}

TEST(AddObjectsSpec, DefaultsAndKeys) {
  const AddObjectsSpec d = parseAddObjectsSpec("");
  EXPECT_EQ(d.objects, 4);
  EXPECT_EQ(d.moves, 10);
  EXPECT_DOUBLE_EQ(d.glide_s, 0);
  const AddObjectsSpec s = parseAddObjectsSpec(
      "objects=3,moves=7,seed=9,sizes=0.25-0.5,glide=3,wall=0.2,path=0.6,"
      "seen=12,beams=4");
  EXPECT_EQ(s.objects, 3);
  EXPECT_EQ(s.moves, 7);
  EXPECT_EQ(s.seed, 9u);
  EXPECT_DOUBLE_EQ(s.min_diameter, 0.25);
  EXPECT_DOUBLE_EQ(s.max_diameter, 0.5);
  EXPECT_DOUBLE_EQ(s.glide_s, 3);
  EXPECT_DOUBLE_EQ(s.wall_clearance_m, 0.2);
  EXPECT_DOUBLE_EQ(s.path_clearance_m, 0.6);
  EXPECT_EQ(s.seen_scans, 12);
  EXPECT_EQ(s.seen_beams, 4);
}

TEST(AddObjectsSpec, ErrorsNameTheKey) {
  auto message = [](const std::string& text) {
    try {
      parseAddObjectsSpec(text);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("colour=red").find("unknown key 'colour'"), std::string::npos);
  EXPECT_NE(message("objects=0").find("objects"), std::string::npos);
  EXPECT_NE(message("objects=2.5").find("objects"), std::string::npos);
  EXPECT_NE(message("moves=x").find("moves: not a number"), std::string::npos);
  EXPECT_NE(message("sizes=0.6-0.2").find("sizes"), std::string::npos);
  EXPECT_NE(message("sizes=0.3").find("sizes: expected MIN-MAX"), std::string::npos);
  EXPECT_NE(message("glide=-1").find("glide"), std::string::npos);
  EXPECT_NE(message("seed").find("expected key=value"), std::string::npos);
}

TEST(AddedObjects, BeamsOnADiscAreTheBeamsThatMeetItBeforeTheirReturn) {
  // A disc of radius 0.3 at 3 m straight ahead spans +-asin(0.1) = +-5.74 deg: beams -5..5.
  EXPECT_EQ(beamsOnDisc(fan({0, 0}, 0, 10), {3, 0}, 0.3), 11);
  EXPECT_EQ(beamsOnDisc(fan({0, 0}, kPi / 2, 10), {0, 3}, 0.3), 11);  // facing +y
  EXPECT_EQ(beamsOnDisc(fan({0, 0}, 0, 2), {3, 0}, 0.3), 0);          // a wall at 2 m hides it
  EXPECT_EQ(beamsOnDisc(fan({0, 0}, 0, 10), {-3, 0}, 0.3), 0);        // behind the laser
  EXPECT_EQ(beamsOnDisc(fan({0, 0}, 0, 10), {3, 0}, 0.3, 2.5), 0);    // beyond the counted range
}

TEST(AddedObjects, ReturnsOfTheLogInsideADiscAreCounted) {
  // Returns at 3.1 m straight ahead: beams -5..5 meet the disc of radius 0.3 at (3, 0), and
  // their end points lie inside it (beam 5: (3.088, 0.270), 0.284 m from the centre).
  EXPECT_EQ(ownReturnsInDisc(fan({0, 0}, 0, 3.1f), {3, 0}, 0.3), 11);
  EXPECT_EQ(ownReturnsInDisc(fan({0, 0}, 0, 3.1f), {3, 0}, 0.05), 0);  // beam 0 ends 0.1 m off
  EXPECT_EQ(ownReturnsInDisc(fan({0, 0}, 0, 3.1f), {3.1, 0}, 0.05), 1);
  EXPECT_EQ(ownReturnsInDisc(fan({0, 0}, 0, 10), {3, 0}, 0.3), 0);  // they pass through it
  EXPECT_EQ(ownReturnsInDisc(fan({0, 0}, 0, 2), {3, 0}, 0.3), 0);   // they end before it
  ScanGeometry none = fan({0, 0}, 0, 3.1f);
  none.valid.assign(none.valid.size(), 0);  // no return at all
  EXPECT_EQ(ownReturnsInDisc(none, {3, 0}, 0.3), 0);
  // Beams at max range (30 m) end inside a disc at 29.9 m but are no return either.
  EXPECT_EQ(ownReturnsInDisc(fan({0, 0}, 0, 30), {29.9, 0}, 0.3), 0);
  EXPECT_EQ(ownReturnsInDisc(fan({0, 0}, 0, 29.99f), {29.9, 0}, 0.3), 1);
}

TEST(AddedObjects, APlaceSomeoneOfTheLogStandsInIsNotClear) {
  // Scans at t = 0..9 s; someone stands 3.1 m ahead in those of t 4 and 5 only.
  std::vector<ScanGeometry> scans;
  for (int t = 0; t < 10; ++t) scans.push_back(fan({0, 0}, 0, t == 4 || t == 5 ? 3.1f : 10, t));
  EXPECT_FALSE(clearOfTheLog(scans, {3, 0}, 0.3, 0, 9));
  EXPECT_FALSE(clearOfTheLog(scans, {3, 0}, 0.3, 5, 5));
  EXPECT_TRUE(clearOfTheLog(scans, {3, 0}, 0.3, 0, 3.9));
  EXPECT_TRUE(clearOfTheLog(scans, {3, 0}, 0.3, 5.5, 9));
  EXPECT_TRUE(clearOfTheLog(scans, {-3, 0}, 0.3, 0, 9));  // elsewhere
}

TEST(AddedObjects, TheEditAgreesWithTheGeometryAndTheHits) {
  AddedPlan plan;
  plan.objects = {{1, 0.6, {3, 0}}, {2, 0.4, {4, 1}}};
  ScanGeometry g = fan({0, 0}, 0, 10);
  g.valid[100] = 0;  // a beam without a return that meets nothing stays so
  AddObjectsSpec spec;
  spec.range_noise_m = 0;
  const std::vector<int> hits = applyAddedObjects(plan, g, spec, 1);
  ASSERT_EQ(hits.size(), 2u);
  EXPECT_EQ(hits[0], 11);
  int changed = 0;
  for (std::size_t i = 0; i < g.ranges.size(); ++i) {
    if (g.ranges[i] == 10.0f) continue;
    ++changed;
    const double a = g.first_angle + static_cast<double>(i) * g.step;
    const double d1 = rayCircle({0, 0}, {std::cos(a), std::sin(a)}, {3, 0}, 0.3);
    const double d2 = rayCircle({0, 0}, {std::cos(a), std::sin(a)}, {4, 1}, 0.2);
    EXPECT_NEAR(g.ranges[i], std::min(d1, d2), 1e-5) << "beam " << i;
  }
  EXPECT_EQ(changed, hits[0] + hits[1]);
  EXPECT_EQ(g.valid[100], 0);
}

TEST(AddedObjects, AnObjectGlidesAtConstantSpeedAndJumpsAtOnce) {
  AddedPlan plan;
  plan.objects = {{1, 0.3, {0, 0}}, {2, 0.3, {5, 5}}};
  plan.moves = {{1, 1, 10, 13, {0, 0}, {3, 0}}, {2, 2, 20, 20, {5, 5}, {6, 5}}};
  EXPECT_DOUBLE_EQ(addedPositionAt(plan, 0, 9.9).x, 0);
  EXPECT_DOUBLE_EQ(addedPositionAt(plan, 0, 11).x, 1);
  EXPECT_DOUBLE_EQ(addedPositionAt(plan, 0, 13).x, 3);
  EXPECT_DOUBLE_EQ(addedPositionAt(plan, 1, 19.99).x, 5);
  EXPECT_DOUBLE_EQ(addedPositionAt(plan, 1, 20).x, 6);
}

/// A robot going round a 16 x 16 m room's centre on a circle of radius 3 m, looking ahead, at
/// 5 Hz for `seconds`; the walls stop each beam (exact).
std::vector<ScanGeometry> roomLog(double seconds) {
  std::vector<ScanGeometry> scans;
  for (int k = 0; k < seconds * 5; ++k) {
    const double t = k / 5.0, a = t * 0.1;
    ScanGeometry g = fan({3 * std::cos(a), 3 * std::sin(a)}, a + kPi / 2, 0, t);
    for (std::size_t i = 0; i < g.ranges.size(); ++i) {
      const double b = g.sensor_phi + g.first_angle + static_cast<double>(i) * g.step;
      const Vec2 d{std::cos(b), std::sin(b)};
      double r = kNoHit;
      for (const Segment& s : {Segment{{-8, -8}, {8, -8}}, Segment{{8, -8}, {8, 8}},
                               Segment{{8, 8}, {-8, 8}}, Segment{{-8, 8}, {-8, -8}}}) {
        r = std::min(r, raySegment(g.sensor, d, s));
      }
      g.ranges[i] = static_cast<float>(std::min(r, 30.0));
    }
    scans.push_back(g);
  }
  return scans;
}

/// The room of roomLog as S holds it: free within 7.9 m of its centre, and short of
/// x = `free_below_x`.
FreeSpace roomFree(const std::vector<ScanGeometry>& scans, double t, double free_below_x = 1e9) {
  FreeSpace f;
  f.t = t;
  f.x_min = f.y_min = -8.5;
  f.resolution = 0.1;
  f.size_x = f.size_y = 170;
  std::vector<std::uint8_t> flags(170 * 170, 0);
  for (int y = 0; y < 170; ++y) {
    for (int x = 0; x < 170; ++x) {
      const double cx = -8.45 + x * 0.1, cy = -8.45 + y * 0.1;
      flags[y * 170 + x] = std::abs(cx) < 7.9 && std::abs(cy) < 7.9 && cx < free_below_x;
    }
  }
  std::vector<Vec2> robot;
  for (const auto& s : scans) robot.push_back(s.robot);
  f.build(flags, robot, 3);
  return f;
}

TEST(AddedObjects, ABeamWithoutAReturnSeesACylinderOnlyAlongThePathTheMapHoldsFree) {
  // The room, but not free from x = 4.0 on: a surface there that the laser does not return
  // from, and what lies behind it unknown.
  const FreeSpace f = roomFree({}, 0, 4.0);
  EXPECT_NEAR(f.freeRun({0, 0}, 0, 30), 4.0, 0.05 + 1e-9);        // the wall's near edge
  EXPECT_NEAR(f.freeRun({0, 0}, kPi / 2, 30), 7.9, 0.05 + 1e-9);  // the room's wall
  EXPECT_NEAR(f.freeRun({0, 0}, kPi / 2, 2.5), 2.5, 1e-9);        // capped
  EXPECT_EQ(f.freeRun({5, 0}, kPi, 30), 0);                       // from a cell not free

  ScanGeometry g = fan({0, 0}, 0, 30);  // every beam at max range: no return
  g.valid[10] = 0;                      // and one invalid
  g.ranges[20] = 3.0f;                  // one return of its own, kept as it is
  limitBeamsWithoutReturn(g, f);
  EXPECT_NEAR(g.ranges[90], 4.0, 0.05 + 1e-6);  // straight ahead: up to the wall
  EXPECT_EQ(g.valid[90], 0);
  EXPECT_NEAR(g.ranges[10], f.freeRun({0, 0}, -kPi / 2 + 10 * kPi / 180, 30), 1e-5);
  EXPECT_EQ(g.ranges[20], 3.0f);
  EXPECT_EQ(g.valid[20], 1);

  // A cylinder beyond the wall is not seen; one before it is, by beams now valid.
  AddObjectsSpec spec;
  spec.range_noise_m = 0;
  AddedPlan behind;
  behind.objects = {{1, 0.6, {6, 0}}};
  ScanGeometry b = g;
  EXPECT_EQ(applyAddedObjects(behind, b, spec, 1)[0], 0);
  EXPECT_EQ(beamsOnDisc(g, {6, 0}, 0.3), 0);
  AddedPlan before;
  before.objects = {{1, 0.6, {3, 0}}};
  ScanGeometry a = g;
  EXPECT_EQ(applyAddedObjects(before, a, spec, 1)[0], 11);
  EXPECT_NEAR(a.ranges[90], 2.7, 1e-5);
  EXPECT_EQ(a.valid[90], 1);
}

TEST(AddedObjects, APlanKeepsItsRules) {
  const auto scans = roomLog(400);
  AddObjectsSpec spec = parseAddObjectsSpec("objects=3,moves=6,seed=4");
  std::vector<FreeSpace> free;
  for (double t : addedSlotTimes(scans.back().t, spec)) free.push_back(roomFree(scans, t));
  AddedPlan plan = planAddedObjects(scans, free, spec);
  dropUnseenMoves(scans, spec, plan);
  ASSERT_EQ(plan.objects.size(), 3u);
  EXPECT_DOUBLE_EQ(plan.objects[0].diameter, 0.2);
  EXPECT_DOUBLE_EQ(plan.objects[2].diameter, 0.6);
  EXPECT_EQ(plan.moves.size() + plan.dropped.size(), 6u);
  EXPECT_GE(plan.moves.size(), 4u);
  for (const AddedMove& m : plan.moves) {
    const double r = plan.objects[static_cast<std::size_t>(m.object_id - 1)].diameter / 2;
    EXPECT_LE(std::max(std::abs(m.to.x), std::abs(m.to.y)) + r + spec.wall_clearance_m, 7.9);
    for (const auto& s : scans) {
      EXPECT_GE(distance(s.robot, m.to), r + spec.path_clearance_m) << "move " << m.id;
      // A jump: nobody saw either place within a second of it.
      if (std::abs(s.t - m.t_start) <= 1.0) {
        EXPECT_EQ(beamsOnDisc(s, m.to, r), 0) << "move " << m.id << " at " << s.t;
        EXPECT_EQ(beamsOnDisc(s, m.from, r), 0) << "move " << m.id << " at " << s.t;
      }
    }
  }
  // The same seed gives the same plan.
  AddedPlan again = planAddedObjects(scans, free, spec);
  dropUnseenMoves(scans, spec, again);
  ASSERT_EQ(again.moves.size(), plan.moves.size());
  for (std::size_t i = 0; i < plan.moves.size(); ++i) {
    EXPECT_DOUBLE_EQ(again.moves[i].to.x, plan.moves[i].to.x);
    EXPECT_DOUBLE_EQ(again.moves[i].t_start, plan.moves[i].t_start);
  }
}

TEST(AddedObjects, AMoveWhoseNewPlaceIsNotSeenIsDropped) {
  const auto scans = roomLog(60);
  AddedPlan plan;
  plan.objects = {{1, 0.3, {-6, -6}}};
  // The first move's place has 1 s (5 scans) before the object moves on: too few.
  plan.moves = {{1, 1, 10, 10, {-6, -6}, {0, 0}}, {2, 1, 11, 11, {0, 0}, {5, 0}}};
  AddObjectsSpec spec;
  dropUnseenMoves(scans, spec, plan);
  ASSERT_EQ(plan.moves.size(), 1u);
  ASSERT_EQ(plan.dropped.size(), 1u);
  EXPECT_NE(plan.dropped[0].find("object 1 at t 10 s"), std::string::npos) << plan.dropped[0];
  EXPECT_DOUBLE_EQ(plan.moves[0].to.x, 5);
  EXPECT_DOUBLE_EQ(plan.moves[0].from.x, -6);  // the move left starts where the object stood
  EXPECT_EQ(plan.moves[0].id, 1);
}

/// S as a mapper that never sees a place again would hold it: wherever an edited beam ended on a
/// cylinder (shorter than the log's own return), occupied for good. `forgets`: holds nothing.
struct CylinderEnds : EditedMap {
  struct End {
    Vec2 at;
    double t;
  };
  const std::vector<ScanGeometry>& log;
  bool forgets = false;
  std::vector<End> ends;
  std::vector<std::vector<float>> ranges;  // of every scan inserted, as edited
  std::size_t inserted = 0;
  explicit CylinderEnds(const std::vector<ScanGeometry>& l) : log(l) {}
  bool heldFree(Vec2 c, double radius) const override {
    for (const End& e : ends) {
      if (!forgets && std::hypot(e.at.x - c.x, e.at.y - c.y) <= radius + 0.05) return false;
    }
    return true;
  }
  void insert(std::size_t index, const ScanGeometry& g) override {
    ASSERT_EQ(index, inserted++);
    ranges.push_back(g.ranges);
    for (std::size_t i = 0; i < g.ranges.size(); ++i) {
      if (g.ranges[i] >= log[index].ranges[i] - 1e-3) continue;
      const double b = g.sensor_phi + g.first_angle + static_cast<double>(i) * g.step;
      ends.push_back(
          {{g.sensor.x + g.ranges[i] * std::cos(b), g.sensor.y + g.ranges[i] * std::sin(b)}, g.t});
    }
  }
};

TEST(AddedObjects, AMoveOntoAPlaceSHoldsFromAnotherCylinderIsDropped) {
  const auto scans = roomLog(60);
  const AddObjectsSpec spec;
  AddedPlan plan;
  // Object 1 stands at (0, 5), seen from the start, and leaves at 10 s; at 20 s object 2 comes
  // to where it stood, which this S still holds; at 40 s object 2 moves on.
  plan.objects = {{1, 0.4, {0, 5}}, {2, 0.4, {5, -5}}};
  plan.moves = {{1, 1, 10, 10, {0, 5}, {-5, -5}},
                {2, 2, 20, 20, {5, -5}, {0, 5.1}},
                {3, 2, 40, 40, {0, 5.1}, {-5, 0}}};
  AddedPlan kept = plan;
  CylinderEnds held(scans);
  dropMovesIntoHeldPlaces(scans, spec, plan, held);
  EXPECT_EQ(held.inserted, scans.size());
  ASSERT_EQ(plan.moves.size(), 2u);
  ASSERT_EQ(plan.dropped.size(), 1u);
  EXPECT_NE(plan.dropped[0].find("object 2 at t 20 s"), std::string::npos) << plan.dropped[0];
  EXPECT_EQ(plan.moves[1].id, 2);
  EXPECT_DOUBLE_EQ(plan.moves[1].from.x, 5);  // object 2 stayed where it stood
  EXPECT_DOUBLE_EQ(plan.moves[1].from.y, -5);
  // The scans after the drop were edited without it: no cylinder at (0, 5.1) from 20 s on.
  std::size_t before = 0;
  for (const auto& e : held.ends) {
    const bool there = std::hypot(e.at.x, e.at.y - 5.05) < 0.3;
    EXPECT_FALSE(there && e.t >= 20) << e.t;
    before += there && e.t < 10;
  }
  EXPECT_GT(before, 0u);  // object 1 was seen there
  // Every scan was mapped as the final plan edits it, noise and all: as perturb writes it.
  for (std::size_t s = 0; s < scans.size(); ++s) {
    ScanGeometry g = scans[s];
    applyAddedObjects(plan, g, spec, addedNoiseStream(spec, s));
    ASSERT_EQ(g.ranges, held.ranges[s]) << "scan " << s;
  }
  // A map that holds nothing keeps every move.
  CylinderEnds forgets(scans);
  forgets.forgets = true;
  dropMovesIntoHeldPlaces(scans, spec, kept, forgets);
  EXPECT_EQ(kept.moves.size(), 3u);
  EXPECT_TRUE(kept.dropped.empty());
}

}  // namespace
}  // namespace dynamap::sim
