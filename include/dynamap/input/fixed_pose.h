#pragma once
// The fixed pose source (PoseSource::Fixed): every scan of a log at one pose, for a robot that
// stands still. It works on top of any reader: the reader is opened without needing a pose of
// its own, and this source puts every scan it returns at the fixed pose.

#include <mrpt/poses/CPose2D.h>

#include <memory>
#include <string>

#include "dynamap/input/scan_source.h"

namespace dynamap {

/// "x y phi" ([m] [m] [rad], blanks between): three finite numbers, nothing else. Throws
/// std::invalid_argument saying what is wrong otherwise.
mrpt::poses::CPose2D parseFixedPose(const std::string& text);
/// The text parseFixedPose reads back to the same pose (shortest exact decimal form).
std::string formatFixedPose(const mrpt::poses::CPose2D& pose);

/// `inner`'s scans, each at `pose`; poseSource() is Fixed, stats and progress are inner's.
std::unique_ptr<ScanSource> withFixedPose(std::unique_ptr<ScanSource> inner,
                                          const mrpt::poses::CPose2D& pose);

/// `inner`'s scans with every pose moved rigidly so that the first scan's pose is `first`: a
/// session started at a known place of an earlier session's map (dynamap map --initial-pose).
/// poseSource(), stats and progress are inner's.
std::unique_ptr<ScanSource> startingAt(std::unique_ptr<ScanSource> inner,
                                       const mrpt::poses::CPose2D& first);

}  // namespace dynamap
