// dynamap map --prior: a second session of a simulated room, mapped from the first one's
// session.json, reports exactly what changed between them (objects moved, new and gone, with
// their ids; a partition removed, one added); --initial-pose; the errors of both options.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <vector>

#include "../test_util.h"

namespace dynamap {
namespace {

const std::string kExe = DYNAMAP_EXE;

// The room of both sessions: an 8 x 8 m box the robot circles, 2 minutes at 5 Hz each.
const char* const kLaser = R"(
[laser]
beams = 181
fov_deg = 180
max_range_m = 8
range_noise_std_m = 0.01
)";

// Session 1: a partition at x = -3; four objects stand still; objects 5 and 6 are moved in
// view, so the table holds them (ids 1 and 2).
const char* const kSession1 = R"(
[scenario]
name = s1
duration_s = 120
seed = 1

[world]
wall.1 = -4 -4  4 -4
wall.2 =  4 -4  4  4
wall.3 =  4  4 -4  4
wall.4 = -4  4 -4 -4
wall.5 = -3.0 3.0  -3.0 1.0

[objects]
object.1 = 0.20  2.8 2.8
object.2 = 0.30  3.0 -2.8
object.3 = 0.45  -2.8 -2.8
object.4 = 0.60  0.3 0.5
object.5 = 0.25  1.0 -3.2
object.6 = 0.50  -3.0 -0.5

[moves]
move.1 = 30 5  2.6 -1.6  0
move.2 = 45 6  -2.9 0.4  0
)";

// Session 2, driven the other way round: the partition is gone and another stands at x = 2.8;
// object 2 (in S) moved; object 3 (in S) and table object 2 are gone (out of the room); table
// object 1 moved; a new object stands at (-2.2, 2.6).
const char* const kSession2 = R"(
[scenario]
name = s2
duration_s = 120
seed = 2

[world]
wall.1 = -4 -4  4 -4
wall.2 =  4 -4  4  4
wall.3 =  4  4 -4  4
wall.4 = -4  4 -4 -4
wall.6 = 2.8 -0.8  2.8 0.8

[objects]
object.1 = 0.20  2.8 2.8
object.2 = 0.30  -0.5 -2.9
object.3 = 0.45  40 40
object.4 = 0.60  0.3 0.5
object.5 = 0.35  -2.2 2.6
object.6 = 0.25  -1.0 3.2
object.7 = 0.50  40 -40
)";

struct Change {
  std::string kind;
  int id;
  double size, from_x, from_y, to_x, to_y;
};

double field(const std::string& s) {
  return s.empty() ? NAN : std::stod(s);
}

std::vector<Change> readChanges(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "kind,id,size_m,from_x,from_y,to_x,to_y,first_seen_t,cells");
  std::vector<Change> rows;
  while (std::getline(in, line)) {
    std::stringstream s(line);
    std::string f[9];
    for (auto& x : f) std::getline(s, x, ',');
    rows.push_back(
        {f[0], std::stoi(f[1]), field(f[2]), field(f[3]), field(f[4]), field(f[5]), field(f[6])});
  }
  return rows;
}

void writeScenario(const std::string& path, const char* text) {
  const bool first = std::string(text).find("name = s1") != std::string::npos;
  std::ofstream(path) << text << "\n[robot]\nloop = true\nwaypoints = "
                      << (first ? "-1.5 -1.5  1.5 -1.5  1.5 1.5  -1.5 1.5\n"
                                : "1.5 1.5  -1.5 1.5  -1.5 -1.5  1.5 -1.5\n")
                      << kLaser;
}

// Both sessions simulated and the first mapped, once for the whole suite.
class Sessions : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = test::tempDir("sessions");
    for (const auto& [name, text] : {std::pair{"s1", kSession1}, {"s2", kSession2}}) {
      writeScenario(dir_ + "/" + name + ".ini", text);
      ASSERT_EQ(test::run(kExe + " simulate --scenario " + dir_ + "/" + name + ".ini --out " +
                          dir_ + "/sim"),
                0);
    }
    std::string out;
    ASSERT_EQ(test::run(kExe + " map --input " + dir_ +
                            "/sim/s1.rawlog --poses ground_truth --out " + dir_ + "/m1",
                        &out),
              0)
        << out;
  }
  static std::string dir_;
};
std::string Sessions::dir_;

const Change* find(const std::vector<Change>& rows, const std::string& kind, double x, double y) {
  for (const Change& c : rows) {
    const bool gone = kind.rfind("_gone") != std::string::npos || kind == "structure_removed";
    const double cx = gone ? c.from_x : c.to_x, cy = gone ? c.from_y : c.to_y;
    if (c.kind == kind && std::hypot(cx - x, cy - y) < 0.15) return &c;
  }
  return nullptr;
}

