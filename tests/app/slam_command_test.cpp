// `dynamap map --poses slam` end to end on simulated worlds: a loop with drifting odometry, a
// four-fold symmetric ring of corridors (every corner looks like every other), byte-identical
// reruns, bad input; and `dynamap perturb`.

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/serialization/CArchive.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

#include "../test_util.h"
#include "dynamap/evaluation/evaluation.h"
#include "dynamap/input/pose_file.h"

namespace dynamap {
namespace {

namespace fs = std::filesystem;
const std::string kExe = DYNAMAP_EXE;

// A ring corridor round a block, driven twice, odometry with 5 %/m and 0.05 rad/rad noise.
// `block` and `outer`: half sizes; stubs on the walls break the symmetry unless `symmetric`.
std::string scenario(const std::string& name, double outer_x, double outer_y, double block_x,
                     double block_y, bool symmetric, double duration_s) {
  auto rect = [](int first, double hx, double hy) {
    std::string s;
    const double c[5][2] = {{-hx, -hy}, {hx, -hy}, {hx, hy}, {-hx, hy}, {-hx, -hy}};
    for (int i = 0; i < 4; ++i) {
      s += "wall." + std::to_string(first + i) + " = " + std::to_string(c[i][0]) + " " +
           std::to_string(c[i][1]) + " " + std::to_string(c[i + 1][0]) + " " +
           std::to_string(c[i + 1][1]) + "\n";
    }
    return s;
  };
  const double wx = (outer_x + block_x) / 2, wy = (outer_y + block_y) / 2;  // the route
  std::string s = "[scenario]\nname = " + name + "\nduration_s = " + std::to_string(duration_s) +
                  "\nseed = 3\n\n[world]\n" + rect(1, outer_x, outer_y) + rect(5, block_x, block_y);
  if (!symmetric) s += "wall.9 = -1 -4 -1 -3.5\nwall.10 = 2 4 2 3.4\nwall.11 = -6 0 -5.4 0\n";
  s += "\n[robot]\nwaypoints = " + std::to_string(-wx) + " " + std::to_string(-wy) + "  " +
       std::to_string(wx) + " " + std::to_string(-wy) + "  " + std::to_string(wx) + " " +
       std::to_string(wy) + "  " + std::to_string(-wx) + " " + std::to_string(wy) +
       "\nloop = true\nspeed_mps = 0.5\nturn_rate_dps = 45\nscan_rate_hz = 5\n\n"
       "[laser]\nbeams = 181\nfov_deg = 180\nmax_range_m = 8\nrange_noise_std_m = 0.01\n"
       "mount = 0 0 0\n\n[odometry]\nnoise_xy_per_m = 0.05\nnoise_yaw_per_rad = 0.05\n";
  return s;
}

/// Simulates `text` into `dir`; the truth is moved to dir/gt.txt, so the rawlog has odometry only.
std::string simulate(const std::string& dir, const std::string& name, const std::string& text) {
  std::ofstream(dir + "/" + name + ".ini") << text;
  std::string out;
  EXPECT_EQ(
      test::run(kExe + " simulate --scenario " + dir + "/" + name + ".ini --out " + dir, &out), 0)
      << out;
  fs::rename(dir + "/" + name + ".gt.txt", dir + "/gt.txt");
  return dir + "/" + name + ".rawlog";
}

double alignedError(const std::string& poses, const std::string& truth) {
  return alignedTrajectoryError(readPoseFile(poses), readPoseFile(truth)).aligned_rmse_xy_m;
}

class SlamLoop : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new std::string(test::tempDir("slam"));
    log_ = new std::string(simulate(*dir_, "loop", scenario("loop", 6, 4, 4, 2, false, 130)));
    for (const char* run : {"a", "b"}) {
      EXPECT_EQ(test::run(kExe + " map --no-baseline --poses slam --input " + *log_ + " --out " +
                          *dir_ + "/" + run),
                0);
    }
    EXPECT_EQ(test::run(kExe + " map --no-baseline --poses odometry --input " + *log_ + " --out " +
                        *dir_ + "/odo"),
              0);
    // Every loop search matching the recent scans' cloud, however narrow its window.
    std::ofstream(*dir_ + "/cloud.ini") << "[slam]\nloop_cloud_window_m = 0.01\n";
    EXPECT_EQ(test::run(kExe + " map --no-baseline --poses slam --config " + *dir_ +
                        "/cloud.ini --input " + *log_ + " --out " + *dir_ + "/cloud"),
              0);
    std::ofstream(*dir_ + "/line.ini") << "[scan_matching]\npoint_to_line = true\n";
    EXPECT_EQ(test::run(kExe + " map --no-baseline --poses slam --config " + *dir_ +
                        "/line.ini --input " + *log_ + " --out " + *dir_ + "/line"),
              0);
  }
  static std::string *dir_, *log_;
};
std::string* SlamLoop::dir_ = nullptr;
std::string* SlamLoop::log_ = nullptr;

