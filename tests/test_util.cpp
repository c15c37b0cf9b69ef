#include "test_util.h"

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <mrpt/serialization/CArchive.h>

#include <unistd.h>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace dynamap::test {

using mrpt::obs::CObservation2DRangeScan;

CObservation2DRangeScan::Ptr makeScan(const std::vector<float>& ranges, double aperture, double t,
                                      float max_range) {
  auto scan = CObservation2DRangeScan::Create();
  scan->aperture = static_cast<float>(aperture);
  scan->rightToLeft = true;
  scan->maxRange = max_range;
  scan->sensorLabel = "LASER";
  scan->timestamp = mrpt::Clock::fromDouble(t);
  scan->resizeScan(ranges.size());
  for (std::size_t i = 0; i < ranges.size(); ++i) {
    scan->setScanRange(i, ranges[i] > 0 ? ranges[i] : 0.0f);
    scan->setScanRangeValidity(i, ranges[i] > 0);
  }
  return scan;
}

std::vector<float> roomRanges(double x0, double x1, double y0, double y1,
                              const mrpt::poses::CPose2D& pose, int n, double aperture) {
  std::vector<float> out(n);
  for (int i = 0; i < n; ++i) {
    const double a = pose.phi() + (n > 1 ? -0.5 * aperture + aperture * i / (n - 1) : 0.0);
    const double c = std::cos(a), s = std::sin(a);
    double best = std::numeric_limits<double>::infinity();
    if (c > 1e-12) best = std::min(best, (x1 - pose.x()) / c);
    if (c < -1e-12) best = std::min(best, (x0 - pose.x()) / c);
    if (s > 1e-12) best = std::min(best, (y1 - pose.y()) / s);
    if (s < -1e-12) best = std::min(best, (y0 - pose.y()) / s);
    out[i] = static_cast<float>(best);
  }
  return out;
}

void writeObsRawlog(const std::string& path, const std::vector<LogStep>& steps, bool with_gt) {
  mrpt::io::CFileGZOutputStream out(path);
  auto ar = mrpt::serialization::archiveFrom(out);
  for (const auto& s : steps) {
    auto odo = mrpt::obs::CObservationOdometry::Create();
    odo->odometry = s.pose;
    odo->timestamp = mrpt::Clock::fromDouble(s.t);
    odo->sensorLabel = "ODOMETRY";
    ar << *odo;
    s.scan->timestamp = mrpt::Clock::fromDouble(s.t);
    ar << *s.scan;
    if (with_gt) {
      auto gt = mrpt::obs::CObservationRobotPose::Create();
      gt->pose.mean = mrpt::poses::CPose3D(s.pose);
      gt->timestamp = mrpt::Clock::fromDouble(s.t);
      gt->sensorLabel = "GT";
      ar << *gt;
    }
  }
}

std::vector<std::size_t> writeSimplemap(const std::string& path,
                                        const std::vector<LogStep>& steps) {
  mrpt::maps::CSimpleMap map;
  for (const auto& s : steps) {
    auto sf = mrpt::obs::CSensoryFrame::Create();
    s.scan->timestamp = mrpt::Clock::fromDouble(s.t);
    sf->insert(s.scan);
    auto pose = mrpt::poses::CPose3DPDFGaussian::Create();
    pose->mean = mrpt::poses::CPose3D(s.pose);
    map.insert(pose, sf);
  }
  {
    mrpt::io::CFileOutputStream out(path);
    mrpt::serialization::archiveFrom(out) << map;
  }
  // Each keyframe starts with its pose object: a length byte, then the class name.
  const std::string bytes = readFile(path);
  const std::string name = "mrpt::poses::CPose3DPDFGaussian";
  std::vector<std::size_t> starts;
  for (auto at = bytes.find(name); at != std::string::npos; at = bytes.find(name, at + 1)) {
    starts.push_back(at - 1);
  }
  starts.push_back(bytes.size());
  return starts;
}

void writeActionSfRawlog(const std::string& path, const std::vector<LogStep>& steps) {
  mrpt::io::CFileGZOutputStream out(path);
  auto ar = mrpt::serialization::archiveFrom(out);
  mrpt::poses::CPose2D prev;
  for (const auto& s : steps) {
    mrpt::obs::CActionCollection acts;
    mrpt::obs::CActionRobotMovement2D mv;
    mrpt::obs::CActionRobotMovement2D::TMotionModelOptions opts;
    mv.computeFromOdometry(s.pose - prev, opts);
    mv.timestamp = mrpt::Clock::fromDouble(s.t);
    acts.insert(mv);
    ar << acts;
    mrpt::obs::CSensoryFrame sf;
    s.scan->timestamp = mrpt::Clock::fromDouble(s.t);
    sf.insert(s.scan);
    ar << sf;
    prev = s.pose;
  }
}

std::string tempDir(const std::string& tag) {
  static std::atomic<int> counter{0};
  const auto dir =
      std::filesystem::temp_directory_path() /
      ("dynamap-test-" + tag + "-" + std::to_string(getpid()) + "-" + std::to_string(counter++));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

int run(const std::string& command, std::string* output) {
  FILE* p = popen((command + " 2>&1").c_str(), "r");
  if (!p) throw std::runtime_error("cannot run: " + command);
  std::string text;
  char buf[4096];
  std::size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) text.append(buf, n);
  const int status = pclose(p);
  if (output) *output = text;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::vector<ScanRecord> readAll(ScanSource& src) {
  std::vector<ScanRecord> out;
  ScanRecord r;
  while (src.next(r)) out.push_back(r);
  return out;
}

std::string inputError(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace dynamap::test