TEST_F(Sessions, TheSecondSessionReportsEveryChangeAndNoOther) {
  std::string out;
  ASSERT_EQ(
      test::run(kExe + " map --input " + dir_ + "/sim/s2.rawlog --poses ground_truth --prior " +
                    dir_ + "/m1 --out " + dir_ + "/m2",
                &out),
      0)
      << out;
  const std::vector<Change> rows = readChanges(dir_ + "/m2/changes.csv");
  EXPECT_EQ(rows.size(), 7u);
  // Table objects keep their ids: object 1 moved, object 2 gone.
  const Change* moved1 = find(rows, "object_moved", -1.0, 3.2);
  ASSERT_NE(moved1, nullptr);
  EXPECT_EQ(moved1->id, 1);
  EXPECT_NEAR(moved1->from_x, 2.6, 0.1);
  EXPECT_NEAR(moved1->from_y, -1.6, 0.1);
  const Change* gone2 = find(rows, "object_gone", -2.9, 0.4);
  ASSERT_NE(gone2, nullptr);
  EXPECT_EQ(gone2->id, 2);
  // Objects of the first session's S: the 0.30 m one moved (the place it left has its size),
  // the 0.45 m one is gone (no id: it never moved before); the new one is new.
  const Change* moved_s = find(rows, "object_moved", -0.5, -2.9);
  ASSERT_NE(moved_s, nullptr);
  EXPECT_NEAR(moved_s->size, 0.30, 0.03);
  EXPECT_NEAR(moved_s->from_x, 3.0, 0.2);
  EXPECT_NEAR(moved_s->from_y, -2.8, 0.2);
  EXPECT_GE(moved_s->id, 3);
  const Change* gone_s = find(rows, "object_gone", -2.8, -2.8);
  ASSERT_NE(gone_s, nullptr);
  EXPECT_EQ(gone_s->id, 0);
  const Change* fresh = find(rows, "object_new", -2.2, 2.6);
  ASSERT_NE(fresh, nullptr);
  EXPECT_NEAR(fresh->size, 0.35, 0.03);
  EXPECT_NE(fresh->id, moved_s->id);
  EXPECT_GE(fresh->id, 3);
  // The partitions: removed at x = -3 (2 m), added at x = 2.8 (1.6 m).
  const Change* removed = find(rows, "structure_removed", -3.0, 2.0);
  ASSERT_NE(removed, nullptr);
  EXPECT_NEAR(removed->size, 2.0, 0.1);
  const Change* added = find(rows, "structure_added", 2.8, 0.0);
  ASSERT_NE(added, nullptr);
  EXPECT_NEAR(added->size, 1.6, 0.1);
  // The state it leaves for a third session counts two, and the summary counts the changes.
  EXPECT_NE(test::readFile(dir_ + "/m2/session.json").find("\"sessions\": 2"), std::string::npos);
  EXPECT_NE(test::readFile(dir_ + "/m2/summary.json").find("\"structure_added\": 1"),
            std::string::npos);
  EXPECT_FALSE(test::readFile(dir_ + "/m2/changes.png").empty());
}

TEST_F(Sessions, TheFirstSessionAgainstItselfChangesNothing) {
  std::string out;
  ASSERT_EQ(
      test::run(kExe + " map --input " + dir_ + "/sim/s1.rawlog --poses ground_truth --prior " +
                    dir_ + "/m1 --out " + dir_ + "/again",
                &out),
      0)
      << out;
  const std::vector<Change> rows = readChanges(dir_ + "/again/changes.csv");
  for (const Change& c : rows) ADD_FAILURE() << c.kind << " " << c.id << " at " << c.to_x;
}

TEST_F(Sessions, AnInitialPoseMovesTheWholeLogRigidly) {
  // The log's first true pose as the initial pose: the same run to the byte.
  std::ifstream gt(dir_ + "/sim/s2.gt.txt");
  std::string line;
  while (std::getline(gt, line) && (line.empty() || line[0] == '%')) {
  }
  std::stringstream s(line);
  double t, x, y, phi;
  s >> t >> x >> y >> phi;
  std::ostringstream pose;
  pose.precision(17);
  pose << x << " " << y << " " << phi;
  std::string out;
  const std::string second =
      kExe + " map --input " + dir_ + "/sim/s2.rawlog --poses ground_truth --prior " + dir_ + "/m1";
  ASSERT_EQ(test::run(second + " --out " + dir_ + "/m2i", &out), 0) << out;
  ASSERT_EQ(
      test::run(second + " --initial-pose \"" + pose.str() + "\" --out " + dir_ + "/m3", &out), 0)
      << out;
  EXPECT_EQ(test::readFile(dir_ + "/m3/changes.csv"), test::readFile(dir_ + "/m2i/changes.csv"));
  // Half a metre off: the walls no longer agree, and the report says so.
  pose.str("");
  pose << x + 0.5 << " " << y << " " << phi;
  ASSERT_EQ(
      test::run(kExe + " map --input " + dir_ + "/sim/s2.rawlog --poses ground_truth --prior " +
                dir_ + "/m1 --initial-pose \"" + pose.str() + "\" --out " + dir_ + "/m4"),
      0);
  EXPECT_GT(readChanges(dir_ + "/m4/changes.csv").size(), 7u);
}

