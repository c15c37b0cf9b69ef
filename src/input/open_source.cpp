#include "dynamap/input/open_source.h"

#include <filesystem>

#include "dynamap/input/fixed_pose.h"
#include "dynamap/input/mrpt_records.h"
#include "dynamap/input/pose_file.h"
#include "dynamap/input/rawlog_source.h"
#include "dynamap/input/ros2_bag.h"
#include "dynamap/input/simplemap_source.h"

namespace dynamap {
namespace {

std::unique_ptr<ScanSource> openBag(const std::string& path, PoseSource source,
                                    const BagOptions& options) {
#ifdef DYNAMAP_HAVE_ROSBAG
  return openBagSource(path, source, options);
#else
  (void)source;
  (void)options;
  throw InputError(path +
                   ": a ROS bag, but this dynamap was built without ROS bag support "
                   "(-DDYNAMAP_ROSBAG=OFF); rebuild with -DDYNAMAP_ROSBAG=ON");
#endif
}

/// A simplemap's first object: CSimpleMap, or CSensFrameProbSequence, its name before MRPT 1.0
/// (MRPT's own localization_demo.simplemap.gz), which MRPT 2.5 still reads as a CSimpleMap.
bool isSimplemapHead(const std::string& head) {
  return head.find("CSimpleMap") != std::string::npos ||
         head.find("CSensFrameProbSequence") != std::string::npos;
}

/// `slam`: the run asked for pose source slam, which needs the log's odometry.
std::unique_ptr<ScanSource> openMrptLog(const std::string& path, PoseSource source, bool slam,
                                        const PoseTrackOptions& track) {
  const std::string head = fileHead(path, 256);
  if (head.empty()) throw InputError(path + ": empty file");
  if (isSimplemapHead(head)) {
    if (source != PoseSource::Auto && source != PoseSource::Simplemap &&
        source != PoseSource::Fixed) {
      throw InputError(path + ": a simplemap only carries simplemap poses (asked for " +
                       toString(source) + ")");
    }
    return openSimplemapSource(path);
  }
  if (head.find("CSensoryFrame") == std::string::npos &&
      head.find("CActionCollection") == std::string::npos &&
      head.find("CObservation") == std::string::npos) {
    throw InputError(path + ": not an MRPT rawlog, simplemap, CARMEN log or ROS bag");
  }
  if (source == PoseSource::Simplemap) {
    throw InputError(path + ": pose source simplemap needs a .simplemap file");
  }
  if (slam && !peekRawlog(path).odometry) {
    throw InputError(path + ": pose source slam needs odometry, and the log has none");
  }
  if (source == PoseSource::Auto) {
    const RawlogPeek peek = peekRawlog(path);
    if (peek.ground_truth || fileExists(companionGroundTruth(path))) {
      source = PoseSource::GroundTruth;
    } else if (peek.odometry) {
      source = PoseSource::Odometry;
    } else {
      throw InputError(path +
                       ": no poses found (no ground truth, no odometry; --poses fixed maps a "
                       "robot that stands still)");
    }
  }
  return openRawlogSource(path, source, track);
}

/// A ROS 1 bag, or a ROS 2 bag (an MCAP file, a .db3 file, a rosbag2 folder).
bool isBag(const std::string& path) {
  return looksLikeRosBag(path) || ros2::looksLikeRos2Bag(path);
}

// Whether the log has odometry for scan matching to start each scan from. A CARMEN laser line
// always carries its odometry.
bool hasOdometry(const std::string& path, const InputOptions& options) {
  if (isBag(path)) {
#ifdef DYNAMAP_HAVE_ROSBAG
    const BagContents c = BagReader(path, options.bag).contents();
    return c.odometry;
#else
    (void)options;
    return true;  // openBag says why it cannot read it
#endif
  }
  if (looksLikeCarmen(path)) return true;
  return isSimplemapHead(fileHead(path, 256)) || peekRawlog(path).odometry;
}

}  // namespace

std::unique_ptr<ScanSource> openScanSource(const std::string& path, const InputOptions& options) {
  // Before any reader opens it: a fifo would block, /dev/null or a directory reach MRPT's
  // exceptions. Logs are files (a reader may open one twice: format, then data, or two passes).
  std::error_code ec;
  const auto st = std::filesystem::status(path, ec);
  if (!std::filesystem::exists(st)) throw InputError(path + ": no such file");
  const bool bag = isBag(path);  // a rosbag2 folder is a directory
  if (std::filesystem::is_directory(st) && !bag) {
    throw InputError(path + ": is a directory, not a log (nor a rosbag2 folder)");
  }
  if (!std::filesystem::is_regular_file(st) && !bag) {
    throw InputError(path + ": not a regular file (a fifo, device or socket); give a log file");
  }
  PoseSource source = options.poses;
  // Corrected by the Mapper. Without odometry each scan is matched from where the last one was:
  // a LaserScan-only bag of a moving robot still gets its poses.
  if (source == PoseSource::ScanMatching)
    source = hasOdometry(path, options) ? PoseSource::Odometry : PoseSource::Fixed;
  const bool slam = source == PoseSource::Slam;  // odometry, turned into poses by the pipeline
  if (slam) source = PoseSource::Odometry;
  std::unique_ptr<ScanSource> inner;
  if (bag) {
    inner = openBag(path, source, options.bag);
  } else if (looksLikeCarmen(path)) {
    CarmenOptions carmen = options.carmen;
    carmen.odometry_track = options.pose_track;
    inner = openCarmenSource(path, source, carmen);
  } else {
    inner = openMrptLog(path, source, slam, options.pose_track);
  }
  if (source == PoseSource::Fixed) return withFixedPose(std::move(inner), options.fixed_pose);
  return inner;
}

std::unique_ptr<ScanSource> openScanSource(const std::string& path, PoseSource source,
                                           const CarmenOptions* carmen) {
  InputOptions options;
  options.poses = source;
  if (carmen) options.carmen = *carmen;
  return openScanSource(path, options);
}

}  // namespace dynamap
