// `dynamap map` end to end on the bundled tiny rawlog: every output, readable by MRPT, the
// documented exit statuses, and byte-identical outputs for identical runs.

#include <mrpt/img/CImage.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/serialization/CArchive.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

#include "../test_util.h"

namespace dynamap {
namespace {

namespace fs = std::filesystem;
const std::string kExe = DYNAMAP_EXE;
const std::string kSrc = DYNAMAP_SOURCE_DIR;
const std::string kTiny = kSrc + "/rawlogs/tiny/tiny.rawlog";

int map(const std::string& args, std::string* out = nullptr) {
  return test::run(kExe + " map " + args, out);
}

mrpt::maps::COccupancyGridMap2D loadGrid(const std::string& path) {
  mrpt::maps::COccupancyGridMap2D grid;
  mrpt::io::CFileGZInputStream in(path);
  mrpt::serialization::archiveFrom(in) >> grid;
  return grid;
}

// summary.json without its "timing" block, the one part that differs between runs.
std::string summaryWithoutTiming(const std::string& path) {
  const std::string s = test::readFile(path);
  return s.substr(0, s.find("\"timing\""));
}

class MapCommand : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    out_ = new std::string(test::tempDir("map"));
    std::string log;
    status_ =
        map("--config " + kSrc + "/config/default.ini --input " + kTiny + " --out " + *out_, &log);
    log_ = new std::string(log);
  }
  static std::string* out_;
  static std::string* log_;
  static int status_;
};
std::string* MapCommand::out_ = nullptr;
std::string* MapCommand::log_ = nullptr;
int MapCommand::status_ = -1;

TEST_F(MapCommand, WritesEveryOutput) {
  ASSERT_EQ(status_, 0) << *log_;
  for (const char* f :
       {"static.png", "dynamic.png", "overlay.png", "static.gridmap.gz", "dynamic.gridmap.gz",
        "static.pgm", "static.yaml", "config.ini", "summary.json", "objects.csv", "events.csv",
        "tracks.csv", "mrpt_plain.png", "poses.txt"}) {
    EXPECT_TRUE(fs::exists(*out_ + "/" + f)) << f;
  }
  for (const auto& e : fs::directory_iterator(*out_)) {
    EXPECT_NE(e.path().filename().string().rfind(".tmp-", 0), 0u) << "left behind: " << e.path();
  }
}

TEST_F(MapCommand, GridmapLoadsBackInMrptAndPicturesHaveTheGridsSize) {
  ASSERT_EQ(status_, 0) << *log_;
  const auto s = loadGrid(*out_ + "/static.gridmap.gz");
  const auto d = loadGrid(*out_ + "/dynamic.gridmap.gz");
  EXPECT_GT(s.getSizeX(), 50u);
  EXPECT_EQ(d.getSizeX(), s.getSizeX());
  EXPECT_EQ(d.getSizeY(), s.getSizeY());
  EXPECT_NEAR(s.getResolution(), 0.05, 1e-6);
  const std::string summary = test::readFile(*out_ + "/summary.json");
  const auto json = nlohmann::json::parse(summary);
  EXPECT_EQ(json["map"]["size_cells"], nlohmann::json::array({s.getSizeX(), s.getSizeY()}));
  EXPECT_NE(summary.find("\"read\": 301"), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"pose_source\": \"ground_truth\""), std::string::npos);
  for (const char* png : {"static.png", "dynamic.png"}) {
    mrpt::img::CImage img;
    ASSERT_TRUE(img.loadFromFile(*out_ + "/" + png)) << png;
    EXPECT_EQ(img.getWidth(), s.getSizeX()) << png;
    EXPECT_EQ(img.getHeight(), s.getSizeY()) << png;
  }
  // The ROS map: P5 header with the grid's size.
  const std::string pgm = test::readFile(*out_ + "/static.pgm");
  EXPECT_EQ(pgm.rfind("P5\n", 0), 0u);
  EXPECT_NE(pgm.find(std::to_string(s.getSizeX()) + " " + std::to_string(s.getSizeY()) + "\n255\n"),
            std::string::npos);
}

