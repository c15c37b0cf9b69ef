// Multi-session scenarios: [session.N] read as written, each session's world and objects, the
// truth of the changes between sessions, and every error naming the section and the key.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "../test_util.h"
#include "dynamap/sim/scenario.h"
#include "dynamap/sim/simulator.h"

namespace dynamap::sim {
namespace {

// A 6 x 4 m room, a partition, two objects; object 1 moves in session 1.
const std::string kBase = R"(
[scenario]
name = room
duration_s = 20
seed = 7

[world]
wall.1 = -3 -2 3 -2
wall.2 = 3 -2 3 2
wall.3 = 3 2 -3 2
wall.4 = -3 2 -3 -2
wall.5 = 0 -2 0 -1

[robot]
waypoints = -2 0  2 0

[laser]
beams = 91

[objects]
object.1 = 0.3  1.0 1.2
object.2 = 0.5 -1.0 -1.2

[moves]
move.1 = 5 1  -1.0 1.2 2
)";

const std::string kSessions = R"(
[session.2]
duration_s = 10
waypoints = 2 0.5  -2 0.5
move.2 = -2.0 -1.2
object.3 = 0.4  1.5 -1.2
remove_walls = 5
wall.6 = 1 1.5  2 1.5

[session.3]
waypoints = -2 -0.5  2 -0.5
remove = 1
remove_walls = 6
)";

Scenario parse(const std::string& text) {
  return parseScenario(IniFile::fromText(text, "s.ini"), ".");
}

