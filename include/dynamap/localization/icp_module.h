#pragma once
// MRPT's classic point-to-point ICP (mrpt::slam::CICP), reached through a module loaded on first
// use. libmrpt-slam brings some 120 shared libraries of its own (OpenCV's video and GUI modules,
// Qt, GStreamer, FFmpeg) that every start of dynamap would otherwise load and relocate, though
// only runs that match scans need them: the module, libdynamap_icp.so, is built beside the
// executables and is the only part of dynamap that links libmrpt-slam.

#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/poses/CPose2D.h>

namespace dynamap {

/// What CICP is told beyond the two point sets (the rest of its options are fixed: classic
/// algorithm, no RANSAC, no covariance or quality, every point).
struct IcpParams {
  unsigned max_iterations = 0;
  double threshold_dist = 0;           ///< [m] initial matching distance
  double threshold_ang = 0;            ///< [rad] its angular part
  double alfa = 0;                     ///< the factor that shrinks both on convergence
  double smallest_threshold_dist = 0;  ///< [m] where shrinking stops
};

/// Loads the module now if it is not loaded yet; throws std::runtime_error naming it (and where
/// it was looked for) when it cannot be.
void requireIcpModule();

/// The pose that ICP aligns `scan` onto `reference` at, starting from `start`; `iterations` gets
/// CICP's count. Throws std::runtime_error naming the module when it cannot be loaded.
mrpt::poses::CPose2D icpAlignModule(const mrpt::maps::CSimplePointsMap& reference,
                                    const mrpt::maps::CSimplePointsMap& scan,
                                    const mrpt::poses::CPose2D& start, const IcpParams& params,
                                    unsigned& iterations);

}  // namespace dynamap
