#include "import_output.h"

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/serialization/CArchive.h>

#include <filesystem>

#include "commands.h"
#include "dynamap/input/pose_file.h"
#include "dynamap/input/scan_source.h"

namespace dynamap::app {

std::string groundTruthPath(std::string out) {
  for (const std::string ext : {".gz", ".rawlog"}) {
    if (out.size() > ext.size() && out.compare(out.size() - ext.size(), ext.size(), ext) == 0) {
      out.resize(out.size() - ext.size());
    }
  }
  return out + ".gt.txt";
}

namespace {

// An existing file at `out` may be replaced only when it is an earlier import's output: never the
// input itself, never something else (a log, a map) that a typo pointed at.
void requireReplaceable(const std::string& input, const std::string& out, bool rawlog) {
  std::error_code ec;
  if (!std::filesystem::exists(out, ec)) return;
  if (std::filesystem::equivalent(input, out, ec)) {
    throw UsageError(out + ": is the input; give another --out");
  }
  bool ours = false;
  if (rawlog) {
    mrpt::io::CFileGZInputStream in;
    std::string head(256, '\0');
    head.resize(in.open(out) ? in.Read(head.data(), head.size()) : 0);
    ours = head.find("CObservation") != std::string::npos;
  } else {
    try {
      readPoseFile(out);  // every line `t x y phi`: an earlier import's ground truth
      ours = true;
    } catch (const InputError&) {
    }
  }
  if (!ours) {
    throw UsageError(out + ": exists and is not " +
                     (rawlog ? std::string("an MRPT rawlog") : std::string("a pose file")) +
                     "; refusing to overwrite it");
  }
}

}  // namespace

ImportOutput::ImportOutput(const std::string& input, const std::string& rawlog,
                           bool with_ground_truth)
    : rawlog_(rawlog), gt_(with_ground_truth ? groundTruthPath(rawlog) : "") {
  requireReplaceable(input, rawlog_, true);
  if (!gt_.empty()) requireReplaceable(input, gt_, false);
  if (!rawlog_out_.open(tmp(rawlog_))) throw InputError(rawlog_ + ": cannot write");
  if (gt_.empty()) return;
  gt_out_ = std::fopen(tmp(gt_).c_str(), "w");
  if (!gt_out_) throw InputError(gt_ + ": cannot write");
}

ImportOutput::~ImportOutput() {
  if (gt_out_) std::fclose(gt_out_);
  if (!committed_) {
    rawlog_out_.close();
    std::error_code ec;
    std::filesystem::remove(tmp(rawlog_), ec);
    if (!gt_.empty()) std::filesystem::remove(tmp(gt_), ec);
  }
}

void ImportOutput::write(const mrpt::serialization::CSerializable& obj) {
  auto arch = mrpt::serialization::archiveFrom(rawlog_out_);
  arch << obj;
}

void ImportOutput::writeGroundTruth(double t, const mrpt::poses::CPose2D& p) {
  if (gt_out_) std::fprintf(gt_out_, "%.6f %.6f %.6f %.6f\n", t, p.x(), p.y(), p.phi());
}

void ImportOutput::commit() {
  rawlog_out_.close();
  if (gt_out_) {
    const bool gt_ok = std::fclose(gt_out_) == 0;
    gt_out_ = nullptr;
    if (!gt_ok) throw InputError(gt_ + ": write error");
  }
  std::filesystem::rename(tmp(rawlog_), rawlog_);
  if (!gt_.empty()) std::filesystem::rename(tmp(gt_), gt_);
  committed_ = true;
}

mrpt::obs::CObservationOdometry odometryAt(double t, const mrpt::poses::CPose2D& pose) {
  mrpt::obs::CObservationOdometry odo;
  odo.sensorLabel = "ODOMETRY";
  odo.timestamp = mrpt::Clock::fromDouble(t);
  odo.odometry = pose;
  return odo;
}

mrpt::obs::CObservationRobotPose groundTruthAt(double t, const mrpt::poses::CPose2D& pose) {
  mrpt::obs::CObservationRobotPose gt;
  gt.sensorLabel = "GT";
  gt.timestamp = mrpt::Clock::fromDouble(t);
  gt.pose.mean = mrpt::poses::CPose3D(pose);
  return gt;
}

}  // namespace dynamap::app
