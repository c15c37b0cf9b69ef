// Scenario parsing: a valid file reads as written, and every error names its key and the file.

#include <gtest/gtest.h>
#include <mrpt/img/CImage.h>

#include <cstdio>
#include <filesystem>
#include <regex>

#include "dynamap/sim/scenario.h"

namespace dynamap::sim {
namespace {

const char* kValid = R"(
[scenario]
name = room
duration_s = 20   ; seconds
seed = 7

[world]
wall.1 = -3 -2 3 -2
wall.2 = 3 -2 3 2
wall.3 = 3 2 -3 2
wall.4 = -3 2 -3 -2

[robot]
waypoints = -2 0  2 0
loop = true
speed_mps = 0.5
turn_rate_dps = 90
scan_rate_hz = 5

[laser]
beams = 91
fov_deg = 180
max_range_m = 8
range_noise_std_m = 0.01
mount = 0.1 0 0

[odometry]
noise_xy_per_m = 0.01
noise_yaw_per_rad = 0.01

[objects]
object.1 = 0.3  1.0 1.2
object.2 = 0.5 -1.0 -1.2

[moves]
move.1 = 5 1  -1.0 1.2 2
move.2 = 9 2   1.0 -1.2 0

[people]
person.1 = 0.4 1.0 -2 1.6 2 1.6
)";

Scenario parse(const std::string& text) {
  return parseScenario(IniFile::fromText(text, "test.ini"), ".");
}

/// Replaces the first match of `pattern` in the valid scenario.
std::string edit(const std::string& pattern, const std::string& with) {
  return std::regex_replace(std::string(kValid), std::regex(pattern), with,
                            std::regex_constants::format_first_only);
}

/// Parsing `text` must fail with a message naming the file and every string in `names`.
void expectError(const std::string& text, const std::vector<std::string>& names) {
  try {
    parse(text);
    ADD_FAILURE() << "no error; expected one naming " << names.front();
  } catch (const ConfigError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("test.ini"), std::string::npos) << msg;
    for (const auto& n : names) EXPECT_NE(msg.find(n), std::string::npos) << msg;
  }
}

TEST(SimScenario, ValidFileReadsAsWritten) {
  const Scenario sc = parse(kValid);
  EXPECT_EQ(sc.name, "room");
  EXPECT_EQ(sc.seed, 7u);
  EXPECT_DOUBLE_EQ(sc.duration_s, 20);
  ASSERT_EQ(sc.world.segments.size(), 4u);
  EXPECT_EQ(sc.wall_keys[1], "wall.2");
  ASSERT_EQ(sc.robot.waypoints.size(), 2u);
  EXPECT_DOUBLE_EQ(sc.robot.waypoints[1].x, 2);
  EXPECT_EQ(sc.laser.beams, 91);
  EXPECT_DOUBLE_EQ(sc.laser.mount.x, 0.1);
  ASSERT_EQ(sc.objects.size(), 2u);
  EXPECT_DOUBLE_EQ(sc.objects[1].diameter, 0.5);
  ASSERT_EQ(sc.moves.size(), 2u);
  EXPECT_EQ(sc.moves[0].object_id, 1);
  EXPECT_DOUBLE_EQ(sc.moves[0].tEnd(), 7);
  ASSERT_EQ(sc.people.size(), 1u);
  EXPECT_EQ(sc.people[0].path.size(), 2u);
}

TEST(SimScenario, ObjectsGlideAndJump) {
  const Scenario sc = parse(kValid);
  EXPECT_DOUBLE_EQ(objectPositionAt(sc, 0, 4.9).x, 1.0);
  EXPECT_DOUBLE_EQ(objectPositionAt(sc, 0, 6.0).x, 0.0);  // half way through its glide
  EXPECT_DOUBLE_EQ(objectPositionAt(sc, 0, 7.0).x, -1.0);
  EXPECT_DOUBLE_EQ(objectPositionAt(sc, 1, 8.99).x, -1.0);
  EXPECT_DOUBLE_EQ(objectPositionAt(sc, 1, 9.0).x, 1.0);
  EXPECT_DOUBLE_EQ(moveOrigin(sc, sc.moves[1]).x, -1.0);
  // The person walks 4 m to the end and back at 1 m/s.
  EXPECT_DOUBLE_EQ(personPositionAt(sc.people[0], 1).x, -1);
  EXPECT_DOUBLE_EQ(personPositionAt(sc.people[0], 5).x, 1);
}

