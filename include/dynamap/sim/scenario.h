#pragma once
// A simulation scenario: the world, the robot's route, its laser and odometry, the movable
// objects with their moves and the walking people. loadScenario() reads the ini format of
// docs/scenario_format.md and validates it completely; everything downstream may trust it.
// Every error is a dynamap::ConfigError naming the file, the section and the key.

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "dynamap/base/ini.h"
#include "dynamap/sim/world.h"

namespace dynamap::sim {

struct RobotSpec {
  std::vector<Vec2> waypoints;  ///< driven in order, starting at the first
  bool loop = true;             ///< after the last, back to the first and again
  double speed_mps = 0.4;       ///< m/s along straight legs
  double turn_rate_dps = 45;    ///< deg/s, turning in place at each waypoint
  double scan_rate_hz = 5;      ///< scans per second (one ODOMETRY, LASER, GT triple each)
};

struct LaserSpec {
  int beams = 361;
  double fov_deg = 180;
  double max_range_m = 8;
  double range_noise_std_m = 0.01;
  Vec2 mount;                ///< x y of the sensor on the robot, metres
  double mount_yaw_deg = 0;  ///< sensor heading on the robot
};

struct OdometrySpec {
  double noise_xy_per_m = 0;     ///< std (m) of each translation error component per metre driven
  double noise_yaw_per_rad = 0;  ///< std (rad) of heading error per radian turned
};

struct ObjectSpec {
  int id = 0;  ///< the n of object.<n>
  double diameter = 0;
  Vec2 start;
};

struct MoveSpec {
  int id = 0;  ///< the n of move.<n>
  int object_id = 0;
  double t_start = 0;
  Vec2 to;
  double duration = 0;  ///< 0: the object is at `to` at once
  double tEnd() const { return t_start + duration; }
};

/// A stop of a walker at one point of its path, each time it arrives there.
struct PauseSpec {
  std::size_t point = 0;  ///< 0-based index into the path
  double duration = 0;    ///< [s]
};

struct PersonSpec {
  int id = 0;           ///< the n of person.<n>
  double diameter = 0;  ///< the whole body's width (legs: from one leg's outside to the other's)
  double speed_mps = 0;
  std::vector<Vec2> path;   ///< walked to its end and back, for the whole run
  double leg_diameter = 0;  ///< > 0: seen as two legs of this diameter (legs.<n>), else one disc
  double stride = 0;        ///< [m] each leg swings this far fore and aft of the body (legs.<n>)
  std::vector<PauseSpec> pauses;  ///< by point (pause.<n>)
};

/// Where a walker is at one moment and how its legs stand.
struct PersonPose {
  Vec2 centre;
  Vec2 heading{1, 0};     ///< unit vector of the leg being walked
  double walked = 0;      ///< [m] distance walked since t = 0 (the gait's phase)
  bool standing = false;  ///< in a pause
};

/// What changes before session N (N >= 2) of a multi-session scenario, and the route it drives.
/// Session 1 is the scenario itself; session N starts from the world and the objects as
/// session N-1 left them, these changes applied.
struct SessionSpec {
  int number = 0;               ///< the N of [session.N]: 2, 3, ... without gaps
  double duration_s = 0;        ///< the scenario's when not given
  std::vector<Vec2> waypoints;  ///< this session's route (its own start)
  bool loop = true;
  struct Move {
    int object_id = 0;
    Vec2 to;
  };
  std::vector<Move> moved;           ///< move.<id> = x y, by id
  std::vector<int> removed;          ///< remove = ids: taken out of the building
  std::vector<ObjectSpec> added;     ///< object.<n> = diameter x y, n new to the scenario
  std::vector<Segment> walls_added;  ///< wall.<n> = x1 y1 x2 y2, n new to the scenario
  std::vector<int> wall_numbers_added;
  std::vector<int> walls_removed;  ///< remove_walls = numbers of walls standing before it
};

/// One change between two sessions, as the simulator's truth states it.
struct SessionChange {
  int session = 0;   ///< the session it is seen in (2, 3, ...)
  std::string kind;  ///< object_moved, object_new, object_gone, structure_added, structure_removed
  int id = 0;        ///< the object's or the wall's number in the scenario
  double size = 0;   ///< the object's diameter or the wall's length [m]
  Vec2 from, to;     ///< moved: old and new place; new: to; gone: from; a wall: its two ends
};

struct Scenario {
  std::string file;  ///< where it was read from (for messages)
  std::string name;  ///< names the output files; letters, digits, '_' and '-'
  double duration_s = 0;
  std::uint64_t seed = 0;
  StaticWorld world;
  std::vector<std::string> wall_keys;  ///< wall.<n> of each world.segments entry ("[session.N]
                                       ///< wall.<n>" for one a session added)
  std::string map_image;               ///< resolved path, empty if none
  RobotSpec robot;
  LaserSpec laser;
  OdometrySpec odometry;
  std::vector<ObjectSpec> objects;    ///< by id
  std::vector<MoveSpec> moves;        ///< by t_start, then id
  std::vector<PersonSpec> people;     ///< by id
  std::vector<SessionSpec> sessions;  ///< [session.N], N = 2, 3, ...; empty for one session
  double clock_offset_s = 0;          ///< added to every timestamp written (a later session's day)
};

/// Reads and validates the scenario file at `path`.
Scenario loadScenario(const std::string& path);
/// Reads and validates `ini`; a map_image is looked up relative to `base_dir`.
Scenario parseScenario(const IniFile& ini, const std::string& base_dir);

/// Session n (1-based) as a scenario of its own, to simulate like any other: session 1 is the
/// scenario without its sessions; session N >= 2 is named "<name>.s<N>", takes the world and the
/// objects where session N-1 left them with its changes applied, has no moves, keeps the people,
/// drives its own route, draws its noise from seed + N - 1 and is timed (N - 1) days later.
Scenario sessionScenario(const Scenario& scenario, int n);
/// Calls `f` with sessionScenario(scenario, 1), 2, ... in turn, each built from the one before
/// (linear in the sessions; one session's copy alive at a time besides the scenario).
void forEachSession(const Scenario& scenario, const std::function<void(const Scenario&)>& f);
/// Every change between consecutive sessions, by session, then kind as in SessionChange, then id.
std::vector<SessionChange> sessionChanges(const Scenario& scenario);

/// Where object `index` (into scenario.objects) is at time t, moves applied.
Vec2 objectPositionAt(const Scenario& scenario, std::size_t index, double t);
/// Where the object of move m stands when the move begins.
Vec2 moveOrigin(const Scenario& scenario, const MoveSpec& m);
/// Where a person is at time t (walking the path to its end and back, standing at its pauses).
Vec2 personPositionAt(const PersonSpec& person, double t);
PersonPose personPoseAt(const PersonSpec& person, double t);
/// The laser targets of a person at time t: one disc, or two legs side by side whose fore-aft
/// offsets swing as +-stride * sin(pi * walked / stride) (opposite for the two legs; still
/// while standing).
std::vector<Body> personBodies(const PersonSpec& person, double t);
/// Every object and person as a laser target at time t: objects first (by id), then people
/// (by id; a person with legs is two bodies of the same id).
std::vector<Body> bodiesAt(const Scenario& scenario, double t);

}  // namespace dynamap::sim
