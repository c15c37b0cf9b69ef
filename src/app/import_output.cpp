#include "import_output.h"

#include <mrpt/poses/CPose3D.h>
#include <mrpt/serialization/CArchive.h>

#include <filesystem>

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

ImportOutput::ImportOutput(const std::string& rawlog, bool with_ground_truth)
    : rawlog_(rawlog), gt_(with_ground_truth ? groundTruthPath(rawlog) : "") {
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