TEST_F(MapCommand, TheEffectiveConfigurationRunsAgainToTheSameBytes) {
  ASSERT_EQ(status_, 0) << *log_;
  const std::string again = test::tempDir("map-again");
  ASSERT_EQ(map("--config " + *out_ + "/config.ini --input " + kTiny + " --out " + again), 0);
  for (const auto& e : fs::directory_iterator(*out_)) {
    const std::string name = e.path().filename().string();
    if (!e.is_regular_file()) continue;
    if (name == "summary.json") {
      EXPECT_EQ(summaryWithoutTiming(again + "/" + name), summaryWithoutTiming(e.path().string()));
    } else {
      EXPECT_EQ(test::readFile(again + "/" + name), test::readFile(e.path().string())) << name;
    }
  }
}

TEST_F(MapCommand, SummaryComparesSWithAPlainMrptGridUnlessToldNotTo) {
  ASSERT_EQ(status_, 0) << *log_;
  const std::string summary = test::readFile(*out_ + "/summary.json");
  EXPECT_NE(summary.find("\"plain_occupied_static_free\": "), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"mrpt_baseline_scans_per_s\": "), std::string::npos) << summary;
  const std::string bare = test::tempDir("map-bare");
  ASSERT_EQ(map("--no-baseline --input " + kTiny + " --out " + bare), 0);
  EXPECT_FALSE(fs::exists(bare + "/mrpt_plain.png"));
  EXPECT_EQ(test::readFile(bare + "/summary.json").find("mrpt_baseline"), std::string::npos);
}

// poses.txt: a `timestamp x y phi` line per scan, the poses used; with ground truth, the truth.
TEST_F(MapCommand, PosesTxtHoldsThePoseOfEveryScan) {
  ASSERT_EQ(status_, 0) << *log_;
  std::ifstream poses(*out_ + "/poses.txt"), truth(kSrc + "/rawlogs/tiny/tiny.gt.txt");
  std::string line;
  std::getline(poses, line);
  EXPECT_EQ(line[0], '%');  // the header
  std::size_t n = 0;
  double t, x, y, phi, gt, gx, gy, gphi;
  while (poses >> t >> x >> y >> phi) {
    ASSERT_TRUE(truth >> gt >> gx >> gy >> gphi);
    EXPECT_NEAR(t, gt, 1e-6);
    EXPECT_NEAR(x, gx, 1e-5);
    EXPECT_NEAR(y, gy, 1e-5);
    ++n;
  }
  EXPECT_EQ(n, 301u);
}

// dynamap copied away from build/ without libdynamap_icp.so: runs that match no scan work, and
// one that does stops before its first scan with an error naming the module.
TEST(MapCommandIcpModule, WithoutTheModuleOnlyScanMatchingFailsAndSaysWhy) {
  const std::string dir = test::tempDir("map-no-icp");
  const std::string exe = dir + "/dynamap";
  fs::copy_file(kExe, exe);
  fs::permissions(exe, fs::perms::owner_all);
  const std::string ok = dir + "/gt", sm = dir + "/sm";
  std::string log;
  EXPECT_EQ(test::run(exe + " map --no-baseline --input " + kTiny + " --out " + ok, &log), 0)
      << log;
  EXPECT_NE(
      test::run(exe + " map --poses scan_matching --no-baseline --input " + kTiny + " --out " + sm,
                &log),
      0);
  EXPECT_NE(log.find("scan matching needs libdynamap_icp.so"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(sm + "/summary.json"));
}

// --poses scan_matching: the odometry corrected against S, counted in summary.json, the same
// bytes when run again; in the tiny room its heading is better than the odometry's and its
// position within a cell of the truth (the odometry drifts only 3 cm in this minute).
TEST(MapCommandScanMatching, CorrectsTheOdometryAndIsReproducible) {
  const std::string a = test::tempDir("map-sm"), b = test::tempDir("map-sm2"),
                    odo = test::tempDir("map-odo");
  ASSERT_EQ(map("--poses scan_matching --no-baseline --input " + kTiny + " --out " + a), 0);
  ASSERT_EQ(map("--poses scan_matching --no-baseline --input " + kTiny + " --out " + b), 0);
  ASSERT_EQ(map("--poses odometry --no-baseline --input " + kTiny + " --out " + odo), 0);
  const std::string summary = test::readFile(a + "/summary.json");
  EXPECT_NE(summary.find("\"pose_source\": \"scan_matching\""), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"scan_matching\": {"), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"too few map points\": 1"), std::string::npos) << summary;
  for (const char* f : {"poses.txt", "static.gridmap.gz", "tracks.csv", "config.ini"}) {
    EXPECT_EQ(test::readFile(a + "/" + f), test::readFile(b + "/" + f)) << f;
  }
  EXPECT_EQ(summaryWithoutTiming(a + "/summary.json"), summaryWithoutTiming(b + "/summary.json"));
  EXPECT_NE(test::readFile(a + "/config.ini").find("[scan_matching]"), std::string::npos);
  // Scored against the truth by dynamap eval --trajectory.
  auto ate = [&](const std::string& dir, const char* what) {
    std::string out;
    EXPECT_EQ(test::run(kExe + " eval --truth " + kSrc + "/rawlogs/tiny --trajectory " + dir +
                            "/poses.txt",
                        &out),
              0)
        << out;
    const auto at = out.find(what);
    EXPECT_NE(at, std::string::npos) << out;
    return std::stod(out.substr(at + std::string(what).size()));
  };
  EXPECT_LT(ate(a, "heading "), ate(odo, "heading "));
  EXPECT_LT(ate(a, "position "), 0.05);
}

