#pragma once
// Helpers shared by the tests: synthetic scans, rawlogs written on the fly, running the command.

#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose2D.h>

#include <functional>
#include <string>
#include <vector>

#include "dynamap/input/scan_source.h"

namespace dynamap::test {

/// A scan of ranges.size() beams spread over `aperture` (rad), beam 0 on the right
/// (rightToLeft). A range <= 0 is an invalid (no-echo) beam.
mrpt::obs::CObservation2DRangeScan::Ptr makeScan(const std::vector<float>& ranges, double aperture,
                                                 double t = 0.0, float max_range = 30.0f);

/// The ranges a scan of `n` beams over `aperture` from pose (x, y, phi) measures in a
/// rectangular room [x0, x1] x [y0, y1] (exact).
std::vector<float> roomRanges(double x0, double x1, double y0, double y1,
                              const mrpt::poses::CPose2D& pose, int n, double aperture);

/// One step of a synthetic log: the robot's true pose and a scan.
struct LogStep {
  double t;
  mrpt::poses::CPose2D pose;
  mrpt::obs::CObservation2DRangeScan::Ptr scan;
};

/// Writes an observations-only rawlog (gz): per step ODOMETRY, LASER, and GT (a
/// CObservationRobotPose) unless `with_gt` is false.
void writeObsRawlog(const std::string& path, const std::vector<LogStep>& steps,
                    bool with_gt = true);
/// Writes an action / sensory-frame rawlog with odometry increments between steps.
void writeActionSfRawlog(const std::string& path, const std::vector<LogStep>& steps);

/// Writes an uncompressed MRPT simplemap: one keyframe per step, its scan at its pose (a
/// CPose3DPDFGaussian); returns the byte offset where each keyframe starts, and the file's size.
std::vector<std::size_t> writeSimplemap(const std::string& path, const std::vector<LogStep>& steps);

/// A fresh, empty directory under the system's temp dir, unique per call.
std::string tempDir(const std::string& tag);

/// Runs a shell command; returns its exit status and fills `output` with stdout + stderr.
int run(const std::string& command, std::string* output = nullptr);

std::string readFile(const std::string& path);

/// Every record `src` gives, in order.
std::vector<ScanRecord> readAll(ScanSource& src);
/// The message of the InputError `f` throws; empty when it throws none.
std::string inputError(const std::function<void()>& f);

}  // namespace dynamap::test
