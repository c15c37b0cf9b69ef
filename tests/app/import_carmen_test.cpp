// dynamap import-carmen end to end: its rawlog reads back with MRPT, objects in log order.

#include <gtest/gtest.h>

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/serialization/CArchive.h>
#include <unistd.h>
#include "../test_util.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

std::string beams(int n, const char* r) {
  std::string s;
  for (int i = 0; i < n; ++i) s += std::string(" ") + r;
  return s;
}

// Two laser lines (old and new format), two ODOM lines, a PARAM, a comment and a SYNC.
const char* const kHeader = "# CARMEN Logfile\nPARAM laser_front_laser_resolution 1.0 0 h 0\n";
std::string sampleLog() {
  return std::string(kHeader) + "ODOM 1 2 0.1 0.2 0 0 10.0 h 10.0\n" + "FLASER 180" +
         beams(180, "2.5") + " 5 6 0.5 4 5 0.4 10.5 h 10.6\n" + "SYNC x 10.7 h 10.7\n" +
         "ODOM 1.5 2 0.1 0.2 0 0 11.0 h 11.0\n" + "ROBOTLASER1 0 -1.5707963 3.1415927 0.0174533 " +
         "80 0.01 0 181" + beams(181, "3.0") + " 0 2 3.1 1.5707963 2 3 1.5707963 " +
         "0.3 0 1 0.5 0 11.5 h 11.6\n";
}

class ImportCarmenTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("dynamap_import_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(path(name)) << text;
    return path(name);
  }
  /// Runs dynamap with `args`; returns its exit status, its output in `out`.
  int run(const std::string& args, std::string* out = nullptr) const {
    const std::string log = path("run.out");
    const int rc =
        std::system((std::string(DYNAMAP_EXE) + " " + args + " >" + log + " 2>&1").c_str());
    if (out) {
      std::ifstream in(log);
      out->assign(std::istreambuf_iterator<char>(in), {});
    }
    return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
  }

  fs::path dir_;
};

std::vector<mrpt::serialization::CSerializable::Ptr> readRawlog(const std::string& path) {
  mrpt::io::CFileGZInputStream in(path);
  auto arch = mrpt::serialization::archiveFrom(in);
  std::vector<mrpt::serialization::CSerializable::Ptr> objs;
  while (true) {
    try {
      objs.push_back(arch.ReadObject());
    } catch (const mrpt::serialization::CExceptionEOF&) {
      break;
    }
  }
  return objs;
}

std::vector<std::string> lines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> out;
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

TEST_F(ImportCarmenTest, RawlogReadsBackInLogOrderWithGroundTruthFile) {
  const std::string log = write("in.log", sampleLog());
  std::string output;
  ASSERT_EQ(run("import-carmen " + log + " --out " + path("out.rawlog"), &output), 0) << output;
  EXPECT_NE(output.find("scans:       2"), std::string::npos) << output;
  EXPECT_NE(output.find("1 line type SYNC"), std::string::npos) << output;

  using namespace mrpt::obs;
  const auto objs = readRawlog(path("out.rawlog"));
  // FLASER: odometry (its odom fields), scan, GT; ROBOTLASER1: odometry (the last ODOM), scan,
  // GT. The ODOM lines are not the odometry stream by default (--carmen-odometry laser).
  const std::vector<std::pair<std::string, std::string>> want = {
      {"mrpt::obs::CObservationOdometry", "ODOMETRY"},
      {"mrpt::obs::CObservation2DRangeScan", "LASER"},
      {"mrpt::obs::CObservationRobotPose", "GT"},
      {"mrpt::obs::CObservationOdometry", "ODOMETRY"},
      {"mrpt::obs::CObservation2DRangeScan", "LASER"},
      {"mrpt::obs::CObservationRobotPose", "GT"}};
  ASSERT_EQ(objs.size(), want.size());
  const double times[] = {10.5, 10.5, 10.5, 11.5, 11.5, 11.5};
  for (std::size_t k = 0; k < want.size(); ++k) {
    auto obs = std::dynamic_pointer_cast<CObservation>(objs[k]);
    ASSERT_TRUE(obs) << k;
    EXPECT_EQ(std::string(objs[k]->GetRuntimeClass()->className), want[k].first) << k;
    EXPECT_EQ(obs->sensorLabel, want[k].second) << k;
    EXPECT_NEAR(mrpt::Clock::toDouble(obs->timestamp), times[k], 1e-6) << k;
  }
  const auto scan = std::dynamic_pointer_cast<CObservation2DRangeScan>(objs[1]);
  EXPECT_EQ(scan->getScanSize(), 180u);
  EXPECT_NEAR(scan->aperture, 179 * M_PI / 180, 1e-5);
  const auto gt = std::dynamic_pointer_cast<CObservationRobotPose>(objs[2]);
  EXPECT_NEAR(gt->pose.mean.x(), 5, 1e-9);
  const auto odo = std::dynamic_pointer_cast<CObservationOdometry>(objs[0]);
  EXPECT_NEAR(odo->odometry.x(), 4, 1e-9);
  // --carmen-odometry odom: the ODOM lines (with their velocities) are the odometry instead.
  ASSERT_EQ(run("import-carmen " + log + " --carmen-odometry odom --out " + path("odom.rawlog"),
                &output),
            0)
      << output;
  const auto odom = readRawlog(path("odom.rawlog"));
  ASSERT_EQ(odom.size(), 6u);
  const double odom_times[] = {10.0, 10.5, 10.5, 11.0, 11.5, 11.5};
  for (std::size_t k = 0; k < odom.size(); ++k) {
    auto obs = std::dynamic_pointer_cast<CObservation>(odom[k]);
    ASSERT_TRUE(obs) << k;
    EXPECT_NEAR(mrpt::Clock::toDouble(obs->timestamp), odom_times[k], 1e-6) << k;
  }
  const auto line_odo = std::dynamic_pointer_cast<CObservationOdometry>(odom[3]);
  ASSERT_TRUE(line_odo);
  EXPECT_NEAR(line_odo->odometry.x(), 1.5, 1e-9);
  EXPECT_TRUE(line_odo->hasVelocities);

  const auto gt_lines = lines(path("out.gt.txt"));
  ASSERT_EQ(gt_lines.size(), 2u);
  EXPECT_EQ(gt_lines[0], "10.500000 5.000000 6.000000 0.500000");
  EXPECT_FALSE(fs::exists(path("out.rawlog.part")));
}

