#include "dynamap/input/open_source.h"

#include "dynamap/input/mrpt_records.h"
#include "dynamap/input/pose_file.h"
#include "dynamap/input/rawlog_source.h"
#include "dynamap/input/simplemap_source.h"

namespace dynamap {

std::unique_ptr<ScanSource> openScanSource(const std::string& path, PoseSource source,
                                           const CarmenOptions* carmen) {
  if (!fileExists(path)) throw InputError(path + ": no such file");
  if (source == PoseSource::ScanMatching) source = PoseSource::Odometry;  // corrected by Mapper
  if (looksLikeCarmen(path))
    return openCarmenSource(path, source, carmen ? *carmen : CarmenOptions{});
  const std::string head = fileHead(path, 256);
  if (head.empty()) throw InputError(path + ": empty file");
  if (head.find("CSimpleMap") != std::string::npos) {
    if (source != PoseSource::Auto && source != PoseSource::Simplemap) {
      throw InputError(path + ": a simplemap only carries simplemap poses (asked for " +
                       toString(source) + ")");
    }
    return openSimplemapSource(path);
  }
  if (head.find("CSensoryFrame") == std::string::npos &&
      head.find("CActionCollection") == std::string::npos &&
      head.find("CObservation") == std::string::npos) {
    throw InputError(path + ": not an MRPT rawlog, simplemap or CARMEN log");
  }
  if (source == PoseSource::Simplemap) {
    throw InputError(path + ": pose source simplemap needs a .simplemap file");
  }
  if (source == PoseSource::Auto) {
    const RawlogPeek peek = peekRawlog(path);
    if (peek.ground_truth || fileExists(companionGroundTruth(path))) {
      source = PoseSource::GroundTruth;
    } else if (peek.odometry) {
      source = PoseSource::Odometry;
    } else {
      throw InputError(path + ": no poses found (no ground truth, no odometry)");
    }
  }
  return openRawlogSource(path, source);
}

}  // namespace dynamap