TEST_F(SlamLoop, LoopClosureRemovesTheOdometryDrift) {
  const double odo = alignedError(*dir_ + "/odo/poses.txt", *dir_ + "/gt.txt");
  const double slam = alignedError(*dir_ + "/a/poses.txt", *dir_ + "/gt.txt");
  EXPECT_GT(odo, 0.1);
  EXPECT_LT(slam, 0.05);
  EXPECT_LT(slam, odo / 3);
  const std::string summary = test::readFile(*dir_ + "/a/summary.json");
  EXPECT_NE(summary.find("\"pose_source\": \"slam\""), std::string::npos);
  EXPECT_NE(summary.find("\"converged\": true"), std::string::npos);
  EXPECT_GT(nlohmann::json::parse(summary)["slam"]["loop_closures"]["proposed"].get<int>(), 0);
  EXPECT_NE(test::readFile(*dir_ + "/a/config.ini").find("[slam]"), std::string::npos);
  // Drifting odometry lays the scans apart: the optimised poses are kept.
  const auto check = nlohmann::json::parse(summary)["slam"]["odometry_check"];
  EXPECT_EQ(check["kept"], "slam") << check;
  EXPECT_LT(check["slam_global_mm"].get<double>(), check["odometry_global_mm"].get<double>() / 2);
  EXPECT_EQ(check["scans_scored"], 651);
}

// The same loop with odometry as good as the truth (a log whose poses were corrected already,
// given as odometry): slam's poses are no better, and pass 2 maps on the odometry.
TEST(SlamOdometryCheck, OdometryThatLaysTheScansBetterIsKept) {
  const std::string dir = test::tempDir("slam-perfect");
  std::string text = scenario("loop", 6, 4, 4, 2, false, 130);
  const std::string noisy = "noise_xy_per_m = 0.05\nnoise_yaw_per_rad = 0.05\n";
  ASSERT_NE(text.find(noisy), std::string::npos);
  text.replace(text.find(noisy), noisy.size(), "noise_xy_per_m = 0\nnoise_yaw_per_rad = 0\n");
  const std::string log = simulate(dir, "loop", text);
  const std::string map = kExe + " map --no-baseline --input " + log;
  ASSERT_EQ(test::run(map + " --poses slam --out " + dir + "/slam"), 0);
  ASSERT_EQ(test::run(map + " --poses odometry --out " + dir + "/odo"), 0);
  std::ofstream(dir + "/off.ini") << "[slam]\nkeep_better_odometry = false\n";
  ASSERT_EQ(test::run(map + " --poses slam --config " + dir + "/off.ini --out " + dir + "/off"), 0);
  const std::string odometry = test::readFile(dir + "/odo/poses.txt");
  EXPECT_EQ(test::readFile(dir + "/slam/poses.txt"), odometry);
  const auto slam = nlohmann::json::parse(test::readFile(dir + "/slam/summary.json"))["slam"];
  EXPECT_EQ(slam["odometry_check"]["kept"], "odometry") << slam;
  EXPECT_LT(slam["odometry_check"]["odometry_global_mm"].get<double>(),
            slam["odometry_check"]["slam_global_mm"].get<double>());
  EXPECT_EQ(slam["poses"], "odometry (it lays the scans onto each other better)");
  // Asked not to, slam keeps its own poses, which differ from the truth a little.
  EXPECT_NE(test::readFile(dir + "/off/poses.txt"), odometry);
  const auto off = nlohmann::json::parse(test::readFile(dir + "/off/summary.json"))["slam"];
  EXPECT_EQ(off["poses"], "optimised");
  EXPECT_TRUE(off["odometry_check"].is_string()) << off;
  EXPECT_LT(alignedError(dir + "/off/poses.txt", dir + "/gt.txt"), 0.05);
}