TEST_F(ImportCarmenTest, BadLineFailsNamingItAndLeavesNoOutput) {
  const std::string log = write("bad.log", sampleLog() + "FLASER 180 1 2 3\n");
  std::string output;
  EXPECT_EQ(run("import-carmen " + log + " --out " + path("out.rawlog"), &output), 1);
  EXPECT_NE(output.find("bad.log:8:"), std::string::npos) << output;
  EXPECT_FALSE(fs::exists(path("out.rawlog")));
  EXPECT_FALSE(fs::exists(path("out.rawlog.part")));
  EXPECT_FALSE(fs::exists(path("out.gt.txt")));

  EXPECT_EQ(run("import-carmen " + log + " --skip-bad-lines --out " + path("out.rawlog"), &output),
            0)
      << output;
  EXPECT_NE(output.find("bad lines:   1"), std::string::npos) << output;
  EXPECT_EQ(lines(path("out.gt.txt")).size(), 2u);
}

TEST_F(ImportCarmenTest, CommandLine) {
  std::string output;
  EXPECT_EQ(run("import-carmen --help", &output), 0);
  for (const char* opt : {"--out", "--fov", "--skip-bad-lines", "--carmen-odometry"}) {
    EXPECT_NE(output.find(opt), std::string::npos) << opt;
  }
  const std::string log = write("in.log", sampleLog());
  EXPECT_EQ(run("import-carmen " + log), 2);  // no --out
  EXPECT_EQ(run("import-carmen " + log + " --out " + path("o.rawlog") + " --fov -3"), 2);
  EXPECT_EQ(run("import-carmen " + log + " --out " + path("o.rawlog") + " --carmen-odometry x"), 2);
  EXPECT_EQ(run("import-carmen " + path("missing.log") + " --out " + path("o.rawlog")), 1);
  EXPECT_EQ(run("import-carmen " + log + " --out " + path("o.rawlog") + " --fov 90"), 0);
  const auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(
      readRawlog(path("o.rawlog")).at(1));
  ASSERT_TRUE(scan);
  EXPECT_NEAR(scan->aperture, 89.5 * M_PI / 180, 1e-5);  // 180 beams over 90 deg
}

TEST_F(ImportCarmenTest, AnOutputThatIsTheInputOrNotARawlogIsRefusedAndLeftAlone) {
  const std::string log = write("keep.log", sampleLog());
  std::string output;
  EXPECT_EQ(run("import-carmen " + log + " --out " + log, &output), 2) << output;
  EXPECT_NE(output.find("is the input"), std::string::npos) << output;
  EXPECT_EQ(dynamap::test::readFile(log), sampleLog());  // untouched
  const std::string notes = write("notes.rawlog", "my notes\n");
  EXPECT_EQ(run("import-carmen " + log + " --out " + notes, &output), 2) << output;
  EXPECT_NE(output.find("is not an MRPT rawlog"), std::string::npos) << output;
  EXPECT_EQ(dynamap::test::readFile(notes), "my notes\n");
  // An earlier import's output is replaced as before.
  EXPECT_EQ(run("import-carmen " + log + " --out " + path("o.rawlog")), 0);
  EXPECT_EQ(run("import-carmen " + log + " --out " + path("o.rawlog")), 0);
}

}  // namespace
