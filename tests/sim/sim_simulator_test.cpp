// The time loop, the output files and the bundled rawlogs.

#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/serialization/CArchive.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "dynamap/sim/simulator.h"

namespace dynamap::sim {
namespace {

namespace fs = std::filesystem;
constexpr double kPi = 3.14159265358979323846;

// A 6 × 4 m room; the robot stands still at the centre facing +x. Object 1 starts behind it
// (outside the 180° field of view) and is carried in front of it at t = 2 s.
const char* kStandStill = R"(
[scenario]
name = still
duration_s = 4
seed = 3
[world]
wall.1 = -3 -2 3 -2
wall.2 = 3 -2 3 2
wall.3 = 3 2 -3 2
wall.4 = -3 2 -3 -2
[robot]
waypoints = 0 0
scan_rate_hz = 5
[laser]
beams = 181
fov_deg = 180
max_range_m = 8
[objects]
object.1 = 0.3 -2 0
[moves]
move.1 = 2 1 2 0 0
)";

const char* kSmall = R"(
[scenario]
name = small
duration_s = 12
seed = 11
[world]
wall.1 = -3 -2 3 -2
wall.2 = 3 -2 3 2
wall.3 = 3 2 -3 2
wall.4 = -3 2 -3 -2
[robot]
waypoints = -2 0  2 0
speed_mps = 0.5
turn_rate_dps = 90
[laser]
beams = 91
fov_deg = 180
max_range_m = 5
range_noise_std_m = 0.02
[odometry]
noise_xy_per_m = 0.02
noise_yaw_per_rad = 0.02
[objects]
object.1 = 0.3 1 1.2
[moves]
move.1 = 3 1 -1 1.2 2
[people]
person.1 = 0.4 0.8 -2 -1.4 2 -1.4
)";

Scenario parse(const std::string& text) {
  return parseScenario(IniFile::fromText(text, "test.ini"), ".");
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

fs::path tempDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("dynamap_sim_test_" + name);
  fs::remove_all(d);
  return d;
}

TEST(SimSimulator, RobotDrivesTurnsAndLoops) {
  RobotSpec spec;
  spec.waypoints = {{0, 0}, {2, 0}};
  spec.speed_mps = 0.5;
  spec.turn_rate_dps = 90;
  const RobotPath path(spec);
  EXPECT_NEAR(path.at(0).phi, 0, 1e-12);
  EXPECT_NEAR(path.at(2).x, 1, 1e-12);
  EXPECT_NEAR(path.at(4).x, 2, 1e-12);
  EXPECT_NEAR(std::abs(path.at(6).phi), kPi, 1e-12);  // turned about after 2 s at 90°/s
  EXPECT_NEAR(path.at(8).x, 1, 1e-12);                // half way back
  EXPECT_NEAR(path.passDuration(), 12, 1e-12);
  EXPECT_NEAR(path.at(14).x, 1, 1e-12);  // the second lap
}

TEST(SimSimulator, ScansHaveTheLaserGeometry) {
  const Scenario sc = parse(kStandStill);
  Simulator sim(sc);
  EXPECT_EQ(sim.scanCount(), 21u);
  ScanTruth st;
  ASSERT_TRUE(sim.next(st));
  ASSERT_EQ(st.ranges.size(), 181u);
  // Beam 90 looks straight ahead at the wall 3 m away; beam 0 to the right at the wall 2 m away.
  EXPECT_NEAR(st.angles[90], 0, 1e-6);
  EXPECT_NEAR(st.ranges[90], 3, 0.06);
  EXPECT_NEAR(st.ranges[0], 2, 0.06);
  EXPECT_TRUE(st.valid[0] && st.valid[90]);
}

TEST(SimSimulator, HitsAreZeroBeforeTheMoveBringsAnObjectIntoViewAndPositiveAfter) {
  const Scenario sc = parse(kStandStill);
  Simulator sim(sc);
  ScanTruth st;
  int seen = 0;
  while (sim.next(st)) {
    ASSERT_EQ(st.bodies.size(), 1u);
    if (st.t < 2) {
      EXPECT_EQ(st.hits[0], 0) << "t = " << st.t;
    } else {
      EXPECT_GT(st.hits[0], 0) << "t = " << st.t;
      ++seen;
    }
  }
  EXPECT_EQ(seen, 11);
}

