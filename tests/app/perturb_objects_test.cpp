// dynamap perturb --add-objects: the edited scans agree with the truth written beside them, the
// same spec gives the same bytes, option and spec errors; on a real log (DYNAMAP_DATASETS), an
// added cylinder is found by `dynamap map` and scored by `dynamap eval`.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "dynamap/input/open_source.h"
#include "dynamap/outputs/json.h"
#include "../test_util.h"

namespace dynamap {
namespace {

const std::string kExe = DYNAMAP_EXE;

/// A robot driving round a 1.5 m square in a 12 x 12 m room (ground truth in the log), 5 Hz.
void writeRoom(const std::string& path, int scans) {
  std::vector<test::LogStep> steps;
  const double corners[4][2] = {{-1.5, -1.5}, {1.5, -1.5}, {1.5, 1.5}, {-1.5, 1.5}};
  for (int k = 0; k < scans; ++k) {
    const double s = std::fmod(k * 0.08, 12.0);  // 0.4 m/s along a 12 m loop
    const int leg = static_cast<int>(s / 3.0);
    const double f = (s - leg * 3.0) / 3.0;
    const auto& a = corners[leg];
    const auto& b = corners[(leg + 1) % 4];
    const mrpt::poses::CPose2D pose(a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1]),
                                    std::atan2(b[1] - a[1], b[0] - a[0]));
    steps.push_back({1000.0 + 0.2 * k, pose,
                     test::makeScan(test::roomRanges(-6, 6, -6, 6, pose, 181, M_PI), M_PI,
                                    1000.0 + 0.2 * k)});
  }
  test::writeObsRawlog(path, steps);
}

std::vector<ScanRecord> readLog(const std::string& path) {
  auto source = openScanSource(path, PoseSource::GroundTruth);
  std::vector<ScanRecord> out;
  for (ScanRecord r; source->next(r);) out.push_back(r);
  return out;
}

/// objects.csv: the hits of every object per scan, summed.
std::map<std::size_t, int> hitsPerScan(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "scan_index,t,kind,id,x,y,diameter,hits");
  std::map<std::size_t, int> hits;
  while (std::getline(in, line)) {
    std::stringstream s(line);
    std::string f[8];
    for (auto& x : f) std::getline(s, x, ',');
    hits[std::stoul(f[0])] += std::stoi(f[7]);
  }
  return hits;
}

TEST(PerturbObjects, TheTruthAgreesWithTheScansItEdited) {
  const std::string dir = test::tempDir("addobj");
  writeRoom(dir + "/room.rawlog", 1500);
  const std::string cmd = kExe + " perturb --input " + dir + "/room.rawlog --add-objects " +
                          "objects=2,moves=4,seed=3,path=0.4 --name room --out ";
  std::string out;
  ASSERT_EQ(test::run(cmd + dir + "/a", &out), 0) << out;
  ASSERT_EQ(test::run(cmd + dir + "/b"), 0);
  for (const char* f : {"room.rawlog", "room.objects.csv", "room.moves.csv", "room.gt.txt"}) {
    EXPECT_EQ(test::readFile(dir + "/a/" + f), test::readFile(dir + "/b/" + f)) << f;
  }
  const auto before = readLog(dir + "/room.rawlog");
  const auto after = readLog(dir + "/a/room.rawlog");
  ASSERT_EQ(before.size(), after.size());
  const auto hits = hitsPerScan(dir + "/a/room.objects.csv");
  int total = 0;
  for (std::size_t s = 0; s < before.size(); ++s) {
    EXPECT_NEAR(before[s].pose.x(), after[s].pose.x(), 1e-9);
    int changed = 0;
    for (std::size_t i = 0; i < before[s].scan->getScanSize(); ++i) {
      const float b = before[s].scan->getScanRange(i), a = after[s].scan->getScanRange(i);
      if (a == b) continue;
      ++changed;
      EXPECT_LT(a, b) << "scan " << s << " beam " << i;  // only ever shortened
    }
    // Every beam shortened lies within the counted range here: one hit each.
    EXPECT_EQ(changed, hits.count(s) ? hits.at(s) : 0) << "scan " << s;
    total += changed;
  }
  EXPECT_GT(total, 1000);
  const std::string moves = test::readFile(dir + "/a/room.moves.csv");
  EXPECT_EQ(moves.rfind("move_id,object_id,t_start,t_end,from_x,from_y,to_x,to_y\n", 0), 0u);
  EXPECT_NE(test::readFile(dir + "/a/room.added.txt").find("moves planned: 4"), std::string::npos);
}

TEST(PerturbObjects, OptionAndSpecErrors) {
  const std::string dir = test::tempDir("addobj_err");
  writeRoom(dir + "/room.rawlog", 50);
  const std::string base = kExe + " perturb --input " + dir + "/room.rawlog --out " + dir + "/o ";
  std::string out;
  EXPECT_EQ(test::run(base + "--add-objects objects=0", &out), 2);
  EXPECT_NE(out.find("--add-objects: objects"), std::string::npos) << out;
  EXPECT_EQ(test::run(base + "--add-objects colour=red", &out), 2);
  EXPECT_NE(out.find("unknown key 'colour'"), std::string::npos) << out;
  EXPECT_EQ(test::run(base + "--add-objects moves=3 --trans-noise 0.1", &out), 2);
  EXPECT_NE(out.find("--trans-noise does not go with --add-objects"), std::string::npos) << out;
  EXPECT_EQ(test::run(base + "--add-objects moves=3 --seed 4", &out), 2);
  EXPECT_EQ(test::run(base + "--name x", &out), 2);
  EXPECT_NE(out.find("--name goes with --add-objects"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir + "/o/room.rawlog"));
}

/// The real logs, when DYNAMAP_DATASETS names where they are.
std::string dataset(const std::string& name) {
  const char* root = std::getenv("DYNAMAP_DATASETS");
  if (root == nullptr || *root == '\0') return "";
  const std::string path = std::string(root) + "/carmen/" + name;
  return std::filesystem::exists(path) ? path : "";
}

TEST(PerturbObjects, AnAddedCylinderIsFoundOnARealLog) {
  const std::string log = dataset("freiburg-campus-corrected.log.gz");
  if (log.empty()) GTEST_SKIP() << "DYNAMAP_DATASETS unset or without carmen/freiburg-campus";
  const std::string dir = test::tempDir("addobj_real");
  std::string out;
  ASSERT_EQ(test::run(kExe + " perturb --input " + log + " --out " + dir +
                          "/truth --name campus --add-objects objects=4,moves=10,seed=2",
                      &out),
            0)
      << out;
  ASSERT_EQ(test::run(kExe + " map --input " + dir + "/truth/campus.rawlog --out " + dir + "/r",
                      &out),
            0)
      << out;
  ASSERT_EQ(test::run(kExe + " eval --truth " + dir + "/truth/campus --result " + dir + "/r", &out),
            0)
      << out;
  const Json m = parseJson(test::readFile(dir + "/r/metrics.json"), "metrics.json");
  EXPECT_EQ(m.at("moves_visible").get<int>(), 10) << out;
  EXPECT_GE(m.at("correctly_detected").get<int>(), 9) << out;
  EXPECT_EQ(m.at("size_estimation_errors").get<int>(), 0) << out;
}

}  // namespace
}  // namespace dynamap