// Loop closures found with the last metres of scans (laid out by the front end, in the current
// scan's frame) close the loop as well as those of the scan alone: a cloud in a wrong frame
// would find no place or a wrong one.
TEST_F(SlamLoop, LoopSearchesMatchingTheRecentScansCloseTheLoopToo) {
  const double slam = alignedError(*dir_ + "/cloud/poses.txt", *dir_ + "/gt.txt");
  EXPECT_LT(slam, 0.05);
  EXPECT_LT(slam, alignedError(*dir_ + "/odo/poses.txt", *dir_ + "/gt.txt") / 3);
  const auto loops =
      nlohmann::json::parse(test::readFile(*dir_ + "/cloud/summary.json"))["slam"]["loop_closures"];
  EXPECT_GT(loops["accepted"].get<int>(), 10) << loops;
  EXPECT_NE(test::readFile(*dir_ + "/cloud/config.ini").find("loop_cloud_window_m = 0.01"),
            std::string::npos);
}

// The front end with point-to-line ICP on the submap's cells instead of MRPT's ICP.
TEST_F(SlamLoop, APointToLineFrontEndRemovesTheDriftToo) {
  const double odo = alignedError(*dir_ + "/odo/poses.txt", *dir_ + "/gt.txt");
  const double line = alignedError(*dir_ + "/line/poses.txt", *dir_ + "/gt.txt");
  EXPECT_LT(line, 0.05);
  EXPECT_LT(line, odo / 3);
  EXPECT_NE(test::readFile(*dir_ + "/line/poses.txt"), test::readFile(*dir_ + "/a/poses.txt"));
  EXPECT_NE(test::readFile(*dir_ + "/line/config.ini").find("point_to_line = true"),
            std::string::npos);
}

TEST_F(SlamLoop, SameInputGivesTheSamePosesAndGraphByteForByte) {
  EXPECT_EQ(test::readFile(*dir_ + "/a/poses.txt"), test::readFile(*dir_ + "/b/poses.txt"));
  const std::string g2o = test::readFile(*dir_ + "/a/graph.g2o");
  EXPECT_EQ(g2o, test::readFile(*dir_ + "/b/graph.g2o"));
  EXPECT_NE(g2o.find("VERTEX_SE2 650 "), std::string::npos);  // one node per scan (651)
  EXPECT_NE(g2o.find("EDGE_SE2 0 1 "), std::string::npos);
}

// Four identical corridors and four identical corners: a loop closure matched at the wrong
// corner, or shifted along a corridor, would fold the map.
TEST(SlamSymmetric, ASymmetricRingKeepsItsAccuracy) {
  const std::string dir = test::tempDir("slam-sym");
  const std::string log = simulate(dir, "ring", scenario("ring", 6, 6, 4, 4, true, 200));
  ASSERT_EQ(
      test::run(kExe + " map --no-baseline --poses slam --input " + log + " --out " + dir + "/s"),
      0);
  ASSERT_EQ(test::run(kExe + " map --no-baseline --poses odometry --input " + log + " --out " +
                      dir + "/o"),
            0);
  const double slam = alignedError(dir + "/s/poses.txt", dir + "/gt.txt");
  EXPECT_LT(slam, 0.06);
  EXPECT_LT(slam, alignedError(dir + "/o/poses.txt", dir + "/gt.txt"));
}

