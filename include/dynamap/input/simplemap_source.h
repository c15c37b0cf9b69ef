#pragma once
// The MRPT simplemap reader (.simplemap, plain or gz): each keyframe's scans at its mean pose.

#include <memory>
#include <string>

#include "dynamap/input/scan_source.h"

namespace dynamap {

/// Loads the whole simplemap (MRPT reads it in one piece); throws InputError if it cannot.
std::unique_ptr<ScanSource> openSimplemapSource(const std::string& path);

}  // namespace dynamap
