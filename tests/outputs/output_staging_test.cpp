// OutputStaging and runMapJob's output directory: one run's outputs as one set, the previous
// run's stale files gone, a failed or interrupted run leaving the directory as it was, and a
// second run into a busy directory refused.

#include "dynamap/outputs/output_staging.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "../test_util.h"
#include "dynamap/outputs/map_job.h"

namespace dynamap {
namespace {

namespace fs = std::filesystem;
const std::string kTiny = std::string(DYNAMAP_SOURCE_DIR) + "/rawlogs/tiny/tiny.rawlog";

// Every entry of `dir`, hidden ones included.
std::vector<std::string> entries(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

MapJob tinyJob(const std::string& out) {
  MapJob job;
  job.input = kTiny;
  job.out_dir = out;
  job.config.poses = PoseSource::GroundTruth;
  return job;
}

TEST(OutputStaging, ARerunReplacesThePreviousRunsOutputsAndKeepsOtherFiles) {
  const std::string dir = test::tempDir("staging") + "/o";
  MapJob job = tinyJob(dir);
  job.frames_every = 150;
  runMapJob(job);
  ASSERT_TRUE(fs::exists(dir + "/mrpt_plain.png"));
  ASSERT_TRUE(fs::exists(dir + "/frames/000150.png"));
  std::ofstream(dir + "/notes.txt") << "mine\n";
  std::ofstream(dir + "/report.md") << "an evaluation of the earlier map\n";
  job.baseline = false;
  job.frames_every = 0;
  runMapJob(job);
  EXPECT_EQ(entries(dir),
            (std::vector<std::string>{"config.ini", "dynamic.gridmap.gz", "dynamic.png",
                                      "events.csv", "notes.txt", "objects.csv", "overlay.png",
                                      "people.csv", "poses.txt", "session.json",
                                      "static.gridmap.gz", "static.pgm", "static.png",
                                      "static.yaml", "summary.json", "tracks.csv"}));
}

TEST(OutputStaging, AnInterruptedRunLeavesTheDirectoryAsItWas) {
  const std::string dir = test::tempDir("staging") + "/o";
  runMapJob(tinyJob(dir));
  const std::vector<std::string> before = entries(dir);
  const std::string summary = test::readFile(dir + "/summary.json");
  MapJob job = tinyJob(dir);
  job.baseline = false;
  int scans = 0;
  job.cancelled = [&] { return ++scans > 100; };  // as a signal after 100 scans would
  EXPECT_THROW(runMapJob(job), RunCancelled);
  EXPECT_EQ(scans, 101);
  EXPECT_EQ(entries(dir), before);  // no staging directory left, mrpt_plain.png still there
  EXPECT_EQ(test::readFile(dir + "/summary.json"), summary);
}

TEST(OutputStaging, ASecondRunIntoABusyDirectoryIsRefused) {
  const std::string dir = test::tempDir("staging") + "/o";
  OutputStaging first(dir);
  EXPECT_EQ(first.path().rfind(dir + "/.dynamap-run-", 0), 0u) << first.path();
  try {
    OutputStaging second(dir);
    ADD_FAILURE() << "a second run was let in";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), dir + ": another dynamap run is writing into this directory");
  }
}

TEST(OutputStaging, LeftoversOfAKilledRunAreRemovedByTheNextOne) {
  const std::string dir = test::tempDir("staging") + "/o";
  fs::create_directories(dir + "/.dynamap-run-dead01");
  std::ofstream(dir + "/.dynamap-run-dead01/tracks.csv") << "half\n";
  std::ofstream(dir + "/.tmp-tracks.csv") << "an older version's temporary\n";
  {
    OutputStaging stage(dir);
    std::ofstream(stage.path() + "/summary.json") << "{}\n";
    stage.commit();
  }
  EXPECT_EQ(entries(dir), std::vector<std::string>{"summary.json"});
}

}  // namespace
}  // namespace dynamap