/// `steps` scans 5 cm apart along a 10 m x 4 m room; odometry for the first `with_odometry` only.
void writeRoomLog(const std::string& path, std::size_t steps, std::size_t with_odometry) {
  mrpt::io::CFileGZOutputStream out(path);
  auto ar = mrpt::serialization::archiveFrom(out);
  for (std::size_t i = 0; i < steps; ++i) {
    const double t = 1000.0 + 0.2 * double(i);
    const mrpt::poses::CPose2D pose(-3 + 0.05 * double(i), 0, 0);
    if (i < with_odometry) {
      mrpt::obs::CObservationOdometry odo;
      odo.odometry = pose;
      odo.timestamp = mrpt::Clock::fromDouble(t);
      odo.sensorLabel = "ODOMETRY";
      ar << odo;
    }
    auto scan = test::makeScan(test::roomRanges(-5, 5, -2, 2, pose, 181, M_PI), M_PI, t);
    scan->timestamp = mrpt::Clock::fromDouble(t);
    ar << *scan;
  }
}

TEST(SlamInput, AutoPicksSlamForALogWithOdometryOnly) {
  const std::string dir = test::tempDir("slam-auto");
  writeRoomLog(dir + "/room.rawlog", 40, 40);
  ASSERT_EQ(
      test::run(kExe + " map --no-baseline --input " + dir + "/room.rawlog --out " + dir + "/o"),
      0);
  EXPECT_NE(test::readFile(dir + "/o/summary.json").find("\"pose_source\": \"slam\""),
            std::string::npos);
  EXPECT_TRUE(fs::exists(dir + "/o/graph.g2o"));
}

TEST(SlamInput, ALogWithoutOdometryIsAnErrorNamingIt) {
  const std::string dir = test::tempDir("slam-noodo");
  writeRoomLog(dir + "/scans.rawlog", 20, 0);
  std::string out;
  EXPECT_EQ(
      test::run(kExe + " map --poses slam --input " + dir + "/scans.rawlog --out " + dir + "/o",
                &out),
      1);
  EXPECT_NE(out.find(dir + "/scans.rawlog: pose source slam needs odometry"), std::string::npos)
      << out;
}

TEST(SlamInput, OdometryThatStopsMidwayKeepsTheScansBeforeIt) {
  const std::string dir = test::tempDir("slam-stop");
  writeRoomLog(dir + "/half.rawlog", 80, 40);
  std::string out;
  const int status = test::run(
      kExe + " map --no-baseline --poses slam --input " + dir + "/half.rawlog --out " + dir + "/o",
      &out);
  EXPECT_TRUE(status == 0 || status == 4) << out;
  const auto poses = readPoseFile(dir + "/o/poses.txt");
  ASSERT_GE(poses.size(), 40u) << out;
  for (std::size_t i = 0; i < 40; ++i) {
    EXPECT_NEAR(poses[i].x, -3 + 0.05 * double(i), 0.05) << i;
    EXPECT_NEAR(poses[i].y, 0.0, 0.05) << i;
  }
}

