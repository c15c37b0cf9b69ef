#pragma once
// The files an import-* command writes: an MRPT rawlog (observations only, gz) and its companion
// <out>.gt.txt of ground-truth poses, both under temporary names until the import completes, so
// a failed import leaves nothing that looks like a result.

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/serialization/CSerializable.h>

#include <cstdio>
#include <string>

namespace dynamap::app {

/// <out without .gz and .rawlog>.gt.txt: where the rawlog reader looks for ground truth.
std::string groundTruthPath(std::string rawlog);

class ImportOutput {
 public:
  /// Opens both files (`with_ground_truth` false: no .gt.txt) for the import of `input`. Throws
  /// UsageError before writing anything when either would overwrite the input (the same file,
  /// by inode) or an existing file that is not an MRPT rawlog or pose file; InputError when a
  /// file cannot be opened.
  ImportOutput(const std::string& input, const std::string& rawlog, bool with_ground_truth = true);
  ~ImportOutput();
  ImportOutput(const ImportOutput&) = delete;
  ImportOutput& operator=(const ImportOutput&) = delete;

  void write(const mrpt::serialization::CSerializable& obj);
  /// One "t x y phi" line of the .gt.txt (ignored without one).
  void writeGroundTruth(double t, const mrpt::poses::CPose2D& p);
  /// Closes both and renames them into place; throws InputError on a write error.
  void commit();
  const std::string& groundTruthFile() const { return gt_; }

 private:
  static std::string tmp(const std::string& p) { return p + ".part"; }
  std::string rawlog_, gt_;
  mrpt::io::CFileGZOutputStream rawlog_out_;
  std::FILE* gt_out_ = nullptr;
  bool committed_ = false;
};

/// The CObservationOdometry (label ODOMETRY) and CObservationRobotPose (label GT) of a pose at t.
mrpt::obs::CObservationOdometry odometryAt(double t, const mrpt::poses::CPose2D& pose);
mrpt::obs::CObservationRobotPose groundTruthAt(double t, const mrpt::poses::CPose2D& pose);

}  // namespace dynamap::app