TEST(SimSimulator, MaxRangeGivesInvalidReturns) {
  std::string text = kStandStill;
  text.replace(text.find("max_range_m = 8"), 15, "max_range_m = 2.5");
  Simulator sim(parse(text));
  ScanTruth st;
  ASSERT_TRUE(sim.next(st));
  EXPECT_FALSE(st.valid[90]);  // the wall ahead is 3 m away
  EXPECT_EQ(st.ranges[90], 0.f);
  EXPECT_TRUE(st.valid[0]);  // the one on the right is 2 m away
}

TEST(SimSimulator, TwoRunsWriteIdenticalBytes) {
  const Scenario sc = parse(kSmall);
  const fs::path a = tempDir("det_a"), b = tempDir("det_b");
  writeSimulation(sc, a.string());
  writeSimulation(sc, b.string());
  for (const char* ext : {".rawlog", ".gt.txt", ".objects.csv", ".moves.csv", ".world.png"}) {
    const std::string fa = slurp((a / ("small" + std::string(ext))).string());
    EXPECT_FALSE(fa.empty()) << ext;
    EXPECT_EQ(fa, slurp((b / ("small" + std::string(ext))).string())) << ext;
  }
}

TEST(SimSimulator, AnotherSeedGivesOtherNoise) {
  std::string text = kSmall;
  text.replace(text.find("seed = 11"), 9, "seed = 12");
  ScanTruth s1, s2;
  Simulator a(parse(kSmall)), b(parse(text));
  ASSERT_TRUE(a.next(s1) && b.next(s2));
  EXPECT_NE(s1.ranges, s2.ranges);
}

// ---- the bundled scenarios ----------------------------------------------------------------

const char* const kBundled[] = {"arena", "corridors", "corridors_odom", "people", "tiny", "walkers", "storeroom"};

std::string bundledDir(const std::string& name) {
  return std::string(DYNAMAP_SOURCE_DIR) + "/rawlogs/" + name;
}

struct GtLine {
  double t, x, y, phi;
};

std::vector<GtLine> readGt(const std::string& path) {
  std::ifstream in(path);
  std::vector<GtLine> out;
  GtLine g{};
  while (in >> g.t >> g.x >> g.y >> g.phi) out.push_back(g);
  return out;
}

TEST(SimBundled, RawlogsLoadInMrptAndMatchTheirGroundTruth) {
  for (const std::string name : kBundled) {
    SCOPED_TRACE(name);
    const std::string base = bundledDir(name) + "/" + name;
    const auto gt = readGt(base + ".gt.txt");
    ASSERT_FALSE(gt.empty());
    mrpt::io::CFileGZInputStream in(base + ".rawlog");
    auto ar = mrpt::serialization::archiveFrom(in);
    std::size_t records = 0;
    const char* labels[] = {"ODOMETRY", "LASER", "GT"};
    for (;;) {
      mrpt::serialization::CSerializable::Ptr obj;
      try {
        obj = ar.ReadObject();
      } catch (const std::exception&) {
        break;  // end of file
      }
      auto obs = std::dynamic_pointer_cast<mrpt::obs::CObservation>(obj);
      ASSERT_TRUE(obs) << "record " << records;
      const std::size_t scan = records / 3;
      ASSERT_LT(scan, gt.size());
      EXPECT_EQ(obs->sensorLabel, labels[records % 3]);
      EXPECT_NEAR(mrpt::Clock::toDouble(obs->timestamp), gt[scan].t, 1e-3);
      switch (records % 3) {
        case 0:
          EXPECT_TRUE(std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(obs));
          break;
        case 1:
          EXPECT_TRUE(std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(obs));
          break;
        case 2: {
          auto pose = std::dynamic_pointer_cast<mrpt::obs::CObservationRobotPose>(obs);
          ASSERT_TRUE(pose);
          EXPECT_NEAR(pose->pose.mean.x(), gt[scan].x, 1e-5);
          EXPECT_NEAR(pose->pose.mean.y(), gt[scan].y, 1e-5);
          EXPECT_NEAR(std::remainder(pose->pose.mean.yaw() - gt[scan].phi, 2 * kPi), 0, 1e-5);
        }
      }
      ++records;
    }
    EXPECT_EQ(records, 3 * gt.size());
  }
}

struct Row {
  std::size_t scan;
  double t;
  int hits;
};