TEST(SimScenario, LegsSwingAndPausesHoldTheWalker) {
  // 4 m path at 1 m/s; 2 s at its end (point 2), 1 s at its start (point 1, also at t = 0).
  const Scenario sc = parse(edit("person.1 = 0.4 1.0 -2 1.6 2 1.6",
                                 "person.1 = 0.4 1.0 -2 1.6 2 1.6\nlegs.1 = 0.1 0.2\n"
                                 "pause.1 = 1 2 2\npause.2 = 1 1 1"));
  const PersonSpec& p = sc.people[0];
  EXPECT_DOUBLE_EQ(personPositionAt(p, 0.5).x, -2);  // waiting at the start
  EXPECT_DOUBLE_EQ(personPositionAt(p, 2.0).x, -1);  // 1 s of walking
  EXPECT_DOUBLE_EQ(personPositionAt(p, 6.0).x, 2);   // standing at the end (5 .. 7 s)
  EXPECT_TRUE(personPoseAt(p, 6.0).standing);
  EXPECT_DOUBLE_EQ(personPositionAt(p, 8.0).x, 1);   // on the way back
  EXPECT_DOUBLE_EQ(personPositionAt(p, 11.5).x, -2);  // a cycle is 1 + 4 + 2 + 4 = 11 s
  // Two legs, 0.1 m each, their centres 0.3 m apart across the walk; standing, side by side.
  const auto standing = personBodies(p, 6.0);
  ASSERT_EQ(standing.size(), 2u);
  EXPECT_DOUBLE_EQ(standing[0].radius, 0.05);
  EXPECT_NEAR(standing[0].centre.x, 2, 1e-12);
  EXPECT_NEAR(std::abs(standing[0].centre.y - standing[1].centre.y), 0.3, 1e-12);
  // Walking, 0.1 m into the gait (a quarter of its 0.4 m cycle): swung 0.2 m fore and aft.
  const auto walking = personBodies(p, 1.1);
  EXPECT_NEAR(walking[0].centre.x - walking[1].centre.x, 0.4, 1e-9);
  // Without legs and pauses, one disc as before.
  EXPECT_EQ(personBodies(parse(kValid).people[0], 1).size(), 1u);
}

TEST(SimScenario, BadLegsAndPauses) {
  const std::string person = "person.1 = 0.4 1.0 -2 1.6 2 1.6";
  expectError(edit(person, person + "\nlegs.2 = 0.1 0.2"), {"[people] legs.2", "no person.2"});
  expectError(edit(person, person + "\nlegs.1 = 0.3 0.2"), {"[people] legs.1", "do not fit"});
  expectError(edit(person, person + "\nlegs.1 = 0.1 -1"), {"[people] legs.1", "stride"});
  expectError(edit(person, person + "\nlegs.1 = 0.1"), {"[people] legs.1"});
  expectError(edit(person, person + "\npause.1 = 3 1 2"), {"[people] pause.1", "no person"});
  expectError(edit(person, person + "\npause.1 = 1 3 2"), {"[people] pause.1", "point must be"});
  expectError(edit(person, person + "\npause.1 = 1 1 0"), {"[people] pause.1"});
  expectError(edit(person, person + "\npause.1 = 1 1 2\npause.2 = 1 1 3"),
              {"[people] pause.2", "same point"});
  expectError(edit(person, person + "\nstride.1 = 1"), {"[people] stride.1"});
}

TEST(SimScenario, UnknownSectionOrKey) {
  expectError(std::string(kValid) + "\n[bogus]\nx = 1\n", {"[bogus]"});
  expectError(edit("beams = 91", "beams = 91\nbeamz = 3"), {"[laser]", "beamz"});
  expectError(edit("wall.1 =", "wal.1 ="), {"[world]", "wal.1"});
  expectError(edit("object.2 =", "object.x ="), {"[objects]", "object.x"});
  expectError(edit("seed = 7", "seed = 7\nspeed = 3"), {"[scenario]", "speed"});
}

TEST(SimScenario, MissingRequiredSectionOrKey) {
  expectError(edit("\\[robot\\]", "[robots]"), {"robots"});  // unknown, and [robot] is missing
  expectError(edit("duration_s = 20", ""), {"duration_s"});
  expectError(edit("waypoints = -2 0  2 0", ""), {"waypoints"});
}