TEST_F(Sessions, ErrorsNameTheOptionOrTheFile) {
  std::string out;
  const std::string log = " --input " + dir_ + "/sim/s2.rawlog --poses ground_truth";
  EXPECT_EQ(
      test::run(kExe + " map" + log + " --initial-pose \"0 0 0\" --out " + dir_ + "/e1", &out), 2);
  EXPECT_NE(out.find("--initial-pose: only with --prior"), std::string::npos) << out;
  EXPECT_NE(
      test::run(kExe + " map" + log + " --prior " + dir_ + "/sim --out " + dir_ + "/e2", &out), 0);
  EXPECT_NE(out.find(dir_ + "/sim/session.json: no session state there"), std::string::npos) << out;
  EXPECT_NE(test::run(kExe + " map" + log + " --prior " + dir_ +
                          "/m1 --initial-pose \"1 2\" --out " + dir_ + "/e3",
                      &out),
            0);
  EXPECT_NE(out.find("--initial-pose: "), std::string::npos) << out;
  // A prior of another resolution does not fit: the file is named, nothing is written.
  std::ofstream(dir_ + "/coarse.ini") << "[dynamic_map]\nresolution = 0.1\n";
  EXPECT_NE(test::run(kExe + " map" + log + " --config " + dir_ + "/coarse.ini --prior " + dir_ +
                          "/m1 --out " + dir_ + "/e4",
                      &out),
            0);
  EXPECT_NE(out.find(dir_ + "/m1: the prior session's map does not fit this run: its resolution"),
            std::string::npos)
      << out;
  // The same on odometry, where the start is searched for: the prior is checked first.
  EXPECT_EQ(test::run(kExe + " map --input " + dir_ + "/sim/s2.rawlog --poses odometry --config " +
                          dir_ + "/coarse.ini --prior " + dir_ + "/m1 --out " + dir_ + "/e5",
                      &out),
            1);
  EXPECT_NE(out.find(dir_ + "/m1: the prior session's map does not fit this run: its resolution"),
            std::string::npos)
      << out;
}

// The start a run printed ("the log starts at X Y PHI"): within 0.05 m and 1 degree of (x, y, phi).
void expectStart(const std::string& out, double x, double y, double phi) {
  const auto at = out.find("the log starts at ");
  ASSERT_NE(at, std::string::npos) << out;
  double fx = 0, fy = 0, fphi = 0;
  std::istringstream(out.substr(at + 18)) >> fx >> fy >> fphi;
  EXPECT_NEAR(fx, x, 0.05);
  EXPECT_NEAR(fy, y, 0.05);
  EXPECT_NEAR(std::remainder(fphi - phi, 2 * M_PI), 0.0, 1.0 * M_PI / 180);
}

// Without --initial-pose, on odometry: the first scans are searched for in the whole prior map
// (the first session's log again, its frame not used: only its poses relative to each other).
TEST_F(Sessions, TheStartOfALogOnOdometryIsFoundInThePriorMap) {
  std::string out;
  ASSERT_EQ(test::run(kExe + " map --input " + dir_ + "/sim/s1.rawlog --poses odometry --prior " +
                          dir_ + "/m1 --no-baseline --out " + dir_ + "/m5",
                      &out),
            0)
      << out;
  // Session 1 starts at (-1.5, -1.5) facing east (towards the second waypoint).
  expectStart(out, -1.5, -1.5, 0.0);
  EXPECT_EQ(readChanges(dir_ + "/m5/changes.csv").size(), 0u);
}

// A bare square room looks the same from four headings: the search says so and names them.
TEST_F(Sessions, AStartTheMapCannotTellApartIsAnErrorWithTheCandidates) {
  const std::string d = test::tempDir("sessions_square");
  std::ofstream(d + "/square.ini") << "[scenario]\nname = square\nduration_s = 20\nseed = 3\n"
                                   << "[world]\nwall.1 = -4 -4  4 -4\nwall.2 = 4 -4  4 4\n"
                                   << "wall.3 = 4 4  -4 4\nwall.4 = -4 4  -4 -4\n"
                                   << "[robot]\nwaypoints = 0 0  1 0\nloop = true\n"
                                   << kLaser;
  ASSERT_EQ(test::run(kExe + " simulate --scenario " + d + "/square.ini --out " + d), 0);
  ASSERT_EQ(test::run(kExe + " map --input " + d + "/square.rawlog --poses ground_truth --out " +
                      d + "/first"),
            0);
  std::string out;
  EXPECT_EQ(test::run(kExe + " map --input " + d + "/square.rawlog --poses odometry --prior " + d +
                          "/first --out " + d + "/second",
                      &out),
            1);
  EXPECT_NE(out.find(d + "/square.rawlog: its first scans fit two places of the prior session's "
                         "map (best "),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("give --initial-pose"), std::string::npos);
}