/// objects.csv rows of kind "object", by object id.
std::map<int, std::vector<Row>> readObjectRows(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "scan_index,t,kind,id,x,y,diameter,hits");
  std::map<int, std::vector<Row>> out;
  while (std::getline(in, line)) {
    std::istringstream ss(line);
    std::string f[8];
    for (auto& s : f) std::getline(ss, s, ',');
    if (f[2] == "object")
      out[std::stoi(f[3])].push_back({std::stoul(f[0]), std::stod(f[1]), std::stoi(f[7])});
  }
  return out;
}

int hitsBetween(const std::vector<Row>& rows, double t0, double t1) {
  int n = 0;
  for (const auto& r : rows) n += (r.t >= t0 && r.t <= t1) ? r.hits : 0;
  return n;
}

TEST(SimBundled, CommittedTruthIsUpToDateWithTheScenario) {
  for (const std::string name : kBundled) {
    SCOPED_TRACE(name);
    const Scenario sc =
        loadScenario(std::string(DYNAMAP_SOURCE_DIR) + "/config/scenarios/" + name + ".ini");
    const fs::path out = tempDir("bundled_" + name);
    writeSimulation(sc, out.string());
    for (const char* ext : {".gt.txt", ".objects.csv", ".moves.csv"}) {
      EXPECT_EQ(slurp((out / (name + ext)).string()), slurp(bundledDir(name) + "/" + name + ext))
          << ext << " is stale: run make scenarios";
    }
  }
}

TEST(SimBundled, EveryMovedObjectIsSeenAfterItsMove) {
  for (const std::string name : kBundled) {
    SCOPED_TRACE(name);
    const Scenario sc =
        loadScenario(std::string(DYNAMAP_SOURCE_DIR) + "/config/scenarios/" + name + ".ini");
    auto rows = readObjectRows(bundledDir(name) + "/" + name + ".objects.csv");
    for (const auto& m : sc.moves) {
      double next = sc.duration_s;  // until the object's next move
      for (const auto& o : sc.moves) {
        if (o.object_id == m.object_id && o.t_start > m.t_start) next = std::min(next, o.t_start);
      }
      EXPECT_GT(hitsBetween(rows[m.object_id], m.tEnd(), next), 0) << "move." << m.id;
    }
  }
}

TEST(SimBundled, ArenaMovesHappenInViewCorridorMovesOutOfView) {
  for (const std::string name : {"arena", "corridors"}) {
    SCOPED_TRACE(name);
    const Scenario sc =
        loadScenario(std::string(DYNAMAP_SOURCE_DIR) + "/config/scenarios/" + name + ".ini");
    ASSERT_EQ(sc.moves.size(), 20u);
    ASSERT_EQ(sc.objects.size(), 6u);
    auto rows = readObjectRows(bundledDir(name) + "/" + name + ".objects.csv");
    for (const auto& m : sc.moves) {
      const int during = hitsBetween(rows[m.object_id], m.t_start, m.tEnd());
      const int around = hitsBetween(rows[m.object_id], m.t_start - 3, m.tEnd() + 3);
      if (name == "arena") {
        EXPECT_GT(m.duration, 0) << "move." << m.id;
        EXPECT_GT(during, 0) << "move." << m.id << " not watched";
      } else {
        EXPECT_EQ(m.duration, 0) << "move." << m.id;
        EXPECT_EQ(around, 0) << "move." << m.id << " seen within 3 s of happening";
      }
    }
  }
}

TEST(SimBundled, ObjectsStayClearOfTheRobotsRoute) {
  constexpr double kRobotRadius = 0.25;
  for (const std::string name : kBundled) {
    SCOPED_TRACE(name);
    const Scenario sc =
        loadScenario(std::string(DYNAMAP_SOURCE_DIR) + "/config/scenarios/" + name + ".ini");
    const auto& w = sc.robot.waypoints;
    auto check = [&](Vec2 p, double d, const std::string& what) {
      for (std::size_t i = 0; i < w.size(); ++i) {
        const Segment leg{w[i], w[(i + 1) % w.size()]};
        EXPECT_GE(pointSegmentDistance(p, leg), d / 2 + kRobotRadius) << what;
      }
    };
    for (const auto& o : sc.objects) check(o.start, o.diameter, "object." + std::to_string(o.id));
    for (const auto& m : sc.moves) {
      for (const auto& o : sc.objects) {
        if (o.id == m.object_id) check(m.to, o.diameter, "move." + std::to_string(m.id));
      }
    }
  }
}

}  // namespace
}  // namespace dynamap::sim
