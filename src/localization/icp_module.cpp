// The module side of icp_module.h: the one translation unit that calls libmrpt-slam. Built as
// libdynamap_icp.so; its entry point is C-linkage so that dlsym finds it by a plain name.

#include <mrpt/slam/CICP.h>

#include <exception>
#include <string>

#include "dynamap/localization/icp_module.h"

extern "C" __attribute__((visibility("default"))) int dynamap_icp_align(
    const mrpt::maps::CSimplePointsMap* reference, const mrpt::maps::CSimplePointsMap* scan,
    const mrpt::poses::CPose2D* start, const dynamap::IcpParams* p, mrpt::poses::CPose2D* out,
    unsigned* iterations, std::string* error) {
  // Nothing may unwind through the C boundary: an exception becomes the error text.
  try {
    mrpt::slam::CICP icp;
    icp.setMinLoggingLevel(mrpt::system::LVL_ERROR);
    auto& io = icp.options;
    io.ICP_algorithm = mrpt::slam::icpClassic;
    io.maxIterations = p->max_iterations;
    io.thresholdDist = p->threshold_dist;
    io.thresholdAng = p->threshold_ang;
    io.ALFA = p->alfa;
    io.smallestThresholdDist = p->smallest_threshold_dist;
    io.onlyUniqueRobust = false;
    io.doRANSAC = false;
    io.skip_cov_calculation = true;
    io.skip_quality_calculation = true;
    io.corresponding_points_decimation = 1;  // every point: few points, the pose must be exact
    mrpt::slam::CICP::TReturnInfo info;
    const auto pdf = icp.Align(reference, scan, *start, info);
    *iterations = info.nIterations;
    *out = pdf->getMeanVal();
    return 1;
  } catch (const std::exception& e) {
    *error = e.what();
  } catch (...) {
    *error = "unknown exception";
  }
  return 0;
}
