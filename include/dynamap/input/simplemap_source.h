#pragma once
// The MRPT simplemap reader (.simplemap, plain or gz): each keyframe's scans at its mean pose.

#include <memory>
#include <string>

#include "dynamap/input/scan_source.h"

namespace dynamap {

/// Opens a simplemap of either of MRPT's formats (CSimpleMap, or CSensFrameProbSequence from
/// before MRPT 1.0) and reads it a keyframe at a time: memory holds one keyframe, and a file cut
/// or damaged in keyframe k gives the scans of keyframes 0 … k-1, then an InputError naming the
/// keyframe and its byte. Throws InputError when the file's header is no simplemap's.
std::unique_ptr<ScanSource> openSimplemapSource(const std::string& path);

}  // namespace dynamap