TEST(SimScenario, MalformedValues) {
  expectError(edit("speed_mps = 0.5", "speed_mps = fast"), {"[robot]", "speed_mps"});
  expectError(edit("speed_mps = 0.5", "speed_mps = -1"), {"speed_mps"});
  expectError(edit("beams = 91", "beams = 9.5"), {"beams"});
  expectError(edit("loop = true", "loop = maybe"), {"loop"});
  expectError(edit("wall.1 = -3 -2 3 -2", "wall.1 = -3 -2 3"), {"wall.1"});
  expectError(edit("waypoints = -2 0  2 0", "waypoints = -2 0  2"), {"waypoints"});
  expectError(edit("mount = 0.1 0 0", "mount = 0.1 0"), {"mount"});
  expectError(edit("object.1 = 0.3", "object.1 = -0.3"), {"object.1"});
  expectError(edit("move.1 = 5 1 ", "move.1 = 5 3 "), {"move.1", "object.3"});
  expectError(edit("move.1 = 5 1  -1.0 1.2 2", "move.1 = 5 1  -1.0 1.2 -2"), {"move.1"});
  expectError(edit("move.1 = 5 1 ", "move.1 = 50 1 "), {"move.1", "t_start"});
  expectError(edit("person.1 = 0.4 1.0 -2 1.6 2 1.6", "person.1 = 0.4 1.0 -2 1.6"), {"person.1"});
  expectError(edit("fov_deg = 180", "fov_deg = 400"), {"fov_deg"});
  expectError(edit("name = room", "name = ../room"), {"name"});
}

TEST(SimScenario, ObjectOverlappingAWallOrAnotherObjectAtItsStart) {
  expectError(edit("object.1 = 0.3  1.0 1.2", "object.1 = 0.3  1.0 1.9"), {"object.1", "wall.3"});
  expectError(edit("object.2 = 0.5 -1.0 -1.2", "object.2 = 0.5 0.8 1.0"), {"object.2", "object.1"});
}

TEST(SimScenario, MoveTargetOverlappingAWallOrAnotherObject) {
  expectError(edit("move.1 = 5 1  -1.0 1.2 2", "move.1 = 5 1  2.9 1.2 2"), {"move.1", "wall.2"});
  expectError(edit("move.1 = 5 1  -1.0 1.2 2", "move.1 = 5 1  -1.0 -1.0 2"),
              {"move.1", "object.2"});
  // Object 2 arrives where object 1 already stands.
  expectError(edit("move.2 = 9 2   1.0 -1.2 0", "move.2 = 9 2  -1.1 1.0 0"),
              {"move.2", "object.1"});
  // Two moves of one object may not overlap in time.
  expectError(edit("move.2 = 9 2   1.0 -1.2 0", "move.2 = 6 1   1.0 -1.2 0"), {"move.2"});
}

TEST(SimScenario, WaypointInsideAWall) {
  expectError(edit("waypoints = -2 0  2 0", "waypoints = -2 0  3 0"), {"waypoints", "wall.2"});
  expectError(edit("waypoints = -2 0  2 0", "waypoints = -2 0  4 0"), {"waypoints", "wall.2"});
}

TEST(SimScenario, MapImageWalls) {
  const auto dir = std::filesystem::temp_directory_path() / "dynamap_sim_scenario_test";
  std::filesystem::create_directories(dir);
  mrpt::img::CImage img(40, 20, mrpt::img::CH_GRAY);
  img.filledRectangle(0, 0, 39, 19, mrpt::img::TColor(255, 255, 255));
  img.filledRectangle(30, 0, 39, 19, mrpt::img::TColor(0, 0, 0));  // x >= 3 m is wall
  ASSERT_TRUE(img.saveToFile((dir / "walls.png").string()));
  const std::string world =
      "[world]\nmap_image = walls.png\nmap_resolution = 0.1\nmap_origin = 0 -1\n";
  const std::string base =
      std::regex_replace(std::string(kValid), std::regex("\\[world\\][^\\[]*"), world);
  auto withRoute = [&](const std::string& route) {
    return std::regex_replace(
        std::regex_replace(base, std::regex("waypoints = -2 0  2 0"), "waypoints = " + route),
        std::regex("\\[objects\\][\\s\\S]*"), "");
  };
  const Scenario sc =
      parseScenario(IniFile::fromText(withRoute("0.5 0  2 0"), "test.ini"), dir.string());
  EXPECT_EQ(sc.world.grid.width, 40);
  EXPECT_TRUE(sc.world.grid.isWall(35, 0));
  EXPECT_FALSE(sc.world.grid.isWall(25, 0));
  try {
    parseScenario(IniFile::fromText(withRoute("0.5 0  3.5 0"), "test.ini"), dir.string());
    ADD_FAILURE() << "waypoint in a dark pixel accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("waypoints"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("map_image"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parseScenario(IniFile::fromText(withRoute("0.5 0  2 0"), "test.ini"), "/nowhere"),
               ConfigError);
}

TEST(SimScenario, MissingFileNamesIt) {
  try {
    loadScenario("/nonexistent/scenario.ini");
    ADD_FAILURE();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/scenario.ini"), std::string::npos);
  }
}

}  // namespace
}  // namespace dynamap::sim