// Later sessions that start where the first 4 m fit several places of the map before (the
// offices' third: two rooms alike; the atrium's second: a hall symmetric under a half turn):
// followed along the log, the scans keep fitting one place clearly better than every other.
struct FollowedStart {
  const char* world;
  int session;
  double x, y, phi;  // its first true pose
};
class SessionStarts : public ::testing::TestWithParam<FollowedStart> {};

TEST_P(SessionStarts, PlacesThatFitTheFirstMetresAlikeAreToldApartAlongTheLog) {
  const FollowedStart c = GetParam();
  const std::string w = c.world, d = test::tempDir(std::string("sessions_follow_") + c.world);
  ASSERT_EQ(test::run(kExe + " simulate --scenario " + std::string(DYNAMAP_SOURCE_DIR) +
                      "/config/sessions/" + w + ".ini --out " + d + "/sim"),
            0);
  for (int k = 1; k < c.session; ++k) {  // the sessions before, on ground truth
    std::string cmd = kExe + " map --input " + d + "/sim/" + w +
                      (k > 1 ? ".s" + std::to_string(k) : std::string()) + ".rawlog --poses ground_truth --no-baseline --out " + d + "/m" +
                      std::to_string(k);
    if (k > 1) cmd += " --prior " + d + "/m" + std::to_string(k - 1);
    ASSERT_EQ(test::run(cmd), 0) << cmd;
  }
  std::string out;
  ASSERT_EQ(test::run(kExe + " map --input " + d + "/sim/" + w + ".s" + std::to_string(c.session) +
                          ".rawlog --poses odometry --no-baseline --prior " + d + "/m" +
                          std::to_string(c.session - 1) + " --out " + d + "/next",
                      &out),
            0)
      << out;
  expectStart(out, c.x, c.y, c.phi);
}

INSTANTIATE_TEST_SUITE_P(Bundled, SessionStarts,
                         ::testing::Values(FollowedStart{"offices", 3, -5.5, 0.3, M_PI / 2},
                                           FollowedStart{"atrium", 2, 7.5, 4.0, M_PI}));

// The bundled multi-session worlds: three sessions each, each later one started elsewhere with
// ten or eleven changes made before it (objects the table holds and objects of S moved, new and gone
// objects, walls added and removed, an added wall removed again). Mapped in order on
// ground-truth poses and scored by eval --sessions: every change found under the right id,
// nothing false.
class SessionWorlds : public ::testing::TestWithParam<const char*> {};

TEST_P(SessionWorlds, EverySessionReportsEveryChangeAndNoOther) {
  const std::string w = GetParam();
  const std::string d = test::tempDir("sessions_" + w);
  ASSERT_EQ(test::run(kExe + " simulate --scenario " + std::string(DYNAMAP_SOURCE_DIR) +
                      "/config/sessions/" + w + ".ini --out " + d + "/sim"),
            0);
  const std::string logs[] = {w, w + ".s2", w + ".s3"};
  for (int k = 0; k < 3; ++k) {
    std::string cmd = kExe + " map --input " + d + "/sim/" + logs[k] +
                      ".rawlog --poses ground_truth --no-baseline --out " + d + "/m" +
                      std::to_string(k + 1);
    if (k > 0) cmd += " --prior " + d + "/m" + std::to_string(k);
    std::string out;
    ASSERT_EQ(test::run(cmd, &out), 0) << out;
  }
  std::string out;
  ASSERT_EQ(test::run(kExe + " eval --truth " + d + "/sim/" + w + " --sessions " + d + "/m1 " + d +
                          "/m2 " + d + "/m3",
                      &out),
            0);
  for (const char* session : {"session 2", "session 3"}) {  // as many found as there are
    const std::regex all(std::string(session) +
                         ": (1[0-9]) changes, \\1 found, 0 under a wrong id, 0 misplaced, 0 "
                         "missed; 0 false changes");
    EXPECT_TRUE(std::regex_search(out, all)) << out;
  }
  EXPECT_TRUE(std::filesystem::exists(d + "/m3/changes_score.json"));
}

INSTANTIATE_TEST_SUITE_P(Bundled, SessionWorlds,
                         ::testing::Values("offices", "warehouse", "atrium", "clinic"));

}  // namespace
}  // namespace dynamap