TEST(MapCommandErrors, ExitStatusesAndOneLineMessages) {
  const std::string dir = test::tempDir("maperr");
  std::string out;
  EXPECT_EQ(test::run(kExe + " map --bogus", &out), 2) << out;
  EXPECT_EQ(test::run(kExe + " nonsense", &out), 2) << out;
  EXPECT_EQ(map("--out " + dir, &out), 2) << out;  // --input is required
  std::ofstream(dir + "/bad.ini") << "[dynamic_map]\nobject_treshold = 0.9\n";
  EXPECT_EQ(map("--config " + dir + "/bad.ini --input " + kTiny + " --out " + dir + "/o", &out), 3);
  EXPECT_EQ(out, "dynamap map: " + dir + "/bad.ini: [dynamic_map] object_treshold: unknown key\n");
  EXPECT_EQ(map("--input " + dir + "/missing.rawlog --out " + dir + "/o", &out), 1);
  EXPECT_EQ(out, "dynamap map: " + dir + "/missing.rawlog: no such file\n");
  EXPECT_EQ(map("--input " + kTiny + " --poses gps --out " + dir + "/o", &out), 2);
  std::ofstream(dir + "/file") << "x";
  EXPECT_EQ(map("--input " + kTiny + " --out " + dir + "/file/sub", &out), 1);
  EXPECT_NE(out.find("cannot create output directory"), std::string::npos) << out;
}

TEST(MapCommandFaults, ATruncatedLogMapsEverythingBeforeTheCutAndExitsWithFour) {
  const std::string dir = test::tempDir("mapcut");
  ASSERT_EQ(test::run("gzip -dc " + kTiny + " > " + dir + "/plain.rawlog"), 0);
  const std::string bytes = test::readFile(dir + "/plain.rawlog");
  std::ofstream(dir + "/cut.rawlog", std::ios::binary) << bytes.substr(0, bytes.size() / 2 + 7);
  std::string out;
  EXPECT_EQ(map("--input " + dir + "/cut.rawlog --out " + dir + "/o", &out), 4) << out;
  EXPECT_NE(out.find("warning: input ended in a fault"), std::string::npos) << out;
  EXPECT_NE(out.find("cut.rawlog: record "), std::string::npos) << out;
  EXPECT_NE(out.find(" at byte "), std::string::npos) << out;
  for (const char* f : {"static.png", "overlay.png", "static.gridmap.gz", "summary.json",
                        "tracks.csv", "objects.csv"}) {
    EXPECT_TRUE(fs::exists(dir + "/o/" + f)) << f;
  }
  const std::string summary = test::readFile(dir + "/o/summary.json");
  EXPECT_NE(summary.find("\"complete_input\": false"), std::string::npos);
  // About half of the 301 scans were mapped.
  const auto pos = summary.find("\"used\": ");
  ASSERT_NE(pos, std::string::npos);
  const int used = std::stoi(summary.substr(pos + 8));
  EXPECT_GT(used, 140);
  EXPECT_LT(used, 160);
}