std::string errorOf(const std::string& text) {
  try {
    parse(text);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(SimSessions, EachSessionStartsFromTheWorldTheLastLeftWithItsChanges) {
  const Scenario sc = parse(kBase + kSessions);
  ASSERT_EQ(sc.sessions.size(), 2u);
  const Scenario s2 = sessionScenario(sc, 2);
  EXPECT_EQ(s2.name, "room.s2");
  EXPECT_EQ(s2.duration_s, 10);
  EXPECT_EQ(s2.seed, 8u);
  EXPECT_EQ(s2.clock_offset_s, 86400);
  EXPECT_TRUE(s2.moves.empty());
  ASSERT_EQ(s2.objects.size(), 3u);
  EXPECT_DOUBLE_EQ(s2.objects[0].start.x, -1.0);  // where session 1's move left it
  EXPECT_DOUBLE_EQ(s2.objects[1].start.x, -2.0);  // moved between the sessions
  EXPECT_EQ(s2.objects[2].id, 3);
  ASSERT_EQ(s2.wall_keys.size(), 5u);
  EXPECT_EQ(s2.wall_keys.back(), "[session.2] wall.6");
  EXPECT_DOUBLE_EQ(s2.robot.waypoints.front().x, 2);
  const Scenario s3 = sessionScenario(sc, 3);
  EXPECT_EQ(s3.duration_s, 20);  // the scenario's when not given
  EXPECT_EQ(s3.objects.size(), 2u);
  EXPECT_EQ(s3.world.segments.size(), 4u);
  EXPECT_EQ(s3.clock_offset_s, 2 * 86400);
  EXPECT_EQ(sessionScenario(sc, 1).objects[0].start.x, 1.0);
  EXPECT_THROW(sessionScenario(sc, 4), std::out_of_range);
}

TEST(SimSessions, TheTruthListsEveryChangeWithItsPlaces) {
  const std::vector<SessionChange> c = sessionChanges(parse(kBase + kSessions));
  ASSERT_EQ(c.size(), 6u);
  EXPECT_EQ(c[0].kind, "object_moved");
  EXPECT_EQ(c[0].id, 2);
  EXPECT_DOUBLE_EQ(c[0].from.x, -1.0);
  EXPECT_DOUBLE_EQ(c[0].to.x, -2.0);
  EXPECT_EQ(c[1].kind, "object_new");
  EXPECT_DOUBLE_EQ(c[1].size, 0.4);
  EXPECT_EQ(c[2].kind, "structure_added");
  EXPECT_EQ(c[2].id, 6);
  EXPECT_EQ(c[3].kind, "structure_removed");
  EXPECT_EQ(c[3].id, 5);
  EXPECT_DOUBLE_EQ(c[3].size, 1.0);
  EXPECT_EQ(c[4].session, 3);
  EXPECT_EQ(c[4].kind, "object_gone");
  EXPECT_EQ(c[4].id, 1);
  EXPECT_DOUBLE_EQ(c[4].from.x, -1.0);  // where session 1's move left it
  EXPECT_EQ(c[5].kind, "structure_removed");
  EXPECT_EQ(c[5].id, 6);
}

TEST(SimSessions, SimulateWritesOneRawlogPerSessionAndTheTruth) {
  const std::string dir = test::tempDir("sim_sessions");
  std::ofstream(dir + "/s.ini") << kBase << kSessions;
  ASSERT_EQ(test::run(std::string(DYNAMAP_EXE) + " simulate --scenario " + dir + "/s.ini --out " +
                      dir + "/o"),
            0);
  for (const char* f : {"room.rawlog", "room.s2.rawlog", "room.s3.rawlog", "room.s2.gt.txt"}) {
    EXPECT_TRUE(std::filesystem::exists(dir + "/o/" + f)) << f;
  }
  std::ifstream in(dir + "/o/room.changes.csv");
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(),
            "session,kind,id,size_m,from_x,from_y,to_x,to_y\n"
            "2,object_moved,2,0.500,-1.0000,-1.2000,-2.0000,-1.2000\n"
            "2,object_new,3,0.400,,,1.5000,-1.2000\n"
            "2,structure_added,6,1.000,1.0000,1.5000,2.0000,1.5000\n"
            "2,structure_removed,5,1.000,0.0000,-2.0000,0.0000,-1.0000\n"
            "3,object_gone,1,0.300,-1.0000,1.2000,,\n"
            "3,structure_removed,6,1.000,1.0000,1.5000,2.0000,1.5000\n");
  std::ifstream gt(dir + "/o/room.s2.gt.txt");
  double t = 0;
  gt >> t;
  EXPECT_DOUBLE_EQ(t, kEpochUnixSeconds + 86400);  // a day later
}

TEST(SimSessions, ErrorsNameTheSessionAndTheKey) {
  const auto with = [](const std::string& s) { return errorOf(kBase + s); };
  EXPECT_NE(with("[session.3]\nwaypoints = 0 0 1 0\n").find("[session.2]"), std::string::npos);
  EXPECT_NE(with("[session.1]\nwaypoints = 0 0 1 0\n").find("N = 2 .. 100"), std::string::npos);
  EXPECT_NE(with("[session.2]\nmove.2 = 0 0\n").find("[session.2] waypoints: missing"),
            std::string::npos);
  EXPECT_NE(with("[session.2]\nwaypoints = -2 0 2 0\nmove.9 = 0 1\n").find("move.9: no object 9"),
            std::string::npos);
  EXPECT_NE(with("[session.2]\nwaypoints = -2 0 2 0\nobject.2 = 0.2 1 1\n").find("existed before"),
            std::string::npos);
  EXPECT_NE(
      with("[session.2]\nwaypoints = -2 0 2 0\nremove = 2\nmove.2 = 1 1\n").find("also moved"),
      std::string::npos);
  EXPECT_NE(with("[session.2]\nwaypoints = -2 0 2 0\nremove_walls = 9\n").find("no wall 9"),
            std::string::npos);
  EXPECT_NE(
      with("[session.2]\nwaypoints = -2 0 2 0\nwall.7 = -2.5 -1 2.5 -1\nwall.8 = 0 -0.5 0 0.5\n")
          .find("crosses [session.2] wall.8"),
      std::string::npos);
  EXPECT_NE(with("[session.2]\nwaypoints = -2 0 2 0\nmove.2 = 2.9 -1.2\n")
                .find("overlaps [world] wall.2"),
            std::string::npos);
  EXPECT_NE(with("[session.2]\nwaypoints = -2 0 2 0\nspeed = 3\n").find("speed: unknown key"),
            std::string::npos);
  // A wall removed in session 2 is no longer there to remove in session 3.
  EXPECT_NE(with(kSessions + "[session.4]\nwaypoints = -2 0 2 0\nremove_walls = 5\n")
                .find("[session.4] remove_walls: no wall 5"),
            std::string::npos);
}

}  // namespace
}  // namespace dynamap::sim