// A second session of the loop against the first's map (mapped on the truth): its trajectory
// is tied to the prior's frame by scans matched there, so it lies on the truth without any
// alignment; the same slam only moved to its start drifts away from it between loop closures.
TEST(SlamTiedToPrior, ASessionsPosesLieInThePriorMapsFrame) {
  const std::string dir = test::tempDir("slam-tie");
  std::ofstream(dir + "/loop.ini") << scenario("loop", 6, 4, 4, 2, false, 130);
  ASSERT_EQ(test::run(kExe + " simulate --scenario " + dir + "/loop.ini --out " + dir), 0);
  const std::string log = dir + "/loop.rawlog", map = kExe + " map --no-baseline --input " + log;
  ASSERT_EQ(test::run(map + " --poses ground_truth --out " + dir + "/prior"), 0);
  fs::rename(dir + "/loop.gt.txt", dir + "/gt.txt");
  const std::vector<TimedPose> truth = readPoseFile(dir + "/gt.txt");
  ASSERT_FALSE(truth.empty());
  const std::string start = " --initial-pose \"" + std::to_string(truth[0].x) + " " +
                            std::to_string(truth[0].y) + " " + std::to_string(truth[0].phi) + "\"";
  std::string out;
  ASSERT_EQ(
      test::run(map + " --poses slam --prior " + dir + "/prior" + start + " --out " + dir + "/tied",
                &out),
      0)
      << out;
  ASSERT_EQ(test::run(map + " --poses slam --out " + dir + "/alone"), 0);  // anchored below
  const auto ties =
      nlohmann::json::parse(test::readFile(dir + "/tied/summary.json"))["slam"]["prior_map_ties"];
  EXPECT_GT(ties["accepted"].get<int>(), 20) << ties;
  const TrajectoryError tied = trajectoryError(readPoseFile(dir + "/tied/poses.txt"), truth);
  const TrajectoryError alone = trajectoryError(readPoseFile(dir + "/alone/poses.txt"), truth);
  EXPECT_EQ(tied.matched, truth.size());
  EXPECT_LT(tied.rmse_xy_m, 0.03);
  EXPECT_LT(tied.max_xy_m, 0.08);
  EXPECT_LT(tied.rmse_xy_m, 0.6 * alone.rmse_xy_m) << alone.rmse_xy_m;
}

TEST(Perturb, SameSeedSameBytesAndTheTruthBeside) {
  const std::string dir = test::tempDir("perturb");
  writeRoomLog(dir + "/room.rawlog", 60, 60);
  // The room log's odometry is exact: as ground truth, from a companion file.
  std::ofstream gt(dir + "/room.gt.txt");
  for (std::size_t i = 0; i < 60; ++i)
    gt << std::fixed << 1000.0 + 0.2 * double(i) << " " << -3 + 0.05 * double(i) << " 0 0\n";
  gt.close();
  for (const char* d : {"p1", "p2"}) {
    ASSERT_EQ(test::run(kExe + " perturb --input " + dir + "/room.rawlog --out " + dir + "/" + d +
                        " --seed 7"),
              0);
  }
  ASSERT_EQ(
      test::run(kExe + " perturb --input " + dir + "/room.rawlog --out " + dir + "/p3 --seed 8"),
      0);
  const std::string a = test::readFile(dir + "/p1/odometry.rawlog");
  EXPECT_EQ(a, test::readFile(dir + "/p2/odometry.rawlog"));
  EXPECT_NE(a, test::readFile(dir + "/p3/odometry.rawlog"));
  EXPECT_EQ(readPoseFile(dir + "/p1/gt.txt").size(), 60u);
  // odometry.txt: the drifting odometry of each scan, starting on the truth, then off it.
  EXPECT_EQ(test::readFile(dir + "/p1/odometry.txt"), test::readFile(dir + "/p2/odometry.txt"));
  const auto odo = readPoseFile(dir + "/p1/odometry.txt"), truth = readPoseFile(dir + "/p1/gt.txt");
  ASSERT_EQ(odo.size(), 60u);
  EXPECT_EQ(odo.front().t, truth.front().t);
  EXPECT_DOUBLE_EQ(odo.front().x, truth.front().x);
  EXPECT_EQ(odo.back().t, truth.back().t);
  EXPECT_GT(std::hypot(odo.back().x - truth.back().x, odo.back().y - truth.back().y), 1e-4);
  std::string out;
  EXPECT_EQ(test::run(kExe + " perturb --input " + dir + "/room.rawlog --out " + dir +
                          "/p4 --trans-noise 2",
                      &out),
            2)
      << out;
}

}  // namespace
}  // namespace dynamap
