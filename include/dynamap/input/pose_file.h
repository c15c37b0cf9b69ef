#pragma once
// Pose files: `timestamp x y phi` per line (MRPT's <log>.gt.txt, dynamap's poses.txt); lines
// starting with '%' or '#' and blank lines are comments.

#include <string>
#include <vector>

#include "dynamap/base/pose_track.h"

namespace dynamap {

/// Every pose of `path`, in file order. Throws InputError naming the file and line of the first
/// line that is not four numbers or is longer than LineReader::kMaxLineBytes, or when the file
/// cannot be opened (a gz file is read inflated).
std::vector<TimedPose> readPoseFile(const std::string& path);

/// MRPT's companion ground-truth file of a rawlog: <log without .rawlog[.gz]>.gt.txt.
std::string companionGroundTruth(const std::string& rawlog_path);

}  // namespace dynamap