TEST(MapCommandHelp, ExplainsEveryOption) {
  std::string out;
  ASSERT_EQ(test::run(kExe + " map --help", &out), 0);
  for (const char* opt : {"--input", "--config", "--out", "--poses", "--verbose", "--no-baseline",
                          "--skip-bad-lines", "--fov", "--frames-every"}) {
    EXPECT_NE(out.find(opt), std::string::npos) << opt;
  }
  ASSERT_EQ(test::run(kExe + " --help", &out), 0);
  EXPECT_NE(out.find("map"), std::string::npos);
}

}  // namespace
}  // namespace dynamap

namespace dynamap {
namespace {

// The timelapse: one frame per --frames-every scans, people drawn, turned into timelapse.mp4 by
// ffmpeg (installed by make deps; without it the test is skipped, not passed).
TEST(MapTimelapse, FramesBecomeAVideoOfThemAll) {
  if (test::run("command -v ffmpeg >/dev/null 2>&1 && command -v ffprobe >/dev/null 2>&1") != 0) {
    GTEST_SKIP() << "ffmpeg is not installed";
  }
  const std::string out = test::tempDir("timelapse");
  const std::string people = std::string(DYNAMAP_SOURCE_DIR) + "/rawlogs/people/people.rawlog";
  std::string log;
  ASSERT_EQ(test::run(std::string(DYNAMAP_EXE) + " map --config " + DYNAMAP_SOURCE_DIR +
                          "/config/default.ini --poses ground_truth --no-baseline --input " +
                          people + " --frames-every 100 --out " + out,
                      &log),
            0)
      << log;
  std::size_t frames = 0;
  for (const auto& e : std::filesystem::directory_iterator(out + "/frames")) {
    frames += e.path().extension() == ".png";
  }
  EXPECT_EQ(frames, 16u);  // scans 0, 100, ..., 1500
  std::string count;
  ASSERT_EQ(test::run("ffprobe -v error -count_frames -select_streams v:0 -show_entries "
                      "stream=nb_read_frames -of csv=p=0 " +
                          out + "/timelapse.mp4",
                      &count),
            0)
      << count;
  EXPECT_EQ(std::stoi(count), 16);
  // People are on the frames: the map of a frame mid-run holds the trail of the one person in
  // view then (id 3, teal), and the final overlay a colour for each of the three people (magenta,
  // orange, teal for ids 1 to 3). The legend strip below the map (its last 50 rows at most)
  // shows the first three colours too: it is not counted.
  const auto pixels = [](const std::string& png, int r, int g, int b) {
    mrpt::img::CImage img;
    EXPECT_TRUE(img.loadFromFile(png)) << png;
    std::size_t n = 0;
    for (int y = 0; y + 50 < static_cast<int>(img.getHeight()); ++y) {
      for (int x = 0; x < static_cast<int>(img.getWidth()); ++x) {
        const auto* px = img.ptr<std::uint8_t>(x, y);  // BGR
        n += px[0] == b && px[1] == g && px[2] == r;
      }
    }
    return n;
  };
  EXPECT_GT(pixels(out + "/frames/000800.png", 0, 130, 150), 20u);
  EXPECT_EQ(pixels(out + "/frames/000800.png", 200, 0, 200), 0u);  // person 1 is not in view
  EXPECT_GT(pixels(out + "/overlay.png", 200, 0, 200), 20u);
  EXPECT_GT(pixels(out + "/overlay.png", 220, 100, 0), 20u);
  EXPECT_GT(pixels(out + "/overlay.png", 0, 130, 150), 20u);
}

}  // namespace
}  // namespace dynamap
