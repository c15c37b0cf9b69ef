#pragma once
// The simulation's time loop and its output files.
//
// Time: scan k is taken at t = k / scan_rate_hz, k = 0 .. floor(duration_s · scan_rate_hz).
// Every timestamp written is kEpochUnixSeconds + t. The robot pose, the objects and the people
// are all evaluated at t; the laser sweep is instantaneous.

#include <cstddef>
#include <string>
#include <vector>

#include "dynamap/sim/random.h"
#include "dynamap/sim/scenario.h"

namespace dynamap::sim {

/// Simulated time 0 is 2024-01-01T00:00:00Z (UNIX seconds); rawlog timestamps and gt.txt use it
/// (plus the scenario's clock_offset_s: a later session's day).
constexpr double kEpochUnixSeconds = 1704067200.0;

struct Pose2 {
  double x = 0;
  double y = 0;
  double phi = 0;  ///< rad, in (-pi, pi]
};

/// The robot's true pose over time: it starts at the first waypoint facing the second, drives
/// each leg straight at speed_mps and turns in place (the short way) at turn_rate_dps toward the
/// next. With loop it returns to the first waypoint and starts over; without, it stays at the last.
class RobotPath {
 public:
  explicit RobotPath(const RobotSpec& spec);
  Pose2 at(double t) const;
  /// Duration of one pass over the route (a full cycle when looping).
  double passDuration() const { return pass_; }

 private:
  struct Leg {
    double t0 = 0, t1 = 0;
    Pose2 from;
    double dx = 0, dy = 0, dphi = 0;  ///< change over the whole leg (a drive or a turn)
  };
  std::vector<Leg> legs_;
  double pass_ = 0;
  bool loop_ = true;
  Pose2 end_;
};

/// One scan and the truth behind it.
struct ScanTruth {
  std::size_t index = 0;
  double t = 0;                ///< simulated seconds
  Pose2 pose;                  ///< true robot pose
  Pose2 odometry;              ///< noisy odometry (starts equal to the true start pose)
  Pose2 sensor;                ///< true sensor pose in the world
  std::vector<double> angles;  ///< beam angles relative to the sensor, rad (MRPT order)
  std::vector<float> ranges;   ///< measured (noisy) ranges, m; 0 where invalid
  std::vector<char> valid;     ///< false: no echo within max range
  std::vector<Body> bodies;    ///< objects then people, where they are at t
  std::vector<int> hits;       ///< per body: beams whose first surface was that body
};

/// Steps through a scenario scan by scan. Range noise and odometry noise come from two streams
/// seeded from the scenario's seed, so changing one noise setting leaves the other unchanged.
class Simulator {
 public:
  explicit Simulator(const Scenario& scenario);
  std::size_t scanCount() const { return scan_count_; }
  /// Fills `out` with the next scan; false after the last.
  bool next(ScanTruth& out);

 private:
  const Scenario sc_;  // a copy: small, and no lifetime to get wrong
  RobotPath path_;
  Rng range_rng_;
  Rng odo_rng_;
  std::size_t scan_count_ = 0;
  std::size_t k_ = 0;
  Pose2 last_pose_;
  Pose2 odometry_;
  std::vector<double> angles_;
};

/// The files one run writes into out_dir, each named <scenario name>.<ext>.
struct SimulationFiles {
  std::string rawlog, gt, objects, moves, world_png;
};
SimulationFiles outputPaths(const Scenario& scenario, const std::string& out_dir);

/// Runs the whole scenario and writes every output file (creating out_dir). Same scenario, same
/// bytes. Returns the number of scans written.
std::size_t writeSimulation(const Scenario& scenario, const std::string& out_dir);

/// Runs every session of a multi-session scenario (sessionScenario 1, 2, ...) into out_dir, each
/// as writeSimulation does (files "<name>.*", "<name>.s2.*", ...), and writes the truth of the
/// changes between them to "<name>.changes.csv" (csv::kSessionChanges). A scenario without
/// sessions writes what writeSimulation writes and no changes file. Returns the scans of each.
std::vector<std::size_t> writeSessions(const Scenario& scenario, const std::string& out_dir);

/// The world at t = 0 as a PNG: walls, objects, people and their paths, the robot's route.
void renderWorldImage(const Scenario& scenario, const std::string& path);

}  // namespace dynamap::sim
