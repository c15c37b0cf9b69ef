#pragma once
// The one factory of scan sources: a log's format is told by its content, not its name.

#include <memory>
#include <string>

#include "dynamap/input/carmen_reader.h"
#include "dynamap/input/scan_source.h"

namespace dynamap {

/// Opens `path`, telling its format by content (CARMEN text, simplemap, rawlog); `carmen`
/// (nullptr: defaults) applies to CARMEN logs. ScanMatching opens the odometry poses.
/// Throws InputError if the file cannot be read or no scan can have a pose under `source`.
std::unique_ptr<ScanSource> openScanSource(const std::string& path, PoseSource source,
                                           const CarmenOptions* carmen = nullptr);

}  // namespace dynamap
